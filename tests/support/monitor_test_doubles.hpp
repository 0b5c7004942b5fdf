// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Doubles for the tests that run the monitor's loop: a clock that steps on
// every reading and a CAN sender that counts what it is given.
#ifndef CELLGUARD_TESTS_MONITOR_TEST_DOUBLES_HPP
#define CELLGUARD_TESTS_MONITOR_TEST_DOUBLES_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/can/can_sender.hpp"
#include "cellguard/safety/clock.hpp"

namespace cellguard::test {

/// A clock that advances 10 us (or @ref step) per reading, from 5 s.
class SteppingClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return now += step; }
    std::uint64_t now = 5000000U;  ///< the last reading, microseconds
    std::uint64_t step = 10U;      ///< microseconds per reading (a large one: a slow, loaded host)
};

/// Accepts every frame and counts them.
class CountingSender final : public CanSender {
public:
    bool send(const CanFrame& /*frame*/) noexcept override {
        ++frames;
        return true;
    }
    std::size_t frames = 0U;  ///< frames sent
};

}  // namespace cellguard::test

#endif
