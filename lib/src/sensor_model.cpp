#include "cellguard/sensor_model.hpp"

#include <cmath>

#include "cellguard/log_odds.hpp"

namespace cellguard {

SensorModelTable::SensorModelTable() noexcept { tabulate(SensorModelParams{}); }

Result<SensorModelTable> SensorModelTable::make(const SensorModelParams& params) noexcept {
    if (!std::isfinite(params.p_origin) || !std::isfinite(params.p_reading) || !std::isfinite(params.ramp_length)) {
        return ErrorCode::kNonFiniteValue;
    }
    if (!(params.p_origin > 0.0 && params.p_origin < 0.5 && params.p_reading > 0.5 && params.p_reading < 1.0 &&
          params.ramp_length >= 0.0 && params.ramp_length <= 10.0)) {
        return ErrorCode::kInvalidArgument;
    }
    SensorModelTable t;
    t.tabulate(params);
    return t;
}

void SensorModelTable::tabulate(const SensorModelParams& params) noexcept {
    SensorModelTable& t = *this;
    t.params_ = params;
    t.ramp_length_ = params.ramp_length;
    t.free_ = log_odds_from_probability(params.p_origin);
    t.reading_ = log_odds_from_probability(params.p_reading);
    t.steps_per_metre_ = params.ramp_length > 0.0 ? static_cast<double>(kRampSteps) / params.ramp_length : 0.0;
    for (std::int32_t i = 0; i < kRampSteps; ++i) {
        // Entry i covers d in [i, i+1) steps; it takes the value at d = (i+1) steps,
        // the far (free) end of the step.
        const double d = static_cast<double>(i + 1) / static_cast<double>(kRampSteps);  // fraction of the ramp
        const double p = 0.5 + (params.p_origin - 0.5) * d;
        t.ramp_[i] = log_odds_from_probability(p);
    }
}

}  // namespace cellguard
