// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: integer log-odds, saturation, sentinel, conversion bound.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "cellguard/grid/log_odds.hpp"

using namespace cellguard;

// verifies: SR-GRID-002
TEST_CASE("log-odds: probability 0.5 is zero and the scale is 256 units per nat") {
    CHECK(log_odds_from_probability(0.5) == 0);
    CHECK(log_odds_from_probability(1.0 / (1.0 + std::exp(-1.0))) == 256);
    CHECK(log_odds_from_probability(1.0 / (1.0 + std::exp(1.0))) == -256);
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: a round trip stays within the stated bound over the range the method uses") {
    double worst = 0.0;
    for (int i = 0; i <= 200000; ++i) {
        // log-spaced towards both ends, from 1e-6 to 1 - 1e-6
        const double u = static_cast<double>(i) / 200000.0;
        const double p = (u < 0.5) ? 1e-6 * std::pow(0.5e6, 2.0 * u) : 1.0 - 1e-6 * std::pow(0.5e6, 2.0 * (1.0 - u));
        const double back = probability_from_log_odds(log_odds_from_probability(p));
        worst = std::fmax(worst, std::fabs(back - p));
    }
    CHECK(worst <= kProbabilityRoundTripBound);
    CHECK(kProbabilityRoundTripBound < 0.001);
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: probability 0 and NaN give the never-foreground sentinel, 1 gives the maximum") {
    CHECK(log_odds_from_probability(0.0) == kNeverForeground);
    CHECK(log_odds_from_probability(-0.5) == kNeverForeground);
    CHECK(log_odds_from_probability(std::nan("")) == kNeverForeground);
    CHECK(log_odds_from_probability(1.0) == kLogOddsMax);
    CHECK(probability_from_log_odds(kNeverForeground) == 0.0);
    CHECK(log_odds_from_probability(1e-300) == kLogOddsMin);  // tiny but not zero: finite, clamped
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: addition saturates at both ends instead of wrapping") {
    CHECK(add_saturating(30000, 30000) == kLogOddsMax);
    CHECK(add_saturating(-30000, -30000) == kLogOddsMin);
    CHECK(add_saturating(kLogOddsMax, 1) == kLogOddsMax);
    CHECK(add_saturating(kLogOddsMin, -1) == kLogOddsMin);
    CHECK(add_saturating(100, -40) == 60);
    CHECK(add_finite_saturating(kLogOddsMin, kLogOddsMin) == kLogOddsMin);  // never reaches the sentinel
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: no addition lifts the never-foreground sentinel") {
    for (std::int32_t v = -32768; v <= 32767; v += 7) {
        const auto b = static_cast<std::int16_t>(v);
        CHECK_EQ(add_saturating(kNeverForeground, b), kNeverForeground);
        CHECK_EQ(add_saturating(b, kNeverForeground), kNeverForeground);
    }
    CHECK(add_saturating(kNeverForeground, kLogOddsMax) == kNeverForeground);
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: a threshold in log-odds agrees with thresholding the probability") {
    for (const double t : {0.1, 0.5, 0.51, 0.73, 0.9}) {
        const std::int16_t th = threshold_log_odds(t);
        for (std::int32_t v = -3000; v <= 3000; ++v) {
            const auto raw = static_cast<std::int16_t>(v);
            const double p = probability_from_log_odds(raw);
            if (std::fabs(p - t) > 1e-12) {
                CHECK_EQ(raw >= th, p >= t);
            }
        }
    }
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: a threshold at or beyond 0 or 1, or NaN, or beyond the log-odds range, maps to the range's end") {
    CHECK(threshold_log_odds(0.0) == kLogOddsMin);
    CHECK(threshold_log_odds(-0.5) == kLogOddsMin);
    CHECK(threshold_log_odds(std::nan("")) == kLogOddsMin);  // never a threshold that lets a NaN through as 'above'
    CHECK(threshold_log_odds(1.0) == kLogOddsMax);
    CHECK(threshold_log_odds(2.0) == kLogOddsMax);
    // A probability whose log-odds lie below int16 at 256 units per nat
    // (below -128 nats). Above +128 nats there is no double below 1.
    CHECK(threshold_log_odds(1e-60) == kLogOddsMin);
    CHECK(threshold_log_odds(1e-50) > kLogOddsMin);  // -115 nats: inside the range
}

// verifies: SR-GRID-002
TEST_CASE("log-odds: sums computed at run time clamp at both ends as the compile-time ones do") {
    // Operands the compiler cannot fold (read from a vector), each pair with its expected sum.
    struct Sum {
        std::int16_t a;
        std::int16_t b;
        std::int16_t want;
    };
    const std::vector<Sum> sums = {{30000, 30000, kLogOddsMax},
                                   {-30000, -30000, kLogOddsMin},
                                   {kLogOddsMin, kLogOddsMin, kLogOddsMin},
                                   {kLogOddsMax, 1, kLogOddsMax},
                                   {100, -40, 60}};
    for (const Sum& s : sums) {
        CAPTURE(s.a);
        CAPTURE(s.b);
        CHECK(add_finite_saturating(s.a, s.b) == s.want);
        CHECK(add_saturating(s.a, s.b) == s.want);
        CHECK(clamp_log_odds(static_cast<std::int32_t>(s.a) + static_cast<std::int32_t>(s.b)) == s.want);
    }
}
