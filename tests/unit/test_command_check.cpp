// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the controller's check of the PLC's command (check_command):
// each refusal in the order of command_check.hpp, and the names of the refusals.
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "cellguard/safety/command_check.hpp"
#include "enum_names.hpp"
#include "test_robot.hpp"

using namespace cellguard;

namespace {
struct Cell {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{4, 4, 4}).value();
    std::vector<std::uint32_t> mask = std::vector<std::uint32_t>(64);
    CompiledZones zones;
    MonitoringCases cases;
    Cell() {
        std::vector<ZoneConfig> zs(2);
        for (ZoneConfig& z : zs) {
            z.box_max = Eigen::Vector3d(0.2, 0.2, 0.2);
        }
        zones = CompiledZones::compile(g, {zs.data(), zs.size()}, {mask.data(), mask.size()}).value();
        cases = MonitoringCases::all_zones(zones);  // one case, number 0
    }
};

constexpr std::uint32_t kImageCrc = 0xABCD1234U;

CommandInput good_input(std::uint8_t joints) {
    CommandInput in;
    in.valid = true;
    in.received_us = 1000U;
    in.command.monitoring_case = 0U;
    in.command.speed_class = 0U;
    in.command.joint_count = joints;
    in.command.robot_id = static_cast<std::uint16_t>(kImageCrc & 0xFFFFU);
    return in;
}
}  // namespace

// verifies: SR-GEN-004
TEST_CASE("command check: every refusal has its own name and unknown values the fallback") {
    const CommandRefusal all[] = {
        CommandRefusal::kNone,          CommandRefusal::kJointCountMismatch, CommandRefusal::kInvalidRaw,
        CommandRefusal::kOutsideLimits, CommandRefusal::kRobotIdMismatch,    CommandRefusal::kMissing,
        CommandRefusal::kStale,         CommandRefusal::kUnknownCase,        CommandRefusal::kUnknownSpeedClass};
    for (std::size_t i = 0; i < sizeof(all) / sizeof(all[0]); ++i) {
        CAPTURE(i);
        REQUIRE(to_string(all[i]) != nullptr);
        CHECK(std::strcmp(to_string(all[i]), "unknown refusal") != 0);
        for (std::size_t j = 0; j < i; ++j) {
            CHECK(std::strcmp(to_string(all[i]), to_string(all[j])) != 0);
        }
    }
    CHECK(std::strcmp(to_string(static_cast<CommandRefusal>(5)), "unknown refusal") == 0);
    CHECK(std::strcmp(to_string(static_cast<CommandRefusal>(255)), "unknown refusal") == 0);
}

// verifies: SR-CASE-011
TEST_CASE("command check: missing, stale, future and unknown-case commands are refused in that order") {
    const Cell cell;
    CommandLimits limits;
    limits.cases = &cell.cases;
    limits.max_age_us = 500U;
    CommandInput in = good_input(0U);
    CHECK(check_command(in, 1000U, limits).ok());
    CHECK(check_command(in, 1500U, limits).ok());  // exactly max_age_us old
    CHECK(check_command(in, 1501U, limits).error() == CommandRefusal::kStale);
    CHECK(check_command(in, 999U, limits).error() == CommandRefusal::kStale);  // stamped after the cycle start
    in.command.monitoring_case = 1U;
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kUnknownCase);
    in.valid = false;
    CHECK(check_command(in, 5000U, limits).error() == CommandRefusal::kMissing);  // missing before stale
    in = good_input(0U);
    limits.cases = nullptr;  // no cases: every case refused
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kUnknownCase);
}

// verifies: SR-ROB-210
TEST_CASE("command check: without a robot the command carries no joints") {
    const Cell cell;
    CommandLimits limits;
    limits.cases = &cell.cases;
    limits.max_age_us = 500U;
    CommandInput in = good_input(0U);
    in.command.speed_class = 3U;  // speed classes are not checked without a robot
    const Result<CheckedCommand, CommandRefusal> ok = check_command(in, 1000U, limits);
    REQUIRE(ok.ok());
    CHECK(ok.value().monitoring_case == 0U);
    CHECK(ok.value().speed_class == 3U);
    CHECK(ok.value().joints.count == 0U);
    in.command.joint_count = 1U;
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kJointCountMismatch);
}

// verifies: SR-ROB-210
TEST_CASE("command check: with a robot the speed class and the joints are checked") {
    const Cell cell;
    const RobotModel arm = test::make_test_arm();
    CommandLimits limits;
    limits.cases = &cell.cases;
    limits.robot = &arm;
    limits.image_crc = kImageCrc;
    limits.speed_classes = 2U;
    limits.max_age_us = 500U;
    CommandInput in = good_input(static_cast<std::uint8_t>(arm.joint_count));
    in.command.speed_class = 1U;
    const Result<CheckedCommand, CommandRefusal> ok = check_command(in, 1000U, limits);
    REQUIRE(ok.ok());
    CHECK(ok.value().speed_class == 1U);
    CHECK(ok.value().joints.count == arm.joint_count);
    in.command.speed_class = 2U;  // not commissioned
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kUnknownSpeedClass);
    limits.speed_classes = 255U;
    in.command.speed_class = kSpeedClasses;  // beyond the protocol's classes
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kUnknownSpeedClass);
    in.command.speed_class = 0U;
    in.command.robot_id = static_cast<std::uint16_t>(in.command.robot_id + 1U);
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kRobotIdMismatch);
    in = good_input(static_cast<std::uint8_t>(arm.joint_count));
    in.command.joint_raw[0] = kJointRawInvalid;
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kInvalidRaw);
    in.command.joint_raw[0] = 0;
    in.command.joint_raw[2] = 20000;  // elbow at 4 rad, beyond its limit of pi
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kOutsideLimits);
    in.command.joint_raw[2] = 0;
    in.command.joint_count = 1U;
    CHECK(check_command(in, 1000U, limits).error() == CommandRefusal::kJointCountMismatch);
}

// verifies: SR-GEN-004
TEST_CASE("command check: every speed request has its own name and unknown values INVALID") {
    test::check_enum_names<SpeedRequest>(3U, "INVALID");
}

// verifies: SR-CMD-001
TEST_CASE("command check: two commands are equal only when every field and every joint value is") {
    RobotCommand a;
    a.joint_count = 2U;
    a.joint_raw[0] = 5;
    a.joint_raw[1] = -5;
    const RobotCommand b = a;
    CHECK(a == b);
    CHECK_FALSE(a != b);
    RobotCommand c = a;
    c.monitoring_case = 1U;
    CHECK(a != c);
    c = a;
    c.speed_class = 1U;
    CHECK(a != c);
    c = a;
    c.joint_count = 3U;
    CHECK(a != c);
    c = a;
    c.robot_id = 7U;
    CHECK(a != c);
    c = a;
    c.joint_raw[1] = -6;
    CHECK(a != c);
    c = a;
    c.joint_raw[kMaxCommandJoints - 1U] = 1;  // an unused entry counts as well
    CHECK(a != c);
}
