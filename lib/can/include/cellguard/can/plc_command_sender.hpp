// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file plc_command_sender.hpp
/// The PLC side of the command message (command_frame.hpp): code to port to
/// the robot PLC, beside the PLC-side receiver of the safety output
/// (plc_receiver.hpp). Portable C++17, fixed size, no heap, no OS calls.
///
/// Each PLC send cycle, the PLC application fills a RobotCommand (the
/// monitoring case it wants, the robot's speed class, the joint positions
/// from the robot controller in robot_command.hpp units, the commissioned
/// robot ID) and calls next_sample(); it sends the six frames it gets, in
/// their order (A, A', B, B', C, C'), back to back on the bus. The sender
/// holds the E2E counter: one value per sample, the same in all six frames,
/// +1 per sample, wrapping 14 -> 0. A command that is not well formed is
/// refused and the counter does not advance; the PLC then sends nothing, and
/// the controller's receiver stops the robot when its SCT runs out.
///
/// Protocol 0.2 (session_link.hpp): next_sample(command, link, channel) adds
/// the PLC's link frame after C' (counter the sample's, CRC bound to parts
/// A, B and C), with the fields the PLC's receiver gives
/// (PlcReceiver::next_link at the sending time): seven frames a sample.
///
/// The PLC should send a sample at least every sct_us / 2 of the controller's
/// receiver (every 50 ms with the defaults), and check the safety frame's
/// ActiveCase echo against the case it asked for.
#ifndef CELLGUARD_CAN_PLC_COMMAND_SENDER_HPP
#define CELLGUARD_CAN_PLC_COMMAND_SENDER_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/command_frame.hpp"
#include "cellguard/can/session_link.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// The seven frames of a protocol 0.2 sample: A, A', B, B', C, C', then the link frame.
struct LinkedCommandFrames {
    CommandFrames sample;  ///< A, A', B, B', C, C'
    CanFrame link;         ///< the PLC's link frame, sent last
};

/// Turns RobotCommands into the six frames of successive samples.
class PlcCommandSender {
public:
    /// kInvalidArgument unless @p config passes check_command_channel_config.
    [[nodiscard]] static Status check_config(const CommandChannelConfig& config) noexcept;

    /// A sender whose first sample carries counter 0. @p config must pass check_config (contract).
    explicit PlcCommandSender(const CommandChannelConfig& config) noexcept;

    /// The six frames of the next sample for @p command, in sending order,
    /// and the counter advanced; kInvalidArgument (counter unchanged) when
    /// @p command is not well formed (command_well_formed).
    [[nodiscard]] Result<CommandFrames> next_sample(const RobotCommand& command) noexcept;

    /// The seven frames of the next sample: the six above and the link frame
    /// for @p link on @p channel; kInvalidArgument (counter unchanged) when
    /// the command is not well formed or the link fields or channel are invalid.
    [[nodiscard]] Result<LinkedCommandFrames> next_sample(const RobotCommand& command, const LinkFields& link,
                                                          const LinkChannel& channel) noexcept;

    /// Counter the next sample will carry, 0..14.
    [[nodiscard]] std::uint8_t counter() const noexcept { return counter_; }
    /// The configuration in use.
    [[nodiscard]] const CommandChannelConfig& config() const noexcept { return config_; }

private:
    CommandChannelConfig config_;
    std::uint8_t counter_ = 0U;
};

}  // namespace cellguard

#endif  // CELLGUARD_CAN_PLC_COMMAND_SENDER_HPP
