// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the Linux port's FrameSignal (frame_signal.hpp) wakes the
// waiter when a frame is published, never loses a notify between the
// waiter's look and its sleep, and never returns "no frame" before the deadline.
#include <doctest/doctest.h>

#include <atomic>
#include <cstdint>
#include <thread>

#include "alloc_counter.hpp"
#include "cellguard/port/clock.hpp"
#include "cellguard/port/frame_signal.hpp"

using namespace cellguard::linux_port;

// verifies: SR-CAM-010
TEST_CASE("frame signal: a notify changes the value, and a wait after an older value returns at once") {
    FrameSignal signal;
    const std::uint32_t before = signal.value();
    const std::size_t allocations = cellguard::test::thread_allocation_count();
    signal.notify();
    CHECK(signal.value() == before + 1U);
    // Already changed: true without sleeping, even with a deadline in the past.
    CHECK(signal.wait_after(before, 0U));
    // Unchanged and the deadline over: false at once.
    CHECK_FALSE(signal.wait_after(signal.value(), monotonic_now_us()));
    CHECK(cellguard::test::thread_allocation_count() == allocations);
}

// verifies: SR-CAM-010
TEST_CASE("frame signal: without a notify the wait ends at its deadline, never before") {
    FrameSignal signal;
    const std::uint64_t deadline = monotonic_now_us() + 30000U;
    CHECK_FALSE(signal.wait_after(signal.value(), deadline));
    CHECK(monotonic_now_us() >= deadline);
}

// verifies: SR-CAM-010
TEST_CASE("frame signal: a notify from another thread wakes the waiter before its deadline") {
    FrameSignal signal;
    std::atomic<bool> waiting{false};
    const std::uint32_t seen = signal.value();
    std::thread camera([&] {
        while (!waiting.load()) {
            std::this_thread::yield();
        }
        signal.notify();  // before, during or after the sleep: the waiter must see it
    });
    waiting.store(true);
    const std::uint64_t deadline = monotonic_now_us() + 60000000U;  // a minute: only a lost notify reaches it
    const bool woke = signal.wait_after(seen, deadline);
    camera.join();
    CHECK(woke);
    CHECK(monotonic_now_us() < deadline);
}

// verifies: SR-CAM-010
TEST_CASE("frame signal: many notifies from several threads are never lost to a waiter that keeps looking") {
    FrameSignal signal;
    constexpr int kThreads = 4;
    constexpr int kEach = 2000;
    std::thread threads[kThreads];
    for (std::thread& t : threads) {
        t = std::thread([&] {
            for (int i = 0; i < kEach; ++i) {
                signal.notify();
            }
        });
    }
    // The waiter follows the count until it has seen every notify; a minute per wait bounds a lost wake.
    std::uint32_t seen = 0U;
    bool all_woke = true;
    while (seen != static_cast<std::uint32_t>(kThreads * kEach) && all_woke) {
        all_woke = signal.wait_after(seen, monotonic_now_us() + 60000000U);
        seen = signal.value();
    }
    for (std::thread& t : threads) {
        t.join();
    }
    CHECK(all_woke);
    CHECK(signal.value() == static_cast<std::uint32_t>(kThreads * kEach));
}
