// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the controller clock's rate against the PLC's command samples
// (clock_rate_check.hpp): 5 % fast and slow are found within the window, 0.5 %
// with stamp jitter is not; the counter's wrap, lost samples, a PLC that
// stops, time going backwards; no heap.
#include <doctest/doctest.h>

#include <cstdint>

#include "alloc_counter.hpp"
#include "cellguard/can/clock_rate_check.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

constexpr std::uint64_t kT = 100000U;    // the PLC's nominal period, 100 ms
constexpr std::uint64_t kT0 = 5000000U;  // the local time of the PLC's sample 0

ClockRateConfig config(std::uint32_t window = 50U, std::uint32_t tolerance_ppm = 20000U) {
    ClockRateConfig c;
    c.nominal_period_us = kT;
    c.window_periods = window;
    c.tolerance_ppm = tolerance_ppm;
    return c;
}

/// A PLC whose sample k is sent at k T on its own clock and stamped on the
/// local clock, which runs at (1 + rate_ppm / 1e6) times the true rate,
/// plus a jitter of at most @p jitter_us (alternating +- its full value: the
/// worst case for a window's two ends, and a pseudo-random one between).
struct Plc {
    std::int64_t rate_ppm = 0;
    std::int64_t jitter_us = 0;
    std::uint64_t stamp(std::uint64_t k) const {
        const std::int64_t ideal = static_cast<std::int64_t>(k * kT) +
                                   static_cast<std::int64_t>(k * kT) * rate_ppm / 1000000;
        std::int64_t j = 0;
        if (jitter_us != 0) {
            j = (k % 2U == 0U) ? jitter_us : -jitter_us;
            if (k % 7U == 3U) {
                j = static_cast<std::int64_t>((k * 7919U) % static_cast<std::uint64_t>(2 * jitter_us + 1)) - jitter_us;
            }
        }
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(kT0) + ideal + j);
    }
    static std::uint8_t counter(std::uint64_t k) { return static_cast<std::uint8_t>(k % 15U); }
};

/// Feeds samples [from, to) of @p plc; returns the sample index of the first
/// kOutOfTolerance verdict, or -1.
long long feed(ClockRateCheck& check, const Plc& plc, std::uint64_t from, std::uint64_t to) {
    for (std::uint64_t k = from; k < to; ++k) {
        if (check.on_sample(Plc::counter(k), plc.stamp(k)) == ClockRateVerdict::kOutOfTolerance) {
            return static_cast<long long>(k);
        }
    }
    return -1;
}

}  // namespace

// verifies: SR-WDG-003
TEST_CASE("clock rate: a clock 5 percent fast or slow is a clock fault at the end of the first window") {
    for (const std::int64_t rate : {50000, -50000}) {
        CAPTURE(rate);
        ClockRateCheck check(config());
        const Plc plc{rate, 10000};              // and 10 ms of stamp jitter
        CHECK(feed(check, plc, 0U, 50U) == -1);  // samples 0..49: 49 periods, the window is not complete
        CHECK_FALSE(check.faulted());
        CHECK(check.faults() == 0U);
        CHECK(check.on_sample(Plc::counter(50U), plc.stamp(50U)) == ClockRateVerdict::kOutOfTolerance);
        CHECK(check.faulted());
        CHECK(check.faults() == fault_bit(Fault::kClockFault));
        // Measured within 2 J / (W T) = 0.4 % of the true 5 %.
        CHECK(check.counts().last_deviation_ppm * (rate > 0 ? 1 : -1) >= 46000);
        CHECK(check.counts().last_deviation_ppm * (rate > 0 ? 1 : -1) <= 54000);
        // It stays faulted, whatever follows.
        const Plc good{0, 0};
        static_cast<void>(feed(check, good, 51U, 300U));
        CHECK(check.faulted());
    }
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: 0.5 percent fast or slow with 10 ms of stamp jitter is never flagged") {
    for (const std::int64_t rate : {5000, -5000, 0}) {
        CAPTURE(rate);
        ClockRateCheck check(config());
        const Plc plc{rate, 10000};
        CHECK(feed(check, plc, 0U, 2001U) == -1);
        CHECK_FALSE(check.faulted());
        CHECK(check.counts().windows == 40U);
        CHECK(check.counts().max_abs_deviation_ppm <= 9000);  // 0.5 % + 2 J / (W T) = 0.9 %
    }
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: the counter wraps every 15 samples and the windows stay exact") {
    ClockRateCheck check(config(20U));
    const Plc plc{0, 0};
    CHECK(feed(check, plc, 0U, 201U) == -1);  // 200 periods: 13 wraps of the counter
    CHECK(check.counts().windows == 10U);
    CHECK(check.counts().max_abs_deviation_ppm == 0);
    CHECK(check.counts().restarts == 0U);
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: lost samples still count by the counter, and a fast clock is still found") {
    SUBCASE("every third sample lost and runs of 4 lost: no fault at the true rate") {
        ClockRateCheck check(config());
        const Plc plc{0, 5000};
        for (std::uint64_t k = 0U; k < 1000U; ++k) {
            const bool lost = (k % 3U == 1U) || (k % 100U >= 40U && k % 100U < 44U);
            if (!lost) {
                CHECK(check.on_sample(Plc::counter(k), plc.stamp(k)) != ClockRateVerdict::kOutOfTolerance);
            }
        }
        CHECK_FALSE(check.faulted());
        CHECK(check.counts().restarts == 0U);
        CHECK(check.counts().windows >= 18U);
    }
    SUBCASE("every other sample lost, the clock 5 percent fast: found within the first window") {
        ClockRateCheck check(config());
        const Plc plc{50000, 0};
        long long found = -1;
        for (std::uint64_t k = 0U; k <= 60U && found < 0; k += 2U) {
            if (check.on_sample(Plc::counter(k), plc.stamp(k)) == ClockRateVerdict::kOutOfTolerance) {
                found = static_cast<long long>(k);
            }
        }
        CHECK(found == 50);
    }
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: a PLC that stops, a link fault and time going backwards restart the window, no fault") {
    ClockRateCheck check(config());
    const Plc plc{0, 0};
    CHECK(feed(check, plc, 0U, 30U) == -1);
    // Silence for 1 s (10 periods), then the PLC resumes: counter 40 after 29 (a step of 11, beyond 7).
    CHECK(feed(check, plc, 40U, 60U) == -1);
    CHECK(check.counts().restarts == 1U);
    // A step within the counter bound but too long in local time (the PLC paused 8 periods, counter +1).
    CHECK(check.on_sample(Plc::counter(60U), plc.stamp(68U)) == ClockRateVerdict::kPending);
    CHECK(check.counts().restarts == 2U);
    // The receiver found a fault: the caller restarts the window.
    check.restart();
    CHECK(check.counts().restarts == 3U);
    CHECK(check.on_sample(0U, plc.stamp(100U)) == ClockRateVerdict::kPending);
    CHECK(check.on_sample(1U, plc.stamp(100U) - 1U) == ClockRateVerdict::kPending);  // backwards
    CHECK(check.counts().restarts == 4U);
    // A repeated counter carries no time: ignored.
    CHECK(check.on_sample(1U, plc.stamp(101U)) == ClockRateVerdict::kPending);
    CHECK(check.counts().restarts == 4U);
    CHECK(check.counts().windows == 0U);
    CHECK_FALSE(check.faulted());
    // A counter out of range (15) restarts too.
    CHECK(check.on_sample(15U, plc.stamp(102U)) == ClockRateVerdict::kPending);
    CHECK(check.counts().restarts == 5U);
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: off without a nominal period, and a configuration is checked") {
    ClockRateCheck off(ClockRateConfig{});
    CHECK_FALSE(off.enabled());
    const Plc fast{200000, 0};
    CHECK(feed(off, fast, 0U, 500U) == -1);
    CHECK(off.counts().samples == 0U);

    CHECK(ClockRateCheck::check_config(config()).ok());
    ClockRateConfig c = config();
    c.nominal_period_us = 999U;
    CHECK_FALSE(ClockRateCheck::check_config(c).ok());
    c = config(9U);
    CHECK_FALSE(ClockRateCheck::check_config(c).ok());
    c = config(50U, 999U);
    CHECK_FALSE(ClockRateCheck::check_config(c).ok());
    c = config();
    c.max_gap_periods = 8U;
    CHECK_FALSE(ClockRateCheck::check_config(c).ok());
    c.max_gap_periods = 0U;
    CHECK_FALSE(ClockRateCheck::check_config(c).ok());
    c = config();
    c.nominal_period_us = 10000001U;
    CHECK_FALSE(ClockRateCheck::check_config(c).ok());
    c = config(5U);
    CHECK(test::violates_contract([&c] { const ClockRateCheck refused(c); }));
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: the deviation in ppm rounds and saturates") {
    CHECK(ClockRateCheck::deviation_ppm(1050000U, 10U, 100000U) == 50000);
    CHECK(ClockRateCheck::deviation_ppm(950000U, 10U, 100000U) == -50000);
    CHECK(ClockRateCheck::deviation_ppm(1000000U, 10U, 100000U) == 0);
    CHECK(ClockRateCheck::deviation_ppm(1000001U, 10U, 100000U) == 1);
    CHECK(ClockRateCheck::deviation_ppm(0U, 10U, 100000U) == -1000000);
    CHECK(ClockRateCheck::deviation_ppm(UINT64_MAX, 10U, 100000U) == INT32_MAX);
    CHECK(ClockRateCheck::deviation_ppm(5U, 0U, 100000U) == 0);
    CHECK(ClockRateCheck::deviation_ppm(5U, UINT64_MAX, 100000U) == 0);
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: samples allocate nothing") {
    ClockRateCheck check(config());
    const Plc plc{50000, 1000};
    const test::AllocationScope scope;
    static_cast<void>(feed(check, plc, 0U, 200U));
    CHECK(scope.allocations() == 0U);
    CHECK(check.faulted());
}

// verifies: SR-WDG-003
TEST_CASE("clock rate: the configuration's upper limits are accepted and one beyond each is refused") {
    CHECK(ClockRateCheck::check_config(config(100000U)).ok());
    CHECK_FALSE(ClockRateCheck::check_config(config(100001U)).ok());
    CHECK(ClockRateCheck::check_config(config(50U, 500000U)).ok());
    CHECK_FALSE(ClockRateCheck::check_config(config(50U, 500001U)).ok());
    CHECK(ClockRateCheck::check_config(config(10U, 1000U)).ok());
    ClockRateConfig c = config();
    c.nominal_period_us = 10000000U;
    c.max_gap_periods = 7U;
    CHECK(ClockRateCheck::check_config(c).ok());
    c.max_gap_periods = 1U;
    CHECK(ClockRateCheck::check_config(c).ok());
}

// verifies: SR-WDG-003
TEST_CASE(
    "clock rate: a restart with no window open counts nothing, and only a faulted check reports the clock fault") {
    ClockRateCheck check(config());
    check.restart();  // no sample yet
    CHECK(check.counts().restarts == 0U);
    CHECK(check.faults() == 0U);
    CHECK(check.on_sample(0U, kT0) == ClockRateVerdict::kPending);
    check.restart();
    check.restart();  // the window is already closed
    CHECK(check.counts().restarts == 1U);
    const Plc fast{50000, 0};  // 5 percent fast
    CHECK(feed(check, fast, 0U, 60U) == 50);
    CHECK(check.faulted());
    CHECK(check.faults() == fault_bit(Fault::kClockFault));
}
