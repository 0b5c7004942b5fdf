// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: CRC-32 (IEEE 802.3): catalogue check value, known vectors, incremental update, table self-test.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "cellguard/base/crc32.hpp"

using namespace cellguard;

namespace {
Span<const std::uint8_t> bytes_of(const char* s) {
    return Span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(s), std::strlen(s));
}

// The register @p r after shifting @p data through it bit by bit, from the definition
// (reflected, poly 0x04C11DB7), without the table.
std::uint32_t shift_bitwise(std::uint32_t r, Span<const std::uint8_t> data) {
    for (const std::uint8_t b : data) {
        r ^= b;
        for (int i = 0; i < 8; ++i) {
            r = (r & 1U) != 0U ? (r >> 1U) ^ 0xEDB88320U : r >> 1U;
        }
    }
    return r;
}

// Bit-by-bit CRC-32: initial register 0xFFFFFFFF, final XOR 0xFFFFFFFF.
std::uint32_t crc32_bitwise(Span<const std::uint8_t> data) { return shift_bitwise(0xFFFFFFFFU, data) ^ 0xFFFFFFFFU; }

// The bare register after shifting @p data from 0, with no initial value or final XOR.
std::uint32_t register_from_zero(Span<const std::uint8_t> data) { return shift_bitwise(0U, data); }

constexpr std::uint8_t kCheck[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
static_assert(crc32(Span<const std::uint8_t>(kCheck)) == 0xCBF43926U, "check value at compile time");
}  // namespace

// verifies: SR-PRIOR-013
TEST_CASE("crc32: the check value of \"123456789\" is 0xCBF43926") {
    CHECK(crc32(bytes_of("123456789")) == 0xCBF43926U);
    CHECK(kCrc32Check == 0xCBF43926U);
}

// verifies: SR-PRIOR-013
TEST_CASE("crc32: known vectors and the empty message") {
    CHECK(crc32(Span<const std::uint8_t>()) == 0x00000000U);
    CHECK(crc32(bytes_of("a")) == 0xE8B7BE43U);
    CHECK(crc32(bytes_of("The quick brown fox jumps over the lazy dog")) == 0x414FA339U);
    const std::uint8_t zeros[32] = {};
    CHECK(crc32(Span<const std::uint8_t>(zeros)) == 0x190A55ADU);
}

// verifies: SR-PRIOR-013
TEST_CASE("crc32: the polynomial is 0x04C11DB7, reflected as 0xEDB88320") {
    std::uint32_t reflected = 0U;
    for (int i = 0; i < 32; ++i) {
        if ((kCrc32Polynomial >> static_cast<unsigned>(i) & 1U) != 0U) {
            reflected |= 1U << static_cast<unsigned>(31 - i);
        }
    }
    CHECK(reflected == kCrc32ReflectedPolynomial);
    CHECK(kCrc32Table.slices[0][0] == 0U);
    CHECK(kCrc32Table.slices[0][128] == kCrc32ReflectedPolynomial);
}

// verifies: SR-PRIOR-013
TEST_CASE("crc32: the table-driven CRC equals the bitwise definition on random messages") {
    std::mt19937 rng(7U);
    for (std::size_t len : {1U, 2U, 3U, 7U, 8U, 9U, 15U, 16U, 17U, 64U, 255U, 1000U}) {
        std::vector<std::uint8_t> data(len + 7U);
        for (auto& b : data)
            b = static_cast<std::uint8_t>(rng());
        // Every start offset modulo 8, so the sliced loads also run unaligned.
        for (std::size_t offset = 0; offset < 8U; ++offset) {
            const Span<const std::uint8_t> s(data.data() + offset, len);
            CHECK(crc32(s) == crc32_bitwise(s));
        }
    }
}

// verifies: SR-PRIOR-013
TEST_CASE("crc32: updating over slices gives the CRC of the whole message, for every split") {
    std::vector<std::uint8_t> data(97);
    for (std::size_t i = 0; i < data.size(); ++i)
        data[i] = static_cast<std::uint8_t>(i * 31U + 5U);
    const Span<const std::uint8_t> all(data.data(), data.size());
    const std::uint32_t whole = crc32(all);
    for (std::size_t split = 0; split <= data.size(); ++split) {
        Crc32 c;
        c.update(all.subspan(0, split));
        c.update(all.subspan(split, data.size() - split));
        CHECK(c.value() == whole);
    }
    // Many small slices, through the raw register functions.
    std::uint32_t state = kCrc32Init;
    for (std::size_t i = 0; i < data.size(); i += 5) {
        state = crc32_update(state, all.subspan(i, data.size() - i < 5 ? data.size() - i : 5));
    }
    CHECK(crc32_finish(state) == whole);
    Crc32 c;
    c.update(all);
    c.reset();
    c.update(bytes_of("123456789"));
    CHECK(c.value() == kCrc32Check);
}

// verifies: SR-PRIOR-013
TEST_CASE("crc32: a single flipped bit anywhere changes the CRC") {
    std::vector<std::uint8_t> data(40, 0x5AU);
    const std::uint32_t ref = crc32(Span<const std::uint8_t>(data.data(), data.size()));
    for (std::size_t bit = 0; bit < data.size() * 8U; ++bit) {
        data[bit / 8U] = static_cast<std::uint8_t>(data[bit / 8U] ^ (1U << (bit % 8U)));
        CHECK(crc32(Span<const std::uint8_t>(data.data(), data.size())) != ref);
        data[bit / 8U] = static_cast<std::uint8_t>(data[bit / 8U] ^ (1U << (bit % 8U)));
    }
}

// verifies: SR-PRIOR-013
TEST_CASE("crc32: the start-up self-test passes on the table in flash and fails on a corrupted copy") {
    CHECK(crc32_table_self_test());
    Crc32Table copy = kCrc32Table;
    CHECK(crc32_table_self_test(copy));
    for (std::size_t k = 0; k < kCrc32Slices; ++k) {
        for (const std::size_t i : {0U, 1U, 128U, 255U}) {
            copy.slices[k][i] ^= 1U << 17U;
            CHECK_FALSE(crc32_table_self_test(copy));
            copy.slices[k][i] ^= 1U << 17U;
        }
    }
    CHECK(crc32_table_self_test(copy));
    for (std::uint32_t i = 0; i < 256U; ++i) {
        CHECK(kCrc32Table.slices[0][i] == crc32_table_entry(i));
        // slices[k][i] is byte i followed by k zero bytes, shifted through a register that starts at 0.
        for (std::size_t k = 1; k < kCrc32Slices; ++k) {
            std::uint8_t message[kCrc32Slices] = {};
            message[0] = static_cast<std::uint8_t>(i);
            CHECK(kCrc32Table.slices[k][i] == register_from_zero(Span<const std::uint8_t>(message, k + 1U)));
        }
    }
}
