// Requirements: the 1-D sensor evidence profile and its integer table.
#include <doctest/doctest.h>

#include <limits>

#include "cellguard/log_odds.hpp"
#include "cellguard/sensor_model.hpp"

using namespace cellguard;

// verifies: SR-FUSE-005
TEST_CASE("sensor model: the defaults are the paper's trough 0.44 and peak 0.56") {
    const SensorModelTable t;
    CHECK(t.constant_free_evidence() == log_odds_from_probability(0.44));
    CHECK(t.reading_evidence() == log_odds_from_probability(0.56));
    CHECK(probability_from_log_odds(t.reading_evidence()) == doctest::Approx(0.56).epsilon(0.001));
    CHECK(t.free_evidence(1.0) == t.constant_free_evidence());
    CHECK(t.free_evidence(t.ramp_length()) == t.constant_free_evidence());
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
    CHECK(SensorModelTable::make(SensorModelParams{0.5, 0.56, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 0.5, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.0, 0.56, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 1.0, 0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 0.56, -0.1}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{nan, 0.56, 0.1}).error() == ErrorCode::kNonFiniteValue);
    // Each remaining bound on its own: p_reading non-finite, ramp non-finite,
    // ramp over 10 m; the limits themselves are accepted.
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(SensorModelTable::make(SensorModelParams{0.44, nan, 0.1}).error() == ErrorCode::kNonFiniteValue);
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 0.56, inf}).error() == ErrorCode::kNonFiniteValue);
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 0.56, 10.001}).error() == ErrorCode::kInvalidArgument);
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 0.56, 10.0}).ok());
    CHECK(SensorModelTable::make(SensorModelParams{0.44, 0.56, 0.0}).ok());
}
