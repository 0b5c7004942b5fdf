// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/plc_receiver.hpp"

#include "cellguard/base/saturating.hpp"

namespace cellguard {
namespace {

ReceiverFault fault_of(FrameCheck check) noexcept {
    switch (check) {
        case FrameCheck::kWrongLength: return ReceiverFault::kWrongLength;
        case FrameCheck::kWrongDataIdNibble: return ReceiverFault::kWrongDataIdNibble;
        case FrameCheck::kWrongCrc: return ReceiverFault::kWrongCrc;
        case FrameCheck::kCounterOutOfRange: return ReceiverFault::kCounterOutOfRange;
        case FrameCheck::kOk:          // not a fault; never passed here
        case FrameCheck::kWrongCanId:  // frames are dispatched by CAN ID first
        case FrameCheck::kMalformedContent: return ReceiverFault::kMalformedContent;
    }
    return ReceiverFault::kMalformedContent;
}

// ReceiverFault lists the link faults in LinkFault's order (link_fault_as).
static_assert(link_fault_as(LinkFault::kNoEchoYet, ReceiverFault::kNoEchoYet) == ReceiverFault::kNoEchoYet);
static_assert(link_fault_as(LinkFault::kSessionChanged, ReceiverFault::kNoEchoYet) == ReceiverFault::kSessionChanged);
static_assert(link_fault_as(LinkFault::kRepeatedSequence, ReceiverFault::kNoEchoYet) ==
              ReceiverFault::kRepeatedSequence);
static_assert(link_fault_as(LinkFault::kSequenceJump, ReceiverFault::kNoEchoYet) == ReceiverFault::kSequenceJump);
static_assert(link_fault_as(LinkFault::kWrongEchoSession, ReceiverFault::kNoEchoYet) ==
              ReceiverFault::kWrongEchoSession);
static_assert(link_fault_as(LinkFault::kEchoUnknown, ReceiverFault::kNoEchoYet) == ReceiverFault::kEchoUnknown);
static_assert(link_fault_as(LinkFault::kEchoBackwards, ReceiverFault::kNoEchoYet) == ReceiverFault::kEchoBackwards);
static_assert(link_fault_as(LinkFault::kWatchdogExpired, ReceiverFault::kNoEchoYet) == ReceiverFault::kWatchdogExpired);

/// The endpoint's config: the given one when the link is enabled, else a valid placeholder (never used).
LinkConfig usable_link(const LinkConfig& link) noexcept { return link.enabled ? link : plc_link_config(); }

}  // namespace

const char* to_string(ReceiverFault fault) noexcept {
    switch (fault) {
        case ReceiverFault::kNone: return "none";
        case ReceiverFault::kNoFrameYet: return "no frame yet";
        case ReceiverFault::kWrongLength: return "wrong length";
        case ReceiverFault::kWrongCrc: return "wrong CRC or data ID";
        case ReceiverFault::kWrongDataIdNibble: return "wrong data ID nibble";
        case ReceiverFault::kCounterOutOfRange: return "counter out of range";
        case ReceiverFault::kMalformedContent: return "malformed content";
        case ReceiverFault::kZoneCountMismatch: return "zone count mismatch";
        case ReceiverFault::kRepeatedCounter: return "repeated counter";
        case ReceiverFault::kCounterJump: return "counter jump";
        case ReceiverFault::kInvertedCopyMissing: return "inverted copy missing";
        case ReceiverFault::kInvertedCopyMismatch: return "inverted copy mismatch";
        case ReceiverFault::kInvertedCopyLate: return "inverted copy late";
        case ReceiverFault::kUnexpectedInvertedCopy: return "unexpected inverted copy";
        case ReceiverFault::kSctExpired: return "safeguard cycle time expired";
        case ReceiverFault::kTimeWentBackwards: return "time went backwards";
        case ReceiverFault::kLinkFrameMissing: return "link frame missing";
        case ReceiverFault::kLinkFrameInvalid: return "link frame invalid";
        case ReceiverFault::kUnexpectedLinkFrame: return "unexpected link frame";
        case ReceiverFault::kNoEchoYet: return "no echo of this session yet";
        case ReceiverFault::kSessionChanged: return "controller session changed";
        case ReceiverFault::kRepeatedSequence: return "repeated sequence";
        case ReceiverFault::kSequenceJump: return "sequence jump";
        case ReceiverFault::kWrongEchoSession: return "echo of another session";
        case ReceiverFault::kEchoUnknown: return "echo of a sequence not sent";
        case ReceiverFault::kEchoBackwards: return "echo older than the last one";
        case ReceiverFault::kWatchdogExpired: return "round trip or data age above the watchdog time";
    }
    return "unknown receiver fault";
}

SafetyMessage safe_state_message(std::uint8_t zone_count) noexcept {
    CG_ENFORCE(zone_count <= kMaxZonesInFrame, "at most 16 zones in a safety frame");
    const auto zones = static_cast<std::uint16_t>((std::uint32_t{1} << zone_count) - 1U);
    SafetyMessage m;
    m.protective_stop = true;
    m.warning = true;
    m.fault = true;
    m.active_case = 0U;
    m.reduced_speed = true;  // stop wins; every alarm bit is set
    m.zone_intrusion = zones;
    m.zone_unseen = zones;
    m.zone_count = zone_count;
    return m;
}

Status PlcReceiver::check_config(const PlcReceiverConfig& config) noexcept {
    if (!check_channel_config(config.channel).ok() || config.srvt_us == 0U || config.srvt_us >= config.sct_us ||
        config.max_delta_counter < 1U || config.max_delta_counter > kE2eP01CounterMax ||
        config.recovery_good_pairs < 1U || config.expected_zone_count > kMaxZonesInFrame) {
        return ErrorCode::kInvalidArgument;
    }
    if (config.link.enabled) {
        const std::uint32_t peer = config.link.peer.can_id;
        const SafetyChannelConfig& ch = config.channel;
        if (!LinkEndpoint::check_config(config.link).ok() || peer == ch.safety_can_id || peer == inverted_can_id(ch) ||
            peer == ch.diagnostics_can_id || peer == ch.separation_can_id) {
            return ErrorCode::kInvalidArgument;
        }
    }
    return Status{};
}

PlcReceiver::PlcReceiver(const PlcReceiverConfig& config) noexcept : config_(config), link_(usable_link(config.link)) {
    CG_ENFORCE(check_config(config).ok(), "PlcReceiver needs a configuration that passes check_config");
}

ReceiverStatus PlcReceiver::on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (advance_time(now_us)) {
        if (frame.id == config_.channel.safety_can_id) {
            on_normal_frame(frame, now_us);
        } else if (frame.id == inverted_can_id(config_.channel)) {
            on_inverted_copy(frame, now_us);
        } else if (config_.link.enabled && frame.id == config_.link.peer.can_id) {
            on_link_frame(frame, now_us);
        } else {
            check_timeouts(now_us);  // not ours: only time has passed
        }
        // Every frame, not only polls: the status returned here is never valid for a reference pair older than
        // the SCT (an inverted copy accepts no pair, so nothing else checks it there) or data older than the
        // watchdog time.
        if (valid_ && now_us - reference_time_us_ > config_.sct_us) {
            enter_safe_state(ReceiverFault::kSctExpired);
        }
        if (valid_ && config_.link.enabled && link_.age_check(now_us) != LinkFault::kNone) {
            enter_safe_state(ReceiverFault::kWatchdogExpired);
        }
    }
    return status();
}

ReceiverStatus PlcReceiver::poll(std::uint64_t now_us) noexcept {
    if (advance_time(now_us)) {
        check_timeouts(now_us);
    }
    return status();
}

void PlcReceiver::on_normal_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (pending_) {
        pending_ = false;
        enter_safe_state(ReceiverFault::kInvertedCopyMissing);
    }
    if (awaiting_link_) {
        awaiting_link_ = false;
        enter_safe_state(ReceiverFault::kLinkFrameMissing);
    }
    if (have_reference_ && now_us - reference_time_us_ > config_.sct_us) {
        enter_safe_state(ReceiverFault::kSctExpired);  // a late frame; it may still start a new reference
    }
    SafetyFrameContent content;
    const FrameCheck check = check_safety_frame(frame, config_.channel, content);
    if (check != FrameCheck::kOk) {
        enter_safe_state(fault_of(check));
        return;
    }
    if (content.message.zone_count != config_.expected_zone_count) {
        enter_safe_state(ReceiverFault::kZoneCountMismatch);
        return;
    }
    pending_ = true;
    pending_frame_ = frame;
    pending_content_ = content;
    pending_time_us_ = now_us;
}

void PlcReceiver::on_inverted_copy(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (!pending_) {
        enter_safe_state(ReceiverFault::kUnexpectedInvertedCopy);
        return;
    }
    pending_ = false;
    if (now_us - pending_time_us_ > config_.srvt_us) {
        enter_safe_state(ReceiverFault::kInvertedCopyLate);
        return;
    }
    bool inverse = frame.dlc == pending_frame_.dlc;
    for (std::size_t k = 0U; k < kCanMaxDataLength; ++k) {
        inverse = inverse && frame.data[k] == static_cast<std::uint8_t>(~pending_frame_.data[k]);
    }
    if (!inverse) {
        enter_safe_state(ReceiverFault::kInvertedCopyMismatch);
        return;
    }
    if (config_.link.enabled) {
        awaiting_link_ = true;  // pending_frame_, pending_content_ and pending_time_us_ stay for the link frame
        return;
    }
    accept_pair(now_us);
}

void PlcReceiver::on_link_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (!awaiting_link_) {
        enter_safe_state(ReceiverFault::kUnexpectedLinkFrame);
        return;
    }
    awaiting_link_ = false;
    if (now_us - pending_time_us_ > config_.srvt_us) {
        enter_safe_state(ReceiverFault::kLinkFrameMissing);
        return;
    }
    LinkFields fields;
    if (check_link_frame(frame, config_.link.peer, Span<const CanFrame>(&pending_frame_, 1U), pending_content_.counter,
                         fields) != LinkFrameCheck::kOk) {
        enter_safe_state(ReceiverFault::kLinkFrameInvalid);
        return;
    }
    const LinkFault link_fault = link_.on_peer(fields, now_us);
    if (link_fault != LinkFault::kNone) {
        enter_safe_state(link_fault_as(link_fault, ReceiverFault::kNoEchoYet));
        return;
    }
    accept_pair(now_us);
}

void PlcReceiver::accept_pair(std::uint64_t now_us) noexcept {
    // A complete pair. Check it against the previous good pair, if there is one.
    if (have_reference_ && now_us - reference_time_us_ > config_.sct_us) {
        enter_safe_state(ReceiverFault::kSctExpired);  // late; the pair may still start a new reference
    }
    if (have_reference_) {
        const std::uint8_t delta = e2e_p01_counter_delta(pending_content_.counter, reference_counter_);
        if (delta == 0U) {
            enter_safe_state(ReceiverFault::kRepeatedCounter);
            return;
        }
        if (delta > config_.max_delta_counter) {
            enter_safe_state(ReceiverFault::kCounterJump);
            return;
        }
        good_pairs_ = saturating_increment(good_pairs_);
    }
    have_reference_ = true;
    reference_counter_ = pending_content_.counter;
    reference_time_us_ = now_us;
    message_ = pending_content_.message;
    if (!valid_ && good_pairs_ >= config_.recovery_good_pairs) {
        valid_ = true;
        fault_ = ReceiverFault::kNone;
    }
}

bool PlcReceiver::advance_time(std::uint64_t now_us) noexcept {
    if (have_time_ && now_us < last_time_us_) {
        last_time_us_ = now_us;  // continue on the new time line; every time reference is dropped
        pending_ = false;
        awaiting_link_ = false;
        enter_safe_state(ReceiverFault::kTimeWentBackwards);
        return false;
    }
    have_time_ = true;
    last_time_us_ = now_us;
    return true;
}

void PlcReceiver::check_timeouts(std::uint64_t now_us) noexcept {
    if (pending_ && now_us - pending_time_us_ > config_.srvt_us) {
        pending_ = false;
        enter_safe_state(ReceiverFault::kInvertedCopyMissing);
    }
    if (awaiting_link_ && now_us - pending_time_us_ > config_.srvt_us) {
        awaiting_link_ = false;
        enter_safe_state(ReceiverFault::kLinkFrameMissing);
    }
    if (have_reference_ && now_us - reference_time_us_ > config_.sct_us) {
        enter_safe_state(ReceiverFault::kSctExpired);
    }
    if (valid_ && config_.link.enabled && link_.age_check(now_us) != LinkFault::kNone) {
        enter_safe_state(ReceiverFault::kWatchdogExpired);  // the data in use is older than the watchdog time
    }
}

void PlcReceiver::enter_safe_state(ReceiverFault reason) noexcept {
    valid_ = false;
    fault_ = reason;
    fault_events_ = saturating_increment(fault_events_);
    have_reference_ = false;
    good_pairs_ = 0U;
}

ReceiverStatus PlcReceiver::status() const noexcept {
    ReceiverStatus s;
    s.communication_valid = valid_;
    s.stop_requested = !valid_ || message_.protective_stop;
    s.fault = valid_ ? ReceiverFault::kNone : fault_;
    s.message = valid_ ? message_ : safe_state_message(config_.expected_zone_count);
    s.fault_events = fault_events_;
    return s;
}

}  // namespace cellguard
