// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/plc_command_sender.hpp"

namespace cellguard {

Status PlcCommandSender::check_config(const CommandChannelConfig& config) noexcept {
    return check_command_channel_config(config);
}

PlcCommandSender::PlcCommandSender(const CommandChannelConfig& config) noexcept : config_(config) {
    CG_ENFORCE(check_config(config).ok(), "PlcCommandSender needs a configuration that passes check_config");
}

Result<CommandFrames> PlcCommandSender::next_sample(const RobotCommand& command) noexcept {
    Result<CommandFrames> frames = encode_command_sample(command, counter_, config_);
    if (frames.ok()) {
        counter_ = e2e_p01_next_counter(counter_);
    }
    return frames;
}

Result<LinkedCommandFrames> PlcCommandSender::next_sample(const RobotCommand& command, const LinkFields& link,
                                                          const LinkChannel& channel) noexcept {
    const Result<CommandFrames> frames = encode_command_sample(command, counter_, config_);
    if (!frames.ok()) {
        return frames.error();
    }
    const CanFrame parts[kCommandParts] = {frames.value().frame[0], frames.value().frame[2], frames.value().frame[4]};
    const Result<CanFrame> link_frame = encode_link_frame(link, counter_, channel, Span<const CanFrame>(parts));
    if (!link_frame.ok()) {
        return link_frame.error();
    }
    counter_ = e2e_p01_next_counter(counter_);
    return LinkedCommandFrames{frames.value(), link_frame.value()};
}

}  // namespace cellguard
