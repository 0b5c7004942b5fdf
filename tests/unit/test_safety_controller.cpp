// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the cycle executive on the simulated workcell: intrusion
// gives a stop in the same cycle, a quiet or stale sensor gives a fault, a
// corrupted prior is caught while running, unseen space is not clear, and a
// cycle allocates no memory. With a robot and the PLC's command: the case
// switch takes effect in the cycle whose command arrived before it starts and
// is echoed; an unknown case, a missing, stale or kept-too-long command, or
// another robot's command stops; the robot's voxels are not foreground;
// separation gives REDUCED then STOP; the robot model is checked in RAM.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/firmware/scenario.hpp"
#include "cellguard/host/io/background_files.hpp"
#include "cellguard/host/owned_footprint.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "contract_capture.hpp"
#include "paper_cell.hpp"
#include "ray_table_vectors.hpp"
#include "settable_clock.hpp"
#include "test_robot.hpp"
#include "test_tags.hpp"

using namespace cellguard;

namespace {

class TestClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t += 1U; }  // 1 us per reading
    std::uint64_t t = 1000000U;
};

class RecordingOutput final : public CycleOutput {
public:
    bool publish(const CycleReport& r) noexcept override {
        last_stop = r.safety.stop_requested;
        ++published;
        return !fail;
    }
    bool fail = false;
    bool last_stop = true;
    int published = 0;
};

// The paper's cell, its background prior (probabilistic method), and the
// firmware scenario's two zones on the free floor in front of the first
// background box. The render of the empty cell, G_B and the prior are built once per
// process (paper_cell.hpp); each Workcell has its own copies of every buffer
// the controller or a test may change.
struct Workcell {
    GridGeometry g = paper_grid_geometry();
    std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const test::PaperCellCommissioning& commissioned = test::paper_cell_commissioning();  // built once, read-only
    std::vector<std::int16_t> frame_lo = commissioned.frame_log_odds;
    std::vector<std::int16_t> prior = commissioned.prior;
    std::vector<std::int16_t> scratch = commissioned.scratch;
    std::vector<std::uint8_t> frame_ob = commissioned.frame_observed;
    std::vector<std::uint32_t> mask;
    EvidenceGrid frame_grid;
    CompiledZones zones;
    SensorModelTable model;

    Workcell() : mask(g.voxel_count()) {
        frame_grid =
            EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
        // The firmware scenario's zones: zone 0 protective, on the floor in
        // front of box B; zone 1 a warning zone across it.
        const auto zs = firmware::scenario_zone_configs();
        zones = CompiledZones::compile(g, {zs.data(), zs.size()}, {mask.data(), mask.size()}).value();
    }

    // The firmware scenario's configuration: no restart delay, recovery
    // after 2 good cycles, a 10 s budget (the test clock advances 1 us per reading).
    ControllerConfig config() const { return firmware::scenario_controller_config(sensors.size()); }

    // A controller over this cell's grid, prior, zones and model.
    SafetyController controller(const ControllerConfig& c, MonotonicClock& clock, CycleOutput* out = nullptr) {
        return SafetyController(c, frame_grid, fusion_scratch(), {prior.data(), prior.size()}, zones, model, clock,
                                out);
    }
    Span<std::int16_t> fusion_scratch() { return {scratch.data(), scratch.size()}; }
    SafetyController controller(MonotonicClock& clock, CycleOutput* out = nullptr) {
        return controller(config(), clock, out);
    }
};

struct Frame {
    sim::SimulatedFrame sim;
    std::vector<SensorInput> inputs;
    Frame(const Workcell& w, const sim::Scene& scene, std::uint64_t now) : sim(sim::render_frame(w.sensors, scene)) {
        for (const SensorReading& r : sim.readings) {
            SensorInput in;
            in.reading = r;
            in.captured_us = now;
            in.present = true;
            inputs.push_back(in);
        }
    }
    Span<const SensorInput> span() const { return {inputs.data(), inputs.size()}; }
};

sim::Scene with_person(double x, double y) {
    sim::Scene s = sim::reference_scene();
    s.boxes.push_back(sim::Box{{x, y, 0.85}, {0.3, 0.3, 1.7}, 0.0, false});
    return s;
}

// The robot side on the paper cell: the 6-axis test arm standing straight
// up (all joints 0) at (x, y), three monitoring cases over the scenario's
// zones (0: both, 1: the warning zone, 2: the protective zone), and
// separation parameters scaled to the 1.7 m cell: S_p(0) = 1.6 (0.03 +
// 0.02) + 0.3 0.03 + 0.01 + 0.01 + 0.005 = 0.114 m, REDUCED below 0.114 +
// (1.6 + 0.3) 0.06 = 0.228 m.
struct RobotCell {
    static constexpr std::uint32_t kImageCrc = 0xC0FFEE42U;
    double x;
    double y;
    RobotModel arm;
    std::vector<std::uint8_t> mask;
    MonitoringCases cases;

    RobotCell(const Workcell& w, double x_m, double y_m)
        : x(x_m), y(y_m), arm(test::make_test_arm(x_m, y_m)), mask(w.g.voxel_count()) {
        const std::uint32_t zone_masks[] = {0b11U, 0b10U, 0b01U};
        cases = MonitoringCases::make(w.zones, zone_masks).value();
    }
    ControllerConfig config(const Workcell& w) {
        ControllerConfig c = w.config();
        c.robot.model = &arm;
        c.robot.image_crc = kImageCrc;
        c.robot.mask_margin_m = 0.05;
        c.robot.mask = Span<std::uint8_t>(mask.data(), mask.size());
        SeparationParams& p = c.robot.separation;
        p.reaction_time_s = 0.03;
        p.classes[0] = SpeedClassLimits{0.3, 0.02, 0.01};
        p.classes[1] = SpeedClassLimits{0.1, 0.01, 0.002};
        p.class_count = 2U;
        p.reduced_class = 1U;
        p.slowdown_time_s = 0.06;
        p.sensing_uncertainty_m = 0.01;
        p.robot_uncertainty_m = 0.005;
        p.min_hidden_voxels = 8U;
        c.cases = &cases;
        c.max_command_age_us = 250000U;
        return c;
    }
    // The arm as the sensors see it: a column of the upper arm's width up to the grid's top.
    sim::Box box() const { return sim::Box{{x, y, 0.75}, {0.12, 0.12, 1.5}, 0.0, false}; }
    sim::Scene scene() const {
        sim::Scene s = sim::reference_scene();
        s.boxes.push_back(box());
        return s;
    }
    sim::Scene scene_with_person(double px, double py) const {
        sim::Scene s = with_person(px, py);
        s.boxes.push_back(box());
        return s;
    }
};

// A good command for the arm straight up: case @p monitoring_case, received at @p received_us.
CommandInput arm_command(std::uint8_t monitoring_case, std::uint64_t received_us, std::uint8_t counter = 0U) {
    CommandInput in;
    in.valid = true;
    in.received_us = received_us;
    in.counter = counter;
    in.command.monitoring_case = monitoring_case;
    in.command.joint_count = 6U;
    in.command.robot_id = robot_id(RobotCell::kImageCrc);
    return in;
}

}  // namespace

// verifies: SR-CTRL-001, SR-LOGIC-001, SR-LOGIC-004
TEST_CASE("controller: the empty cell is clear and the stop is released") {
    Workcell w;
    TestClock clock;
    RecordingOutput out;
    SafetyController c = w.controller(clock, &out);
    const Frame f(w, sim::reference_scene(), clock.t);
    const CycleReport& r = c.run_cycle(f.span(), false);
    INFO("protective: fg " << r.zones.zones[0].foreground << " unseen " << r.zones.zones[0].unseen);
    INFO("warning: fg " << r.zones.zones[1].foreground << " unseen " << r.zones.zones[1].unseen);
    CHECK(r.zones.zones[0].state == ZoneState::kClear);
    CHECK(r.zones.zones[1].state == ZoneState::kClear);
    CHECK(r.detected_faults == 0U);
    CHECK_FALSE(r.safety.stop_requested);
    CHECK(out.published == 1);
}

// verifies: SR-CTRL-001, SR-LOGIC-002
TEST_CASE("controller: a person entering the protective zone gives a stop request in the same cycle") {
    Workcell w;
    TestClock clock;
    RecordingOutput out;
    SafetyController c = w.controller(clock, &out);
    CHECK_FALSE(c.run_cycle(Frame(w, sim::reference_scene(), clock.t).span(), false).safety.stop_requested);
    const CycleReport& r = c.run_cycle(Frame(w, with_person(0.2, 0.4), clock.t).span(), false);
    CHECK(r.zones.zones[0].state == ZoneState::kIntruded);
    CHECK(r.zones.zones[0].foreground > 10U);
    CHECK(r.safety.stop_requested);
    CHECK(out.last_stop);  // what was published in that cycle
}

// verifies: SR-CTRL-001, SR-LOGIC-003
TEST_CASE("controller: a person in the warning zone only gives a warning, not a stop") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    const CycleReport& r = c.run_cycle(Frame(w, with_person(-0.6, 0.6), clock.t).span(), false);
    CHECK(r.zones.zones[1].state == ZoneState::kIntruded);
    CHECK(r.zones.zones[0].state == ZoneState::kClear);
    CHECK(r.safety.warning);
    CHECK_FALSE(r.safety.stop_requested);
}

// verifies: SR-FUSE-010, SR-FUSE-011
TEST_CASE("controller: fusing by footprint gives the ray path's zone states, and no workspace is a frame fault") {
    Workcell w;
    host::OwnedFootprintWorkspaces ws(w.g, w.sensors.size(), 320, 240);
    ControllerConfig fc = w.config();
    fc.footprint.method = FusionMethod::kFootprint;
    fc.footprint.workspaces = ws.spans();
    const sim::Scene scenes[] = {sim::reference_scene(), with_person(-0.6, 0.6), with_person(0.2, 0.4),
                                 sim::reference_scene()};
    TestClock ray_clock;
    TestClock fp_clock;
    SafetyController ray = w.controller(ray_clock);
    SafetyController fp = w.controller(fc, fp_clock);
    for (const sim::Scene& scene : scenes) {
        const CycleReport r = ray.run_cycle(Frame(w, scene, ray_clock.t).span(), false);
        const CycleReport f = fp.run_cycle(Frame(w, scene, fp_clock.t).span(), false);
        REQUIRE(f.detected_faults == 0U);
        CHECK(f.fusion.rays_fused == r.fusion.rays_fused);
        CHECK(f.fusion.readings_in_grid == r.fusion.readings_in_grid);
        for (std::size_t z = 0; z < 2U; ++z) {
            INFO("zone " << z << ": fg " << f.zones.zones[z].foreground << " / " << r.zones.zones[z].foreground
                         << ", unseen " << f.zones.zones[z].unseen << " / " << r.zones.zones[z].unseen);
            CHECK(f.zones.zones[z].state == r.zones.zones[z].state);
            CHECK(f.zones.zones[z].foreground == r.zones.zones[z].foreground);
        }
        CHECK(f.safety.stop_requested == r.safety.stop_requested);
        CHECK(f.safety.warning == r.safety.warning);
    }
    fc.footprint.workspaces = {};
    TestClock clock;
    SafetyController none = w.controller(fc, clock);
    const CycleReport& r = none.run_cycle(Frame(w, sim::reference_scene(), clock.t).span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kFrameInconsistent)) != 0U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-FUSE-014
TEST_CASE("controller: by footprint, a camera refused in a cycle leaves every other camera its own table, made once") {
    Workcell w;
    const Frame empty(w, sim::reference_scene(), 0U);
    std::vector<SensorReading> readings;
    for (const SensorInput& in : empty.inputs) {
        readings.push_back(in.reading);
    }
    host::OwnedFootprintWorkspaces ws(w.g, readings);
    ControllerConfig fc = w.config();
    fc.footprint.method = FusionMethod::kFootprint;
    fc.footprint.workspaces = ws.spans();
    TestClock clock;
    SafetyController c = w.controller(fc, clock);
    CHECK(c.run_cycle(Frame(w, with_person(0.2, 0.4), clock.t).span(), false).detected_faults == 0U);
    for (std::size_t slot = 0; slot < readings.size(); ++slot) {
        CAPTURE(slot);
        Frame f(w, with_person(0.2, 0.4), clock.t);
        f.inputs[slot].captured_us = clock.t - 300000U;  // older than the 200 ms limit: refused
        const CycleReport r = c.run_cycle(f.span(), false);
        CHECK((r.detected_faults & fault_bit(Fault::kSensorStale)) != 0U);
        Frame quiet(w, with_person(0.2, 0.4), clock.t);
        quiet.inputs[slot].present = false;
        CHECK((c.run_cycle(quiet.span(), false).detected_faults & fault_bit(Fault::kSensorMissing)) != 0U);
    }
    CHECK(c.run_cycle(Frame(w, with_person(0.2, 0.4), clock.t).span(), false).detected_faults == 0U);
    for (const FootprintWorkspace& space : ws.spans()) {
        REQUIRE(space.table != nullptr);
        CHECK(space.table->makes() == 1U);  // on its camera's first frame, never again
    }
}

// verifies: SR-CTRL-002, SR-LOGIC-002, SR-LOGIC-005
TEST_CASE("controller: a sensor that goes quiet or delivers a stale frame gives a fault and the stop") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    Frame quiet(w, sim::reference_scene(), clock.t);
    quiet.inputs[2].present = false;
    CycleReport r = c.run_cycle(quiet.span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kSensorMissing)) != 0U);
    CHECK(r.safety.stop_requested);
    Frame stale(w, sim::reference_scene(), clock.t);
    stale.inputs[1].captured_us = clock.t - 300000U;  // older than the 200 ms limit
    r = c.run_cycle(stale.span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kSensorStale)) != 0U);
    CHECK(r.safety.stop_requested);
    Frame fresh_but_short(w, sim::reference_scene(), clock.t);
    fresh_but_short.inputs.pop_back();  // one sensor fewer than configured
    r = c.run_cycle(fresh_but_short.span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kSensorMissing)) != 0U);
    // Recovery: fault-free cycles clear the latch, then the interlock releases.
    CHECK(c.run_cycle(Frame(w, sim::reference_scene(), clock.t).span(), false).safety.stop_requested);  // 1 clean cycle
    CHECK_FALSE(c.run_cycle(Frame(w, sim::reference_scene(), clock.t).span(), false).safety.stop_requested);
}

// verifies: SR-CTRL-008
TEST_CASE(
    "controller: a sensor whose image stays bit-identical under fresh time stamps is frozen after max_repeated_frames new frames") {
    Workcell w;
    TestClock clock;
    ControllerConfig config = w.config();
    config.max_repeated_frames = 3U;
    SafetyController c = w.controller(config, clock);
    Frame f(w, sim::reference_scene(), clock.t);
    const std::uint32_t stale = fault_bit(Fault::kSensorStale);
    // Sensors 0, 1 and 3 are alive: one pixel alternates, as noise would make
    // every frame differ. Sensor 2 delivers the same image with fresh stamps.
    const auto next_frame = [&](int k) {
        for (std::size_t s = 0; s < f.inputs.size(); ++s) {
            f.inputs[s].captured_us = clock.t;
            if (s != 2U) {
                f.sim.depth[s][0] = (k % 2 == 0) ? 1.0F : 1.001F;
            }
        }
    };
    next_frame(0);
    const std::uint64_t all_rays =
        c.run_cycle(f.span(), false).fusion.rays_fused;  // the first frame: nothing to compare
    for (int k = 1; k <= 2; ++k) {                       // repeats 1 and 2 of sensor 2: below the limit
        next_frame(k);
        const CycleReport& r = c.run_cycle(f.span(), false);
        CHECK((r.detected_faults & stale) == 0U);
        CHECK(r.fusion.rays_fused == all_rays);
    }
    next_frame(3);  // the third new frame with the same data: frozen
    const CycleReport& frozen = c.run_cycle(f.span(), false);
    CHECK((frozen.detected_faults & stale) != 0U);
    CHECK(frozen.safety.stop_requested);
    CHECK(frozen.fusion.rays_fused < all_rays);  // sensor 2's frame was not fused
    next_frame(4);                               // still frozen
    CHECK((c.run_cycle(f.span(), false).detected_faults & stale) != 0U);
    // Recovery: sensor 2's image changes; after fault_recovery_cycles (2)
    // clean cycles the latch clears (restart delay 0 in this configuration).
    f.sim.depth[2][0] += 0.01F;
    next_frame(5);
    const CycleReport& changed = c.run_cycle(f.span(), false);
    CHECK((changed.detected_faults & stale) == 0U);
    CHECK(changed.fusion.rays_fused == all_rays);
    CHECK(changed.safety.stop_requested);  // 1 clean cycle
    f.sim.depth[2][0] += 0.01F;
    next_frame(6);
    CHECK_FALSE(c.run_cycle(f.span(), false).safety.stop_requested);
}

// verifies: SR-CTRL-008
TEST_CASE("controller: the frozen-sensor check judges the frame as delivered when a filter changed the reading") {
    Workcell w;
    TestClock clock;
    ControllerConfig config = w.config();
    config.max_repeated_frames = 2U;
    SafetyController c = w.controller(config, clock);
    Frame f(w, sim::reference_scene(), clock.t);
    const std::uint32_t stale = fault_bit(Fault::kSensorStale);
    // Every sensor's filtered reading repeats bit for bit (as a filter that
    // puts near-background readings onto the background makes it); what the
    // sensors delivered changes from frame to frame in sensors 0, 1 and 3.
    std::vector<std::vector<float>> raw(f.inputs.size());
    std::vector<SensorReading> delivered(f.inputs.size());
    for (std::size_t s = 0; s < f.inputs.size(); ++s) {
        raw[s].assign(f.inputs[s].reading.depth.begin(), f.inputs[s].reading.depth.end());
        delivered[s] = f.inputs[s].reading;
        delivered[s].depth = {raw[s].data(), raw[s].size()};
        f.inputs[s].delivered = &delivered[s];
    }
    for (int k = 0; k < 4; ++k) {
        for (std::size_t s = 0; s < f.inputs.size(); ++s) {
            f.inputs[s].captured_us = clock.t;
            if (s != 2U) {
                raw[s][0] = (k % 2 == 0) ? 1.0F : 1.001F;
            }
        }
        const CycleReport& r = c.run_cycle(f.span(), false);
        CHECK((r.detected_faults & stale) == (k >= 2 ? stale : 0U));  // sensor 2's delivered frames repeat
    }
    // Without the delivered frames the repeating filtered readings are frozen too (all four sensors).
    SafetyController plain = w.controller(config, clock);
    for (std::size_t s = 0; s < f.inputs.size(); ++s) {
        f.inputs[s].delivered = nullptr;
    }
    std::uint32_t faults = 0U;
    for (int k = 0; k < 3; ++k) {
        for (SensorInput& in : f.inputs) {
            in.captured_us = clock.t;
        }
        faults = plain.run_cycle(f.span(), false).detected_faults;
    }
    CHECK((faults & stale) != 0U);
}

// verifies: SR-CTRL-008
TEST_CASE(
    "controller: a frame delivered again with its old time stamp is not a frozen sensor, and the check is on by default") {
    Workcell w;
    TestClock clock;
    ControllerConfig config = w.config();
    config.max_repeated_frames = 1U;  // the strictest limit: one new frame with the same data
    SafetyController c = w.controller(config, clock);
    const Frame f(w, sim::reference_scene(), clock.t);  // one time stamp for every cycle
    for (int k = 0; k < 5; ++k) {
        const CycleReport& r = c.run_cycle(f.span(), false);
        CHECK((r.detected_faults & fault_bit(Fault::kSensorStale)) == 0U);
    }
    // The same data with a new stamp is frozen at once with a limit of 1.
    const Frame restamped(w, sim::reference_scene(), clock.t);
    CHECK((c.run_cycle(restamped.span(), false).detected_faults & fault_bit(Fault::kSensorStale)) != 0U);

    // The library's default is on (3 new frames with the same data: frozen).
    CHECK(ControllerConfig{}.max_repeated_frames == 3U);
    // The check off (the scenario's configuration, whose simulated frames
    // repeat by design): identical images with fresh stamps are fused, no fault.
    REQUIRE(w.config().max_repeated_frames == 0U);
    SafetyController off = w.controller(clock);
    for (int k = 0; k < 5; ++k) {
        const CycleReport& r = off.run_cycle(Frame(w, sim::reference_scene(), clock.t).span(), false);
        CHECK(r.detected_faults == 0U);
    }
}

// verifies: SR-CTRL-003, SR-PRIOR-012, SR-LOGIC-006
TEST_CASE("controller: a corrupted prior is caught while running within one check pass" * CELLGUARD_LONG_REPLAY) {
    Workcell w;
    TestClock clock;
    const Frame f(w, sim::reference_scene(), clock.t);
    const std::size_t pass = (w.prior.size() * 2U + 4095U) / 4096U;
    // The first, a middle and the last value: the check reads all of them.
    for (const std::size_t at : {std::size_t{0}, std::size_t{12345}, w.prior.size() - 1U}) {
        CAPTURE(at);
        SafetyController c = w.controller(clock);
        CHECK(c.prior_crc() == crc32(as_bytes(Span<const std::int16_t>(w.prior.data(), w.prior.size()))));
        CHECK_FALSE(c.run_cycle(f.span(), false).safety.stop_requested);
        w.prior[at] ^= 0x0100;  // a bit flips in RAM
        std::size_t cycles = 0U;
        while (!c.run_cycle(f.span(), false).safety.stop_requested) {
            ++cycles;
            REQUIRE(cycles <= 2U * pass);
        }
        CHECK(cycles <= 2U * pass);
        CHECK((c.report().safety.latched_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U);
        w.prior[at] ^= 0x0100;  // even repaired, the fault stays latched
        for (int i = 0; i < 5; ++i)
            CHECK(c.run_cycle(f.span(), false).safety.stop_requested);
    }
}

// verifies: SR-CTRL-007, SR-LOGIC-006, SR-MEM-006
TEST_CASE("controller: a ray table corrupted in RAM is caught while running within two check passes") {
    Workcell w;
    TestClock clock;
    ControllerConfig config = w.config();
    REQUIRE(config.table_check_slice_bytes == 1U << 20U);  // the default slice (SR-MEM-006)
    SafetyController c = w.controller(config, clock);
    Frame f(w, sim::reference_scene(), clock.t);
    std::vector<test::RayTableVectors> storage;
    std::vector<RayTable> tables;
    storage.reserve(f.inputs.size());
    tables.reserve(f.inputs.size());
    std::size_t longest_pass = 0U;  // calls per pass of the largest table
    for (SensorInput& in : f.inputs) {
        storage.emplace_back(w.g, in.reading);
        tables.push_back(RayTable::build(w.g, in.reading, storage.back().storage()).value());
        in.table = &tables.back();
        longest_pass = std::max(longest_pass, (tables.back().checked_bytes() + config.table_check_slice_bytes - 1U) /
                                                  config.table_check_slice_bytes);
    }
    // Each sensor's table gets a slice every sensor_count cycles.
    const std::size_t two_passes = 2U * longest_pass * f.inputs.size();
    for (std::size_t k = 0U; k < two_passes; ++k) {
        const CycleReport& r = c.run_cycle(f.span(), false);
        REQUIRE(r.detected_faults == 0U);  // intact tables pass, pass after pass
    }
    CHECK_FALSE(c.report().safety.stop_requested);
    storage[2].full_hits[storage[2].crossed[5]] ^= 0x4U;  // a bit flips in the third sensor's table
    std::size_t cycles = 0U;
    while ((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kInternalCheck)) == 0U) {
        ++cycles;
        REQUIRE(cycles <= two_passes);
    }
    CHECK(c.report().safety.stop_requested);
    CHECK((c.report().safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);
    storage[2].full_hits[storage[2].crossed[5]] ^= 0x4U;  // even repaired, the fault stays latched
    for (int i = 0; i < 5; ++i)
        CHECK(c.run_cycle(f.span(), false).safety.stop_requested);
}

// verifies: SR-CTRL-007, SR-LOGIC-006
TEST_CASE(
    "controller: a sensor slot's table check starts afresh on another table, and a table object whose regions or limits changed is caught at its next turn" *
    CELLGUARD_LONG_REPLAY) {
    Workcell w;
    TestClock clock;
    ControllerConfig config = w.config();
    config.table_check_slice_bytes = 1U << 20U;
    Frame f(w, sim::reference_scene(), clock.t);
    const SensorReading& r0 = f.inputs[0].reading;
    test::RayTableVectors first(w.g, r0);
    test::RayTableVectors second(w.g, r0);
    test::RayTableVectors third(w.g, r0);
    const RayTable a = RayTable::build(w.g, r0, first.storage()).value();
    RayTable b = RayTable::build(w.g, r0, second.storage()).value();
    const std::size_t pass = (a.checked_bytes() + config.table_check_slice_bytes - 1U) / config.table_check_slice_bytes;
    REQUIRE(pass >= 2U);
    const std::size_t round = f.inputs.size();  // cycles per turn of slot 0
    SafetyController c = w.controller(config, clock);
    f.inputs[0].table = &a;
    for (std::size_t k = 0U; k < round * (pass / 2U + 1U); ++k)
        REQUIRE(c.run_cycle(f.span(), false).detected_faults == 0U);
    // Mid-pass, slot 0 shows another table: its check is remade over that
    // table, which passes pass after pass, and a flip in that table's RAM
    // (not a's) is found.
    f.inputs[0].table = &b;
    for (std::size_t k = 0U; k < 3U * round * pass; ++k)
        REQUIRE(c.run_cycle(f.span(), false).detected_faults == 0U);
    second.full_hits[second.crossed[5]] ^= 0x4U;
    std::size_t cycles = 1U;
    while ((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kInternalCheck)) == 0U) {
        ++cycles;
        REQUIRE(cycles <= 2U * round * pass);
    }
    CHECK(c.report().safety.stop_requested);
    second.full_hits[second.crossed[5]] ^= 0x4U;

    // The table object at the same address replaced by one over other
    // storage: the check no longer reads the table's regions, at once.
    SafetyController d = w.controller(config, clock);
    for (std::size_t k = 0U; k < round; ++k)
        REQUIRE(d.run_cycle(f.span(), false).detected_faults == 0U);
    b = RayTable::build(w.g, r0, third.storage()).value();
    cycles = 1U;
    while ((d.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kInternalCheck)) == 0U) {
        ++cycles;
        REQUIRE(cycles <= round);
    }
    CHECK((d.report().safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);

    // The table's stored limits no longer match the ones fuse() uses: at
    // the next turn, not only at the end of a pass.
    SafetyController e = w.controller(config, clock);
    for (std::size_t k = 0U; k < round; ++k)
        REQUIRE(e.run_cycle(f.span(), false).detected_faults == 0U);
    std::uint8_t* const words = const_cast<std::uint8_t*>(
        b.signature_regions()[0].data());  // NOLINT: bit flip for the test
    words[0] ^= 0x01U;
    cycles = 1U;
    while ((e.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kInternalCheck)) == 0U) {
        ++cycles;
        REQUIRE(cycles <= round);
    }
    words[0] ^= 0x01U;
}

// verifies: SR-CTRL-010, SR-LOGIC-006
TEST_CASE(
    "controller: a zone mask bit flipped in RAM is caught within two check passes, changed zone settings at once") {
    Workcell w;
    TestClock clock;
    ControllerConfig config = w.config();
    SafetyController c = w.controller(config, clock);
    const Frame f(w, sim::reference_scene(), clock.t);
    CHECK_FALSE(c.run_cycle(f.span(), false).safety.stop_requested);
    const std::size_t pass = (w.mask.size() * 4U + config.zone_check_slice_bytes - 1U) / config.zone_check_slice_bytes;
    // A voxel of the protective zone drops out of it (bit 0 clears).
    const auto in_zone = std::find_if(w.mask.begin(), w.mask.end(), [](std::uint32_t m) { return (m & 1U) != 0U; });
    REQUIRE(in_zone != w.mask.end());
    *in_zone &= ~1U;
    std::size_t cycles = 0U;
    while ((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kInternalCheck)) == 0U) {
        ++cycles;
        REQUIRE(cycles <= 2U * pass);
    }
    CHECK(c.report().safety.stop_requested);
    *in_zone |= 1U;  // repaired: the fault stays latched
    for (int i = 0; i < 4; ++i)
        CHECK(c.run_cycle(f.span(), false).safety.stop_requested);

    // The zones object rewritten under a running controller: the protective
    // zone turned into a warning zone. Caught in the next cycle.
    Workcell v;
    SafetyController d = v.controller(clock);
    CHECK_FALSE(d.run_cycle(Frame(v, sim::reference_scene(), clock.t).span(), false).safety.stop_requested);
    auto zs = firmware::scenario_zone_configs();
    zs[0].kind = ZoneKind::kWarning;
    v.zones = CompiledZones::compile(v.g, {zs.data(), zs.size()}, {v.mask.data(), v.mask.size()}).value();
    const CycleReport& r = d.run_cycle(Frame(v, sim::reference_scene(), clock.t).span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kInternalCheck)) != 0U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-CTRL-011
TEST_CASE("controller: with commissioned background views, a bumped or covered sensor is refused, a person is not") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    // Commissioning: each sensor's view of the empty cell.
    const sim::SimulatedFrame empty = sim::render_frame(w.sensors, sim::reference_scene());
    std::vector<BackgroundReference> refs(empty.depth.size());
    for (std::size_t s = 0; s < refs.size(); ++s) {
        refs[s].depth = Span<const float>(empty.depth[s].data(), empty.depth[s].size());
    }
    const auto with_refs = [&](Frame& f) {
        for (std::size_t s = 0; s < f.inputs.size(); ++s)
            f.inputs[s].background = &refs[s];
        return f.span();
    };
    Frame clear(w, sim::reference_scene(), clock.t);
    CHECK(c.run_cycle(with_refs(clear), false).detected_faults == 0U);
    // A person in the protective zone hides some background: still fused, still a stop for the intrusion.
    Frame person(w, with_person(0.2, 0.4), clock.t);
    const CycleReport& in_zone = c.run_cycle(with_refs(person), false);
    CHECK(in_zone.detected_faults == 0U);
    CHECK(in_zone.zones.zones[0].state == ZoneState::kIntruded);
    // Sensor 1 bumped: it now aims 0.5 m off, but the controller still has
    // its commissioned pose.
    std::vector<sim::SensorSpec> bumped = w.sensors;
    bumped[1].target += Eigen::Vector3d(0.5, 0.0, 0.0);
    const sim::SimulatedFrame moved = sim::render_frame(bumped, sim::reference_scene());
    Frame b(w, sim::reference_scene(), clock.t);
    b.sim.depth[1] = moved.depth[1];  // same size: the depth span stays valid
    b.inputs[1].reading.depth = Span<const float>(b.sim.depth[1].data(), b.sim.depth[1].size());
    const BackgroundMatch seen = match_background(b.inputs[1].reading.depth, refs[1]).value();
    INFO("bumped sensor: " << seen.matching << " of " << seen.referenced << " pixels match");
    const CycleReport& r = c.run_cycle(with_refs(b), false);
    CHECK((r.detected_faults & fault_bit(Fault::kFrameInconsistent)) != 0U);
    CHECK(r.safety.stop_requested);
    // A covered lens: no reading at all.
    Frame covered(w, sim::reference_scene(), clock.t);
    std::fill(covered.sim.depth[3].begin(), covered.sim.depth[3].end(), std::numeric_limits<float>::quiet_NaN());
    CHECK((c.run_cycle(with_refs(covered), false).detected_faults & fault_bit(Fault::kFrameInconsistent)) != 0U);
}

// verifies: SR-CTRL-003, SR-LOGIC-006
TEST_CASE("controller: a prior of the wrong size is refused for good") {
    Workcell w;
    TestClock clock;
    SafetyController c(w.config(), w.frame_grid, w.fusion_scratch(), {w.prior.data(), w.prior.size() - 1U}, w.zones,
                       w.model, clock, nullptr);
    const Frame f(w, sim::reference_scene(), clock.t);
    for (int i = 0; i < 5; ++i)
        CHECK(c.run_cycle(f.span(), false).safety.stop_requested);
    CHECK((c.report().safety.latched_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U);
}

// verifies: SR-CTRL-009, SR-LOGIC-006
TEST_CASE(
    "controller: zones of another grid, or no sensors or more than eight, latch an internal-check fault for good") {
    Workcell w;
    TestClock clock;
    const Frame f(w, sim::reference_scene(), clock.t);
    // Zones compiled for a grid shifted by one voxel.
    const GridGeometry shifted = GridGeometry::make(w.g.origin() + Eigen::Vector3d(w.g.voxel_size(), 0.0, 0.0),
                                                    w.g.voxel_size(), w.g.dims())
                                     .value();
    std::vector<std::uint32_t> other_mask(shifted.voxel_count());
    const auto zs = firmware::scenario_zone_configs();
    ZoneConfig inside = zs[0];  // the protective zone moved into the shifted grid
    inside.box_min += Eigen::Vector3d(w.g.voxel_size(), 0.0, 0.0);
    inside.box_max += Eigen::Vector3d(w.g.voxel_size(), 0.0, 0.0);
    const CompiledZones other_zones =
        CompiledZones::compile(shifted, {&inside, 1U}, {other_mask.data(), other_mask.size()}).value();
    SafetyController wrong_grid(w.config(), w.frame_grid, w.fusion_scratch(), {w.prior.data(), w.prior.size()},
                                other_zones, w.model, clock, nullptr);
    ControllerConfig none = w.config();
    none.sensor_count = 0U;
    SafetyController no_sensors = w.controller(none, clock);
    ControllerConfig nine = w.config();
    nine.sensor_count = kMaxSensors + 1U;
    SafetyController nine_sensors = w.controller(nine, clock);
    for (SafetyController* c : {&wrong_grid, &no_sensors, &nine_sensors}) {
        for (int i = 0; i < 4; ++i) {
            const CycleReport& r = c->run_cycle(f.span(), false);
            CHECK((r.detected_faults & fault_bit(Fault::kInternalCheck)) != 0U);
            CHECK(r.safety.stop_requested);
        }
        CHECK((c->report().safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);
    }
}

// verifies: SR-LOGIC-007, SR-LOGIC-006
TEST_CASE("controller: a clock that stops advancing latches a clock fault and the stop, for good") {
    Workcell w;
    test::SettableClock clock(5000000U);  // stuck until the test moves it
    SafetyController c = w.controller(clock);
    const Frame f(w, sim::reference_scene(), clock.t);
    (void)c.run_cycle(f.span(), false);  // the first cycle has no previous time to compare with
    const CycleReport& r = c.run_cycle(f.span(), false);
    CHECK((r.safety.latched_faults & fault_bit(Fault::kClockFault)) != 0U);
    CHECK(r.safety.stop_requested);
    clock.t += 100000U;  // moving again does not clear it
    for (int i = 0; i < 5; ++i) {
        clock.t += 100000U;
        CHECK(c.run_cycle(f.span(), false).safety.stop_requested);
    }
    CHECK((c.report().safety.latched_faults & fault_bit(Fault::kClockFault)) != 0U);
}

// verifies: SR-WDG-004
TEST_CASE("controller: a clock fault reported from outside (the clock-rate check) latches the stop, for good") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    const Frame f(w, sim::reference_scene(), clock.t);
    CHECK_FALSE(c.run_cycle(f.span(), false).safety.stop_requested);
    c.report_faults(fault_bit(Fault::kClockFault) | 0x80000000U);  // bits beyond the defined faults are ignored
    const CycleReport& r = c.run_cycle(f.span(), false);
    CHECK(r.detected_faults == fault_bit(Fault::kClockFault));
    CHECK(r.safety.stop_requested);
    for (int i = 0; i < 20; ++i) {
        CHECK(c.run_cycle(f.span(), false).safety.stop_requested);
    }
    CHECK((c.report().safety.latched_faults & fault_bit(Fault::kClockFault)) != 0U);
}

// verifies: SR-CTRL-002
TEST_CASE("controller: a frame stamped in the future is stale") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    Frame f(w, sim::reference_scene(), clock.t);
    f.inputs[3].captured_us = clock.t + 1000000U;  // 1 s ahead of the controller's clock
    const CycleReport& r = c.run_cycle(f.span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kSensorStale)) != 0U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-FUSE-003, SR-ZONE-004
TEST_CASE("controller: sensors that send frames without a valid reading leave the protective zone UNSEEN, not CLEAR") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    Frame blind(w, sim::reference_scene(), clock.t);
    std::uint64_t pixels = 0U;
    for (std::vector<float>& image : blind.sim.depth) {
        std::fill(image.begin(), image.end(), std::numeric_limits<float>::quiet_NaN());  // covered lenses
        pixels += image.size();
    }
    const CycleReport& r = c.run_cycle(blind.span(), false);
    CHECK(r.fusion.rays_fused == 0U);
    CHECK(r.fusion.skipped_nan == pixels);
    CHECK(r.detected_faults == 0U);  // frames arrive on time: no sensor fault, the zone logic must catch it
    CHECK(r.zones.zones[0].state == ZoneState::kUnseen);
    CHECK(r.zones.zones[0].unseen > 20U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-CTRL-004
TEST_CASE("controller: a failed output is a CAN fault in the next cycle") {
    Workcell w;
    TestClock clock;
    RecordingOutput out;
    SafetyController c = w.controller(clock, &out);
    const Frame f(w, sim::reference_scene(), clock.t);
    out.fail = true;
    (void)c.run_cycle(f.span(), false);
    out.fail = false;
    const CycleReport& r = c.run_cycle(f.span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kCanError)) != 0U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-CTRL-005
TEST_CASE("controller: a cycle over its budget is a fault in the next cycle") {
    Workcell w;
    TestClock clock;
    ControllerConfig cfg = w.config();
    cfg.cycle_budget_us = 3U;  // the test clock advances 1 us per reading: every cycle overruns
    SafetyController c = w.controller(cfg, clock);
    const Frame f(w, sim::reference_scene(), clock.t);
    (void)c.run_cycle(f.span(), false);
    CHECK((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kCycleOverrun)) != 0U);
    CHECK(c.monitor().overruns() >= 1U);
}

// verifies: SR-GEN-002
TEST_CASE("controller: a whole cycle allocates no memory") {
    Workcell w;
    TestClock clock;
    RecordingOutput out;
    SafetyController c = w.controller(clock, &out);
    const Frame f(w, with_person(0.2, 0.4), clock.t);
    const test::AllocationScope scope;
    (void)c.run_cycle(f.span(), false);
    CHECK(scope.allocations() == 0U);
}

// verifies: SR-ROB-201
TEST_CASE(
    "controller: the robot standing in the protective zone is not foreground, while the same frames without a robot configured stop") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, 0.2, 0.4);  // in the protective zone, reaching into the warning zone
    SafetyController plain = w.controller(clock);
    const CycleReport& a = plain.run_cycle(Frame(w, rc.scene(), clock.t).span(), false);
    CHECK(a.zones.zones[0].state == ZoneState::kIntruded);
    CHECK(a.safety.stop_requested);
    CHECK_FALSE(a.robot.configured);
    SafetyController c = w.controller(rc.config(w), clock);
    const CycleReport& b = c.run_cycle(Frame(w, rc.scene(), clock.t).span(), false, arm_command(0U, clock.t));
    INFO("protective: fg " << b.zones.zones[0].foreground << " unseen " << b.zones.zones[0].unseen << " robot "
                           << b.zones.zones[0].robot << "; distance " << b.robot.distance_mm << " mm");
    CHECK(b.detected_faults == 0U);
    CHECK(b.zones.zones[0].state == ZoneState::kClear);
    CHECK(b.zones.zones[0].foreground == 0U);
    CHECK(b.zones.zones[0].robot > 100U);
    CHECK(b.zones.zones[1].state == ZoneState::kClear);
    CHECK(b.robot.configured);
    CHECK(b.robot.command_valid);
    CHECK(b.robot.robot_voxels >= b.zones.zones[0].robot);
    CHECK(b.robot.speed_request == SpeedRequest::kFull);
    CHECK(b.robot.distance_mm == kDistanceFarMm);
    CHECK_FALSE(b.safety.stop_requested);
    CHECK_FALSE(b.safety.reduced_speed);
}

// verifies: SR-ROB-203
TEST_CASE("controller: a refused command uses no pose at all: the robot is foreground again and separation stops") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, 0.2, 0.4);
    SafetyController c = w.controller(rc.config(w), clock);
    REQUIRE_FALSE(
        c.run_cycle(Frame(w, rc.scene(), clock.t).span(), false, arm_command(0U, clock.t)).safety.stop_requested);
    CommandInput lost = arm_command(0U, clock.t);
    lost.valid = false;
    const CycleReport& r = c.run_cycle(Frame(w, rc.scene(), clock.t).span(), false, lost);
    CHECK((r.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);
    CHECK(r.robot.command_check == static_cast<std::uint8_t>(CommandRefusal::kMissing));
    CHECK_FALSE(r.robot.command_valid);
    CHECK(r.robot.robot_voxels == 0U);
    CHECK(r.zones.zones[0].robot == 0U);
    CHECK(r.zones.zones[0].state == ZoneState::kIntruded);  // the unmasked arm
    CHECK(r.robot.speed_request == SpeedRequest::kProtectiveStop);
    CHECK(r.robot.distance_mm == 0U);
    CHECK(r.safety.stop_requested);
    CHECK(r.safety.reduced_speed);
}

// verifies: SR-SSM-022, SR-SSM-021
TEST_CASE("controller: a person walking up to the robot gives FULL, then REDUCED, then STOP at the computed distance") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);  // away from the zones: only separation acts
    const ControllerConfig config = rc.config(w);
    const SeparationParams& p = config.robot.separation;
    const double sp = protective_separation_distance(p, 0U);
    const double reduced = reduced_speed_distance(p);
    REQUIRE(sp == doctest::Approx(0.114));
    REQUIRE(reduced == doctest::Approx(0.228));
    SafetyController c = w.controller(config, clock);
    SpeedRequest last = SpeedRequest::kFull;
    std::uint16_t last_mm = kDistanceFarMm;
    bool saw_reduced = false;
    bool saw_stop = false;
    for (const double px : {0.1, 0.0, -0.05, -0.1, -0.15, -0.2, -0.25}) {
        CAPTURE(px);
        const CycleReport& r = c.run_cycle(Frame(w, rc.scene_with_person(px, -0.5), clock.t).span(), false,
                                           arm_command(1U, clock.t));
        CAPTURE(r.robot.distance_mm);
        REQUIRE(r.detected_faults == 0U);
        CHECK(r.robot.distance_mm < last_mm);  // the person comes closer
        CHECK(r.robot.required_mm == static_cast<std::uint16_t>(std::ceil(sp * 1000.0)));
        const double d = r.robot.distance_mm / 1000.0;
        const SpeedRequest expected = d < sp ? SpeedRequest::kProtectiveStop
                                             : (d < reduced ? SpeedRequest::kReduced : SpeedRequest::kFull);
        CHECK(r.robot.speed_request == expected);
        CHECK(static_cast<int>(r.robot.speed_request) >= static_cast<int>(last));  // never back to a faster one
        CHECK(r.safety.stop_requested == (expected == SpeedRequest::kProtectiveStop));
        CHECK(r.safety.separation_stop == (expected == SpeedRequest::kProtectiveStop));
        CHECK(r.safety.reduced_speed == (expected != SpeedRequest::kFull));
        saw_reduced = saw_reduced || expected == SpeedRequest::kReduced;
        saw_stop = saw_stop || expected == SpeedRequest::kProtectiveStop;
        last = r.robot.speed_request;
        last_mm = r.robot.distance_mm;
    }
    CHECK(saw_reduced);
    CHECK(saw_stop);
    // The person steps back: the stop ends in that cycle (no restart interlock for separation).
    const CycleReport& back = c.run_cycle(Frame(w, rc.scene_with_person(0.1, -0.5), clock.t).span(), false,
                                          arm_command(1U, clock.t));
    CHECK(back.robot.speed_request == SpeedRequest::kFull);
    CHECK_FALSE(back.safety.stop_requested);
    CHECK(back.detected_faults == 0U);
}

// verifies: SR-CASE-010
TEST_CASE(
    "controller: a case switch takes effect in the cycle whose command arrived before it started, and is echoed") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    SafetyController c = w.controller(rc.config(w), clock);
    const Frame person(w, rc.scene_with_person(0.2, 0.4), clock.t);  // in the protective and the warning zone
    // Case 1: the warning zone only: a warning, no stop; the protective zone's bits are 0.
    CycleReport r = c.run_cycle(person.span(), false, arm_command(1U, clock.t, 3U));
    CHECK(r.robot.active_case == 1U);
    CHECK(r.robot.command_counter == 3U);
    CHECK(r.zones.active_mask == 0b10U);
    CHECK(r.safety.warning);
    CHECK_FALSE(r.safety.stop_requested);
    CHECK(r.safety.intruded_mask == 0b10U);
    // The PLC switches to case 2 (the protective zone only): stop in this very cycle, echoed.
    r = c.run_cycle(person.span(), false, arm_command(2U, clock.t, 4U));
    CHECK(r.robot.active_case == 2U);
    CHECK(r.robot.command_counter == 4U);
    CHECK(r.safety.stop_requested);
    CHECK_FALSE(r.safety.warning);
    CHECK(r.safety.intruded_mask == 0b01U);
    // A command that arrives after the cycle has started is not this cycle's
    // (refused as stale: it is stamped after the cycle's start), and the case
    // in force stays the last good one.
    r = c.run_cycle(person.span(), false, arm_command(1U, clock.t + 1000U, 5U));
    CHECK(r.robot.active_case == 2U);
    CHECK(r.robot.command_check == static_cast<std::uint8_t>(CommandRefusal::kStale));
    CHECK((r.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-CASE-011
TEST_CASE(
    "controller: an unknown case number stops in that cycle and keeps the last good case, and good commands recover") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    SafetyController c = w.controller(rc.config(w), clock);
    const Frame empty(w, rc.scene(), clock.t);
    REQUIRE_FALSE(c.run_cycle(empty.span(), false, arm_command(1U, clock.t)).safety.stop_requested);
    for (const std::uint8_t unknown : {3U, 15U, 16U, 255U}) {
        CAPTURE(static_cast<int>(unknown));
        const CycleReport& r = c.run_cycle(empty.span(), false, arm_command(unknown, clock.t));
        CHECK((r.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);
        CHECK(r.robot.command_check == static_cast<std::uint8_t>(CommandRefusal::kUnknownCase));
        CHECK(r.robot.active_case == 1U);
        CHECK_FALSE(r.robot.command_valid);
        CHECK(r.safety.stop_requested);
    }
    // fault_recovery_cycles (2) good cycles clear the fault; no restart delay in this configuration.
    CHECK(c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).safety.stop_requested);
    const CycleReport& ok = c.run_cycle(empty.span(), false, arm_command(0U, clock.t));
    CHECK_FALSE(ok.safety.stop_requested);
    CHECK(ok.robot.active_case == 0U);
}

// verifies: SR-ROB-210
TEST_CASE("controller: a missing, stale or kept-too-long command stops within the documented cycles") {
    Workcell w;
    test::SettableClock clock(10000000U);
    RobotCell rc(w, -0.6, -0.5);
    ControllerConfig config = rc.config(w);
    config.max_command_age_us = 250000U;  // 250 ms; cycles every 100 ms below
    SafetyController c = w.controller(config, clock);
    const Frame empty(w, rc.scene(), clock.t);
    const auto cycle = [&](const CommandInput& in) -> const CycleReport& {
        clock.t += 100000U;
        Frame f(w, rc.scene(), clock.t);
        return c.run_cycle(f.span(), false, in);
    };
    // A sample the receiver keeps (the PLC fell silent) is used while it is
    // at most 250 ms old: cycles 100 and 200 ms after it; the cycle at 300
    // ms stops, the first one after max_command_age_us.
    const CommandInput kept = arm_command(0U, clock.t);
    CHECK_FALSE(cycle(kept).safety.stop_requested);
    CHECK_FALSE(cycle(kept).safety.stop_requested);
    const CycleReport& stale = cycle(kept);
    CHECK((stale.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);
    CHECK(stale.robot.command_check == static_cast<std::uint8_t>(CommandRefusal::kStale));
    CHECK(stale.robot.command_age_us == 300000U);
    CHECK(stale.safety.stop_requested);
    // The receiver's own verdict (missing, repeated counter, corrupt): the same cycle.
    CHECK(cycle(arm_command(0U, clock.t)).safety.stop_requested);  // 1 of 2 recovery cycles
    CHECK_FALSE(cycle(arm_command(0U, clock.t)).safety.stop_requested);
    CommandInput refused = arm_command(0U, clock.t);
    refused.valid = false;
    const CycleReport& missing = cycle(refused);
    CHECK(missing.robot.command_check == static_cast<std::uint8_t>(CommandRefusal::kMissing));
    CHECK(missing.safety.stop_requested);
    // A robot cell run without a command (the legacy run_cycle) is a missing command.
    clock.t += 100000U;
    const CycleReport& legacy = c.run_cycle(Frame(w, rc.scene(), clock.t).span(), false);
    CHECK((legacy.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);
    CHECK(legacy.safety.stop_requested);
}

// verifies: SR-CMD-010
TEST_CASE("controller: the PLC's ResetRequest ends the restart interlock only when pressed after a valid release") {
    Workcell w;
    test::SettableClock clock(10000000U);
    RobotCell rc(w, -0.6, -0.5);
    ControllerConfig config = rc.config(w);
    config.logic.reset_required = true;  // no restart delay, recovery after 2 good cycles (the scenario's)
    SafetyController c = w.controller(config, clock);
    const auto cycle = [&](bool reset, bool valid = true) -> const CycleReport& {
        clock.t += 100000U;
        CommandInput in = arm_command(0U, clock.t);
        in.valid = valid;
        in.command.reset_request = reset;
        const Frame f(w, rc.scene(), clock.t);
        return c.run_cycle(f.span(), false, in);
    };
    // Start-up: the zones are clear, but the interlock holds the stop until the reset is pressed.
    for (int k = 0; k < 3; ++k) {
        const CycleReport& r = cycle(false);
        CHECK(r.robot.command_valid);
        CHECK_FALSE(r.robot.command_reset);
        CHECK(r.safety.stop_requested);
        CHECK(r.safety.interlock_holding);
    }
    const CycleReport& pressed = cycle(true);
    CHECK(pressed.robot.command_reset);
    CHECK_FALSE(pressed.safety.stop_requested);
    CHECK_FALSE(cycle(true).safety.stop_requested);  // still pressed: still released
    // A refused sample stops (kCommandInvalid) and holds the command's reset level high.
    const CycleReport& refused = cycle(true, false);
    CHECK(refused.safety.stop_requested);
    CHECK(refused.robot.command_reset);
    CHECK(cycle(false, false).robot.command_reset);  // released, but refused: still held high
    // Pressed again as the samples come back: no edge after the refusal, so once the fault has
    // recovered the interlock still holds.
    for (int k = 0; k < 4; ++k) {
        CHECK(cycle(true).safety.stop_requested);
    }
    CHECK(cycle(true).safety.interlock_holding);
    // Released in a valid sample, then pressed: that edge ends the stop.
    CHECK(cycle(false).safety.stop_requested);
    CHECK_FALSE(cycle(true).safety.stop_requested);
    // The caller's own reset input still works beside it (OR): a cell with a wired reset as well.
    CHECK(cycle(false, false).safety.stop_requested);
    for (int k = 0; k < 3; ++k) {
        CHECK(cycle(false).safety.stop_requested);
    }
    clock.t += 100000U;
    const Frame f(w, rc.scene(), clock.t);
    CHECK_FALSE(c.run_cycle(f.span(), true, arm_command(0U, clock.t)).safety.stop_requested);
}

// verifies: SR-ROB-211
TEST_CASE("controller: a command for another robot, with another joint count or outside the limits, stops") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    SafetyController c = w.controller(rc.config(w), clock);
    const Frame empty(w, rc.scene(), clock.t);
    REQUIRE_FALSE(c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).safety.stop_requested);
    CommandInput other = arm_command(0U, clock.t);
    other.command.robot_id = static_cast<std::uint16_t>(other.command.robot_id ^ 0x0100U);
    CommandInput five = arm_command(0U, clock.t);
    five.command.joint_count = 5U;
    CommandInput beyond = arm_command(0U, clock.t);
    beyond.command.joint_raw[2] = 20000;  // 4 rad: the elbow's limit is pi
    CommandInput fast = arm_command(0U, clock.t);
    fast.command.speed_class = 2U;  // two classes commissioned
    const std::pair<const CommandInput*, CommandRefusal> cases[] = {
        {&other, CommandRefusal::kRobotIdMismatch},
        {&five, CommandRefusal::kJointCountMismatch},
        {&beyond, CommandRefusal::kOutsideLimits},
        {&fast, CommandRefusal::kUnknownSpeedClass},
    };
    for (const auto& item : cases) {
        const CommandInput* in = item.first;
        const CommandRefusal why = item.second;  // not a structured binding: doctest's CHECK lambdas capture it
        CAPTURE(to_string(why));
        const CycleReport& r = c.run_cycle(empty.span(), false, *in);
        CHECK((r.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);
        CHECK(r.robot.command_check == static_cast<std::uint8_t>(why));
        CHECK(r.safety.stop_requested);
        CHECK(r.robot.speed_request == SpeedRequest::kProtectiveStop);
    }
}

// verifies: SR-ROB-212
TEST_CASE("controller: the robot model corrupted in RAM is an internal-check fault within two check passes, for good") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    ControllerConfig config = rc.config(w);
    config.robot_check_slice_bytes = 512U;
    SafetyController c = w.controller(config, clock);
    const Frame empty(w, rc.scene(), clock.t);
    const std::size_t pass = (sizeof(RobotModel) + 511U) / 512U;
    for (std::size_t k = 0U; k < 2U * pass; ++k)
        REQUIRE(c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).detected_faults == 0U);
    rc.arm.capsules[3].radius = 0.01;  // the forearm shrinks in RAM
    std::size_t cycles = 1U;
    while ((c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).detected_faults &
            fault_bit(Fault::kInternalCheck)) == 0U) {
        ++cycles;
        REQUIRE(cycles <= 2U * pass);
    }
    CHECK(c.report().safety.stop_requested);
    rc.arm.capsules[3].radius = 0.06;  // repaired: the fault stays latched
    for (int i = 0; i < 4; ++i)
        CHECK(c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).safety.stop_requested);
    CHECK((c.report().safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);
}

// verifies: SR-ROB-213
TEST_CASE("controller: a refused robot configuration latches an internal-check fault at construction") {
    Workcell w;
    TestClock clock;
    const Frame f(w, sim::reference_scene(), clock.t);
    RobotCell rc(w, -0.6, -0.5);
    RobotModel broken = rc.arm;
    broken.capsules[0].radius = -1.0;
    std::vector<ControllerConfig> configs(6U, rc.config(w));
    configs[0].robot.mask = Span<std::uint8_t>(rc.mask.data(), rc.mask.size() - 1U);
    configs[1].robot.mask_margin_m = std::numeric_limits<double>::quiet_NaN();
    configs[2].robot.mask_margin_m = -0.01;
    configs[3].robot.separation.class_count = 0U;
    configs[4].robot.model = &broken;
    // Cases made for other zones (three zones, here two).
    std::vector<std::uint32_t> other_mask(w.g.voxel_count());
    const auto zs = firmware::scenario_zone_configs();
    const ZoneConfig three[] = {zs[0], zs[1], zs[1]};
    const CompiledZones other = CompiledZones::compile(w.g, three, {other_mask.data(), other_mask.size()}).value();
    const std::uint32_t zone2[] = {0b100U};
    const MonitoringCases foreign = MonitoringCases::make(other, zone2).value();
    configs[5].cases = &foreign;
    for (std::size_t k = 0U; k < configs.size(); ++k) {
        CAPTURE(k);
        SafetyController c = w.controller(configs[k], clock);
        for (int i = 0; i < 3; ++i) {
            const CycleReport& r = c.run_cycle(f.span(), false, arm_command(0U, clock.t));
            CHECK((r.safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);
            CHECK(r.safety.stop_requested);
        }
    }
}

// verifies: SR-CASE-012
TEST_CASE(
    "controller: a cell without a robot or cases ignores commands, and one with cases only takes a joint-less command") {
    Workcell w;
    TestClock clock;
    const Frame f(w, sim::reference_scene(), clock.t);
    SafetyController plain = w.controller(clock);
    CommandInput junk = arm_command(9U, clock.t);
    junk.valid = false;
    const CycleReport& r = plain.run_cycle(f.span(), false, junk);
    CHECK(r.detected_faults == 0U);
    CHECK_FALSE(r.safety.stop_requested);
    CHECK_FALSE(r.robot.configured);
    CHECK(r.robot.active_case == 0U);
    CHECK(r.robot.speed_request == SpeedRequest::kFull);
    CHECK(r.robot.distance_mm == kDistanceFarMm);
    CHECK(r.zones.active_mask == 0b11U);
    // Cases without a robot: the command selects the case and carries no joints.
    const std::uint32_t masks[] = {0b11U, 0b10U};
    const MonitoringCases cases = MonitoringCases::make(w.zones, masks).value();
    ControllerConfig config = w.config();
    config.cases = &cases;
    SafetyController switched = w.controller(config, clock);
    const Frame person(w, with_person(0.2, 0.4), clock.t);
    CommandInput in;
    in.valid = true;
    in.received_us = clock.t;
    in.command.monitoring_case = 1U;
    const CycleReport& a = switched.run_cycle(person.span(), false, in);
    CHECK(a.detected_faults == 0U);
    CHECK(a.robot.active_case == 1U);
    CHECK_FALSE(a.robot.configured);
    CHECK_FALSE(a.safety.stop_requested);
    in.command.joint_count = 6U;  // joints for a cell without a robot
    const CycleReport& b = switched.run_cycle(person.span(), false, in);
    CHECK(b.robot.command_check == static_cast<std::uint8_t>(CommandRefusal::kJointCountMismatch));
    CHECK(b.safety.stop_requested);
}

// verifies: SR-CMD-010
TEST_CASE(
    "controller: a cell with cases and no robot takes the reset from the command too, one without cases ignores it") {
    Workcell w;
    TestClock clock;
    const Frame f(w, sim::reference_scene(), clock.t);
    const std::uint32_t masks[] = {0b11U};
    const MonitoringCases cases = MonitoringCases::make(w.zones, masks).value();
    ControllerConfig config = w.config();
    config.cases = &cases;
    config.logic.reset_required = true;
    SafetyController c = w.controller(config, clock);
    CommandInput in;  // joint-less: case 0, the reset released
    in.valid = true;
    in.received_us = clock.t;
    const CycleReport& held = c.run_cycle(f.span(), false, in);
    CHECK(held.robot.command_valid);
    CHECK(held.safety.stop_requested);
    CHECK(held.safety.interlock_holding);
    in.command.reset_request = true;
    in.received_us = clock.t;
    const CycleReport& released = c.run_cycle(f.span(), false, in);
    CHECK(released.robot.command_reset);
    CHECK_FALSE(released.safety.stop_requested);
    // A cell that expects no command: a pressed ResetRequest in whatever arrives adds nothing.
    config.cases = nullptr;
    SafetyController plain = w.controller(config, clock);
    in.received_us = clock.t;
    for (int k = 0; k < 3; ++k) {
        const CycleReport& r = plain.run_cycle(f.span(), false, in);
        CHECK_FALSE(r.robot.command_reset);
        CHECK(r.safety.stop_requested);  // the interlock waits for the caller's reset input
    }
    CHECK_FALSE(plain.run_cycle(f.span(), true, in).safety.stop_requested);
}

// verifies: SR-ROB-210, SR-CASE-011, SR-ROB-211
TEST_CASE("command check: each refusal, in order, and the names") {
    const RobotModel arm = test::make_test_arm();
    const std::uint32_t crc = RobotCell::kImageCrc;
    MonitoringCases cases;
    {
        Workcell w;
        const std::uint32_t masks[] = {0b01U, 0b10U};
        cases = MonitoringCases::make(w.zones, masks).value();
    }
    CommandLimits limits;
    limits.cases = &cases;
    limits.robot = &arm;
    limits.image_crc = crc;
    limits.speed_classes = 2U;
    limits.max_age_us = 1000U;
    CommandInput in = arm_command(1U, 5000U);
    in.command.speed_class = 1U;
    in.command.joint_raw[1] = 5000;  // 1 rad
    const Result<CheckedCommand, CommandRefusal> ok = check_command(in, 6000U, limits);
    REQUIRE(ok.ok());
    CHECK(ok.value().monitoring_case == 1U);
    CHECK(ok.value().speed_class == 1U);
    CHECK(ok.value().joints.count == 6U);
    CHECK(ok.value().joints.q[1] == doctest::Approx(1.0));
    CHECK(check_command(in, 5000U, limits).ok());  // age 0
    CHECK(check_command(in, 6001U, limits).error() == CommandRefusal::kStale);
    CHECK(check_command(in, 4999U, limits).error() == CommandRefusal::kStale);  // arrived after the start
    in.command.monitoring_case = 2U;
    CHECK(check_command(in, 5500U, limits).error() == CommandRefusal::kUnknownCase);
    in.valid = false;
    CHECK(check_command(in, 5500U, limits).error() == CommandRefusal::kMissing);  // checked first
    in = arm_command(0U, 5000U);
    limits.cases = nullptr;
    CHECK(check_command(in, 5500U, limits).error() == CommandRefusal::kUnknownCase);
    limits.cases = &cases;
    in.command.joint_raw[0] = kJointRawInvalid;
    CHECK(check_command(in, 5500U, limits).error() == CommandRefusal::kInvalidRaw);
    CHECK(std::string(to_string(CommandRefusal::kStale)) == "command stale");
    CHECK(std::string(to_string(static_cast<CommandRefusal>(99))) == "unknown refusal");
}

// verifies: SR-GEN-002, SR-ROB-201
TEST_CASE("controller: a whole cycle with a robot allocates no memory") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    SafetyController c = w.controller(rc.config(w), clock);
    const Frame f(w, rc.scene_with_person(-0.1, -0.5), clock.t);
    const CommandInput in = arm_command(0U, clock.t);
    const test::AllocationScope scope;
    const CycleReport& r = c.run_cycle(f.span(), false, in);
    CHECK(scope.allocations() == 0U);
    CHECK(r.robot.command_valid);
}

// verifies: SR-CASE-004, SR-LOGIC-006
TEST_CASE("controller: the monitoring cases rewritten in RAM are an internal-check fault in the next cycle, for good") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    SafetyController c = w.controller(rc.config(w), clock);
    const Frame empty(w, rc.scene(), clock.t);
    REQUIRE(c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).detected_faults == 0U);
    CHECK(c.cases().settings_crc() == rc.cases.settings_crc());  // the controller's own copy
    // Case 0 loses its protective zone in the controller's copy.
    const std::uint32_t weaker[] = {0b10U, 0b10U, 0b01U};
    const_cast<MonitoringCases&>(
        c.cases()) = MonitoringCases::make(w.zones, weaker).value();  // NOLINT: fault injection
    const CycleReport& r = c.run_cycle(empty.span(), false, arm_command(0U, clock.t));
    CHECK((r.detected_faults & fault_bit(Fault::kInternalCheck)) != 0U);
    CHECK(r.safety.stop_requested);
    const_cast<MonitoringCases&>(c.cases()) = rc.cases;  // NOLINT: repaired: the fault stays latched
    for (int i = 0; i < 3; ++i)
        CHECK(c.run_cycle(empty.span(), false, arm_command(0U, clock.t)).safety.stop_requested);
}

// verifies: SR-CTRL-007, SR-CTRL-010, SR-MEM-001
TEST_CASE("controller: a check slice of 0 bytes or a CRC table check count outside 1..256 is a contract violation") {
    Workcell w;
    TestClock clock;
    const ControllerConfig good = w.config();
    CHECK_FALSE(test::violates_contract([&] {
        const SafetyController c = w.controller(good, clock);
        (void)c;
    }));
    for (int field = 0; field < 6; ++field) {
        CAPTURE(field);
        ControllerConfig bad = good;
        switch (field) {
            case 0: bad.prior_check_slice_bytes = 0U; break;
            case 1: bad.table_check_slice_bytes = 0U; break;
            case 2: bad.zone_check_slice_bytes = 0U; break;
            case 3: bad.robot_check_slice_bytes = 0U; break;
            case 4: bad.crc_table_check_values = 0U; break;
            default: bad.crc_table_check_values = 257U; break;
        }
        CHECK(test::violates_contract([&] {
            const SafetyController c = w.controller(bad, clock);
            (void)c;
        }));
    }
    ControllerConfig edge = good;
    edge.crc_table_check_values = 256U;
    CHECK_FALSE(test::violates_contract([&] {
        const SafetyController c = w.controller(edge, clock);
        (void)c;
    }));
}

// verifies: SR-CTRL-001, SR-LOGIC-004
TEST_CASE("controller: a commissioned background view of another size than the sensor's image refuses the frame") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    const sim::SimulatedFrame empty = sim::render_frame(w.sensors, sim::reference_scene());
    BackgroundReference short_ref;
    short_ref.depth = Span<const float>(empty.depth[2].data(), empty.depth[2].size() - 1U);
    Frame f(w, sim::reference_scene(), clock.t);
    f.inputs[2].background = &short_ref;
    const CycleReport& r = c.run_cycle(f.span(), false);
    CHECK((r.detected_faults & fault_bit(Fault::kFrameInconsistent)) != 0U);
    CHECK(r.safety.stop_requested);
}

// verifies: SR-SSM-001, SR-SSM-022
TEST_CASE(
    "controller: a protective separation distance beyond the frame's range is refused and reported as far, a NaN one as 0") {
    Workcell w;
    TestClock clock;
    RobotCell rc(w, -0.6, -0.5);
    ControllerConfig cfg = rc.config(w);
    cfg.robot.separation.classes[0].stopping_distance_m = 100.0;  // 100 m: beyond 65,535 mm
    SafetyController far = w.controller(cfg, clock);
    const Frame f(w, rc.scene(), clock.t);
    const CycleReport& a = far.run_cycle(f.span(), false);                      // no command: no pose, the stop
    CHECK((a.safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);  // refused at construction (SR-SSM-002)
    CHECK(a.robot.configured);
    CHECK(a.robot.required_mm == kDistanceFarMm);
    CHECK(a.robot.speed_request == SpeedRequest::kProtectiveStop);
    CHECK(a.safety.stop_requested);
    cfg.robot.separation.classes[0].stopping_distance_m = std::numeric_limits<double>::quiet_NaN();
    SafetyController nan = w.controller(cfg, clock);
    const CycleReport& b = nan.run_cycle(f.span(), false);
    CHECK(b.robot.required_mm == 0U);
    CHECK(b.robot.speed_request == SpeedRequest::kProtectiveStop);
    CHECK(b.safety.stop_requested);
}

// verifies: SR-CTRL-002
TEST_CASE("controller: more sensor inputs than sensor slots are a missing-sensor fault, cycle after cycle") {
    Workcell w;
    TestClock clock;
    ControllerConfig cfg = w.config();
    cfg.max_repeated_frames = 100U;
    SafetyController c = w.controller(cfg, clock);
    Frame f(w, sim::reference_scene(), clock.t);
    const std::vector<SensorInput> four = f.inputs;
    while (f.inputs.size() <= kMaxSensors) {
        f.inputs.push_back(four[f.inputs.size() % four.size()]);
    }
    REQUIRE(f.inputs.size() == kMaxSensors + 1U);
    for (std::size_t cycle = 0U; cycle <= kMaxSensors + 1U; ++cycle) {  // the table check passes every slot
        for (SensorInput& in : f.inputs) {
            in.captured_us = clock.t;
        }
        const CycleReport& r = c.run_cycle(f.span(), false);
        CAPTURE(cycle);
        CHECK((r.detected_faults & fault_bit(Fault::kSensorMissing)) != 0U);
        CHECK((r.detected_faults & fault_bit(Fault::kSensorStale)) == 0U);
        CHECK(r.safety.stop_requested);
    }
}

// verifies: SR-CTRL-002
TEST_CASE(
    "controller: by footprint, a depth image beyond the sensor slots is fused by its rays, as the ray path does") {
    Workcell w;
    host::OwnedFootprintWorkspaces ws(w.g, kMaxSensors, 320, 240);
    ControllerConfig fc = w.config();
    fc.footprint.method = FusionMethod::kFootprint;
    fc.footprint.workspaces = ws.spans();
    TestClock ray_clock;
    TestClock fp_clock;
    SafetyController ray = w.controller(ray_clock);
    SafetyController fp = w.controller(fc, fp_clock);
    const auto nine = [](Frame& f, std::uint64_t now) {
        const std::vector<SensorInput> four = f.inputs;
        while (f.inputs.size() <= kMaxSensors) {
            f.inputs.push_back(four[f.inputs.size() % four.size()]);
        }
        for (SensorInput& in : f.inputs) {
            in.captured_us = now;
        }
        return f.span();
    };
    Frame a(w, with_person(0.2, 0.4), ray_clock.t);
    Frame b(w, with_person(0.2, 0.4), fp_clock.t);
    const CycleReport r = ray.run_cycle(nine(a, ray_clock.t), false);
    const CycleReport f = fp.run_cycle(nine(b, fp_clock.t), false);
    CHECK(f.detected_faults == fault_bit(Fault::kSensorMissing));  // 9 inputs for 4 sensors, every one fused
    CHECK(r.detected_faults == fault_bit(Fault::kSensorMissing));
    CHECK(f.fusion.rays_fused == r.fusion.rays_fused);
    CHECK(f.fusion.readings_in_grid == r.fusion.readings_in_grid);
    CHECK(f.safety.stop_requested);
}

// verifies: SR-CASE-002, SR-LOGIC-006
TEST_CASE("controller: a monitoring case set without any case is refused at construction: internal-check fault, stop") {
    Workcell w;
    TestClock clock;
    const MonitoringCases none;  // the placeholder: no case 0 either
    ControllerConfig cfg = w.config();
    cfg.cases = &none;
    SafetyController c = w.controller(cfg, clock);
    const Frame f(w, sim::reference_scene(), clock.t);
    for (int i = 0; i < 2; ++i) {
        const CycleReport& r = c.run_cycle(f.span(), false);
        CHECK((r.safety.latched_faults & fault_bit(Fault::kInternalCheck)) != 0U);
        CHECK((r.detected_faults & fault_bit(Fault::kCommandInvalid)) != 0U);  // no command can name a case
        CHECK(r.safety.stop_requested);
    }
}

namespace {
/// Runs every task in order on the calling thread, counting the batches it was given.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class CountingRunner final : public TaskRunner {
public:
    void run(std::size_t count, TaskFunction task, void* context) noexcept override {
        ++batches;
        sequential.run(count, task, context);
    }
    [[nodiscard]] std::size_t concurrency() const noexcept override { return sequential.concurrency(); }
    SequentialRunner sequential;
    int batches = 0;
};
}  // namespace

// verifies: SR-CTRL-001
TEST_CASE("controller: footprint fusion uses the port's task runner when one is given, with the built-in's result") {
    Workcell w;
    host::OwnedFootprintWorkspaces ws(w.g, w.sensors.size(), 320, 240);
    ControllerConfig fc = w.config();
    fc.footprint.method = FusionMethod::kFootprint;
    fc.footprint.workspaces = ws.spans();
    TestClock own_clock;
    SafetyController own = w.controller(fc, own_clock);
    const CycleReport a = own.run_cycle(Frame(w, with_person(0.2, 0.4), own_clock.t).span(), false);
    CountingRunner runner;
    fc.footprint.runner = &runner;
    TestClock port_clock;
    SafetyController port = w.controller(fc, port_clock);
    const CycleReport b = port.run_cycle(Frame(w, with_person(0.2, 0.4), port_clock.t).span(), false);
    CHECK(runner.batches > 0);
    CHECK(b.detected_faults == 0U);
    CHECK(b.fusion.rays_fused == a.fusion.rays_fused);
    CHECK(b.zones.zones[0].state == a.zones.zones[0].state);
    CHECK(b.zones.zones[0].foreground == a.zones.zones[0].foreground);
    CHECK(b.safety.stop_requested);
}

// verifies: SR-CTRL-001
TEST_CASE(
    "controller: by footprint, a point-set sensor among depth images is fused by its rays, as the ray path does") {
    Workcell w;
    host::OwnedFootprintWorkspaces ws(w.g, w.sensors.size(), 320, 240);
    ControllerConfig fc = w.config();
    fc.footprint.method = FusionMethod::kFootprint;
    fc.footprint.workspaces = ws.spans();
    TestClock ray_clock;
    TestClock fp_clock;
    TestClock table_clock;
    SafetyController ray = w.controller(ray_clock);
    SafetyController fp = w.controller(fc, fp_clock);
    SafetyController with_table = w.controller(table_clock);  // by ray, the slot's depth-image ray table attached
    Frame a(w, with_person(0.2, 0.4), ray_clock.t);
    Frame b(w, with_person(0.2, 0.4), fp_clock.t);
    Frame c(w, with_person(0.2, 0.4), table_clock.t);
    test::RayTableVectors storage(w.g, c.inputs[3].reading);
    const Result<RayTable> table = RayTable::build(w.g, c.inputs[3].reading, storage.storage());
    REQUIRE(table.ok());
    const std::vector<Eigen::Vector3f> points = depth_image_points(a.inputs[3].reading);
    REQUIRE_FALSE(points.empty());
    for (Frame* f : {&a, &b, &c}) {
        SensorReading p = f->inputs[3].reading;
        p.kind = SensorDataKind::kPointSet;
        p.points = Span<const Eigen::Vector3f>(points.data(), points.size());
        f->inputs[3].reading = p;
    }
    c.inputs[3].table = &table.value();
    const CycleReport r = ray.run_cycle(a.span(), false);
    const CycleReport f = fp.run_cycle(b.span(), false);
    const CycleReport t = with_table.run_cycle(c.span(), false);
    CHECK(r.detected_faults == 0U);
    CHECK(f.detected_faults == 0U);
    CHECK(f.fusion.rays_fused == r.fusion.rays_fused);
    CHECK(f.zones.zones[0].state == r.zones.zones[0].state);
    CHECK(f.zones.zones[0].state == ZoneState::kIntruded);
    CHECK(f.safety.stop_requested);
    // A point set is never fused through a table (its points are not the table's rays): as without one.
    CHECK(t.detected_faults == 0U);
    CHECK(t.fusion.rays_fused == r.fusion.rays_fused);
    CHECK(t.fusion.voxel_updates == r.fusion.voxel_updates);
    CHECK(t.zones.zones[0].state == ZoneState::kIntruded);
    CHECK(t.safety.stop_requested);
}

// verifies: SR-CTRL-002
TEST_CASE("controller: a cycle without any sensor input is a missing-sensor fault and the stop") {
    Workcell w;
    TestClock clock;
    SafetyController c = w.controller(clock);
    for (int i = 0; i < 2; ++i) {
        const CycleReport& r = c.run_cycle(Span<const SensorInput>{}, false);
        CHECK((r.detected_faults & fault_bit(Fault::kSensorMissing)) != 0U);
        CHECK((r.detected_faults & fault_bit(Fault::kInternalCheck)) == 0U);
        CHECK(r.fusion.rays_fused == 0U);
        CHECK(r.safety.stop_requested);
    }
}
