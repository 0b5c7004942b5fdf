// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_command.hpp
/// What the PLC tells the controller every cycle (the command message of
/// certification/can-safety-protocol.md): the monitoring case to apply, the
/// robot's speed class, its joint positions and the reset button; and what the controller
/// answers about the robot (the speed request). A small interface header:
/// the CAN command codec and the PLC-side sender use it without the grid.
///
/// Joint positions travel as signed 16-bit raw values: revolute joints in
/// units of kRevoluteJointUnitRad (0.2 mrad, range +-6.5534 rad, so +-2 pi
/// fits), prismatic joints in units of kPrismaticJointUnitM (0.1 mm, range
/// +-3.2767 m). The raw value kJointRawInvalid (-32768) is reserved: it is
/// never a valid position, so an all-ones or all-zeros fault pattern of a
/// sender is not silently a pose.
#ifndef CELLGUARD_SAFETY_ROBOT_COMMAND_HPP
#define CELLGUARD_SAFETY_ROBOT_COMMAND_HPP

#include <cstddef>
#include <cstdint>

namespace cellguard {

/// Most joint positions one command carries (a 7-axis arm).
constexpr std::size_t kMaxCommandJoints = 7U;
/// Most monitoring cases (zone sets) a configuration commissions; case numbers are 0..15.
constexpr std::uint8_t kMaxMonitoringCases = 16U;
/// Speed classes the command can report, 0..3 (their limits are commissioned).
constexpr std::uint8_t kSpeedClasses = 4U;
/// Raw unit of a revolute joint position, radians.
constexpr double kRevoluteJointUnitRad = 0.0002;
/// Raw unit of a prismatic joint position, metres.
constexpr double kPrismaticJointUnitM = 0.0001;
/// Reserved raw joint value: never a valid position.
constexpr std::int16_t kJointRawInvalid = -32768;

/// One sample of the PLC's command message, as decoded (not yet checked
/// against the commissioned cell: the controller does that).
struct RobotCommand {
    std::uint8_t monitoring_case = 0U;  ///< case to apply, 0..15
    std::uint8_t speed_class = 0U;      ///< the robot's current speed class, 0..3
    std::uint8_t joint_count = 0U;      ///< joints carried, 0..kMaxCommandJoints
    std::uint16_t robot_id = 0U;        ///< low 16 bits of the robot image CRC the PLC was commissioned with
    std::int16_t joint_raw[kMaxCommandJoints] = {};  ///< positions in joint units; unused entries 0
    /// The PLC's reset button is pressed (the level; the controller takes a
    /// rising edge between two valid samples as the restart interlock's reset).
    bool reset_request = false;
    /// Field-wise equality (unused joints included).
    friend constexpr bool operator==(const RobotCommand& a, const RobotCommand& b) noexcept {
        if (a.monitoring_case != b.monitoring_case || a.speed_class != b.speed_class ||
            a.joint_count != b.joint_count || a.robot_id != b.robot_id || a.reset_request != b.reset_request) {
            return false;
        }
        for (std::size_t j = 0U; j < kMaxCommandJoints; ++j) {
            if (a.joint_raw[j] != b.joint_raw[j]) {
                return false;
            }
        }
        return true;
    }
    /// Field-wise inequality.
    friend constexpr bool operator!=(const RobotCommand& a, const RobotCommand& b) noexcept { return !(a == b); }
};

/// The command side of one cycle, as the receiver hands it to the controller.
struct CommandInput {
    bool valid = false;              ///< the receiver holds a good, complete, timely sample
    RobotCommand command{};          ///< that sample (meaningless when !valid)
    std::uint8_t counter = 0U;       ///< its E2E counter, 0..14
    std::uint64_t received_us = 0U;  ///< when its last frame arrived, on the controller's clock
};

/// What the controller requests of the robot's speed. Values appear on CAN: append only.
enum class SpeedRequest : std::uint8_t {
    kFull = 0,            ///< no limit from speed and separation monitoring
    kReduced = 1,         ///< move at the reduced speed class
    kProtectiveStop = 2,  ///< stop (also the ProtectiveStop bit)
};

/// Static name of a speed request ("FULL", "REDUCED", "STOP").
[[nodiscard]] const char* to_string(SpeedRequest request) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_ROBOT_COMMAND_HPP
