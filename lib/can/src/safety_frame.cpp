// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/safety_frame.hpp"

#include "frame_protection.hpp"

namespace cellguard {
namespace {

/// Byte index of the E2E CRC, from the layout table (both frames alike).
constexpr std::size_t kCrcByte = safety_layout::kCrc.start_bit / 8U;
static_assert(safety_layout::kCrc.start_bit % 8U == 0U && safety_layout::kCrc.length == 8U,
              "the E2E CRC is one whole byte");
static_assert(diagnostics_layout::kCrc.start_bit == safety_layout::kCrc.start_bit &&
                  diagnostics_layout::kCounter.start_bit == safety_layout::kCounter.start_bit &&
                  diagnostics_layout::kDataIdNibble.start_bit == safety_layout::kDataIdNibble.start_bit,
              "both frames share the E2E header layout");

Span<const std::uint8_t> payload(const CanFrame& frame) noexcept { return {frame.data, kCanMaxDataLength}; }

/// Mask of the zone bits below @p zone_count (zone_count <= 16).
constexpr std::uint32_t zone_mask(std::uint8_t zone_count) noexcept { return (std::uint32_t{1} << zone_count) - 1U; }

bool safety_message_valid(const SafetyMessage& m) noexcept {
    return m.zone_count <= kMaxZonesInFrame && (m.zone_intrusion & ~zone_mask(m.zone_count)) == 0U &&
           (m.zone_unseen & ~zone_mask(m.zone_count)) == 0U && m.active_case <= kMaxActiveCase;
}

bool diagnostics_message_valid(const DiagnosticsMessage& m) noexcept {
    return m.cycle_time <= kDiagnosticsTimeSaturated && m.max_cycle_time <= kDiagnosticsTimeSaturated &&
           (static_cast<unsigned>(m.active_faults) & ~static_cast<unsigned>(kAssignedFaultBits)) == 0U &&
           m.prior_crc_page < 4U;
}

/// The multiplexed signal that carries prior CRC page @p page.
const SignalLayout& prior_crc_signal(std::uint8_t page) noexcept {
    switch (page) {
        case 0U: return diagnostics_layout::kPriorCrcBits0To7;
        case 1U: return diagnostics_layout::kPriorCrcBits8To15;
        case 2U: return diagnostics_layout::kPriorCrcBits16To23;
        default: return diagnostics_layout::kPriorCrcBits24To31;
    }
}

}  // namespace

namespace detail {

void protect_frame(CanFrame& frame, std::uint8_t counter, std::uint16_t data_id, E2eP01DataIdMode mode) noexcept {
    set_signal(frame, safety_layout::kCounter, counter);
    set_signal(frame, safety_layout::kDataIdNibble,
               mode == E2eP01DataIdMode::kNibble ? e2e_p01_data_id_nibble(data_id) : 0U);
    set_signal(frame, safety_layout::kCrc, e2e_p01_crc(payload(frame), kCrcByte, data_id, mode, counter));
}

FrameCheck check_frame_protection(const CanFrame& frame, std::uint32_t can_id, std::uint16_t data_id,
                                  E2eP01DataIdMode mode) noexcept {
    if (frame.id != can_id) {
        return FrameCheck::kWrongCanId;
    }
    if (frame.dlc != kCanMaxDataLength) {
        return FrameCheck::kWrongLength;
    }
    const std::uint32_t nibble = get_signal(frame, safety_layout::kDataIdNibble);
    const std::uint32_t expected_nibble = mode == E2eP01DataIdMode::kNibble ? e2e_p01_data_id_nibble(data_id) : 0U;
    if (mode == E2eP01DataIdMode::kNibble && nibble != expected_nibble) {
        return FrameCheck::kWrongDataIdNibble;
    }
    const auto counter = static_cast<std::uint8_t>(get_signal(frame, safety_layout::kCounter));
    if (get_signal(frame, safety_layout::kCrc) != e2e_p01_crc(payload(frame), kCrcByte, data_id, mode, counter)) {
        return FrameCheck::kWrongCrc;
    }
    if (counter > kE2eP01CounterMax) {
        return FrameCheck::kCounterOutOfRange;
    }
    if (nibble != expected_nibble) {
        return FrameCheck::kMalformedContent;  // the nibble bits are reserved outside kNibble mode
    }
    return FrameCheck::kOk;
}

}  // namespace detail

Status check_channel_config(const SafetyChannelConfig& config) noexcept {
    const E2eP01DataIdMode mode = config.data_id_mode;
    if (!e2e_p01_mode_valid(mode)) {
        return ErrorCode::kInvalidArgument;
    }
    const std::uint32_t ids[] = {config.safety_can_id, inverted_can_id(config), config.diagnostics_can_id,
                                 config.separation_can_id};
    const std::uint16_t data_ids[] = {config.safety_data_id, config.diagnostics_data_id, config.separation_data_id};
    if (config.safety_can_id >= kCanMaxStandardId || config.diagnostics_can_id > kCanMaxStandardId ||
        config.separation_can_id > kCanMaxStandardId) {
        return ErrorCode::kInvalidArgument;
    }
    for (std::size_t i = 0U; i < 4U; ++i) {
        for (std::size_t j = i + 1U; j < 4U; ++j) {
            if (ids[i] == ids[j]) {
                return ErrorCode::kInvalidArgument;
            }
        }
    }
    for (std::size_t i = 0U; i < 3U; ++i) {
        if (!e2e_p01_data_id_valid(data_ids[i], mode)) {
            return ErrorCode::kInvalidArgument;
        }
        for (std::size_t j = i + 1U; j < 3U; ++j) {
            if (!e2e_p01_data_ids_distinguishable(data_ids[i], data_ids[j], mode)) {
                return ErrorCode::kInvalidArgument;
            }
        }
    }
    return Status{};
}

const char* to_string(FrameCheck check) noexcept {
    switch (check) {
        case FrameCheck::kOk: return "ok";
        case FrameCheck::kWrongCanId: return "wrong CAN ID";
        case FrameCheck::kWrongLength: return "wrong length";
        case FrameCheck::kWrongDataIdNibble: return "wrong data ID nibble";
        case FrameCheck::kWrongCrc: return "wrong CRC";
        case FrameCheck::kCounterOutOfRange: return "counter out of range";
        case FrameCheck::kMalformedContent: return "malformed content";
    }
    return "unknown frame check";
}

ErrorCode to_error_code(FrameCheck check) noexcept {
    switch (check) {
        case FrameCheck::kOk: return ErrorCode::kOk;
        case FrameCheck::kWrongLength: return ErrorCode::kTruncatedInput;
        case FrameCheck::kWrongDataIdNibble:
        case FrameCheck::kWrongCrc: return ErrorCode::kCrcMismatch;
        case FrameCheck::kWrongCanId:
        case FrameCheck::kCounterOutOfRange:
        case FrameCheck::kMalformedContent: return ErrorCode::kMalformedInput;
    }
    return ErrorCode::kMalformedInput;
}

Result<CanFrame> encode_safety_frame(const SafetyMessage& message, std::uint8_t counter,
                                     const SafetyChannelConfig& config) noexcept {
    if (!check_channel_config(config).ok() || counter > kE2eP01CounterMax || !safety_message_valid(message)) {
        return ErrorCode::kInvalidArgument;
    }
    CanFrame frame = detail::empty_frame(config.safety_can_id);
    set_signal(frame, safety_layout::kProtectiveStop, message.protective_stop ? 1U : 0U);
    set_signal(frame, safety_layout::kWarning, message.warning ? 1U : 0U);
    set_signal(frame, safety_layout::kFault, message.fault ? 1U : 0U);
    set_signal(frame, safety_layout::kActiveCase, message.active_case);
    set_signal(frame, safety_layout::kReducedSpeed, message.reduced_speed ? 1U : 0U);
    set_signal(frame, safety_layout::kZoneIntrusion, message.zone_intrusion);
    set_signal(frame, safety_layout::kZoneUnseen, message.zone_unseen);
    set_signal(frame, safety_layout::kZoneCount, message.zone_count);
    detail::protect_frame(frame, counter, config.safety_data_id, config.data_id_mode);
    return frame;
}

CanFrame inverted_copy(const CanFrame& frame) noexcept {
    CanFrame copy = frame;
    copy.id = frame.id + 1U;
    for (std::uint8_t& byte : copy.data) {
        byte = static_cast<std::uint8_t>(~byte);
    }
    return copy;
}

Result<CanFrame> encode_diagnostics_frame(const DiagnosticsMessage& message, std::uint8_t counter,
                                          const SafetyChannelConfig& config) noexcept {
    if (!check_channel_config(config).ok() || counter > kE2eP01CounterMax || !diagnostics_message_valid(message)) {
        return ErrorCode::kInvalidArgument;
    }
    CanFrame frame = detail::empty_frame(config.diagnostics_can_id);
    set_signal(frame, diagnostics_layout::kActiveFaults, message.active_faults);
    set_signal(frame, diagnostics_layout::kCycleTime, message.cycle_time);
    set_signal(frame, diagnostics_layout::kMaxCycleTime, message.max_cycle_time);
    set_signal(frame, diagnostics_layout::kPriorCrcPage, message.prior_crc_page);
    set_signal(frame, prior_crc_signal(message.prior_crc_page), message.prior_crc_part);
    detail::protect_frame(frame, counter, config.diagnostics_data_id, config.data_id_mode);
    return frame;
}

FrameCheck check_safety_frame(const CanFrame& frame, const SafetyChannelConfig& config,
                              SafetyFrameContent& out) noexcept {
    CG_ENFORCE(check_channel_config(config).ok(), "check_safety_frame needs a valid channel config");
    const FrameCheck e2e = detail::check_frame_protection(frame, config.safety_can_id, config.safety_data_id,
                                                          config.data_id_mode);
    if (e2e != FrameCheck::kOk) {
        return e2e;
    }
    if ((frame_bits(frame) & safety_layout::kReservedBits) != 0U) {
        return FrameCheck::kMalformedContent;
    }
    SafetyFrameContent content;
    content.counter = static_cast<std::uint8_t>(get_signal(frame, safety_layout::kCounter));
    content.message.protective_stop = get_signal(frame, safety_layout::kProtectiveStop) != 0U;
    content.message.warning = get_signal(frame, safety_layout::kWarning) != 0U;
    content.message.fault = get_signal(frame, safety_layout::kFault) != 0U;
    content.message.active_case = static_cast<std::uint8_t>(get_signal(frame, safety_layout::kActiveCase));
    content.message.reduced_speed = get_signal(frame, safety_layout::kReducedSpeed) != 0U;
    content.message.zone_intrusion = static_cast<std::uint16_t>(get_signal(frame, safety_layout::kZoneIntrusion));
    content.message.zone_unseen = static_cast<std::uint16_t>(get_signal(frame, safety_layout::kZoneUnseen));
    const std::uint32_t zone_count = get_signal(frame, safety_layout::kZoneCount);
    if (zone_count > kMaxZonesInFrame) {
        return FrameCheck::kMalformedContent;
    }
    content.message.zone_count = static_cast<std::uint8_t>(zone_count);
    if (!safety_message_valid(content.message)) {
        return FrameCheck::kMalformedContent;
    }
    out = content;
    return FrameCheck::kOk;
}

Result<SafetyFrameContent> decode_safety_frame(const CanFrame& frame, const SafetyChannelConfig& config) noexcept {
    SafetyFrameContent content;
    const FrameCheck check = check_safety_frame(frame, config, content);
    if (check != FrameCheck::kOk) {
        return to_error_code(check);
    }
    return content;
}

FrameCheck check_diagnostics_frame(const CanFrame& frame, const SafetyChannelConfig& config,
                                   DiagnosticsFrameContent& out) noexcept {
    CG_ENFORCE(check_channel_config(config).ok(), "check_diagnostics_frame needs a valid channel config");
    const FrameCheck e2e = detail::check_frame_protection(frame, config.diagnostics_can_id, config.diagnostics_data_id,
                                                          config.data_id_mode);
    if (e2e != FrameCheck::kOk) {
        return e2e;
    }
    DiagnosticsFrameContent content;
    content.counter = static_cast<std::uint8_t>(get_signal(frame, diagnostics_layout::kCounter));
    content.message.active_faults = static_cast<std::uint16_t>(get_signal(frame, diagnostics_layout::kActiveFaults));
    content.message.cycle_time = static_cast<std::uint16_t>(get_signal(frame, diagnostics_layout::kCycleTime));
    content.message.max_cycle_time = static_cast<std::uint16_t>(get_signal(frame, diagnostics_layout::kMaxCycleTime));
    content.message.prior_crc_page = static_cast<std::uint8_t>(get_signal(frame, diagnostics_layout::kPriorCrcPage));
    content.message.prior_crc_part = static_cast<std::uint8_t>(
        get_signal(frame, prior_crc_signal(content.message.prior_crc_page)));
    if (!diagnostics_message_valid(content.message)) {
        return FrameCheck::kMalformedContent;
    }
    out = content;
    return FrameCheck::kOk;
}

Result<DiagnosticsFrameContent> decode_diagnostics_frame(const CanFrame& frame,
                                                         const SafetyChannelConfig& config) noexcept {
    DiagnosticsFrameContent content;
    const FrameCheck check = check_diagnostics_frame(frame, config, content);
    if (check != FrameCheck::kOk) {
        return to_error_code(check);
    }
    return content;
}

}  // namespace cellguard
