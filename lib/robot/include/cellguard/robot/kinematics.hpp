// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file kinematics.hpp
/// From the PLC's joint positions to the robot's capsules in the cell's
/// world frame: the command's raw values checked and converted, then forward
/// kinematics over the link tree (Eigen fixed-size types, no heap; the same
/// sequence of IEEE-754 double operations on every target, built with
/// -ffp-contract=off, so x86-64, aarch64 and Cortex-M7 give the same bits).
#ifndef CELLGUARD_ROBOT_KINEMATICS_HPP
#define CELLGUARD_ROBOT_KINEMATICS_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Joint positions in SI units (rad or m), by command index.
struct JointPositions {
    double q[kMaxRobotJoints] = {};  ///< position of movable joint k
    std::uint8_t count = 0U;         ///< joints used (= the model's joint_count)
};

/// Why a command's joints were refused. Values are stable (logged).
enum class JointCheck : std::uint8_t {
    kOk = 0,                  ///< usable
    kJointCountMismatch = 1,  ///< the command carries another number of joints than the robot has
    kInvalidRaw = 2,          ///< a used joint carries kJointRawInvalid, or an unused one is not 0
    kOutsideLimits = 3,       ///< a position outside its joint's [lower, upper]
    kRobotIdMismatch = 4,     ///< the command names another robot image (robot_id)
};

/// True when @p check is kOk: what Result<T, JointCheck> checks.
constexpr bool is_no_error(JointCheck check) noexcept { return check == JointCheck::kOk; }

/// Static name of @p check (never nullptr).
[[nodiscard]] const char* to_string(JointCheck check) noexcept;

/// Checks @p command against @p model (whose image CRC is @p image_crc) and
/// converts its raw values (kRevoluteJointUnitRad / kPrismaticJointUnitM).
/// A position beyond a limit by less than half a raw unit is accepted (the
/// wire cannot say it more exactly). Checks in this order, the first failure
/// returned: robot id, joint count, raw values (used ones not
/// kJointRawInvalid, unused ones 0), limits (by command index). A mimic
/// joint is not checked here: check_robot_model has shown that its master's
/// whole range maps inside its limits.
/// @p model must pass check_robot_model (contract).
[[nodiscard]] Result<JointPositions, JointCheck> joint_positions(const RobotModel& model, std::uint32_t image_crc,
                                                                 const RobotCommand& command) noexcept;

/// A capsule in the world frame.
struct PlacedCapsule {
    double a[3] = {0.0, 0.0, 0.0};  ///< first end, metres
    double b[3] = {0.0, 0.0, 0.0};  ///< second end, metres
    double radius = 0.0;            ///< metres
    std::uint8_t link = 0U;         ///< the link it belongs to
};

/// Every capsule of the robot in one pose.
struct RobotPose {
    PlacedCapsule capsules[kMaxRobotCapsules] = {};  ///< in the model's capsule order
    std::uint8_t count = 0U;                         ///< the model's capsule_count
};

/// Places every capsule of @p model at joint positions @p q (q.count must be
/// the model's joint_count and the model checked: contracts). A mimic joint
/// stands at its multiplier times its master's position plus its offset.
/// Work: one transform per link and two points per capsule. Sine and cosine come from
/// a fixed polynomial (fdlibm's kernels after a Cody-Waite reduction, within
/// 4e-16 of the C library's over the wire's joint range), not the C library,
/// and every product is written out in scalar operations: the same bits on
/// every target.
void place_robot(const RobotModel& model, const JointPositions& q, RobotPose& out) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ROBOT_KINEMATICS_HPP
