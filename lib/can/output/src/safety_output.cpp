// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/safety_output.hpp"

namespace cellguard {
namespace {

/// The encoder's config: the given one when valid, else a valid placeholder (never used to send).
SafetyOutputConfig usable_config(const SafetyOutputConfig& config) noexcept {
    return check_safety_output_config(config).ok() ? config : SafetyOutputConfig{};
}

}  // namespace

Status check_safety_output_config(const SafetyOutputConfig& config) noexcept {
    if (!check_channel_config(config.channel).ok()) {
        return ErrorCode::kInvalidArgument;
    }
    if (config.zone_count > kMaxZonesInFrame) {
        return ErrorCode::kCapacityExceeded;
    }
    return Status{};
}

SafetyMessage safety_message(const SafetyOutputs& outputs, std::uint8_t zone_count) noexcept {
    CG_ENFORCE(zone_count <= kMaxZonesInFrame, "a safety frame carries at most 16 zones");
    const std::uint32_t mask = (std::uint32_t{1} << zone_count) - 1U;
    SafetyMessage m;
    m.protective_stop = outputs.stop_requested;
    m.warning = outputs.warning;
    m.fault = outputs.latched_faults != 0U;
    m.zone_intrusion = static_cast<std::uint16_t>(outputs.intruded_mask & mask);
    m.zone_unseen = static_cast<std::uint16_t>(outputs.unseen_mask & mask);
    m.zone_count = zone_count;
    return m;
}

SafetyMessage safety_message(const SafetyOutputs& outputs, const RobotReport& robot, std::uint8_t zone_count) noexcept {
    CG_ENFORCE(robot.active_case <= kMaxActiveCase, "a safety frame carries cases 0..15");
    SafetyMessage m = safety_message(outputs, zone_count);
    m.protective_stop = m.protective_stop || robot.speed_request == SpeedRequest::kProtectiveStop;
    m.active_case = robot.active_case;
    m.reduced_speed = robot.speed_request == SpeedRequest::kReduced;
    return m;
}

SeparationMessage separation_message(const RobotReport& robot) noexcept {
    CG_ENFORCE(robot.active_case <= kMaxActiveCase && robot.command_counter <= kE2eP01CounterMax,
               "case 0..15 and an E2E command counter 0..14");
    SeparationMessage m;
    m.distance_mm = robot.distance_mm;
    m.required_mm = robot.required_mm;
    m.active_case = robot.active_case;
    const bool known = robot.speed_request == SpeedRequest::kFull || robot.speed_request == SpeedRequest::kReduced;
    m.speed_request = known ? robot.speed_request : SpeedRequest::kProtectiveStop;
    m.command_valid = robot.command_valid;
    m.command_counter = robot.command_counter;
    return m;
}

DiagnosticsMessage diagnostics_message(const CycleReport& report, std::uint8_t page, std::uint32_t prior_crc,
                                       std::uint16_t can_detail_faults) noexcept {
    DiagnosticsMessage m;
    m.cycle_time = diagnostics_time_saturating(report.timing.total_us);
    m.max_cycle_time = diagnostics_time_saturating(report.worst.total_us);
    m.active_faults = static_cast<std::uint16_t>(wire_fault_bits(report.safety.latched_faults) |
                                                 (static_cast<unsigned>(can_detail_faults) & kCanDetailFaultBits));
    m.prior_crc_page = page;
    m.prior_crc_part = prior_crc_part(prior_crc, page);
    return m;
}

CycleFrameEncoder::CycleFrameEncoder(const SafetyOutputConfig& config) noexcept : config_(config) {
    CG_ENFORCE(check_safety_output_config(config).ok(), "CycleFrameEncoder needs a valid configuration");
}

CycleFrames CycleFrameEncoder::encode(const CycleReport& report, std::uint16_t can_detail_faults,
                                      LinkEndpoint* link) noexcept {
    const std::uint8_t counter = safety_counter_;
    const Result<CanFrame> safety = encode_safety_frame(safety_message(report.safety, report.robot, config_.zone_count),
                                                        safety_counter_, config_.channel);
    const Result<CanFrame> diagnostics = encode_diagnostics_frame(
        diagnostics_message(report, page_, config_.prior_crc, can_detail_faults), diagnostics_counter_,
        config_.channel);
    // Both cannot fail: the config was checked, counters stay 0..14, page 0..3, messages are in range.
    CG_ENFORCE(safety.ok() && diagnostics.ok(), "frames of a checked configuration always encode");
    safety_counter_ = e2e_p01_next_counter(safety_counter_);
    diagnostics_counter_ = e2e_p01_next_counter(diagnostics_counter_);
    page_ = static_cast<std::uint8_t>((page_ + 1U) % 4U);
    CycleFrames frames{
        safety.value(), inverted_copy(safety.value()), diagnostics.value(), CanFrame{}, false, CanFrame{}, false};
    if (link != nullptr) {
        const CanFrame bound[1] = {frames.safety};
        const Result<CanFrame> link_frame = encode_link_frame(link->next(report.started_us), counter,
                                                              link->config().own, Span<const CanFrame>(bound));
        CG_ENFORCE(link_frame.ok(), "a checked link endpoint's frame always encodes");
        frames.link = link_frame.value();
        frames.has_link = true;
    }
    if (report.robot.configured) {
        const Result<CanFrame> separation = encode_separation_frame(separation_message(report.robot),
                                                                    separation_counter_, config_.channel);
        CG_ENFORCE(separation.ok(), "the separation frame of a checked configuration always encodes");
        separation_counter_ = e2e_p01_next_counter(separation_counter_);
        frames.separation = separation.value();
        frames.has_separation = true;
    }
    return frames;
}

CanSafetyOutput::CanSafetyOutput(const SafetyOutputConfig& config, CanSender& sender, LinkEndpoint* link) noexcept
    : status_(check_safety_output_config(config)),
      encoder_(usable_config(config)),
      sender_(&sender),
      link_(config.session_link ? link : nullptr) {
    if (status_.ok() && config.session_link && link == nullptr) {
        status_ = ErrorCode::kInvalidArgument;  // protocol 0.2 needs the controller's link endpoint
    }
}

bool CanSafetyOutput::publish(const CycleReport& report) noexcept {
    if (!status_.ok()) {
        return false;
    }
    last_ = encoder_.encode(report, sender_->detail_faults(), link_);
    return sender_->send(last_.safety) && sender_->send(last_.inverted) &&
           (!last_.has_link || sender_->send(last_.link)) && sender_->send(last_.diagnostics) &&
           (!last_.has_separation || sender_->send(last_.separation));
}

}  // namespace cellguard
