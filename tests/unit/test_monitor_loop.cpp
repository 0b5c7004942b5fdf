// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the monitor's cycle (apps/monitor: monitor_loop.hpp): after start-up
// its cycles allocate nothing, on the simulated demo and with a recorded PCD
// sensor, each sensor's frame is loaded exactly once per cycle, and the
// simulator's allocation-free rendering into caller buffers gives
// render_frame's images bit for bit; protocol 0.2 in a cell without a robot:
// the simulated PLC's link frames alone are echoed and its receiver accepts
// the controller's pairs, and without a PLC link no pair is accepted.
#include <doctest/doctest.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/port/clock.hpp"
#include "cellguard/port/frame_signal.hpp"
#include "monitor_test_doubles.hpp"
#include "test_tags.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;
using cellguard::test::CountingSender;
using cellguard::test::SteppingClock;

namespace {

/// Passes loads on to another source and counts them per cycle.
class CountingSource final : public FrameSource {
public:
    explicit CountingSource(FrameSource& inner) : inner_(&inner) {}
    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override {
        // Loads must come once per cycle, in cycle order.
        if (cycle != next_cycle) {
            ++out_of_order;
        }
        next_cycle = cycle + 1U;
        ++loads;
        return inner_->load_frame(cycle, reading, status);
    }
    void write_summary(std::FILE* out) const noexcept override { inner_->write_summary(out); }
    [[nodiscard]] bool has_new_frame() const noexcept override { return new_frames; }

    bool new_frames = true;  ///< what has_new_frame() says (a live camera's answer, set by the test)
    std::uint64_t loads = 0U;
    std::uint64_t next_cycle = 0U;
    std::uint64_t out_of_order = 0U;

private:
    FrameSource* inner_;
};

/// A sink for status lines whose buffer is the caller's: writing allocates nothing.
struct NullOutput {
    NullOutput() : file(std::fopen("/dev/null", "w")) {
        REQUIRE(file != nullptr);
        std::setvbuf(file, buffer, _IOFBF, sizeof buffer);
    }
    ~NullOutput() { std::fclose(file); }
    NullOutput(const NullOutput&) = delete;
    NullOutput& operator=(const NullOutput&) = delete;
    std::FILE* file;
    char buffer[8192] = {};
};

/// A CanSender that counts the frames and hands each to a PLC receiver (the monitor's frames as a PLC gets them).
class PlcSideSender final : public CanSender {
public:
    explicit PlcSideSender(const PlcReceiverConfig& config) : plc(config) {}
    bool send(const CanFrame& frame) noexcept override {
        ++frames;
        if (frame.id != plc.config().link.own.can_id) {  // not the PLC's own link frames
            status = plc.on_frame(frame, ++now_us);
        }
        return true;
    }
    PlcReceiver plc;
    ReceiverStatus status{};
    std::uint64_t now_us = 0U;
    std::size_t frames = 0U;
};

/// The monitor as main wires it, with counting sources and a counting sender;
/// with @p with_plc the simulated PLC of a log run (its link frames alone).
struct Monitor {
    explicit Monitor(MonitorConfig config, bool with_plc = true) : cfg(std::move(config)), clock(false, source_clock) {
        cfg.budget_us = 60000000U;  // the cycles' decisions, not this host's speed (as the demo's ctest)
        REQUIRE_FALSE(cell.configure(cfg).failed());
        REQUIRE_FALSE(cell.build_prior(cfg, nullptr).failed());
        REQUIRE_FALSE(cell.build_tables(cfg, nullptr).failed());
        for (std::size_t s = 0U; s < cfg.sensors.size(); ++s) {
            const sim::SensorSpec& spec = cell.specs[s];
            if (cfg.sensors[s].pcd_files.empty()) {
                simulated.push_back(std::make_unique<SimulatedFrameSource>(spec));
                counted.push_back(std::make_unique<CountingSource>(*simulated.back()));
            } else {
                recorded.push_back(std::make_unique<PcdFrameSource>(spec.name, cfg.sensors[s].pcd_files,
                                                                    sensor_pose(cfg.sensors[s]), spec.width,
                                                                    spec.height, spec.max_range));
                counted.push_back(std::make_unique<CountingSource>(*recorded.back()));
            }
            sources.push_back(counted.back().get());
        }
        can.use_sender(sender);
        if (with_plc) {
            plc = std::make_unique<SimulatedPlcLink>(command_receiver_config(cfg), plc_receiver_config(cfg), &can);
        }
        loop = std::make_unique<MonitorLoop>(cfg, cell, sources, can, clock, out.file, plc.get());
        REQUIRE(loop->status().ok());
    }

    /// Runs @p cycles cycles; returns the allocations of each.
    std::vector<std::size_t> run(int cycles) {
        std::vector<std::size_t> allocations(static_cast<std::size_t>(cycles));
        for (int k = 0; k < cycles; ++k) {
            const test::AllocationScope scope;
            (void)loop->run_cycle(k);
            allocations[static_cast<std::size_t>(k)] = scope.allocations();
        }
        return allocations;
    }

    MonitorConfig cfg;
    MonitorCell cell;
    SteppingClock source_clock;
    CycleClock clock;
    CountingSender sender;
    CanPort can;
    NullOutput out;
    std::vector<std::unique_ptr<SimulatedFrameSource>> simulated;
    std::vector<std::unique_ptr<PcdFrameSource>> recorded;
    std::vector<std::unique_ptr<CountingSource>> counted;
    std::vector<FrameSource*> sources;
    std::unique_ptr<SimulatedPlcLink> plc;
    std::unique_ptr<MonitorLoop> loop;
};

/// Cycles of @p allocations that allocated.
int cycles_that_allocated(const std::vector<std::size_t>& allocations) {
    int n = 0;
    for (const std::size_t a : allocations) {
        n += a != 0U ? 1 : 0;
    }
    return n;
}

}  // namespace

// verifies: SR-GEN-002, SR-SYS-001
TEST_CASE("monitor loop: 1,000 cycles of the simulated demo allocate nothing and load each frame once per cycle" *
          CELLGUARD_LONG_REPLAY) {
    Monitor m(demo_config());
    const int cycles = 1000;
    const std::vector<std::size_t> allocations = m.run(cycles);
    CHECK(cycles_that_allocated(allocations) == 0);
    CHECK(allocations[0] == 0U);
    for (const std::unique_ptr<CountingSource>& c : m.counted) {
        CHECK(c->loads == static_cast<std::uint64_t>(cycles));
        CHECK(c->out_of_order == 0U);
    }
    for (const std::unique_ptr<SimulatedFrameSource>& s : m.simulated) {
        CHECK(s->renders() == static_cast<std::uint64_t>(cycles));  // each image rendered once per cycle
    }
    // The demo's decisions: four frames per cycle and the PLC's link frame,
    // the stop when the person enters the protective zone (cycle 15), no fault.
    CHECK(m.sender.frames == 5U * static_cast<std::size_t>(cycles));
    // Protocol 0.2 without a robot: the controller refuses the PLC's first link
    // frame (no echo of its session yet: the handshake) and accepts the rest;
    // the PLC's receiver accepts the controller's pairs.
    CHECK(m.plc->standalone_link().accepted == static_cast<std::uint32_t>(cycles - 1));
    CHECK(m.plc->standalone_link().refused == 1U);
    CHECK(m.plc->standalone_link().last == LinkFault::kNoEchoYet);
    CHECK(m.plc->plc_status().communication_valid);
    CHECK(m.plc->plc_status().fault_events == 0U);
    const MonitorStats& st = m.loop->stats();
    CHECK(st.cycles_run == cycles);
    CHECK(st.send_failures == 0);
    CHECK(st.faults_seen == 0U);
    CHECK(st.first_stop_after_release == 15);
    const std::string line = m.loop->status_line();
    CHECK(line.rfind("t= 99.900s cycle 999 person (-1.40, 0.20) outside          | protective:CLEAR "
                     "warning:CLEAR | run  -    | faults - | cycle ",
                     0) == 0);
    CHECK(line.back() == '\n');
}

// Issue 32: live-camera runs printed the demo's scripted person on the status line.
// verifies: SR-SYS-001
TEST_CASE("monitor loop: the summary's figures are the median, the 99th and 99.9th percentiles and the maximum") {
    std::vector<std::uint64_t> us;
    for (std::uint64_t k = 1000U; k >= 1U; --k) {  // 1000 .. 1, descending: the figures sort
        us.push_back(k);
    }
    const DurationFigures f = duration_figures(us, us.size());
    CHECK(f.count == 1000U);
    CHECK(f.median == 501U);
    CHECK(f.p99 == 990U);
    CHECK(f.p999 == 999U);
    CHECK(f.max == 1000U);
    const DurationFigures few = duration_figures(us, 10U);  // the first 10: 1000 .. 991
    CHECK(few.count == 10U);
    CHECK(few.p999 == 1000U);  // with fewer than 1,000 durations p99.9 is the maximum
    CHECK(few.median == 996U);
    CHECK(duration_figures(us, 0U).count == 0U);
}

// verifies: SR-SYS-001
TEST_CASE("monitor loop: the status line shows the scripted person for simulated sensors only") {
    Monitor m(demo_config());
    static_cast<void>(m.loop->run_cycle(0));
    CHECK(std::string(m.loop->status_line()).find(" person (") != std::string::npos);
    for (SensorSettings& s : m.cfg.sensors) {
        s.camera.enabled = true;  // as a configuration of live cameras says (the frames here stay simulated)
    }
    m.loop = std::make_unique<MonitorLoop>(m.cfg, m.cell, m.sources, m.can, m.clock, m.out.file);
    static_cast<void>(m.loop->run_cycle(1));
    const std::string line = m.loop->status_line();
    INFO(line);
    CHECK(line.find(" person (") == std::string::npos);
    CHECK(line.find(" live cameras ") != std::string::npos);
}

// verifies: SR-GEN-002, SR-SYS-001
TEST_CASE("monitor loop: with footprint fusion the demo's and the real cell's cycles allocate nothing" *
          CELLGUARD_LONG_REPLAY) {
    MonitorConfig paper = demo_config();
    paper.fusion.method = FusionMethod::kFootprint;
    Monitor m(paper);
    const int cycles = 30;
    const std::vector<std::size_t> allocations = m.run(cycles);
    CHECK(cycles_that_allocated(allocations) == 0);
    CHECK(m.loop->stats().faults_seen == 0U);
    CHECK(m.loop->stats().first_stop_after_release == 15);
    // The real cell: four 640 x 480 cameras into 80 x 80 x 50 voxels (its
    // start-up fuses the fewest background frames, for this test's time).
    const ConfigLoad real = load_monitor_config(std::string(CELLGUARD_SOURCE_DIR) +
                                                "/apps/monitor/config/real-cell.toml");
    REQUIRE(real.ok);
    MonitorConfig cfg = real.config;
    cfg.prior.background_frames = 3;
    Monitor r(cfg);
    const std::vector<std::size_t> real_allocations = r.run(3);
    CHECK(cycles_that_allocated(real_allocations) == 0);
    CHECK(r.loop->stats().faults_seen == 0U);
    CHECK(r.loop->stats().cycles_run == 3);
}

// verifies: SR-GEN-002, SR-SYS-005
TEST_CASE("monitor loop: with a recorded PCD sensor, good and refused frames allocate nothing, each read once") {
    const ConfigLoad load = load_monitor_config(CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd-cell.toml");
    REQUIRE_MESSAGE(load.ok, load.error);
    Monitor m(load.config);
    REQUIRE(m.recorded.size() == 1U);
    // Its six files, in turn: ASCII, binary, another sensor's, the wrong size, truncated, ASCII again.
    const int cycles = 120;
    const std::vector<std::size_t> allocations = m.run(cycles);
    CHECK(cycles_that_allocated(allocations) == 0);
    for (const std::unique_ptr<CountingSource>& c : m.counted) {
        CHECK(c->loads == static_cast<std::uint64_t>(cycles));
        CHECK(c->out_of_order == 0U);
    }
    const PcdFrameSource& pcd = *m.recorded.front();
    CHECK(pcd.used() == 60U);  // every file read once per cycle it is due
    CHECK(pcd.refused() == 60U);
    CHECK((m.loop->stats().faults_seen & fault_bit(Fault::kFrameInconsistent)) != 0U);
    CHECK(m.sender.frames == 5U * static_cast<std::size_t>(cycles));
}

// verifies: SR-CAN-017
TEST_CASE("monitor loop: without a PLC link the controller's link frames echo nothing and a PLC refuses every pair") {
    // The PLC's receiver sees the monitor's frames but sends nothing itself:
    // no round trip, so no age bound, so no pair is ever accepted (the stop holds).
    Monitor m(demo_config(), false);
    PlcSideSender plc_side(plc_receiver_config(m.cfg));
    m.can.use_sender(plc_side);
    static_cast<void>(m.run(20));
    CHECK(plc_side.frames == 4U * 20U);  // safety frame, copy, link frame, diagnostics
    CHECK_FALSE(plc_side.status.communication_valid);
    CHECK(plc_side.status.stop_requested);
    CHECK(plc_side.status.fault == ReceiverFault::kNoEchoYet);
    CHECK(plc_side.status.fault_events >= 20U);  // every pair refused
    // The summary says so.
    char text[4096] = {};
    std::FILE* summary = fmemopen(text, sizeof text, "w");
    REQUIRE(summary != nullptr);
    m.loop->write_summary(summary, RunResult{}, true);
    std::fclose(summary);
    CHECK(std::string(text).find("summary: no PLC link: the link frames carry no echo, a PLC refuses them") !=
          std::string::npos);
}

// verifies: SR-SYS-005
TEST_CASE("monitor loop: the allocation-free PCD load finds what load() finds") {
    const ConfigLoad load = load_monitor_config(CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd-cell.toml");
    REQUIRE_MESSAGE(load.ok, load.error);
    const SensorSettings& s = load.config.sensors.back();
    REQUIRE_FALSE(s.pcd_files.empty());
    PcdFrameSource a("recorded", s.pcd_files, sensor_pose(s), s.width, s.height, static_cast<float>(s.max_range));
    PcdFrameSource b("recorded", s.pcd_files, sensor_pose(s), s.width, s.height, static_cast<float>(s.max_range));
    for (std::uint64_t k = 0U; k < s.pcd_files.size(); ++k) {
        SensorReading ra;
        SensorReading rb;
        const PcdFrameCheck c = a.load(k, ra);
        FrameStatus st;
        const bool ok = b.load_frame(k, rb, st);
        CAPTURE(c.reason);
        CHECK(ok == c.ok);
        CHECK(c.file == st.file);
        CHECK(c.reason == st.reason);
        CHECK(c.points == st.points);
        CHECK(c.nonfinite == st.nonfinite);
        REQUIRE(ra.points.size() == rb.points.size());
        CHECK(std::memcmp(ra.points.data(), rb.points.data(), ra.points.size() * sizeof(Eigen::Vector3f)) == 0);
        CHECK(validate_sensor_reading(rb).ok() == ok);
    }
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: rendering into caller buffers gives render_frame's images and readings, bit for bit") {
    const std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    std::vector<std::vector<float>> images(sensors.size());
    std::vector<Span<float>> spans;
    std::vector<SensorReading> readings(sensors.size());
    for (std::size_t i = 0U; i < sensors.size(); ++i) {
        images[i].assign(static_cast<std::size_t>(sensors[i].width * sensors[i].height), -1.0F);
        spans.emplace_back(images[i].data(), images[i].size());
    }
    sim::PreparedScene prepared(4U);
    std::vector<SimulatedFrameSource> sources;  // undithered: the render bit for bit
    sources.reserve(sensors.size());
    for (const sim::SensorSpec& spec : sensors)
        sources.emplace_back(spec, FrameDither::kOff);
    for (const int k : {0, 15, 22, 34, 55}) {
        CAPTURE(k);
        // The demo's scene as the monitor always made it.
        sim::Scene scene = sim::reference_scene();
        scene.boxes.push_back(person_box(demo_person(k)));
        const sim::SimulatedFrame expected = sim::render_frame(sensors, scene);
        REQUIRE(prepared.assign(scene));
        REQUIRE(sim::render_frame_into(sensors, prepared, {spans.data(), spans.size()},
                                       {readings.data(), readings.size()}));
        for (std::size_t i = 0U; i < sensors.size(); ++i) {
            CHECK(std::memcmp(images[i].data(), expected.depth[i].data(), images[i].size() * sizeof(float)) == 0);
            CHECK(readings[i].depth.data() == images[i].data());
            CHECK(readings[i].pose.matrix() == expected.readings[i].pose.matrix());
            CHECK(readings[i].intrinsics.fx == expected.readings[i].intrinsics.fx);
            CHECK(readings[i].max_range == expected.readings[i].max_range);
            SensorReading r;
            FrameStatus st;
            REQUIRE(sources[i].load_frame(static_cast<std::uint64_t>(k), r, st));
            REQUIRE(r.depth.size() == expected.depth[i].size());
            CHECK(std::memcmp(r.depth.data(), expected.depth[i].data(), r.depth.size() * sizeof(float)) == 0);
        }
    }
    // Wrong sizes are refused, nothing written; a scene with more boxes than reserved is refused.
    std::vector<float> small(10U, -1.0F);
    CHECK_FALSE(sim::render_depth_into(sensors[0], prepared, {small.data(), small.size()}));
    CHECK(small[0] == -1.0F);
    CHECK_FALSE(sim::render_frame_into(sensors, prepared, {spans.data(), 2U}, {readings.data(), readings.size()}));
    sim::Scene crowded = sim::reference_scene();
    crowded.boxes.resize(5U);
    CHECK_FALSE(prepared.assign(crowded));
    CHECK(prepared.scene().boxes.size() == 3U);
}

// verifies: SR-CFG-018
TEST_CASE("monitor: reset_required on is refused at start in a cell without a PLC command, and kept in one with it") {
    cell::MonitorConfig cfg = cell::demo_config();
    CHECK_FALSE(cfg.reset_required);  // paper-cell.toml turns it off, with opt_out.reset_required
    CHECK_FALSE(monitor::check_start_settings(cfg).failed());
    cfg.reset_required = true;  // the loader's default
    const monitor::SetupError e = monitor::check_start_settings(cfg);
    CHECK(e.exit_status == 2);
    CHECK(e.message.find("no PLC command") != std::string::npos);
    CHECK(e.message.find("ResetRequest") != std::string::npos);
    CHECK(e.message.find("reset_required = \"<reason>\"") != std::string::npos);
    CHECK(cell::MonitorConfig{}.reset_required);
    // The robot cell: its PLC's command carries the reset request, so the interlock may wait for it.
    cell::MonitorConfig robot = cell::robot_cell_demo_config();
    CHECK(robot.reset_required);  // robot-cell.toml keeps the default
    CHECK_FALSE(monitor::check_start_settings(robot).failed());
    // A cell with monitoring cases and no robot has a command too, so its reset.
    cfg.cases.push_back(cell::CaseSettings{});
    CHECK_FALSE(monitor::check_start_settings(cfg).failed());
}

// A paced run started by the cameras' frames (run_cycles with a FrameSignal), on
// sources whose has_new_frame() the test sets. Only lower bounds of time are
// checked (a loaded host makes every wait longer, never shorter).
// verifies: SR-CAM-010
TEST_CASE("monitor loop: paced by frames, cycles start when every source has a new frame, half a period apart") {
    Monitor m(demo_config());
    CHECK(m.loop->frames_ready());
    linux_port::FrameSignal signal;
    const volatile std::sig_atomic_t stop = 0;
    const std::uint64_t period_us = 20000U;
    const std::uint64_t start = linux_port::monotonic_now_us();
    const RunResult run = run_cycles(*m.loop, 6, period_us, true, stop, &signal);
    const std::uint64_t elapsed = linux_port::monotonic_now_us() - start;
    CHECK(run.frame_started);
    CHECK(run.frame_starts == 6U);
    CHECK(run.deadline_starts == 0U);
    CHECK(elapsed >= 5U * period_us / 2U);  // the first at once, then every half period at the earliest
    for (const std::unique_ptr<CountingSource>& c : m.counted) {
        CHECK(c->loads == 6U);
    }
}

// verifies: SR-CAM-010
TEST_CASE("monitor loop: paced by frames, a source without a new frame holds the cycle to 1.125 periods, no longer") {
    Monitor m(demo_config());
    m.counted.back()->new_frames = false;  // one camera sends nothing new
    CHECK_FALSE(m.loop->frames_ready());
    linux_port::FrameSignal signal;
    signal.notify();  // a notify without a new frame of every source starts nothing
    const volatile std::sig_atomic_t stop = 0;
    const std::uint64_t period_us = 16000U;
    const std::uint64_t start = linux_port::monotonic_now_us();
    const RunResult run = run_cycles(*m.loop, 4, period_us, true, stop, &signal);
    const std::uint64_t elapsed = linux_port::monotonic_now_us() - start;
    CHECK(run.frame_starts == 0U);
    CHECK(run.deadline_starts == 4U);
    CHECK(elapsed >= 3U * (period_us + period_us / 8U));
    // Every cycle ran and loaded every source: the old frame goes to the controller, whose frame-age check judges it.
    CHECK(m.loop->stats().cycles_run == 4);
    for (const std::unique_ptr<CountingSource>& c : m.counted) {
        CHECK(c->loads == 4U);
    }
}

// verifies: SR-CAM-007
TEST_CASE("monitor loop: the cycle thread's CPU time is counted per cycle and against the budget") {
    Monitor m(demo_config());
    static_cast<void>(m.run(5));
    const MonitorStats& st = m.loop->stats();
    REQUIRE(st.cpu_us.size() >= 5U);
    for (std::size_t k = 0U; k < 5U; ++k) {
        CHECK(st.cpu_us[k] > 0U);  // a cycle fuses four images: it takes CPU time (the clock here is simulated)
    }
    CHECK(st.cpu_over_budget == 0);  // the test's budget is 60 s
    CHECK(st.arrival_count == 0U);   // no live camera: no arrival times
}
