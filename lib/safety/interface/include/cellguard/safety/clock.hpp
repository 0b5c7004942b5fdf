// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file clock.hpp
/// The clock a port provides to the cycle executive. A small interface
/// header: a port's clock compiles it without the controller.
#ifndef CELLGUARD_SAFETY_CLOCK_HPP
#define CELLGUARD_SAFETY_CLOCK_HPP

#include <cstdint>

namespace cellguard {

/// A monotonic clock in microseconds, provided by the port.
class MonotonicClock {
public:
    /// Microseconds since an arbitrary fixed start; never decreases on a healthy clock.
    virtual std::uint64_t now_us() noexcept = 0;

protected:
    MonotonicClock() = default;
    ~MonotonicClock() = default;
    MonotonicClock(const MonotonicClock&) = default;
    MonotonicClock& operator=(const MonotonicClock&) = default;
    MonotonicClock(MonotonicClock&&) = default;
    MonotonicClock& operator=(MonotonicClock&&) = default;
};

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_CLOCK_HPP
