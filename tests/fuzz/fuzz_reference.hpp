// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The CAN fuzz targets' independent reference: an ORACLE that aborts with the
// failed condition, and the AUTOSAR E2E Profile 1 CRC written bitwise from the
// profile's rules (polynomial 0x1D, no table), independent of e2e_crc.cpp.
#ifndef CELLGUARD_FUZZ_REFERENCE_HPP
#define CELLGUARD_FUZZ_REFERENCE_HPP

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "cellguard/can/e2e_crc.hpp"

/// Aborts (a fuzzer finding) when @p cond is false, naming it and its line.
#define ORACLE(cond)                                                                \
    do {                                                                            \
        if (!(cond)) {                                                              \
            std::fprintf(stderr, "oracle failed: %s (line %d)\n", #cond, __LINE__); \
            std::abort();                                                           \
        }                                                                           \
    } while (false)

namespace cellguard::fuzz {

/// One byte through the bitwise CRC-8, polynomial 0x1D.
inline std::uint8_t ref_update(std::uint8_t reg, std::uint8_t byte) {
    unsigned r = static_cast<unsigned>(reg ^ byte);
    for (int i = 0; i < 8; ++i) {
        r = (r & 0x80U) != 0U ? ((r << 1U) ^ 0x1DU) & 0xFFU : (r << 1U) & 0xFFU;
    }
    return static_cast<std::uint8_t>(r);
}

/// E2E P01 CRC of an 8-byte frame with the CRC in byte 0 and the counter in
/// bits 8..11: the data ID as @p mode puts it first, then bytes 1..7.
inline std::uint8_t ref_p01_crc(const std::uint8_t (&d)[8], std::uint16_t id, E2eP01DataIdMode mode) {
    const auto lo = static_cast<std::uint8_t>(id & 0xFFU);
    const auto hi = static_cast<std::uint8_t>(id >> 8U);
    const unsigned counter = d[1] & 0x0FU;
    std::uint8_t reg = 0U;
    if (mode == E2eP01DataIdMode::kBoth) {
        reg = ref_update(ref_update(reg, lo), hi);
    } else if (mode == E2eP01DataIdMode::kAlt) {
        reg = ref_update(reg, counter % 2U == 0U ? lo : hi);
    } else if (mode == E2eP01DataIdMode::kLow) {
        reg = ref_update(reg, lo);
    } else {
        reg = ref_update(ref_update(reg, lo), 0U);
    }
    for (int k = 1; k < 8; ++k) {
        reg = ref_update(reg, d[k]);
    }
    return reg;
}

}  // namespace cellguard::fuzz

#endif  // CELLGUARD_FUZZ_REFERENCE_HPP
