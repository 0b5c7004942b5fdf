// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file plc_receiver.hpp
/// The PLC side of the CAN safety output: checks every safety frame and its
/// inverted copy and turns any failure into the safe state (protective stop
/// requested) with a reason code. Portable, no heap, no OS calls: the
/// integrator ports this class to the PLC, feeds it every received CAN frame
/// and calls poll() every PLC cycle. Time is passed in by the caller
/// (monotonic microseconds).
///
/// Checks, in the words of EN 50325-5 (CANopen Safety) and AUTOSAR E2E:
/// - each normal frame: CAN ID, DLC, data ID, CRC, counter range and content
///   (check_safety_frame);
/// - its inverted copy: must be the next frame on the channel, equal to the
///   bitwise inverse, and arrive within the SRVT (safety-relevant validation
///   time) after the normal frame;
/// - the counter of each completed pair against the previous good pair:
///   repeated (delta 0) or jumped by more than max_delta_counter is a fault;
/// - the SCT (safeguard cycle time): a new good pair must complete within
///   sct_us of the previous one; a late pair and silence (seen by poll()) are faults;
/// - time going backwards is a fault (the caller's clock is not monotonic);
/// - protocol 0.2, the session link (session_link.hpp; on unless
///   config.link.enabled is false): each pair is closed by the controller's
///   link frame (CRC bound to the safety frame, the pair's counter, within
///   the SRVT of the safety frame); its session, sequence and echo pass the
///   PLC's LinkEndpoint, whose round trip and data age must stay within
///   link.watchdog_us (checked on every frame and poll). The PLC sends its
///   own link frames with next_link() (PlcCommandSender::next_sample).
///
/// Safe state and recovery: any failure sets communication_valid = false and
/// stop_requested = true, records the reason and drops the counter reference.
/// Recovery is automatic, as in E2E's state machine: the next good pair sets a
/// new counter reference, then recovery_good_pairs further pairs must each pass
/// every check in a row (counter delta 1..max_delta_counter, within SCT). Any
/// failure on the way starts over. At start-up the receiver is in the safe
/// state with reason kNoFrameYet and leaves it by the same rule. Restarting
/// the robot after a protective stop is the PLC's restart interlock, not this class.
///
/// While valid, the reported message is from the last good pair; the data is
/// then at most sct_us + srvt_us newer than the previous pair, and, with the
/// session link, at most link.watchdog_us old on the PLC's own clock (the
/// controller built it after it had received a link frame the PLC sent at
/// most watchdog_us before). While not valid, the reported message is
/// the safe-state message (stop, warning, fault and reduced speed set, case 0,
/// every zone intruded and unseen). While valid, stop_requested follows the
/// frame's ProtectiveStop bit; the PLC reads message.reduced_speed (meaningful
/// without a stop) and checks message.active_case against the case it commanded.
#ifndef CELLGUARD_PLC_RECEIVER_HPP
#define CELLGUARD_PLC_RECEIVER_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/can/session_link.hpp"

namespace cellguard {

/// Why the receiver is in the safe state. Values are stable (logged by PLCs).
enum class ReceiverFault : std::uint8_t {
    kNone = 0,                     ///< communication valid
    kNoFrameYet = 1,               ///< start-up: recovery not yet complete
    kWrongLength = 2,              ///< a safety frame's DLC is not 8
    kWrongCrc = 3,                 ///< CRC mismatch: corrupted data or a wrong (implicit) data ID
    kWrongDataIdNibble = 4,        ///< kNibble mode: explicit data ID nibble differs
    kCounterOutOfRange = 5,        ///< counter value 15
    kMalformedContent = 6,         ///< reserved bits, zone count or zone bits invalid
    kZoneCountMismatch = 7,        ///< zone count differs from the configured one
    kRepeatedCounter = 8,          ///< same counter as the previous good pair
    kCounterJump = 9,              ///< counter advanced by more than max_delta_counter
    kInvertedCopyMissing = 10,     ///< no copy before the next normal frame or before SRVT ran out
    kInvertedCopyMismatch = 11,    ///< the copy is not the bitwise inverse (or its DLC differs)
    kInvertedCopyLate = 12,        ///< the copy arrived after the SRVT
    kUnexpectedInvertedCopy = 13,  ///< a copy with no normal frame waiting for it
    kSctExpired = 14,              ///< no good pair within the SCT (late frame or silence)
    kTimeWentBackwards = 15,       ///< the caller's time decreased
    kLinkFrameMissing = 16,        ///< no link frame after the copy, or not within the SRVT
    kLinkFrameInvalid = 17,        ///< the link frame failed its check (CRC bound to the pair, counter, length)
    kUnexpectedLinkFrame = 18,     ///< a link frame with no pair waiting for it
    kNoEchoYet = 19,               ///< start-up: the controller has not echoed this PLC's session yet
    kSessionChanged = 20,          ///< the controller's session changed (restart, or a replay of another session)
    kRepeatedSequence = 21,        ///< the controller's sequence did not advance (replay)
    kSequenceJump = 22,            ///< the controller's sequence jumped (loss beyond the bound, old replay)
    kWrongEchoSession = 23,        ///< the echo names another session of this PLC (replay across its restart)
    kEchoUnknown = 24,             ///< the echo is no sequence this PLC sent recently
    kEchoBackwards = 25,           ///< the echo is older than the last one
    kWatchdogExpired = 26,         ///< round trip or data age above link.watchdog_us (unacceptable delay)
};
/// A short, static name for @p fault (never nullptr).
[[nodiscard]] const char* to_string(ReceiverFault fault) noexcept;

/// Configuration of a PlcReceiver; check with PlcReceiver::check_config().
struct PlcReceiverConfig {
    SafetyChannelConfig channel;            ///< CAN IDs, data IDs, data ID mode (same as the sender's)
    std::uint64_t srvt_us = 10000U;         ///< SRVT: latest copy arrival after its normal frame, > 0
    std::uint64_t sct_us = 50000U;          ///< SCT: longest time between good pairs, > srvt_us
    std::uint8_t max_delta_counter = 1U;    ///< largest accepted counter step, 1..14 (1 = no frame may be lost)
    std::uint8_t recovery_good_pairs = 2U;  ///< good pairs after the reference pair to leave the safe state, >= 1
    std::uint8_t expected_zone_count = 0U;  ///< zone count the frames must carry, 0..16
    LinkConfig link = plc_link_config();    ///< the session link (own: the PLC's link channel)
};

/// What the PLC acts on.
struct ReceiverStatus {
    bool stop_requested = true;        ///< true unless communication is valid and the frame asks no stop
    bool communication_valid = false;  ///< every check passed and recovery is complete
    ReceiverFault fault = ReceiverFault::kNoFrameYet;  ///< kNone exactly when communication_valid
    SafetyMessage message;            ///< last good content when valid, the safe-state message otherwise
    std::uint32_t fault_events = 0U;  ///< faults detected since construction (saturating)
};

/// The safe-state message for @p zone_count zones: stop, warning, fault and
/// reduced speed set, case 0, every zone intruded and unseen.
[[nodiscard]] SafetyMessage safe_state_message(std::uint8_t zone_count) noexcept;

/// Checks safety frames and their inverted copies; see the file comment.
class PlcReceiver {
public:
    /// kInvalidArgument unless the channel config is valid, 0 < srvt_us < sct_us,
    /// max_delta_counter is 1..14, recovery_good_pairs >= 1 and expected_zone_count <= 16;
    /// with the link enabled, LinkEndpoint::check_config and a peer link CAN ID
    /// that is none of the output channel's.
    [[nodiscard]] static Status check_config(const PlcReceiverConfig& config) noexcept;

    /// A receiver in the safe state (kNoFrameYet). @p config must pass check_config (contract).
    explicit PlcReceiver(const PlcReceiverConfig& config) noexcept;

    /// Processes one received frame at time @p now_us; frames with other CAN IDs
    /// than the safety frame and its copy are ignored. Returns the status.
    [[nodiscard]] ReceiverStatus on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;

    /// Applies the time checks (SRVT of a waiting frame, SCT) at @p now_us and
    /// returns the status. Call it every PLC cycle and act on its result.
    [[nodiscard]] ReceiverStatus poll(std::uint64_t now_us) noexcept;

    /// The fields of the PLC's next link frame, sent at @p now_us (its send
    /// time is recorded for the round trip): hand them to PlcCommandSender.
    [[nodiscard]] LinkFields next_link(std::uint64_t now_us) noexcept { return link_.next(now_us); }
    /// The PLC's link endpoint.
    [[nodiscard]] const LinkEndpoint& link() const noexcept { return link_; }

    /// The configuration in use.
    [[nodiscard]] const PlcReceiverConfig& config() const noexcept { return config_; }

private:
    void on_link_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;
    void accept_pair(std::uint64_t now_us) noexcept;
    void on_normal_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;
    void on_inverted_copy(const CanFrame& frame, std::uint64_t now_us) noexcept;
    /// False (after entering the safe state) when time went backwards.
    bool advance_time(std::uint64_t now_us) noexcept;
    void check_timeouts(std::uint64_t now_us) noexcept;
    void enter_safe_state(ReceiverFault reason) noexcept;
    [[nodiscard]] ReceiverStatus status() const noexcept;

    PlcReceiverConfig config_;
    ReceiverFault fault_ = ReceiverFault::kNoFrameYet;
    bool valid_ = false;
    std::uint32_t fault_events_ = 0U;
    std::uint8_t good_pairs_ = 0U;  // consecutive checked good pairs since the last fault (saturating)
    bool have_reference_ = false;   // a good pair gives the counter and SCT reference
    std::uint8_t reference_counter_ = 0U;
    std::uint64_t reference_time_us_ = 0U;  // completion time of the last good pair
    bool pending_ = false;                  // a checked normal frame waits for its copy
    CanFrame pending_frame_{};
    SafetyFrameContent pending_content_;
    std::uint64_t pending_time_us_ = 0U;
    bool have_time_ = false;
    std::uint64_t last_time_us_ = 0U;
    SafetyMessage message_;       // content of the last good pair
    bool awaiting_link_ = false;  // the pair passed; its link frame is due
    LinkEndpoint link_;
};

}  // namespace cellguard

#endif  // CELLGUARD_PLC_RECEIVER_HPP
