// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file saturating.hpp
/// Unsigned counters that stop at their type's largest value instead of
/// wrapping to 0: event counters (faults, samples, windows, repeated frames)
/// and run lengths whose wrap would read as "nothing happened" or restart a
/// run. One definition for every module (until 2026-12-06 each of seven
/// sources had its own copy).
///
/// Defined out of line (saturating.cpp), not constexpr: each caller then runs
/// the one tested definition, and the coverage measurement counts its two
/// branches once instead of once per inlined copy in every caller, where the
/// saturated side needs 2^32 events and no test reaches it.
/// No heap, no OS call.
#ifndef CELLGUARD_SATURATING_HPP
#define CELLGUARD_SATURATING_HPP

#include <cstdint>

namespace cellguard {

/// @p n + 1, or @p n when it is already UINT32_MAX.
[[nodiscard]] std::uint32_t saturating_increment(std::uint32_t n) noexcept;

/// @p n + 1, or @p n when it is already UINT8_MAX.
[[nodiscard]] std::uint8_t saturating_increment(std::uint8_t n) noexcept;

/// @p a + @p b, or UINT32_MAX when the sum does not fit.
[[nodiscard]] std::uint32_t saturating_add(std::uint32_t a, std::uint32_t b) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_SATURATING_HPP
