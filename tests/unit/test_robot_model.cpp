// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the robot model's check refuses every impossible robot (counts, numbers, chain, joints, capsules,
// reach) with the reason and the item.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>

#include "cellguard/robot/robot_model.hpp"
#include "test_robot.hpp"

using namespace cellguard;
using cellguard::test::make_test_arm;

namespace {

// Applies @p change to the test arm and returns the check's verdict.
RobotModelError check_changed(const std::function<void(RobotModel&)>& change) {
    RobotModel m = make_test_arm();
    change(m);
    const RobotModelError e = check_robot_model(m);
    REQUIRE(e.reason != nullptr);
    return e;
}

void expect_refused(const std::function<void(RobotModel&)>& change, ErrorCode code, std::size_t index) {
    const RobotModelError e = check_changed(change);
    INFO(std::string(e.reason));
    CHECK(e.code == code);
    CHECK(e.index == index);
    CHECK(std::string(e.reason).size() > 10U);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

// verifies: SR-ROB-001
TEST_CASE("the 6-axis test arm and a one-link robot pass the model check") {
    CHECK(is_no_error(check_robot_model(make_test_arm())));
    CHECK(is_no_error(check_robot_model(make_test_arm(1.0, -2.0, 0.5))));
    RobotModel one;
    one.link_count = 1U;
    one.capsule_count = 1U;
    one.capsules[0].radius = 0.1;
    CHECK(is_no_error(check_robot_model(one)));
    // Unused entries are not read.
    one.links[5].origin_xyz[0] = kNaN;
    one.capsules[9].radius = -1.0;
    CHECK(is_no_error(check_robot_model(one)));
}

// verifies: SR-ROB-001
TEST_CASE("the model check refuses counts outside capacity and a name without its terminating zero") {
    expect_refused([](RobotModel& m) { m.link_count = 0U; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.capsule_count = 0U; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.link_count = 17U; }, ErrorCode::kCapacityExceeded, 0U);
    expect_refused([](RobotModel& m) { m.capsule_count = 33U; }, ErrorCode::kCapacityExceeded, 0U);
    expect_refused([](RobotModel& m) { m.joint_count = 8U; }, ErrorCode::kCapacityExceeded, 0U);
    expect_refused(
        [](RobotModel& m) {
            for (char& c : m.name) {
                c = 'x';
            }
        },
        ErrorCode::kInvalidArgument, 0U);
}

// verifies: SR-ROB-001
TEST_CASE("the model check refuses every number that is not finite") {
    expect_refused([](RobotModel& m) { m.base_xyz[1] = kNaN; }, ErrorCode::kNonFiniteValue, 0U);
    expect_refused([](RobotModel& m) { m.base_wxyz[0] = kInf; }, ErrorCode::kNonFiniteValue, 0U);
    expect_refused([](RobotModel& m) { m.links[3].origin_xyz[2] = kNaN; }, ErrorCode::kNonFiniteValue, 3U);
    expect_refused([](RobotModel& m) { m.links[2].origin_wxyz[3] = kNaN; }, ErrorCode::kNonFiniteValue, 2U);
    expect_refused([](RobotModel& m) { m.links[4].axis[0] = kNaN; }, ErrorCode::kNonFiniteValue, 4U);
    expect_refused([](RobotModel& m) { m.links[5].lower = -kInf; }, ErrorCode::kNonFiniteValue, 5U);
    expect_refused([](RobotModel& m) { m.links[6].upper = kNaN; }, ErrorCode::kNonFiniteValue, 6U);
    expect_refused([](RobotModel& m) { m.links[1].max_velocity = kInf; }, ErrorCode::kNonFiniteValue, 1U);
    expect_refused([](RobotModel& m) { m.links[0].origin_xyz[0] = kNaN; }, ErrorCode::kNonFiniteValue, 0U);
    expect_refused([](RobotModel& m) { m.capsules[3].a[1] = kNaN; }, ErrorCode::kNonFiniteValue, 3U);
    expect_refused([](RobotModel& m) { m.capsules[4].b[2] = -kInf; }, ErrorCode::kNonFiniteValue, 4U);
    expect_refused([](RobotModel& m) { m.capsules[6].radius = kNaN; }, ErrorCode::kNonFiniteValue, 6U);
}

// verifies: SR-ROB-002
TEST_CASE("the model check refuses a broken chain and a root that moves or has an origin") {
    expect_refused([](RobotModel& m) { m.links[3].parent = 3U; }, ErrorCode::kInvalidArgument, 3U);
    expect_refused([](RobotModel& m) { m.links[3].parent = 5U; }, ErrorCode::kInvalidArgument, 3U);
    expect_refused([](RobotModel& m) { m.links[0].parent = 1U; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[0].joint = JointType::kRevolute; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[0].command_index = 0U; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[0].origin_xyz[2] = 0.1; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[0].origin_wxyz[0] = -1.0; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[0].origin_xyz[0] = 0.1; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[0].origin_xyz[1] = -0.1; }, ErrorCode::kInvalidArgument, 0U);
    for (std::size_t k = 1U; k < 4U; ++k) {
        CAPTURE(k);
        expect_refused(
            [k](RobotModel& m) {
                m.links[0].origin_wxyz[0] = 0.0;
                m.links[0].origin_wxyz[k] = 1.0;  // a unit rotation other than the identity
            },
            ErrorCode::kInvalidArgument, 0U);
    }
    expect_refused([](RobotModel& m) { m.links[2].joint = static_cast<JointType>(3); }, ErrorCode::kInvalidArgument,
                   2U);
}

// verifies: SR-ROB-002
TEST_CASE("the model check refuses rotations and axes that are not of unit length") {
    expect_refused([](RobotModel& m) { m.base_wxyz[0] = 1.00001; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[2].origin_wxyz[0] = 0.0; }, ErrorCode::kInvalidArgument, 2U);
    expect_refused([](RobotModel& m) { m.links[4].axis[1] = 0.9999; }, ErrorCode::kInvalidArgument, 4U);
    expect_refused([](RobotModel& m) { m.links[5].axis[2] = 0.0; }, ErrorCode::kInvalidArgument, 5U);
    // Within the tolerance: accepted.
    CHECK(is_no_error(check_changed([](RobotModel& m) { m.links[5].axis[2] = 1.0 + 5e-7; })));
    CHECK(is_no_error(check_changed([](RobotModel& m) { m.base_wxyz[0] = 1.0 - 5e-7; })));
    // A fixed joint's axis is not used and not checked.
    CHECK(is_no_error(check_changed([](RobotModel& m) {
        m.link_count = 8U;
        m.links[7].parent = 6U;
        m.links[7].axis[0] = 0.0;
    })));
}

// verifies: SR-ROB-002
TEST_CASE("the model check refuses command indices that are not exactly 0..joint_count-1, and bad limits") {
    expect_refused([](RobotModel& m) { m.links[3].command_index = 1U; }, ErrorCode::kInvalidArgument, 3U);
    expect_refused([](RobotModel& m) { m.links[6].command_index = 6U; }, ErrorCode::kInvalidArgument, 6U);
    expect_refused([](RobotModel& m) { m.links[6].command_index = kNoCommandIndex; }, ErrorCode::kInvalidArgument, 6U);
    expect_refused([](RobotModel& m) { m.joint_count = 7U; }, ErrorCode::kInvalidArgument, 0U);
    expect_refused(
        [](RobotModel& m) {
            m.links[6].joint = JointType::kFixed;
            m.links[6].command_index = kNoCommandIndex;
        },
        ErrorCode::kInvalidArgument, 0U);
    expect_refused([](RobotModel& m) { m.links[6].joint = JointType::kFixed; }, ErrorCode::kInvalidArgument, 6U);
    expect_refused([](RobotModel& m) { m.links[2].lower = 0.1 + m.links[2].upper; }, ErrorCode::kInvalidArgument, 2U);
    expect_refused([](RobotModel& m) { m.links[5].max_velocity = 0.0; }, ErrorCode::kInvalidArgument, 5U);
    expect_refused([](RobotModel& m) { m.links[5].max_velocity = -1.0; }, ErrorCode::kInvalidArgument, 5U);
    CHECK(is_no_error(check_changed([](RobotModel& m) { m.links[2].lower = m.links[2].upper; })));
    // Limits within +-100 rad (revolute) and +-10 m (prismatic): the kinematics stay exact.
    expect_refused([](RobotModel& m) { m.links[4].upper = 100.001; }, ErrorCode::kInvalidArgument, 4U);
    expect_refused([](RobotModel& m) { m.links[4].lower = -2e35; }, ErrorCode::kInvalidArgument, 4U);
    CHECK(is_no_error(check_changed([](RobotModel& m) { m.links[4].upper = kMaxRevoluteLimit; })));
    expect_refused(
        [](RobotModel& m) {
            m.links[4].joint = JointType::kPrismatic;
            m.links[4].upper = 10.001;
        },
        ErrorCode::kInvalidArgument, 4U);
}

// verifies: SR-ROB-003
TEST_CASE("the model check refuses capsules on missing links, bad radii and anything beyond the reach") {
    expect_refused([](RobotModel& m) { m.capsules[2].link = 7U; }, ErrorCode::kInvalidArgument, 2U);
    expect_refused([](RobotModel& m) { m.capsules[2].radius = 0.0; }, ErrorCode::kInvalidArgument, 2U);
    expect_refused([](RobotModel& m) { m.capsules[2].radius = -0.1; }, ErrorCode::kInvalidArgument, 2U);
    expect_refused([](RobotModel& m) { m.capsules[2].radius = 1.0001; }, ErrorCode::kInvalidArgument, 2U);
    CHECK(is_no_error(check_changed([](RobotModel& m) { m.capsules[2].radius = kMaxCapsuleRadius; })));
    expect_refused([](RobotModel& m) { m.capsules[1].b[0] = 10.001; }, ErrorCode::kInvalidArgument, 1U);
    expect_refused([](RobotModel& m) { m.capsules[1].a[2] = -10.001; }, ErrorCode::kInvalidArgument, 1U);
    expect_refused([](RobotModel& m) { m.links[3].origin_xyz[0] = 10.001; }, ErrorCode::kInvalidArgument, 3U);
    expect_refused([](RobotModel& m) { m.base_xyz[2] = -10.001; }, ErrorCode::kInvalidArgument, 0U);
    CHECK(is_no_error(check_changed([](RobotModel& m) {
        m.capsules[1].b[0] = kMaxRobotReach;
        m.capsules[1].b[1] = 0.0;
    })));
}

// verifies: SR-ROB-002
TEST_CASE("the model check refuses a root rotation that differs from the identity in any one of x, y, z") {
    for (std::size_t k = 1U; k < 4U; ++k) {
        CAPTURE(k);
        const RobotModelError e = check_changed([k](RobotModel& m) {
            m.links[0].origin_wxyz[0] = 1.0;
            m.links[0].origin_wxyz[k] = 1e-9;  // of unit length within any tolerance, but not the identity
        });
        CHECK(e.code == ErrorCode::kInvalidArgument);
        CHECK(e.index == 0U);
        CHECK(std::string(e.reason).find("identity") != std::string::npos);
    }
}

// verifies: SR-ROB-007
TEST_CASE("a mimic joint passes the model check when its master's range maps inside its limits") {
    using cellguard::test::make_test_arm_with_mimic;
    const RobotModel bar = make_test_arm_with_mimic();
    CHECK(is_no_error(check_robot_model(bar)));
    CHECK(bar.joint_count == 6U);  // the mimic is not sent
    CHECK(has_mimic_joint(bar));
    CHECK_FALSE(has_mimic_joint(make_test_arm()));
    CHECK(is_no_error(check_robot_model(make_test_arm_with_mimic(-0.5, 0.25))));
    CHECK(is_no_error(check_robot_model(make_test_arm_with_mimic(3.0, -1.0))));
    // commanded_link skips the mimic: index 1 is the shoulder lift (link 2), not the bar (link 7).
    CHECK(commanded_link(bar, 1U) == &bar.links[2]);
    CHECK(commanded_link(bar, 6U) == nullptr);
    // Limits a little wider than the mapped range are fine; within the tolerance too.
    RobotModel wider = bar;
    wider.links[7].upper += 0.5;
    CHECK(is_no_error(check_robot_model(wider)));
    RobotModel within = bar;
    within.links[7].upper -= 0.5 * kMimicRangeTolerance * within.links[7].upper;
    CHECK(is_no_error(check_robot_model(within)));
}

// verifies: SR-ROB-007
TEST_CASE("the model check refuses a mimic with a wrong ratio, a zero or non-finite one, or without a master") {
    using cellguard::test::make_test_arm_with_mimic;
    const auto refused = [](const std::function<void(RobotModel&)>& change, ErrorCode code, std::size_t index) {
        RobotModel m = make_test_arm_with_mimic();
        change(m);
        const RobotModelError e = check_robot_model(m);
        INFO(std::string(e.reason));
        CHECK(e.code == code);
        CHECK(e.index == index);
    };
    // The master's range maps outside the mimic's own limits: a wrong multiplier or offset.
    refused([](RobotModel& m) { m.links[7].mimic_multiplier = 1.01; }, ErrorCode::kInvalidArgument, 7U);
    refused([](RobotModel& m) { m.links[7].mimic_offset = 0.01; }, ErrorCode::kInvalidArgument, 7U);
    refused([](RobotModel& m) { m.links[7].upper -= 1e-3; }, ErrorCode::kInvalidArgument, 7U);
    refused([](RobotModel& m) { m.links[7].mimic_multiplier = 0.0; }, ErrorCode::kInvalidArgument, 7U);
    refused([](RobotModel& m) { m.links[7].mimic_multiplier = kNaN; }, ErrorCode::kNonFiniteValue, 7U);
    refused([](RobotModel& m) { m.links[7].mimic_offset = kInf; }, ErrorCode::kNonFiniteValue, 7U);
    // A master that is not a commanded joint: beyond joint_count, or a mimic itself.
    refused([](RobotModel& m) { m.links[7].command_index = 6U; }, ErrorCode::kInvalidArgument, 7U);
    refused(
        [](RobotModel& m) {
            m.links[2].mimic = true;  // the lift a mimic too: index 1 has no commanded joint
        },
        ErrorCode::kInvalidArgument, 0U);
    // A fixed joint or the root cannot be a mimic; a link that is not one carries multiplier 1 and offset 0.
    refused([](RobotModel& m) { m.links[7].joint = JointType::kFixed; }, ErrorCode::kInvalidArgument, 7U);
    refused([](RobotModel& m) { m.links[0].mimic = true; }, ErrorCode::kInvalidArgument, 0U);
    refused([](RobotModel& m) { m.links[3].mimic_multiplier = 2.0; }, ErrorCode::kInvalidArgument, 3U);
    refused([](RobotModel& m) { m.links[3].mimic_offset = 0.1; }, ErrorCode::kInvalidArgument, 3U);
    refused(
        [](RobotModel& m) {
            m.links[7].mimic = false;  // the bar commanded with index 1 as well: two joints share it
        },
        ErrorCode::kInvalidArgument, 7U);
}
