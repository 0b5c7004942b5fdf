// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/session_link.hpp"

#include "frame_protection.hpp"

namespace cellguard {
namespace {

static_assert(link_layout::kCrc.start_bit == safety_layout::kCrc.start_bit &&
                  link_layout::kCounter.start_bit == safety_layout::kCounter.start_bit &&
                  link_layout::kDataIdNibble.start_bit == safety_layout::kDataIdNibble.start_bit,
              "the link frame shares the E2E header layout");

/// The Profile 1 CRC of @p frame (byte 0 skipped) continued over every byte of @p bound.
std::uint8_t bound_crc(const CanFrame& frame, const LinkChannel& channel, std::uint8_t counter,
                       Span<const CanFrame> bound) noexcept {
    // e2e_p01_crc is the raw register (start 0x00, no final XOR); Crc_CalculateCRC8
    // continues from a start value XORed with 0xFF, and XORs its result with 0xFF.
    std::uint8_t reg = e2e_p01_crc({frame.data, kCanMaxDataLength}, 0U, channel.data_id, channel.data_id_mode, counter);
    for (const CanFrame& f : bound) {
        reg = static_cast<std::uint8_t>(
            crc8_sae_j1850({f.data, kCanMaxDataLength}, static_cast<std::uint8_t>(reg ^ 0xFFU), false) ^ 0xFFU);
    }
    return reg;
}

bool fields_valid(const LinkFields& f) noexcept { return f.sequence != 0U && f.session != 0U; }

}  // namespace

Status check_link_channel(const LinkChannel& channel) noexcept {
    if (channel.can_id > kCanMaxStandardId || !e2e_p01_data_id_valid(channel.data_id, channel.data_id_mode)) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

Result<CanFrame> encode_link_frame(const LinkFields& fields, std::uint8_t counter, const LinkChannel& channel,
                                   Span<const CanFrame> bound) noexcept {
    if (!check_link_channel(channel).ok() || counter > kE2eP01CounterMax || !fields_valid(fields)) {
        return ErrorCode::kInvalidArgument;
    }
    CanFrame frame = detail::empty_frame(channel.can_id);
    set_signal(frame, link_layout::kSequence, fields.sequence);
    set_signal(frame, link_layout::kEcho, fields.echo);
    set_signal(frame, link_layout::kSession, fields.session);
    set_signal(frame, link_layout::kEchoSession, fields.echo_session);
    set_signal(frame, link_layout::kCounter, counter);
    set_signal(frame, link_layout::kDataIdNibble,
               channel.data_id_mode == E2eP01DataIdMode::kNibble ? e2e_p01_data_id_nibble(channel.data_id) : 0U);
    set_signal(frame, link_layout::kCrc, bound_crc(frame, channel, counter, bound));
    return frame;
}

const char* to_string(LinkFrameCheck check) noexcept {
    switch (check) {
        case LinkFrameCheck::kOk: return "ok";
        case LinkFrameCheck::kWrongCanId: return "wrong CAN ID";
        case LinkFrameCheck::kWrongLength: return "wrong length";
        case LinkFrameCheck::kWrongDataIdNibble: return "wrong data ID nibble";
        case LinkFrameCheck::kWrongCrc: return "wrong CRC or another sample's link frame";
        case LinkFrameCheck::kCounterMismatch: return "counter differs from the sample's";
        case LinkFrameCheck::kMalformedContent: return "malformed content";
    }
    return "unknown link frame check";
}

LinkFrameCheck check_link_frame(const CanFrame& frame, const LinkChannel& channel, Span<const CanFrame> bound,
                                std::uint8_t counter, LinkFields& out) noexcept {
    CG_ENFORCE(check_link_channel(channel).ok(), "check_link_frame needs a valid link channel");
    if (frame.id != channel.can_id) {
        return LinkFrameCheck::kWrongCanId;
    }
    if (frame.dlc != kCanMaxDataLength) {
        return LinkFrameCheck::kWrongLength;
    }
    const bool nibble_mode = channel.data_id_mode == E2eP01DataIdMode::kNibble;
    const std::uint32_t expected_nibble = nibble_mode ? e2e_p01_data_id_nibble(channel.data_id) : 0U;
    const std::uint32_t nibble = get_signal(frame, link_layout::kDataIdNibble);
    if (nibble_mode && nibble != expected_nibble) {
        return LinkFrameCheck::kWrongDataIdNibble;
    }
    const auto frame_counter = static_cast<std::uint8_t>(get_signal(frame, link_layout::kCounter));
    if (get_signal(frame, link_layout::kCrc) != bound_crc(frame, channel, frame_counter, bound)) {
        return LinkFrameCheck::kWrongCrc;
    }
    if (frame_counter != counter) {
        return LinkFrameCheck::kCounterMismatch;
    }
    LinkFields f;
    f.sequence = static_cast<std::uint16_t>(get_signal(frame, link_layout::kSequence));
    f.echo = static_cast<std::uint16_t>(get_signal(frame, link_layout::kEcho));
    f.session = static_cast<std::uint8_t>(get_signal(frame, link_layout::kSession));
    f.echo_session = static_cast<std::uint8_t>(get_signal(frame, link_layout::kEchoSession));
    if (!fields_valid(f) || nibble != expected_nibble || frame_counter > kE2eP01CounterMax) {
        return LinkFrameCheck::kMalformedContent;
    }
    out = f;
    return LinkFrameCheck::kOk;
}

const char* to_string(LinkFault fault) noexcept {
    switch (fault) {
        case LinkFault::kNone: return "none";
        case LinkFault::kNoEchoYet: return "no echo of this session yet";
        case LinkFault::kSessionChanged: return "session of the other side changed";
        case LinkFault::kRepeatedSequence: return "repeated sequence";
        case LinkFault::kSequenceJump: return "sequence jump";
        case LinkFault::kWrongEchoSession: return "echo of another session";
        case LinkFault::kEchoUnknown: return "echo of a sequence not sent";
        case LinkFault::kEchoBackwards: return "echo older than the last one";
        case LinkFault::kWatchdogExpired: return "round trip or data age above the watchdog time";
    }
    return "unknown link fault";
}

Status LinkEndpoint::check_config(const LinkConfig& config) noexcept {
    if (!check_link_channel(config.own).ok() || !check_link_channel(config.peer).ok() ||
        config.own.can_id == config.peer.can_id || config.session == 0U || config.watchdog_us == 0U ||
        config.max_sequence_step < 1U || config.max_sequence_step > kLinkHistory) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

LinkEndpoint::LinkEndpoint(const LinkConfig& config) noexcept : config_(config) {
    CG_ENFORCE(check_config(config).ok(), "LinkEndpoint needs a configuration that passes check_config");
}

LinkFields LinkEndpoint::next(std::uint64_t now_us) noexcept {
    sequence_ = link_next_sequence(sequence_);
    const std::size_t slot = sequence_ % kLinkHistory;
    sent_sequence_[slot] = sequence_;
    sent_us_[slot] = now_us;
    LinkFields f;
    f.sequence = sequence_;
    f.session = config_.session;
    f.echo = peer_sequence_;
    f.echo_session = peer_session_;
    return f;
}

LinkFault LinkEndpoint::on_peer(const LinkFields& fields, std::uint64_t now_us) noexcept {
    if (!fields_valid(fields)) {
        return LinkFault::kSequenceJump;  // never produced by check_link_frame; refused all the same
    }
    const LinkFault order = check_order(fields, now_us);
    return order != LinkFault::kNone ? order : check_echo(fields, now_us);
}

bool LinkEndpoint::reference_fresh(std::uint64_t now_us) const noexcept {
    return peer_session_ != 0U && now_us >= peer_us_ && now_us - peer_us_ <= config_.watchdog_us;
}

void LinkEndpoint::take_reference(const LinkFields& fields, std::uint64_t now_us) noexcept {
    peer_session_ = fields.session;
    peer_sequence_ = fields.sequence;
    peer_us_ = now_us;
}

LinkFault LinkEndpoint::check_order(const LinkFields& fields, std::uint64_t now_us) noexcept {
    if (peer_session_ == 0U) {
        take_reference(fields, now_us);
        return LinkFault::kNone;
    }
    // A frame that would move the reference back (behind it, or to the session just left) is a replay
    // while the reference is younger than the watchdog time: refused, the reference kept. An older
    // reference may move: any frame sent before it arrived echoes a sequence older than the watchdog time.
    const bool fresh = reference_fresh(now_us);
    if (fields.session != peer_session_) {
        if (fresh && fields.session == left_session_) {
            return LinkFault::kSessionChanged;
        }
        left_session_ = peer_session_;
        take_reference(fields, now_us);
        return LinkFault::kSessionChanged;
    }
    const std::uint16_t step = link_sequence_delta(fields.sequence, peer_sequence_);
    if (step == 0U || (fresh && step >= kLinkSequenceBehind)) {
        return LinkFault::kRepeatedSequence;
    }
    take_reference(fields, now_us);
    return step > config_.max_sequence_step ? LinkFault::kSequenceJump : LinkFault::kNone;
}

LinkFault LinkEndpoint::check_echo(const LinkFields& fields, std::uint64_t now_us) noexcept {
    if (fields.echo_session == 0U || fields.echo == 0U) {
        return LinkFault::kNoEchoYet;  // the other side has not heard this side yet
    }
    if (fields.echo_session != config_.session) {
        return LinkFault::kWrongEchoSession;
    }
    const std::size_t slot = fields.echo % kLinkHistory;
    if (sent_sequence_[slot] != fields.echo || link_sequence_delta(sequence_, fields.echo) >= kLinkHistory) {
        return LinkFault::kEchoUnknown;
    }
    if (echo_ != 0U && link_sequence_delta(fields.echo, echo_) >= kLinkHistory) {
        return LinkFault::kEchoBackwards;
    }
    const std::uint64_t sent_us = sent_us_[slot];
    if (now_us < sent_us || now_us - sent_us > config_.watchdog_us) {
        return LinkFault::kWatchdogExpired;
    }
    echo_ = fields.echo;
    echo_sent_us_ = sent_us;
    return LinkFault::kNone;
}

LinkFault LinkEndpoint::on_standalone_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
    LinkFields fields;
    const auto counter = static_cast<std::uint8_t>(get_signal(frame, link_layout::kCounter));
    if (check_link_frame(frame, config_.peer, {}, counter, fields) != LinkFrameCheck::kOk) {
        return LinkFault::kSequenceJump;
    }
    return on_peer(fields, now_us);
}

LinkFault LinkEndpoint::age_check(std::uint64_t now_us) const noexcept {
    if (echo_ == 0U) {
        return LinkFault::kNoEchoYet;
    }
    if (now_us < echo_sent_us_ || now_us - echo_sent_us_ > config_.watchdog_us) {
        return LinkFault::kWatchdogExpired;
    }
    return LinkFault::kNone;
}

}  // namespace cellguard
