// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file e2e_crc.hpp
/// CRC-8 SAE J1850 and the protection of AUTOSAR E2E Profile 1 (P01): the
/// checksum, counter and data ID that guard every cellguard CAN frame.
///
/// CRC-8 SAE J1850, as the AUTOSAR CRC routines define Crc_CalculateCRC8:
/// polynomial 0x1D, not reflected, initial value 0xFF, final XOR 0xFF. With
/// `is_first_call == false` the start value is the result of the previous call
/// (it is XORed with 0xFF back into the register), so a CRC over a buffer can
/// be computed in pieces. Tested against the seven check values the AUTOSAR
/// CRC specification publishes (00 00 00 00 -> 0x59 ... FF FF FF FF -> 0x74).
///
/// E2E Profile 1 CRC (E2E_P01Protect / E2E_P01Check): the profile chains
/// Crc_CalculateCRC8 with start value 0xFF and is_first_call = false, first
/// over the data ID bytes selected by the data ID mode, then over the data
/// before the CRC byte, then over the data after it, and XORs the result with
/// 0xFF. The net effect is CRC-8 polynomial 0x1D with register start 0x00 and
/// no final XOR over (data ID bytes || data without the CRC byte). Data ID
/// modes (E2E_P01DataIDMode):
/// - kBoth:   low byte, then high byte of the data ID (variant 1A).
/// - kAlt:    low byte when the counter is even, high byte when odd (1B).
/// - kLow:    low byte only; the high byte is never used.
/// - kNibble: low byte, then a 0x00 byte; the low nibble of the high byte is
///            sent explicitly in the data (variant 1C, 12-bit data IDs).
/// Checked against the P01 vectors of an independent implementation
/// (data ID 0x123, 8 zero bytes: CRC 0xCC BOTH, 0xCE ALT/LOW, 0x2A NIBBLE).
///
/// Counter: 4 bits, 0..14 (15 is never sent), incremented by one per frame
/// and wrapping 14 -> 0.
#ifndef CELLGUARD_E2E_CRC_HPP
#define CELLGUARD_E2E_CRC_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"

namespace cellguard {

/// CRC-8 SAE J1850 generator polynomial x^8 + x^4 + x^3 + x^2 + 1 (normal form).
constexpr std::uint8_t kCrc8SaeJ1850Polynomial = 0x1DU;
/// CRC-8 SAE J1850 initial register value (Crc_CalculateCRC8, first call).
constexpr std::uint8_t kCrc8SaeJ1850InitialValue = 0xFFU;
/// CRC-8 SAE J1850 final XOR value.
constexpr std::uint8_t kCrc8SaeJ1850XorValue = 0xFFU;

/// CRC-8 SAE J1850 of @p data, with the semantics of AUTOSAR Crc_CalculateCRC8:
/// on a first call the register starts at 0xFF and @p start_value is ignored;
/// otherwise @p start_value is the previous call's result. The result is XORed
/// with 0xFF. An empty @p data returns the start value unchanged (first call: 0x00).
[[nodiscard]] std::uint8_t crc8_sae_j1850(Span<const std::uint8_t> data,
                                          std::uint8_t start_value = kCrc8SaeJ1850InitialValue,
                                          bool is_first_call = true) noexcept;

/// How the 16-bit data ID enters the Profile 1 CRC (AUTOSAR E2E_P01DataIDMode;
/// the values are AUTOSAR's).
enum class E2eP01DataIdMode : std::uint8_t {
    kBoth = 0,    ///< both bytes, low then high (E2E_P01_DATAID_BOTH)
    kAlt = 1,     ///< low byte for even counters, high byte for odd (E2E_P01_DATAID_ALT)
    kLow = 2,     ///< low byte only (E2E_P01_DATAID_LOW)
    kNibble = 3,  ///< low byte and 0x00; high byte's low nibble sent explicitly (E2E_P01_DATAID_NIBBLE)
};

/// Largest Profile 1 counter value; 15 is never sent.
constexpr std::uint8_t kE2eP01CounterMax = 14U;
/// Number of counter values (0..14).
constexpr std::uint8_t kE2eP01CounterModulo = 15U;
/// Largest data ID usable in kNibble mode (12 bits: the high nibble is not transmitted).
constexpr std::uint16_t kE2eP01NibbleModeMaxDataId = 0x0FFFU;

/// The counter after @p counter: +1, wrapping 14 -> 0. @p counter must be 0..14.
[[nodiscard]] constexpr std::uint8_t e2e_p01_next_counter(std::uint8_t counter) noexcept {
    return static_cast<std::uint8_t>((counter + 1U) % kE2eP01CounterModulo);
}

/// Forward distance from @p last to @p received in counter steps, 0..14
/// (0 = repeated, 1 = the next one, k = k - 1 frames lost). Both must be 0..14.
[[nodiscard]] constexpr std::uint8_t e2e_p01_counter_delta(std::uint8_t received, std::uint8_t last) noexcept {
    return static_cast<std::uint8_t>((received + kE2eP01CounterModulo - last) % kE2eP01CounterModulo);
}

/// True when @p mode is one of the four defined modes.
[[nodiscard]] constexpr bool e2e_p01_mode_valid(E2eP01DataIdMode mode) noexcept {
    return mode == E2eP01DataIdMode::kBoth || mode == E2eP01DataIdMode::kAlt || mode == E2eP01DataIdMode::kLow ||
           mode == E2eP01DataIdMode::kNibble;
}

/// True when @p data_id can be used in @p mode: any 16-bit ID in kBoth, kAlt
/// and kLow, at most 12 bits (<= 0x0FFF) in kNibble.
[[nodiscard]] constexpr bool e2e_p01_data_id_valid(std::uint16_t data_id, E2eP01DataIdMode mode) noexcept {
    return e2e_p01_mode_valid(mode) && (mode != E2eP01DataIdMode::kNibble || data_id <= kE2eP01NibbleModeMaxDataId);
}

/// The explicit data ID nibble of kNibble mode: bits 8..11 of @p data_id.
[[nodiscard]] constexpr std::uint8_t e2e_p01_data_id_nibble(std::uint16_t data_id) noexcept {
    return static_cast<std::uint8_t>((static_cast<unsigned>(data_id) >> 8U) & 0x0FU);
}

/// Profile 1 CRC of @p data (the whole protected data, CRC byte included) for
/// @p data_id in @p mode with counter @p counter (kAlt picks the data ID byte by
/// the counter's parity). The byte at @p crc_byte_index is skipped. Contract:
/// @p crc_byte_index < data.size(), @p mode is valid.
[[nodiscard]] std::uint8_t e2e_p01_crc(Span<const std::uint8_t> data, std::size_t crc_byte_index, std::uint16_t data_id,
                                       E2eP01DataIdMode mode, std::uint8_t counter) noexcept;

/// True when a frame protected with data ID @p a can never pass a check with
/// data ID @p b, whatever the data: the CRC register after the implicit data
/// ID bytes differs (or, in kNibble mode, the explicit nibble differs). In kBoth
/// mode two IDs whose byte streams (low byte, high byte) differ by a multiple of
/// the CRC polynomial 0x11D give the same CRC for all data (e.g. 0x0000 and
/// 0x1D01, sent as 01 1D) and are not distinguishable.
[[nodiscard]] bool e2e_p01_data_ids_distinguishable(std::uint16_t a, std::uint16_t b, E2eP01DataIdMode mode) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_E2E_CRC_HPP
