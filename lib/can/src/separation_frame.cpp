// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/separation_frame.hpp"

#include "frame_protection.hpp"

namespace cellguard {
namespace {

static_assert(separation_layout::kCrc.start_bit == safety_layout::kCrc.start_bit &&
                  separation_layout::kCounter.start_bit == safety_layout::kCounter.start_bit &&
                  separation_layout::kDataIdNibble.start_bit == safety_layout::kDataIdNibble.start_bit,
              "the separation frame shares the E2E header layout");

bool separation_message_valid(const SeparationMessage& m) noexcept {
    return m.active_case <= kMaxActiveCase && static_cast<unsigned>(m.speed_request) <= 2U &&
           m.command_counter <= kE2eP01CounterMax;
}

}  // namespace

Result<CanFrame> encode_separation_frame(const SeparationMessage& message, std::uint8_t counter,
                                         const SafetyChannelConfig& config) noexcept {
    if (!check_channel_config(config).ok() || counter > kE2eP01CounterMax || !separation_message_valid(message)) {
        return ErrorCode::kInvalidArgument;
    }
    CanFrame frame = detail::empty_frame(config.separation_can_id);
    set_signal(frame, separation_layout::kSeparationDistance, message.distance_mm);
    set_signal(frame, separation_layout::kRequiredDistance, message.required_mm);
    set_signal(frame, separation_layout::kActiveCase, message.active_case);
    set_signal(frame, separation_layout::kSpeedRequest, static_cast<std::uint32_t>(message.speed_request));
    set_signal(frame, separation_layout::kCommandValid, message.command_valid ? 1U : 0U);
    set_signal(frame, separation_layout::kCommandCounter, message.command_counter);
    detail::protect_frame(frame, counter, config.separation_data_id, config.data_id_mode);
    return frame;
}

FrameCheck check_separation_frame(const CanFrame& frame, const SafetyChannelConfig& config,
                                  SeparationFrameContent& out) noexcept {
    CG_ENFORCE(check_channel_config(config).ok(), "check_separation_frame needs a valid channel config");
    const FrameCheck e2e = detail::check_frame_protection(frame, config.separation_can_id, config.separation_data_id,
                                                          config.data_id_mode);
    if (e2e != FrameCheck::kOk) {
        return e2e;
    }
    if ((frame_bits(frame) & separation_layout::kReservedBits) != 0U) {
        return FrameCheck::kMalformedContent;
    }
    const std::uint32_t request = get_signal(frame, separation_layout::kSpeedRequest);
    const std::uint32_t command_counter = get_signal(frame, separation_layout::kCommandCounter);
    if (request > 2U || command_counter > kE2eP01CounterMax) {
        return FrameCheck::kMalformedContent;
    }
    SeparationFrameContent content;
    content.counter = static_cast<std::uint8_t>(get_signal(frame, separation_layout::kCounter));
    content.message.distance_mm = static_cast<std::uint16_t>(get_signal(frame, separation_layout::kSeparationDistance));
    content.message.required_mm = static_cast<std::uint16_t>(get_signal(frame, separation_layout::kRequiredDistance));
    content.message.active_case = static_cast<std::uint8_t>(get_signal(frame, separation_layout::kActiveCase));
    content.message.speed_request = static_cast<SpeedRequest>(request);
    content.message.command_valid = get_signal(frame, separation_layout::kCommandValid) != 0U;
    content.message.command_counter = static_cast<std::uint8_t>(command_counter);
    out = content;
    return FrameCheck::kOk;
}

Result<SeparationFrameContent> decode_separation_frame(const CanFrame& frame,
                                                       const SafetyChannelConfig& config) noexcept {
    SeparationFrameContent content;
    const FrameCheck check = check_separation_frame(frame, config, content);
    if (check != FrameCheck::kOk) {
        return to_error_code(check);
    }
    return content;
}

}  // namespace cellguard
