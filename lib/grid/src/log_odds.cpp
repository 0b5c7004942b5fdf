// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/log_odds.hpp"

#include <cmath>

namespace cellguard {

std::int16_t log_odds_from_probability(double p) noexcept {
    if (!(p > 0.0)) {  // also catches NaN
        return kNeverForeground;
    }
    if (p >= 1.0) {
        return kLogOddsMax;
    }
    const double nats = std::log(p) - std::log1p(-p);
    const double units = std::nearbyint(nats * static_cast<double>(kLogOddsScale));
    if (units >= static_cast<double>(kLogOddsMax)) {  // GCOVR_EXCL_BR_LINE: unreachable, binary64 p < 1 is < 9400 units
        return kLogOddsMax;
    }
    if (units <= static_cast<double>(kLogOddsMin)) {
        return kLogOddsMin;
    }
    return static_cast<std::int16_t>(units);
}

double probability_from_log_odds(std::int16_t raw) noexcept {
    if (raw == kNeverForeground) {
        return 0.0;
    }
    const double nats = static_cast<double>(raw) / static_cast<double>(kLogOddsScale);
    // Logistic function written to stay accurate for both signs.
    if (nats >= 0.0) {
        return 1.0 / (1.0 + std::exp(-nats));
    }
    const double e = std::exp(nats);
    return e / (1.0 + e);
}

std::int16_t threshold_log_odds(double t) noexcept {
    if (!(t > 0.0)) {
        return kLogOddsMin;
    }
    if (t >= 1.0) {
        return kLogOddsMax;
    }
    const double units = std::ceil((std::log(t) - std::log1p(-t)) * static_cast<double>(kLogOddsScale));
    if (units >= static_cast<double>(kLogOddsMax)) {  // GCOVR_EXCL_BR_LINE: unreachable, binary64 t < 1 is < 9400 units
        return kLogOddsMax;
    }
    if (units <= static_cast<double>(kLogOddsMin)) {
        return kLogOddsMin;
    }
    return static_cast<std::int16_t>(units);
}

}  // namespace cellguard
