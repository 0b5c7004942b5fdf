// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monotone bucket queue pops items in key order (across
// fine and coarse buckets), re-files decreased keys, and refuses small storage.
#include <doctest/doctest.h>

#include <sys/mman.h>

#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "cellguard/prior/bucket_queue.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

struct QueueStorage {
    explicit QueueStorage(std::size_t items)
        : keys(items, 0U),
          next(MonotoneBucketQueue::link_count(items), 0U),
          prev(MonotoneBucketQueue::link_count(items), 0U) {}
    MonotoneBucketQueue make() {
        return MonotoneBucketQueue::make(Span<const std::uint32_t>(keys.data(), keys.size()),
                                         Span<std::uint32_t>(next.data(), next.size()),
                                         Span<std::uint32_t>(prev.data(), prev.size()))
            .value();
    }
    std::vector<std::uint32_t> keys;
    std::vector<std::uint32_t> next;
    std::vector<std::uint32_t> prev;
};

}  // namespace

// verifies: SR-PRIOR-002
TEST_CASE("bucket queue: link storage smaller than the items plus the list heads is refused") {
    std::vector<std::uint32_t> keys(10U);
    std::vector<std::uint32_t> links(MonotoneBucketQueue::link_count(10U));
    std::vector<std::uint32_t> short_links(MonotoneBucketQueue::link_count(10U) - 1U);
    const Span<const std::uint32_t> k(keys.data(), keys.size());
    CHECK(MonotoneBucketQueue::make(k, Span<std::uint32_t>(short_links.data(), short_links.size()),
                                    Span<std::uint32_t>(links.data(), links.size()))
              .error() == ErrorCode::kStorageTooSmall);
    CHECK(MonotoneBucketQueue::make(k, Span<std::uint32_t>(links.data(), links.size()),
                                    Span<std::uint32_t>(short_links.data(), short_links.size()))
              .error() == ErrorCode::kStorageTooSmall);
    std::vector<std::uint32_t> links2(MonotoneBucketQueue::link_count(10U));
    CHECK(MonotoneBucketQueue::make(k, Span<std::uint32_t>(links.data(), links.size()),
                                    Span<std::uint32_t>(links2.data(), links2.size()))
              .ok());
}

// verifies: SR-PRIOR-002
TEST_CASE("bucket queue: items come out in key order, across fine and coarse buckets") {
    const std::vector<std::uint32_t> keys = {
        5U, 0U, 2047U, 2048U, 4095U, 1U << 20U, MonotoneBucketQueue::kKeyLimit - 1U, 3U, 5U, 2048U + 7U};
    QueueStorage s(keys.size());
    s.keys = keys;
    MonotoneBucketQueue q = s.make();
    CHECK(q.empty());
    for (std::uint32_t i = 0U; i < keys.size(); ++i) {
        q.push(i);
    }
    CHECK(q.size() == keys.size());
    std::vector<std::uint32_t> popped;
    while (!q.empty()) {
        const std::uint32_t item = q.pop();
        popped.push_back(keys[item]);
        CHECK(q.last_key() == keys[item]);
    }
    const std::vector<std::uint32_t> sorted = {0U,    3U,    5U,    5U,        2047U,
                                               2048U, 2055U, 4095U, 1U << 20U, MonotoneBucketQueue::kKeyLimit - 1U};
    CHECK(popped == sorted);
}

// verifies: SR-PRIOR-002
TEST_CASE("bucket queue: a decreased key is popped at its new key, also from a coarse bucket") {
    QueueStorage s(3U);
    MonotoneBucketQueue q = s.make();
    s.keys = {100U, 50000U, 70000U};
    q.push(0U);
    q.push(1U);
    q.push(2U);
    CHECK(q.pop() == 0U);
    s.keys[2] = 150U;  // from a coarse bucket into the current fine window
    q.decrease(2U);
    s.keys[1] = 40000U;  // from one coarse bucket to another
    q.decrease(1U);
    CHECK(q.pop() == 2U);
    CHECK(q.pop() == 1U);
    CHECK(q.last_key() == 40000U);
    CHECK(q.empty());
}

// verifies: SR-PRIOR-002
TEST_CASE("bucket queue: random Dijkstra-like use agrees with an ordered set") {
    std::mt19937 rng(7U);
    for (int trial = 0; trial < 20; ++trial) {
        const std::size_t n = 3000U;
        QueueStorage s(n);
        MonotoneBucketQueue q = s.make();
        std::set<std::pair<std::uint32_t, std::uint32_t>> reference;
        std::vector<int> state(n, 0);  // 0 new, 1 queued, 2 popped
        std::uint32_t next_new = 0U;
        const std::uint32_t spread = trial % 2 == 0 ? 300U : 400000U;
        auto push_new = [&](std::uint32_t base) {
            if (next_new == n)
                return;
            const std::uint32_t item = next_new++;
            s.keys[item] = std::min<std::uint32_t>(base + rng() % spread, MonotoneBucketQueue::kKeyLimit - 1U);
            q.push(item);
            state[item] = 1;
            reference.insert({s.keys[item], item});
        };
        for (int i = 0; i < 50; ++i)
            push_new(0U);
        while (!reference.empty()) {
            const std::uint32_t item = q.pop();
            REQUIRE(state[item] == 1);
            REQUIRE(s.keys[item] == reference.begin()->first);
            reference.erase({s.keys[item], item});
            state[item] = 2;
            const std::uint32_t last = q.last_key();
            const int pushes = static_cast<int>(rng() % 4U);
            for (int i = 0; i < pushes; ++i)
                push_new(last);
            // Lower a few queued keys, never below the last pop.
            for (int i = 0; i < 3 && !reference.empty(); ++i) {
                auto it = reference.begin();
                std::advance(it, static_cast<long>(rng() % reference.size()));
                const auto [key, victim] = *it;
                if (key == last)
                    continue;
                const std::uint32_t lowered = last + rng() % (key - last);
                reference.erase(it);
                s.keys[victim] = lowered;
                q.decrease(victim);
                reference.insert({lowered, victim});
            }
            CHECK(q.size() == reference.size());
        }
        CHECK(q.empty());
    }
}

// verifies: SR-PRIOR-002, SR-GEN-003
TEST_CASE("bucket queue: popping an empty queue violates a contract") {
    QueueStorage s(2U);
    MonotoneBucketQueue q = s.make();
    CHECK(test::violates_contract([&] { (void)q.pop(); }));
}

// verifies: SR-PRIOR-002
TEST_CASE("bucket queue: more items than 32-bit links can index are refused before any key is read") {
    if constexpr (sizeof(std::size_t) > 4U) {
        // kMaxItems + 1 keys of address space that is reserved but not readable: a read would fault.
        const std::size_t items = MonotoneBucketQueue::kMaxItems + 1U;
        const std::size_t bytes = items * sizeof(std::uint32_t);
        void* const reserved = ::mmap(nullptr, bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
        REQUIRE(reserved != MAP_FAILED);
        std::vector<std::uint32_t> links(16U);
        const Span<std::uint32_t> l(links.data(), links.size());
        const Span<const std::uint32_t> keys(static_cast<const std::uint32_t*>(reserved), items);
        CHECK(MonotoneBucketQueue::make(keys, l, l).error() == ErrorCode::kCapacityExceeded);
        CHECK(MonotoneBucketQueue::make(keys.subspan(0U, 8U), l, l).error() == ErrorCode::kStorageTooSmall);
        CHECK(::munmap(reserved, bytes) == 0);
    }
}
