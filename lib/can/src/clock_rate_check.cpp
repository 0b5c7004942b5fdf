// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The clock's rate against the PLC's command samples (clock_rate_check.hpp).
#include "cellguard/can/clock_rate_check.hpp"

#include <cstdint>

#include "cellguard/base/contract.hpp"
#include "cellguard/base/saturating.hpp"
#include "cellguard/can/e2e_crc.hpp"

namespace cellguard {
namespace {

constexpr std::uint64_t kMinPeriodUs = 1000U;
constexpr std::uint64_t kMaxPeriodUs = 10000000U;
constexpr std::uint32_t kMinWindow = 10U;
constexpr std::uint32_t kMaxWindow = 100000U;
constexpr std::uint32_t kMinTolerancePpm = 1000U;
constexpr std::uint32_t kMaxTolerancePpm = 500000U;
constexpr std::uint8_t kMaxGapPeriods = 7U;  // under half the counter's 15 values: a step cannot alias

std::int32_t abs_ppm(std::int32_t v) noexcept { return v < 0 ? (v == INT32_MIN ? INT32_MAX : -v) : v; }

}  // namespace

Status ClockRateCheck::check_config(const ClockRateConfig& config) noexcept {
    if (config.nominal_period_us == 0U) {
        return Status{};  // off
    }
    if (config.nominal_period_us < kMinPeriodUs || config.nominal_period_us > kMaxPeriodUs ||
        config.window_periods < kMinWindow || config.window_periods > kMaxWindow ||
        config.tolerance_ppm < kMinTolerancePpm || config.tolerance_ppm > kMaxTolerancePpm ||
        config.max_gap_periods < 1U || config.max_gap_periods > kMaxGapPeriods) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

ClockRateCheck::ClockRateCheck(const ClockRateConfig& config) noexcept : config_(config) {
    CG_ENFORCE(check_config(config).ok(), "ClockRateCheck needs a configuration that passes check_config");
}

std::int32_t ClockRateCheck::deviation_ppm(std::uint64_t elapsed_us, std::uint64_t periods,
                                           std::uint64_t period_us) noexcept {
    if (periods == 0U || period_us == 0U || periods > UINT64_MAX / period_us) {
        return 0;
    }
    const std::uint64_t expected = periods * period_us;
    const bool fast = elapsed_us >= expected;
    const std::uint64_t diff = fast ? elapsed_us - expected : expected - elapsed_us;
    // diff * 1e6 / expected without overflow: whole multiples first, then the rest.
    const std::uint64_t whole = diff / expected;
    if (whole >= 2147U) {
        return fast ? INT32_MAX : INT32_MIN + 1;  // GCOVR_EXCL_BR_LINE: a slow clock has whole <= 1
    }
    const std::uint64_t rest = diff % expected;  // < expected <= 1e5 * 1e7 = 1e12: rest * 1e6 < 2^64
    const std::uint64_t ppm = whole * 1000000U + (rest * 1000000U + expected / 2U) / expected;
    const std::uint64_t capped = ppm > static_cast<std::uint64_t>(INT32_MAX) ? INT32_MAX : ppm;
    return fast ? static_cast<std::int32_t>(capped) : -static_cast<std::int32_t>(capped);
}

void ClockRateCheck::restart() noexcept {
    if (have_last_) {
        counts_.restarts = saturating_increment(counts_.restarts);
    }
    have_last_ = false;
    window_periods_ = 0U;
}

void ClockRateCheck::start_window(std::uint8_t counter, std::uint64_t received_us) noexcept {
    have_last_ = true;
    last_counter_ = counter;
    last_us_ = received_us;
    window_start_us_ = received_us;
    window_periods_ = 0U;
}

ClockRateVerdict ClockRateCheck::finish_window(std::uint64_t received_us) noexcept {
    const std::int32_t dev = deviation_ppm(received_us - window_start_us_, window_periods_, config_.nominal_period_us);
    counts_.windows = saturating_increment(counts_.windows);
    counts_.last_deviation_ppm = dev;
    if (abs_ppm(dev) > counts_.max_abs_deviation_ppm) {
        counts_.max_abs_deviation_ppm = abs_ppm(dev);
    }
    // The next window starts at this sample: consecutive windows share it, so no time goes unmeasured.
    window_start_us_ = received_us;
    window_periods_ = 0U;
    if (abs_ppm(dev) > static_cast<std::int32_t>(config_.tolerance_ppm)) {
        faulted_ = true;
        return ClockRateVerdict::kOutOfTolerance;
    }
    return ClockRateVerdict::kWithinTolerance;
}

ClockRateVerdict ClockRateCheck::on_sample(std::uint8_t counter, std::uint64_t received_us) noexcept {
    if (!enabled()) {
        return ClockRateVerdict::kPending;
    }
    counts_.samples = saturating_increment(counts_.samples);
    if (counter > kE2eP01CounterMax) {
        restart();
        return ClockRateVerdict::kPending;
    }
    if (!have_last_) {
        start_window(counter, received_us);
        return ClockRateVerdict::kPending;
    }
    const std::uint8_t delta = e2e_p01_counter_delta(counter, last_counter_);
    if (delta == 0U) {
        return ClockRateVerdict::kPending;  // a repeated sample: no time information
    }
    const std::uint64_t gap_limit_us = config_.nominal_period_us * config_.max_gap_periods;
    if (received_us < last_us_ || delta > config_.max_gap_periods || received_us - last_us_ > gap_limit_us) {
        restart();
        start_window(counter, received_us);
        return ClockRateVerdict::kPending;
    }
    window_periods_ += delta;
    last_counter_ = counter;
    last_us_ = received_us;
    if (window_periods_ < config_.window_periods) {
        return ClockRateVerdict::kPending;
    }
    return finish_window(received_us);
}

}  // namespace cellguard
