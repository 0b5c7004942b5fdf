// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the controller's command receiver, protocol 0.2 (session link
// on), on arbitrary sequences of command frames, polls and time steps (good
// samples frame by frame closed by the PLC's link frame, the controller's own
// link frames to a PLC endpoint that echoes them, parts, copies and link
// frames out of order, repeated, corrupted, under other data IDs, raw garbage
// on any ID, single frames and whole samples replayed, delays between the
// controller's link frame and the echo, a PLC restart, parts of the previous
// sample or with another counter mixed in, samples abandoned half-way, time
// going backwards).
// Aborts if the receiver ever reports "valid" for data that a fresh,
// independent check rejects: the last seven frames on the command and PLC
// link IDs before any sample in progress must be A, A', B, B', C, C' and the
// link frame of one sample, each part passing a bitwise CRC written from the
// AUTOSAR E2E Profile 1 rules with its own data ID, its counter range and
// reserved bits, each copy the inverse of its part within the SRVT, all three
// with one counter, the link frame's CRC continued over parts A, B and C with
// that counter, the sample within its window and within the SCT of now, the
// link frame's echo naming this controller's session and a link frame it sent
// at most watchdog_us before now (the age bound, on the controller's clock),
// while valid its sequence never going back (no replay), the frames in
// progress a correct prefix of the next sample; and the reported command and
// counter must be that sample's (decoded here byte by byte), with a counter
// step of 1..max_delta_counter from the previous valid report.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "cellguard/can/command_receiver.hpp"
#include "fuzz_reference.hpp"

using namespace cellguard;
using cellguard::fuzz::ref_p01_crc;
using cellguard::fuzz::ref_update;

namespace {

std::int16_t ref_joint(const CanFrame& f, int byte) {
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(f.data[byte] | (f.data[byte + 1] << 8U)));
}

/// Independent check of command part @p part (0..2): ID, DLC, P01 CRC with the part's data ID, counter, nibble.
bool ref_part_ok(const CanFrame& f, int part, const CommandChannelConfig& c) {
    if (f.id != c.base_can_id + 2U * static_cast<unsigned>(part) || f.dlc != 8U) {
        return false;
    }
    const unsigned counter = f.data[1] & 0x0FU;
    const unsigned nibble = f.data[1] >> 4U;
    if (counter > 14U) {
        return false;
    }
    const std::uint16_t id = c.data_id[part];
    const auto hi = static_cast<std::uint8_t>(id >> 8U);
    if (nibble != (c.data_id_mode == E2eP01DataIdMode::kNibble ? (hi & 0x0FU) : 0U)) {
        return false;
    }
    if (ref_p01_crc(f.data, id, c.data_id_mode) != f.data[0]) {
        return false;
    }
    if (part == 0 && ((f.data[2] & 0x80U) != 0U || (f.data[3] & 0xF8U) != 0U)) {
        return false;  // reserved bits of part A: 23 and 27..31 (22 is ResetRequest)
    }
    for (int byte = (part == 0 ? 4 : 2); byte < (part == 2 ? 6 : 8); byte += 2) {
        if (ref_joint(f, byte) == -32768) {
            return false;
        }
    }
    return true;
}

bool ref_is_copy(const CanFrame& copy, const CanFrame& f) {
    if (copy.id != f.id + 1U || copy.dlc != 8U) {
        return false;
    }
    for (int k = 0; k < 8; ++k) {
        if (static_cast<std::uint8_t>(copy.data[k] ^ f.data[k]) != 0xFFU) {
            return false;
        }
    }
    return true;
}

/// The command of a checked sample (parts at a, b, c), decoded byte by byte.
RobotCommand ref_decode(const CanFrame& a, const CanFrame& b, const CanFrame& c) {
    RobotCommand r;
    r.monitoring_case = static_cast<std::uint8_t>(a.data[2] & 0x0FU);
    r.speed_class = static_cast<std::uint8_t>((a.data[2] >> 4U) & 0x03U);
    r.reset_request = (a.data[2] & 0x40U) != 0U;
    r.joint_count = static_cast<std::uint8_t>(a.data[3] & 0x07U);
    r.joint_raw[0] = ref_joint(a, 4);
    r.joint_raw[1] = ref_joint(a, 6);
    r.joint_raw[2] = ref_joint(b, 2);
    r.joint_raw[3] = ref_joint(b, 4);
    r.joint_raw[4] = ref_joint(b, 6);
    r.joint_raw[5] = ref_joint(c, 2);
    r.joint_raw[6] = ref_joint(c, 4);
    r.robot_id = static_cast<std::uint16_t>(c.data[6] | (c.data[7] << 8U));
    return r;
}

struct Seen {
    CanFrame frame;
    std::uint64_t time;
};

constexpr std::size_t kSampleFrames = kCommandFramesPerSample + 1U;  // A, A', B, B', C, C' and the PLC's link frame
constexpr std::size_t kHistory = 2U * kSampleFrames - 1U;  // a complete sample and six frames of one in progress
// Every link frame the controller sends in one input (at most one a step, 512 steps): the oracle
// finds the send time of any echo, however many frames were sent since without time passing.
constexpr std::size_t kSentHistory = 1024U;

/// The controller's link frames: sequence and send time (the age bound's reference).
struct Sent {
    std::uint16_t sequence[kSentHistory] = {};
    std::uint64_t us[kSentHistory] = {};
    std::size_t count = 0U;
};

/// Independent check of the PLC's link frame closing parts @p a, @p b, @p c:
/// the E2E P01 CRC over the link channel's data ID and bytes 1..7, continued
/// over the 8 bytes of each part, the counter part A's, the length 8.
bool ref_link_ok(const CanFrame& link, const CanFrame& a, const CanFrame& b, const CanFrame& c, const LinkChannel& ch) {
    if (link.id != ch.can_id || link.dlc != 8U || (link.data[1] & 0x0FU) != (a.data[1] & 0x0FU)) {
        return false;
    }
    std::uint8_t reg = ref_p01_crc(link.data, ch.data_id, ch.data_id_mode);
    for (const CanFrame* part : {&a, &b, &c}) {
        for (const std::uint8_t byte : part->data) {
            reg = ref_update(reg, byte);
        }
    }
    return reg == link.data[0];
}

/// With CELLGUARD_FUZZ_STATS set, reports at exit how often the oracle saw a valid status.
struct Stats {
    std::uint64_t statuses = 0U;
    std::uint64_t valid = 0U;
    Stats() = default;
    Stats(const Stats&) = delete;
    Stats& operator=(const Stats&) = delete;
    ~Stats() {
        if (std::getenv("CELLGUARD_FUZZ_STATS") != nullptr) {
            std::fprintf(stderr, "statuses checked: %llu, valid: %llu\n", static_cast<unsigned long long>(statuses),
                         static_cast<unsigned long long>(valid));
        }
    }
};
Stats g_stats;  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables): fuzz statistics

RobotCommand fuzzed_command(FuzzedDataProvider& in) {
    RobotCommand c;
    c.monitoring_case = in.ConsumeIntegralInRange<std::uint8_t>(0U, 15U);
    c.speed_class = in.ConsumeIntegralInRange<std::uint8_t>(0U, 3U);
    c.joint_count = in.ConsumeIntegralInRange<std::uint8_t>(0U, 7U);
    c.robot_id = in.ConsumeIntegral<std::uint16_t>();
    for (std::size_t j = 0U; j < c.joint_count; ++j) {
        c.joint_raw[j] = in.ConsumeIntegralInRange<std::int16_t>(-32767, 32767);
    }
    c.reset_request = in.ConsumeBool();
    return c;
}

/// The oracle for a valid status: see the file comment. Returns the link frame's session (bits 16..23) and
/// sequence (bits 0..15).
unsigned check_valid(const CommandPoll& p, const Seen* history, std::size_t seen, std::uint64_t now,
                     const CommandReceiverConfig& config, const Sent& sent) {
    const CommandChannelConfig& ch = config.channel;
    const LinkChannel& link_ch = config.link.peer;
    // The newest PLC link frame ends the sample; frames after it are a sample in progress.
    std::size_t end = seen;  // index one past the sample's link frame
    while (end > 0U && history[end - 1U].frame.id != link_ch.can_id) {
        --end;
    }
    ORACLE(end >= kSampleFrames);
    const std::size_t progress = seen - end;
    ORACLE(progress <= kCommandFramesPerSample);
    const Seen* s = history + (end - kSampleFrames);
    for (int part = 0; part < 3; ++part) {
        const Seen& f = s[2 * part];
        const Seen& copy = s[2 * part + 1];
        ORACLE(ref_part_ok(f.frame, part, ch));
        ORACLE(ref_is_copy(copy.frame, f.frame));
        ORACLE(copy.time >= f.time && copy.time - f.time <= config.srvt_us);
        ORACLE((f.frame.data[1] & 0x0FU) == (s[0].frame.data[1] & 0x0FU));
    }
    const Seen& link = s[kCommandFramesPerSample];
    ORACLE(ref_link_ok(link.frame, s[0].frame, s[2].frame, s[4].frame, link_ch));
    ORACLE(link.time >= s[5].time && link.time - s[0].time <= config.sample_window_us);
    ORACLE(now >= link.time && now - link.time <= config.sct_us);
    // The age bound: the echo names this controller's session and a link frame it sent at most watchdog_us ago.
    const unsigned sequence = static_cast<unsigned>(link.frame.data[2] | (link.frame.data[3] << 8U));
    const unsigned echo = static_cast<unsigned>(link.frame.data[4] | (link.frame.data[5] << 8U));
    ORACLE(link.frame.data[7] == config.link.session && link.frame.data[6] != 0U && sequence != 0U);
    bool found = false;
    for (std::size_t i = 0U; i < kSentHistory && i < sent.count; ++i) {
        const std::size_t slot = (sent.count - 1U - i) % kSentHistory;
        if (sent.sequence[slot] == echo) {
            found = true;
            ORACLE(now >= sent.us[slot] && now - sent.us[slot] <= config.link.watchdog_us);
            break;
        }
    }
    ORACLE(found);
    const RobotCommand expected = ref_decode(s[0].frame, s[2].frame, s[4].frame);
    for (std::size_t j = expected.joint_count; j < kMaxCommandJoints; ++j) {
        ORACLE(expected.joint_raw[j] == 0);
    }
    ORACLE(p.input.valid);
    ORACLE(p.input.command == expected);
    ORACLE(p.input.counter == (s[0].frame.data[1] & 0x0FU));
    ORACLE(p.input.received_us == link.time);
    // The sample in progress is a correct prefix of the next one, within its limits.
    const Seen* n = history + end;
    for (std::size_t i = 0U; i < progress; ++i) {
        ORACLE(n[i].frame.id == ch.base_can_id + i);
        if (i % 2U == 0U) {
            ORACLE(ref_part_ok(n[i].frame, static_cast<int>(i / 2U), ch));
            ORACLE((n[i].frame.data[1] & 0x0FU) == (n[0].frame.data[1] & 0x0FU));
        } else {
            ORACLE(ref_is_copy(n[i].frame, n[i - 1U].frame));
            ORACLE(n[i].time - n[i - 1U].time <= config.srvt_us);
        }
        ORACLE(now - n[0].time <= config.sample_window_us);
    }
    if (progress % 2U == 1U) {
        ORACLE(now - n[progress - 1U].time <= config.srvt_us);
    }
    return (static_cast<unsigned>(link.frame.data[6]) << 16U) | sequence;
}

/// The seven frames of a sample of @p command with counter @p counter: the PLC's link frame from @p plc.
void make_sample(CanFrame (&out)[kSampleFrames], const RobotCommand& command, std::uint8_t counter,
                 const CommandChannelConfig& ch, LinkEndpoint& plc, std::uint64_t now) {
    const CommandFrames frames = encode_command_sample(command, counter, ch).value();
    for (std::size_t i = 0U; i < kCommandFramesPerSample; ++i) {
        out[i] = frames.frame[i];
    }
    const CanFrame parts[3] = {frames.frame[0], frames.frame[2], frames.frame[4]};
    out[kCommandFramesPerSample] =
        encode_link_frame(plc.next(now), counter, plc.config().own, Span<const CanFrame>(parts)).value();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    CommandReceiverConfig config;
    config.channel.data_id_mode = static_cast<E2eP01DataIdMode>(in.ConsumeIntegralInRange<int>(0, 3));
    config.srvt_us = 5000U;
    config.sample_window_us = 12000U;
    config.sct_us = 40000U;
    config.max_delta_counter = in.ConsumeIntegralInRange<std::uint8_t>(1U, 3U);
    config.recovery_good_samples = in.ConsumeIntegralInRange<std::uint8_t>(1U, 3U);
    config.link.session = in.ConsumeIntegralInRange<std::uint8_t>(1U, 255U);
    config.link.watchdog_us = in.ConsumeIntegralInRange<std::uint32_t>(1000U, 80000U);
    config.link.max_sequence_step = in.ConsumeIntegralInRange<std::uint16_t>(1U, 3U);
    CommandReceiver receiver(config);
    const CommandChannelConfig& ch = config.channel;

    // The PLC's side of the link: echoes the controller's link frames it gets; restarts with a new session.
    LinkConfig plc_config = plc_link_config();
    plc_config.session = in.ConsumeIntegralInRange<std::uint8_t>(1U, 255U);
    plc_config.watchdog_us = 1000000000U;  // the PLC's own checks do not matter here
    LinkEndpoint plc(plc_config);
    Sent sent;

    std::uint64_t now = 1000000U;
    std::uint8_t counter = 0U;
    CanFrame sample[kSampleFrames] = {};
    make_sample(sample, RobotCommand{}, counter, ch, plc, now);
    CanFrame previous[kSampleFrames] = {};
    CanFrame mixed[kSampleFrames] = {};
    for (std::size_t i = 0U; i < kSampleFrames; ++i) {
        previous[i] = sample[i];
        mixed[i] = sample[i];
    }
    CanFrame queue[kSampleFrames] = {};  // a replayed sample being delivered, one frame a step
    std::size_t queued = 0U;
    std::size_t queue_next = 0U;
    std::size_t next = 0U;  // the frame of `sample` to send next
    Seen history[kHistory] = {};
    std::size_t seen = 0U;
    CanFrame replay[4] = {};
    std::size_t replay_count = 0U;
    bool was_valid = false;
    std::uint8_t last_counter = 0U;
    unsigned used = 0U;  // session << 16 | sequence of the newest sample in use since the PLC's last restart, 0 = none

    for (int step = 0; step < 512 && (queued > queue_next || in.remaining_bytes() > 0U); ++step) {
        CanFrame f{};
        bool deliver = true;
        const int op = queued > queue_next ? -1 : in.ConsumeIntegralInRange<int>(0, 16);
        switch (op) {
            case -1:  // the next frame of a replayed sample
                f = queue[queue_next++];
                if (queue_next == queued) {
                    queued = 0U;
                    queue_next = 0U;
                }
                break;
            case 0:  // time passes, with or without a poll (up to twice the largest watchdog time: a delay)
                now += in.ConsumeBool() ? in.ConsumeIntegralInRange<std::uint32_t>(0U, 50000U)
                                        : in.ConsumeIntegralInRange<std::uint32_t>(0U, 160000U);
                deliver = false;
                if (in.ConsumeBool()) {
                    continue;
                }
                break;
            case 1:  // a new sample: the counter advances, repeats, skips or jumps
                switch (in.ConsumeIntegralInRange<int>(0, 3)) {
                    case 0: counter = e2e_p01_next_counter(counter); break;
                    case 1: break;
                    case 2:
                        counter = static_cast<std::uint8_t>((counter + in.ConsumeIntegralInRange<int>(2, 4)) % 15);
                        break;
                    default: counter = in.ConsumeIntegralInRange<std::uint8_t>(0U, 14U); break;
                }
                for (std::size_t i = 0U; i < kSampleFrames; ++i) {
                    previous[i] = sample[i];
                }
                make_sample(sample, fuzzed_command(in), counter, ch, plc, now);
                next = 0U;
                [[fallthrough]];
            case 2:  // the next frame of the sample, shortly after the previous one
            case 3:
            case 4:
                now += in.ConsumeIntegralInRange<std::uint32_t>(0U, 3000U);
                f = sample[next];
                next = (next + 1U) % kSampleFrames;
                break;
            case 5:  // any frame of the sample: reordered or repeated
                f = sample[in.ConsumeIntegralInRange<std::size_t>(0U, kSampleFrames - 1U)];
                break;
            case 6: {  // raw bytes on a command ID, the PLC's link ID or any ID
                switch (in.ConsumeIntegralInRange<int>(0, 2)) {
                    case 0: f.id = ch.base_can_id + in.ConsumeIntegralInRange<std::uint32_t>(0U, 5U); break;
                    case 1: f.id = config.link.peer.can_id; break;
                    default: f.id = in.ConsumeIntegralInRange<std::uint32_t>(0U, 0x7FFU); break;
                }
                f.dlc = in.ConsumeIntegralInRange<std::uint8_t>(0U, 15U);
                for (std::uint8_t& b : f.data) {
                    b = in.ConsumeIntegral<std::uint8_t>();
                }
                break;
            }
            case 7: {  // a frame of the sample with one bit flipped
                f = sample[in.ConsumeIntegralInRange<std::size_t>(0U, kSampleFrames - 1U)];
                const unsigned bit = in.ConsumeIntegralInRange<unsigned>(0U, 63U);
                f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] ^ (1U << (bit % 8U)));
                break;
            }
            case 8:  // replay an earlier frame
                if (replay_count == 0U) {
                    deliver = false;
                } else {
                    f = replay[in.ConsumeIntegralInRange<std::size_t>(0U, replay_count - 1U)];
                }
                break;
            case 9:  // time goes backwards
                now -= in.ConsumeIntegralInRange<std::uint64_t>(0U, 1000U);
                deliver = false;
                break;
            case 10: {  // masquerade: a part under another data ID or mode, with another counter, or of another command
                CommandChannelConfig other = ch;
                const std::size_t part = in.ConsumeIntegralInRange<std::size_t>(0U, 2U);
                std::uint8_t other_counter = counter;
                switch (in.ConsumeIntegralInRange<int>(0, 2)) {
                    case 0:
                        other.data_id[part] = in.ConsumeIntegralInRange<std::uint16_t>(0U, 0x0FFFU);
                        other.data_id_mode = static_cast<E2eP01DataIdMode>(in.ConsumeIntegralInRange<int>(0, 3));
                        break;
                    case 1: other_counter = in.ConsumeIntegralInRange<std::uint8_t>(0U, 14U); break;
                    default: break;  // the same counter and data ID, another command: parts of two commands mixed
                }
                const Result<CommandFrames> r = encode_command_sample(fuzzed_command(in), other_counter, other);
                if (!r.ok()) {
                    deliver = false;
                } else {
                    f = r.value().frame[2U * part + (in.ConsumeBool() ? 1U : 0U)];
                }
                break;
            }
            case 12: {  // splice: the rest of the sample in progress comes from another command, same counter
                const CommandFrames other = encode_command_sample(fuzzed_command(in), counter, ch).value();
                for (std::size_t i = next + (next % 2U); i < kCommandFramesPerSample; ++i) {
                    sample[i] = other.frame[i];  // the link frame stays bound to the original parts
                }
                deliver = false;
                break;
            }
            case 11:  // a frame of the previous sample: parts of two samples mixed
                f = previous[in.ConsumeIntegralInRange<std::size_t>(0U, kSampleFrames - 1U)];
                break;
            case 13: {  // the controller sends its link frame; the PLC gets it (or it is lost)
                const LinkFields fields = receiver.link().next(now);
                sent.sequence[sent.count % kSentHistory] = fields.sequence;
                sent.us[sent.count % kSentHistory] = now;
                ++sent.count;
                if (in.ConsumeBool()) {
                    static_cast<void>(plc.on_peer(fields, now));
                }
                deliver = false;
                break;
            }
            case 14:  // a whole earlier sample replayed, frame by frame
                for (std::size_t i = 0U; i < kSampleFrames; ++i) {
                    queue[i] = in.ConsumeBool() ? previous[i] : mixed[i];
                }
                queued = kSampleFrames;
                queue_next = 0U;
                deliver = false;
                break;
            case 15:  // keep the current sample for a later replay
                for (std::size_t i = 0U; i < kSampleFrames; ++i) {
                    mixed[i] = sample[i];
                }
                deliver = false;
                break;
            default: {  // the PLC restarts: a new session, its sequence from 1 again
                plc_config.session = static_cast<std::uint8_t>(plc_config.session % 255U + 1U);
                plc = LinkEndpoint(plc_config);
                used = 0U;  // its sequence starts again; its session values wrap after 255 restarts
                deliver = false;
                break;
            }
        }

        if (deliver) {
            (void)receiver.on_frame(f, now);
            if ((f.id >= ch.base_can_id && f.id < ch.base_can_id + kCommandFramesPerSample) ||
                f.id == config.link.peer.can_id) {
                if (seen == kHistory) {
                    for (std::size_t i = 1U; i < kHistory; ++i) {
                        history[i - 1U] = history[i];
                    }
                    --seen;
                }
                history[seen++] = Seen{f, now};
                replay[replay_count < 4U ? replay_count : static_cast<std::size_t>(step % 4)] = f;
                replay_count = replay_count < 4U ? replay_count + 1U : 4U;
            }
        }
        const CommandPoll p = receiver.poll(now);

        ++g_stats.statuses;
        g_stats.valid += p.status.valid ? 1U : 0U;
        ORACLE(p.status.valid == (p.status.fault == CommandFault::kNone));
        if (!p.status.valid) {
            ORACLE(!p.input.valid);
            was_valid = false;
            continue;
        }
        const unsigned in_use = check_valid(p, history, seen, now, config, sent);
        if (was_valid && p.input.counter != last_counter) {
            const std::uint8_t delta = e2e_p01_counter_delta(p.input.counter, last_counter);
            ORACLE(delta >= 1U && delta <= config.max_delta_counter);
        }
        // No replay, across faults too: within one session of the PLC the sequence in use never goes back (the
        // endpoint keeps its reference against frames behind it; fewer than 32768 of the PLC's frames here).
        if (used != 0U && (in_use >> 16U) == (used >> 16U)) {
            ORACLE(in_use >= used);
        }
        used = in_use;
        was_valid = true;
        last_counter = p.input.counter;
    }
    return 0;
}
