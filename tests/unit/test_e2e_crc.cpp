// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: CRC-8 SAE J1850 check values, E2E Profile 1 CRC in every data ID mode, counter arithmetic, data ID rules.
#include <doctest/doctest.h>

#include <cstdint>
#include <initializer_list>
#include <vector>

#include "cellguard/can/e2e_crc.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

std::uint8_t crc_of(std::initializer_list<std::uint8_t> bytes) {
    const std::vector<std::uint8_t> v(bytes);
    return crc8_sae_j1850(Span<const std::uint8_t>(v.data(), v.size()));
}

Span<const std::uint8_t> view(const std::vector<std::uint8_t>& v) {
    return Span<const std::uint8_t>(v.data(), v.size());
}

/// E2E_P01 as the AUTOSAR profile writes it: Crc_CalculateCRC8 chained with
/// start value 0xFF and is_first_call = false over the data ID bytes, the data
/// before the CRC byte and the data after it; the result XORed with 0xFF.
std::uint8_t p01_as_specified(const std::vector<std::uint8_t>& data, std::size_t crc_index, std::uint16_t id,
                              E2eP01DataIdMode mode, std::uint8_t counter) {
    const auto low = static_cast<std::uint8_t>(id & 0xFFU);
    const auto high = static_cast<std::uint8_t>(id >> 8U);
    const std::uint8_t zero = 0U;
    std::uint8_t crc = 0U;
    switch (mode) {
        case E2eP01DataIdMode::kBoth:
            crc = crc8_sae_j1850(Span<const std::uint8_t>(&low, 1U), 0xFFU, false);
            crc = crc8_sae_j1850(Span<const std::uint8_t>(&high, 1U), crc, false);
            break;
        case E2eP01DataIdMode::kAlt:
            crc = crc8_sae_j1850(Span<const std::uint8_t>(counter % 2U == 0U ? &low : &high, 1U), 0xFFU, false);
            break;
        case E2eP01DataIdMode::kLow: crc = crc8_sae_j1850(Span<const std::uint8_t>(&low, 1U), 0xFFU, false); break;
        case E2eP01DataIdMode::kNibble:
            crc = crc8_sae_j1850(Span<const std::uint8_t>(&low, 1U), 0xFFU, false);
            crc = crc8_sae_j1850(Span<const std::uint8_t>(&zero, 1U), crc, false);
            break;
    }
    crc = crc8_sae_j1850(view(data).subspan(0U, crc_index), crc, false);
    crc = crc8_sae_j1850(view(data).subspan(crc_index + 1U, data.size() - crc_index - 1U), crc, false);
    return static_cast<std::uint8_t>(crc ^ 0xFFU);
}

constexpr E2eP01DataIdMode kAllModes[] = {E2eP01DataIdMode::kBoth, E2eP01DataIdMode::kAlt, E2eP01DataIdMode::kLow,
                                          E2eP01DataIdMode::kNibble};

}  // namespace

// verifies: SR-CAN-001
TEST_CASE("e2e crc: CRC-8 SAE J1850 gives the check values of the AUTOSAR CRC specification") {
    CHECK(crc_of({0x00, 0x00, 0x00, 0x00}) == 0x59);
    CHECK(crc_of({0xF2, 0x01, 0x83}) == 0x37);
    CHECK(crc_of({0x0F, 0xAA, 0x00, 0x55}) == 0x79);
    CHECK(crc_of({0x00, 0xFF, 0x55, 0x11}) == 0xB8);
    CHECK(crc_of({0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF}) == 0xCB);
    CHECK(crc_of({0x92, 0x6B, 0x55}) == 0x8C);
    CHECK(crc_of({0xFF, 0xFF, 0xFF, 0xFF}) == 0x74);
    CHECK(crc_of({'1', '2', '3', '4', '5', '6', '7', '8', '9'}) == 0x4B);  // the catalogue's "check"
}

// verifies: SR-CAN-001
TEST_CASE("e2e crc: a CRC computed in pieces, each call continuing the previous one, equals the one-shot CRC") {
    const std::vector<std::uint8_t> v{0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF};
    for (std::size_t split = 0U; split <= v.size(); ++split) {
        const std::uint8_t first = crc8_sae_j1850(view(v).subspan(0U, split));
        const std::uint8_t whole = crc8_sae_j1850(view(v).subspan(split, v.size() - split), first, false);
        CHECK(whole == 0xCB);
    }
    // A first call ignores the start value; no data leaves a start value as it is.
    CHECK(crc8_sae_j1850(view(v), 0x12U, true) == 0xCB);
    CHECK(crc8_sae_j1850(Span<const std::uint8_t>(), 0x12U, false) == 0x12U);
    CHECK(crc8_sae_j1850(Span<const std::uint8_t>()) == 0x00U);
}

// verifies: SR-CAN-001
TEST_CASE("e2e crc: Profile 1 CRCs match an independent implementation's vectors in all four data ID modes") {
    // Data ID 0x123, 8 bytes, CRC in byte 0, counter in byte 1's low nibble,
    // NIBBLE mode's explicit nibble in byte 1's high nibble.
    std::vector<std::uint8_t> d(8U, 0U);
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kBoth, 0U) == 0xCC);
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kAlt, 0U) == 0xCE);
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kLow, 0U) == 0xCE);
    d[1] = 0x01U;
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kBoth, 1U) == 0x91);
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kAlt, 1U) == 0x02);
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kLow, 1U) == 0x93);
    d[1] = 0x10U;
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kNibble, 0U) == 0x2A);
    d[1] = 0x11U;
    CHECK(e2e_p01_crc(view(d), 0U, 0x123U, E2eP01DataIdMode::kNibble, 1U) == 0x77);
}

// verifies: SR-CAN-001
TEST_CASE("e2e crc: the Profile 1 CRC equals the profile's chain of Crc_CalculateCRC8 calls, the CRC byte skipped") {
    std::uint32_t state = 12345U;
    std::vector<std::uint8_t> d(8U);
    for (int round = 0; round < 200; ++round) {
        for (auto& b : d) {
            state = state * 1103515245U + 12345U;
            b = static_cast<std::uint8_t>(state >> 16U);
        }
        const auto id = static_cast<std::uint16_t>(state & 0x0FFFU);
        const auto crc_index = static_cast<std::size_t>(round % 8);
        const auto counter = static_cast<std::uint8_t>(round % 15);
        for (const E2eP01DataIdMode mode : kAllModes) {
            CHECK(e2e_p01_crc(view(d), crc_index, id, mode, counter) ==
                  p01_as_specified(d, crc_index, id, mode, counter));
        }
        // The CRC byte's own value never enters the CRC.
        const std::uint8_t before = e2e_p01_crc(view(d), crc_index, id, E2eP01DataIdMode::kBoth, counter);
        d[crc_index] = static_cast<std::uint8_t>(d[crc_index] ^ 0xA5U);
        CHECK(e2e_p01_crc(view(d), crc_index, id, E2eP01DataIdMode::kBoth, counter) == before);
    }
}

// verifies: SR-CAN-001
TEST_CASE("e2e crc: the counter runs 0 to 14 and wraps 14 -> 0, the delta counts forward modulo 15") {
    CHECK(e2e_p01_next_counter(0U) == 1U);
    CHECK(e2e_p01_next_counter(13U) == 14U);
    CHECK(e2e_p01_next_counter(14U) == 0U);
    CHECK(e2e_p01_counter_delta(5U, 4U) == 1U);
    CHECK(e2e_p01_counter_delta(0U, 14U) == 1U);
    CHECK(e2e_p01_counter_delta(1U, 14U) == 2U);
    CHECK(e2e_p01_counter_delta(7U, 7U) == 0U);
    CHECK(e2e_p01_counter_delta(6U, 7U) == 14U);
    for (std::uint8_t c = 0U; c <= kE2eP01CounterMax; ++c) {
        CHECK(e2e_p01_counter_delta(e2e_p01_next_counter(c), c) == 1U);
    }
}

// verifies: SR-CAN-001
TEST_CASE("e2e crc: NIBBLE mode takes 12-bit data IDs only, other modes any 16-bit ID, unknown modes none") {
    CHECK(e2e_p01_data_id_valid(0x0FFFU, E2eP01DataIdMode::kNibble));
    CHECK_FALSE(e2e_p01_data_id_valid(0x1000U, E2eP01DataIdMode::kNibble));
    CHECK(e2e_p01_data_id_valid(0xFFFFU, E2eP01DataIdMode::kBoth));
    CHECK(e2e_p01_data_id_valid(0xFFFFU, E2eP01DataIdMode::kAlt));
    CHECK(e2e_p01_data_id_valid(0xFFFFU, E2eP01DataIdMode::kLow));
    CHECK_FALSE(e2e_p01_data_id_valid(0x0001U, static_cast<E2eP01DataIdMode>(4)));
    CHECK(e2e_p01_data_id_nibble(0x0ABCU) == 0x0AU);
}

// verifies: SR-CAN-004, SR-CAN-010
TEST_CASE("e2e crc: data IDs are distinguishable exactly when no data can pass a check with the other ID") {
    // BOTH: IDs whose byte streams (low, high) differ by a multiple of the polynomial 0x11D
    // collide for all data: 0x1D01 is sent as 01 1D.
    CHECK_FALSE(e2e_p01_data_ids_distinguishable(0x0000U, 0x1D01U, E2eP01DataIdMode::kBoth));
    CHECK(e2e_p01_data_ids_distinguishable(0x0000U, 0x011DU, E2eP01DataIdMode::kBoth));
    std::vector<std::uint8_t> d{0x00, 0x37, 0x42, 0x99, 0x00, 0xFF, 0x10, 0x01};
    CHECK(e2e_p01_crc(view(d), 0U, 0x0000U, E2eP01DataIdMode::kBoth, 7U) ==
          e2e_p01_crc(view(d), 0U, 0x1D01U, E2eP01DataIdMode::kBoth, 7U));
    CHECK(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0D52U, E2eP01DataIdMode::kBoth));
    CHECK(e2e_p01_crc(view(d), 0U, 0x0C51U, E2eP01DataIdMode::kBoth, 7U) !=
          e2e_p01_crc(view(d), 0U, 0x0D52U, E2eP01DataIdMode::kBoth, 7U));
    // ALT needs both bytes to differ (each is used on every other frame).
    CHECK_FALSE(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0D51U, E2eP01DataIdMode::kAlt));
    CHECK_FALSE(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0C52U, E2eP01DataIdMode::kAlt));
    CHECK(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0D52U, E2eP01DataIdMode::kAlt));
    // LOW ignores the high byte.
    CHECK_FALSE(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0D51U, E2eP01DataIdMode::kLow));
    CHECK(e2e_p01_crc(view(d), 0U, 0x0C51U, E2eP01DataIdMode::kLow, 3U) ==
          e2e_p01_crc(view(d), 0U, 0x0D51U, E2eP01DataIdMode::kLow, 3U));
    // NIBBLE: an explicit nibble that differs is enough.
    CHECK(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0D51U, E2eP01DataIdMode::kNibble));
    CHECK_FALSE(e2e_p01_data_ids_distinguishable(0x0C51U, 0x0C51U, E2eP01DataIdMode::kNibble));
}

// verifies: SR-CAN-001, SR-GEN-003
TEST_CASE("e2e crc: a CRC byte outside the data is a contract violation") {
    const std::vector<std::uint8_t> d(8U, 0U);
    CHECK(test::violates_contract([&] { (void)e2e_p01_crc(view(d), 8U, 1U, E2eP01DataIdMode::kBoth, 0U); }));
    CHECK(test::violates_contract([&] { (void)e2e_p01_crc(view(d), 0U, 1U, static_cast<E2eP01DataIdMode>(9), 0U); }));
}

// verifies: SR-CAN-001, SR-GEN-003
TEST_CASE("e2e crc: comparing data IDs under an unknown data ID mode is a contract violation") {
    CHECK_FALSE(
        test::violates_contract([] { (void)e2e_p01_data_ids_distinguishable(1U, 2U, E2eP01DataIdMode::kBoth); }));
    CHECK(test::violates_contract(
        [] { (void)e2e_p01_data_ids_distinguishable(1U, 2U, static_cast<E2eP01DataIdMode>(4)); }));
}
