#include "cellguard/crc32.hpp"

namespace cellguard {

namespace {
// The check value of the catalogue, proven at compile time.
constexpr std::uint8_t kCheckInput[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
static_assert(crc32(Span<const std::uint8_t>(kCheckInput)) == kCrc32Check, "CRC-32 check value");
static_assert(kCrc32Table.entries[1] == 0x77073096U && kCrc32Table.entries[255] == 0x2D02EF8DU,
              "CRC-32 table entries");
}  // namespace

bool crc32_table_self_test(const Crc32Table& table) noexcept {
    const volatile std::uint32_t* const entries = table.entries;
    bool intact = true;
    for (std::uint32_t i = 0U; i < 256U; ++i) {
        intact = intact && (entries[i] == crc32_table_entry(i));
    }
    return intact;
}

}  // namespace cellguard
