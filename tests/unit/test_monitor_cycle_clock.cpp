// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monitor's clock passes a stuck CLOCK_MONOTONIC through to
// the controller when paced, so the safety logic sees it (H-CLK-1).
#include <doctest/doctest.h>

#include <cstdint>

#include "cellguard/monitor/cycle_clock.hpp"
#include "settable_clock.hpp"

using namespace cellguard;
using test::SettableClock;

// verifies: SR-LOGIC-007
TEST_CASE("monitor clock: paced, a source clock that stops or steps back is passed through unchanged") {
    SettableClock source(1000U);
    monitor::CycleClock clock(true, source);
    clock.start_cycle(0U);
    CHECK(clock.base() == 1000U);
    CHECK(clock.now_us() == 1000U);
    CHECK(clock.now_us() == 1000U);  // stopped: the same value again, not one made up
    source.t = 900U;
    CHECK(clock.now_us() == 900U);  // stepped back: seen as such
    source.t = 5000U;
    clock.start_cycle(123U);  // the simulated time is ignored when paced
    CHECK(clock.base() == 5000U);
}

// verifies: SR-LOGIC-007
TEST_CASE("monitor clock: unpaced, a cycle's first reading is its simulated start, and time never repeats") {
    SettableClock source(1000U);
    monitor::CycleClock clock(false, source);
    clock.start_cycle(100000U);
    CHECK(clock.base() == 100000U);
    source.t += 40U;  // the host is slow to start the cycle: it does not count
    CHECK(clock.now_us() == 100000U);
    source.t += 250U;  // real time passes within the cycle
    CHECK(clock.now_us() == 100250U);
    CHECK(clock.now_us() == 100251U);  // the source stood still: the simulated clock still moves
    clock.start_cycle(200000U);
    CHECK(clock.base() == 200000U);
    clock.start_cycle(150000U);  // a start before the last reading is moved after it
    CHECK(clock.base() > 100251U);
}

// verifies: SR-LOGIC-007, SR-LOGIC-006
TEST_CASE("monitor clock: paced, a stuck CLOCK_MONOTONIC latches the controller's clock fault") {
    SettableClock source(1000U);
    monitor::CycleClock clock(true, source);
    SafetyLogicConfig config;
    config.restart_delay_us = 0U;
    std::uint32_t mask[8] = {};
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.5, GridDims{2, 2, 2}).value();
    const CompiledZones zones = CompiledZones::compile(g, {}, {mask, 8U}).value();
    SafetyLogic logic(config, zones);
    ZoneEvaluation none;
    SafetyInputs in;
    in.zones = &none;
    clock.start_cycle(0U);
    in.now_us = clock.now_us();
    (void)logic.step(in);
    clock.start_cycle(0U);  // the next cycle, but the source has not moved
    in.now_us = clock.now_us();
    const SafetyOutputs out = logic.step(in);
    CHECK((out.latched_faults & fault_bit(Fault::kClockFault)) != 0U);
    CHECK(out.stop_requested);
}
