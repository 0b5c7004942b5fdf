// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A 6-axis test arm of a UR10's size, built in code for the robot module's
// tests and bench_cycle: base column 0.13 m, upper arm 0.61 m, forearm
// 0.57 m, two wrist links of 0.12 m and a 0.09 m flange, capsule radii
// 0.05..0.09 m. Joint axes z, y, y, y, z, y (pan, shoulder, elbow, three
// wrists); at all joints 0 the arm stands straight up from its base.
// Header-only: the benchmarks include it without the unit tests' sources.
#ifndef CELLGUARD_TESTS_TEST_ROBOT_HPP
#define CELLGUARD_TESTS_TEST_ROBOT_HPP

#include <cstdint>
#include <cstring>

#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_model.hpp"

namespace cellguard::test {

/// Heights of the test arm's segments at joints 0, metres.
constexpr double kArmBaseHeight = 0.13;
constexpr double kArmUpperArm = 0.61;
constexpr double kArmForearm = 0.57;
constexpr double kArmWrist1 = 0.12;
constexpr double kArmWrist2 = 0.12;
constexpr double kArmFlange = 0.09;
/// Its height when straight up (base column to flange end).
constexpr double kArmStraightHeight = kArmBaseHeight + kArmUpperArm + kArmForearm + kArmWrist1 + kArmWrist2 +
                                      kArmFlange;

/// A movable link of the test arm: revolute about @p axis (a unit axis x, y or z) at @p z_offset above its parent.
inline RobotLink test_arm_joint(std::uint8_t parent, std::uint8_t index, int axis, double z_offset, double limit,
                                double velocity) {
    RobotLink l;
    l.parent = parent;
    l.joint = JointType::kRevolute;
    l.command_index = index;
    l.origin_xyz[2] = z_offset;
    l.axis[0] = axis == 0 ? 1.0 : 0.0;
    l.axis[1] = axis == 1 ? 1.0 : 0.0;
    l.axis[2] = axis == 2 ? 1.0 : 0.0;
    l.lower = -limit;
    l.upper = limit;
    l.max_velocity = velocity;
    return l;
}

/// A capsule of the test arm on @p link from (ax, ay, az) to (bx, by, bz), radius @p r.
inline RobotCapsule test_arm_capsule(std::uint8_t link, double ax, double ay, double az, double bx, double by,
                                     double bz, double r) {
    RobotCapsule c;
    c.link = link;
    c.a[0] = ax;
    c.a[1] = ay;
    c.a[2] = az;
    c.b[0] = bx;
    c.b[1] = by;
    c.b[2] = bz;
    c.radius = r;
    return c;
}

/// The test arm with its base at (x, y, z) in the world frame, not rotated.
inline RobotModel make_test_arm(double x = 0.0, double y = 0.0, double z = 0.0) {
    constexpr double kTwoPi = 6.283185307179586;
    constexpr double kPi = 3.141592653589793;
    RobotModel m;
    std::strncpy(m.name, "cellguard_test_arm", sizeof m.name - 1U);
    m.base_xyz[0] = x;
    m.base_xyz[1] = y;
    m.base_xyz[2] = z;
    m.link_count = 7U;
    m.joint_count = 6U;
    m.links[1] = test_arm_joint(0U, 0U, 2, kArmBaseHeight, kTwoPi, 2.094);  // shoulder pan
    m.links[2] = test_arm_joint(1U, 1U, 1, 0.0, kTwoPi, 2.094);             // shoulder lift
    m.links[3] = test_arm_joint(2U, 2U, 1, kArmUpperArm, kPi, 3.142);       // elbow
    m.links[4] = test_arm_joint(3U, 3U, 1, kArmForearm, kTwoPi, 3.142);     // wrist 1
    m.links[5] = test_arm_joint(4U, 4U, 2, kArmWrist1, kTwoPi, 3.142);      // wrist 2
    m.links[6] = test_arm_joint(5U, 5U, 1, kArmWrist2, kTwoPi, 3.142);      // wrist 3
    m.capsule_count = 7U;
    m.capsules[0] = test_arm_capsule(0U, 0.0, 0.0, 0.0, 0.0, 0.0, kArmBaseHeight, 0.09);  // base column
    m.capsules[1] = test_arm_capsule(1U, 0.0, -0.09, 0.0, 0.0, 0.09, 0.0, 0.09);          // shoulder housing
    m.capsules[2] = test_arm_capsule(2U, 0.0, 0.0, 0.0, 0.0, 0.0, kArmUpperArm, 0.075);   // upper arm
    m.capsules[3] = test_arm_capsule(3U, 0.0, 0.0, 0.0, 0.0, 0.0, kArmForearm, 0.06);     // forearm
    m.capsules[4] = test_arm_capsule(4U, 0.0, 0.0, 0.0, 0.0, 0.0, kArmWrist1, 0.05);      // wrist 1
    m.capsules[5] = test_arm_capsule(5U, 0.0, 0.0, 0.0, 0.0, 0.0, kArmWrist2, 0.05);      // wrist 2
    m.capsules[6] = test_arm_capsule(6U, 0.0, 0.0, 0.0, 0.0, 0.0, kArmFlange, 0.05);      // flange
    return m;
}

/// The test arm with a parallel bar, as a palletizer's parallelogram has: link
/// 7 hangs from the pan link 0.1 m behind the shoulder, turns about y as a
/// mimic of the shoulder lift (command index 1) at @p multiplier x lift +
/// @p offset, its limits exactly the lift's range mapped, and carries capsule
/// 7 (0.5 m up its z axis, radius 0.04 m). Still 6 commanded joints.
inline RobotModel make_test_arm_with_mimic(double multiplier = 1.0, double offset = 0.0) {
    constexpr double kTwoPi = 6.283185307179586;
    RobotModel m = make_test_arm();
    RobotLink bar = test_arm_joint(1U, 1U, 1, 0.0, kTwoPi, 2.094);
    bar.origin_xyz[0] = -0.1;
    bar.mimic = true;
    bar.mimic_multiplier = multiplier;
    bar.mimic_offset = offset;
    const double at_lower = multiplier * -kTwoPi + offset;
    const double at_upper = multiplier * kTwoPi + offset;
    bar.lower = at_lower < at_upper ? at_lower : at_upper;
    bar.upper = at_lower < at_upper ? at_upper : at_lower;
    m.links[7] = bar;
    m.link_count = 8U;
    m.capsules[7] = test_arm_capsule(7U, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.04);
    m.capsule_count = 8U;
    return m;
}

/// Joint positions of the test arm (6 joints), radians.
inline JointPositions test_arm_joints(double q0, double q1, double q2, double q3, double q4, double q5) {
    JointPositions q;
    q.count = 6U;
    q.q[0] = q0;
    q.q[1] = q1;
    q.q[2] = q2;
    q.q[3] = q3;
    q.q[4] = q4;
    q.q[5] = q5;
    return q;
}

/// The test arm placed at @p q.
inline RobotPose test_arm_pose(const RobotModel& arm, const JointPositions& q) {
    RobotPose pose;
    place_robot(arm, q, pose);
    return pose;
}

}  // namespace cellguard::test

#endif
