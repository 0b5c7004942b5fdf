// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the saturating counters of lib/base (saturating.hpp) stop at
// their type's largest value and never wrap to 0: the point-set check's counts
// (SR-BKG-007) and the receivers' runs of good samples before recovery
// (SR-CAN-009, SR-CMD-006), which a wrap to 0 would restart.
#include <doctest/doctest.h>

#include <cstdint>

#include "cellguard/base/saturating.hpp"

using namespace cellguard;

// verifies: SR-BKG-007
TEST_CASE("saturating_increment of a 32-bit counter counts up to UINT32_MAX and stays there") {
    CHECK(saturating_increment(std::uint32_t{0U}) == 1U);
    CHECK(saturating_increment(std::uint32_t{41U}) == 42U);
    CHECK(saturating_increment(std::uint32_t{UINT32_MAX - 1U}) == UINT32_MAX);
    CHECK(saturating_increment(std::uint32_t{UINT32_MAX}) == UINT32_MAX);
    std::uint32_t n = UINT32_MAX - 2U;
    for (int i = 0; i < 5; ++i) {
        n = saturating_increment(n);
    }
    CHECK(n == UINT32_MAX);
}

// verifies: SR-CAN-009, SR-CMD-006
TEST_CASE("saturating_increment of an 8-bit counter counts up to UINT8_MAX and stays there") {
    std::uint8_t n = 0U;
    for (int i = 0; i < 300; ++i) {
        n = saturating_increment(n);
        CHECK(n == (i < UINT8_MAX ? i + 1 : UINT8_MAX));
    }
    CHECK(saturating_increment(std::uint8_t{UINT8_MAX - 1U}) == UINT8_MAX);
    CHECK(saturating_increment(std::uint8_t{UINT8_MAX}) == UINT8_MAX);
}

// verifies: SR-BKG-007
TEST_CASE("saturating_add stops at UINT32_MAX instead of wrapping") {
    CHECK(saturating_add(0U, 0U) == 0U);
    CHECK(saturating_add(1U, 2U) == 3U);
    CHECK(saturating_add(UINT32_MAX - 3U, 3U) == UINT32_MAX);  // the largest sum that fits
    CHECK(saturating_add(UINT32_MAX - 3U, 4U) == UINT32_MAX);  // one more saturates
    CHECK(saturating_add(UINT32_MAX, 1U) == UINT32_MAX);
    CHECK(saturating_add(1U, UINT32_MAX) == UINT32_MAX);
    CHECK(saturating_add(UINT32_MAX, UINT32_MAX) == UINT32_MAX);
    CHECK(saturating_add(0U, UINT32_MAX) == UINT32_MAX);
}
