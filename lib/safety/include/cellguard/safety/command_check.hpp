// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file command_check.hpp
/// The controller's check of the PLC's command against the commissioned
/// cell, once per cycle, before the command is used for anything.
///
/// In order, the first failure is the reason:
/// 1. the receiver holds a good sample (CommandInput::valid): else kMissing
///    (a missing, corrupt, repeated or reordered sample is the receiver's
///    finding, command_receiver.hpp);
/// 2. the sample arrived no later than the cycle's start and at most
///    max_age_us before it: else kStale. A sample that arrives during cycle
///    k is applied from cycle k + 1 (it is "received before the cycle
///    starts" only then); a sample kept by the receiver is used again in
///    the next cycles until it is older than max_age_us;
/// 3. the monitoring case exists: else kUnknownCase;
/// 4. with a robot: the speed class is commissioned (< class_count of the
///    separation parameters): else kUnknownSpeedClass; then the robot's
///    joint_positions (robot id, joint count, raw values, limits), whose
///    JointCheck is the reason. Without a robot the command must carry no
///    joints (joint_count 0): else kJointCountMismatch.
#ifndef CELLGUARD_SAFETY_COMMAND_CHECK_HPP
#define CELLGUARD_SAFETY_COMMAND_CHECK_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "cellguard/safety/monitoring_cases.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Why a command was refused (RobotReport::command_check). Values 1..4 are
/// JointCheck's; values appear in logs: append only.
enum class CommandRefusal : std::uint8_t {
    kNone = 0,                                                                         ///< accepted
    kJointCountMismatch = static_cast<std::uint8_t>(JointCheck::kJointCountMismatch),  ///< see JointCheck
    kInvalidRaw = static_cast<std::uint8_t>(JointCheck::kInvalidRaw),                  ///< see JointCheck
    kOutsideLimits = static_cast<std::uint8_t>(JointCheck::kOutsideLimits),            ///< see JointCheck
    kRobotIdMismatch = static_cast<std::uint8_t>(JointCheck::kRobotIdMismatch),        ///< see JointCheck
    kMissing = 16,            ///< no good sample (CommandInput::valid false)
    kStale = 17,              ///< older than the limit, or stamped after the cycle's start
    kUnknownCase = 18,        ///< a monitoring case the cell does not have
    kUnknownSpeedClass = 19,  ///< a speed class not commissioned
};

/// True when @p r is kNone: what Result<T, CommandRefusal> checks.
constexpr bool is_no_error(CommandRefusal r) noexcept { return r == CommandRefusal::kNone; }

/// Static name of @p r (never nullptr).
[[nodiscard]] const char* to_string(CommandRefusal r) noexcept;

/// What a command is checked against.
struct CommandLimits {
    const MonitoringCases* cases = nullptr;  ///< the cell's cases (required: nullptr refuses every case)
    const RobotModel* robot = nullptr;       ///< the checked robot model; nullptr: a cell without a robot
    std::uint32_t image_crc = 0U;            ///< the robot image's CRC-32 (robot id = its low 16 bits)
    std::uint8_t speed_classes = 1U;         ///< commissioned speed classes (SeparationParams::class_count)
    std::uint64_t max_age_us = 0U;           ///< oldest sample accepted, microseconds
};

/// A command that passed: what the cycle uses.
struct CheckedCommand {
    std::uint8_t monitoring_case = 0U;  ///< the case to apply
    std::uint8_t speed_class = 0U;      ///< the robot's speed class
    JointPositions joints{};            ///< the robot's joints in SI units (count 0 without a robot)
};

/// Checks @p input for the cycle that starts at @p now_us (see the file comment).
[[nodiscard]] Result<CheckedCommand, CommandRefusal> check_command(const CommandInput& input, std::uint64_t now_us,
                                                                   const CommandLimits& limits) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_COMMAND_CHECK_HPP
