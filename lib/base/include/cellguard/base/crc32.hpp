// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file crc32.hpp
/// CRC-32 as in IEEE 802.3 (also called CRC-32/ISO-HDLC): polynomial
/// 0x04C11DB7, processed reflected (LSB first, table polynomial 0xEDB88320),
/// initial register 0xFFFFFFFF, final XOR 0xFFFFFFFF. Check value: the CRC
/// of the nine ASCII bytes "123456789" is 0xCBF43926.
///
/// Table-driven, slicing-by-8 (eight lookups per eight bytes); the eight
/// 256-entry tables are built at compile time (`kCrc32Table`, 8 KiB in
/// .rodata) and every function here is
/// constexpr, so a CRC of a short constant can be a static_assert (the
/// generated prior source uses this for its header). Incremental: feeding a
/// message in slices through `crc32_update` (or `Crc32::update`) gives the
/// same CRC as one call over the whole message.
///
/// Detection properties relied on by the prior image (prior_image.hpp) and
/// the run-time signature checks (ram_check.hpp): CRC-32 detects every error
/// confined to one burst of at most 32 bits, hence every single-bit error,
/// in a message of any length.
#ifndef CELLGUARD_CRC32_HPP
#define CELLGUARD_CRC32_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"

namespace cellguard {

/// The generator polynomial in normal (MSB-first) notation.
constexpr std::uint32_t kCrc32Polynomial = 0x04C11DB7U;
/// The same polynomial bit-reversed, as the reflected algorithm uses it.
constexpr std::uint32_t kCrc32ReflectedPolynomial = 0xEDB88320U;
/// Register value before the first byte.
constexpr std::uint32_t kCrc32Init = 0xFFFFFFFFU;
/// Value XOR-ed into the register to give the CRC.
constexpr std::uint32_t kCrc32XorOut = 0xFFFFFFFFU;
/// CRC of the ASCII bytes "123456789" (the catalogue's check value).
constexpr std::uint32_t kCrc32Check = 0xCBF43926U;

/// Bytes folded into the register per step of the sliced update (slicing-by-8).
constexpr std::size_t kCrc32Slices = 8U;

/// The lookup tables, one per byte position of an eight-byte step.
/// slices[0][i] is the register after shifting byte i through eight reflected
/// steps (the classic one-byte table); slices[k][i] is slices[k-1][i] shifted
/// through eight more zero bits, i.e. the contribution of byte i when k bytes
/// follow it in the step. 8 KiB, in .rodata.
struct Crc32Table {
    std::uint32_t slices[kCrc32Slices][256];  ///< [byte position from the end of a step][byte value]
};

/// One table entry computed bit by bit from the definition (the reference
/// that the table and crc32_table_self_test are checked against).
constexpr std::uint32_t crc32_table_entry(std::uint32_t byte) noexcept {
    std::uint32_t r = byte & 0xFFU;
    for (int bit = 0; bit < 8; ++bit) {
        r = ((r & 1U) != 0U) ? ((r >> 1U) ^ kCrc32ReflectedPolynomial) : (r >> 1U);
    }
    return r;
}

/// The register @p r shifted through eight zero bits, bit by bit from the definition.
constexpr std::uint32_t crc32_shift_zero_byte(std::uint32_t r) noexcept {
    return (r >> 8U) ^ crc32_table_entry(r & 0xFFU);
}

/// Builds all eight tables at compile time.
constexpr Crc32Table make_crc32_table() noexcept {
    Crc32Table t{};
    for (std::uint32_t i = 0U; i < 256U; ++i) {
        t.slices[0][i] = crc32_table_entry(i);
        for (std::size_t k = 1U; k < kCrc32Slices; ++k) {
            t.slices[k][i] = crc32_shift_zero_byte(t.slices[k - 1U][i]);
        }
    }
    return t;
}

/// The tables, built at compile time; one copy in .rodata.
inline constexpr Crc32Table kCrc32Table = make_crc32_table();

/// Four bytes from @p bytes at @p at, least significant first. Written with
/// shifts, so it is constexpr and independent of the host's byte order;
/// compilers turn it into one load on little-endian targets.
constexpr std::uint32_t crc32_load_le32(Span<const std::uint8_t> bytes, std::size_t at) noexcept {
    return static_cast<std::uint32_t>(bytes[at]) | (static_cast<std::uint32_t>(bytes[at + 1U]) << 8U) |
           (static_cast<std::uint32_t>(bytes[at + 2U]) << 16U) | (static_cast<std::uint32_t>(bytes[at + 3U]) << 24U);
}

/// Feeds @p bytes into the raw (not yet final-XOR-ed) register @p state and
/// returns the new register. Start from kCrc32Init; finish with crc32_finish.
/// Work: eight table lookups per eight bytes (slicing-by-8), then one lookup
/// per remaining byte. The result equals the one-byte-at-a-time algorithm's
/// for every length and every split of a message (tested against the bitwise
/// definition).
constexpr std::uint32_t crc32_update(std::uint32_t state, Span<const std::uint8_t> bytes) noexcept {
    const auto& t = kCrc32Table.slices;
    const std::size_t size = bytes.size();
    std::size_t at = 0U;
    for (; size - at >= kCrc32Slices; at += kCrc32Slices) {
        const std::uint32_t lo = state ^ crc32_load_le32(bytes, at);
        const std::uint32_t hi = crc32_load_le32(bytes, at + 4U);
        state = t[7][lo & 0xFFU] ^ t[6][(lo >> 8U) & 0xFFU] ^ t[5][(lo >> 16U) & 0xFFU] ^ t[4][lo >> 24U] ^
                t[3][hi & 0xFFU] ^ t[2][(hi >> 8U) & 0xFFU] ^ t[1][(hi >> 16U) & 0xFFU] ^ t[0][hi >> 24U];
    }
    for (; at < size; ++at) {
        state = t[0][(state ^ bytes[at]) & 0xFFU] ^ (state >> 8U);
    }
    return state;
}

/// The CRC of a message whose bytes have all been fed into @p state.
constexpr std::uint32_t crc32_finish(std::uint32_t state) noexcept { return state ^ kCrc32XorOut; }

/// CRC-32 of @p bytes in one call.
constexpr std::uint32_t crc32(Span<const std::uint8_t> bytes) noexcept {
    return crc32_finish(crc32_update(kCrc32Init, bytes));
}

/// An incremental CRC-32: update over consecutive slices of a message, then
/// read value(). Holds only the 32-bit register.
class Crc32 {
public:
    /// Feeds the next slice of the message.
    constexpr void update(Span<const std::uint8_t> bytes) noexcept { state_ = crc32_update(state_, bytes); }
    /// CRC of every byte fed since construction or the last reset().
    [[nodiscard]] constexpr std::uint32_t value() const noexcept { return crc32_finish(state_); }
    /// Starts a new message.
    constexpr void reset() noexcept { state_ = kCrc32Init; }

private:
    std::uint32_t state_ = kCrc32Init;
};

/// Start-up diagnostic of the tables as they sit in memory (by default the
/// ones in flash that every CRC here uses): reads every entry through a
/// volatile pointer, so the compiler cannot fold the comparison, and compares
/// it with the bitwise definition (crc32_table_entry, then
/// crc32_shift_zero_byte from the entry before it, as read). True when all
/// 8 x 256 entries are intact. Work: 8 x 256 x 8 bit steps.
[[nodiscard]] bool crc32_table_self_test(const Crc32Table& table = kCrc32Table) noexcept;

/// The same test over the byte values [@p first, @p first + @p count) of
/// every slice (all 8 entries of each; the range is clipped at 256): true
/// when those 8 x count entries are intact. crc32_table_self_test is this
/// over [0, 256).
[[nodiscard]] bool crc32_table_entries_intact(const Crc32Table& table, std::uint32_t first,
                                              std::uint32_t count) noexcept;

/// The run-time test of the CRC-32 tables (hazard H-MEM-2): the start-up
/// self-test spread over the cycles. Each step() tests the next
/// @p values_per_step byte values (8 entries each) against the bitwise
/// definition, so it does not depend on the tables it tests; a pass covers
/// all 256 values in ceil(256 / values_per_step) steps. An entry corrupted
/// at any time is found by the step that next tests it: within
/// steps_per_pass() steps. The verdict latches. Holds a pointer and counters.
class Crc32TableCheck {
public:
    /// A check of @p table (it must outlive the check; default: the tables every CRC here uses).
    explicit Crc32TableCheck(const Crc32Table& table = kCrc32Table) noexcept : table_(&table) {}
    /// Tests the next @p values_per_step (1..256: contract) byte values; true once any test failed.
    [[nodiscard]] bool step(std::uint32_t values_per_step) noexcept;
    /// True once a step has found a corrupted entry (latched).
    [[nodiscard]] bool failed() const noexcept { return failed_; }
    /// The tables under test.
    [[nodiscard]] const Crc32Table* table() const noexcept { return table_; }
    /// The byte value the next step starts at.
    [[nodiscard]] std::uint32_t position() const noexcept { return next_; }
    /// Steps of @p values_per_step (1..256: contract) per pass over all 256 values.
    [[nodiscard]] static std::uint32_t steps_per_pass(std::uint32_t values_per_step) noexcept;

private:
    const Crc32Table* table_;
    std::uint32_t next_ = 0U;
    bool failed_ = false;
};

}  // namespace cellguard

#endif  // CELLGUARD_CRC32_HPP
