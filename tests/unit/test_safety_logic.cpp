// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: protective stop, warning, restart interlock, fault latching
// and recovery, clock monitoring; only the active monitoring case's zones
// count; speed and separation monitoring's stop and reduced speed.
#include <doctest/doctest.h>

#include <vector>

#include "cellguard/safety/robot_command.hpp"
#include "cellguard/safety/safety_logic.hpp"
#include "contract_capture.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {
struct Cell {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{4, 4, 4}).value();
    std::vector<std::uint32_t> mask = std::vector<std::uint32_t>(64);
    CompiledZones zones;
    ZoneEvaluation eval;
    std::uint64_t now = 1000U;
    std::uint32_t active = 0xFFFFFFFFU;        // the active case's zones
    SpeedRequest speed = SpeedRequest::kFull;  // the separation's request
    Cell() {
        ZoneConfig protective;
        protective.box_max = Eigen::Vector3d(0.2, 0.2, 0.2);
        ZoneConfig warning = protective;
        warning.kind = ZoneKind::kWarning;
        warning.box_max = Eigen::Vector3d(0.4, 0.4, 0.4);
        const ZoneConfig zs[] = {protective, warning};
        zones = CompiledZones::compile(g, zs, {mask.data(), mask.size()}).value();
        set(ZoneState::kClear, ZoneState::kClear);
    }
    void set(ZoneState protective, ZoneState warning) {
        eval = ZoneEvaluation{};
        eval.count = 2U;
        eval.zones[0].state = protective;
        eval.zones[1].state = warning;
        for (std::uint32_t z = 0; z < 2U; ++z) {
            const ZoneState s = eval.zones[z].state;
            if (s == ZoneState::kIntruded)
                eval.intruded_mask |= 1U << z;
            if (s == ZoneState::kUnseen)
                eval.unseen_mask |= 1U << z;
            if (s != ZoneState::kClear)
                eval.not_clear_mask |= 1U << z;
        }
    }
    SafetyOutputs step(SafetyLogic& logic, std::uint32_t faults = 0U, bool reset = false, std::uint64_t dt = 10000U) {
        now += dt;
        SafetyInputs in;
        in.now_us = now;
        in.zones = &eval;
        in.detected_faults = faults;
        in.reset_input = reset;
        in.active_zones = active;
        in.speed_request = speed;
        return logic.step(in);
    }
};
SafetyLogicConfig config(std::uint64_t delay_us, bool reset) {
    SafetyLogicConfig c;
    c.restart_delay_us = delay_us;
    c.reset_required = reset;
    c.fault_recovery_cycles = 3U;
    return c;
}
}  // namespace

// verifies: SR-LOGIC-001
TEST_CASE("safety logic: the stop is requested at start-up until the restart interlock releases it") {
    Cell c;
    SafetyLogic logic(config(50000U, false), c.zones);
    CHECK(logic.outputs().stop_requested);
    CHECK(c.step(logic).stop_requested);  // t = 0 of the clear period
    for (int i = 0; i < 4; ++i)
        CHECK(c.step(logic).stop_requested);    // 40 ms < 50 ms
    CHECK_FALSE(c.step(logic).stop_requested);  // 50 ms
}

// verifies: SR-LOGIC-002
TEST_CASE("safety logic: an intrusion of a protective zone requests a stop in the same cycle") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    CHECK_FALSE(c.step(logic).stop_requested);
    c.set(ZoneState::kIntruded, ZoneState::kClear);
    const SafetyOutputs o = c.step(logic);
    CHECK(o.stop_requested);
    CHECK(o.intruded_mask == 1U);
    c.set(ZoneState::kUnseen, ZoneState::kClear);  // unseen is not clear either
    CHECK(c.step(logic).stop_requested);
}

// verifies: SR-LOGIC-003
TEST_CASE("safety logic: a warning zone raises a warning but no stop") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    (void)c.step(logic);
    c.set(ZoneState::kClear, ZoneState::kIntruded);
    const SafetyOutputs o = c.step(logic);
    CHECK(o.warning);
    CHECK_FALSE(o.stop_requested);
    c.set(ZoneState::kClear, ZoneState::kClear);
    CHECK_FALSE(c.step(logic).warning);  // no interlock on warnings
}

// verifies: SR-LOGIC-004
TEST_CASE("safety logic: the restart interlock keeps the stop for its full time, restarting on any interruption") {
    Cell c;
    SafetyLogic logic(config(100000U, false), c.zones);  // 100 ms
    c.set(ZoneState::kIntruded, ZoneState::kClear);
    (void)c.step(logic);
    c.set(ZoneState::kClear, ZoneState::kClear);
    for (int i = 0; i < 5; ++i)
        CHECK(c.step(logic).stop_requested);         // 0..40 ms clear
    c.set(ZoneState::kIntruded, ZoneState::kClear);  // interrupted
    CHECK(c.step(logic).stop_requested);
    c.set(ZoneState::kClear, ZoneState::kClear);
    int cycles = 0;
    while (c.step(logic).stop_requested) {
        ++cycles;
        REQUIRE(cycles < 100);
    }
    CHECK(cycles == 10);  // the full 100 ms again, counted from the interruption's end
}

// verifies: SR-LOGIC-004
TEST_CASE("safety logic: with reset required, only a rising edge after the delay releases the stop") {
    Cell c;
    SafetyLogic logic(config(20000U, true), c.zones);
    CHECK(c.step(logic, 0U, true).stop_requested);  // reset held high before the delay: no edge later
    CHECK(c.step(logic, 0U, true).stop_requested);
    CHECK(c.step(logic, 0U, true).stop_requested);  // delay over, but the input never rose
    CHECK(c.step(logic, 0U, false).stop_requested);
    CHECK_FALSE(c.step(logic, 0U, true).stop_requested);  // rising edge after the delay
}

// verifies: SR-LOGIC-004
TEST_CASE("safety logic: by default the restart needs the reset edge, the clear zones and the delay are not enough") {
    Cell c;
    SafetyLogicConfig defaults;
    CHECK(defaults.reset_required);
    defaults.restart_delay_us = 0U;
    SafetyLogic logic(defaults, c.zones);
    for (int k = 0; k < 5; ++k) {
        CHECK(c.step(logic, 0U, false).stop_requested);  // clear, delay over, no reset: the stop holds
    }
    CHECK_FALSE(c.step(logic, 0U, true).stop_requested);  // the rising edge releases it
}

// verifies: SR-LOGIC-005
TEST_CASE("safety logic: a recoverable fault latches the safe state and clears after fault-free cycles") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    CHECK_FALSE(c.step(logic).stop_requested);
    SafetyOutputs o = c.step(logic, fault_bit(Fault::kSensorStale));
    CHECK(o.stop_requested);
    CHECK(o.latched_faults == fault_bit(Fault::kSensorStale));
    CHECK(o.fault_zone_mask == 0b11U);
    CHECK(o.warning);                     // warning zones are FAULT too
    CHECK(c.step(logic).stop_requested);  // 1 clean cycle
    CHECK(c.step(logic).stop_requested);  // 2
    o = c.step(logic);                    // 3: cleared, then the interlock (0 delay) releases
    CHECK(o.latched_faults == 0U);
    CHECK_FALSE(o.stop_requested);
}

// verifies: SR-LOGIC-005
TEST_CASE("safety logic: a fault detected again restarts its recovery count") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    (void)c.step(logic, fault_bit(Fault::kCanError));
    (void)c.step(logic);
    (void)c.step(logic);
    CHECK(c.step(logic, fault_bit(Fault::kCanError)).stop_requested);
    CHECK(c.step(logic).stop_requested);
    CHECK(c.step(logic).stop_requested);
    CHECK_FALSE(c.step(logic).stop_requested);
}

// verifies: SR-LOGIC-006
TEST_CASE("safety logic: non-recoverable faults stay latched") {
    for (const Fault f : {Fault::kPriorCheckFailed, Fault::kInternalCheck}) {
        Cell c;
        SafetyLogic logic(config(0U, false), c.zones);
        (void)c.step(logic, fault_bit(f));
        for (int i = 0; i < 50; ++i) {
            const SafetyOutputs o = c.step(logic, 0U, true);
            CHECK(o.stop_requested);
            CHECK((o.latched_faults & fault_bit(f)) != 0U);
        }
    }
}

// verifies: SR-LOGIC-007
TEST_CASE("safety logic: a clock that does not advance latches a clock fault") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    CHECK_FALSE(c.step(logic).stop_requested);
    const SafetyOutputs o = c.step(logic, 0U, false, 0U);  // same time again
    CHECK(o.stop_requested);
    CHECK((o.latched_faults & fault_bit(Fault::kClockFault)) != 0U);
}

// verifies: SR-LOGIC-008
TEST_CASE("safety logic: missing zone results are a fault") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    SafetyInputs in;
    in.now_us = 5U;
    const SafetyOutputs o = logic.step(in);
    CHECK(o.stop_requested);
    CHECK((o.latched_faults & fault_bit(Fault::kZoneEvaluation)) != 0U);
}

// verifies: SR-CASE-005
TEST_CASE("safety logic: only the active case's zones stop or warn, and the other zones' bits are 0 in every output") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    c.active = 0b10U;  // the warning zone only
    c.set(ZoneState::kIntruded, ZoneState::kClear);
    SafetyOutputs o = c.step(logic);
    CHECK_FALSE(o.stop_requested);  // the protective zone is not monitored in this case
    CHECK(o.intruded_mask == 0U);
    c.set(ZoneState::kUnseen, ZoneState::kIntruded);
    o = c.step(logic);
    CHECK_FALSE(o.stop_requested);
    CHECK(o.warning);
    CHECK(o.intruded_mask == 0b10U);
    CHECK(o.unseen_mask == 0U);
    // Faults: only the active zones are FAULT.
    o = c.step(logic, fault_bit(Fault::kSensorMissing));
    CHECK(o.stop_requested);
    CHECK(o.fault_zone_mask == 0b10U);
    // A case of the protective zone only: its intrusion stops, the warning zone is silent.
    c.active = 0b01U;
    c.set(ZoneState::kIntruded, ZoneState::kIntruded);
    o = c.step(logic);
    CHECK(o.stop_requested);
    CHECK_FALSE(o.warning);
    CHECK(o.intruded_mask == 0U);       // the fault is still latched (recovery takes 3 clean cycles):
    CHECK(o.fault_zone_mask == 0b01U);  // the active zones are FAULT
    // Bits beyond the zone count mean nothing.
    c.active = 0xFFFFFFFCU;
    for (int i = 0; i < 4; ++i)
        o = c.step(logic);
    CHECK(o.latched_faults == 0U);
    CHECK_FALSE(o.stop_requested);
    CHECK(o.intruded_mask == 0U);
}

// verifies: SR-CASE-006
TEST_CASE(
    "safety logic: switching to a case whose protective zone is intruded stops in that cycle, and switching away goes through the interlock") {
    Cell c;
    SafetyLogic logic(config(30000U, false), c.zones);  // 30 ms restart delay
    c.active = 0b10U;
    c.set(ZoneState::kIntruded, ZoneState::kClear);
    for (int i = 0; i < 4; ++i)
        (void)c.step(logic);
    CHECK_FALSE(c.step(logic).stop_requested);
    c.active = 0b11U;  // the case switches: the protective zone counts now
    CHECK(c.step(logic).stop_requested);
    c.active = 0b10U;  // and back: the interlock holds the stop for its delay
    CHECK(c.step(logic).stop_requested);
    CHECK(c.step(logic).stop_requested);
    CHECK(c.step(logic).stop_requested);
    CHECK_FALSE(c.step(logic).stop_requested);
}

// verifies: SR-SSM-020, SR-SSM-021
TEST_CASE("safety logic: a separation stop stops in the same cycle and resumes without the restart interlock") {
    Cell c;
    SafetyLogic logic(config(100000U, true), c.zones);  // 100 ms delay and a reset: neither applies to SSM
    for (int i = 0; i < 10; ++i)
        (void)c.step(logic);
    REQUIRE_FALSE(c.step(logic, 0U, true).stop_requested);  // released by the interlock once
    c.speed = SpeedRequest::kReduced;
    SafetyOutputs o = c.step(logic);
    CHECK_FALSE(o.stop_requested);
    CHECK(o.reduced_speed);
    CHECK_FALSE(o.separation_stop);
    c.speed = SpeedRequest::kProtectiveStop;
    o = c.step(logic);
    CHECK(o.stop_requested);
    CHECK(o.separation_stop);
    CHECK(o.reduced_speed);  // a stop asks for at most reduced speed too
    CHECK_FALSE(o.interlock_holding);
    CHECK(o.latched_faults == 0U);
    c.speed = SpeedRequest::kReduced;  // the distance grew again: resume at once, reduced
    o = c.step(logic);
    CHECK_FALSE(o.stop_requested);
    CHECK(o.reduced_speed);
    c.speed = SpeedRequest::kFull;
    o = c.step(logic);
    CHECK_FALSE(o.stop_requested);
    CHECK_FALSE(o.reduced_speed);
}

// verifies: SR-SSM-021
TEST_CASE("safety logic: a separation stop neither starts nor shortens the restart interlock of the zones") {
    Cell c;
    SafetyLogic logic(config(50000U, false), c.zones);  // 50 ms
    for (int i = 0; i < 6; ++i)
        (void)c.step(logic);
    REQUIRE_FALSE(c.step(logic).stop_requested);
    // A zone stop, then the zone clears while the separation asks for a stop.
    c.set(ZoneState::kIntruded, ZoneState::kClear);
    CHECK(c.step(logic).stop_requested);
    c.set(ZoneState::kClear, ZoneState::kClear);
    c.speed = SpeedRequest::kProtectiveStop;
    for (int i = 0; i < 3; ++i)
        CHECK(c.step(logic).stop_requested);    // 0..20 ms of the 50 ms
    c.speed = SpeedRequest::kFull;              // the separation clears: the interlock still runs
    CHECK(c.step(logic).stop_requested);        // 30 ms
    CHECK(c.step(logic).interlock_holding);     // 40 ms
    CHECK_FALSE(c.step(logic).stop_requested);  // 50 ms
}

// verifies: SR-SSM-020
TEST_CASE("safety logic: a speed request outside the enumeration is a stop") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    REQUIRE_FALSE(c.step(logic).stop_requested);
    for (const std::uint8_t raw : {3U, 0x7FU, 0xFFU}) {
        c.speed = static_cast<SpeedRequest>(raw);
        const SafetyOutputs o = c.step(logic);
        CHECK(o.stop_requested);
        CHECK(o.separation_stop);
        CHECK(o.reduced_speed);
    }
}

// verifies: SR-GEN-004
TEST_CASE("safety logic: every fault has its own name, and a code outside the enumeration is named unknown fault") {
    test::check_enum_names<Fault>(kFaultCount, "unknown fault");
}

// verifies: SR-LOGIC-008
TEST_CASE("safety logic: zone results for another number of zones are a fault, all active zones not clear") {
    Cell c;
    SafetyLogic logic(config(0U, false), c.zones);
    c.eval.count = 3U;  // the compiled zones are 2
    const SafetyOutputs o = c.step(logic);
    CHECK(o.stop_requested);
    CHECK((o.latched_faults & fault_bit(Fault::kZoneEvaluation)) != 0U);
    CHECK(o.fault_zone_mask == 0x3U);
    CHECK(o.intruded_mask == 0U);
}

// verifies: SR-LOGIC-005, SR-GEN-003
TEST_CASE("safety logic: a fault recovery of 0 cycles is a contract violation") {
    Cell c;
    CHECK_FALSE(test::violates_contract([&] { const SafetyLogic ok_logic(config(0U, false), c.zones); }));
    SafetyLogicConfig zero = config(0U, false);
    zero.fault_recovery_cycles = 0U;
    CHECK(test::violates_contract([&] { const SafetyLogic refused(zero, c.zones); }));
}

// verifies: SR-LOGIC-001, SR-CASE-005
TEST_CASE("safety logic: with 32 zones an intrusion of the last protective zone stops, unless its case is inactive") {
    Cell c;
    std::vector<ZoneConfig> zs(kMaxZones);
    for (ZoneConfig& z : zs) {
        z.box_max = Eigen::Vector3d(0.2, 0.2, 0.2);
    }
    c.zones = CompiledZones::compile(c.g, {zs.data(), zs.size()}, {c.mask.data(), c.mask.size()}).value();
    c.set(ZoneState::kClear, ZoneState::kClear);  // every zone clear
    c.eval.count = kMaxZones;
    SafetyLogic logic(config(0U, false), c.zones);
    CHECK_FALSE(c.step(logic).stop_requested);
    c.eval.zones[kMaxZones - 1U].state = ZoneState::kIntruded;
    c.eval.intruded_mask = 0x80000000U;
    c.eval.not_clear_mask = 0x80000000U;
    const SafetyOutputs o = c.step(logic);
    CHECK(o.stop_requested);
    CHECK(o.intruded_mask == 0x80000000U);
    c.active = 0x7FFFFFFFU;  // a case without zone 31
    const SafetyOutputs off = c.step(logic);
    CHECK(off.intruded_mask == 0U);
}
