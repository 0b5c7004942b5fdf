// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the sensor model (one opinion per sensor, voxel and frame), its integer table and the pooling of opinions.
#include <doctest/doctest.h>

#include <algorithm>
#include <limits>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/grid/sensor_model.hpp"

using namespace cellguard;

// verifies: SR-FUSE-005
TEST_CASE("sensor model: the defaults are p_miss 0.30, p_hit 0.90, pooled evidence clamped to [0.12, 0.97]") {
    const SensorModelTable t;
    CHECK(t.constant_free_evidence() == log_odds_from_probability(0.30));
    CHECK(t.reading_evidence() == log_odds_from_probability(0.90));
    CHECK(t.pooled_min() == log_odds_from_probability(0.12));
    CHECK(t.pooled_max() == log_odds_from_probability(0.97));
    CHECK(probability_from_log_odds(t.reading_evidence()) == doctest::Approx(0.90).epsilon(0.001));
    CHECK(t.free_evidence(1.0) == t.constant_free_evidence());
    CHECK(t.free_evidence(t.ramp_length()) == t.constant_free_evidence());
}

// verifies: SR-FUSE-002, SR-FUSE-005
TEST_CASE("sensor model: pooling is occupied-wins, commutative and associative, and clamped") {
    const SensorModelTable t;
    const std::int16_t hit = t.reading_evidence();
    const std::int16_t miss = t.constant_free_evidence();
    const std::int16_t ramp = t.free_evidence(0.01);
    CHECK(t.pool(0, hit) == hit);
    CHECK(t.pool(0, miss) == miss);
    CHECK(t.pool(miss, hit) == hit);  // a hit after a free opinion: occupied
    CHECK(t.pool(hit, miss) == hit);  // a free opinion after a hit: still occupied
    CHECK(t.pool(hit, hit) == std::min<std::int32_t>(2 * hit, t.pooled_max()));
    CHECK(t.pool(miss, miss) == std::max<std::int32_t>(2 * miss, t.pooled_min()));
    // Every order of every multiset of up to four opinions pools to the same value.
    const std::int16_t values[4] = {hit, miss, ramp, 0};
    for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
            for (int c = 0; c < 4; ++c) {
                const std::int16_t x = values[a], y = values[b], z = values[c];
                const std::int16_t xyz = t.pool(t.pool(t.pool(0, x), y), z);
                CHECK(xyz == t.pool(t.pool(t.pool(0, z), x), y));
                CHECK(xyz == t.pool(t.pool(t.pool(0, y), z), x));
                CHECK(xyz == t.pool(t.pool(t.pool(0, z), y), x));
                CHECK((xyz > 0) == (x == hit || y == hit || z == hit));  // occupied exactly when a sensor hit
                CHECK(xyz >= t.pooled_min());
                CHECK(xyz <= t.pooled_max());
            }
        }
    }
}

// verifies: SR-FUSE-005
TEST_CASE("sensor model: evidence rises monotonically towards 0.5 on the ramp before the reading") {
    const SensorModelTable t;
    std::int16_t previous = 0;  // d = 0: the value right before the reading, at most 0.5
    for (int i = 0; i <= 200; ++i) {
        const double d = t.ramp_length() * i / 200.0;
        const std::int16_t e = t.free_evidence(d);
        CHECK(e <= 0);  // never occupied evidence before the reading
        CHECK(e >= t.constant_free_evidence());
        if (i > 0) {
            CHECK(e <= previous);  // farther from the reading: more free
        }
        previous = e;
    }
    CHECK(t.free_evidence(0.0) > t.constant_free_evidence());
    CHECK(t.free_evidence(-1.0) == t.free_evidence(0.0));  // clamped, never indexes outside the table
}

// verifies: SR-FUSE-005
TEST_CASE("sensor model: a zero ramp gives the constant everywhere before the reading") {
    SensorModelParams p;
    p.ramp_length = 0.0;
    const SensorModelTable t = SensorModelTable::make(p).value();
    CHECK(t.free_evidence(0.0) == t.constant_free_evidence());
}

// verifies: SR-FUSE-005
TEST_CASE("sensor model: parameters outside their range are rejected") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(SensorModelTable::make(SensorModelParams{0.5, 0.9, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.5, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.0, 0.9, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 1.0, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, -0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{nan, 0.9, 0.1}).error() == ErrorCode::kNonFiniteValue);
    // Each remaining bound on its own: p_hit non-finite, ramp non-finite,
    // ramp over 10 m, the clamps outside [0, p_miss] and [p_hit, 1] or
    // non-finite, p_hit or p_miss within rounding of 0.5; the limits
    // themselves are accepted.
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(SensorModelTable::make(SensorModelParams{0.3, nan, 0.1}).error() == ErrorCode::kNonFiniteValue);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, inf}).error() == ErrorCode::kNonFiniteValue);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 10.001}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 10.0}).ok());
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.0}).ok());
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, 0.31, 0.97}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, 0.12, 0.89}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, 0.0, 0.97}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, 0.12, 1.0}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, nan, 0.97}).error() == ErrorCode::kNonFiniteValue);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, 0.12, inf}).error() == ErrorCode::kNonFiniteValue);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.5001, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.4999, 0.9, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.3, 0.9, 0.1, 0.3, 0.9}).ok());
}
