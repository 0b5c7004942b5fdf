// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/crc32.hpp"

#include "cellguard/base/contract.hpp"

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

bool crc32_table_self_test(const Crc32Table& table) noexcept { return crc32_table_entries_intact(table, 0U, 256U); }

bool crc32_table_entries_intact(const Crc32Table& table, std::uint32_t first, std::uint32_t count) noexcept {
    bool intact = true;
    const std::uint32_t end = (first >= 256U || count > 256U - first) ? 256U : first + count;
    for (std::uint32_t i = first; i < end; ++i) {
        const volatile std::uint32_t* const head = &table.slices[0][i];
        std::uint32_t previous = *head;
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

bool Crc32TableCheck::step(std::uint32_t values_per_step) noexcept {
    CG_ENFORCE(values_per_step >= 1U && values_per_step <= 256U, "a CRC table check step tests 1 to 256 values");
    if (next_ >= 256U) {
        next_ = 0U;  // a corrupted position restarts the pass: no value is skipped for good
    }
    const bool intact = crc32_table_entries_intact(*table_, next_, values_per_step);
    failed_ = failed_ || !intact;
    next_ = next_ + values_per_step >= 256U ? 0U : next_ + values_per_step;
    return failed_;
}

std::uint32_t Crc32TableCheck::steps_per_pass(std::uint32_t values_per_step) noexcept {
    CG_ENFORCE(values_per_step >= 1U && values_per_step <= 256U, "a CRC table check step tests 1 to 256 values");
    return (256U + values_per_step - 1U) / values_per_step;
}

}  // namespace cellguard
