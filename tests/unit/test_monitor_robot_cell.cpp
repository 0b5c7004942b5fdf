// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the robot-cell demo as cellguard-monitor wires it (apps/monitor:
// command_link.hpp, robot_cell_demo.hpp, monitor_loop.hpp): the PLC's command
// through the PLC-side sender, the CAN port and the receiver; the arm alone
// never stops the robot; the person brings reduced speed, then the stop below
// S_p; the cases switch with the robot's program and are echoed; no cycle allocates.
#include <doctest/doctest.h>

#include <stdlib.h>  // mkdtemp

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/demo_log_check.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/robot_cell_demo.hpp"
#include "monitor_test_doubles.hpp"
#include "test_tags.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;
using cellguard::test::SteppingClock;

#if CELLGUARD_HOST_URDF
namespace {

/// Counts the frames sent, by CAN ID range.
class CountingSender final : public CanSender {
public:
    bool send(const CanFrame& frame) noexcept override {
        ++frames;
        if (frame.id >= 0x0C1U && frame.id <= 0x0C6U) {
            ++command_frames;
        }
        return true;
    }
    std::size_t frames = 0U;
    std::size_t command_frames = 0U;
};

/// One cycle's decisions.
struct CycleRecord {
    bool stop = false;
    SpeedRequest request = SpeedRequest::kFull;
    std::uint16_t distance_mm = 0U;
    std::uint16_t required_mm = 0U;
    std::uint8_t active_case = 0U;
    std::uint8_t commanded_case = 0U;
    bool command_valid = false;
    bool protective_intruded = false;
    bool reset = false;  ///< the reset level the command gave the restart interlock
    std::uint32_t faults = 0U;
};

/// The robot-cell demo as main wires it, with a counting sender, or with
/// @p log_path: into that candump log as `--log` does. @p step_us: the real
/// clock's advance per reading (a large one: a slow, loaded host).
struct RobotCell {
    explicit RobotCell(const std::string& log_path = "", std::uint64_t step_us = 10U)
        : cfg(robot_cell_demo_config()),
          clock(false, source_clock),
          plc(command_receiver_config(cfg), plc_receiver_config(cfg), &can) {
        source_clock.step = step_us;
        cfg.budget_us = 60000000U;  // the decisions, not this host's speed
        REQUIRE_FALSE(cell.configure(cfg).failed());
        REQUIRE_FALSE(cell.configure_robot(cfg, nullptr).failed());
        REQUIRE_FALSE(cell.build_prior(cfg, nullptr).failed());
        REQUIRE_FALSE(cell.build_tables(cfg, nullptr).failed());
        for (const sim::SensorSpec& spec : cell.specs) {
            owned.push_back(std::make_unique<SceneFrameSource>(spec, cell.simulation));
            sources.push_back(owned.back().get());
        }
        if (log_path.empty()) {
            can.use_sender(sender);
        } else {
            REQUIRE(can.open_log(log_path, cfg.can.log_interface_name, clock).ok());
        }
        demo = std::make_unique<RobotCellDemo>(cfg, cell, plc);
        out = std::fopen("/dev/null", "w");
        REQUIRE(out != nullptr);
        static_cast<void>(std::setvbuf(out, buffer, _IOFBF, sizeof buffer));
        loop = std::make_unique<MonitorLoop>(cfg, cell, sources, can, clock, out, &plc, demo.get());
        REQUIRE(loop->status().ok());
    }
    ~RobotCell() { static_cast<void>(std::fclose(out)); }
    RobotCell(const RobotCell&) = delete;
    RobotCell& operator=(const RobotCell&) = delete;

    /// Runs the configured cycles; records each and counts the cycles that allocated.
    void run() {
        for (int k = 0; k < cfg.demo_cycles; ++k) {
            const test::AllocationScope scope;
            const CycleReport& r = loop->run_cycle(k);
            allocating_cycles += scope.allocations() != 0U ? 1 : 0;
            CycleRecord c;
            c.stop = r.safety.stop_requested;
            c.request = r.robot.speed_request;
            c.distance_mm = r.robot.distance_mm;
            c.required_mm = r.robot.required_mm;
            c.active_case = r.robot.active_case;
            c.commanded_case = demo->command().monitoring_case;
            c.command_valid = r.robot.command_valid;
            c.reset = r.robot.command_reset;
            c.faults = r.safety.latched_faults;
            for (std::size_t z = 0U; z < 2U; ++z) {  // station-a, station-b
                c.protective_intruded = c.protective_intruded || r.zones.zones[z].state == ZoneState::kIntruded;
            }
            cycles.push_back(c);
        }
    }

    MonitorConfig cfg;
    MonitorCell cell;
    SteppingClock source_clock;
    CycleClock clock;
    CountingSender sender;
    CanPort can;
    SimulatedPlcLink plc;
    std::vector<std::unique_ptr<SceneFrameSource>> owned;
    std::vector<FrameSource*> sources;
    std::unique_ptr<RobotCellDemo> demo;
    std::FILE* out = nullptr;
    char buffer[8192] = {};
    std::unique_ptr<MonitorLoop> loop;
    std::vector<CycleRecord> cycles;
    int allocating_cycles = 0;
};

}  // namespace

// verifies: SR-SSM-010, SR-CMD-020, SR-CASE-010, SR-GEN-002
TEST_CASE("robot cell demo: the arm alone never stops, the person brings reduced speed then the stop below S_p" *
          CELLGUARD_LONG_REPLAY) {
    RobotCell c;
    c.run();
    REQUIRE(c.cycles.size() == 170U);
    CHECK(c.allocating_cycles == 0);
    CHECK(c.sender.command_frames == 6U * c.cycles.size());  // the PLC's six frames every cycle (and its link frame)
    // Protocol 0.2: the simulated PLC's receiver accepts the controller's pairs
    // with their link frames from its third pair on and never refuses one after.
    CHECK(c.plc.plc_status().communication_valid);
    CHECK(c.plc.plc_status().fault_events == 0U);
    CHECK(c.plc.receiver().link().sequence() == c.cycles.size());  // one controller link frame a cycle
    // Start-up: the receiver needs a reference sample and two good ones, then
    // the faults recover and the restart interlock runs; from cycle 20 on the
    // commands are good in every cycle.
    int first_reduced = -1;
    int first_stop = -1;
    for (std::size_t k = 20U; k < c.cycles.size(); ++k) {
        const CycleRecord& r = c.cycles[k];
        INFO("cycle " << k);
        CHECK(r.command_valid);
        CHECK((r.faults & fault_bit(Fault::kCommandInvalid)) == 0U);
        CHECK(r.active_case == r.commanded_case);  // applied in the cycle that received it, and echoed
        CHECK_FALSE(r.protective_intruded);        // the arm works inside the stations' zones: never foreground
        if (r.request == SpeedRequest::kReduced && first_reduced < 0) {
            first_reduced = static_cast<int>(k);
        }
        if (r.stop && first_stop < 0) {
            first_stop = static_cast<int>(k);
            CHECK(r.request == SpeedRequest::kProtectiveStop);
            CHECK(r.distance_mm < r.required_mm);  // the stop at the computed distance
        }
        if (first_reduced < 0) {
            CHECK_FALSE(r.stop);  // until the person comes near, the robot runs at full speed
            CHECK(r.request == SpeedRequest::kFull);
        }
    }
    // Before the first valid command the arm cannot be masked (its pose is unknown): the start-up
    // cycles before it alone find it in a station's zone, while the command fault holds the stop
    // (README). Protocol 0.2's start-up handshake (the PLC echoes the controller's first link frame)
    // makes the first valid command cycle 3.
    std::size_t first_valid = c.cycles.size();
    for (std::size_t k = 0U; k < c.cycles.size() && first_valid == c.cycles.size(); ++k) {
        if (c.cycles[k].command_valid) {
            first_valid = k;
        }
    }
    CHECK(first_valid == 3U);
    // The configuration keeps reset_required on: the start-up stop ends in the cycle whose sample carries
    // the simulated operator's press after a valid release (a rising edge of ResetRequest), not before.
    std::size_t first_run = c.cycles.size();
    for (std::size_t k = 0U; k < c.cycles.size() && first_run == c.cycles.size(); ++k) {
        if (!c.cycles[k].stop) {
            first_run = k;
        }
    }
    REQUIRE(first_run > first_valid);
    REQUIRE(first_run < 20U);
    CHECK(c.cycles[first_run].reset);
    CHECK(c.cycles[first_run].command_valid);
    CHECK_FALSE(c.cycles[first_run - 1U].reset);
    CHECK(c.cycles[first_run - 1U].command_valid);
    MESSAGE("start-up stop released by the PLC's reset in cycle " << first_run);
    for (std::size_t k = 0U; k < c.cycles.size(); ++k) {
        INFO("cycle " << k);
        if (c.cycles[k].protective_intruded) {
            CHECK(k < first_valid);
            CHECK_FALSE(c.cycles[k].command_valid);
            CHECK(c.cycles[k].stop);
            CHECK(c.cycles[k].faults != 0U);
        }
    }
    MESSAGE("first reduced cycle " << first_reduced << ", first stop cycle " << first_stop);
    CHECK(first_reduced > 20);
    CHECK(first_stop > first_reduced);
    // The case switched during the run (0 -> 2 -> 1 with the robot's program).
    bool saw[3] = {false, false, false};
    for (const CycleRecord& r : c.cycles) {
        if (r.active_case < 3U) {
            saw[r.active_case] = true;
        }
    }
    CHECK((saw[0] && saw[1] && saw[2]));
}

// verifies: SR-CMD-021
TEST_CASE("robot cell demo: a PLC that falls silent stops the robot within the command age" * CELLGUARD_LONG_REPLAY) {
    RobotCell c;
    for (int k = 0; k < 30; ++k) {
        static_cast<void>(c.loop->run_cycle(k));
    }
    REQUIRE_FALSE(c.loop->controller().report().safety.stop_requested);
    c.plc.go_silent();
    int stop_at = -1;
    for (int k = 30; k < 40 && stop_at < 0; ++k) {
        if (c.loop->run_cycle(k).safety.stop_requested) {
            stop_at = k;
        }
    }
    // max_command_age_ms = 200 at a 100 ms period: the third silent cycle at the latest.
    CHECK(stop_at >= 30);
    CHECK(stop_at <= 32);
}

// Issue 32: the status line said CLEAR (or INTRUDED) for zones while a fault held the stop; the CAN
// frame's Fault bit and the browser view say FAULT then, and so does the status line now.
// verifies: SR-SYS-001
TEST_CASE("robot cell demo: while a fault is latched the status line shows every zone as FAULT, as CAN does") {
    RobotCell c;
    const CycleReport& r = c.loop->run_cycle(0);  // no valid command yet: the command fault is latched
    REQUIRE(r.safety.latched_faults != 0U);
    CHECK(r.zones.zones[0].state != ZoneState::kFault);  // the zone's own evaluation is not FAULT
    const std::string line = c.loop->status_line();
    INFO(line);
    CHECK(line.find("station-a:FAULT station-b:FAULT approach:FAULT") != std::string::npos);
    CHECK(line.find(":CLEAR") == std::string::npos);
    CHECK(line.find(":INTRUDED") == std::string::npos);
}

/// The whole text of the file at @p path.
std::string file_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream all;
    all << in.rdbuf();
    return all.str();
}

// Issue 32: the unpaced monitor added the host's real time within a cycle to
// its simulated clock, so on a loaded host the command frames' inverted
// copies came late and the safety frames' gaps passed the safeguard cycle
// time in the CAN log. Unpaced time is simulated only: a host that takes
// 40 ms per clock reading (cycles of several periods) writes the same log.
// verifies: SR-SYS-001, SR-SYS-006, SR-CMD-008
TEST_CASE("robot cell demo: unpaced, a slow host writes the same CAN log as a fast one, and the log check passes" *
          CELLGUARD_LONG_REPLAY) {
    char dir[] = "/tmp/cellguard-robot-log-test-XXXXXX";
    REQUIRE(::mkdtemp(dir) != nullptr);
    const std::string fast = std::string(dir) + "/fast.log";
    const std::string slow = std::string(dir) + "/slow.log";
    int slow_reads_per_cycle = 0;
    const std::pair<std::string, std::uint64_t> runs[] = {{fast, 10U}, {slow, 40000U}};
    for (const auto& [path, step] : runs) {
        RobotCell c(path, step);
        const std::uint64_t before = c.source_clock.now;
        c.run();
        REQUIRE(c.can.close());
        slow_reads_per_cycle = static_cast<int>((c.source_clock.now - before) / step / 170U);
    }
    // 40 ms per reading, several readings per cycle: each cycle took longer than its 100 ms period.
    CHECK(slow_reads_per_cycle * 40 > 100);
    const std::string fast_text = file_text(fast);
    CHECK(fast_text.size() > 1000U);
    CHECK(fast_text == file_text(slow));
    const DemoLogCheck r = check_demo_log_file(slow, 170, robot_cell_demo_config());
    INFO(r.summary);
    for (const std::string& f : r.failures) {
        INFO(f);
    }
    CHECK(r.failures.empty());
    CHECK(r.passed());
    static_cast<void>(std::system(("rm -rf '" + std::string(dir) + "'").c_str()));
}
#endif

// verifies: SR-CMD-010
TEST_CASE(
    "case cell demo: the simulated PLC sends its case without joints, the operator presses only while the "
    "interlock holds") {
    const MonitorConfig cfg = robot_cell_demo_config();
    SimulatedPlcLink plc(command_receiver_config(cfg), plc_receiver_config(cfg), nullptr);
    CaseCellDemo demo(3U, plc);
    CycleReport holding;
    holding.safety.interlock_holding = true;
    CycleReport running;
    running.safety.interlock_holding = false;
    demo.before_cycle(0, 0.0);
    CHECK(demo.command().monitoring_case == 3U);
    CHECK(demo.command().joint_count == 0U);
    CHECK_FALSE(demo.command().reset_request);  // nothing seen yet: released
    // While the interlock holds: pressed for one sample, released for the next, so each press is a rising edge.
    std::vector<bool> levels;
    for (int k = 1; k <= 4; ++k) {
        demo.after_cycle(holding);
        demo.before_cycle(k, 0.0);
        levels.push_back(demo.command().reset_request);
        CHECK(demo.command().monitoring_case == 3U);
    }
    CHECK(levels == std::vector<bool>{true, false, true, false});
    char text[96];
    demo.after_cycle(holding);
    demo.before_cycle(5, 0.0);
    demo.describe("person (0.45, 0.60)", text, sizeof text);
    CHECK(std::string(text) == "person (0.45, 0.60) reset");  // the status line shows the press
    // Released (the run goes on, or the stop holds for another reason): never pressed.
    for (int k = 6; k <= 8; ++k) {
        demo.after_cycle(running);
        demo.before_cycle(k, 0.0);
        CHECK_FALSE(demo.command().reset_request);
    }
    demo.describe("live cameras", text, sizeof text);
    CHECK(std::string(text) == "live cameras");
}
