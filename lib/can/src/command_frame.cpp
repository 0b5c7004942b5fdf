// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/command_frame.hpp"

#include "frame_protection.hpp"

namespace cellguard {
namespace {

static_assert(command_layout::kCrc.start_bit == safety_layout::kCrc.start_bit &&
                  command_layout::kCounter.start_bit == safety_layout::kCounter.start_bit &&
                  command_layout::kDataIdNibble.start_bit == safety_layout::kDataIdNibble.start_bit,
              "the command parts share the output frames' E2E header layout");

/// Index of part @p part, 0..2.
constexpr std::size_t index_of(CommandPart part) noexcept { return static_cast<std::size_t>(part); }

bool part_valid(CommandPart part) noexcept {
    return part == CommandPart::kA || part == CommandPart::kB || part == CommandPart::kC;
}

/// True when @p a and @p b are distinguishable in @p mode and, if it differs, in @p other_mode too.
bool distinguishable_in(std::uint16_t a, std::uint16_t b, E2eP01DataIdMode mode, E2eP01DataIdMode other_mode) noexcept {
    return e2e_p01_data_ids_distinguishable(a, b, mode) && e2e_p01_data_ids_distinguishable(a, b, other_mode);
}

}  // namespace

Status check_command_channel_config(const CommandChannelConfig& config) noexcept {
    const E2eP01DataIdMode mode = config.data_id_mode;
    if (!e2e_p01_mode_valid(mode) || config.base_can_id + (kCommandFramesPerSample - 1U) > kCanMaxStandardId) {
        return ErrorCode::kInvalidArgument;
    }
    for (std::size_t i = 0U; i < kCommandParts; ++i) {
        if (!e2e_p01_data_id_valid(config.data_id[i], mode)) {
            return ErrorCode::kInvalidArgument;
        }
        for (std::size_t j = i + 1U; j < kCommandParts; ++j) {
            if (!e2e_p01_data_ids_distinguishable(config.data_id[i], config.data_id[j], mode)) {
                return ErrorCode::kInvalidArgument;
            }
        }
    }
    return Status{};
}

Status check_channels_compatible(const SafetyChannelConfig& output, const CommandChannelConfig& command) noexcept {
    if (!check_channel_config(output).ok() || !check_command_channel_config(command).ok()) {
        return ErrorCode::kInvalidArgument;
    }
    const std::uint32_t output_ids[] = {output.safety_can_id, inverted_can_id(output), output.diagnostics_can_id,
                                        output.separation_can_id};
    const std::uint16_t output_data_ids[] = {output.safety_data_id, output.diagnostics_data_id,
                                             output.separation_data_id};
    for (const std::uint32_t id : output_ids) {
        if (id >= command.base_can_id && id < command.base_can_id + kCommandFramesPerSample) {
            return ErrorCode::kInvalidArgument;
        }
    }
    for (const std::uint16_t c : command.data_id) {
        for (const std::uint16_t o : output_data_ids) {
            if (!distinguishable_in(c, o, command.data_id_mode, output.data_id_mode)) {
                return ErrorCode::kInvalidArgument;
            }
        }
    }
    return Status{};
}

bool command_well_formed(const RobotCommand& command) noexcept {
    if (command.monitoring_case >= kMaxMonitoringCases || command.speed_class >= kSpeedClasses ||
        command.joint_count > kMaxCommandJoints) {
        return false;
    }
    for (std::size_t j = 0U; j < kMaxCommandJoints; ++j) {
        const bool used = j < command.joint_count;
        if ((used && command.joint_raw[j] == kJointRawInvalid) || (!used && command.joint_raw[j] != 0)) {
            return false;
        }
    }
    return true;
}

Result<CanFrame> encode_command_part(const RobotCommand& command, CommandPart part, std::uint8_t counter,
                                     const CommandChannelConfig& config) noexcept {
    if (!check_command_channel_config(config).ok() || !part_valid(part) || counter > kE2eP01CounterMax ||
        !command_well_formed(command)) {
        return ErrorCode::kInvalidArgument;
    }
    CanFrame frame = detail::empty_frame(command_can_id(config, part));
    if (part == CommandPart::kA) {
        set_signal(frame, command_layout::kMonitoringCase, command.monitoring_case);
        set_signal(frame, command_layout::kSpeedClass, command.speed_class);
        set_signal(frame, command_layout::kResetRequest, command.reset_request ? 1U : 0U);
        set_signal(frame, command_layout::kJointCount, command.joint_count);
    }
    if (part == CommandPart::kC) {
        set_signal(frame, command_layout::kRobotId, command.robot_id);
    }
    for (std::size_t j = 0U; j < kMaxCommandJoints; ++j) {
        if (part_of_joint(j) == part) {
            set_signed_signal(frame, command_layout::kJoints[j], command.joint_raw[j]);
        }
    }
    detail::protect_frame(frame, counter, config.data_id[index_of(part)], config.data_id_mode);
    return frame;
}

Result<CommandFrames> encode_command_sample(const RobotCommand& command, std::uint8_t counter,
                                            const CommandChannelConfig& config) noexcept {
    CommandFrames frames{};
    for (std::size_t p = 0U; p < kCommandParts; ++p) {
        const Result<CanFrame> frame = encode_command_part(command, static_cast<CommandPart>(p), counter, config);
        if (!frame.ok()) {
            return frame.error();
        }
        frames.frame[2U * p] = frame.value();
        frames.frame[2U * p + 1U] = inverted_copy(frame.value());
    }
    return frames;
}

FrameCheck check_command_part(const CanFrame& frame, CommandPart part, const CommandChannelConfig& config,
                              CommandPartContent& out) noexcept {
    CG_ENFORCE(check_command_channel_config(config).ok() && part_valid(part),
               "check_command_part needs a valid channel config and part");
    const FrameCheck e2e = detail::check_frame_protection(frame, command_can_id(config, part),
                                                          config.data_id[index_of(part)], config.data_id_mode);
    if (e2e != FrameCheck::kOk) {
        return e2e;
    }
    CommandPartContent content;
    content.part = part;
    content.counter = static_cast<std::uint8_t>(get_signal(frame, command_layout::kCounter));
    if (part == CommandPart::kA) {
        if ((frame_bits(frame) & command_layout::kPartAReservedBits) != 0U) {
            return FrameCheck::kMalformedContent;
        }
        content.fields.monitoring_case = static_cast<std::uint8_t>(get_signal(frame, command_layout::kMonitoringCase));
        content.fields.speed_class = static_cast<std::uint8_t>(get_signal(frame, command_layout::kSpeedClass));
        content.fields.reset_request = get_signal(frame, command_layout::kResetRequest) != 0U;
        content.fields.joint_count = static_cast<std::uint8_t>(get_signal(frame, command_layout::kJointCount));
    }
    if (part == CommandPart::kC) {
        content.fields.robot_id = static_cast<std::uint16_t>(get_signal(frame, command_layout::kRobotId));
    }
    for (std::size_t j = 0U; j < kMaxCommandJoints; ++j) {
        if (part_of_joint(j) == part) {
            const std::int32_t raw = get_signed_signal(frame, command_layout::kJoints[j]);
            if (raw == kJointRawInvalid) {
                return FrameCheck::kMalformedContent;
            }
            content.fields.joint_raw[j] = static_cast<std::int16_t>(raw);
        }
    }
    out = content;
    return FrameCheck::kOk;
}

Result<CommandPartContent> decode_command_part(const CanFrame& frame, CommandPart part,
                                               const CommandChannelConfig& config) noexcept {
    CommandPartContent content;
    const FrameCheck check = check_command_part(frame, part, config, content);
    if (check != FrameCheck::kOk) {
        return to_error_code(check);
    }
    return content;
}

void merge_command_part(const CommandPartContent& content, RobotCommand& command) noexcept {
    if (content.part == CommandPart::kA) {
        command.monitoring_case = content.fields.monitoring_case;
        command.speed_class = content.fields.speed_class;
        command.reset_request = content.fields.reset_request;
        command.joint_count = content.fields.joint_count;
    }
    if (content.part == CommandPart::kC) {
        command.robot_id = content.fields.robot_id;
    }
    for (std::size_t j = 0U; j < kMaxCommandJoints; ++j) {
        if (part_of_joint(j) == content.part) {
            command.joint_raw[j] = content.fields.joint_raw[j];
        }
    }
}

}  // namespace cellguard
