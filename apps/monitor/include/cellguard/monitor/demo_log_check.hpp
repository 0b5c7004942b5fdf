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
///   inverted copy, the controller's link frame, the diagnostics frame of
///   the demo's channel or the simulated PLC's link frame (protocol 0.2);
/// - safety counters run 0..14 in order; each inverted copy matches the
///   safety frame before it; diagnostics pages run 0..3 in order;
/// - the PLC receiver never enters the safe state (every fault is reported
///   with where it was seen: a log line or a poll), it is valid from the third
///   pair on (the reference pair and two recovery pairs; one more after a
///   start-up handshake) and its stop decision, taken when the pair's link
///   frame arrives, follows each frame's stop bit;
/// - the session link: both endpoints are re-run from the log (each side's
///   session taken from its first link frame): every link frame must carry
///   the sequence, session and echo its endpoint sends (the controller's
///   stamped at its safety frame's time, the PLC's at its sample's part A
///   or, alone, at its own time); the PLC receiver checks the controller's
///   link frames (binding to the pair, echo, round trip within the watchdog
///   time on the log's clock), the controller's side the PLC's (closing a
///   command sample, or alone: LinkEndpoint::on_standalone_frame); a
///   kNoEchoYet on a side that has sent nothing yet is the start-up
///   handshake, counted, not a failure; one link frame of each side per cycle;
/// - 5 x CYCLES lines and CYCLES safety frames;
/// - the stop request appears in the cycle in which the scripted person
///   (scenario.hpp) enters a protective zone, and not in the cycle before.
///
/// A cell with a robot (`--demo robot-cell`: config.robot.enabled) sends a
/// fifth frame per cycle, the separation frame, and its log also holds the
/// simulated PLC's command frames (six per sample and its link frame, one
/// sample per cycle, before the cycle's output frames). There, besides the
/// checks above:
/// - every separation frame decodes (E2E: data ID, CRC, counter range,
///   reserved bits), comes right after its cycle's diagnostics frame, and its
///   counter runs 0..14 in order; its case is the safety frame's ActiveCase,
///   its speed request matches the safety frame's ReducedSpeed bit (and a stop
///   request its ProtectiveStop bit), and a distance below the required one
///   comes with a stop request;
/// - the command frames go to a CommandReceiver configured as the monitor's
///   (command_receiver_config, command_link.hpp), polled at each safety frame's time:
///   it never enters the safe state (so every command in the log was valid,
///   in order, complete and timely), and it is valid from the third sample on;
/// - a cycle whose separation frame says CommandValid used exactly the
///   sample the receiver holds: same command counter, and the echoed case
///   (ActiveCase) is the commanded one;
/// - (5 + 7) x CYCLES lines, CYCLES safety and separation frames;
/// - instead of the scripted person's entry: the start-up stop is released,
///   and a stop request follows the release (the scene's person comes close);
///   the summary names the cycles of the release, the first reduced speed and
///   the first stop after it.
#ifndef CELLGUARD_MONITOR_DEMO_LOG_CHECK_HPP
#define CELLGUARD_MONITOR_DEMO_LOG_CHECK_HPP

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "cellguard/can/command_receiver.hpp"
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
/// zone count, SRVT half a period, SCT three periods, the session link's
/// watchdog three periods (plc_receiver_config, command_link.hpp).
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
