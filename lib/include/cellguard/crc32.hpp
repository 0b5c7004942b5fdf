/// @file crc32.hpp
/// CRC-32 as in IEEE 802.3 (also called CRC-32/ISO-HDLC): polynomial
/// 0x04C11DB7, processed reflected (LSB first, table polynomial 0xEDB88320),
/// initial register 0xFFFFFFFF, final XOR 0xFFFFFFFF. Check value: the CRC
/// of the nine ASCII bytes "123456789" is 0xCBF43926.
///
/// Table-driven, one table lookup per byte; the 256-entry table is built at
/// compile time (`kCrc32Table`, in .rodata) and every function here is
/// constexpr, so a CRC of a short constant can be a static_assert (the
/// generated prior source uses this for its header). Incremental: feeding a
/// message in slices through `crc32_update` (or `Crc32::update`) gives the
/// same CRC as one call over the whole message.
///
/// Detection properties relied on by the prior image (prior_image.hpp) and
/// its run-time check (prior_integrity.hpp): CRC-32 detects every error
/// confined to one burst of at most 32 bits, hence every single-bit error,
/// in a message of any length.
#ifndef CELLGUARD_CRC32_HPP
#define CELLGUARD_CRC32_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/span.hpp"

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

/// The lookup table: entry i is the register after shifting byte i through
/// eight reflected steps.
struct Crc32Table {
    std::uint32_t entries[256];  ///< one entry per byte value
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

/// Builds the whole table at compile time.
constexpr Crc32Table make_crc32_table() noexcept {
    Crc32Table t{};
    for (std::uint32_t i = 0U; i < 256U; ++i) {
        t.entries[i] = crc32_table_entry(i);
    }
    return t;
}

/// The table, built at compile time; one copy in .rodata.
inline constexpr Crc32Table kCrc32Table = make_crc32_table();

/// Feeds @p bytes into the raw (not yet final-XOR-ed) register @p state and
/// returns the new register. Start from kCrc32Init; finish with crc32_finish.
/// Work: exactly one table lookup, one shift and two XORs per byte.
constexpr std::uint32_t crc32_update(std::uint32_t state, Span<const std::uint8_t> bytes) noexcept {
    for (const std::uint8_t b : bytes) {
        state = kCrc32Table.entries[(state ^ b) & 0xFFU] ^ (state >> 8U);
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

/// Start-up diagnostic of a table as it sits in memory (by default the one
/// in flash that every CRC here uses): reads every entry through a volatile
/// pointer, so the compiler cannot fold the comparison, and compares it with
/// crc32_table_entry. True when all 256 entries are intact. Work: 256 x 8
/// bit steps.
[[nodiscard]] bool crc32_table_self_test(const Crc32Table& table = kCrc32Table) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_CRC32_HPP
