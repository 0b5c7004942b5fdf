// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: a changed background is detected at run time (hazards
// H-PRI-3, H-SEN-3): a background box moved 10 cm or removed, or a sensor
// tilted by 1 degree, makes pixels LONGER than the commissioned view; more
// than BackgroundReference::max_longer_pixels of them in changed_cycles
// frames in a row latch kPriorCheckFailed and the stop, for good. An empty
// cell and the demo's person (who can only make depths shorter) do not.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "cellguard/firmware/scenario.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "paper_cell.hpp"
#include "test_tags.hpp"

using namespace cellguard;

namespace {

class StepClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t += 1U; }
    std::uint64_t t = 1000000U;
};

// The paper cell with its prior, the firmware scenario's zones and each
// sensor's commissioned view of the empty cell (as the monitor builds it
// for prior.source = "simulated-background"). The render of the empty cell,
// G_B and the prior are built once per process (paper_cell.hpp); each Cell
// has its own copies of every buffer the controller or a test may change.
struct Cell {
    GridGeometry g = paper_grid_geometry();
    std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const test::PaperCellCommissioning& commissioned = test::paper_cell_commissioning();
    std::vector<std::int16_t> frame_lo = commissioned.frame_log_odds;
    std::vector<std::int16_t> prior = commissioned.prior;
    std::vector<std::int16_t> scratch = commissioned.scratch;
    std::vector<std::uint8_t> frame_ob = commissioned.frame_observed;
    std::vector<std::uint32_t> mask;
    EvidenceGrid frame_grid;
    CompiledZones zones;
    SensorModelTable model;
    const sim::SimulatedFrame& empty = commissioned.empty;  // read-only, shared
    std::vector<BackgroundReference> refs;

    Cell() : mask(g.voxel_count()), refs(sensors.size()) {
        frame_grid =
            EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
        const auto zs = firmware::scenario_zone_configs();
        zones = CompiledZones::compile(g, {zs.data(), zs.size()}, {mask.data(), mask.size()}).value();
        for (std::size_t s = 0; s < refs.size(); ++s) {
            refs[s].depth = Span<const float>(empty.depth[s].data(), empty.depth[s].size());  // the defaults otherwise
        }
    }

    SafetyController controller(MonotonicClock& clock) {
        return SafetyController(firmware::scenario_controller_config(sensors.size()), frame_grid,
                                {scratch.data(), scratch.size()}, {prior.data(), prior.size()}, zones, model, clock,
                                nullptr);
    }
};

// One cycle's inputs: sensor s renders @p scene with @p specs[s] (the
// controller keeps the commissioned poses of @p cell.sensors), each with its reference.
struct Inputs {
    sim::SimulatedFrame sim;
    std::vector<SensorInput> in;
    Inputs(const Cell& cell, const std::vector<sim::SensorSpec>& specs, const sim::Scene& scene, std::uint64_t now)
        : sim(sim::render_frame(specs, scene)) {
        add(cell, sim, now);
    }
    // The empty cell seen from the commissioned poses: the shared render of
    // it (render_frame of the same sensors and scene gives these images, bit for bit).
    Inputs(const Cell& cell, std::uint64_t now) { add(cell, cell.empty, now); }
    void add(const Cell& cell, const sim::SimulatedFrame& frame, std::uint64_t now) {
        for (std::size_t s = 0; s < frame.depth.size(); ++s) {
            SensorInput i;
            i.reading = sim::depth_reading(cell.sensors[s],
                                           Span<const float>(frame.depth[s].data(), frame.depth[s].size()));
            i.captured_us = now;
            i.present = true;
            i.background = &cell.refs[s];
            in.push_back(i);
        }
    }
    Span<const SensorInput> span() const { return {in.data(), in.size()}; }
};

// What a run of a changed cell gives: the cycle (1-based, after the
// change) in which kPriorCheckFailed was first detected (0: never), and
// the largest count of longer pixels of any sensor.
struct ChangeRun {
    int detected_cycle = 0;
    std::uint32_t max_longer = 0U;
    std::uint32_t changed_sensors = 0U;
    bool stop_after = false;
    bool stays_latched = true;
};

// The cycles a changed view is shown: the stated detection bound (BackgroundReference::changed_cycles'
// default) and one more, so a fault found later than the bound fails the check, not the run's length.
constexpr int kBound = 3;
constexpr int kChangedCycles = kBound + 1;
// The cycles of the empty cell after the change: the latch must hold through them.
constexpr int kCyclesAfter = 2;

// Two cycles of the empty cell, then @p cycles of @p specs looking at @p
// scene, then the empty cell again (the change undone): the fault must stay.
ChangeRun run_change(const std::vector<sim::SensorSpec>& specs, const sim::Scene& scene, int cycles) {
    Cell cell;
    StepClock clock;
    SafetyController c = cell.controller(clock);
    ChangeRun out;
    for (int k = 0; k < 2; ++k) {
        const Inputs empty(cell, clock.t);
        REQUIRE(c.run_cycle(empty.span(), false).detected_faults == 0U);
    }
    Inputs changed(cell, specs, scene, clock.t);
    for (int k = 1; k <= cycles; ++k) {
        for (SensorInput& i : changed.in)  // fresh time stamps, the same data
            i.captured_us = clock.t;
        const CycleReport& r = c.run_cycle(changed.span(), false);
        for (std::size_t s = 0; s < specs.size(); ++s)
            out.max_longer = std::max(out.max_longer, c.background_change().last[s].longer);
        if (out.detected_cycle == 0 && (r.detected_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U) {
            out.detected_cycle = k;
            out.stop_after = r.safety.stop_requested;
        }
    }
    out.changed_sensors = c.background_change().latched;
    for (int k = 0; k < kCyclesAfter; ++k) {
        const Inputs empty(cell, clock.t);
        const CycleReport& r = c.run_cycle(empty.span(), false);
        out.stays_latched = out.stays_latched && r.safety.stop_requested &&
                            (r.safety.latched_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U;
    }
    return out;
}

void report(const char* what, const ChangeRun& r) {
    std::printf("background change: %s: detected in cycle %d, up to %u longer pixels per sensor, sensors 0x%x\n", what,
                r.detected_cycle, r.max_longer, r.changed_sensors);
}

// Sensor @p s of @p specs turned by @p degrees about its own horizontal axis (pitch) or the vertical (yaw).
std::vector<sim::SensorSpec> turned(std::vector<sim::SensorSpec> specs, std::size_t s, double degrees, bool pitch) {
    const Eigen::Vector3d view = specs[s].target - specs[s].position;
    const Eigen::Vector3d axis = pitch ? view.cross(Eigen::Vector3d::UnitZ()).normalized() : Eigen::Vector3d::UnitZ();
    specs[s].target = specs[s].position + Eigen::AngleAxisd(degrees * M_PI / 180.0, axis) * view;
    return specs;
}

}  // namespace

// verifies: SR-BKG-004
TEST_CASE("background change: a background box moved 10 cm latches the prior fault and the stop within 3 cycles") {
    for (const double dx : {0.1, -0.1}) {
        sim::Scene moved = sim::reference_scene();
        moved.boxes[0].center.x() += dx;
        const ChangeRun r = run_change(sim::paper_sensors(), moved, kChangedCycles);
        report(dx > 0.0 ? "box A moved +10 cm in x" : "box A moved -10 cm in x", r);
        CHECK(r.detected_cycle == kBound);
        CHECK(r.stop_after);
        CHECK(r.max_longer > BackgroundReference{}.max_longer_pixels);
        CHECK(r.stays_latched);
    }
    sim::Scene moved = sim::reference_scene();
    moved.boxes[1].center.y() += 0.1;
    const ChangeRun r = run_change(sim::paper_sensors(), moved, kChangedCycles);
    report("box B moved +10 cm in y", r);
    CHECK(r.detected_cycle == kBound);
    CHECK(r.stays_latched);
}

// verifies: SR-BKG-004
TEST_CASE("background change: a removed background box latches the prior fault and the stop within 3 cycles") {
    for (std::size_t b = 0; b < 2U; ++b) {
        sim::Scene removed = sim::reference_scene();
        removed.boxes.erase(removed.boxes.begin() + static_cast<std::ptrdiff_t>(b));
        const ChangeRun r = run_change(sim::paper_sensors(), removed, kChangedCycles);
        report(b == 0U ? "box A removed" : "box B removed", r);
        CHECK(r.detected_cycle == kBound);
        CHECK(r.stop_after);
        CHECK(r.stays_latched);
    }
}

// verifies: SR-BKG-004
TEST_CASE("background change: a sensor tilted or turned by 1 degree latches the prior fault within 3 cycles" *
          CELLGUARD_LONG_REPLAY) {
    for (std::size_t s = 0; s < 4U; ++s) {
        for (const double deg : {1.0, -1.0}) {
            for (const bool pitch : {true, false}) {
                const ChangeRun r = run_change(turned(sim::paper_sensors(), s, deg, pitch), sim::reference_scene(),
                                               kChangedCycles);
                char what[64];
                std::snprintf(what, sizeof what, "sensor %zu %s %+.0f degree", s, pitch ? "pitched" : "yawed", deg);
                report(what, r);
                CAPTURE(what);
                CHECK(r.detected_cycle == kBound);
                CHECK(r.changed_sensors == (1U << s));
                CHECK(r.stays_latched);
            }
        }
    }
}

// verifies: SR-BKG-004
TEST_CASE("background change: the empty cell and the demo's walking person never trip it" * CELLGUARD_LONG_REPLAY) {
    Cell cell;
    StepClock clock;
    SafetyController c = cell.controller(clock);
    std::vector<cell::SimulatedFrameSource> sources;
    sources.reserve(cell.sensors.size());
    for (const sim::SensorSpec& spec : cell.sensors)
        sources.emplace_back(spec);
    std::vector<SensorInput> in(cell.sensors.size());
    std::uint32_t max_longer = 0U;
    double min_fraction = 1.0;
    bool person_stop = false;
    for (int k = 0; k < 120; ++k) {
        for (std::size_t s = 0; s < in.size(); ++s) {
            cell::FrameStatus status;
            REQUIRE(sources[s].load_frame(static_cast<std::uint64_t>(k), in[s].reading, status));
            in[s].captured_us = clock.t;
            in[s].present = true;
            in[s].background = &cell.refs[s];
        }
        const CycleReport& r = c.run_cycle({in.data(), in.size()}, false);
        CHECK((r.detected_faults & fault_bit(Fault::kPriorCheckFailed)) == 0U);
        person_stop = person_stop || r.safety.stop_requested;
        for (std::size_t s = 0; s < in.size(); ++s) {
            const BackgroundMatch m = c.background_change().last[s];
            max_longer = std::max(max_longer, m.longer);
            min_fraction = std::min(min_fraction, static_cast<double>(m.matching) / m.referenced);
        }
    }
    std::printf(
        "background change: demo person, 120 cycles: at most %u longer pixels per sensor (limit %u), "
        "at least %.3f of a view matched (limit 0.5)\n",
        max_longer, BackgroundReference{}.max_longer_pixels, min_fraction);
    CHECK(person_stop);  // the person did enter the protective zone: the run exercised the scenario
    CHECK(c.background_change().latched == 0U);
    CHECK(max_longer <= BackgroundReference{}.max_longer_pixels);
}

// verifies: SR-BKG-003
TEST_CASE(
    "background change: a changed frame that comes back to the view before changed_cycles frames does not latch") {
    Cell cell;
    StepClock clock;
    SafetyController c = cell.controller(clock);
    sim::Scene removed = sim::reference_scene();
    removed.boxes.erase(removed.boxes.begin());
    for (int k = 0; k < 12; ++k) {
        // Two changed frames, one of the empty cell: never three in a row.
        const Inputs f(cell, cell.sensors, (k % 3 == 2) ? sim::reference_scene() : removed, clock.t);
        CHECK((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kPriorCheckFailed)) == 0U);
    }
    // changed_cycles = 0 turns the check off; 1 latches in the first changed frame.
    for (BackgroundReference& r : cell.refs)
        r.changed_cycles = 0U;
    for (int k = 0; k < 4; ++k) {
        const Inputs f(cell, cell.sensors, removed, clock.t);
        CHECK((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kPriorCheckFailed)) == 0U);
    }
    for (BackgroundReference& r : cell.refs)
        r.changed_cycles = 1U;
    const Inputs f(cell, cell.sensors, removed, clock.t);
    CHECK((c.run_cycle(f.span(), false).detected_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U);
}

// verifies: SR-BKG-003
TEST_CASE("background change: a uint16 depth image read with a wrong scale or offset is refused or latches the fault") {
    struct Case {
        const char* what;
        float scale;
        float offset;
        bool latches;  // deeper than the view: the changed-background check; shallower: the match fraction
    };
    const Case cases[] = {{"scale 1.1 mm instead of 1 mm", 0.0011F, 0.0F, true},
                          {"scale 0.9 mm instead of 1 mm", 0.0009F, 0.0F, false},
                          {"offset +0.1 m left in", 0.001F, 0.1F, true},
                          {"0.1 mm units read as mm", 0.01F, 0.0F, true}};
    for (const Case& k : cases) {
        CAPTURE(k.what);
        Cell cell;
        StepClock clock;
        SafetyController c = cell.controller(clock);
        // The cameras deliver whole millimetres of the empty cell; the reading's scale and offset are wrong.
        std::vector<std::vector<std::uint16_t>> raw(cell.sensors.size());
        std::vector<SensorInput> in(cell.sensors.size());
        for (std::size_t s = 0; s < in.size(); ++s) {
            for (const float d : cell.empty.depth[s])
                raw[s].push_back(std::isfinite(d) && d > 0.0F ? static_cast<std::uint16_t>(std::lround(d * 1000.0F))
                                                              : std::uint16_t{0U});
            in[s].reading = cell.empty.readings[s];
            in[s].reading.kind = SensorDataKind::kDepthImageU16;
            in[s].reading.depth_u16 = Span<const std::uint16_t>(raw[s].data(), raw[s].size());
            in[s].present = true;
            in[s].background = &cell.refs[s];
        }
        int latched = 0;
        bool refused = false;
        for (int cycle = 1; cycle <= 5; ++cycle) {
            for (std::size_t s = 0; s < in.size(); ++s) {
                in[s].captured_us = clock.t;
                in[s].reading.depth_scale = (cycle == 1) ? 0.001F : k.scale;  // the first cycle is right
                in[s].reading.depth_offset = (cycle == 1) ? 0.0F : k.offset;
            }
            const CycleReport& r = c.run_cycle({in.data(), in.size()}, false);
            if (cycle == 1) {
                REQUIRE(r.detected_faults == 0U);  // whole millimetres match the view
                continue;
            }
            refused = refused || (r.detected_faults & fault_bit(Fault::kFrameInconsistent)) != 0U;
            if (latched == 0 && (r.detected_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U)
                latched = cycle - 1;
            CHECK(r.safety.stop_requested);
        }
        std::printf("background change: uint16 %s: frame refused %s, prior fault latched in cycle %d\n", k.what,
                    refused ? "yes" : "no", latched);
        CHECK(refused);  // either way less than half the view matches
        CHECK((latched == kBound) == k.latches);
    }
}
