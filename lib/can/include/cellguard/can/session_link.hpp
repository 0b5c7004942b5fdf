// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file session_link.hpp
/// Protocol 0.2: the age and replay supervision of both CAN directions, with
/// no shared clock (certification/can-safety-protocol.md, "Session link").
///
/// Each side (the controller and the PLC) owns a LinkEndpoint. With every
/// sample it sends (the controller's safety pair, the PLC's command sample)
/// it sends one link frame: its own 16-bit sequence number (+1 per sample,
/// 1..65535, wrapping 65535 -> 1), its session value (1..255, chosen at
/// start-up: a boot count or a random value, different from the previous
/// start's), and the echo of the other side's latest accepted sequence number
/// and session (0 = none yet). The endpoint records the time, on its own
/// monotonic clock, at which it sent each of its last kLinkHistory sequence
/// numbers. When a link frame of the other side arrives, the endpoint checks:
/// - session nonzero; the other side's session equal to the one it had (a
///   change is a restart of the other side: a fault, then a new reference;
///   back to the session just left is a replay and leaves the reference);
/// - the other side's sequence advanced by 1..max_sequence_step from the last
///   accepted one (0 or behind it is a repetition or a replay and leaves the
///   reference; more ahead is a loss: a fault, then the new reference);
/// - the echoed session is its own (a replay from before its own restart, or a
///   peer that has not yet heard it, fails here: the start-up handshake);
/// - the echoed sequence is one it sent among its last kLinkHistory, and not
///   older than the last echo it accepted;
/// - the round trip: now - (time it sent the echoed sequence) <= watchdog_us.
/// The other side built its frame after it had received that sequence, so
/// the data of an accepted frame is at most watchdog_us old. poll() applies
/// the same bound to the data in use: when now - (send time of the last
/// accepted echo) exceeds watchdog_us, the data is too old (a fault), so a
/// sample older than watchdog_us is never used, and the stop comes at the
/// first poll after that (within watchdog_us plus one poll period).
///
/// The link frame is bound to its sample: its E2E counter is the sample's
/// and its CRC continues over the bytes of the sample's protected frames
/// (the safety frame; command parts A, B, C), so a stale sample with a fresh
/// link frame fails the CRC. Fixed size, no heap, no OS calls: portable to the PLC.
#ifndef CELLGUARD_CAN_SESSION_LINK_HPP
#define CELLGUARD_CAN_SESSION_LINK_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/e2e_crc.hpp"

namespace cellguard {

/// Link frame layout (Intel, unsigned). Every bit is used.
namespace link_layout {
/// E2E Profile 1 CRC (byte 0), continued over the bound frames.
inline constexpr SignalLayout kCrc{"E2E_Crc", 0U, 8U, ByteOrder::kIntel, 1U, "", 255U, Multiplex::kNone, 0U};
/// E2E Profile 1 counter, 0..14: the counter of the sample the frame closes.
inline constexpr SignalLayout kCounter{"E2E_Counter", 8U, 4U, ByteOrder::kIntel, 1U, "", 14U, Multiplex::kNone, 0U};
/// Data ID bits 8..11 in kNibble mode, else 0.
inline constexpr SignalLayout kDataIdNibble{"E2E_DataIdNibble", 12U, 4U, ByteOrder::kIntel, 1U, "", 15U,
                                            Multiplex::kNone,   0U};
/// The sender's sequence number, 1..65535.
inline constexpr SignalLayout kSequence{"Sequence", 16U, 16U, ByteOrder::kIntel, 1U, "", 65535U, Multiplex::kNone, 0U};
/// The other side's latest accepted sequence number, 0 = none yet.
inline constexpr SignalLayout kEcho{"EchoSequence", 32U, 16U, ByteOrder::kIntel, 1U, "", 65535U, Multiplex::kNone, 0U};
/// The sender's session value, 1..255.
inline constexpr SignalLayout kSession{"Session", 48U, 8U, ByteOrder::kIntel, 1U, "", 255U, Multiplex::kNone, 0U};
/// The other side's session the sender accepted, 0 = none yet.
inline constexpr SignalLayout kEchoSession{"EchoSession",    56U, 8U, ByteOrder::kIntel, 1U, "", 255U,
                                           Multiplex::kNone, 0U};
/// Every signal of the link frame.
inline constexpr SignalLayout kSignals[] = {kCrc, kCounter, kDataIdNibble, kSequence, kEcho, kSession, kEchoSession};
static_assert(layout_is_consistent(kSignals), "link frame layout overlaps or overflows");
static_assert(layout_used_bits(kSignals) == ~std::uint64_t{0}, "the link frame uses every bit");
}  // namespace link_layout

/// Largest sequence number; the sequence wraps 65535 -> 1 (0 means none).
constexpr std::uint16_t kLinkSequenceMax = 65535U;
/// Sent sequence numbers whose send times an endpoint remembers.
constexpr std::size_t kLinkHistory = 32U;
/// Protocol version of the session link (major, minor) = 0.2.
constexpr std::uint8_t kProtocolVersionMinor = 2U;

/// The sequence after @p sequence (1..65535): +1, wrapping 65535 -> 1.
[[nodiscard]] constexpr std::uint16_t link_next_sequence(std::uint16_t sequence) noexcept {
    return static_cast<std::uint16_t>(sequence >= kLinkSequenceMax ? 1U : sequence + 1U);
}
/// Forward distances from this one on (32768..65534) are a sequence behind the reference: an older frame.
constexpr std::uint16_t kLinkSequenceBehind = (kLinkSequenceMax + 1U) / 2U;
/// Forward distance from @p last to @p received on the ring 1..65535 (both nonzero).
[[nodiscard]] constexpr std::uint16_t link_sequence_delta(std::uint16_t received, std::uint16_t last) noexcept {
    return static_cast<std::uint16_t>((static_cast<std::uint32_t>(received) + kLinkSequenceMax - last) %
                                      kLinkSequenceMax);
}

/// The content of a link frame.
struct LinkFields {
    std::uint16_t sequence = 0U;     ///< sender's sequence, 1..65535
    std::uint16_t echo = 0U;         ///< other side's latest accepted sequence, 0 = none
    std::uint8_t session = 0U;       ///< sender's session, 1..255
    std::uint8_t echo_session = 0U;  ///< other side's accepted session, 0 = none
};

/// Where a link frame travels and how it is protected.
struct LinkChannel {
    std::uint32_t can_id = 0x105U;                            ///< 11-bit CAN ID
    std::uint16_t data_id = 0x0F54U;                          ///< E2E data ID
    E2eP01DataIdMode data_id_mode = E2eP01DataIdMode::kBoth;  ///< how the data ID enters the CRC
};

/// Default link channel of the controller (output direction): after the separation frame's 0x104.
inline constexpr LinkChannel kDefaultControllerLinkChannel{0x105U, 0x0F54U, E2eP01DataIdMode::kBoth};
/// Default link channel of the PLC (command direction): after command part C' (0x0C6).
inline constexpr LinkChannel kDefaultPlcLinkChannel{0x0C7U, 0x0A64U, E2eP01DataIdMode::kBoth};

/// The link frame for @p fields with E2E counter @p counter, its CRC
/// continued over the 8 data bytes of each frame of @p bound.
/// kInvalidArgument for an invalid channel, counter > 14, sequence or session 0.
[[nodiscard]] Result<CanFrame> encode_link_frame(const LinkFields& fields, std::uint8_t counter,
                                                 const LinkChannel& channel, Span<const CanFrame> bound) noexcept;

/// Outcome of checking a link frame; checks run in this order.
enum class LinkFrameCheck : std::uint8_t {
    kOk = 0,                 ///< every check passed
    kWrongCanId = 1,         ///< not the channel's CAN ID
    kWrongLength = 2,        ///< DLC is not 8
    kWrongDataIdNibble = 3,  ///< kNibble mode: wrong explicit nibble
    kWrongCrc = 4,           ///< CRC over data ID, frame and bound frames differs (corrupt, or another sample's)
    kCounterMismatch = 5,    ///< counter is not the bound sample's
    kMalformedContent = 6,   ///< sequence or session 0, nibble bits outside kNibble mode
};
/// A short, static name for @p check (never nullptr).
[[nodiscard]] const char* to_string(LinkFrameCheck check) noexcept;

/// Checks @p frame as the link frame of the sample @p bound with E2E counter
/// @p counter; on kOk writes @p out. @p channel must be valid (contract).
[[nodiscard]] LinkFrameCheck check_link_frame(const CanFrame& frame, const LinkChannel& channel,
                                              Span<const CanFrame> bound, std::uint8_t counter,
                                              LinkFields& out) noexcept;

/// kInvalidArgument unless the CAN ID has 11 bits and the data ID is valid for the mode.
[[nodiscard]] Status check_link_channel(const LinkChannel& channel) noexcept;

/// Configuration of a LinkEndpoint.
struct LinkConfig {
    bool enabled = true;                              ///< off only with a stated reason in the caller's configuration
    LinkChannel own = kDefaultControllerLinkChannel;  ///< the channel this side's link frames use
    LinkChannel peer = kDefaultPlcLinkChannel;        ///< the channel the other side's link frames use
    std::uint8_t session = 1U;             ///< this start's session, 1..255 (differ from the previous start's)
    std::uint64_t watchdog_us = 300000U;   ///< longest round trip and data age, > 0
    std::uint16_t max_sequence_step = 2U;  ///< largest accepted step of the other side's sequence, 1..kLinkHistory
};

/// The controller side's default link configuration (own: the controller's channel).
[[nodiscard]] constexpr LinkConfig controller_link_config() noexcept { return LinkConfig{}; }
/// The PLC side's default link configuration: the channels swapped.
[[nodiscard]] constexpr LinkConfig plc_link_config() noexcept {
    LinkConfig c;
    c.own = kDefaultPlcLinkChannel;
    c.peer = kDefaultControllerLinkChannel;
    return c;
}

/// Why the link is not valid. Values are stable (logged).
enum class LinkFault : std::uint8_t {
    kNone = 0,              ///< the last frame passed and the data is young enough
    kNoEchoYet = 1,         ///< start-up: no frame echoing this side's session yet
    kSessionChanged = 2,    ///< the other side's session changed (it restarted) or a frame of another session
    kRepeatedSequence = 3,  ///< the other side's sequence did not advance or went back (repetition, replay)
    kSequenceJump = 4,      ///< it advanced by more than max_sequence_step (loss, insertion, old replay)
    kWrongEchoSession = 5,  ///< the echo names another session of this side (replay across its restart)
    kEchoUnknown = 6,       ///< the echo is no sequence this side sent among its last kLinkHistory
    kEchoBackwards = 7,     ///< the echo is older than the last accepted echo
    kWatchdogExpired = 8,   ///< round trip or data age above watchdog_us (unacceptable delay, loss)
};
/// A short, static name for @p fault (never nullptr).
[[nodiscard]] const char* to_string(LinkFault fault) noexcept;

/// A receiver's own fault value for link fault @p fault (not kNone): @p Fault
/// lists the eight link faults in LinkFault's order, @p no_echo_yet (kNoEchoYet's
/// counterpart) first, as CommandFault and ReceiverFault do (static_asserts where used).
template <typename Fault>
[[nodiscard]] constexpr Fault link_fault_as(LinkFault fault, Fault no_echo_yet) noexcept {
    return static_cast<Fault>(static_cast<unsigned>(no_echo_yet) + static_cast<unsigned>(fault) -
                              static_cast<unsigned>(LinkFault::kNoEchoYet));
}

/// One side's session, sequence, echo and round-trip watchdog; see the file comment.
class LinkEndpoint {
public:
    /// kInvalidArgument unless both channels are valid and differ in CAN ID,
    /// session is nonzero, watchdog_us > 0 and max_sequence_step is 1..kLinkHistory.
    [[nodiscard]] static Status check_config(const LinkConfig& config) noexcept;

    /// An endpoint that has sent nothing. @p config must pass check_config (contract).
    explicit LinkEndpoint(const LinkConfig& config) noexcept;

    /// The fields of this side's next link frame, sent at @p now_us: the next
    /// sequence (its send time recorded), the echo of the other side.
    [[nodiscard]] LinkFields next(std::uint64_t now_us) noexcept;

    /// Checks the other side's link fields @p fields, received at @p now_us;
    /// kNone when accepted. The other side's session and sequence become the
    /// reference (and the echo this side sends next) when the session and
    /// sequence checks pass, and also on a session change or a forward jump, so
    /// the next frame is checked against the latest one. A repetition leaves
    /// them, and so does, while the reference is at most watchdog_us old, a
    /// frame that would move it back: a sequence behind it (kRepeatedSequence)
    /// or the session just left (kSessionChanged); a replay cannot take the
    /// reference back across a fault. An older reference may move: any frame
    /// sent before it arrived echoes a sequence older than watchdog_us.
    [[nodiscard]] LinkFault on_peer(const LinkFields& fields, std::uint64_t now_us) noexcept;

    /// kNoEchoYet before the first accepted echo, kWatchdogExpired when the
    /// data last accepted is older than watchdog_us at @p now_us, kNone
    /// otherwise; does not change the state.
    [[nodiscard]] LinkFault age_check(std::uint64_t now_us) const noexcept;

    /// Checks @p frame as a link frame of the other side that closes no
    /// sample (a PLC in a cell without a robot sends its link frame alone):
    /// the CRC over the frame alone, its own counter; then on_peer.
    /// kSequenceJump stands for a frame that fails the frame check.
    [[nodiscard]] LinkFault on_standalone_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;

    /// Time the last accepted echo was sent, i.e. the data's age origin (0 before the first).
    [[nodiscard]] std::uint64_t data_origin_us() const noexcept { return echo_sent_us_; }
    /// Sequence of the last frame this side sent, 0 before the first.
    [[nodiscard]] std::uint16_t sequence() const noexcept { return sequence_; }
    /// The configuration in use.
    [[nodiscard]] const LinkConfig& config() const noexcept { return config_; }

private:
    [[nodiscard]] bool reference_fresh(std::uint64_t now_us) const noexcept;
    void take_reference(const LinkFields& fields, std::uint64_t now_us) noexcept;
    [[nodiscard]] LinkFault check_order(const LinkFields& fields, std::uint64_t now_us) noexcept;
    [[nodiscard]] LinkFault check_echo(const LinkFields& fields, std::uint64_t now_us) noexcept;

    LinkConfig config_;
    std::uint16_t sequence_ = 0U;  // last sent, 0 = none
    std::uint16_t sent_sequence_[kLinkHistory] = {};
    std::uint64_t sent_us_[kLinkHistory] = {};
    std::uint8_t peer_session_ = 0U;    // 0 = none
    std::uint16_t peer_sequence_ = 0U;  // the reference: last accepted (or jumped to), 0 = none
    std::uint64_t peer_us_ = 0U;        // when the reference was taken
    std::uint8_t left_session_ = 0U;    // the other side's session before its last change, 0 = none
    std::uint16_t echo_ = 0U;           // last accepted echo, 0 = none
    std::uint64_t echo_sent_us_ = 0U;
};

}  // namespace cellguard

#endif  // CELLGUARD_CAN_SESSION_LINK_HPP
