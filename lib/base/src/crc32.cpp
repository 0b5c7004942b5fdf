// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/crc32.hpp"

namespace cellguard {

namespace {
// The check value of the catalogue, proven at compile time.
constexpr std::uint8_t kCheckInput[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
static_assert(crc32(Span<const std::uint8_t>(kCheckInput)) == kCrc32Check, "CRC-32 check value");
static_assert(kCrc32Table.slices[0][1] == 0x77073096U && kCrc32Table.slices[0][255] == 0x2D02EF8DU,
              "CRC-32 table entries");
// Eight bytes and more take the sliced path: the catalogue's check input is nine bytes,
// so the static_assert above covers one sliced step and one single-byte step.
}  // namespace

bool crc32_table_self_test(const Crc32Table& table) noexcept {
    bool intact = true;
    for (std::uint32_t i = 0U; i < 256U; ++i) {
        const volatile std::uint32_t* const first = &table.slices[0][i];
        std::uint32_t previous = *first;
        intact = intact && (previous == crc32_table_entry(i));
        for (std::size_t k = 1U; k < kCrc32Slices; ++k) {
            const volatile std::uint32_t* const entry = &table.slices[k][i];
            const std::uint32_t read = *entry;
            intact = intact && (read == crc32_shift_zero_byte(previous));
            previous = read;
        }
    }
    return intact;
}

}  // namespace cellguard
