// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/port/clock.hpp"

#include <ctime>

namespace cellguard::linux_port {

std::uint64_t LinuxMonotonicClock::now_us() noexcept { return monotonic_now_us(); }

std::uint64_t monotonic_now_us() noexcept {
    timespec ts{};
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0 || ts.tv_sec < 0 || ts.tv_nsec < 0) {
        return 0U;
    }
    return static_cast<std::uint64_t>(ts.tv_sec) * 1000000U + static_cast<std::uint64_t>(ts.tv_nsec) / 1000U;
}

}  // namespace cellguard::linux_port
