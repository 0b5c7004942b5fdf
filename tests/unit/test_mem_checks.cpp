// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: memory diagnostics while running (hazards H-MEM-2, H-MEM-3):
// the CRC-32 tables tested in slices, the seals of the safety logic's and the
// controller's state and configuration copy, stack painting with a guard band
// (lib/base and port/linux), each found within its stated bound and latched.
#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/base/stack_paint.hpp"
#include "cellguard/base/state_seal.hpp"
#include "cellguard/port/stack.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/safety_logic.hpp"
#include "contract_capture.hpp"
#include "mem_test_access.hpp"

using namespace cellguard;

namespace {

class StepClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t += 1U; }
    std::uint64_t t = 1000000U;
};

// An 8 x 8 x 8 cell of 0.1 m with a prior that is background everywhere
// (never foreground, never unseen), a protective and a warning zone, and
// one point sensor: every cycle is clear, so the stop is released at once.
struct SmallCell {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{8, 8, 8}).value();
    std::vector<std::int16_t> frame_lo = std::vector<std::int16_t>(g.voxel_count());
    std::vector<std::uint8_t> frame_ob = std::vector<std::uint8_t>(g.voxel_count());
    std::vector<std::int16_t> scratch = std::vector<std::int16_t>(g.voxel_count());
    std::vector<std::int16_t> prior = std::vector<std::int16_t>(g.voxel_count(), -2000);
    std::vector<std::uint32_t> mask = std::vector<std::uint32_t>(g.voxel_count());
    EvidenceGrid grid;
    CompiledZones zones;
    SensorModelTable model;
    StepClock clock;
    std::array<Eigen::Vector3f, 1> points{Eigen::Vector3f(0.7F, 0.7F, 0.3F)};
    SmallCell() {
        grid = EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
        ZoneConfig protective;
        protective.box_min = Eigen::Vector3d(0.0, 0.5, 0.0);
        protective.box_max = Eigen::Vector3d(0.2, 0.8, 0.2);
        ZoneConfig warning = protective;
        warning.kind = ZoneKind::kWarning;
        warning.box_max = Eigen::Vector3d(0.3, 0.8, 0.3);
        const ZoneConfig zs[] = {protective, warning};
        zones = CompiledZones::compile(g, zs, {mask.data(), mask.size()}).value();
    }
    ControllerConfig config() const {
        ControllerConfig c;
        c.sensor_count = 1U;
        c.logic.restart_delay_us = 0U;
        c.logic.reset_required = false;  // no reset input here: a release follows the clear zones alone
        c.logic.fault_recovery_cycles = 2U;
        c.max_repeated_frames = 0U;  // the same simulated frame every cycle, by design
        c.cycle_budget_us = 10000000U;
        return c;
    }
    std::unique_ptr<SafetyController> controller(const ControllerConfig& c) {
        return std::make_unique<SafetyController>(c, grid, Span<std::int16_t>(scratch.data(), scratch.size()),
                                                  Span<const std::int16_t>(prior.data(), prior.size()), zones, model,
                                                  clock, nullptr);
    }
    const CycleReport& cycle(SafetyController& c) {
        SensorInput in;
        in.reading.pose.translation() = Eigen::Vector3d(0.05, 0.05, 0.05);
        in.reading.points = Span<const Eigen::Vector3f>(points.data(), points.size());
        in.present = true;
        in.captured_us = clock.t;
        return c.run_cycle(Span<const SensorInput>(&in, 1U), false);
    }
};

constexpr std::uint32_t kInternal = fault_bit(Fault::kInternalCheck);

}  // namespace

// verifies: SR-MEM-001
TEST_CASE("crc32 table check: a corrupted entry of a copy is found within one pass from any point of a pass") {
    for (const std::uint32_t per_step : {1U, 32U, 100U, 256U}) {
        const std::uint32_t pass = Crc32TableCheck::steps_per_pass(per_step);
        CHECK(pass == (256U + per_step - 1U) / per_step);
        for (const std::uint32_t start : {0U, 1U, pass / 2U, pass - 1U}) {
            const std::pair<int, int> spots[] = {{0, 0}, {7, 255}, {3, 128}, {5, 17}};
            for (const auto& [k, i] : spots) {
                auto copy = std::make_unique<Crc32Table>(kCrc32Table);
                Crc32TableCheck check(*copy);
                for (std::uint32_t s = 0U; s < start; ++s) {
                    REQUIRE_FALSE(check.step(per_step));
                }
                copy->slices[k][i] ^= 1U << 13U;
                std::uint32_t steps = 0U;
                while (!check.step(per_step) && steps < 4U * pass) {
                    ++steps;
                }
                CHECK(steps < pass);              // the step that found it is steps + 1 <= pass
                copy->slices[k][i] ^= 1U << 13U;  // repaired: the verdict stays
                CHECK(check.step(per_step));
                CHECK(check.failed());
            }
        }
    }
    // The tables in use pass every step of three passes.
    Crc32TableCheck intact;
    for (int s = 0; s < 3 * 256; ++s) {
        REQUIRE_FALSE(intact.step(1U));
    }
    CHECK(crc32_table_entries_intact(kCrc32Table, 250U, 100U));  // clipped at 256
    CHECK(test::violates_contract([] { static_cast<void>(Crc32TableCheck::steps_per_pass(0U)); }));
    CHECK(test::violates_contract([] { static_cast<void>(Crc32TableCheck::steps_per_pass(257U)); }));
}

// verifies: SR-MEM-001
TEST_CASE("controller: a corrupted CRC-32 table is kInternalCheck within 256 over crc_table_check_values cycles") {
    SmallCell cell;
    ControllerConfig cfg = cell.config();
    REQUIRE(cfg.crc_table_check_values == 32U);  // the default: a pass in 8 cycles
    auto copy = std::make_unique<Crc32Table>(kCrc32Table);
    auto c = cell.controller(cfg);
    SafetyControllerTestAccess::check_crc_table(*c, *copy);
    for (int k = 0; k < 16; ++k) {  // two passes over an intact copy: no fault
        const CycleReport& r = cell.cycle(*c);
        REQUIRE(r.detected_faults == 0U);
        REQUIRE_FALSE(r.safety.stop_requested);
    }
    copy->slices[2][200] ^= 0x80000000U;
    int cycles = 0;
    while (cycles < 64 && (cell.cycle(*c).detected_faults & kInternal) == 0U) {
        ++cycles;
    }
    CHECK(cycles + 1 <= 8);
    CHECK(c->report().safety.stop_requested);
    copy->slices[2][200] ^= 0x80000000U;  // repaired: the stop stays (non-recoverable)
    for (int k = 0; k < 5; ++k) {
        CHECK(cell.cycle(*c).safety.stop_requested);
    }
    CHECK((c->report().safety.latched_faults & kInternal) != 0U);
}

// verifies: SR-MEM-002
TEST_CASE("safety logic: one bit flipped in any sealed field stops in the next step, for good") {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{4, 4, 4}).value();
    std::vector<std::uint32_t> mask(64);
    ZoneConfig protective;
    protective.box_max = Eigen::Vector3d(0.2, 0.2, 0.2);
    const CompiledZones zones = CompiledZones::compile(g, {&protective, 1U}, {mask.data(), mask.size()}).value();
    ZoneEvaluation eval;
    eval.count = 1U;
    eval.zones[0].state = ZoneState::kClear;
    SafetyLogicConfig config;
    config.restart_delay_us = 0U;
    config.reset_required = false;  // no reset input here: a release follows the clear zones alone
    config.fault_recovery_cycles = 3U;
    SafetyLogic probe(config, zones);
    const std::size_t n = SafetyLogicTestAccess::fields(probe).size();
    REQUIRE(n >= 12U);
    for (std::size_t f = 0U; f < n; ++f) {
        SafetyLogic logic(config, zones);
        std::uint64_t now = 1000U;
        SafetyInputs in;
        in.zones = &eval;
        for (int k = 0; k < 3; ++k) {
            in.now_us = (now += 10000U);
            REQUIRE_FALSE(logic.step(in).stop_requested);
        }
        const test::Field field = SafetyLogicTestAccess::fields(logic)[f];
        CAPTURE(field.name);
        test::flip_bit(field);
        in.now_us = (now += 10000U);
        const SafetyOutputs o = logic.step(in);
        CHECK(o.stop_requested);
        CHECK((o.latched_faults & kInternal) != 0U);
        for (int k = 0; k < 5; ++k) {  // and it stays: non-recoverable
            in.now_us = (now += 10000U);
            CHECK(logic.step(in).stop_requested);
        }
    }
    StateSeal unsealed;
    CHECK_FALSE(unsealed.matches(0U));  // a seal never sealed matches nothing
}

// verifies: SR-MEM-003
TEST_CASE(
    "controller: one bit flipped in any sealed field of its state or configuration copy stops in the next cycle") {
    SmallCell cell;
    const std::size_t n = SafetyControllerTestAccess::fields(*cell.controller(cell.config())).size();
    REQUIRE(n >= 40U);
    for (std::size_t f = 0U; f < n; ++f) {
        auto c = cell.controller(cell.config());
        for (int k = 0; k < 2; ++k) {
            const CycleReport& r = cell.cycle(*c);
            REQUIRE(r.detected_faults == 0U);
            REQUIRE_FALSE(r.safety.stop_requested);
        }
        REQUIRE(SafetyControllerTestAccess::seal_matches(*c));
        const test::Field field = SafetyControllerTestAccess::fields(*c)[f];
        CAPTURE(field.name);
        test::flip_bit(field);
        if (field.calls_through) {  // the clock and the output are still called to send the stop
            CHECK_FALSE(SafetyControllerTestAccess::seal_matches(*c));
            continue;
        }
        const CycleReport& r = cell.cycle(*c);
        CHECK((r.detected_faults & kInternal) != 0U);
        CHECK(r.safety.stop_requested);
        test::flip_bit(field);  // repaired: the stop stays (non-recoverable)
        for (int k = 0; k < 4; ++k) {
            CHECK(cell.cycle(*c).safety.stop_requested);
        }
    }
}

// verifies: SR-MEM-003, SR-WDG-004
TEST_CASE(
    "controller: a fault reported between cycles renews the seal only if it held, so a corruption is still found") {
    SmallCell cell;
    auto c = cell.controller(cell.config());
    REQUIRE(cell.cycle(*c).detected_faults == 0U);
    c->report_faults(fault_bit(Fault::kClockFault));  // an intact state: the report itself is no corruption
    CHECK(SafetyControllerTestAccess::seal_matches(*c));
    CHECK(cell.cycle(*c).detected_faults == fault_bit(Fault::kClockFault));
    auto d = cell.controller(cell.config());
    REQUIRE(cell.cycle(*d).detected_faults == 0U);
    const test::Field field = SafetyControllerTestAccess::fields(*d)[0];
    CAPTURE(field.name);
    test::flip_bit(field);
    d->report_faults(fault_bit(Fault::kClockFault));  // must not seal the flipped bit in
    CHECK_FALSE(SafetyControllerTestAccess::seal_matches(*d));
    if (!field.calls_through) {
        CHECK((cell.cycle(*d).detected_faults & kInternal) != 0U);
    }
}

// verifies: SR-MEM-004
TEST_CASE("stack paint: the guard band and the high-water mark of a painted region") {
    std::vector<std::uint32_t> stack(1024U, 0U);
    StackPaint paint(Span<std::uint32_t>(stack.data(), stack.size()), 64U);
    CHECK_FALSE(paint.guard_intact());  // not painted yet
    paint.paint();
    CHECK(paint.guard_intact());
    CHECK(paint.high_water_bytes() == 0U);
    CHECK(paint.region_bytes() == 4096U);
    CHECK(paint.guard_bytes() == 256U);
    stack[1000] = 0U;  // a frame 24 words below the top
    CHECK(paint.high_water_bytes() == 24U * 4U);
    stack[64] = 1U;  // the deepest use just above the guard band
    CHECK(paint.guard_intact());
    CHECK(paint.high_water_bytes() == (1024U - 64U) * 4U);
    stack[63] = 7U;  // into the guard band
    CHECK_FALSE(paint.guard_intact());
    CHECK(paint.high_water_bytes() == (1024U - 63U) * 4U);
    const StackPaint none;
    CHECK(none.guard_intact());
    CHECK(none.high_water_bytes() == 0U);
    CHECK(test::violates_contract([&stack] { StackPaint bad(Span<std::uint32_t>(stack.data(), 8U), 9U); }));
}

// verifies: SR-MEM-004
TEST_CASE("controller: a stack grown into the guard band is kInternalCheck in the same cycle, for good") {
    SmallCell cell;
    std::vector<std::uint32_t> stack(2048U);
    StackPaint paint(Span<std::uint32_t>(stack.data(), stack.size()), 256U);
    paint.paint();
    ControllerConfig cfg = cell.config();
    cfg.stack = &paint;
    auto c = cell.controller(cfg);
    stack[300] = 0U;  // deep, but above the guard band
    for (int k = 0; k < 3; ++k) {
        REQUIRE(cell.cycle(*c).detected_faults == 0U);
    }
    stack[255] = 0U;
    const CycleReport& r = cell.cycle(*c);
    CHECK((r.detected_faults & kInternal) != 0U);
    CHECK(r.safety.stop_requested);
    paint.paint();  // repainted: the stop stays
    for (int k = 0; k < 4; ++k) {
        CHECK(cell.cycle(*c).safety.stop_requested);
    }
}

namespace {
// Uses about @p bytes of stack below its caller's frame.
__attribute__((noinline)) std::uint32_t use_stack(std::size_t bytes) {
    constexpr std::size_t kMax = 128U * 1024U;
    volatile std::uint8_t buffer[kMax];
    const std::size_t n = bytes < kMax ? bytes : kMax;
    for (std::size_t i = 0U; i < n; ++i) {
        buffer[kMax - 1U - i] = static_cast<std::uint8_t>(i);  // from the top down, as a stack grows
    }
    return buffer[kMax - 1U];
}
}  // namespace

// verifies: SR-MEM-005
TEST_CASE("linux stack monitor: a deep call raises the high-water mark, one past the budget reaches the guard band") {
    linux_port::StackMonitor monitor;
    CHECK(monitor.start(1000U, 0U).error() == ErrorCode::kInvalidArgument);
    CHECK(monitor.start(4096U, 4096U).error() == ErrorCode::kInvalidArgument);
    CHECK(monitor.start(std::size_t{1} << 40U, 4096U).error() == ErrorCode::kStorageTooSmall);
    CHECK_FALSE(monitor.started());
    CHECK(monitor.paint().guard_intact());  // nothing painted: the check is off
    REQUIRE(monitor.start(512U * 1024U, 4096U).ok());
    CHECK(monitor.started());
    CHECK(monitor.paint().guard_intact());
    const std::size_t before = monitor.high_water_bytes();
    CHECK(use_stack(64U * 1024U) == 0U);
    const std::size_t after = monitor.high_water_bytes();
    CHECK(after >= before);
    CHECK(after >= 64U * 1024U - 2048U);  // less the margin below start()'s frame
    CHECK(after < 512U * 1024U);
    CHECK(monitor.paint().guard_intact());
    // A smaller budget that the same call overruns: its guard band is reached.
    linux_port::StackMonitor small;
    REQUIRE(small.start(32U * 1024U, 4096U).ok());
    CHECK(use_stack(64U * 1024U) == 0U);
    CHECK_FALSE(small.paint().guard_intact());
    CHECK(small.high_water_bytes() == 32U * 1024U);
}

// verifies: SR-MEM-001, SR-GEN-003
TEST_CASE("memory checks: a CRC table check step of 0 or more than 256 values is a contract violation") {
    Crc32TableCheck check;
    CHECK_FALSE(test::violates_contract([&] { (void)check.step(256U); }));
    CHECK(test::violates_contract([&] { (void)check.step(0U); }));
    CHECK(test::violates_contract([&] { (void)check.step(257U); }));
    CHECK_FALSE(check.step(1U));  // the table is still intact
}

// verifies: SR-MEM-001
TEST_CASE("memory checks: a CRC table range starting at or beyond the table's end checks nothing and passes") {
    Crc32Table broken = kCrc32Table;
    broken.slices[0][255] ^= 1U;
    CHECK_FALSE(crc32_table_entries_intact(broken, 255U, 1U));
    CHECK(crc32_table_entries_intact(broken, 256U, 1U));
    CHECK(crc32_table_entries_intact(broken, 0xFFFFFFFFU, 0xFFFFFFFFU));
    CHECK_FALSE(crc32_table_entries_intact(broken, 0U, 0xFFFFFFFFU));  // clipped at 256, reaches entry 255
}
