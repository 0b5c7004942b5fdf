// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the safety and diagnostics frame decoders on arbitrary frames.
// Aborts if a decoder accepts a frame that an independent check (a bitwise
// CRC written from the AUTOSAR E2E Profile 1 rules, the counter range, the
// CAN ID and length) rejects, or if an accepted frame does not re-encode to
// exactly the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "cellguard/can/safety_frame.hpp"
#include "fuzz_reference.hpp"

using namespace cellguard;
using cellguard::fuzz::ref_p01_crc;

namespace {

/// The independent E2E check of a frame on @p can_id with @p data_id.
bool ref_e2e_ok(const CanFrame& f, std::uint32_t can_id, std::uint16_t data_id, E2eP01DataIdMode mode) {
    if (f.id != can_id || f.dlc != 8U || (f.data[1] & 0x0FU) > 14U) {
        return false;
    }
    if (mode == E2eP01DataIdMode::kNibble && (f.data[1] >> 4U) != ((data_id >> 8U) & 0x0FU)) {
        return false;
    }
    return f.data[0] == ref_p01_crc(f.data, data_id, mode);
}

/// With CELLGUARD_FUZZ_STATS set, reports at exit how many frames each decoder accepted.
struct Stats {
    std::uint64_t frames = 0U;
    std::uint64_t safety_ok = 0U;
    std::uint64_t diagnostics_ok = 0U;
    Stats() = default;
    Stats(const Stats&) = delete;
    Stats& operator=(const Stats&) = delete;
    ~Stats() {
        if (std::getenv("CELLGUARD_FUZZ_STATS") != nullptr) {
            std::fprintf(stderr, "frames: %llu, accepted as safety: %llu, as diagnostics: %llu\n",
                         static_cast<unsigned long long>(frames), static_cast<unsigned long long>(safety_ok),
                         static_cast<unsigned long long>(diagnostics_ok));
        }
    }
};
Stats g_stats;  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables): fuzz statistics

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 11U) {
        return 0;
    }
    SafetyChannelConfig config;
    config.data_id_mode = static_cast<E2eP01DataIdMode>(data[0] % 4U);
    CanFrame f{};
    switch ((data[1] >> 4U) % 4U) {
        case 0U: f.id = config.safety_can_id; break;
        case 1U: f.id = inverted_can_id(config); break;
        case 2U: f.id = config.diagnostics_can_id; break;
        default: f.id = static_cast<std::uint32_t>(data[1]) << 3U; break;
    }
    f.dlc = static_cast<std::uint8_t>(data[2] % 16U);
    std::memcpy(f.data, data + 3, 8U);
    const bool fix_crc = (data[1] & 0x01U) != 0U;  // let the fuzzer reach the content checks
    if (fix_crc) {
        const std::uint16_t id = f.id == config.diagnostics_can_id ? config.diagnostics_data_id : config.safety_data_id;
        f.data[0] = ref_p01_crc(f.data, id, config.data_id_mode);
    }

    SafetyFrameContent safety;
    const FrameCheck sc = check_safety_frame(f, config, safety);
    const Result<SafetyFrameContent> sr = decode_safety_frame(f, config);
    ORACLE(sr.ok() == (sc == FrameCheck::kOk));
    if (sc == FrameCheck::kOk) {
        ORACLE(ref_e2e_ok(f, config.safety_can_id, config.safety_data_id, config.data_id_mode));
        ORACLE(safety.message.zone_count <= 16U);
        ORACLE(safety.message.protective_stop == ((f.data[2] & 0x01U) != 0U));
        const Result<CanFrame> again = encode_safety_frame(safety.message, safety.counter, config);
        ORACLE(again.ok());
        ORACLE(std::memcmp(again.value().data, f.data, 8U) == 0);
    } else {
        ORACLE(!sr.ok() && sr.error() == to_error_code(sc));
    }

    DiagnosticsFrameContent diag;
    const FrameCheck dc = check_diagnostics_frame(f, config, diag);
    ORACLE(decode_diagnostics_frame(f, config).ok() == (dc == FrameCheck::kOk));
    if (dc == FrameCheck::kOk) {
        ORACLE(ref_e2e_ok(f, config.diagnostics_can_id, config.diagnostics_data_id, config.data_id_mode));
        const Result<CanFrame> again = encode_diagnostics_frame(diag.message, diag.counter, config);
        ORACLE(again.ok());
        ORACLE(std::memcmp(again.value().data, f.data, 8U) == 0);
    }
    // No frame passes as both; and with the default data IDs the inverted data of a
    // valid frame never passes on the frame's own ID (its CRC differs from the
    // inverted CRC byte by a constant other than 0xFF in every mode).
    ORACLE(!(sc == FrameCheck::kOk && dc == FrameCheck::kOk));
    ++g_stats.frames;
    g_stats.safety_ok += sc == FrameCheck::kOk ? 1U : 0U;
    g_stats.diagnostics_ok += dc == FrameCheck::kOk ? 1U : 0U;
    SafetyFrameContent unused;
    CanFrame back = inverted_copy(f);
    back.id = f.id;
    ORACLE(!(sc == FrameCheck::kOk && check_safety_frame(back, config, unused) == FrameCheck::kOk));
    return 0;
}
