// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file clock.hpp
/// The Linux monotonic clock for the cycle executive: clock_gettime(CLOCK_MONOTONIC)
/// in microseconds (not affected by wall-clock changes or NTP steps).
#ifndef CELLGUARD_PORT_CLOCK_HPP
#define CELLGUARD_PORT_CLOCK_HPP

#include <cstdint>

#include "cellguard/safety/clock.hpp"

namespace cellguard::linux_port {

/// CLOCK_MONOTONIC in microseconds, 0 if the call fails: the one reading of it
/// that the Linux port and the programs on it share (stage and latency timing,
/// camera receive times, pacing of threads).
[[nodiscard]] std::uint64_t monotonic_now_us() noexcept;

/// The calling thread's CPU time (CLOCK_THREAD_CPUTIME_ID) in microseconds, 0
/// if the call fails: the work a thread did, without the time it waited for a
/// core (the monitor's cycle figures beside the wall clock's, the benchmarks).
[[nodiscard]] std::uint64_t thread_cpu_now_us() noexcept;

/// CLOCK_MONOTONIC in microseconds; 0 if the call fails (the controller then sees
/// a clock that does not advance and latches its clock fault).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class LinuxMonotonicClock final : public MonotonicClock {
public:
    /// Microseconds of CLOCK_MONOTONIC.
    std::uint64_t now_us() noexcept override;
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_CLOCK_HPP
