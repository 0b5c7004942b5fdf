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
TEST_CASE("monitor clock: unpaced, a cycle's readings are its simulated start plus one microsecond each") {
    SettableClock source(1000U);
    monitor::CycleClock clock(false, source);
    clock.start_cycle(100000U);
    CHECK(clock.base() == 100000U);
    source.t += 40U;  // the host is slow to start the cycle: it does not count
    CHECK(clock.now_us() == 100000U);
    source.t += 250000U;               // a loaded host: a quarter second passes within the cycle
    CHECK(clock.now_us() == 100001U);  // simulated time only: the decisions do not see it
    CHECK(clock.now_us() == 100002U);  // the source stood still: the simulated clock still moves
    // The real time between readings is kept for the cycle-time figures.
    CHECK(clock.real_span_us(100000U, 100001U) == 250000U);
    CHECK(clock.real_span_us(100000U, 100002U) == 250000U);
    CHECK(clock.real_span_us(100001U, 100002U) == 0U);
    CHECK(clock.real_span_us(100002U, 100000U) == 0U);  // not after: none
    CHECK(clock.real_span_us(100000U, 100003U) == 0U);  // not a reading yet: none
    CHECK(clock.real_span_us(99999U, 100001U) == 0U);   // before the cycle: none
    clock.start_cycle(200000U);
    CHECK(clock.base() == 200000U);
    CHECK(clock.now_us() == 200000U);
    clock.start_cycle(150000U);  // a start before the last reading is moved after it
    CHECK(clock.base() > 200000U);
}

// verifies: SR-LOGIC-007
TEST_CASE("monitor clock: unpaced, a cycle with more readings than are kept still never repeats a value") {
    SettableClock source(1000U);
    monitor::CycleClock clock(false, source);
    clock.start_cycle(0U);
    const std::uint64_t b = clock.base();  // 1: after the clock's initial value, 0
    std::uint64_t last = clock.now_us();
    CHECK(last == b);
    for (int i = 0; i < 200; ++i) {
        source.t += 7U;
        const std::uint64_t v = clock.now_us();
        CHECK(v == last + 1U);
        last = v;
    }
    CHECK(clock.real_span_us(b, b + 63U) == 63U * 7U);  // the first 64 readings keep their real time
    CHECK(clock.real_span_us(b, b + 64U) == 0U);        // later ones do not
    clock.start_cycle(100U);                            // within the last cycle's readings: moved after them
    CHECK(clock.base() == last + 1U);
}

// verifies: SR-LOGIC-007
TEST_CASE("monitor clock: for a measurement, simulated cycle starts and the real time within a cycle") {
    SettableClock source(1000U);
    monitor::CycleClock clock(monitor::CycleClock::Mode::kSimulatedWithRealElapsed, source);
    clock.start_cycle(100000U);
    source.t += 40U;  // before the cycle's first reading: it does not count
    CHECK(clock.now_us() == 100000U);
    source.t += 250U;
    CHECK(clock.now_us() == 100250U);
    CHECK(clock.now_us() == 100251U);  // the source stood still: still no repeated value
    CHECK(clock.real_span_us(100000U, 100250U) == 250U);
    clock.start_cycle(100100U);  // a start before the last reading is moved after it
    CHECK(clock.base() == 100252U);
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
