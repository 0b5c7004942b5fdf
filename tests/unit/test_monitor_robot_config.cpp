// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monitor configuration's robot side (apps/host cell/config.hpp,
// robot_config.cpp): [[cases]], [robot], [separation], [[speed_classes]], the
// command and separation CAN IDs and demo.scene load as written, and every value
// the cell cannot take is refused with its key and line, including a mask margin
// below the derived minimum and a margin a person could hide in.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "cellguard/host/cell/config.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

/// The robot-cell example with the first occurrence of @p from replaced by @p to (which must exist).
std::string edited(const std::string& from, const std::string& to) {
    std::string text = builtin_text("robot-cell.toml");
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    return text;
}

/// Loads @p text and checks that it fails with a message naming @p key and holding @p what.
void check_refused(const std::string& text, const std::string& key, const std::string& what = "") {
    const ConfigLoad l = parse_monitor_config(text, "cell.toml");
    CAPTURE(l.error);
    CHECK_FALSE(l.ok);
    CHECK(l.error.find("cell.toml:") == 0U);
    CHECK(l.error.find(key) != std::string::npos);
    CHECK(l.error.find(what) != std::string::npos);
}

}  // namespace

// verifies: SR-CFG-010
TEST_CASE("monitor config: the robot-cell example loads its cases, robot, separation and speed classes") {
    const ConfigLoad file = load_monitor_config(std::string(CELLGUARD_SOURCE_DIR) +
                                                "/apps/monitor/config/robot-cell.toml");
    REQUIRE_MESSAGE(file.ok, file.error);
    const MonitorConfig& c = file.config;
    REQUIRE(c.cases.size() == 3U);
    CHECK(c.cases[0].zone_mask == 0x5U);  // station-a, approach
    CHECK(c.cases[1].zone_mask == 0x6U);  // station-b, approach
    CHECK(c.cases[2].zone_mask == 0x7U);
    REQUIRE(c.robot.enabled);
    CHECK(c.robot.joints.size() == 6U);
    CHECK(c.robot.joints[2] == "elbow_joint");
    CHECK(c.robot.stroke_joints.empty());  // the demo arm has no gripper
    const ConfigLoad gripper = parse_monitor_config(
        edited("[robot]", "[robot]\nstroke_joints = [\"finger_joint1\", \"finger_joint3\"]"), "cell.toml");
    REQUIRE_MESSAGE(gripper.ok, gripper.error);
    CHECK(gripper.config.robot.stroke_joints == std::vector<std::string>{"finger_joint1", "finger_joint3"});
    CHECK(c.robot.urdf.find("/apps/monitor/config/robot-arm.urdf") != std::string::npos);
    CHECK(c.robot.margin_m == doctest::Approx(0.25));
    CHECK(c.robot.max_command_age_us == 200000U);
    const SeparationParams& sp = c.robot.separation;
    CHECK(sp.class_count == 2U);
    CHECK(sp.reduced_class == 1U);
    CHECK(sp.reaction_time_s == doctest::Approx(0.3));
    CHECK(sp.classes[0].robot_speed_mps == doctest::Approx(0.5));
    CHECK(sp.classes[1].stopping_distance_m == doctest::Approx(0.0125));
    CHECK(protective_separation_distance(sp, 0U) == doctest::Approx(1.92));
    CHECK(protective_separation_distance(sp, 1U) == doctest::Approx(1.6475));
    CHECK(reduced_speed_distance(sp) == doctest::Approx(2.34));
    CHECK(c.demo_scene.find("/../../evaluation/scenes/robot-cell.toml") != std::string::npos);
    // Built in, the same configuration names the built-in scene and robot.
    const MonitorConfig b = robot_cell_demo_config();
    CHECK(b.robot.urdf == "builtin:robot-arm.urdf");
    CHECK(b.demo_scene == "builtin:robot-cell-scene.toml");
    std::string text;
    CHECK(read_config_text(b.robot.urdf, text));
    CHECK(text.find("cellguard_arm6") != std::string::npos);
    CHECK_FALSE(read_config_text("builtin:nothing", text));
    // The derived minimum margin: 0.5 m/s x 0.3 s + 0.05 m + 6 x 0.1 mrad x 2 m.
    CHECK(minimum_mask_margin(c.robot, c.period_us) == doctest::Approx(0.2012));
}

// verifies: SR-CFG-011
TEST_CASE("monitor config: monitoring cases that name unknown zones, repeat or leave gaps are refused") {
    check_refused(edited(R"(zones = ["station-a", "approach"])", R"(zones = ["station-c"])"), "cases[0].zones",
                  "configured zones");
    check_refused(edited(R"(zones = ["station-a", "approach"])", R"(zones = ["station-a", "station-a"])"),
                  "cases[0].zones", "named twice");
    check_refused(edited(R"(zones = ["station-a", "approach"])", "zones = []"), "cases[0].zones");
    check_refused(edited("number = 1", "number = 0"), "cases[1].number", "given twice");
    check_refused(edited("number = 2", "number = 5"), "cases", "without gaps");
    check_refused(edited("number = 2", "number = 16"), "cases[2].number");
}

// verifies: SR-CFG-012
TEST_CASE("monitor config: a mask margin below the derived minimum or one a person could hide in is refused") {
    check_refused(edited("margin = 0.25", "margin = 0.15"), "robot.margin", "at least 0.2");
    // A mask as wide as S_p: a person at its edge would not stop the robot.
    // With C = 0 and margin 0.9 m, S_p(1) = 0.7975 m < margin + a voxel diagonal.
    std::string hiding = edited("intrusion_distance = 0.85", "intrusion_distance = 0.0\ndetection_capability_mm = 14");
    hiding.replace(hiding.find("margin = 0.25"), 13U, "margin = 0.90");
    check_refused(hiding, "robot.margin", "person at the mask's edge");
    check_refused(edited("reaction_time_ms = 300", "reaction_time_ms = 250"), "separation.reaction_time_ms",
                  "max_frame_age_ms + cycle.budget_ms");
    check_refused(edited("max_command_age_ms = 200", "max_command_age_ms = 50"), "robot.max_command_age_ms",
                  "one cycle period");
}

// verifies: SR-CFG-012
TEST_CASE(
    "monitor config: the intrusion distance C is at least what ISO 13855 gives for the stated detection "
    "capability, 850 mm when none is stated") {
    CHECK(minimum_intrusion_distance(0.0) == 0.85);
    CHECK(minimum_intrusion_distance(14.0) == 0.0);
    CHECK(minimum_intrusion_distance(30.0) == doctest::Approx(0.128));
    CHECK(minimum_intrusion_distance(40.0) == doctest::Approx(0.208));
    CHECK(minimum_intrusion_distance(40.5) == 0.85);
    CHECK(minimum_intrusion_distance(55.0) == 0.85);
    // Not stated: the arm allowance.
    check_refused(edited("intrusion_distance = 0.85", "intrusion_distance = 0.84"), "separation.intrusion_distance",
                  "no detection_capability_mm");
    // Stated: C from d; below it refused, at or above it taken.
    check_refused(edited("intrusion_distance = 0.85", "intrusion_distance = 0.12\ndetection_capability_mm = 30"),
                  "separation.intrusion_distance", "at least 0.128");
    check_refused(edited("intrusion_distance = 0.85", "intrusion_distance = 0.5\ndetection_capability_mm = 55"),
                  "separation.intrusion_distance", "at least 0.85");
    check_refused(edited("intrusion_distance = 0.85", "intrusion_distance = 0.85\ndetection_capability_mm = 10"),
                  "separation.detection_capability_mm", "14");
    check_refused(edited("intrusion_distance = 0.85", "intrusion_distance = 0.85\ndetection_capability_mm = 250"),
                  "separation.detection_capability_mm");
    const ConfigLoad ok = parse_monitor_config(
        edited("intrusion_distance = 0.85", "intrusion_distance = 0.13\ndetection_capability_mm = 30"), "cell.toml");
    REQUIRE_MESSAGE(ok.ok, ok.error);
    CHECK(ok.config.robot.detection_capability_mm == 30.0);
    CHECK(ok.config.robot.separation.intrusion_distance_m == 0.13);
    const ConfigLoad plain = parse_monitor_config(builtin_text("robot-cell.toml"), "cell.toml");
    REQUIRE(plain.ok);
    CHECK(plain.config.robot.detection_capability_mm == 0.0);
}

// verifies: SR-CFG-012
TEST_CASE("monitor config: bad robot, separation and speed class values are refused with their key") {
    check_refused(edited("human_speed = 1.6", "human_speed = 1.2"), "separation.human_speed", "ISO 13855");
    check_refused(edited("reduced_class = 1", "reduced_class = 2"), "separation.reduced_class");
    check_refused(edited("speed = 0.5", "speed = 0.0"), "speed_classes[0]");
    check_refused(edited(R"(joints = ["shoulder_pan_joint",)", R"(joints = ["elbow_joint",)"), "robot.joints",
                  "distinct");
    check_refused(edited("urdf = \"builtin:robot-arm.urdf\"", "urdf = \"\""), "robot.urdf");
    check_refused(edited("[robot]", "[robot]\nspeed = 1"), "robot");
    check_refused(edited("[robot]", "[robot]\nstroke_joints = \"finger\""), "robot.stroke_joints", "finger joints");
    check_refused(edited("[robot]", "[robot]\nstroke_joints = [\"f\", \"f\"]"), "robot.stroke_joints", "distinct");
    check_refused(edited("[robot]", "[robot]\nstroke_joints = [\"\"]"), "robot.stroke_joints", "non-empty");
    // [separation] without a robot.
    std::string text = builtin_text("robot-cell.toml");
    const std::size_t from = text.find("[robot]");
    const std::size_t to = text.find("# Speed and separation");
    REQUIRE(from != std::string::npos);
    REQUIRE(to != std::string::npos);
    text.erase(from, to - from);
    check_refused(text, "separation", "needs a [robot] table");
}

// verifies: SR-CFG-013
TEST_CASE("monitor config: the command and separation CAN IDs must not collide with the output's") {
    check_refused(edited("safety_id = 0x101", "safety_id = 0x101\ncommand_id = 0x102"), "can", "must differ");
    check_refused(edited("safety_id = 0x101", "safety_id = 0x101\nseparation_id = 0x103"), "can");
    const ConfigLoad ok = parse_monitor_config(edited("safety_id = 0x101", "safety_id = 0x101\ncommand_id = 0x200"),
                                               "cell.toml");
    REQUIRE_MESSAGE(ok.ok, ok.error);
    CHECK(ok.config.can.command.base_can_id == 0x200U);
}
