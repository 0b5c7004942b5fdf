// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file log_odds.hpp
/// Integer log-odds: the number format of every evidence grid in cellguard.
///
/// A value is an int16 in fixed point: raw = round(256 * ln(p / (1 - p))),
/// i.e. one unit is 1/256 nat (`kLogOddsScale`). Probability 0.5 is 0.
///
/// - The representable range is [-32767, +32767] units, about +-128 nats
///   (p from about 2.6e-56 to 1 - 2.6e-56). Additions saturate at those
///   bounds: they never wrap.
/// - INT16_MIN (-32768) is the sentinel `kNeverForeground`, probability
///   exactly 0 (the accessibility prior of a voxel that cannot be
///   foreground). `add_saturating` keeps it: no addition can lift it.
/// - Error bound: converting a probability to log-odds rounds to the nearest
///   unit (at most 0.5/256 nat), and dp/dl = p(1-p) <= 1/4, so a round trip
///   p -> log-odds -> p is within 0.5/256/4 < 0.00049 in probability, for every
///   p whose log-odds lies inside the range (tested over [1e-6, 1 - 1e-6]).
///   Each sum of n rounded terms carries at most n * 0.5 units of rounding.
#ifndef CELLGUARD_LOG_ODDS_HPP
#define CELLGUARD_LOG_ODDS_HPP

#include <cstdint>

namespace cellguard {

/// Fixed-point scale: raw units per nat.
constexpr std::int32_t kLogOddsScale = 256;
/// Largest finite log-odds value (saturation bound, about +128 nats).
constexpr std::int16_t kLogOddsMax = 32767;
/// Smallest finite log-odds value (saturation bound, about -128 nats).
constexpr std::int16_t kLogOddsMin = -32767;
/// Sentinel for probability exactly 0: "never foreground". Absorbing under add_saturating.
constexpr std::int16_t kNeverForeground = -32768;
/// Log-odds of probability 0.5: no evidence either way.
constexpr std::int16_t kLogOddsUnknown = 0;
/// Bound on |p - to_probability(from_probability(p))| over the representable range.
constexpr double kProbabilityRoundTripBound = 0.5 / kLogOddsScale / 4.0;

/// Clamps a wide sum into [kLogOddsMin, kLogOddsMax] (never yields the sentinel).
constexpr std::int16_t clamp_log_odds(std::int32_t wide) noexcept {
    return static_cast<std::int16_t>(wide > kLogOddsMax ? kLogOddsMax : wide < kLogOddsMin ? kLogOddsMin : wide);
}

/// Saturating sum of two finite log-odds values (neither may be the sentinel):
/// the hot-path form used by fusion, where the sentinel cannot occur.
constexpr std::int16_t add_finite_saturating(std::int16_t a, std::int16_t b) noexcept {
    return clamp_log_odds(static_cast<std::int32_t>(a) + static_cast<std::int32_t>(b));
}

/// Saturating sum that keeps the sentinel: if either operand is
/// kNeverForeground the result is kNeverForeground; otherwise the sum is
/// clamped to [kLogOddsMin, kLogOddsMax]. This is the independent opinion
/// pool of two log-odds opinions.
constexpr std::int16_t add_saturating(std::int16_t a, std::int16_t b) noexcept {
    return (a == kNeverForeground || b == kNeverForeground) ? kNeverForeground : add_finite_saturating(a, b);
}

/// Log-odds of probability @p p, rounded to the nearest unit and clamped.
/// p <= 0 (and NaN) gives kNeverForeground; p >= 1 gives kLogOddsMax.
std::int16_t log_odds_from_probability(double p) noexcept;

/// Probability of log-odds @p raw; kNeverForeground gives exactly 0.
double probability_from_log_odds(std::int16_t raw) noexcept;

/// Log-odds value of a probability threshold such that
/// `raw >= threshold_log_odds(t)` holds exactly when probability_from_log_odds(raw) >= t
/// (up to rounding of the exact boundary). t in (0, 1); other t are clamped.
std::int16_t threshold_log_odds(double t) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_LOG_ODDS_HPP
