// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the Linux port's clocks (clock.hpp): CLOCK_MONOTONIC in
// microseconds never goes back, and the thread's CPU time counts the
// thread's own work, not the time it slept.
#include <doctest/doctest.h>

#include <time.h>

#include <cstdint>

#include "cellguard/port/clock.hpp"

using namespace cellguard::linux_port;

// verifies: SR-CAM-007
TEST_CASE("port clock: the thread's CPU time grows with its work and not while it sleeps") {
    const std::uint64_t wall0 = monotonic_now_us();
    const std::uint64_t cpu0 = thread_cpu_now_us();
    REQUIRE(wall0 != 0U);
    REQUIRE(cpu0 != 0U);
    // Busy until the thread has used 20 ms of CPU (however long that takes on a loaded host).
    volatile std::uint64_t sink = 0U;
    while (thread_cpu_now_us() - cpu0 < 20000U) {
        for (int i = 0; i < 10000; ++i) {
            sink = sink + static_cast<std::uint64_t>(i);
        }
    }
    const std::uint64_t cpu1 = thread_cpu_now_us();
    const std::uint64_t wall1 = monotonic_now_us();
    CHECK(cpu1 - cpu0 >= 20000U);
    CHECK(wall1 - wall0 >= cpu1 - cpu0);  // a thread cannot use more CPU than time passed
    // 100 ms asleep: the wall clock moves by at least that, the CPU time by far less.
    const timespec nap{0, 100000000L};
    static_cast<void>(nanosleep(&nap, nullptr));
    const std::uint64_t cpu2 = thread_cpu_now_us();
    const std::uint64_t wall2 = monotonic_now_us();
    CHECK(wall2 - wall1 >= 100000U);
    CHECK(cpu2 - cpu1 < 50000U);
}
