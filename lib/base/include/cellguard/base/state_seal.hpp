// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file state_seal.hpp
/// A seal over variable safety state (hazard H-MEM-3): the owner computes a
/// CRC-32 over the fields that decide its outputs (its state and its copy of
/// the configuration) at the end of each step, stores it with its complement,
/// and before the next step computes it again and compares. A field changed
/// in RAM between two steps (a flipped bit, a stray write) is found at the
/// start of the next step: CRC-32 detects every single-bit error and every
/// burst of at most 32 bits (crc32.hpp).
///
/// The owner feeds each field separately (seal_add), never a whole struct,
/// so that padding bytes do not take part. The seal itself is stored twice
/// (value and complement): a corrupted seal also fails the comparison.
/// Work: one CRC-32 over the fields' bytes per step; no heap.
#ifndef CELLGUARD_STATE_SEAL_HPP
#define CELLGUARD_STATE_SEAL_HPP

#include <cstdint>
#include <type_traits>

#include "cellguard/base/crc32.hpp"
#include "cellguard/base/span.hpp"

namespace cellguard {

/// Feeds the bytes of the scalar @p value (an integer, bool, enum, floating
/// point number or pointer) into @p crc.
template <typename T>
void seal_add(Crc32& crc, const T& value) noexcept {
    static_assert(std::is_scalar<T>::value, "seal scalar fields one by one (no padding)");
    if constexpr (std::is_pointer<T>::value) {
        // The address is the field's value: sealed as an integer of the same bits.
        // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the address is what is sealed
        const auto address = reinterpret_cast<std::uintptr_t>(value);
        crc.update(as_bytes(Span<const std::uintptr_t>(&address, 1U)));
    } else {
        crc.update(as_bytes(Span<const T>(&value, 1U)));
    }
}

/// A stored CRC-32 and its complement (see the file comment).
class StateSeal {
public:
    /// Stores @p crc, the CRC-32 of the fields as they are now.
    void seal(std::uint32_t crc) noexcept {
        crc_ = crc;
        complement_ = ~crc;
    }
    /// True when @p crc, the fields' CRC-32 computed again, equals the stored
    /// one and the stored one equals its complement's complement.
    [[nodiscard]] bool matches(std::uint32_t crc) const noexcept {
        return crc == crc_ && crc_ == static_cast<std::uint32_t>(~complement_);
    }

private:
    std::uint32_t crc_ = 0U;
    std::uint32_t complement_ = 0U;  ///< ~crc_ once sealed; an unsealed seal matches nothing
};

}  // namespace cellguard

#endif  // CELLGUARD_STATE_SEAL_HPP
