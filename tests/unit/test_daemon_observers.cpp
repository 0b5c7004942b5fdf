// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the monitor's event log and service status (apps/monitor:
// daemon_observers.hpp): a line per change with its priority (zone states,
// stop and release, faults latched and cleared), none for unchanged cycles,
// the heartbeat by the monotonic clock, a full queue dropping lines without
// the cycle waiting, and no allocation.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/daemon_observers.hpp"

using namespace cellguard;
using namespace cellguard::monitor;
using cellguard::linux_port::LogLine;
using cellguard::linux_port::LogPriority;
using cellguard::linux_port::LogQueue;

namespace {

struct Logged {
    LogPriority priority;
    std::string text;
};

std::vector<Logged> take(LogQueue& q) {
    std::vector<Logged> out;
    LogLine line;
    while (q.pop(line)) {
        out.push_back(Logged{line.priority, line.text});
    }
    return out;
}

/// A report with zone 0 (protective) and zone 1 (warning) in the given states.
CycleReport report(bool stop, ZoneState protective, ZoneState warning, std::uint32_t faults) {
    CycleReport r;
    r.safety.stop_requested = stop;
    r.safety.warning = warning == ZoneState::kIntruded;
    r.safety.latched_faults = faults;
    r.zones.count = 2U;
    r.zones.zones[0].state = protective;
    r.zones.zones[1].state = warning;
    return r;
}

}  // namespace

// verifies: SR-SYS-008, SR-GEN-002
TEST_CASE("event log: one line per change with its priority, none for unchanged cycles, no allocation") {
    const cell::MonitorConfig cfg = cell::demo_config();
    REQUIRE(cfg.zones.size() == 2U);
    LogQueue q(64U);
    EventLog log(cfg, q, 10000000U);
    const std::uint32_t missing = fault_bit(Fault::kSensorMissing);
    const std::vector<CycleReport> reports = {
        report(true, ZoneState::kClear, ZoneState::kClear, 0U),        // 0: start-up stop
        report(false, ZoneState::kClear, ZoneState::kClear, 0U),       // 1: released
        report(false, ZoneState::kClear, ZoneState::kClear, 0U),       // 2: nothing
        report(false, ZoneState::kClear, ZoneState::kIntruded, 0U),    // 3: warning zone
        report(true, ZoneState::kIntruded, ZoneState::kIntruded, 0U),  // 4: the protective stop
        report(true, ZoneState::kIntruded, ZoneState::kIntruded, 0U),  // 5: nothing
        report(true, ZoneState::kFault, ZoneState::kFault, missing),   // 6: a camera fault
        report(false, ZoneState::kClear, ZoneState::kClear, 0U),       // 7: cleared, released
    };
    std::size_t allocations = 0U;
    {
        const cellguard::test::AllocationScope scope;
        for (std::size_t k = 0U; k < reports.size(); ++k) {
            log.after_cycle(CycleView{static_cast<int>(k), &reports[k], 1000U, 1000000U + k * 1000U});
        }
        allocations = scope.allocations();
    }
    CHECK(allocations == 0U);
    const std::vector<Logged> lines = take(q);
    std::vector<std::string> texts;
    for (const Logged& l : lines) {
        texts.push_back(l.text);
    }
    const std::vector<std::string> expected = {
        "stop requested at start-up (restart interlock: not yet released): intruded -, unseen -, faults - (cycle 0)",
        "stop released: the robot may run (cycle 1)",
        "zone 'warning' (warning): CLEAR -> INTRUDED (cycle 3)",
        "zone 'protective' (protective): CLEAR -> INTRUDED (cycle 4)",
        "protective stop (a protective zone intruded): intruded protective,warning, unseen -, faults - (cycle 4)",
        "zone 'protective' (protective): INTRUDED -> FAULT (cycle 6)",
        "zone 'warning' (warning): INTRUDED -> FAULT (cycle 6)",
        "fault latched: sensor missing (cycle 6)",
        "zone 'protective' (protective): FAULT -> CLEAR (cycle 7)",
        "zone 'warning' (warning): FAULT -> CLEAR (cycle 7)",
        "fault cleared: sensor missing (cycle 7)",
        "stop released: the robot may run (cycle 7)",
    };
    CHECK(texts == expected);
    REQUIRE(lines.size() == expected.size());
    CHECK(lines[0].priority == LogPriority::kWarning);
    CHECK(lines[1].priority == LogPriority::kNotice);
    CHECK(lines[2].priority == LogPriority::kWarning);
    CHECK(lines[4].priority == LogPriority::kWarning);
    CHECK(lines[7].priority == LogPriority::kError);
    CHECK(lines[8].priority == LogPriority::kNotice);
    CHECK(lines[10].priority == LogPriority::kNotice);
    CHECK(log.counts().stops == 1U);
    CHECK(log.counts().cycles == reports.size());
    CHECK(log.counts().heartbeats == 0U);
}

// Issue 32: a separation stop was logged as "intruded -, unseen -, faults -", with no reason.
// verifies: SR-SYS-008
TEST_CASE("event log: every stop line says why: separation, a fault, an unseen zone, the restart interlock") {
    const cell::MonitorConfig cfg = cell::demo_config();
    LogQueue q(64U);
    EventLog log(cfg, q, 0U);
    CycleReport separation = report(true, ZoneState::kClear, ZoneState::kClear, 0U);
    separation.robot.configured = true;
    separation.robot.speed_request = SpeedRequest::kProtectiveStop;
    separation.robot.distance_mm = 1600U;
    separation.robot.required_mm = 1648U;
    const std::vector<CycleReport> reports = {
        report(false, ZoneState::kClear, ZoneState::kClear, 0U),
        separation,
        report(false, ZoneState::kClear, ZoneState::kClear, 0U),
        report(true, ZoneState::kClear, ZoneState::kClear, fault_bit(Fault::kCommandInvalid)),
        report(false, ZoneState::kClear, ZoneState::kClear, 0U),
        report(true, ZoneState::kUnseen, ZoneState::kClear, 0U),
    };
    for (std::size_t k = 0U; k < reports.size(); ++k) {
        log.after_cycle(CycleView{static_cast<int>(k), &reports[k], 1000U, 1000000U + k * 1000U});
    }
    std::vector<std::string> stops;
    for (const Logged& l : take(q)) {
        if (l.text.find("stop (") != std::string::npos) {
            stops.push_back(l.text);
        }
    }
    const std::vector<std::string> expected = {
        "protective stop (separation: d 1.60 m < S_p 1.65 m): intruded -, unseen -, faults - (cycle 1)",
        "protective stop (a fault latched): intruded -, unseen -, faults command invalid (cycle 3)",
        "protective stop (a protective zone unseen): intruded -, unseen protective, faults - (cycle 5)",
    };
    CHECK(stops == expected);
}

// verifies: SR-SYS-008, SR-GEN-002
TEST_CASE("event log: the heartbeat comes by the monotonic clock, a full queue drops lines and counts them") {
    const cell::MonitorConfig cfg = cell::demo_config();
    LogQueue q(2U);
    EventLog log(cfg, q, 10000000U);
    const CycleReport quiet = report(false, ZoneState::kClear, ZoneState::kClear, 0U);
    std::uint64_t now = 5000000U;
    std::size_t allocations = 0U;
    {
        const cellguard::test::AllocationScope scope;
        for (int k = 0; k < 1000; ++k) {  // 100 ms apart: 100 s
            log.after_cycle(CycleView{k, &quiet, 2000U + static_cast<std::uint64_t>(k), now});
            now += 100000U;
        }
        allocations = scope.allocations();
    }
    CHECK(allocations == 0U);
    CHECK(log.counts().heartbeats == 9U);  // at 10 s, 20 s, ... 90 s after the first cycle
    // The queue holds 2: the release line and the first heartbeat; the rest were dropped.
    CHECK(q.dropped() == 1U + 9U - 2U);
    const std::vector<Logged> lines = take(q);
    REQUIRE(lines.size() == 2U);
    CHECK(lines[1].priority == LogPriority::kInfo);
    CHECK(lines[1].text.rfind("heartbeat: 101 cycles, 0 with the stop requested, 0 stops; longest cycle 2.10 ms since "
                              "the last heartbeat, 2.10 ms in all; faults latched: -; log lines dropped: 0 (cycle 100)",
                              0) == 0);
}
