// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: Span, the bounded view of caller storage, and as_bytes, the byte image a CRC reads.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>

#include "cellguard/base/crc32.hpp"
#include "cellguard/base/span.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

// verifies: SR-GEN-003
TEST_CASE("span: at() and subspan() past the end violate the contract in every build") {
    std::int32_t values[4] = {1, 2, 3, 4};
    const Span<std::int32_t> s(values);
    REQUIRE(s.size() == 4U);
    CHECK(s.at(3) == 4);
    CHECK(test::violates_contract([&] { (void)s.at(4); }));
    CHECK(s.subspan(1, 3).size() == 3U);
    CHECK(s.subspan(4, 0).empty());
    CHECK(test::violates_contract([&] { (void)s.subspan(1, 4); }));
    CHECK(test::violates_contract([&] { (void)s.subspan(5, 0); }));
    CHECK_FALSE(test::violates_contract([&] { (void)s.subspan(0, 4); }));
}

// verifies: SR-FUSE-007
TEST_CASE("span: as_bytes views exactly the bytes of the elements, in memory order") {
    const std::uint16_t values[3] = {0x0102U, 0x0304U, 0xA0B0U};
    const Span<const std::uint8_t> bytes = as_bytes(Span<const std::uint16_t>(values));
    REQUIRE(bytes.size() == sizeof(values));
    CHECK(static_cast<const void*>(bytes.data()) == static_cast<const void*>(values));
    std::uint8_t copy[sizeof(values)] = {};
    std::memcpy(copy, values, sizeof(values));
    for (std::size_t i = 0; i < sizeof(values); ++i) {
        CHECK(bytes[i] == copy[i]);
    }
    // A mutable span gives the same read-only view, so a CRC of either agrees.
    std::uint16_t mutable_values[3] = {0x0102U, 0x0304U, 0xA0B0U};
    CHECK(crc32(as_bytes(Span<std::uint16_t>(mutable_values))) == crc32(bytes));
    mutable_values[2] ^= 0x0001U;
    CHECK(crc32(as_bytes(Span<std::uint16_t>(mutable_values))) != crc32(bytes));
    CHECK(as_bytes(Span<const float>()).empty());
}
