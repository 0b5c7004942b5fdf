// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file command_frame.hpp
/// The command message from the PLC to the controller: its three parts, their
/// bit layout, the encoder of one sample and the check of each frame.
///
/// One sample (a RobotCommand, robot_command.hpp) travels in six classic CAN
/// frames of 8 data bytes, sent in this order:
///   A (base ID), A' (base + 1), B (base + 2), B' (base + 3), C (base + 4), C' (base + 5)
/// with base 0x0C1 by default. A' B' C' are the inverted copies of A B C (every
/// data bit inverted, as the safety frame's copy; EN 50325-5 SRDO style).
/// Each part is protected by AUTOSAR E2E Profile 1 (CRC byte 0, counter bits
/// 8..11, data ID nibble bits 12..15, as the output frames) with its own data
/// ID; all six frames of one sample carry the same counter, which binds the
/// parts of a sample together. The counter advances by one per sample.
///
/// - Part A: MonitoringCase (4 bits), SpeedClass (2), ResetRequest (1), JointCount (3), Joint0, Joint1.
///   ResetRequest (bit 22, protocol 0.2; reserved and 0 before) is the level of the
///   PLC's reset button, which the controller uses for its restart interlock.
/// - Part B: Joint2, Joint3, Joint4.
/// - Part C: Joint5, Joint6, RobotId (the low 16 bits of the robot image CRC).
/// Joints are signed 16-bit raw values in the units of robot_command.hpp
/// (revolute 0.2 mrad, prismatic 0.1 mm); -32768 (kJointRawInvalid) is never
/// sent, joints at and above JointCount are 0.
///
/// The layout tables below are the one statement of the bit positions;
/// certification/cellguard.dbc states the same (tests/unit/test_dbc.cpp).
/// The codec checks the frame alone; what a sample means for the cell (case
/// count, joint count and limits, robot ID) the controller checks.
#ifndef CELLGUARD_CAN_COMMAND_FRAME_HPP
#define CELLGUARD_CAN_COMMAND_FRAME_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/e2e_crc.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Layouts of the three command parts (Intel; joints signed, the rest unsigned).
namespace command_layout {
/// E2E Profile 1 CRC (byte 0), every part.
inline constexpr SignalLayout kCrc{"E2E_Crc", 0U, 8U, ByteOrder::kIntel, 1U, "", 255U, Multiplex::kNone, 0U};
/// E2E Profile 1 counter, 0..14: the sample's counter, the same in all six frames.
inline constexpr SignalLayout kCounter{"E2E_Counter", 8U, 4U, ByteOrder::kIntel, 1U, "", 14U, Multiplex::kNone, 0U};
/// Data ID bits 8..11 in kNibble mode, else 0.
inline constexpr SignalLayout kDataIdNibble{"E2E_DataIdNibble", 12U, 4U, ByteOrder::kIntel, 1U, "", 15U,
                                            Multiplex::kNone,   0U};
/// Part A: monitoring case to apply, 0..15.
inline constexpr SignalLayout kMonitoringCase{"MonitoringCase", 16U, 4U, ByteOrder::kIntel, 1U, "", 15U,
                                              Multiplex::kNone, 0U};
/// Part A: the robot's current speed class, 0..3.
inline constexpr SignalLayout kSpeedClass{"SpeedClass", 20U, 2U, ByteOrder::kIntel, 1U, "", 3U, Multiplex::kNone, 0U};
/// Part A: the PLC's reset button is pressed, 0..1 (the level; bit 22 was reserved before protocol 0.2).
inline constexpr SignalLayout kResetRequest{"ResetRequest",   22U, 1U, ByteOrder::kIntel, 1U, "", 1U,
                                            Multiplex::kNone, 0U};
/// Part A: joints carried, 0..7.
inline constexpr SignalLayout kJointCount{"JointCount", 24U, 3U, ByteOrder::kIntel, 1U, "", 7U, Multiplex::kNone, 0U};
/// A joint position: signed 16 bits, raw -32767..32767 (robot_command.hpp units).
constexpr SignalLayout joint_signal(const char* name, std::uint8_t start_bit) noexcept {
    return SignalLayout{name, start_bit, 16U, ByteOrder::kIntel, 1U, "", 32767U, Multiplex::kNone, 0U, true};
}
/// Part A: joint 0.
inline constexpr SignalLayout kJoint0 = joint_signal("Joint0", 32U);
/// Part A: joint 1.
inline constexpr SignalLayout kJoint1 = joint_signal("Joint1", 48U);
/// Part B: joint 2.
inline constexpr SignalLayout kJoint2 = joint_signal("Joint2", 16U);
/// Part B: joint 3.
inline constexpr SignalLayout kJoint3 = joint_signal("Joint3", 32U);
/// Part B: joint 4.
inline constexpr SignalLayout kJoint4 = joint_signal("Joint4", 48U);
/// Part C: joint 5.
inline constexpr SignalLayout kJoint5 = joint_signal("Joint5", 16U);
/// Part C: joint 6.
inline constexpr SignalLayout kJoint6 = joint_signal("Joint6", 32U);
/// Part C: low 16 bits of the CRC-32 of the robot image the PLC was commissioned with.
inline constexpr SignalLayout kRobotId{"RobotId", 48U, 16U, ByteOrder::kIntel, 1U, "", 65535U, Multiplex::kNone, 0U};

/// Every signal of part A (and, with inverted raw values, of its copy).
inline constexpr SignalLayout kPartASignals[] = {
    kCrc, kCounter, kDataIdNibble, kMonitoringCase, kSpeedClass, kResetRequest, kJointCount, kJoint0, kJoint1};
/// Every signal of part B.
inline constexpr SignalLayout kPartBSignals[] = {kCrc, kCounter, kDataIdNibble, kJoint2, kJoint3, kJoint4};
/// Every signal of part C.
inline constexpr SignalLayout kPartCSignals[] = {kCrc, kCounter, kDataIdNibble, kJoint5, kJoint6, kRobotId};
static_assert(layout_is_consistent(kPartASignals) && layout_is_consistent(kPartBSignals) &&
                  layout_is_consistent(kPartCSignals),
              "command part layout overlaps or overflows");
/// Reserved bits of part A (must be zero): 23 and 27..31, room for later fields.
inline constexpr std::uint64_t kPartAReservedBits = ~layout_used_bits(kPartASignals);
static_assert(kPartAReservedBits == 0x0000'0000'F880'0000ULL, "part A reserves bits 23 and 27..31");
static_assert(layout_used_bits(kPartBSignals) == ~std::uint64_t{0} &&
                  layout_used_bits(kPartCSignals) == ~std::uint64_t{0},
              "parts B and C use every bit");
/// The signal of joint j (0..6), in joint order.
inline constexpr SignalLayout kJoints[kMaxCommandJoints] = {kJoint0, kJoint1, kJoint2, kJoint3,
                                                            kJoint4, kJoint5, kJoint6};
}  // namespace command_layout

/// The three parts of a command sample.
enum class CommandPart : std::uint8_t {
    kA = 0,  ///< case, speed class, reset request, joint count, joints 0 and 1
    kB = 1,  ///< joints 2..4
    kC = 2,  ///< joints 5 and 6, robot ID
};
/// Number of parts of a sample.
constexpr std::size_t kCommandParts = 3U;
/// Frames of a sample: each part and its inverted copy.
constexpr std::size_t kCommandFramesPerSample = 6U;
/// The part that carries joint @p joint (0..6, a contract).
[[nodiscard]] constexpr CommandPart part_of_joint(std::size_t joint) noexcept {
    return joint < 2U ? CommandPart::kA : (joint < 5U ? CommandPart::kB : CommandPart::kC);
}

/// Default CAN ID of part A; the six frames use this ID and the next five.
constexpr std::uint32_t kDefaultCommandBaseCanId = 0x0C1U;
/// Default data IDs of parts A, B and C: distinguishable from each other and
/// from the output frames' defaults in every data ID mode (tested).
constexpr std::uint16_t kDefaultCommandDataIdA = 0x0761U;
/// Default data ID of part B.
constexpr std::uint16_t kDefaultCommandDataIdB = 0x0862U;
/// Default data ID of part C.
constexpr std::uint16_t kDefaultCommandDataIdC = 0x0963U;

/// Identifiers shared by the PLC-side sender and the controller's receiver.
struct CommandChannelConfig {
    std::uint32_t base_can_id = kDefaultCommandBaseCanId;  ///< part A; A' +1, B +2, B' +3, C +4, C' +5 (11-bit)
    std::uint16_t data_id[kCommandParts] = {kDefaultCommandDataIdA, kDefaultCommandDataIdB,
                                            kDefaultCommandDataIdC};  ///< E2E data ID of parts A, B, C
    E2eP01DataIdMode data_id_mode = E2eP01DataIdMode::kBoth;          ///< how the data IDs enter the CRC
};

/// Checks @p config: valid mode, base_can_id + 5 within 11 bits, data IDs
/// valid for the mode and pairwise distinguishable. kInvalidArgument if not.
[[nodiscard]] Status check_command_channel_config(const CommandChannelConfig& config) noexcept;
/// Checks that a controller's output channel and command channel can share a
/// bus: both valid, no CAN ID in common, and every command data ID
/// distinguishable from every output data ID in both data ID modes. kInvalidArgument if not.
[[nodiscard]] Status check_channels_compatible(const SafetyChannelConfig& output,
                                               const CommandChannelConfig& command) noexcept;

/// CAN ID of part @p part.
[[nodiscard]] constexpr std::uint32_t command_can_id(const CommandChannelConfig& config, CommandPart part) noexcept {
    return config.base_can_id + 2U * static_cast<std::uint32_t>(part);
}
/// CAN ID of the inverted copy of part @p part.
[[nodiscard]] constexpr std::uint32_t command_copy_can_id(const CommandChannelConfig& config,
                                                          CommandPart part) noexcept {
    return command_can_id(config, part) + 1U;
}

/// True when @p command can be sent: case 0..15, speed class 0..3, joint count
/// 0..7, no used joint at kJointRawInvalid and every unused joint 0.
[[nodiscard]] bool command_well_formed(const RobotCommand& command) noexcept;

/// The six frames of one sample, in sending order: A, A', B, B', C, C'.
struct CommandFrames {
    CanFrame frame[kCommandFramesPerSample];  ///< the frames
};

/// The protected frame of part @p part of @p command with counter @p counter.
/// kInvalidArgument when the config is invalid, the counter > 14 or the command is not well formed.
[[nodiscard]] Result<CanFrame> encode_command_part(const RobotCommand& command, CommandPart part, std::uint8_t counter,
                                                   const CommandChannelConfig& config) noexcept;
/// The six frames of one sample (all with counter @p counter); errors as encode_command_part.
[[nodiscard]] Result<CommandFrames> encode_command_sample(const RobotCommand& command, std::uint8_t counter,
                                                          const CommandChannelConfig& config) noexcept;

/// A checked part: its counter and the fields it carries (the others 0).
struct CommandPartContent {
    CommandPart part = CommandPart::kA;  ///< which part
    std::uint8_t counter = 0U;           ///< its E2E counter, 0..14
    RobotCommand fields{};               ///< the part's fields; fields of other parts are 0
};

/// Checks @p frame as part @p part of @p config: CAN ID, DLC 8, data ID
/// nibble, CRC, counter range, reserved bits, no joint at kJointRawInvalid;
/// on kOk writes @p out (untouched otherwise). @p config must be valid (contract).
[[nodiscard]] FrameCheck check_command_part(const CanFrame& frame, CommandPart part, const CommandChannelConfig& config,
                                            CommandPartContent& out) noexcept;
/// Same as check_command_part, as a Result (error from to_error_code).
[[nodiscard]] Result<CommandPartContent> decode_command_part(const CanFrame& frame, CommandPart part,
                                                             const CommandChannelConfig& config) noexcept;
/// Copies the fields part @p content carries into @p command (the others stay).
void merge_command_part(const CommandPartContent& content, RobotCommand& command) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_CAN_COMMAND_FRAME_HPP
