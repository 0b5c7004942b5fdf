// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monitor feeds its watchdogs only after healthy cycles
// (watchdog_feed.hpp), and its command link checks the clock's rate against
// the PLC's samples (command_link.hpp, [can] command_period_ms) and the
// controller latches the clock fault it reports.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "cellguard/can/plc_command_sender.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/watchdog_feed.hpp"
#include "cellguard/port/log_queue.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

constexpr std::uint64_t kBudget = 100000U;

CycleReport report(std::uint64_t cycle, std::uint32_t latched, bool stop) {
    CycleReport r;
    r.cycle = cycle;
    r.safety.latched_faults = latched;
    r.safety.stop_requested = stop;
    return r;
}

RobotCommand robot_command() {
    RobotCommand c;
    c.monitoring_case = 1U;
    c.joint_count = 6U;
    c.robot_id = 0x1234U;
    return c;
}

/// Polls a simulated PLC link whose samples come every PLC period; the local
/// clock runs at (1 + rate_ppm / 1e6). Returns the poll at which the link's
/// rate check first reported the clock fault (-1: never within @p polls).
int first_clock_fault(std::int64_t rate_ppm, int polls) {
    ClockRateConfig rate;
    rate.nominal_period_us = 100000U;
    rate.window_periods = 20U;
    CommandReceiverConfig rc;
    rc.sct_us = 250000U;
    PlcReceiverConfig pc;
    pc.sct_us = 250000U;
    SimulatedPlcLink link(rc, pc, nullptr, rate);
    link.set_command(robot_command());
    // The controller's side of the session link: its frames after each poll, echoing the PLC.
    CycleFrameEncoder output(SafetyOutputConfig{});
    for (int k = 0; k < polls; ++k) {
        const std::uint64_t local = 1000000U + static_cast<std::uint64_t>(k) * 100000U +
                                    static_cast<std::uint64_t>(static_cast<std::int64_t>(k) * 100000 * rate_ppm /
                                                               1000000);
        static_cast<void>(link.poll(local));
        CycleReport report{};
        report.started_us = local;
        link.on_sent(output.encode(report, 0U, &link.controller_link()), local + 1U);
        if (link.clock_rate().faults() == fault_bit(Fault::kClockFault)) {
            return k;
        }
    }
    return -1;
}

}  // namespace

// verifies: SR-WDG-001
TEST_CASE("watchdog feed: a new cycle within budget without a non-recoverable fault feeds, a person's stop too") {
    CHECK(decide_feed({1U, 5000U, 0U}, kBudget, 0U) == FeedRefusal::kNone);
    CHECK(decide_feed({2U, kBudget, 0U}, kBudget, 1U) == FeedRefusal::kNone);  // exactly the budget
    // Safe state for reasons that are not the controller's own failure: healthy.
    const std::uint32_t recoverable = fault_bit(Fault::kSensorMissing) | fault_bit(Fault::kSensorStale) |
                                      fault_bit(Fault::kCommandInvalid) | fault_bit(Fault::kCanError) |
                                      fault_bit(Fault::kCycleOverrun) | fault_bit(Fault::kFrameInconsistent) |
                                      fault_bit(Fault::kZoneEvaluation);
    CHECK(decide_feed({3U, 5000U, recoverable}, kBudget, 2U) == FeedRefusal::kNone);
}

// verifies: SR-WDG-001
TEST_CASE("watchdog feed: no new cycle, a cycle over budget or a non-recoverable fault feeds nothing") {
    CHECK(decide_feed({5U, 5000U, 0U}, kBudget, 5U) == FeedRefusal::kNoNewCycle);
    CHECK(decide_feed({4U, 5000U, 0U}, kBudget, 5U) == FeedRefusal::kNoNewCycle);
    CHECK(decide_feed({0U, 5000U, 0U}, kBudget, 0U) == FeedRefusal::kNoNewCycle);
    CHECK(decide_feed({6U, kBudget + 1U, 0U}, kBudget, 5U) == FeedRefusal::kOverBudget);
    for (const Fault f : {Fault::kInternalCheck, Fault::kClockFault, Fault::kPriorCheckFailed}) {
        CAPTURE(to_string(f));
        CHECK(decide_feed({6U, 5000U, fault_bit(f)}, kBudget, 5U) == FeedRefusal::kNonRecoverableFault);
    }
    CHECK(std::string(to_string(FeedRefusal::kOverBudget)) == "cycle over budget");
}

// verifies: SR-WDG-001
TEST_CASE("watchdog feed: the observer counts fed and refused cycles and logs each change once") {
    linux_port::LogQueue log(16U);
    WatchdogFeed feed(nullptr, nullptr, kBudget, &log);
    const CycleReport healthy1 = report(1U, 0U, false);
    const CycleReport person = report(2U, 0U, true);
    const CycleReport slow = report(3U, 0U, false);
    const CycleReport clock = report(4U, fault_bit(Fault::kClockFault), true);
    const CycleReport clock_again = report(5U, fault_bit(Fault::kClockFault), true);
    feed.after_cycle(CycleView{0, &healthy1, 5000U, 1U});
    feed.after_cycle(CycleView{1, &person, 5000U, 2U});
    feed.after_cycle(CycleView{1, &person, 5000U, 3U});  // the same report again
    feed.after_cycle(CycleView{2, &slow, kBudget + 1U, 4U});
    feed.after_cycle(CycleView{3, &clock, 5000U, 5U});
    feed.after_cycle(CycleView{4, &clock_again, 5000U, 6U});
    CHECK(feed.counts().fed == 2U);
    CHECK(feed.counts().no_new_cycle == 1U);
    CHECK(feed.counts().over_budget == 1U);
    CHECK(feed.counts().non_recoverable == 2U);
    // Lines: refused (no new cycle), refused (budget), refused (fault); not one per cycle.
    int lines = 0;
    bool fault_line = false;
    linux_port::LogLine line;
    while (log.pop(line)) {
        ++lines;
        fault_line = fault_line || std::string(line.text).find("not fed: non-recoverable fault latched (cycle 3)") !=
                                       std::string::npos;
    }
    CHECK(lines == 3);
    CHECK(fault_line);
}

// verifies: SR-WDG-004
TEST_CASE("clock rate in the command link: a local clock 5 percent fast is found, the true rate is not") {
    CHECK(first_clock_fault(50000, 60) >= 20);  // not before the first window of 20 PLC periods
    CHECK(first_clock_fault(50000, 60) <= 24);  // within it, after the receiver's start-up samples
    CHECK(first_clock_fault(-50000, 60) >= 20);
    CHECK(first_clock_fault(-50000, 60) <= 24);
    CHECK(first_clock_fault(0, 200) == -1);
    CHECK(first_clock_fault(5000, 200) == -1);
}

// verifies: SR-WDG-004
TEST_CASE("clock rate in the configuration: [can] command_period_ms turns it on, bad values are refused") {
    const std::string base = cell::demo_config_text();
    const std::string with = [&base] {
        std::string t = base;
        const std::size_t at = t.find("[can]\n");
        REQUIRE(at != std::string::npos);
        t.insert(at + 6U, "command_period_ms = 50\nclock_rate_window = 40\nclock_rate_tolerance_percent = 1.5\n");
        return t;
    }();
    const cell::ConfigLoad l = cell::parse_monitor_config(with, "cell.toml");
    CAPTURE(l.error);
    REQUIRE(l.ok);
    CHECK(l.config.can.clock_rate.nominal_period_us == 50000U);
    CHECK(l.config.can.clock_rate.window_periods == 40U);
    CHECK(l.config.can.clock_rate.tolerance_ppm == 15000U);
    CHECK(clock_rate_config(l.config).nominal_period_us == 50000U);
    const cell::ConfigLoad off = cell::parse_monitor_config(base, "cell.toml");
    REQUIRE(off.ok);
    CHECK(off.config.can.clock_rate.nominal_period_us == 0U);
    std::string bad = with;
    const std::string key = "clock_rate_tolerance_percent = 1.5";
    bad.replace(bad.find(key), key.size(), "clock_rate_tolerance_percent = 60");
    const cell::ConfigLoad refused = cell::parse_monitor_config(bad, "cell.toml");
    CHECK_FALSE(refused.ok);
    CHECK(refused.error.find("can.clock_rate_tolerance_percent") != std::string::npos);
}
