// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the Linux port's WorkerPool runs every task exactly once, on several threads, without allocating, and gives SequentialRunner's results.
#include <doctest/doctest.h>

#include <sched.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/base/task_runner.hpp"
#include "cellguard/port/worker_pool.hpp"
#include "contract_capture.hpp"

using namespace cellguard;
using namespace cellguard::linux_port;

namespace {

/// Counts how often each index ran (atomically: a task run twice at the same time would show).
struct RunCounts {
    std::vector<std::atomic<std::uint32_t>> counts;
    explicit RunCounts(std::size_t n) : counts(n) {}
};
void count_task(void* context, std::size_t index) noexcept {
    auto* runs = static_cast<RunCounts*>(context);
    if (index < runs->counts.size()) {
        runs->counts[index].fetch_add(1U, std::memory_order_relaxed);
    }
}

/// Plain (non-atomic) increments of disjoint slots: run() must order them before its return.
void increment_task(void* context, std::size_t index) noexcept { ++static_cast<std::uint32_t*>(context)[index]; }

/// Where slow_increment_task leaves its work, so the compiler keeps it.
std::atomic<std::uint32_t> g_sink{0U};

/// increment_task after some work, so that a run() returning before its
/// tasks have finished is seen: a task is then still busy when the slots are compared.
void slow_increment_task(void* context, std::size_t index) noexcept {
    std::uint32_t state = static_cast<std::uint32_t>(index) + 1U;
    for (int k = 0; k < 4000; ++k) {
        state = state * 1664525U + 1013904223U;
    }
    g_sink.store(state, std::memory_order_relaxed);
    ++static_cast<std::uint32_t*>(context)[index];
}

/// A small float computation whose bits depend on the order of its additions;
/// each task adds its own series into its own slot (a task run twice shows).
struct Series {
    std::vector<float> slots;
};
void series_task(void* context, std::size_t index) noexcept {
    auto* s = static_cast<Series*>(context);
    std::uint32_t state = static_cast<std::uint32_t>(index) * 2654435761U + 1U;
    float sum = 0.0F;
    for (int k = 0; k < 200; ++k) {
        state = state * 1664525U + 1013904223U;
        sum += static_cast<float>(state >> 8U) * 1.0e-7F / static_cast<float>(k + 1);
    }
    s->slots[index] += sum;
}
/// Runs the series on @p runner and reduces it in index order; returns the bits.
std::uint32_t series_bits(TaskRunner& runner, std::size_t count) {
    Series s{std::vector<float>(count, 0.0F)};
    runner.run(count, &series_task, &s);
    float total = 0.0F;
    for (const float v : s.slots) {
        total += v;
    }
    std::uint32_t bits = 0U;
    std::memcpy(&bits, &total, sizeof(bits));
    return bits;
}

/// Two tasks that each wait (bounded) until both have started: they meet only
/// when they run at the same time, on two threads. The one not on the caller's
/// thread then works a while longer: run() must not return before it ends.
struct Rendezvous {
    std::thread::id caller = std::this_thread::get_id();
    std::atomic<int> arrived{0};
    std::atomic<int> met{0};
    std::atomic<bool> other_finished{false};
};
void rendezvous_task(void* context, std::size_t) noexcept {
    auto* r = static_cast<Rendezvous*>(context);
    r->arrived.fetch_add(1);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (r->arrived.load() < 2 && std::chrono::steady_clock::now() < give_up) {
    }
    if (r->arrived.load() >= 2) {
        r->met.fetch_add(1);
    }
    if (std::this_thread::get_id() != r->caller) {
        std::uint32_t state = 1U;
        for (int k = 0; k < 20000000; ++k) {  // milliseconds of work, far longer than run()'s return
            state = state * 1664525U + 1013904223U;
        }
        g_sink.store(state, std::memory_order_relaxed);
        r->other_finished.store(true);
    }
}

}  // namespace

// verifies: SR-GEN-008
TEST_CASE("worker pool: concurrency() is the worker count, the caller included") {
    for (const std::size_t n : {1U, 2U, 3U, 4U, 8U, 16U}) {
        const WorkerPool pool(n);
        CHECK(pool.concurrency() == n);
    }
}

// verifies: SR-GEN-003
TEST_CASE("worker pool: a worker count outside [1, 16] is a contract violation") {
    CHECK(test::violates_contract([] { const WorkerPool pool(0U); }));
    CHECK(test::violates_contract([] { const WorkerPool pool(kMaxWorkers + 1U); }));
}

// verifies: SR-GEN-008
TEST_CASE("worker pool: every index runs exactly once, for few and many tasks, count 0 included") {
    constexpr std::size_t kSlack = 8U;  // slots past count: must stay untouched
    for (const std::size_t workers : {1U, 2U, 3U, 4U, 8U}) {
        WorkerPool pool(workers);
        for (const std::size_t count : {0U, 1U, 2U, 3U, 5U, 7U, 8U, 9U, 16U, 17U, 100U, 1000U, 4097U}) {
            RunCounts runs(count + kSlack);
            pool.run(count, &count_task, &runs);
            std::size_t wrong = 0U;
            for (std::size_t i = 0U; i < runs.counts.size(); ++i) {
                wrong += runs.counts[i].load() == (i < count ? 1U : 0U) ? 0U : 1U;
            }
            INFO("workers ", workers, " count ", count);
            CHECK(wrong == 0U);
        }
    }
}

// verifies: SR-GEN-008
TEST_CASE("worker pool: 1,000 runs in a row each finish before run() returns") {
    constexpr std::size_t kMaxCount = 37U;
    WorkerPool pool(4U);
    std::array<std::uint32_t, kMaxCount> slots{};
    std::array<std::uint32_t, kMaxCount> expected{};
    for (std::size_t r = 0U; r < 1000U; ++r) {
        const std::size_t count = r % kMaxCount;  // 0 .. 36: below, at and above the worker count
        pool.run(count, &slow_increment_task, slots.data());
        for (std::size_t i = 0U; i < count; ++i) {
            ++expected[i];
        }
        if (slots != expected) {
            break;  // a task still running or lost: stop at the first run that shows it
        }
    }
    CHECK(slots == expected);
}

// verifies: SR-GEN-008
TEST_CASE("worker pool: 1, 2, 3 and 4 workers give SequentialRunner's bits") {
    SequentialRunner sequential;
    for (const std::size_t count : {1U, 3U, 64U, 1001U}) {
        const std::uint32_t reference = series_bits(sequential, count);
        for (const std::size_t workers : {1U, 2U, 3U, 4U}) {
            WorkerPool pool(workers);
            INFO("workers ", workers, " count ", count);
            CHECK(series_bits(pool, count) == reference);
            CHECK(series_bits(pool, count) == reference);  // and again on the same pool
        }
    }
    // The check can fail: another order of the same additions changes the bits.
    Series s{std::vector<float>(1001U, 0.0F)};
    sequential.run(s.slots.size(), &series_task, &s);
    float forward = 0.0F;
    float backward = 0.0F;
    for (std::size_t i = 0U; i < s.slots.size(); ++i) {
        forward += s.slots[i];
        backward += s.slots[s.slots.size() - 1U - i];
    }
    CHECK(std::memcmp(&forward, &backward, sizeof(float)) != 0);
}

// verifies: SR-GEN-008
TEST_CASE("worker pool: with two workers two tasks run at the same time, and run() waits for both") {
    WorkerPool pool(2U);
    Rendezvous r;
    pool.run(2U, &rendezvous_task, &r);
    CHECK(r.met.load() == 2);        // a pool that ran them one after another would leave 0
    CHECK(r.other_finished.load());  // run() waited for the worker's task
}

// verifies: SR-GEN-002
TEST_CASE("worker pool: 1,000 runs allocate nothing, on any thread") {
    WorkerPool pool(4U);
    std::array<std::uint32_t, 64U> slots{};
    pool.run(slots.size(), &increment_task, slots.data());  // the threads have started and run once
    const test::AllocationScope scope;
    for (std::size_t r = 0U; r < 1000U; ++r) {
        pool.run(slots.size() - r % 5U, &increment_task, slots.data());
    }
    const std::size_t allocations = scope.allocations();
    CHECK(allocations == 0U);
    CHECK(slots[0] == 1001U);
    // The counter sees the pool's own allocations: starting threads allocates.
    const test::AllocationScope start;
    { const WorkerPool other(2U); }
    CHECK(start.allocations() > 0U);
}

// verifies: SR-GEN-008
TEST_CASE("worker pool: a worker is pinned to a CPU the process may use, bad indices are refused") {
    WorkerPool pool(2U);
    CHECK(pool.pin_worker(2U, 0) == PinError::kNoSuchWorker);
    CHECK(pool.pin_worker(1U, -1) == PinError::kNoSuchCpu);
    CHECK(pool.pin_worker(1U, 1 << 20) == PinError::kNoSuchCpu);
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    REQUIRE(sched_getaffinity(0, sizeof(allowed), &allowed) == 0);
    int cpu = 0;
    while (cpu < CPU_SETSIZE && CPU_ISSET(static_cast<std::size_t>(cpu), &allowed) == 0) {
        ++cpu;
    }
    REQUIRE(cpu < CPU_SETSIZE);
    CHECK(pool.pin_worker(1U, cpu) == PinError::kOk);
    std::array<std::uint32_t, 16U> slots{};
    pool.run(slots.size(), &increment_task, slots.data());
    CHECK(slots == std::array<std::uint32_t, 16U>{1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U, 1U});
    CHECK(std::strlen(to_string(PinError::kRefused)) > 0U);
}
