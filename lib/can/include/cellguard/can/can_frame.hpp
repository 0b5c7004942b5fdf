// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file can_frame.hpp
/// A classic CAN frame and the description of a signal inside its 8 data
/// bytes, in the terms a DBC file uses (start bit, length, byte order,
/// factor, multiplexing), so that one constexpr table serves the encoder,
/// the decoder and the test that compares the table with the DBC file.
///
/// Bit numbering is the DBC one for Intel (little-endian, `@1`) signals:
/// bit b of data byte k is bit 8k + b, and a signal's start bit is its least
/// significant bit. All cellguard signals are Intel and offset 0; most are
/// unsigned, the command message's joint positions are signed (two's
/// complement, DBC `@1-`).
#ifndef CELLGUARD_CAN_FRAME_HPP
#define CELLGUARD_CAN_FRAME_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/contract.hpp"

namespace cellguard {

/// Data bytes of a classic CAN frame.
constexpr std::uint8_t kCanMaxDataLength = 8U;
/// Largest 11-bit (standard) CAN identifier.
constexpr std::uint32_t kCanMaxStandardId = 0x7FFU;

/// A classic CAN frame: identifier, data length code and up to 8 data bytes.
/// `id` holds the bare identifier (no SocketCAN flag bits); bytes at and after
/// `dlc` are not part of the frame.
struct CanFrame {
    std::uint32_t id;      ///< CAN identifier (11-bit for cellguard's frames)
    std::uint8_t dlc;      ///< data length code, 0..8
    std::uint8_t data[8];  ///< data bytes; byte 0 is sent first
};

/// Byte order of a signal, with the DBC's codes (`@0` Motorola, `@1` Intel).
enum class ByteOrder : std::uint8_t {
    kMotorola = 0,  ///< big-endian (not used by cellguard's frames)
    kIntel = 1,     ///< little-endian: the start bit is the least significant bit
};

/// Role of a signal in DBC multiplexing.
enum class Multiplex : std::uint8_t {
    kNone = 0,         ///< always present
    kMultiplexor = 1,  ///< the selector (`M` in the DBC)
    kMultiplexed = 2,  ///< present when the selector equals multiplex_value (`m<value>`)
};

/// One signal of a frame, as a DBC `SG_` line states it. Physical value =
/// raw * factor (offset 0), in `unit`. Unsigned signals have the raw range
/// 0..raw_max; signed ones (two's complement) -raw_max..raw_max.
struct SignalLayout {
    const char* name = "";                     ///< DBC signal name
    std::uint8_t start_bit = 0U;               ///< least significant bit, Intel numbering (8 * byte + bit)
    std::uint8_t length = 0U;                  ///< width in bits, 1..32
    ByteOrder byte_order = ByteOrder::kIntel;  ///< always kIntel in cellguard's tables
    std::uint32_t factor = 1U;                 ///< physical units per raw unit (integer)
    const char* unit = "";                     ///< physical unit, "" for dimensionless
    std::uint32_t raw_max = 0U;                ///< largest valid raw value (DBC maximum = raw_max * factor)
    Multiplex multiplex = Multiplex::kNone;    ///< multiplexing role
    std::uint8_t multiplex_value = 0U;         ///< selector value for kMultiplexed signals, else 0
    bool is_signed = false;                    ///< two's complement (DBC `-`); raw range -raw_max..raw_max
};

/// Mask of the bits @p s occupies in the frame's 64 data bits.
[[nodiscard]] constexpr std::uint64_t signal_mask(const SignalLayout& s) noexcept {
    const std::uint64_t ones = (s.length >= 64U) ? ~std::uint64_t{0} : ((std::uint64_t{1} << s.length) - 1U);
    return ones << s.start_bit;
}

/// True when @p a and @p b can be present in the same frame (not two
/// multiplexed signals of different selector values).
[[nodiscard]] constexpr bool signals_coexist(const SignalLayout& a, const SignalLayout& b) noexcept {
    return !(a.multiplex == Multiplex::kMultiplexed && b.multiplex == Multiplex::kMultiplexed &&
             a.multiplex_value != b.multiplex_value);
}

/// Compile-time check of a layout table: every signal is Intel, 1..32 bits
/// wide, inside the 64 data bits, has a factor >= 1 and a raw_max that fits
/// (for a signed signal: in length - 1 bits, and it is 2..32 bits wide);
/// and no two coexisting signals overlap.
template <std::size_t N>
[[nodiscard]] constexpr bool layout_is_consistent(const SignalLayout (&table)[N]) noexcept {
    for (std::size_t i = 0U; i < N; ++i) {
        const SignalLayout& s = table[i];
        if (s.byte_order != ByteOrder::kIntel || s.length == 0U || s.length > 32U || s.start_bit + s.length > 64U ||
            s.factor == 0U || (s.length < 32U && s.raw_max > ((std::uint32_t{1} << s.length) - 1U))) {
            return false;
        }
        if (s.is_signed && (s.length < 2U || s.raw_max > ((std::uint32_t{1} << (s.length - 1U)) - 1U))) {
            return false;
        }
        for (std::size_t j = i + 1U; j < N; ++j) {
            if (signals_coexist(s, table[j]) && (signal_mask(s) & signal_mask(table[j])) != 0U) {
                return false;
            }
        }
    }
    return true;
}

/// Union of the bits of every signal in @p table (the complement is reserved).
template <std::size_t N>
[[nodiscard]] constexpr std::uint64_t layout_used_bits(const SignalLayout (&table)[N]) noexcept {
    std::uint64_t used = 0U;
    for (std::size_t i = 0U; i < N; ++i) {
        used |= signal_mask(table[i]);
    }
    return used;
}

/// The 8 data bytes of @p frame as one little-endian 64-bit word (byte 0 lowest).
[[nodiscard]] constexpr std::uint64_t frame_bits(const CanFrame& frame) noexcept {
    std::uint64_t bits = 0U;
    for (std::size_t k = 0U; k < kCanMaxDataLength; ++k) {
        bits |= static_cast<std::uint64_t>(frame.data[k]) << (8U * k);
    }
    return bits;
}

/// Raw value of signal @p s in @p frame (Intel signals only, a contract).
[[nodiscard]] constexpr std::uint32_t get_signal(const CanFrame& frame, const SignalLayout& s) noexcept {
    CG_ENFORCE(s.byte_order == ByteOrder::kIntel && s.length >= 1U && s.length <= 32U && s.start_bit + s.length <= 64U,
               "only Intel signals of 1..32 bits inside the frame");
    return static_cast<std::uint32_t>((frame_bits(frame) & signal_mask(s)) >> s.start_bit);
}

/// Writes raw value @p raw into signal @p s of @p frame, leaving the other
/// bits as they are. Contract: Intel signal, and @p raw fits in its length.
constexpr void set_signal(CanFrame& frame, const SignalLayout& s, std::uint32_t raw) noexcept {
    CG_ENFORCE(s.byte_order == ByteOrder::kIntel && s.length >= 1U && s.length <= 32U && s.start_bit + s.length <= 64U,
               "only Intel signals of 1..32 bits inside the frame");
    CG_ENFORCE(s.length == 32U || raw < (std::uint32_t{1} << s.length), "raw value wider than the signal");
    const std::uint64_t mask = signal_mask(s);
    const std::uint64_t bits = (frame_bits(frame) & ~mask) | ((static_cast<std::uint64_t>(raw) << s.start_bit) & mask);
    for (std::size_t k = 0U; k < kCanMaxDataLength; ++k) {
        frame.data[k] = static_cast<std::uint8_t>(bits >> (8U * k));
    }
}

/// Value of signed signal @p s in @p frame: its raw bits sign-extended
/// (two's complement). Contract as get_signal.
[[nodiscard]] constexpr std::int32_t get_signed_signal(const CanFrame& frame, const SignalLayout& s) noexcept {
    const std::uint32_t raw = get_signal(frame, s);
    const std::uint32_t sign = std::uint32_t{1} << (s.length - 1U);
    // (raw ^ sign) - sign sign-extends without a shift of a negative number.
    return static_cast<std::int32_t>(static_cast<std::int64_t>(raw ^ sign) - static_cast<std::int64_t>(sign));
}

/// Writes @p value into signed signal @p s (two's complement, the low
/// s.length bits). Contract: @p value fits in s.length bits, signed.
constexpr void set_signed_signal(CanFrame& frame, const SignalLayout& s, std::int32_t value) noexcept {
    CG_ENFORCE(s.length >= 2U && s.length <= 32U, "a signed signal has 2..32 bits");
    const auto limit = static_cast<std::int64_t>(std::uint64_t{1} << (s.length - 1U));
    CG_ENFORCE(value >= -limit && value < limit, "value wider than the signed signal");
    const std::uint64_t ones = (std::uint64_t{1} << s.length) - 1U;
    set_signal(frame, s,
               static_cast<std::uint32_t>(static_cast<std::uint64_t>(static_cast<std::int64_t>(value)) & ones));
}

}  // namespace cellguard

#endif  // CELLGUARD_CAN_FRAME_HPP
