// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the PLC-side receiver on arbitrary sequences of frames, polls
// and time steps (good pairs, corrupted frames and copies, replays, foreign
// IDs and data IDs, raw garbage, time going backwards).
// Aborts if the receiver ever reports "no stop" without "valid", or "valid"
// for data that a fresh, independent check rejects: the last normal frame and
// its copy on the safety channel must pass a bitwise CRC written from the
// AUTOSAR E2E Profile 1 rules (data ID included), the counter range and the
// inverse-copy comparison, the copy must be within SRVT of its frame and the
// pair within SCT of now, and the reported content must be that frame's.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "cellguard/can/plc_receiver.hpp"
#include "fuzz_reference.hpp"

using namespace cellguard;
using cellguard::fuzz::ref_p01_crc;

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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    PlcReceiverConfig config;
    config.channel.data_id_mode = static_cast<E2eP01DataIdMode>(in.ConsumeIntegralInRange<int>(0, 3));
    // Session link off: this target's independent check models the protocol 0.1 pair
    config.link.enabled = false;
    config.srvt_us = 5000U;
    config.sct_us = 20000U;
    config.max_delta_counter = in.ConsumeIntegralInRange<std::uint8_t>(1U, 3U);
    config.recovery_good_pairs = in.ConsumeIntegralInRange<std::uint8_t>(1U, 3U);
    config.expected_zone_count = in.ConsumeIntegralInRange<std::uint8_t>(0U, 16U);
    PlcReceiver receiver(config);
    const SafetyChannelConfig& ch = config.channel;

    std::uint64_t now = 1000000U;
    std::uint8_t counter = 0U;
    CanFrame last_normal{ch.safety_can_id, 8U, {}};
    Seen history[3] = {};  // the last three frames on the safety channel (normal or copy), newest last
    std::size_t seen = 0U;
    CanFrame replay[4] = {};
    std::size_t replay_count = 0U;

    for (int step = 0; step < 256 && in.remaining_bytes() > 0U; ++step) {
        CanFrame f{};
        bool deliver = true;
        switch (in.ConsumeIntegralInRange<int>(0, 9)) {
            case 0:  // time passes, with or without a poll
                now += in.ConsumeIntegralInRange<std::uint32_t>(0U, 30000U);
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
                const int which = in.ConsumeIntegralInRange<int>(0, 3);
                f.id = which == 0   ? ch.safety_can_id
                       : which == 1 ? ch.safety_can_id + 1U
                       : which == 2 ? ch.diagnostics_can_id
                                    : in.ConsumeIntegralInRange<std::uint32_t>(0U, 0x7FFU);
                f.dlc = in.ConsumeIntegralInRange<std::uint8_t>(0U, 15U);
                for (std::uint8_t& b : f.data) {
                    b = in.ConsumeIntegral<std::uint8_t>();
                }
                break;
            }
            case 4:  // the last frame, or its copy, with one bit flipped
            case 5: {
                f = last_normal;
                if (in.ConsumeBool()) {
                    f = inverted_copy(last_normal);
                }
                const unsigned bit = in.ConsumeIntegralInRange<unsigned>(0U, 63U);
                f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] ^ (1U << (bit % 8U)));
                break;
            }
            case 6: {  // poll
                const ReceiverStatus s = receiver.poll(now);
                (void)s;
                deliver = false;
                break;
            }
            case 7:  // replay an earlier safety-channel frame
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
            default: {  // masquerade: the same content under another data ID or data ID mode
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
        }

        ReceiverStatus s;
        if (deliver) {
            s = receiver.on_frame(f, now);
            if (f.id == ch.safety_can_id || f.id == ch.safety_can_id + 1U) {
                history[0] = history[1];
                history[1] = history[2];
                history[2] = Seen{f, now};
                seen = seen < 3U ? seen + 1U : 3U;
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
        ORACLE(seen >= 2U);
        // The newest frame is the copy of the one before it, or a pending frame follows that pair.
        const bool pending = history[2].frame.id == ch.safety_can_id;
        ORACLE(!pending || seen >= 3U);
        const Seen& copy = pending ? history[1] : history[2];
        const Seen& normal = pending ? history[0] : history[1];
        ORACLE(ref_frame_ok(normal.frame, ch));
        ORACLE(ref_is_copy(copy.frame, normal.frame, ch));
        ORACLE(copy.time >= normal.time && copy.time - normal.time <= config.srvt_us);
        ORACLE(now >= copy.time && now - copy.time <= config.sct_us);
        if (pending) {
            ORACLE(ref_frame_ok(history[2].frame, ch));
            ORACLE(now >= history[2].time && now - history[2].time <= config.srvt_us);
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
