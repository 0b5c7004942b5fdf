// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A MonotonicClock that reads whatever the test set: a clock that stops,
// steps back or jumps, for the tests of the controller and the monitor's clock.
#ifndef CELLGUARD_TESTS_SETTABLE_CLOCK_HPP
#define CELLGUARD_TESTS_SETTABLE_CLOCK_HPP

#include <cstdint>

#include "cellguard/safety/safety_controller.hpp"

namespace cellguard::test {

/// now_us() returns t, unchanged until the test changes it.
class SettableClock final : public MonotonicClock {
public:
    explicit SettableClock(std::uint64_t start_us) noexcept : t(start_us) {}
    std::uint64_t now_us() noexcept override { return t; }
    std::uint64_t t;  ///< the time every reading returns, microseconds
};

}  // namespace cellguard::test

#endif
