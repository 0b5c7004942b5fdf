// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the PLC-side receiver, protocol 0.2 (session link on), on
// arbitrary sequences of frames, polls and time steps (good pairs closed by
// the controller's link frame, the PLC's own link frames to a controller
// endpoint that echoes them, corrupted frames, copies and link frames, single
// frames and whole samples replayed, samples delivered late (made, held, then
// sent whole), the PLC's link frames lost or the time between them and the
// echo grown (delays of the round trip), a controller restart, foreign IDs and data IDs, raw garbage, time
// going backwards).
// Aborts if the receiver ever reports "no stop" without "valid", or "valid"
// for data that a fresh, independent check rejects: the pair in use (normal
// frame, copy, link frame) must pass a bitwise CRC written from the AUTOSAR
// E2E Profile 1 rules (data ID included), the counter range and the
// inverse-copy comparison, the copy and the link frame within SRVT of the
// normal frame, the pair within SCT of now; the link frame's CRC must
// continue over the normal frame's bytes with the pair's counter; its echo
// must name this PLC's session and a link frame this PLC sent at most
// watchdog_us before now (the age bound, on the PLC's clock); while valid its
// sequence must never go back (no replay); the frames after it
// a correct prefix of the next pair; the reported content the normal frame's.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "cellguard/can/plc_receiver.hpp"
#include "fuzz_reference.hpp"

using namespace cellguard;
using cellguard::fuzz::ref_p01_crc;
using cellguard::fuzz::ref_update;

namespace {

/// Independent E2E P01 check of a safety frame (CRC byte 0, counter bits 8..11, nibble bits 12..15).
bool ref_frame_ok(const CanFrame& f, const SafetyChannelConfig& c) {
    if (f.id != c.safety_can_id || f.dlc != 8U) {
        return false;
    }
    const unsigned counter = f.data[1] & 0x0FU;
    if (counter > 14U) {
        return false;
    }
    const auto hi = static_cast<std::uint8_t>(c.safety_data_id >> 8U);
    if (c.data_id_mode == E2eP01DataIdMode::kNibble && (f.data[1] >> 4U) != (hi & 0x0FU)) {
        return false;
    }
    return ref_p01_crc(f.data, c.safety_data_id, c.data_id_mode) == f.data[0];
}

bool ref_is_copy(const CanFrame& copy, const CanFrame& f, const SafetyChannelConfig& c) {
    if (copy.id != c.safety_can_id + 1U || copy.dlc != 8U) {
        return false;
    }
    for (int k = 0; k < 8; ++k) {
        if (static_cast<std::uint8_t>(copy.data[k] ^ f.data[k]) != 0xFFU) {
            return false;
        }
    }
    return true;
}

/// Independent check of a link frame bound to @p normal: the E2E P01 CRC over
/// the link channel's data ID and bytes 1..7, continued over the 8 bytes of
/// @p normal, the counter the normal frame's, the length 8.
bool ref_link_ok(const CanFrame& link, const CanFrame& normal, const LinkChannel& c) {
    if (link.id != c.can_id || link.dlc != 8U || (link.data[1] & 0x0FU) != (normal.data[1] & 0x0FU)) {
        return false;
    }
    std::uint8_t reg = ref_p01_crc(link.data, c.data_id, c.data_id_mode);
    for (const std::uint8_t b : normal.data) {
        reg = ref_update(reg, b);
    }
    return reg == link.data[0];
}

/// Sequence (bytes 2..3), echo (4..5), session (6), echoed session (7) of a link frame, read here byte by byte.
struct RefLink {
    unsigned sequence;
    unsigned echo;
    unsigned session;
    unsigned echo_session;
};
RefLink ref_link(const CanFrame& f) {
    return RefLink{static_cast<unsigned>(f.data[2] | (f.data[3] << 8U)),
                   static_cast<unsigned>(f.data[4] | (f.data[5] << 8U)), f.data[6], f.data[7]};
}

/// With CELLGUARD_FUZZ_STATS set, reports at exit how often the oracle saw a valid status.
struct Stats {
    std::uint64_t statuses = 0U;
    std::uint64_t valid = 0U;
    std::uint64_t no_stop = 0U;
    Stats() = default;
    Stats(const Stats&) = delete;
    Stats& operator=(const Stats&) = delete;
    ~Stats() {
        if (std::getenv("CELLGUARD_FUZZ_STATS") != nullptr) {
            std::fprintf(stderr, "statuses checked: %llu, valid: %llu, valid without stop: %llu\n",
                         static_cast<unsigned long long>(statuses), static_cast<unsigned long long>(valid),
                         static_cast<unsigned long long>(no_stop));
        }
    }
};
Stats g_stats;  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables): fuzz statistics

struct Seen {
    CanFrame frame;
    std::uint64_t time;
};

/// The frames on the pair's IDs (normal, copy, link) the oracle remembers, newest last.
constexpr std::size_t kHistory = 5U;
/// Every link frame the PLC sends in one input (at most one a step, 256 steps): the oracle finds the send
/// time of any echo, however many frames were sent since without time passing.
constexpr std::size_t kSentHistory = 1024U;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    PlcReceiverConfig config;
    config.channel.data_id_mode = static_cast<E2eP01DataIdMode>(in.ConsumeIntegralInRange<int>(0, 3));
    config.srvt_us = 5000U;
    config.sct_us = 20000U;
    config.max_delta_counter = in.ConsumeIntegralInRange<std::uint8_t>(1U, 3U);
    config.recovery_good_pairs = in.ConsumeIntegralInRange<std::uint8_t>(1U, 3U);
    config.expected_zone_count = in.ConsumeIntegralInRange<std::uint8_t>(0U, 16U);
    config.link.session = in.ConsumeIntegralInRange<std::uint8_t>(1U, 255U);
    config.link.watchdog_us = in.ConsumeIntegralInRange<std::uint32_t>(1000U, 60000U);
    config.link.max_sequence_step = in.ConsumeIntegralInRange<std::uint16_t>(1U, 3U);
    PlcReceiver receiver(config);
    const SafetyChannelConfig& ch = config.channel;
    const LinkChannel& link_ch = config.link.peer;  // the controller's link channel

    // The controller's side of the link: echoes the PLC's link frames it gets; restarts with a new session.
    LinkConfig ctrl_config = controller_link_config();
    ctrl_config.session = in.ConsumeIntegralInRange<std::uint8_t>(1U, 255U);
    ctrl_config.watchdog_us = 1000000000U;  // the controller's own checks do not matter here
    LinkEndpoint controller(ctrl_config);

    std::uint64_t now = 1000000U;
    std::uint8_t counter = 0U;
    CanFrame last_normal{ch.safety_can_id, 8U, {}};
    Seen history[kHistory] = {};  // the last frames on the pair's IDs (normal, copy, link), newest last
    std::size_t seen = 0U;
    CanFrame replay[4] = {};
    std::size_t replay_count = 0U;
    CanFrame samples[4][2] = {};  // whole samples sent (normal, link), for replays
    std::size_t sample_count = 0U;
    CanFrame queue[3] = {};  // a replayed sample being delivered, one frame a step
    std::size_t queued = 0U;
    std::size_t queue_next = 0U;
    std::uint16_t sent_sequence[kSentHistory] = {};  // the PLC's link frames: sequence and send time
    std::uint64_t sent_us[kSentHistory] = {};
    std::size_t sent_count = 0U;
    bool have_valid_sequence = false;
    unsigned valid_sequence = 0U;  // of the newest pair in use since the controller's last restart
    unsigned valid_session = 0U;

    for (int step = 0; step < 256 && (queued > queue_next || in.remaining_bytes() > 0U); ++step) {
        CanFrame f{};
        bool deliver = true;
        const int op = queued > queue_next ? -1 : in.ConsumeIntegralInRange<int>(0, 14);
        switch (op) {
            case -1:  // the next frame of a replayed sample
                f = queue[queue_next++];
                queued = queue_next == queued ? 0U : queued;
                queue_next = queued == 0U ? 0U : queue_next;
                break;
            case 0:  // time passes, with or without a poll (up to twice the largest watchdog time: a delay)
                now += in.ConsumeBool() ? in.ConsumeIntegralInRange<std::uint32_t>(0U, 30000U)
                                        : in.ConsumeIntegralInRange<std::uint32_t>(0U, 120000U);
                deliver = false;
                if (in.ConsumeBool()) {
                    continue;  // unobserved: the next frame or poll sees the time
                }
                break;
            case 1: {  // a well-formed frame; the counter advances, repeats, skips or jumps
                switch (in.ConsumeIntegralInRange<int>(0, 3)) {
                    case 0: counter = e2e_p01_next_counter(counter); break;
                    case 1: break;
                    case 2:
                        counter = static_cast<std::uint8_t>((counter + in.ConsumeIntegralInRange<int>(2, 4)) % 15);
                        break;
                    default: counter = in.ConsumeIntegralInRange<std::uint8_t>(0U, 14U); break;
                }
                SafetyMessage m;
                m.zone_count = in.ConsumeBool() ? config.expected_zone_count
                                                : in.ConsumeIntegralInRange<std::uint8_t>(0U, 16U);
                const auto zones = static_cast<std::uint16_t>((1U << m.zone_count) - 1U);
                m.protective_stop = in.ConsumeBool();
                m.warning = in.ConsumeBool();
                m.fault = in.ConsumeBool();
                m.zone_intrusion = static_cast<std::uint16_t>(in.ConsumeIntegral<std::uint16_t>() & zones);
                m.zone_unseen = static_cast<std::uint16_t>(in.ConsumeIntegral<std::uint16_t>() & zones);
                f = encode_safety_frame(m, counter, ch).value();
                last_normal = f;
                break;
            }
            case 2: f = inverted_copy(last_normal); break;
            case 3: {  // raw bytes on a chosen or random ID
                const int which = in.ConsumeIntegralInRange<int>(0, 4);
                f.id = which == 0   ? ch.safety_can_id
                       : which == 1 ? ch.safety_can_id + 1U
                       : which == 2 ? ch.diagnostics_can_id
                       : which == 3 ? link_ch.can_id
                                    : in.ConsumeIntegralInRange<std::uint32_t>(0U, 0x7FFU);
                f.dlc = in.ConsumeIntegralInRange<std::uint8_t>(0U, 15U);
                for (std::uint8_t& b : f.data) {
                    b = in.ConsumeIntegral<std::uint8_t>();
                }
                break;
            }
            case 4:  // the last frame, its copy or the last link frame, with one bit flipped
            case 5: {
                const int which = in.ConsumeIntegralInRange<int>(0, 2);
                f = which == 0                         ? last_normal
                    : which == 1 || sample_count == 0U ? inverted_copy(last_normal)
                                                       : samples[(sample_count - 1U) % 4U][1];
                const unsigned bit = in.ConsumeIntegralInRange<unsigned>(0U, 63U);
                f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] ^ (1U << (bit % 8U)));
                break;
            }
            case 6: {  // poll
                deliver = false;
                break;
            }
            case 7:  // replay an earlier frame of the pair's IDs
                if (replay_count == 0U) {
                    deliver = false;
                } else {
                    f = replay[in.ConsumeIntegralInRange<std::size_t>(0U, replay_count - 1U)];
                }
                break;
            case 8:  // time goes backwards
                now -= in.ConsumeIntegralInRange<std::uint64_t>(0U, 1000U);
                deliver = false;
                break;
            case 9: {  // masquerade: the same content under another data ID or data ID mode
                SafetyChannelConfig other = ch;
                other.safety_data_id = in.ConsumeIntegralInRange<std::uint16_t>(0U, 0x0FFFU);
                other.data_id_mode = static_cast<E2eP01DataIdMode>(in.ConsumeIntegralInRange<int>(0, 3));
                other.diagnostics_data_id = static_cast<std::uint16_t>(other.safety_data_id ^ 0x0A5AU);
                const Result<CanFrame> r = encode_safety_frame(SafetyMessage{}, counter, other);
                if (!r.ok()) {
                    deliver = false;
                } else {
                    f = r.value();
                }
                break;
            }
            case 10: {  // the PLC sends its link frame; the controller gets it after the delay the time steps made
                const LinkFields sent = receiver.next_link(now);
                sent_sequence[sent_count % kSentHistory] = sent.sequence;
                sent_us[sent_count % kSentHistory] = now;
                ++sent_count;
                if (in.ConsumeBool()) {  // not lost
                    static_cast<void>(controller.on_peer(sent, now));
                }
                deliver = false;
                break;
            }
            case 11: {  // the controller's link frame closing the last normal frame's pair
                const CanFrame bound[1] = {last_normal};
                const Result<CanFrame> r = encode_link_frame(controller.next(now),
                                                             static_cast<std::uint8_t>(last_normal.data[1] & 0x0FU),
                                                             link_ch, Span<const CanFrame>(bound));
                if (!r.ok()) {
                    deliver = false;
                    break;
                }
                f = r.value();
                samples[sample_count % 4U][0] = last_normal;
                samples[sample_count % 4U][1] = f;
                ++sample_count;
                break;
            }
            case 12:  // a whole earlier sample replayed: normal frame, copy, link frame
                if (sample_count == 0U) {
                    deliver = false;
                    break;
                } else {
                    const std::size_t k = in.ConsumeIntegralInRange<std::size_t>(
                        0U, sample_count < 4U ? sample_count - 1U : 3U);
                    queue[0] = samples[k][0];
                    queue[1] = inverted_copy(samples[k][0]);
                    queue[2] = samples[k][1];
                    queued = 3U;
                    queue_next = 0U;
                    deliver = false;
                }
                break;
            case 13: {  // a delayed sample: made now (the next counter, its link frame's echo now), held for case 12
                counter = e2e_p01_next_counter(counter);
                SafetyMessage m;
                m.zone_count = config.expected_zone_count;
                m.protective_stop = in.ConsumeBool();
                const CanFrame normal = encode_safety_frame(m, counter, ch).value();
                const CanFrame bound[1] = {normal};
                const Result<CanFrame> r = encode_link_frame(controller.next(now), counter, link_ch,
                                                             Span<const CanFrame>(bound));
                if (r.ok()) {
                    samples[sample_count % 4U][0] = normal;
                    samples[sample_count % 4U][1] = r.value();
                    ++sample_count;
                }
                deliver = false;
                break;
            }
            default: {  // the controller restarts: a new session, its sequence from 1 again
                ctrl_config.session = static_cast<std::uint8_t>(ctrl_config.session % 255U + 1U);
                controller = LinkEndpoint(ctrl_config);
                have_valid_sequence = false;  // its sequence starts again; its session values wrap after 255 restarts
                deliver = false;
                break;
            }
        }

        ReceiverStatus s;
        if (deliver) {
            s = receiver.on_frame(f, now);
            if (f.id == ch.safety_can_id || f.id == ch.safety_can_id + 1U || f.id == link_ch.can_id) {
                for (std::size_t i = 1U; i < kHistory; ++i) {
                    history[i - 1U] = history[i];
                }
                history[kHistory - 1U] = Seen{f, now};
                seen = seen < kHistory ? seen + 1U : kHistory;
                replay[replay_count < 4U ? replay_count : static_cast<std::size_t>(step % 4)] = f;
                replay_count = replay_count < 4U ? replay_count + 1U : 4U;
            }
        } else {
            s = receiver.poll(now);
        }

        // The oracle.
        ++g_stats.statuses;
        g_stats.valid += s.communication_valid ? 1U : 0U;
        g_stats.no_stop += s.stop_requested ? 0U : 1U;
        ORACLE(s.stop_requested || s.communication_valid);
        ORACLE(s.communication_valid == (s.fault == ReceiverFault::kNone));
        if (!s.communication_valid) {
            ORACLE(s.stop_requested);
            continue;
        }
        // The newest link frame closes the pair in use; after it at most the next normal frame and its copy.
        const Seen* h = history + (kHistory - seen);
        std::size_t link_at = seen;
        for (std::size_t i = seen; i > 0U; --i) {
            if (h[i - 1U].frame.id == link_ch.can_id) {
                link_at = i - 1U;
                break;
            }
        }
        ORACLE(link_at < seen && link_at >= 2U);
        const Seen& normal = h[link_at - 2U];
        const Seen& copy = h[link_at - 1U];
        const Seen& link = h[link_at];
        ORACLE(ref_frame_ok(normal.frame, ch));
        ORACLE(ref_is_copy(copy.frame, normal.frame, ch));
        ORACLE(copy.time >= normal.time && copy.time - normal.time <= config.srvt_us);
        ORACLE(link.time >= normal.time && link.time - normal.time <= config.srvt_us);
        ORACLE(ref_link_ok(link.frame, normal.frame, link_ch));
        ORACLE(now >= link.time && now - link.time <= config.sct_us);
        // The age bound: the echo names this PLC's session and a link frame it sent at most watchdog_us ago.
        const RefLink l = ref_link(link.frame);
        ORACLE(l.echo_session == config.link.session && l.session != 0U && l.sequence != 0U);
        bool found = false;
        for (std::size_t i = 0U; i < kSentHistory && i < sent_count; ++i) {
            const std::size_t slot = (sent_count - 1U - i) % kSentHistory;
            if (sent_sequence[slot] == l.echo) {
                found = true;
                ORACLE(now >= sent_us[slot] && now - sent_us[slot] <= config.link.watchdog_us);
                break;
            }
        }
        ORACLE(found);
        // No replay, across faults too: within one session of the controller the sequence in use never goes
        // back (the endpoint keeps its reference against frames behind it; fewer than 32768 frames here).
        if (have_valid_sequence && l.session == valid_session) {
            ORACLE(l.sequence >= valid_sequence);
        }
        have_valid_sequence = true;
        valid_session = l.session;
        valid_sequence = l.sequence;
        // What follows the link frame: nothing, the next normal frame, or it and its copy, within the SRVT.
        const std::size_t after = seen - 1U - link_at;
        ORACLE(after <= 2U);
        if (after >= 1U) {
            ORACLE(ref_frame_ok(h[link_at + 1U].frame, ch));
            ORACLE(now >= h[link_at + 1U].time && now - h[link_at + 1U].time <= config.srvt_us);
        }
        if (after == 2U) {
            ORACLE(ref_is_copy(h[link_at + 2U].frame, h[link_at + 1U].frame, ch));
        }
        // The reported content is the normal frame's.
        const CanFrame& n = normal.frame;
        ORACLE(s.message.protective_stop == ((n.data[2] & 0x01U) != 0U));
        ORACLE(s.message.warning == ((n.data[2] & 0x02U) != 0U));
        ORACLE(s.message.fault == ((n.data[2] & 0x04U) != 0U));
        ORACLE(s.message.zone_intrusion == static_cast<std::uint16_t>(n.data[3] | (n.data[4] << 8U)));
        ORACLE(s.message.zone_unseen == static_cast<std::uint16_t>(n.data[5] | (n.data[6] << 8U)));
        ORACLE(s.message.zone_count == n.data[7] && n.data[7] == config.expected_zone_count);
        ORACLE(s.stop_requested == ((n.data[2] & 0x01U) != 0U));
    }
    return 0;
}
