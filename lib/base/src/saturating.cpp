// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/saturating.hpp"

namespace cellguard {

std::uint32_t saturating_increment(std::uint32_t n) noexcept { return n == UINT32_MAX ? n : n + 1U; }

std::uint8_t saturating_increment(std::uint8_t n) noexcept {
    return n == UINT8_MAX ? n : static_cast<std::uint8_t>(n + 1U);
}

std::uint32_t saturating_add(std::uint32_t a, std::uint32_t b) noexcept {
    return a > UINT32_MAX - b ? UINT32_MAX : a + b;
}

}  // namespace cellguard
