// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/sensor_model.hpp"

#include <cmath>

#include "cellguard/grid/log_odds.hpp"

namespace cellguard {

SensorModelTable::SensorModelTable() noexcept { tabulate(SensorModelParams{}); }

Result<SensorModelTable> SensorModelTable::make(const SensorModelParams& params) noexcept {
    if (!std::isfinite(params.p_miss) || !std::isfinite(params.p_hit) || !std::isfinite(params.ramp_length) ||
        !std::isfinite(params.p_clamp_min) || !std::isfinite(params.p_clamp_max)) {
        return ErrorCode::kNonFiniteValue;
    }
    if (!(params.p_clamp_min > 0.0 && params.p_clamp_min <= params.p_miss && params.p_miss < 0.5 &&
          params.p_hit > 0.5 && params.p_hit <= params.p_clamp_max && params.p_clamp_max < 1.0 &&
          params.ramp_length >= 0.0 && params.ramp_length <= 10.0)) {
        return ErrorCode::kInvalidArgument;
    }
    SensorModelTable t;
    t.tabulate(params);
    if (t.reading_ <= 0 || t.free_ >= 0) {
        return ErrorCode::kInvalidArgument;  // within rounding of 0.5: pool() could not tell a hit from a miss
    }
    return t;
}

void SensorModelTable::tabulate(const SensorModelParams& params) noexcept {
    SensorModelTable& t = *this;
    t.params_ = params;
    t.ramp_length_ = params.ramp_length;
    t.free_ = log_odds_from_probability(params.p_miss);
    t.reading_ = log_odds_from_probability(params.p_hit);
    t.pooled_min_ = log_odds_from_probability(params.p_clamp_min);
    t.pooled_max_ = log_odds_from_probability(params.p_clamp_max);
    t.steps_per_metre_ = params.ramp_length > 0.0 ? static_cast<double>(kRampSteps) / params.ramp_length : 0.0;
    for (std::int32_t i = 0; i < kRampSteps; ++i) {
        // Entry i covers d in [i, i+1) steps; it takes the value at d = (i+1) steps,
        // the far (free) end of the step.
        const double d = static_cast<double>(i + 1) / static_cast<double>(kRampSteps);  // fraction of the ramp
        const double p = 0.5 + (params.p_miss - 0.5) * d;
        t.ramp_[i] = log_odds_from_probability(p);
    }
}

}  // namespace cellguard
