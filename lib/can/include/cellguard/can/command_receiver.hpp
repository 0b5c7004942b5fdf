// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file command_receiver.hpp
/// The controller's side of the PLC's command message (command_frame.hpp):
/// assembles the six frames of each sample, checks them, and hands the
/// controller a CommandInput each cycle. Fixed size, no heap, no OS calls.
/// Fed every received CAN frame (on_frame, with its receive time) and polled
/// once per controller cycle (poll, at the cycle's start).
///
/// Checks (any failure: not valid, with a reason):
/// - each part A, B, C: CAN ID, DLC 8, data ID nibble, CRC with the part's
///   data ID, counter 0..14, reserved bits, no joint at -32768 (check_command_part);
/// - order: the frames of a sample must come as A, A', B, B', C, C'. A frame
///   out of that order is a fault (kPartOutOfOrder, kInvertedCopyMissing,
///   kUnexpectedInvertedCopy); an A that arrives before the previous sample
///   completed is kSampleIncomplete and starts a new sample;
/// - each inverted copy: the bitwise inverse of its part (same DLC), within
///   srvt_us of the part;
/// - all three parts carry the same counter (kCounterMismatch), and the
///   sample completes (C' arrives) within sample_window_us of its A;
/// - the complete sample: joints at and above JointCount are 0;
/// - its counter against the previous good sample: delta 0 is kRepeatedCounter,
///   a delta above max_delta_counter is kCounterJump;
/// - SCT: a good sample completes within sct_us of the previous one; a late
///   sample, and a poll or frame that finds none within sct_us, are kSctExpired;
/// - time going backwards between calls;
/// - protocol 0.2, the session link (session_link.hpp; on unless
///   config.link.enabled is false): each sample is closed by the PLC's link
///   frame (after C', within the sample window; CRC bound to parts A, B and
///   C, the sample's counter); its session, sequence and echo pass the
///   controller's LinkEndpoint (owned here, shared with the CAN output
///   through link()), whose round trip and data age must stay within
///   link.watchdog_us (checked on the link frame and at every poll).
///
/// After a fault, and at start-up, the receiver waits for the next part A:
/// the rest of a broken sample is discarded without further faults, so the
/// reason names the first failure (and joining a bus mid-sample is no fault).
///
/// Safe state and recovery as PlcReceiver: a failure drops the sample in
/// progress and the counter reference; the next good sample sets a new
/// reference, then recovery_good_samples further samples must pass every
/// check in a row. At start-up the reason is kNoSampleYet. While not valid
/// the CommandInput has valid = false and a zero command; the controller
/// turns that into Fault::kCommandInvalid (a protective stop). The receiver
/// does not know the cell: case count, joint count and limits and the robot
/// ID are the controller's checks.
///
/// Response: a fault found in a frame makes the next poll invalid; silence
/// makes the first poll more than sct_us after the last good sample invalid.
/// With the controller period T and the safety frame sent at the end of the
/// cycle that polled, the stop reaches the output at most sct_us + 2 T after
/// the last good sample (certification/can-safety-protocol.md).
#ifndef CELLGUARD_CAN_COMMAND_RECEIVER_HPP
#define CELLGUARD_CAN_COMMAND_RECEIVER_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/command_frame.hpp"
#include "cellguard/can/session_link.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Why the command is not valid. Values are stable (logged).
enum class CommandFault : std::uint8_t {
    kNone = 0,                     ///< valid
    kNoSampleYet = 1,              ///< start-up: recovery not yet complete
    kWrongLength = 2,              ///< a part's DLC is not 8
    kWrongCrc = 3,                 ///< CRC mismatch: corrupted data or a wrong (implicit) data ID
    kWrongDataIdNibble = 4,        ///< kNibble mode: explicit data ID nibble differs
    kCounterOutOfRange = 5,        ///< counter value 15
    kMalformedContent = 6,         ///< reserved bits, a joint at -32768, a joint set beyond JointCount
    kPartOutOfOrder = 7,           ///< a part that is not the next one of the sample (B before A, A twice...)
    kCounterMismatch = 8,          ///< the parts of one sample carry different counters
    kSampleIncomplete = 9,         ///< the sample did not complete within sample_window_us, or a new A came first
    kRepeatedCounter = 10,         ///< the same counter as the previous good sample
    kCounterJump = 11,             ///< counter advanced by more than max_delta_counter
    kInvertedCopyMissing = 12,     ///< another frame, or nothing within srvt_us, where a copy was due
    kInvertedCopyMismatch = 13,    ///< the copy is not the bitwise inverse of its part
    kInvertedCopyLate = 14,        ///< the copy arrived after srvt_us
    kUnexpectedInvertedCopy = 15,  ///< a copy where a part was due, or the copy of another part
    kSctExpired = 16,              ///< no good sample within sct_us (late sample or silence)
    kTimeWentBackwards = 17,       ///< the caller's time decreased
    kLinkFrameMissing = 18,        ///< another frame, or nothing within the sample window, where the link frame was due
    kLinkFrameInvalid = 19,        ///< the link frame failed its check (CRC bound to A, B, C, counter, length)
    kUnexpectedLinkFrame = 20,     ///< a link frame where none was due
    kNoEchoYet = 21,               ///< start-up: the PLC has not echoed this controller's session yet
    kSessionChanged = 22,          ///< the PLC's session changed (restart, or a replay of another session)
    kRepeatedSequence = 23,        ///< the PLC's sequence did not advance (replay)
    kSequenceJump = 24,            ///< the PLC's sequence jumped (loss beyond the bound, old replay)
    kWrongEchoSession = 25,        ///< the echo names another session of this controller (replay across its restart)
    kEchoUnknown = 26,             ///< the echo is no sequence this controller sent recently
    kEchoBackwards = 27,           ///< the echo is older than the last one
    kWatchdogExpired = 28,         ///< round trip or data age above link.watchdog_us (unacceptable delay)
};
/// A short, static name for @p fault (never nullptr).
[[nodiscard]] const char* to_string(CommandFault fault) noexcept;

/// Configuration of a CommandReceiver; check with CommandReceiver::check_config().
/// Defaults suit a controller period of 100 ms and a PLC that sends a sample
/// every 50 ms, its six frames back to back: one lost sample is tolerated
/// (delta 2, 100 ms < SCT), two are not.
struct CommandReceiverConfig {
    CommandChannelConfig channel;                ///< CAN IDs, data IDs, data ID mode (the sender's)
    std::uint64_t srvt_us = 10000U;              ///< latest copy arrival after its part, > 0
    std::uint64_t sample_window_us = 20000U;     ///< latest C' after its A, >= srvt_us
    std::uint64_t sct_us = 120000U;              ///< longest time between good samples, > sample_window_us
    std::uint8_t max_delta_counter = 2U;         ///< largest accepted counter step, 1..14
    std::uint8_t recovery_good_samples = 2U;     ///< good samples after the reference one to become valid, >= 1
    LinkConfig link = controller_link_config();  ///< the session link (own: the controller's link channel)
};

/// The receiver's state, beside the CommandInput.
struct CommandStatus {
    bool valid = false;                               ///< every check passed and recovery is complete
    CommandFault fault = CommandFault::kNoSampleYet;  ///< kNone exactly when valid
    std::uint32_t fault_events = 0U;                  ///< faults detected since construction (saturating)
    std::uint32_t good_samples = 0U;                  ///< samples accepted since construction (saturating)
};

/// What poll() returns: the controller's input and the receiver's status.
struct CommandPoll {
    CommandInput input{};    ///< the last good sample when valid; valid = false and a zero command otherwise
    CommandStatus status{};  ///< validity and the reason
};

/// Assembles and checks command samples; see the file comment.
class CommandReceiver {
public:
    /// kInvalidArgument unless the channel is valid, 0 < srvt_us <= sample_window_us
    /// < sct_us, max_delta_counter is 1..14 and recovery_good_samples >= 1; with
    /// the link enabled, LinkEndpoint::check_config and a peer link CAN ID
    /// outside the six command IDs.
    [[nodiscard]] static Status check_config(const CommandReceiverConfig& config) noexcept;

    /// A receiver in the safe state (kNoSampleYet). @p config must pass check_config (contract).
    explicit CommandReceiver(const CommandReceiverConfig& config) noexcept;

    /// Processes one received frame, received at @p now_us (monotonic); frames
    /// on other CAN IDs only let time pass. Returns the status.
    CommandStatus on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;

    /// Applies the time checks (SRVT, sample window, SCT) at @p now_us and
    /// returns the input for this cycle. Call it at each cycle's start.
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept;

    /// The status now, without a time check.
    [[nodiscard]] CommandStatus status() const noexcept;
    /// The last good sample (its counter and receive time; valid false before
    /// the first), whether or not recovery is complete: the clock-rate check's input.
    [[nodiscard]] const CommandInput& last_sample() const noexcept { return input_; }
    /// The controller's link endpoint: the CAN output takes the fields of its
    /// link frames from it (LinkEndpoint::next).
    [[nodiscard]] LinkEndpoint& link() noexcept { return link_; }
    /// The same, read-only.
    [[nodiscard]] const LinkEndpoint& link() const noexcept { return link_; }
    /// The configuration in use.
    [[nodiscard]] const CommandReceiverConfig& config() const noexcept { return config_; }

private:
    void on_link(const CanFrame& frame, std::uint64_t now_us) noexcept;
    void on_part(const CanFrame& frame, std::size_t index, std::uint64_t now_us) noexcept;
    void on_copy(const CanFrame& frame, std::size_t index, std::uint64_t now_us) noexcept;
    void complete_sample(std::uint64_t now_us) noexcept;
    /// False (after entering the safe state) when time went backwards.
    bool advance_time(std::uint64_t now_us) noexcept;
    void check_timeouts(std::uint64_t now_us) noexcept;
    void enter_safe_state(CommandFault reason) noexcept;

    CommandReceiverConfig config_;
    CommandFault fault_ = CommandFault::kNoSampleYet;
    bool valid_ = false;
    std::uint32_t fault_events_ = 0U;
    std::uint32_t accepted_ = 0U;
    std::uint8_t good_samples_ = 0U;  // consecutive checked good samples since the last fault (saturating)
    bool have_reference_ = false;     // a good sample gives the counter and SCT reference
    std::uint8_t reference_counter_ = 0U;
    std::uint64_t reference_time_us_ = 0U;  // completion time of the last good sample
    // The sample in progress: next_ is the index (0..5: A, A', B, B', C, C') of the frame due.
    std::size_t next_ = 0U;
    bool resync_ = true;  // waiting for an A: at start-up and after a fault, other frames are discarded
    std::uint8_t sample_counter_ = 0U;
    std::uint64_t sample_start_us_ = 0U;
    RobotCommand assembling_{};
    CanFrame part_frame_{};  // the part waiting for its copy
    std::uint64_t part_time_us_ = 0U;
    bool have_time_ = false;
    std::uint64_t last_time_us_ = 0U;
    CommandInput input_{};                // the last good sample
    CanFrame parts_[kCommandParts] = {};  // parts A, B, C of the sample in progress (the link frame's binding)
    LinkEndpoint link_;
};

}  // namespace cellguard

#endif  // CELLGUARD_CAN_COMMAND_RECEIVER_HPP
