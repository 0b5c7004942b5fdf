// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/command_receiver.hpp"

#include "cellguard/base/saturating.hpp"

namespace cellguard {
namespace {

CommandFault fault_of(FrameCheck check) noexcept {
    switch (check) {
        case FrameCheck::kWrongLength: return CommandFault::kWrongLength;
        case FrameCheck::kWrongDataIdNibble: return CommandFault::kWrongDataIdNibble;
        case FrameCheck::kWrongCrc: return CommandFault::kWrongCrc;
        case FrameCheck::kCounterOutOfRange: return CommandFault::kCounterOutOfRange;
        case FrameCheck::kOk:          // not a fault; never passed here
        case FrameCheck::kWrongCanId:  // frames are dispatched by CAN ID first
        case FrameCheck::kMalformedContent: return CommandFault::kMalformedContent;
    }
    return CommandFault::kMalformedContent;
}

// CommandFault lists the link faults in LinkFault's order (link_fault_as).
static_assert(link_fault_as(LinkFault::kNoEchoYet, CommandFault::kNoEchoYet) == CommandFault::kNoEchoYet);
static_assert(link_fault_as(LinkFault::kSessionChanged, CommandFault::kNoEchoYet) == CommandFault::kSessionChanged);
static_assert(link_fault_as(LinkFault::kRepeatedSequence, CommandFault::kNoEchoYet) == CommandFault::kRepeatedSequence);
static_assert(link_fault_as(LinkFault::kSequenceJump, CommandFault::kNoEchoYet) == CommandFault::kSequenceJump);
static_assert(link_fault_as(LinkFault::kWrongEchoSession, CommandFault::kNoEchoYet) == CommandFault::kWrongEchoSession);
static_assert(link_fault_as(LinkFault::kEchoUnknown, CommandFault::kNoEchoYet) == CommandFault::kEchoUnknown);
static_assert(link_fault_as(LinkFault::kEchoBackwards, CommandFault::kNoEchoYet) == CommandFault::kEchoBackwards);
static_assert(link_fault_as(LinkFault::kWatchdogExpired, CommandFault::kNoEchoYet) == CommandFault::kWatchdogExpired);

/// The endpoint's config: the given one when the link is enabled, else a valid placeholder (never used).
LinkConfig usable_link(const LinkConfig& link) noexcept { return link.enabled ? link : controller_link_config(); }

/// Index of the link frame in a sample: after A, A', B, B', C, C'.
constexpr std::size_t kLinkIndex = kCommandFramesPerSample;

/// True when @p copy is the bitwise inverse of @p frame with the same DLC.
bool is_inverse(const CanFrame& copy, const CanFrame& frame) noexcept {
    bool inverse = copy.dlc == frame.dlc;
    for (std::size_t k = 0U; k < kCanMaxDataLength; ++k) {
        inverse = inverse && copy.data[k] == static_cast<std::uint8_t>(~frame.data[k]);
    }
    return inverse;
}

}  // namespace

const char* to_string(CommandFault fault) noexcept {
    switch (fault) {
        case CommandFault::kNone: return "none";
        case CommandFault::kNoSampleYet: return "no sample yet";
        case CommandFault::kWrongLength: return "wrong length";
        case CommandFault::kWrongCrc: return "wrong CRC or data ID";
        case CommandFault::kWrongDataIdNibble: return "wrong data ID nibble";
        case CommandFault::kCounterOutOfRange: return "counter out of range";
        case CommandFault::kMalformedContent: return "malformed content";
        case CommandFault::kPartOutOfOrder: return "part out of order";
        case CommandFault::kCounterMismatch: return "parts with different counters";
        case CommandFault::kSampleIncomplete: return "sample incomplete";
        case CommandFault::kRepeatedCounter: return "repeated counter";
        case CommandFault::kCounterJump: return "counter jump";
        case CommandFault::kInvertedCopyMissing: return "inverted copy missing";
        case CommandFault::kInvertedCopyMismatch: return "inverted copy mismatch";
        case CommandFault::kInvertedCopyLate: return "inverted copy late";
        case CommandFault::kUnexpectedInvertedCopy: return "unexpected inverted copy";
        case CommandFault::kSctExpired: return "safeguard cycle time expired";
        case CommandFault::kTimeWentBackwards: return "time went backwards";
        case CommandFault::kLinkFrameMissing: return "link frame missing";
        case CommandFault::kLinkFrameInvalid: return "link frame invalid";
        case CommandFault::kUnexpectedLinkFrame: return "unexpected link frame";
        case CommandFault::kNoEchoYet: return "no echo of this session yet";
        case CommandFault::kSessionChanged: return "PLC session changed";
        case CommandFault::kRepeatedSequence: return "repeated sequence";
        case CommandFault::kSequenceJump: return "sequence jump";
        case CommandFault::kWrongEchoSession: return "echo of another session";
        case CommandFault::kEchoUnknown: return "echo of a sequence not sent";
        case CommandFault::kEchoBackwards: return "echo older than the last one";
        case CommandFault::kWatchdogExpired: return "round trip or data age above the watchdog time";
    }
    return "unknown command fault";
}

Status CommandReceiver::check_config(const CommandReceiverConfig& config) noexcept {
    if (!check_command_channel_config(config.channel).ok() || config.srvt_us == 0U ||
        config.srvt_us > config.sample_window_us || config.sample_window_us >= config.sct_us ||
        config.max_delta_counter < 1U || config.max_delta_counter > kE2eP01CounterMax ||
        config.recovery_good_samples < 1U) {
        return ErrorCode::kInvalidArgument;
    }
    if (config.link.enabled) {
        const std::uint32_t peer = config.link.peer.can_id;
        const std::uint32_t base = config.channel.base_can_id;
        if (!LinkEndpoint::check_config(config.link).ok() || (peer >= base && peer - base < kCommandFramesPerSample)) {
            return ErrorCode::kInvalidArgument;
        }
    }
    return Status{};
}

CommandReceiver::CommandReceiver(const CommandReceiverConfig& config) noexcept
    : config_(config), link_(usable_link(config.link)) {
    CG_ENFORCE(check_config(config).ok(), "CommandReceiver needs a configuration that passes check_config");
}

CommandStatus CommandReceiver::on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (advance_time(now_us)) {
        const std::uint32_t base = config_.channel.base_can_id;
        if (frame.id >= base && frame.id - base < kCommandFramesPerSample) {
            const std::size_t index = frame.id - base;
            if (index % 2U == 0U) {
                on_part(frame, index, now_us);
            } else {
                on_copy(frame, index, now_us);
            }
        } else if (config_.link.enabled && frame.id == config_.link.peer.can_id) {
            on_link(frame, now_us);
        } else {
            check_timeouts(now_us);  // not ours: only time has passed
        }
    }
    return status();
}

CommandPoll CommandReceiver::poll(std::uint64_t now_us) noexcept {
    if (advance_time(now_us)) {
        check_timeouts(now_us);
        if (valid_ && config_.link.enabled && link_.age_check(now_us) != LinkFault::kNone) {
            enter_safe_state(CommandFault::kWatchdogExpired);  // the command in use is older than the watchdog time
        }
    }
    CommandPoll p;
    p.status = status();
    if (valid_) {
        p.input = input_;
    }
    return p;
}

void CommandReceiver::on_part(const CanFrame& frame, std::size_t index, std::uint64_t now_us) noexcept {
    const bool is_a = index == 0U;
    if (!resync_ && next_ != index) {
        // A part where a copy was due; an A before the sample completed; any other part out of turn.
        enter_safe_state(next_ == kLinkIndex ? CommandFault::kLinkFrameMissing
                         : next_ % 2U == 1U  ? CommandFault::kInvertedCopyMissing
                                            : (is_a ? CommandFault::kSampleIncomplete : CommandFault::kPartOutOfOrder));
    }
    if (resync_ && !is_a) {
        return;  // after a fault (and at start-up) only an A starts a sample
    }
    if (!is_a && now_us - sample_start_us_ > config_.sample_window_us) {
        enter_safe_state(CommandFault::kSampleIncomplete);
        return;
    }
    const auto part = static_cast<CommandPart>(index / 2U);
    CommandPartContent content;
    const FrameCheck check = check_command_part(frame, part, config_.channel, content);
    if (check != FrameCheck::kOk) {
        enter_safe_state(fault_of(check));
        return;
    }
    if (is_a) {
        resync_ = false;
        sample_counter_ = content.counter;
        sample_start_us_ = now_us;
        assembling_ = RobotCommand{};
    } else if (content.counter != sample_counter_) {
        enter_safe_state(CommandFault::kCounterMismatch);
        return;
    }
    merge_command_part(content, assembling_);
    parts_[index / 2U] = frame;
    part_frame_ = frame;
    part_time_us_ = now_us;
    next_ = index + 1U;
}

void CommandReceiver::on_copy(const CanFrame& frame, std::size_t index, std::uint64_t now_us) noexcept {
    if (resync_) {
        return;  // the rest of a broken sample
    }
    if (next_ != index) {
        enter_safe_state(CommandFault::kUnexpectedInvertedCopy);  // a copy where a part, or another copy, was due
        return;
    }
    if (now_us - part_time_us_ > config_.srvt_us) {
        enter_safe_state(CommandFault::kInvertedCopyLate);
        return;
    }
    if (!is_inverse(frame, part_frame_)) {
        enter_safe_state(CommandFault::kInvertedCopyMismatch);
        return;
    }
    if (now_us - sample_start_us_ > config_.sample_window_us) {
        enter_safe_state(CommandFault::kSampleIncomplete);
        return;
    }
    next_ = index + 1U;
    if (next_ == kCommandFramesPerSample && !config_.link.enabled) {
        complete_sample(now_us);
    }
}

void CommandReceiver::on_link(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (resync_) {
        return;  // the rest of a broken sample
    }
    if (next_ != kLinkIndex) {
        enter_safe_state(CommandFault::kUnexpectedLinkFrame);
        return;
    }
    if (now_us - sample_start_us_ > config_.sample_window_us) {
        enter_safe_state(CommandFault::kLinkFrameMissing);
        return;
    }
    LinkFields fields;
    if (check_link_frame(frame, config_.link.peer, Span<const CanFrame>(parts_), sample_counter_, fields) !=
        LinkFrameCheck::kOk) {
        enter_safe_state(CommandFault::kLinkFrameInvalid);
        return;
    }
    const LinkFault link_fault = link_.on_peer(fields, now_us);
    if (link_fault != LinkFault::kNone) {
        enter_safe_state(link_fault_as(link_fault, CommandFault::kNoEchoYet));
        return;
    }
    complete_sample(now_us);
}

void CommandReceiver::complete_sample(std::uint64_t now_us) noexcept {
    next_ = 0U;
    if (!command_well_formed(assembling_)) {
        enter_safe_state(CommandFault::kMalformedContent);  // a joint set beyond the joint count
        return;
    }
    if (have_reference_ && now_us - reference_time_us_ > config_.sct_us) {
        enter_safe_state(CommandFault::kSctExpired);  // late; the sample may still start a new reference
    }
    if (have_reference_) {
        const std::uint8_t delta = e2e_p01_counter_delta(sample_counter_, reference_counter_);
        if (delta == 0U) {
            enter_safe_state(CommandFault::kRepeatedCounter);
            return;
        }
        if (delta > config_.max_delta_counter) {
            enter_safe_state(CommandFault::kCounterJump);
            return;
        }
        good_samples_ = saturating_increment(good_samples_);
    }
    have_reference_ = true;
    reference_counter_ = sample_counter_;
    reference_time_us_ = now_us;
    input_.valid = true;
    input_.command = assembling_;
    input_.counter = sample_counter_;
    input_.received_us = now_us;
    accepted_ = saturating_increment(accepted_);
    if (!valid_ && good_samples_ >= config_.recovery_good_samples) {
        valid_ = true;
        fault_ = CommandFault::kNone;
    }
}

bool CommandReceiver::advance_time(std::uint64_t now_us) noexcept {
    if (have_time_ && now_us < last_time_us_) {
        last_time_us_ = now_us;  // continue on the new time line; every time reference is dropped
        enter_safe_state(CommandFault::kTimeWentBackwards);
        return false;
    }
    have_time_ = true;
    last_time_us_ = now_us;
    return true;
}

void CommandReceiver::check_timeouts(std::uint64_t now_us) noexcept {
    if (next_ % 2U == 1U && now_us - part_time_us_ > config_.srvt_us) {
        enter_safe_state(CommandFault::kInvertedCopyMissing);
    } else if (next_ != 0U && now_us - sample_start_us_ > config_.sample_window_us) {
        enter_safe_state(next_ == kLinkIndex ? CommandFault::kLinkFrameMissing : CommandFault::kSampleIncomplete);
    }
    if (have_reference_ && now_us - reference_time_us_ > config_.sct_us) {
        enter_safe_state(CommandFault::kSctExpired);
    }
}

void CommandReceiver::enter_safe_state(CommandFault reason) noexcept {
    valid_ = false;
    fault_ = reason;
    fault_events_ = saturating_increment(fault_events_);
    have_reference_ = false;
    good_samples_ = 0U;
    next_ = 0U;  // the sample in progress is dropped; wait for the next A
    resync_ = true;
}

CommandStatus CommandReceiver::status() const noexcept {
    CommandStatus s;
    s.valid = valid_;
    s.fault = valid_ ? CommandFault::kNone : fault_;
    s.fault_events = fault_events_;
    s.good_samples = accepted_;
    return s;
}

}  // namespace cellguard
