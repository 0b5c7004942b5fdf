// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/can/e2e_crc.hpp"

#include "cellguard/base/contract.hpp"

namespace cellguard {
namespace {

/// The 256-entry table of the (unreflected) polynomial 0x1D, built at compile time.
struct Crc8Table {
    std::uint8_t entry[256];
};

constexpr Crc8Table make_crc8_table() noexcept {
    Crc8Table table{};
    for (unsigned i = 0U; i < 256U; ++i) {
        unsigned reg = i;
        for (unsigned bit = 0U; bit < 8U; ++bit) {
            reg = ((reg & 0x80U) != 0U) ? (((reg << 1U) ^ kCrc8SaeJ1850Polynomial) & 0xFFU) : ((reg << 1U) & 0xFFU);
        }
        table.entry[i] = static_cast<std::uint8_t>(reg);
    }
    return table;
}

constexpr Crc8Table kTable = make_crc8_table();
static_assert(kTable.entry[1] == kCrc8SaeJ1850Polynomial, "table entry 1 is the polynomial");

/// Advances the raw CRC register (no initial value, no final XOR) over one byte.
constexpr std::uint8_t update(std::uint8_t reg, std::uint8_t byte) noexcept {
    return kTable.entry[static_cast<std::uint8_t>(reg ^ byte)];
}

/// Raw register after the implicit data ID bytes of @p mode, starting from 0x00
/// (Crc_CalculateCRC8 with start value 0xFF and is_first_call = false).
std::uint8_t register_after_data_id(std::uint16_t data_id, E2eP01DataIdMode mode, std::uint8_t counter) noexcept {
    const auto low = static_cast<std::uint8_t>(data_id & 0xFFU);
    const auto high = static_cast<std::uint8_t>(data_id >> 8U);
    std::uint8_t reg = 0x00U;
    switch (mode) {
        case E2eP01DataIdMode::kBoth: reg = update(update(reg, low), high); break;
        case E2eP01DataIdMode::kAlt: reg = update(reg, ((counter % 2U) == 0U) ? low : high); break;
        case E2eP01DataIdMode::kLow: reg = update(reg, low); break;
        case E2eP01DataIdMode::kNibble: reg = update(update(reg, low), 0x00U); break;
    }
    return reg;
}

}  // namespace

std::uint8_t crc8_sae_j1850(Span<const std::uint8_t> data, std::uint8_t start_value, bool is_first_call) noexcept {
    std::uint8_t reg = is_first_call ? kCrc8SaeJ1850InitialValue
                                     : static_cast<std::uint8_t>(start_value ^ kCrc8SaeJ1850XorValue);
    for (const std::uint8_t byte : data) {
        reg = update(reg, byte);
    }
    return static_cast<std::uint8_t>(reg ^ kCrc8SaeJ1850XorValue);
}

std::uint8_t e2e_p01_crc(Span<const std::uint8_t> data, std::size_t crc_byte_index, std::uint16_t data_id,
                         E2eP01DataIdMode mode, std::uint8_t counter) noexcept {
    CG_ENFORCE(crc_byte_index < data.size(), "the CRC byte must lie inside the protected data");
    CG_ENFORCE(e2e_p01_mode_valid(mode), "unknown E2E Profile 1 data ID mode");
    std::uint8_t reg = register_after_data_id(data_id, mode, counter);
    for (std::size_t i = 0U; i < data.size(); ++i) {
        if (i != crc_byte_index) {
            reg = update(reg, data[i]);
        }
    }
    return reg;
}

bool e2e_p01_data_ids_distinguishable(std::uint16_t a, std::uint16_t b, E2eP01DataIdMode mode) noexcept {
    CG_ENFORCE(e2e_p01_mode_valid(mode), "unknown E2E Profile 1 data ID mode");
    const bool low_differs = (a & 0xFFU) != (b & 0xFFU);
    const bool high_differs = (a >> 8U) != (b >> 8U);
    switch (mode) {
        case E2eP01DataIdMode::kBoth: return register_after_data_id(a, mode, 0U) != register_after_data_id(b, mode, 0U);
        case E2eP01DataIdMode::kAlt:
            // Even counters carry the low byte, odd ones the high byte: both must differ.
            return low_differs && high_differs;
        case E2eP01DataIdMode::kLow: return low_differs;
        case E2eP01DataIdMode::kNibble: return low_differs || e2e_p01_data_id_nibble(a) != e2e_p01_data_id_nibble(b);
    }
    return false;
}

}  // namespace cellguard
