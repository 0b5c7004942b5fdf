// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file demo_log_check.hpp
/// The check behind cellguard-monitor-check-log: a candump log written by
/// `cellguard-monitor --demo` is read back as the robot's PLC would receive
/// it. Every frame goes to the PLC-side receiver (plc_receiver.hpp) at its
/// time stamp, and between time stamps the receiver is polled on the log's
/// clock every demo_log_poll_interval_us(), up to the end of the expected run
/// (the first frame's time plus CYCLES periods), as a PLC polls it every PLC
/// cycle. So frames that stop early (silence longer than the SCT), a frame
/// delayed past the SRVT and a pair split by more than the SRVT all fail.
///
/// The checks, each a failure message when it does not hold:
/// - every line parses (candump -L format) and carries the safety frame, its
///   inverted copy or the diagnostics frame of the demo's channel;
/// - safety counters run 0..14 in order; each inverted copy matches the
///   safety frame before it; diagnostics pages run 0..3 in order;
/// - the PLC receiver never enters the safe state (every fault is reported
///   with where it was seen: a log line or a poll), it is valid from the third
///   pair on (the reference pair and two recovery pairs) and its stop
///   decision follows each frame's stop bit;
/// - 3 x CYCLES lines and CYCLES safety frames;
/// - the stop request appears in the cycle in which the scripted person
///   (scenario.hpp) enters a protective zone, and not in the cycle before.
#ifndef CELLGUARD_MONITOR_DEMO_LOG_CHECK_HPP
#define CELLGUARD_MONITOR_DEMO_LOG_CHECK_HPP

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/host/cell/config.hpp"

namespace cellguard::monitor {

/// Largest CYCLES the check accepts (the monitor's --cycles limit).
constexpr int kDemoLogMaxCycles = 1000000;

/// What check_demo_log found.
struct DemoLogCheck {
    /// False when the check could not run: the log cannot be opened, CYCLES is
    /// outside 1..kDemoLogMaxCycles, or the configuration gives no valid PLC
    /// receiver configuration (failures says which). The program exits 2 then.
    bool input_ok = true;
    std::vector<std::string> failures;  ///< one message per failed check, in log order
    std::string summary;                ///< one line: counts, receiver, entry cycle, stop bit

    /// True when the check ran and nothing failed.
    [[nodiscard]] bool passed() const noexcept { return input_ok && failures.empty(); }
};

/// The PLC receiver's configuration for the log of @p config: its channel and
/// zone count, SRVT half a period, SCT three periods.
[[nodiscard]] PlcReceiverConfig demo_log_receiver_config(const cell::MonitorConfig& config);

/// The PLC's poll interval on the log's clock: 1 ms, or SRVT / 10 when that
/// is shorter (at least 1 us).
[[nodiscard]] std::uint64_t demo_log_poll_interval_us(const PlcReceiverConfig& receiver) noexcept;

/// Checks the candump log read from @p log, written by a demo run of
/// @p cycles cycles of @p config (see the file comment).
[[nodiscard]] DemoLogCheck check_demo_log(std::istream& log, int cycles, const cell::MonitorConfig& config);

/// check_demo_log on the file at @p path; input_ok is false when it cannot be opened.
[[nodiscard]] DemoLogCheck check_demo_log_file(const std::string& path, int cycles, const cell::MonitorConfig& config);

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_DEMO_LOG_CHECK_HPP
