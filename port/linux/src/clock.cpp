// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/port/clock.hpp"

#include <ctime>

namespace cellguard::linux_port {

std::uint64_t LinuxMonotonicClock::now_us() noexcept { return monotonic_now_us(); }

namespace {

/// @p clock in microseconds, 0 if the call fails.
std::uint64_t now_us_of(clockid_t clock) noexcept {
    timespec ts{};
    if (clock_gettime(clock, &ts) != 0 || ts.tv_sec < 0 || ts.tv_nsec < 0) {
        return 0U;
    }
    return static_cast<std::uint64_t>(ts.tv_sec) * 1000000U + static_cast<std::uint64_t>(ts.tv_nsec) / 1000U;
}

}  // namespace

std::uint64_t monotonic_now_us() noexcept { return now_us_of(CLOCK_MONOTONIC); }

std::uint64_t thread_cpu_now_us() noexcept { return now_us_of(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace cellguard::linux_port
