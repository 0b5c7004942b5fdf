// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the PLC's joint positions checked and converted (count, reserved value, unused joints, limits,
// robot id), and forward kinematics that places the robot's capsules (hand-computed poses, a 6-axis arm, same bits).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <string>

#include "alloc_counter.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "contract_capture.hpp"
#include "test_robot.hpp"

using namespace cellguard;
using cellguard::test::make_test_arm;
using cellguard::test::test_arm_joints;
using cellguard::test::test_arm_pose;

namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kTol = 1e-12;

// A planar 2-link arm in the x-y plane: both joints about z, link 1 (1 m along x) and link 2 (0.5 m along x).
RobotModel planar_arm() {
    RobotModel m;
    m.link_count = 3U;
    m.joint_count = 2U;
    m.capsule_count = 2U;
    for (std::uint8_t i = 1U; i <= 2U; ++i) {
        RobotLink& l = m.links[i];
        l.parent = static_cast<std::uint8_t>(i - 1U);
        l.joint = JointType::kRevolute;
        l.command_index = static_cast<std::uint8_t>(i - 1U);
        l.axis[0] = 0.0;
        l.axis[2] = 1.0;
        l.lower = -kPi;
        l.upper = kPi;
        l.max_velocity = 1.0;
    }
    m.links[2].origin_xyz[0] = 1.0;
    m.capsules[0].link = 1U;
    m.capsules[0].b[0] = 1.0;
    m.capsules[0].radius = 0.1;
    m.capsules[1].link = 2U;
    m.capsules[1].b[0] = 0.5;
    m.capsules[1].radius = 0.05;
    return m;
}

JointPositions two(double q0, double q1) {
    JointPositions q;
    q.count = 2U;
    q.q[0] = q0;
    q.q[1] = q1;
    return q;
}

void check_point(const double p[3], double x, double y, double z) {
    CHECK(std::fabs(p[0] - x) <= kTol);
    CHECK(std::fabs(p[1] - y) <= kTol);
    CHECK(std::fabs(p[2] - z) <= kTol);
}

RobotCommand command_for(std::uint32_t crc, std::uint8_t count, std::initializer_list<std::int16_t> raw) {
    RobotCommand c;
    c.robot_id = robot_id(crc);
    c.joint_count = count;
    std::size_t k = 0U;
    for (const std::int16_t r : raw) {
        c.joint_raw[k++] = r;
    }
    return c;
}

std::uint64_t bits_of(double d) {
    std::uint64_t b = 0U;
    std::memcpy(&b, &d, sizeof b);
    return b;
}

}  // namespace

// verifies: SR-ROB-010
TEST_CASE("a planar two-link arm is placed where hand computation puts it") {
    const RobotModel arm = planar_arm();
    REQUIRE(is_no_error(check_robot_model(arm)));
    RobotPose pose;
    place_robot(arm, two(0.0, 0.0), pose);
    REQUIRE(pose.count == 2U);
    check_point(pose.capsules[0].a, 0.0, 0.0, 0.0);
    check_point(pose.capsules[0].b, 1.0, 0.0, 0.0);
    check_point(pose.capsules[1].a, 1.0, 0.0, 0.0);
    check_point(pose.capsules[1].b, 1.5, 0.0, 0.0);
    CHECK(pose.capsules[0].radius == 0.1);
    CHECK(pose.capsules[1].link == 2U);

    place_robot(arm, two(kPi / 2.0, 0.0), pose);
    check_point(pose.capsules[0].b, 0.0, 1.0, 0.0);
    check_point(pose.capsules[1].b, 0.0, 1.5, 0.0);

    place_robot(arm, two(kPi / 2.0, -kPi / 2.0), pose);
    check_point(pose.capsules[1].a, 0.0, 1.0, 0.0);
    check_point(pose.capsules[1].b, 0.5, 1.0, 0.0);

    place_robot(arm, two(kPi / 6.0, kPi / 3.0), pose);  // 30 deg, then 90 deg in total
    check_point(pose.capsules[0].b, std::sqrt(3.0) / 2.0, 0.5, 0.0);
    check_point(pose.capsules[1].b, std::sqrt(3.0) / 2.0, 1.0, 0.0);

    place_robot(arm, two(-kPi, kPi), pose);
    check_point(pose.capsules[0].b, -1.0, 0.0, 0.0);
    check_point(pose.capsules[1].b, -0.5, 0.0, 0.0);
}

// verifies: SR-ROB-010
TEST_CASE("the base pose, joint origins' rotations and prismatic joints place the capsules") {
    RobotModel arm = planar_arm();
    // Base at (1, 2, 3), turned 90 degrees about z.
    arm.base_xyz[0] = 1.0;
    arm.base_xyz[1] = 2.0;
    arm.base_xyz[2] = 3.0;
    arm.base_wxyz[0] = std::sqrt(0.5);
    arm.base_wxyz[3] = std::sqrt(0.5);
    REQUIRE(is_no_error(check_robot_model(arm)));
    RobotPose pose;
    place_robot(arm, two(0.0, 0.0), pose);
    check_point(pose.capsules[0].a, 1.0, 2.0, 3.0);
    check_point(pose.capsules[0].b, 1.0, 3.0, 3.0);
    check_point(pose.capsules[1].b, 1.0, 3.5, 3.0);

    // Link 2 becomes prismatic along its x axis, its origin turned 90 degrees about y (x -> -z).
    arm = planar_arm();
    arm.links[2].joint = JointType::kPrismatic;
    arm.links[2].axis[0] = 1.0;
    arm.links[2].axis[2] = 0.0;
    arm.links[2].lower = 0.0;
    arm.links[2].upper = 0.5;
    arm.links[2].origin_wxyz[0] = std::sqrt(0.5);
    arm.links[2].origin_wxyz[2] = std::sqrt(0.5);
    REQUIRE(is_no_error(check_robot_model(arm)));
    place_robot(arm, two(0.0, 0.25), pose);
    check_point(pose.capsules[1].a, 1.0, 0.0, -0.25);
    check_point(pose.capsules[1].b, 1.0, 0.0, -0.75);
    place_robot(arm, two(kPi / 2.0, 0.0), pose);
    check_point(pose.capsules[1].a, 0.0, 1.0, 0.0);
    check_point(pose.capsules[1].b, 0.0, 1.0, -0.5);
}

// verifies: SR-ROB-010
TEST_CASE("the 6-axis test arm: straight up, shoulder down, elbow bent, pan turned") {
    const RobotModel arm = make_test_arm(0.2, -0.1, 0.0);
    REQUIRE(is_no_error(check_robot_model(arm)));
    using namespace cellguard::test;
    RobotPose pose = test_arm_pose(arm, test_arm_joints(0, 0, 0, 0, 0, 0));
    REQUIRE(pose.count == 7U);
    check_point(pose.capsules[0].b, 0.2, -0.1, kArmBaseHeight);
    check_point(pose.capsules[1].a, 0.2, -0.19, kArmBaseHeight);
    check_point(pose.capsules[6].b, 0.2, -0.1, kArmStraightHeight);

    // Shoulder lift +90 degrees about y turns the arm from +z to +x.
    const double reach = kArmStraightHeight - kArmBaseHeight;
    pose = test_arm_pose(arm, test_arm_joints(0, kPi / 2.0, 0, 0, 0, 0));
    check_point(pose.capsules[2].b, 0.2 + kArmUpperArm, -0.1, kArmBaseHeight);
    check_point(pose.capsules[6].b, 0.2 + reach, -0.1, kArmBaseHeight);

    // Pan +90 degrees about z then turns +x into +y.
    pose = test_arm_pose(arm, test_arm_joints(kPi / 2.0, kPi / 2.0, 0, 0, 0, 0));
    check_point(pose.capsules[6].b, 0.2, -0.1 + reach, kArmBaseHeight);

    // Elbow +90 degrees: the forearm and wrist run along +x at the elbow's height.
    pose = test_arm_pose(arm, test_arm_joints(0, 0, kPi / 2.0, 0, 0, 0));
    const double elbow_z = kArmBaseHeight + kArmUpperArm;
    check_point(pose.capsules[3].a, 0.2, -0.1, elbow_z);
    check_point(pose.capsules[6].b, 0.2 + reach - kArmUpperArm, -0.1, elbow_z);

    // Wrist 1 -90 degrees after the elbow's +90: the wrist points up again; wrist 2 about z changes nothing there.
    pose = test_arm_pose(arm, test_arm_joints(0, 0, kPi / 2.0, -kPi / 2.0, 1.0, 0));
    check_point(pose.capsules[4].b, 0.2 + kArmForearm, -0.1, elbow_z + kArmWrist1);
    check_point(pose.capsules[6].b, 0.2 + kArmForearm, -0.1, elbow_z + kArmWrist1 + kArmWrist2 + kArmFlange);

    // Every capsule keeps its length in any pose.
    pose = test_arm_pose(arm, test_arm_joints(0.3, -1.1, 2.0, 0.7, -2.5, 1.9));
    for (std::size_t c = 0; c < arm.capsule_count; ++c) {
        double l0 = 0.0;
        double l1 = 0.0;
        for (int k = 0; k < 3; ++k) {
            l0 += (arm.capsules[c].b[k] - arm.capsules[c].a[k]) * (arm.capsules[c].b[k] - arm.capsules[c].a[k]);
            l1 += (pose.capsules[c].b[k] - pose.capsules[c].a[k]) * (pose.capsules[c].b[k] - pose.capsules[c].a[k]);
        }
        CHECK(std::fabs(std::sqrt(l0) - std::sqrt(l1)) <= kTol);
    }
}

// verifies: SR-ROB-011
TEST_CASE("the kinematics' sine and cosine are accurate over the whole joint range") {
    // One link about z with a capsule end at (1, 0, 0): the end is (cos q, sin q, 0).
    RobotModel arm = planar_arm();
    arm.links[1].lower = -7.0;
    arm.links[1].upper = 7.0;
    RobotPose pose;
    double worst = 0.0;
    for (std::int32_t raw = -32767; raw <= 32767; raw += 7) {
        const double q = raw * kRevoluteJointUnitRad;
        place_robot(arm, two(q, 0.0), pose);
        worst = std::fmax(worst, std::fabs(pose.capsules[0].b[0] - std::cos(q)));
        worst = std::fmax(worst, std::fabs(pose.capsules[0].b[1] - std::sin(q)));
    }
    CHECK(worst <= 4e-16);
}

// verifies: SR-ROB-011
TEST_CASE("placing the 6-axis arm gives the same bits on every target, without the heap") {
    // The golden bits were computed once on x86-64; the cross builds (aarch64, Cortex-M7 under qemu) run this too.
    const RobotModel arm = make_test_arm(0.1, -0.2, 0.05);
    RobotPose pose;
    {
        const cellguard::test::AllocationScope guard;
        place_robot(arm, test_arm_joints(0.3, -1.1, 2.0, 0.7, -2.5, 1.9), pose);
        CHECK(guard.allocations() == 0U);
    }
    // Checked against an independent evaluation with Python's math.sin/cos (agrees within 3e-16 m).
    const std::uint64_t expected[6] = {0x3FCE41BF6BF2DE64ULL, 0xBFC433314575B9F3ULL, 0x3FE9BA65670DE6A4ULL,
                                       0x3FCCDF3DF042396CULL, 0xBFCB752023D84B06ULL, 0x3FEBF010E60658C6ULL};
    const double got[6] = {pose.capsules[6].a[0], pose.capsules[6].a[1], pose.capsules[6].a[2],
                           pose.capsules[6].b[0], pose.capsules[6].b[1], pose.capsules[6].b[2]};
    for (int k = 0; k < 6; ++k) {
        INFO("coordinate " << k);
        CHECK(bits_of(got[k]) == expected[k]);
    }
}

// verifies: SR-ROB-030
TEST_CASE("joint_positions converts raw revolute and prismatic values to SI units") {
    RobotModel arm = planar_arm();
    arm.links[2].joint = JointType::kPrismatic;
    arm.links[2].lower = -0.5;
    arm.links[2].upper = 0.5;
    REQUIRE(is_no_error(check_robot_model(arm)));
    const std::uint32_t crc = 0xABCD1234U;
    const Result<JointPositions, JointCheck> r = joint_positions(arm, crc, command_for(crc, 2U, {5000, -2500}));
    REQUIRE(r.ok());
    CHECK(r.value().count == 2U);
    CHECK(r.value().q[0] == 5000 * kRevoluteJointUnitRad);
    CHECK(std::fabs(r.value().q[0] - 1.0) <= 1e-15);
    CHECK(std::fabs(r.value().q[1] + 0.25) <= 1e-15);
    CHECK(r.value().q[2] == 0.0);
}

// verifies: SR-ROB-031
TEST_CASE("joint_positions refuses another joint count, the reserved value and unused joints that are not 0") {
    const RobotModel arm = make_test_arm();
    const std::uint32_t crc = 0x00C0FFEEU;
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {0, 0, 0, 0, 0, 0})).ok());
    CHECK(joint_positions(arm, crc, command_for(crc, 5U, {0, 0, 0, 0, 0})).error() == JointCheck::kJointCountMismatch);
    CHECK(joint_positions(arm, crc, command_for(crc, 7U, {0, 0, 0, 0, 0, 0, 0})).error() ==
          JointCheck::kJointCountMismatch);
    CHECK(joint_positions(arm, crc, command_for(crc, 0U, {})).error() == JointCheck::kJointCountMismatch);
    for (std::size_t k = 0; k < 6U; ++k) {
        RobotCommand c = command_for(crc, 6U, {0, 0, 0, 0, 0, 0});
        c.joint_raw[k] = kJointRawInvalid;
        CHECK(joint_positions(arm, crc, c).error() == JointCheck::kInvalidRaw);
    }
    RobotCommand c = command_for(crc, 6U, {0, 0, 0, 0, 0, 0});
    c.joint_raw[6] = 1;
    CHECK(joint_positions(arm, crc, c).error() == JointCheck::kInvalidRaw);
    c.joint_raw[6] = kJointRawInvalid;
    CHECK(joint_positions(arm, crc, c).error() == JointCheck::kInvalidRaw);
}

// verifies: SR-ROB-032
TEST_CASE("joint_positions accepts a position within half a raw unit beyond a limit and refuses one further") {
    const RobotModel arm = make_test_arm();  // elbow (index 2) limits +-pi
    const std::uint32_t crc = 0x12345678U;
    // pi / 0.0002 = 15707.96...: raw 15708 is 7.3 urad beyond (less than half a unit), 15709 is 207 urad beyond.
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {0, 0, 15708, 0, 0, 0})).ok());
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {0, 0, -15708, 0, 0, 0})).ok());
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {0, 0, 15709, 0, 0, 0})).error() ==
          JointCheck::kOutsideLimits);
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {0, 0, -15709, 0, 0, 0})).error() ==
          JointCheck::kOutsideLimits);
    // Joint 0's limits +-2 pi are within the wire's range: +-31416 accepted, +-31417 refused.
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {31416, 0, 0, 0, 0, 0})).ok());
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {31417, 0, 0, 0, 0, 0})).error() ==
          JointCheck::kOutsideLimits);
    CHECK(joint_positions(arm, crc, command_for(crc, 6U, {-31417, 0, 0, 0, 0, 0})).error() ==
          JointCheck::kOutsideLimits);
    // An exact limit of a prismatic joint: 0.1 m = raw 1000; 0.10005 m (raw 1000.5) cannot be sent.
    RobotModel slide = planar_arm();
    slide.links[2].joint = JointType::kPrismatic;
    slide.links[2].lower = 0.0;
    slide.links[2].upper = 0.1;
    CHECK(joint_positions(slide, crc, command_for(crc, 2U, {0, 1000})).ok());
    CHECK(joint_positions(slide, crc, command_for(crc, 2U, {0, 1001})).error() == JointCheck::kOutsideLimits);
    CHECK(joint_positions(slide, crc, command_for(crc, 2U, {0, -1})).error() == JointCheck::kOutsideLimits);
}

// verifies: SR-ROB-033
TEST_CASE("joint_positions refuses a command that names another robot image") {
    const RobotModel arm = make_test_arm();
    const std::uint32_t crc = 0xABCD1234U;
    CHECK(robot_id(crc) == 0x1234U);
    RobotCommand c = command_for(crc, 6U, {0, 0, 0, 0, 0, 0});
    CHECK(joint_positions(arm, crc, c).ok());
    c.robot_id = 0x1235U;
    CHECK(joint_positions(arm, crc, c).error() == JointCheck::kRobotIdMismatch);
    // Only the low 16 bits travel: another CRC with the same low half is the same id (the image CRC is checked at start-up).
    CHECK(joint_positions(arm, 0xFFFF1234U, command_for(crc, 6U, {0, 0, 0, 0, 0, 0})).ok());
    // The id is checked first: a command for another robot is refused as such, whatever else it carries.
    RobotCommand other = command_for(0x1U, 3U, {kJointRawInvalid});
    CHECK(joint_positions(arm, crc, other).error() == JointCheck::kRobotIdMismatch);
}

// verifies: SR-ROB-031
TEST_CASE("every JointCheck has its own name") {
    std::set<std::string> names;
    for (const JointCheck c : {JointCheck::kOk, JointCheck::kJointCountMismatch, JointCheck::kInvalidRaw,
                               JointCheck::kOutsideLimits, JointCheck::kRobotIdMismatch}) {
        REQUIRE(to_string(c) != nullptr);
        names.insert(to_string(c));
    }
    CHECK(names.size() == 5U);
    CHECK(std::string(to_string(static_cast<JointCheck>(99))) == "unknown joint check");
}

// verifies: SR-ROB-010
TEST_CASE("place_robot refuses, as a contract violation, a model it was not checked for") {
    const RobotModel arm = planar_arm();
    REQUIRE(is_no_error(check_robot_model(arm)));
    RobotPose pose;
    CHECK_FALSE(test::violates_contract([&] { place_robot(arm, two(0.0, 0.0), pose); }));
    JointPositions short_q = two(0.0, 0.0);
    short_q.count = 1U;
    CHECK(test::violates_contract([&] { place_robot(arm, short_q, pose); }));
    RobotModel no_links = arm;
    no_links.link_count = 0U;
    CHECK(test::violates_contract([&] { place_robot(no_links, two(0.0, 0.0), pose); }));
    RobotModel too_many_links = arm;
    too_many_links.link_count = kMaxRobotLinks + 1U;
    CHECK(test::violates_contract([&] { place_robot(too_many_links, two(0.0, 0.0), pose); }));
    RobotModel too_many_capsules = arm;
    too_many_capsules.capsule_count = kMaxRobotCapsules + 1U;
    CHECK(test::violates_contract([&] { place_robot(too_many_capsules, two(0.0, 0.0), pose); }));
    RobotModel child_first = arm;
    child_first.links[2].parent = 2U;
    CHECK(test::violates_contract([&] { place_robot(child_first, two(0.0, 0.0), pose); }));
    RobotModel revolute_beyond = arm;
    revolute_beyond.links[2].command_index = 2U;
    CHECK(test::violates_contract([&] { place_robot(revolute_beyond, two(0.0, 0.0), pose); }));
    RobotModel prismatic_beyond = arm;
    prismatic_beyond.links[2].joint = JointType::kPrismatic;
    prismatic_beyond.links[2].command_index = 2U;
    CHECK(test::violates_contract([&] { place_robot(prismatic_beyond, two(0.0, 0.0), pose); }));
    RobotModel capsule_beyond = arm;
    capsule_beyond.capsules[1].link = 3U;
    CHECK(test::violates_contract([&] { place_robot(capsule_beyond, two(0.0, 0.0), pose); }));
}

// verifies: SR-ROB-031
TEST_CASE("joint_positions on a model whose joints lack a link is a contract violation") {
    RobotModel arm = planar_arm();
    const std::uint32_t crc = 0x00C0FFEEU;
    REQUIRE(joint_positions(arm, crc, command_for(crc, 2U, {0, 0})).ok());
    arm.links[2].joint = JointType::kFixed;  // joint 1 has no link now: not a checked model
    CHECK(test::violates_contract([&] { (void)joint_positions(arm, crc, command_for(crc, 2U, {0, 0})); }));
}

// verifies: SR-ROB-007
TEST_CASE("a mimic joint stands at multiplier x master + offset: the same bits as that position commanded") {
    using cellguard::test::make_test_arm_with_mimic;
    for (const double multiplier : {1.0, -0.5, 3.0}) {
        const double offset = multiplier == 1.0 ? 0.0 : 0.25;
        const RobotModel bar = make_test_arm_with_mimic(multiplier, offset);
        REQUIRE(is_no_error(check_robot_model(bar)));
        // The reference: the bar an independent, commanded seventh joint, sent the mimic's position.
        RobotModel seven = bar;
        seven.links[7].mimic = false;
        seven.links[7].mimic_multiplier = 1.0;
        seven.links[7].mimic_offset = 0.0;
        seven.links[7].command_index = 6U;
        seven.joint_count = 7U;
        REQUIRE(is_no_error(check_robot_model(seven)));
        for (const double lift : {-1.1, 0.0, 0.4, 2.5}) {
            const JointPositions q = test_arm_joints(0.3, lift, 1.0, 0.7, -2.5, 1.9);
            JointPositions q7 = q;
            q7.count = 7U;
            q7.q[6] = multiplier * lift + offset;
            RobotPose pose;
            {
                const cellguard::test::AllocationScope guard;
                place_robot(bar, q, pose);
                CHECK(guard.allocations() == 0U);
            }
            const RobotPose reference = test_arm_pose(seven, q7);
            REQUIRE(pose.count == 8U);
            INFO("multiplier " << multiplier << ", lift " << lift);
            CHECK(std::memcmp(&pose.capsules[7], &reference.capsules[7], sizeof(PlacedCapsule)) == 0);
            CHECK(std::memcmp(&pose.capsules[2], &reference.capsules[2], sizeof(PlacedCapsule)) == 0);
        }
    }
    // Multiplier 1, offset 0: the bar turns with the upper arm, so the two stay parallel (a parallelogram).
    const RobotModel bar = make_test_arm_with_mimic();
    const RobotPose pose = test_arm_pose(bar, test_arm_joints(0.3, -0.8, 1.0, 0.0, 0.0, 0.0));
    const PlacedCapsule& upper = pose.capsules[2];
    const PlacedCapsule& rear = pose.capsules[7];
    for (int k = 0; k < 3; ++k) {
        CHECK((rear.b[k] - rear.a[k]) / 0.5 == doctest::Approx((upper.b[k] - upper.a[k]) / 0.61).epsilon(1e-12));
    }
}

// verifies: SR-ROB-007
TEST_CASE("joint_positions reads a model with a mimic joint by its commanded joints only") {
    using cellguard::test::make_test_arm_with_mimic;
    const RobotModel bar = make_test_arm_with_mimic(-0.5, 0.25);
    RobotCommand command;
    command.robot_id = robot_id(0x1234U);
    command.joint_count = 6U;
    command.joint_raw[1] = 5000;  // the lift at 1.0 rad (0.2 mrad per raw unit)
    const Result<JointPositions, JointCheck> q = joint_positions(bar, 0x1234U, command);
    REQUIRE(q.ok());
    CHECK(q.value().count == 6U);
    CHECK(q.value().q[1] == doctest::Approx(1.0));
    command.joint_count = 7U;  // the mimic is not a joint the PLC sends
    command.joint_raw[6] = 0;
    const Result<JointPositions, JointCheck> seven = joint_positions(bar, 0x1234U, command);
    REQUIRE(!seven.ok());
    CHECK(seven.error() == JointCheck::kJointCountMismatch);
}
