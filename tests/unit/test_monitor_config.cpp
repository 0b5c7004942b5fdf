// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monitor's TOML configuration: the example file and the built-in demo load, every kind of bad key or value is refused with a message naming the key and its line.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/scenario.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

/// The demo text with the first occurrence of @p from replaced by @p to (which must exist).
std::string edited(const std::string& from, const std::string& to) {
    std::string text = demo_config_text();
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    return text;
}

/// Line (1-based) of the first occurrence of @p needle in @p text.
int line_of(const std::string& text, const std::string& needle) {
    const std::size_t at = text.find(needle);
    REQUIRE(at != std::string::npos);
    int line = 1;
    for (std::size_t i = 0U; i < at; ++i)
        line += text[i] == '\n' ? 1 : 0;
    return line;
}

/// Loads @p text and checks that it fails with a message holding "cell.toml:<line>:" and @p key.
void check_refused(const std::string& text, int line, const std::string& key) {
    const ConfigLoad l = parse_monitor_config(text, "cell.toml");
    CAPTURE(l.error);
    CHECK_FALSE(l.ok);
    CHECK(l.error.find("cell.toml:" + std::to_string(line) + ":") == 0U);
    CHECK(l.error.find(key) != std::string::npos);
}

}  // namespace

// verifies: SR-CFG-001
TEST_CASE("monitor config: the example paper-cell.toml and the built-in demo load with the paper's cell") {
    const ConfigLoad file = load_monitor_config(std::string(CELLGUARD_SOURCE_DIR) +
                                                "/apps/monitor/config/paper-cell.toml");
    REQUIRE_MESSAGE(file.ok, file.error);
    const MonitorConfig& c = file.config;
    CHECK(c.grid.dims[0] == 34);
    CHECK(c.grid.dims[2] == 30);
    CHECK(c.grid.voxel_size == doctest::Approx(0.05));
    REQUIRE(c.sensors.size() == 4U);
    CHECK(c.sensors[2].name == "stereo-a");
    CHECK(c.sensors[2].width == 320);
    CHECK(c.sensors[0].has_target);
    REQUIRE(c.zones.size() == 2U);
    CHECK(c.zones[0].zone.kind == ZoneKind::kProtective);
    CHECK(c.zones[1].zone.kind == ZoneKind::kWarning);
    CHECK(c.zones[1].zone.shape == ZoneShape::kPrism);
    CHECK(c.zones[1].zone.polygon_size == 4U);
    CHECK(c.zones[0].zone.max_unseen_voxels == 20U);
    CHECK(c.table_check_bytes == 1048576U);
    CHECK(c.max_repeated_frames == 3U);
    CHECK(c.zone_check_bytes == 16384U);
    CHECK(c.background_match == 0.5F);
    CHECK(c.background_changed_pixels == 20U);
    CHECK(c.background_changed_cycles == 3U);
    CHECK(c.background_tolerance_m == doctest::Approx(0.05));
    CHECK(c.prior.source == PriorSource::kSimulatedBackground);
    CHECK(c.can.channel.safety_can_id == 0x101U);
    CHECK(c.can.channel.data_id_mode == E2eP01DataIdMode::kBoth);
    CHECK(c.can.log_file == "monitor-demo.log");
    CHECK(c.period_us == 100000U);
    CHECK(c.restart_delay_us == 500000U);
    CHECK(c.demo_cycles == 60);
    const MonitorConfig demo = demo_config();
    CHECK(demo.sensors.size() == 4U);
    CHECK(demo.zones[0].zone.box_max.x() == doctest::Approx(0.4));
}

// verifies: SR-CFG-001
TEST_CASE(
    "monitor config: a sensor may give a rotation instead of a target, a prior file resolves against the config's directory") {
    std::string text = edited("target = [0.0, 0.0, 0.0]\nresolution = [176, 144]",
                              "rotation = { w = 1.0, x = 0.0, y = 0.0, z = 0.0 }\nresolution = [176, 144]");
    text = edited("source = \"simulated-background\"", "source = \"file\"\nfile = \"cell.cgprior\"");
    const ConfigLoad l = parse_monitor_config(text, "cell.toml", "/etc/cellguard");
    REQUIRE_MESSAGE(l.ok, l.error);
    CHECK(l.config.prior.source == PriorSource::kFile);
    CHECK(l.config.prior.file == "/etc/cellguard/cell.cgprior");
    const std::string rot = edited("target = [0.0, 0.0, 0.0]\nresolution = [176, 144]",
                                   "rotation = { w = 1.0, x = 0.0, y = 0.0, z = 0.0 }\nresolution = [176, 144]");
    const ConfigLoad r = parse_monitor_config(rot, "cell.toml");
    REQUIRE_MESSAGE(r.ok, r.error);
    CHECK_FALSE(r.config.sensors[0].has_target);
}

// verifies: SR-CFG-001
TEST_CASE("monitor config: a TOML syntax error names the line") {
    const std::string text = edited("voxel_size = 0.05", "voxel_size = = 0.05");
    const ConfigLoad l = parse_monitor_config(text, "cell.toml");
    CHECK_FALSE(l.ok);
    CHECK(l.error.find("cell.toml:" + std::to_string(line_of(text, "voxel_size = =")) + ":") == 0U);
    CHECK(l.error.find("TOML syntax") != std::string::npos);
}

// verifies: SR-CFG-001
TEST_CASE("monitor config: a value of the wrong type or out of range names the key and its line") {
    std::string t = edited("voxel_size = 0.05", "voxel_size = \"fine\"");
    check_refused(t, line_of(t, "voxel_size"), "grid.voxel_size: expected a number");
    t = edited("voxel_size = 0.05", "voxel_size = -0.05");
    check_refused(t, line_of(t, "voxel_size"), "grid.voxel_size: must be greater than 0");
    t = edited("dims = [34, 30, 30]", "dims = [34, 0, 30]");
    check_refused(t, line_of(t, "dims"), "grid.dims");
    t = edited("dims = [34, 30, 30]", "dims = [34, 30]");
    check_refused(t, line_of(t, "dims"), "grid.dims: expected an array of 3 integers");
    t = edited("resolution = [320, 240]", "resolution = [320.5, 240]");
    check_refused(t, line_of(t, "resolution = [320.5"), "sensors[2].resolution");
    t = edited("fov = [60.0, 45.0]", "fov = [190.0, 45.0]");
    check_refused(t, line_of(t, "fov = [190"), "sensors[2].fov");
    t = edited("max_range = 10.0", "max_range = 0");
    check_refused(t, line_of(t, "max_range = 0"), "sensors[0].max_range");
    t = edited("kind = \"warning\"", "kind = \"caution\"");
    check_refused(t, line_of(t, "caution"), "zones[1].kind: expected \"protective\" or \"warning\", got \"caution\"");
    t = edited("shape = \"box\"\nmin", "shape = \"sphere\"\nmin");
    check_refused(t, line_of(t, "sphere"), "zones[0].shape");
    t = edited("max = [0.4, 0.6, 1.2]", "max = [0.4, 0.1, 1.2]");
    check_refused(t, line_of(t, "max = [0.4, 0.1"), "zones[0].max: every coordinate must be greater than in min");
    t = edited("polygon = [[-0.8, 0.45], [0.8, 0.45], [0.8, 0.75], [-0.8, 0.75]]",
               "polygon = [[-0.8, 0.45], [0.8, 0.45]]");
    check_refused(t, line_of(t, "polygon = [[-0.8"), "zones[1].polygon");
    t = edited("max_unseen_voxels = 20", "max_unseen_voxels = -1");
    check_refused(t, line_of(t, "max_unseen_voxels = -1"), "zones[0].max_unseen_voxels: expected an integer in 0..");
    t = edited("background_frames = 8", "background_frames = 2");
    check_refused(t, line_of(t, "background_frames"),
                  "prior.background_frames: at least 3 frames for the probabilistic prior");
    t = edited("data_id_mode = \"both\"", "data_id_mode = \"all\"");
    check_refused(t, line_of(t, "data_id_mode"), "can.data_id_mode");
    t = edited("safety_id = 0x101", "safety_id = 0x900");
    check_refused(t, line_of(t, "safety_id"), "can.safety_id: expected an integer in 0..2046");
    t = edited("period_ms = 100", "period_ms = 0");
    check_refused(t, line_of(t, "period_ms"), "cycle.period_ms");
    t = edited("budget_ms = 100", "budget_ms = 200");
    check_refused(t, line_of(t, "budget_ms"), "cycle.budget_ms: expected more than 0 and at most period_ms");
    t = edited("table_check_kib = 1024", "table_check_kib = 0");
    check_refused(t, line_of(t, "table_check_kib"), "cycle.table_check_kib: expected an integer in 1..65536");
    t = edited("zone_check_kib = 16", "zone_check_kib = 65537");
    check_refused(t, line_of(t, "zone_check_kib"), "cycle.zone_check_kib: expected an integer in 1..65536");
    t = edited("background_match = 0.5 ", "background_match = 1.5 ");
    check_refused(t, line_of(t, "background_match"), "cycle.background_match: expected 0 (off) to 1");
    t = edited("background_tolerance_m = 0.05", "background_tolerance_m = 0");
    check_refused(t, line_of(t, "background_tolerance_m"), "cycle.background_tolerance_m: expected more than 0");
    const ConfigLoad with_bg = parse_monitor_config(edited("background_match = 0.5 ", "background_match = 0.25 "),
                                                    "cell.toml");
    REQUIRE_MESSAGE(with_bg.ok, with_bg.error);
    CHECK(with_bg.config.background_match == doctest::Approx(0.25));
    t = edited("max_repeated_frames = 3", "max_repeated_frames = 1001");
    check_refused(t, line_of(t, "max_repeated_frames"), "cycle.max_repeated_frames: expected an integer in 0..1000");
    const ConfigLoad frozen_check = parse_monitor_config(edited("max_repeated_frames = 3", "max_repeated_frames = 5"),
                                                         "cell.toml");
    REQUIRE_MESSAGE(frozen_check.ok, frozen_check.error);
    CHECK(frozen_check.config.max_repeated_frames == 5U);
    t = edited("reset_required = false", "reset_required = \"no\"");
    check_refused(t, line_of(t, "reset_required"), "restart_interlock.reset_required: expected true or false");
    t = edited("source = \"simulated-background\"", "source = \"guess\"");
    check_refused(t, line_of(t, "guess"), "prior.source");
}

// verifies: SR-CFG-001
TEST_CASE("monitor config: an unknown key, a missing key or a missing table names it and the line of its table") {
    std::string t = edited("voxel_size = 0.05", "voxel_sise = 0.05");
    check_refused(t, line_of(t, "voxel_sise"), "grid.voxel_sise: unknown key");
    t = edited("[demo]", "[dmeo]");
    check_refused(t, line_of(t, "[dmeo]"), "dmeo: unknown key");
    t = edited("name = \"stereo-b\"\n", "");
    check_refused(t, line_of(t, "[[sensors]]\nposition = [-1.9, 1.9"), "sensors[3].name: missing key");
    t = edited("z_max = 1.2\n", "");
    check_refused(t, line_of(t, "[[zones]]\nname = \"warning\""), "zones[1].z_max: missing key");
    t = edited("[cycle]\nperiod_ms = 100", "[cycle]\nperiod = 100");
    check_refused(t, line_of(t, "period = 100"), "cycle.period: unknown key");
    t = edited("target = [0.0, 0.0, 0.0]\nresolution = [176, 144]", "resolution = [176, 144]");
    check_refused(t, line_of(t, "[[sensors]]"), "sensors[0].target: give exactly one of target and rotation");
}

// verifies: SR-CFG-001
TEST_CASE("monitor config: more than 16 zones is refused, since one safety frame carries 16") {
    std::string text = demo_config_text();
    const std::string zone =
        "\n[[zones]]\nname = \"z\"\nkind = \"warning\"\nshape = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.1]\n";
    std::string extra;
    for (int i = 0; i < 15; ++i)
        extra += zone;
    const std::size_t at = text.find("[thresholds]");
    std::string sixteen = text;
    sixteen.insert(at, extra.substr(0U, extra.size() - zone.size()) + "\n");
    CHECK(parse_monitor_config(sixteen, "cell.toml").ok);  // 2 + 14 = 16 zones
    text.insert(at, extra + "\n");                         // 2 + 15 = 17 zones
    const ConfigLoad l = parse_monitor_config(text, "cell.toml");
    CHECK_FALSE(l.ok);
    CHECK(l.error.find("zones: at most 16 zones") != std::string::npos);
}

// verifies: SR-CFG-001
TEST_CASE("monitor config: a missing file is a clear error") {
    const ConfigLoad l = load_monitor_config("/nonexistent/cell.toml");
    CHECK_FALSE(l.ok);
    CHECK(l.error == "/nonexistent/cell.toml: cannot open the configuration file: No such file or directory");
}

// Issue 32: `--config /tmp` said "grid: missing table" (a directory reads as an empty text).
// verifies: SR-CFG-001
TEST_CASE("monitor config: a directory is refused as such, not parsed as an empty file") {
    const ConfigLoad l = load_monitor_config("/tmp");
    CHECK_FALSE(l.ok);
    CHECK(l.error.find("/tmp: not a configuration file (a directory)") == 0U);
    CHECK(l.error.find("missing table") == std::string::npos);
}

// verifies: SR-CFG-001
TEST_CASE("monitor config: a loaded configuration names its file, a built-in one says so") {
    CHECK(demo_config().source.rfind("<built-in", 0) == 0U);
    const ConfigLoad l = parse_monitor_config(demo_config_text(), "cell.toml");
    REQUIRE(l.ok);
    CHECK(l.config.source == "cell.toml");
}

// verifies: SR-SYS-001
TEST_CASE("monitor scenario: the scripted person enters the protective zone in one step, never before") {
    const MonitorConfig c = demo_config();
    const ZoneConfig& protective = c.zones[0].zone;
    int entry = -1;
    for (int k = 0; k < 60 && entry < 0; ++k) {
        if (person_overlaps(protective, demo_person(k)))
            entry = k;
    }
    CHECK(entry == 15);
    CHECK_FALSE(person_overlaps(c.zones[1].zone, demo_person(0)));  // starts outside the warning zone too
    CHECK(person_overlaps(c.zones[1].zone, demo_person(14)));
    CHECK(demo_person(100).x == doctest::Approx(-1.4));  // stays outside after the path
    CHECK(std::string(demo_phase(15)) == "protective zone");
}

namespace {

/// The demo text (which ends with its [opt_out] table) with the entry @p line added.
std::string with_opt_out(const std::string& text, const std::string& line) { return text + line + "\n"; }

/// The demo text without the first line that starts with @p key (the line must exist).
std::string without_line(std::string text, const std::string& key) {
    const std::size_t at = text.find("\n" + key);
    REQUIRE(at != std::string::npos);
    text.erase(at + 1U, text.find('\n', at + 1U) - at);
    return text;
}

}  // namespace

// verifies: SR-CFG-018
TEST_CASE(
    "monitor config: every protection is on by default, and the shipped configurations state why they turn any off") {
    std::size_t count = 0U;
    const Protection* list = protections(count);
    REQUIRE(count == 8U);
    for (std::size_t i = 0U; i < count; ++i) {
        CAPTURE(list[i].name);
        CHECK(std::string(list[i].setting).size() > 10U);
        CHECK(std::string(list[i].loses).size() > 40U);
        for (std::size_t j = 0U; j < i; ++j) {
            CHECK(std::string(list[i].name) != list[j].name);
        }
    }
    // Without the lines that turn protections off and their opt-outs: every check on.
    std::string plain = without_line(demo_config_text(), "reset_required = false");
    plain = without_line(without_line(plain, "reset_required = \""), "watchdog_device = \"");
    plain = without_line(without_line(plain, "max_repeated_frames = "), "background_match = ");
    plain = without_line(plain, "background_changed_cycles = ");
    const ConfigLoad l = parse_monitor_config(plain, "cell.toml");
    REQUIRE_MESSAGE(l.ok, l.error);
    CHECK(l.config.reset_required);
    CHECK(l.config.max_repeated_frames == 3U);
    CHECK(l.config.background_match == 0.5F);
    CHECK(l.config.background_changed_cycles == 3U);
    CHECK(l.config.opt_outs.empty());
    CHECK_FALSE(opted_out(l.config, "watchdog_device"));
    // The shipped configurations: each opt-out with its reason, nothing else off.
    struct Shipped {
        const char* file;
        std::vector<std::string> off;
    };
    const std::vector<Shipped> shipped = {
        {"paper-cell.toml", {"reset_required", "watchdog_device"}},
        {"robot-cell.toml", {"watchdog_device"}},  // its PLC sends ResetRequest: the interlock stays on
        {"paper-cell-cameras.toml",
         {"reset_required", "frozen_sensor_check", "camera_stamp_tolerance", "watchdog_device"}},
        {"real-cell.toml", {}},  // its one monitoring case gives it the PLC's command and ResetRequest
    };
    for (const Shipped& s : shipped) {
        CAPTURE(s.file);
        const ConfigLoad f = load_monitor_config(std::string(CELLGUARD_SOURCE_DIR) + "/apps/monitor/config/" + s.file);
        REQUIRE_MESSAGE(f.ok, f.error);
        REQUIRE(f.config.opt_outs.size() == s.off.size());
        for (std::size_t i = 0U; i < s.off.size(); ++i) {
            CHECK(f.config.opt_outs[i].name == s.off[i]);
            CHECK(f.config.opt_outs[i].reason.size() > 30U);
            CHECK_FALSE(f.config.opt_outs[i].loses.empty());
        }
        CHECK(f.config.max_repeated_frames == (opted_out(f.config, "frozen_sensor_check") ? 0U : 3U));
    }
    const MonitorConfig robot = robot_cell_demo_config();
    CHECK(robot.can.clock_rate.nominal_period_us == 100000U);  // on: the PLC's period given
    CHECK(robot.reset_required);                               // on: the PLC's command carries the reset
    CHECK(demo_config().opt_outs.size() == 2U);
    const ConfigLoad real = load_monitor_config(std::string(CELLGUARD_SOURCE_DIR) +
                                                "/apps/monitor/config/real-cell.toml");
    REQUIRE(real.ok);
    CHECK(real.config.reset_required);      // on: the case's command carries the reset
    CHECK(real.config.cases.size() == 1U);  // one case, both zones
    CHECK(real.config.cases.front().zone_mask == 0b11U);
    CHECK(real.config.can.clock_rate.nominal_period_us == 20000U);  // on: the PLC's period given
}

// verifies: SR-CFG-018
TEST_CASE("monitor config: a protection turned off without its [opt_out] entry is refused, naming the entry to add") {
    // Each setting that turns one off, without the entry: refused at that setting's line.
    std::string t = without_line(demo_config_text(), "reset_required = \"");
    check_refused(t, line_of(t, "reset_required = false"), "opt_out.reset_required: missing: ");
    CHECK(parse_monitor_config(t, "cell.toml").error.find("reset_required = \"<reason>\"") != std::string::npos);
    t = edited("max_repeated_frames = 3", "max_repeated_frames = 0");
    check_refused(t, line_of(t, "max_repeated_frames = 0"), "opt_out.frozen_sensor_check: missing");
    const ConfigLoad frozen = parse_monitor_config(with_opt_out(t, "frozen_sensor_check = \"ideal frames\""), "c");
    REQUIRE_MESSAGE(frozen.ok, frozen.error);
    CHECK(opted_out(frozen.config, "frozen_sensor_check"));
    REQUIRE(frozen.config.opt_outs.size() == 3U);  // in the order of protections(): reset, frozen, watchdog
    CHECK(frozen.config.opt_outs[1].name == "frozen_sensor_check");
    CHECK(frozen.config.opt_outs[1].reason == "ideal frames");
    t = edited("background_match = 0.5 ", "background_match = 0   ");
    check_refused(t, line_of(t, "background_match = 0 "), "opt_out.background_view_check: missing");
    CHECK(parse_monitor_config(with_opt_out(t, "background_view_check = \"x\""), "c").ok);
    t = edited("background_changed_cycles = 3", "background_changed_cycles = 0");
    check_refused(t, line_of(t, "background_changed_cycles = 0"), "opt_out.background_change_check: missing");
    CHECK(parse_monitor_config(with_opt_out(t, "background_change_check = \"x\""), "c").ok);
    // The clock-rate check in a cell with a PLC command: command_period_ms absent.
    std::string robot = builtin_text("robot-cell.toml");
    robot = without_line(robot, "command_period_ms = ");
    const ConfigLoad no_rate = parse_monitor_config(robot, "robot.toml");
    CHECK_FALSE(no_rate.ok);
    CHECK(no_rate.error.find("opt_out.clock_rate_check: missing") != std::string::npos);
    CHECK(no_rate.error.find("robot.toml:" + std::to_string(line_of(robot, "[can]")) + ":") == 0U);
}

// verifies: SR-CFG-018
TEST_CASE(
    "monitor config: an [opt_out] entry naming no protection, one that is on, or one without a reason is refused") {
    std::string t = with_opt_out(demo_config_text(), "frozen_sensors = \"typo\"");
    check_refused(t, line_of(t, "frozen_sensors"),
                  "opt_out.frozen_sensors: names no protection (known: reset_required,");
    t = with_opt_out(demo_config_text(), "frozen_sensor_check = \"the check is on\"");
    check_refused(t, line_of(t, "frozen_sensor_check"), "opt_out.frozen_sensor_check: the protection is not off");
    t = with_opt_out(demo_config_text(), "clock_rate_check = \"no PLC command in this cell\"");
    check_refused(t, line_of(t, "clock_rate_check"), "opt_out.clock_rate_check: the protection is not off");
    t = with_opt_out(demo_config_text(), "camera_stamp_tolerance = \"no camera\"");
    check_refused(t, line_of(t, "camera_stamp_tolerance"), "the protection is not off");
    t = without_line(demo_config_text(), "reset_required = false");
    check_refused(t, line_of(t, "reset_required = \""), "opt_out.reset_required: the protection is not off");
    for (const char* reason : {"\"\"", "\"   \"", "true", "3", "[\"a\"]"}) {
        CAPTURE(reason);
        t = edited("max_repeated_frames = 3", "max_repeated_frames = 0");
        t = with_opt_out(t, std::string("frozen_sensor_check = ") + reason);
        check_refused(t, line_of(t, "frozen_sensor_check"),
                      "opt_out.frozen_sensor_check: expected the reason for turning the protection off");
    }
    t = demo_config_text();
    t = "opt_out = 3\n" + t.substr(0U, t.find("\n[opt_out]") + 1U);
    check_refused(t, 1, "opt_out: expected a table");
}

// verifies: SR-CFG-019
TEST_CASE("monitor config: the depth filter is off unless [depth_filter] turns a filter on, with a stated reason") {
    const ConfigLoad plain = parse_monitor_config(demo_config_text(), "cell.toml");
    REQUIRE(plain.ok);
    CHECK_FALSE(plain.config.depth_filter.filter.on());
    const std::string on = std::string(demo_config_text()) +
                           "\n[depth_filter]\nedge_jump_percent = 4\nedge_jump_min_m = 0.05\nedge_radius = 2\n"
                           "background_tolerance_percent = 5\nspeckle_min_neighbours = 3\n"
                           "reason = \"1 % noise: d = 100 mm measured with it\"\n";
    const ConfigLoad l = parse_monitor_config(on, "cell.toml");
    REQUIRE(l.ok);
    const cell::DepthConditioning& f = l.config.depth_filter.filter;
    CHECK(f.edge_jump_per_m == doctest::Approx(0.04));
    CHECK(f.edge_jump_min_m == doctest::Approx(0.05));
    CHECK(f.edge_radius == 2);
    CHECK(f.background_tolerance_per_m == doctest::Approx(0.05));
    CHECK(f.speckle_min_neighbours == 3);
    CHECK(l.config.depth_filter.reason == "1 % noise: d = 100 mm measured with it");
    // A filter on without a reason, or with a blank one.
    std::string t = std::string(demo_config_text()) + "\n[depth_filter]\nbackground_tolerance_percent = 5\n";
    check_refused(t, line_of(t, "[depth_filter]"), "depth_filter.reason: a filter is on: state why");
    t += "reason = \"  \"\n";
    check_refused(t, line_of(t, "[depth_filter]"), "depth_filter.reason");
    // A reason with every filter off, a radius without the edge filter, values out of range, an unknown key.
    t = std::string(demo_config_text()) + "\n[depth_filter]\nreason = \"noise\"\n";
    check_refused(t, line_of(t, "reason = \"noise\""), "depth_filter.reason: every filter is off");
    t = std::string(demo_config_text()) +
        "\n[depth_filter]\nedge_radius = 2\nbackground_tolerance_percent = 5\nreason = \"x\"\n";
    check_refused(t, line_of(t, "edge_radius"), "depth_filter.edge_radius: applies only with the edge filter on");
    t = std::string(demo_config_text()) + "\n[depth_filter]\nedge_jump_percent = 60\nreason = \"x\"\n";
    check_refused(t, line_of(t, "edge_jump_percent"), "depth_filter.edge_jump_percent: expected 0 to 50");
    t = std::string(demo_config_text()) + "\n[depth_filter]\nbackground_tolerance_percent = -1\nreason = \"x\"\n";
    check_refused(t, line_of(t, "background_tolerance_percent"), "depth_filter.background_tolerance_percent");
    t = std::string(demo_config_text()) + "\n[depth_filter]\nedge_jump_min_m = 0.05\nedge_radius = 5\nreason = \"x\"\n";
    check_refused(t, line_of(t, "edge_radius"), "depth_filter.edge_radius");
    t = std::string(demo_config_text()) + "\n[depth_filter]\nspeckle_min_neighbours = 9\nreason = \"x\"\n";
    check_refused(t, line_of(t, "speckle_min_neighbours"), "depth_filter.speckle_min_neighbours");
    t = std::string(demo_config_text()) + "\n[depth_filter]\nedge_jump = 4\n";
    check_refused(t, line_of(t, "edge_jump = 4"), "depth_filter.edge_jump: unknown key");
}
