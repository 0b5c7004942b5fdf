// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-vcan-plc: the robot PLC of the vcan integration test's robot cell
// (tools/vcan-integration.sh, tests/integration/vcan/vcan-test.sh, run 3),
// live on a real kernel CAN interface while cellguard-monitor runs
// `--config vcan-robot-cell.toml --commands can --paced` on it. Both ways,
// with the code a PLC ports (lib/can):
// - it sends the command with PlcCommandSender, a sample (six frames back
//   to back) every half period of the monitor (the protocol's "at least
//   every SCT / 2"; every period would leave a cycle without a sample at the
//   least jitter): the arm's pose over station A (the pose the scene
//   vcan-robot-scene.toml holds), speed class 0, the commissioned robot ID,
//   and monitoring case 0, then case 2 from the monitor's cycle SWITCH_AT;
//   ResetRequest pressed in every other monitor cycle while the last valid pair
//   showed a stop with every zone clear and seen and no fault (the PLC's
//   "reset possible" lamp: the monitor's restart interlock waits for it);
//   from cycle SILENT_AT it sends nothing more (a PLC that falls silent);
// - it receives the monitor's frames with PlcReceiver (polled every 10 ms)
//   and decodes the diagnostics and separation frames;
// - protocol 0.2: each sample ends with the PLC's link frame, its fields
//   from the receiver's link endpoint (the echo of the monitor's latest
//   link frame), and the receiver accepts a pair only with the monitor's
//   link frame, whose echo must be at most the watchdog time old;
// - after the silence, at the monitor's cycle DELAY_AT it sends a sample it
//   built when it fell silent (its link frame echoes a monitor link frame
//   then more than the watchdog time old: a delayed sample), and at cycle
//   REPLAY_AT a whole sample it sent 15 samples before the silence, byte for
//   byte (its E2E counter is the one 15 samples on: a replay); the monitor
//   must refuse both: CommandValid stays 0 and the stop stays.
// It starts sending when the monitor's first safety frame arrives and ends
// after the monitor's cycle END_AT (or when the monitor has been silent for
// 6 periods), then checks:
// - the PLC receiver was valid from the third pair on and never left it;
// - every cycle had its safety frame, copy, diagnostics and separation frame;
// - the monitor accepted the commands: from the first cycle that used a
//   valid command up to the silence, every cycle used one (CommandValid, no
//   kCommandInvalid in the diagnostics), and its echoed case (the safety
//   and the separation frame's ActiveCase) is the case of the sample it names
//   by counter (CommandCounter); both cases were echoed;
// - the stop was released after the start-up (by a ResetRequest edge: the
//   configuration requires the reset) and stayed released up to the silence;
// - when the PLC fell silent, the stop came within the stated response time,
//   SCT + 2 T from the last sample (can-safety-protocol.md, "Response time";
//   SCT = robot.max_command_age), with kCommandInvalid, and stayed, through
//   the delayed and the replayed sample.
// Time is CLOCK_MONOTONIC at reception (the monitor's clock in --paced mode).
//
// usage: cellguard-vcan-plc CONFIG IFACE SWITCH_AT SILENT_AT DELAY_AT REPLAY_AT END_AT BUDGET_MS
//        cellguard-vcan-plc link CONFIG IFACE
// BUDGET_MS is the monitor's --budget-ms: the session link's watchdog time is
// two periods plus the cycle budget on both sides (monitor::link_watchdog_us).
// The second form is the PLC of a cell without a robot (runs 1 and 2): it
// sends its link frame alone in reply to each of the monitor's link frames
// (PlcReceiver::next_link, encode_link_frame with no bound frames, its own
// E2E counter), so that the monitor echoes it; it checks nothing (the
// recording is checked by cellguard-vcan-check) and runs until SIGINT or
// SIGTERM, ignoring failed writes (the fault run takes the interface down).
// Exit status: 0 all checks passed, 1 a check failed, 2 usage, set-up or I/O error.
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "cellguard/can/fault_code.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/can/separation_frame.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/monitor_cell.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

int g_failures = 0;

void expect(bool ok, const std::string& what) {
    if (!ok) {
        ++g_failures;
        std::printf("FAIL: %s\n", what.c_str());
    }
}

std::uint64_t now_us() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::uint64_t>(ts.tv_sec) * 1000000U + static_cast<std::uint64_t>(ts.tv_nsec) / 1000U;
}

/// The arm's pose over station A (vcan-robot-scene.toml's keyframes), radians.
constexpr double kPoseRad[6] = {-1.5707963, 0.1, 1.2, 1.8416, 0.0, 0.0};

/// The seven frames of a protocol 0.2 sample, as sent.
using SampleFrames = std::array<CanFrame, kCommandFramesPerSample + 1U>;

/// A sample sent.
struct Sample {
    std::uint64_t t_us = 0U;      ///< after its last frame was written
    std::uint64_t burst_us = 0U;  ///< from before its first write to after its last
    std::uint8_t counter = 0U;
    std::uint8_t monitoring_case = 0U;
    bool reset_request = false;
};

/// What arrived of one monitor cycle.
struct Cycle {
    std::uint64_t t_us = 0U;  ///< safety frame received
    SafetyMessage safety;
    bool copy = false;
    bool receiver_valid = false;  ///< the PLC receiver after the pair's link frame
    bool diagnostics = false;
    std::uint16_t faults = 0U;
    bool separation = false;
    SeparationMessage sep;
};

/// The test's parameters and what happened.
struct Run {
    MonitorConfig cfg;
    std::uint16_t robot_id = 0U;
    int switch_at = 0;
    int silent_at = 0;
    int delay_at = 0;
    int replay_at = 0;
    int end_at = 0;
    std::vector<Sample> samples;
    std::vector<SampleFrames> sent;  ///< the frames of every sample sent, for the replay
    SampleFrames held{};             ///< the sample built at the silence, sent at DELAY_AT
    bool have_held = false;
    std::uint64_t held_us = 0U;      ///< when it was built
    int delayed_cycle = -1;          ///< the monitor's cycle count when the delayed sample went out
    double delayed_ms = -1.0;        ///< how long it was held
    int replayed_cycle = -1;         ///< the same for the replay
    std::size_t replayed_from = 0U;  ///< index of the replayed sample
    std::vector<Cycle> cycles;
    std::uint64_t last_sample_us = 0U;  ///< the last sample sent
    std::uint32_t receiver_faults = 0U;
    int first_valid_pair = -1;  ///< the cycle whose pair first made the receiver valid
    std::uint32_t faults_at_valid = 0U;
    std::string receiver_fault_text;
    bool reset_possible = false;  ///< the last valid pair: a stop with every zone clear and seen, no fault
};

/// As the monitor's simulated PLC: SRVT half a period, SCT three periods, the watchdog time three periods; a
/// session value of this start (the process ID's, 1..255).
PlcReceiverConfig receiver_config(const MonitorConfig& cfg) {
    PlcReceiverConfig rc = monitor::plc_receiver_config(cfg);
    rc.link.session = static_cast<std::uint8_t>(static_cast<unsigned>(getpid()) % 255U + 1U);
    return rc;
}

int open_socket(const char* ifname) {
    const int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        std::perror("socket");
        return -1;
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(if_nametoindex(ifname));
    if (addr.can_ifindex == 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
        std::perror("bind");
        close(fd);
        return -1;
    }
    return fd;
}

bool send_frame(int fd, const CanFrame& f) {
    can_frame k{};
    k.can_id = f.id;
    k.can_dlc = f.dlc;
    std::memcpy(k.data, f.data, sizeof(k.data));
    return write(fd, &k, sizeof(k)) == static_cast<ssize_t>(sizeof(k));
}

/// The next classic data frame waiting on @p fd, without blocking (extended, remote and error frames are
/// skipped); false when none is waiting.
bool receive_frame(int fd, CanFrame& out) {
    can_frame k{};
    while (recv(fd, &k, sizeof(k), MSG_DONTWAIT) == static_cast<ssize_t>(sizeof(k))) {
        if ((k.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0U || k.can_dlc > 8U) {
            continue;
        }
        out = CanFrame{};
        out.id = k.can_id & CAN_SFF_MASK;
        out.dlc = k.can_dlc;
        std::memcpy(out.data, k.data, sizeof(out.data));
        return true;
    }
    return false;
}

/// The next sample's seven frames (its link frame from @p plc at this time), or false when the sender refused.
bool build_sample(PlcCommandSender& sender, PlcReceiver& plc, Run& run, SampleFrames& out, Sample& s) {
    RobotCommand cmd;
    cmd.monitoring_case = static_cast<int>(run.cycles.size()) < run.switch_at ? 0U : 2U;
    cmd.speed_class = 0U;
    cmd.joint_count = 6U;
    for (std::size_t j = 0U; j < 6U; ++j) {
        cmd.joint_raw[j] = static_cast<std::int16_t>(std::lround(kPoseRad[j] / kRevoluteJointUnitRad));
    }
    cmd.robot_id = run.robot_id;
    // The operator presses reset while the lamp is on, in every other monitor cycle (two samples go out per
    // cycle: toggling per sample, every cycle would see the same level and no edge).
    cmd.reset_request = run.reset_possible && run.cycles.size() % 2U == 1U;
    s.counter = sender.counter();
    s.monitoring_case = cmd.monitoring_case;
    s.reset_request = cmd.reset_request;
    const Result<LinkedCommandFrames> frames = sender.next_sample(cmd, plc.next_link(now_us()), plc.config().link.own);
    if (!frames.ok()) {
        std::printf("the PLC-side sender refused the command\n");
        return false;
    }
    for (std::size_t i = 0U; i < kCommandFramesPerSample; ++i) {
        out[i] = frames.value().sample.frame[i];
    }
    out[kCommandFramesPerSample] = frames.value().link;
    return true;
}

/// Writes the seven frames of a sample; false when a write failed.
bool write_sample(int fd, const SampleFrames& frames) {
    for (const CanFrame& f : frames) {
        if (!send_frame(fd, f)) {
            std::perror("write");
            return false;
        }
    }
    return true;
}

/// Sends the next sample; false when the sender refused or a write failed.
bool send_sample(int fd, PlcCommandSender& sender, PlcReceiver& plc, Run& run) {
    Sample s;
    SampleFrames frames{};
    if (!build_sample(sender, plc, run, frames, s)) {
        return false;
    }
    const std::uint64_t t0 = now_us();
    if (!write_sample(fd, frames)) {
        return false;
    }
    s.t_us = now_us();
    s.burst_us = s.t_us - t0;  // the kernel stamps the frames within this span
    run.samples.push_back(s);
    run.sent.push_back(frames);
    run.last_sample_us = s.t_us;
    return true;
}

/// After the silence: the sample held since it began (a delayed sample) at
/// cycle DELAY_AT, a whole sample from 15 samples before it (a replay) at
/// cycle REPLAY_AT. False when a write failed.
bool inject(int fd, PlcCommandSender& sender, PlcReceiver& plc, Run& run) {
    const int cycle = static_cast<int>(run.cycles.size());
    if (!run.have_held) {
        Sample ignored;
        if (!build_sample(sender, plc, run, run.held, ignored)) {
            return false;
        }
        run.have_held = true;
        run.held_us = now_us();
    }
    if (cycle >= run.delay_at && run.delayed_cycle < 0) {
        run.delayed_cycle = cycle;
        run.delayed_ms = static_cast<double>(now_us() - run.held_us) / 1000.0;
        if (!write_sample(fd, run.held)) {
            return false;
        }
    }
    if (cycle >= run.replay_at && run.replayed_cycle < 0 && run.sent.size() >= 15U) {
        run.replayed_cycle = cycle;
        run.replayed_from = run.sent.size() - 15U;
        if (!write_sample(fd, run.sent[run.replayed_from])) {
            return false;
        }
    }
    return true;
}

/// One received frame: to the PLC receiver and into the cycle records.
void on_frame(const CanFrame& f, std::uint64_t t, PlcReceiver& plc, Run& run) {
    const ReceiverStatus rs = plc.on_frame(f, t);
    const SafetyChannelConfig& ch = run.cfg.can.channel;
    if (f.id == ch.safety_can_id) {
        Cycle c;
        c.t_us = t;
        const Result<SafetyFrameContent> d = decode_safety_frame(f, ch);
        expect(d.ok(), "cycle " + std::to_string(run.cycles.size()) + ": safety frame does not decode");
        c.safety = d.ok() ? d.value().message : SafetyMessage{};
        run.cycles.push_back(c);
    } else if (run.cycles.empty()) {
        return;  // the rest of a cycle whose safety frame came before this PLC listened
    } else if (f.id == inverted_can_id(ch)) {
        run.cycles.back().copy = true;
    } else if (f.id == plc.config().link.peer.can_id) {
        run.cycles.back().receiver_valid = rs.communication_valid;
        // The PLC's "reset possible" lamp: the controller holds a stop with every zone clear and seen and no
        // fault, which after the restart delay is its restart interlock waiting for ResetRequest.
        const SafetyMessage& m = rs.message;
        run.reset_possible = rs.communication_valid && m.protective_stop && !m.fault && m.zone_intrusion == 0U &&
                             m.zone_unseen == 0U;
        if (rs.communication_valid && run.first_valid_pair < 0) {
            run.first_valid_pair = static_cast<int>(run.cycles.size()) - 1;
            run.faults_at_valid = rs.fault_events;
        }
    } else if (f.id == ch.diagnostics_can_id) {
        const Result<DiagnosticsFrameContent> d = decode_diagnostics_frame(f, ch);
        expect(d.ok(), "cycle " + std::to_string(run.cycles.size() - 1U) + ": diagnostics frame does not decode");
        run.cycles.back().diagnostics = d.ok();
        run.cycles.back().faults = d.ok() ? d.value().message.active_faults : 0xFFFFU;
    } else if (f.id == ch.separation_can_id) {
        const Result<SeparationFrameContent> d = decode_separation_frame(f, ch);
        expect(d.ok(), "cycle " + std::to_string(run.cycles.size() - 1U) + ": separation frame does not decode");
        run.cycles.back().separation = d.ok();
        run.cycles.back().sep = d.ok() ? d.value().message : SeparationMessage{};
    }
    // Up to the silence: a PLC that sends nothing gets no fresh echo, and its
    // receiver then refuses the data as too old (the watchdog), as it should.
    if (static_cast<int>(run.cycles.size()) <= run.silent_at) {
        if (run.first_valid_pair >= 0 && rs.fault_events > run.faults_at_valid && run.receiver_faults == 0U) {
            run.receiver_fault_text = to_string(rs.fault);
        }
        run.receiver_faults = run.first_valid_pair >= 0 ? rs.fault_events - run.faults_at_valid : 0U;
    }
}

/// Reads every frame waiting on @p fd.
void drain(int fd, PlcReceiver& plc, Run& run) {
    CanFrame f{};
    while (receive_frame(fd, f)) {
        on_frame(f, now_us(), plc, run);
    }
}

/// The PLC's cycle until the monitor's cycle END_AT (see the file comment).
bool exchange(int fd, Run& run) {
    PlcReceiver plc(receiver_config(run.cfg));
    PlcCommandSender sender(run.cfg.can.command);
    const std::uint64_t half = run.cfg.period_us / 2U;
    const std::uint64_t t_begin = now_us();
    std::uint64_t next_send = 0U;
    std::uint64_t last_rx = t_begin;
    std::size_t seen = 0U;
    for (;;) {
        const std::uint64_t now = now_us();
        const bool started = !run.cycles.empty();
        const bool sending = started && static_cast<int>(run.cycles.size()) < run.silent_at;
        if (sending && now >= next_send) {
            if (!send_sample(fd, sender, plc, run)) {
                return false;
            }
            next_send = next_send == 0U || now > next_send + half ? now + half : next_send + half;
        }
        if (started && !sending && !inject(fd, sender, plc, run)) {
            return false;
        }
        // Cycle END_AT complete (or its last frames a period late).
        if (static_cast<int>(run.cycles.size()) > run.end_at &&
            (run.cycles.back().separation || now > run.cycles.back().t_us + run.cfg.period_us)) {
            return true;
        }
        if ((started && now > last_rx + 6U * run.cfg.period_us) || now > t_begin + 600000000U) {
            std::printf("the monitor fell silent after %zu cycles\n", run.cycles.size());
            return true;
        }
        pollfd p{fd, POLLIN, 0};
        static_cast<void>(::poll(&p, 1, 10));
        drain(fd, plc, run);
        if (run.cycles.size() != seen) {
            seen = run.cycles.size();
            last_rx = now_us();
        }
        const ReceiverStatus rs = plc.poll(now_us());
        if (static_cast<int>(run.cycles.size()) < run.silent_at && run.first_valid_pair >= 0 &&
            rs.fault_events > run.faults_at_valid && run.receiver_faults == 0U) {
            run.receiver_fault_text = to_string(rs.fault);
            run.receiver_faults = rs.fault_events - run.faults_at_valid;
        }
    }
}

/// The case of the latest sample with counter @p counter sent before @p t_us (-1: none).
/// The latest sample with E2E counter @p counter sent by @p t_us, or nullptr.
const Sample* sample_named(const Run& run, std::uint8_t counter, std::uint64_t t_us) {
    for (auto it = run.samples.rbegin(); it != run.samples.rend(); ++it) {
        if (it->counter == counter && it->t_us <= t_us) {
            return &*it;
        }
    }
    return nullptr;
}

int commanded_case(const Run& run, std::uint8_t counter, std::uint64_t t_us) {
    const Sample* s = sample_named(run, counter, t_us);
    return s != nullptr ? s->monitoring_case : -1;
}

/// Checks the cycles that used the PLC's commands; returns the first silent cycle.
std::size_t check_commands(const Run& run, int& first_ok, int& released) {
    const std::uint16_t invalid = fault_bit(FaultCode::kCommandInvalid);
    std::size_t silent = run.cycles.size();
    bool saw[3] = {false, false, false};
    for (std::size_t k = 0U; k < run.cycles.size(); ++k) {
        const Cycle& c = run.cycles[k];
        const std::string where = "cycle " + std::to_string(k) + ": ";
        expect(c.copy && c.diagnostics && c.separation, where + "not every frame received");
        if (c.t_us > run.last_sample_us) {
            silent = std::min(silent, k);
        }
        if (first_ok < 0 && c.sep.command_valid && (c.faults & invalid) == 0U) {
            first_ok = static_cast<int>(k);
        }
        if (first_ok < 0 || k >= silent) {
            continue;
        }
        expect(c.sep.command_valid && (c.faults & invalid) == 0U,
               where + "the monitor refused the command after start-up (CommandValid " +
                   std::to_string(c.sep.command_valid ? 1 : 0) + ", diagnostics faults 0x" + std::to_string(c.faults) +
                   ")");
        const int want = commanded_case(run, c.sep.command_counter, c.t_us);
        expect(want >= 0 && c.safety.active_case == want && c.sep.active_case == want,
               where + "echoed case " + std::to_string(c.safety.active_case) + " (separation frame " +
                   std::to_string(c.sep.active_case) + "), commanded " + std::to_string(want) + " in sample " +
                   std::to_string(c.sep.command_counter));
        if (c.safety.active_case < 3U) {
            saw[c.safety.active_case] = true;
        }
        if (released < 0 && !c.safety.protective_stop) {
            released = static_cast<int>(k);
            // reset_required is on: the release is the restart interlock's, on the press the cycle used.
            const Sample* used = sample_named(run, c.sep.command_counter, c.t_us);
            expect(used != nullptr && used->reset_request,
                   where + "the start-up stop was released without the PLC's ResetRequest in the sample used");
        }
        expect(released < 0 || !c.safety.protective_stop,
               where + "stop while the commands are good, after the release");
    }
    expect(first_ok >= 0, "the monitor never used a valid command");
    expect(saw[0] && saw[2], "cases 0 and 2 both commanded and echoed");
    expect(released >= 0, "the start-up stop was released before the PLC fell silent");
    return silent;
}

int check(const Run& run) {
    const std::uint64_t t = run.cfg.period_us;
    const std::uint64_t sct = run.cfg.robot.max_command_age_us;
    expect(static_cast<int>(run.cycles.size()) > run.end_at, "the monitor's cycles up to " +
                                                                 std::to_string(run.end_at) + " received (got " +
                                                                 std::to_string(run.cycles.size()) + ")");
    // Cycle 0's link frame echoes nothing (the start-up handshake), then the reference and two recovery pairs.
    expect(run.first_valid_pair >= 0 && run.first_valid_pair <= 3, "the PLC receiver valid from the fourth pair on");
    expect(run.receiver_faults == 0U, "the PLC receiver left the valid state: " + run.receiver_fault_text);
    int first_ok = -1;
    int released = -1;
    const std::size_t silent = check_commands(run, first_ok, released);
    // The response to the silence: the first stop after the last sample (and
    // after the release: without one there is nothing to measure).
    int stop_at = -1;
    const std::size_t from = released < 0 ? run.cycles.size() : std::max(silent, static_cast<std::size_t>(released));
    for (std::size_t k = from; k < run.cycles.size(); ++k) {
        const Cycle& c = run.cycles[k];
        if (stop_at < 0 && c.safety.protective_stop) {
            stop_at = static_cast<int>(k);
            expect((c.faults & fault_bit(FaultCode::kCommandInvalid)) != 0U && !c.sep.command_valid,
                   "cycle " + std::to_string(k) + ": the stop comes with kCommandInvalid and CommandValid 0");
        }
        expect(stop_at < 0 || c.safety.protective_stop, "cycle " + std::to_string(k) + ": the stop stays");
        // After the delayed and the replayed sample went out: still no valid command.
        const bool injected = (run.delayed_cycle >= 0 && static_cast<int>(k) > run.delayed_cycle) ||
                              (run.replayed_cycle >= 0 && static_cast<int>(k) > run.replayed_cycle);
        if (injected) {
            expect(!c.sep.command_valid && (c.faults & fault_bit(FaultCode::kCommandInvalid)) != 0U,
                   "cycle " + std::to_string(k) + ": the delayed or replayed sample refused (CommandValid 0)");
        }
    }
    expect(run.delayed_cycle >= 0 && run.delayed_cycle < static_cast<int>(run.cycles.size()) - 1,
           "the delayed sample was sent, a cycle before the end");
    expect(run.replayed_cycle >= 0 && run.replayed_cycle < static_cast<int>(run.cycles.size()) - 1,
           "the replayed sample was sent, a cycle before the end");
    expect(run.delayed_ms > static_cast<double>(monitor::link_watchdog_us(run.cfg)) / 1000.0,
           "the delayed sample was held longer than the watchdog time");
    const double bound_ms = static_cast<double>(sct + 2U * t) / 1000.0;
    double response_ms = -1.0;
    if (stop_at >= 0) {
        response_ms = static_cast<double>(run.cycles[static_cast<std::size_t>(stop_at)].t_us - run.last_sample_us) /
                      1000.0;
    }
    expect(stop_at >= 0 && response_ms <= bound_ms, "the stop within SCT + 2 T of the last sample");
    // A sample whose six writes took longer than the monitor's sample window
    // arrives incomplete by the receiver's rule, and its refusal is right: in
    // a TCG VM on a loaded host the guest can stall between two writes. Said
    // so, so that the script can tell such a run from a monitor fault.
    const std::uint64_t window = monitor::command_receiver_config(run.cfg).sample_window_us;
    std::uint64_t longest = 0U;
    std::size_t late = 0U;
    for (const Sample& smp : run.samples) {
        longest = std::max(longest, smp.burst_us);
        late += smp.burst_us > window ? 1U : 0U;
    }
    std::printf(
        "PLC: samples' seven writes took at most %.1f ms (the monitor's sample window %.0f ms); %zu took longer\n",
        static_cast<double>(longest) / 1000.0, static_cast<double>(window) / 1000.0, late);
    if (late > 0U && g_failures > 0) {
        std::printf(
            "PLC: DISTURBED: %zu samples took longer to write than the sample window: the host stalled the "
            "PLC, so the monitor's refusals of them are right\n",
            late);
    }
    std::printf(
        "robot run: %zu samples sent (%zu frames), %zu monitor cycles received; PLC receiver valid from cycle %d, "
        "%u faults after up to the silence; commands used from cycle %d, stop released in cycle %d, case 0 then 2 "
        "from cycle %d echoed; PLC silent from cycle %d (first cycle after the last sample: %zu); stop in cycle %d, "
        "%.0f ms after the last sample (bound SCT + 2 T = %.0f + 2 x %.0f = %.0f ms); delayed sample (held %.0f ms, "
        "watchdog %.0f ms) sent in cycle %d, whole sample %zu replayed in cycle %d: both refused; %d failures\n",
        run.samples.size(), 7U * run.samples.size(), run.cycles.size(), run.first_valid_pair, run.receiver_faults,
        first_ok, released, run.switch_at, run.silent_at, silent, stop_at, response_ms,
        static_cast<double>(sct) / 1000.0, static_cast<double>(t) / 1000.0, bound_ms, run.delayed_ms,
        static_cast<double>(monitor::link_watchdog_us(run.cfg)) / 1000.0, run.delayed_cycle, run.replayed_from,
        run.replayed_cycle, g_failures);
    return g_failures == 0 ? 0 : 1;
}

int cycle_arg(const char* s) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    return end != s && *end == '\0' && v > 0 && v < 100000 ? static_cast<int>(v) : -1;
}

/// The commissioned robot ID: the low 16 bits of the robot image's CRC-32, as the monitor builds it.
bool robot_id(const MonitorConfig& cfg, std::uint16_t& id) {
    monitor::MonitorCell cell;
    const monitor::SetupError e = cell.configure(cfg);
    const monitor::SetupError r = e.failed() ? e : cell.configure_robot(cfg, nullptr);
    if (r.failed() || !cfg.robot.enabled) {
        std::printf("robot: %s\n", r.failed() ? r.message.c_str() : "no [robot] in the configuration");
        return false;
    }
    id = static_cast<std::uint16_t>(cell.robot.crc & 0xFFFFU);
    return true;
}

volatile std::sig_atomic_t g_stop = 0;

void on_signal(int /*signal*/) { g_stop = 1; }

/// The link mode (see the file comment): replies to each of the monitor's link frames with its own, alone.
int link_only(const MonitorConfig& cfg, int fd) {
    PlcReceiver plc(receiver_config(cfg));
    std::uint8_t counter = 0U;
    std::uint64_t replies = 0U;
    std::uint64_t failed = 0U;
    std::printf("PLC: link frames alone on reply, session %u\n", plc.config().link.session);
    std::fflush(stdout);
    while (g_stop == 0) {
        pollfd p{fd, POLLIN, 0};
        static_cast<void>(::poll(&p, 1, 50));
        CanFrame f{};
        while (receive_frame(fd, f)) {
            static_cast<void>(plc.on_frame(f, now_us()));
            if (f.id != plc.config().link.peer.can_id) {
                continue;
            }
            const Result<CanFrame> reply = encode_link_frame(plc.next_link(now_us()), counter, plc.config().link.own,
                                                             Span<const CanFrame>());
            counter = e2e_p01_next_counter(counter);
            ++replies;
            failed += reply.ok() && send_frame(fd, reply.value()) ? 0U : 1U;  // the fault run takes the interface down
        }
        static_cast<void>(plc.poll(now_us()));
    }
    std::printf("PLC: %llu link frames sent in reply, %llu writes failed\n", static_cast<unsigned long long>(replies),
                static_cast<unsigned long long>(failed));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Run run;
    if (argc == 4 && std::strcmp(argv[1], "link") == 0) {
        const ConfigLoad l = load_monitor_config(argv[2]);
        if (!l.ok) {
            std::printf("configuration error: %s\n", l.error.c_str());
            return 2;
        }
        const int fd = open_socket(argv[3]);
        if (fd < 0) {
            return 2;
        }
        static_cast<void>(std::signal(SIGINT, on_signal));
        static_cast<void>(std::signal(SIGTERM, on_signal));
        const int rc = link_only(l.config, fd);
        close(fd);
        return rc;
    }
    if (argc != 9 || cycle_arg(argv[8]) < 0 || cycle_arg(argv[3]) < 0 || cycle_arg(argv[4]) <= cycle_arg(argv[3]) ||
        cycle_arg(argv[5]) <= cycle_arg(argv[4]) || cycle_arg(argv[6]) <= cycle_arg(argv[5]) ||
        cycle_arg(argv[7]) <= cycle_arg(argv[6])) {
        std::fprintf(stderr,
                     "usage: cellguard-vcan-plc CONFIG IFACE SWITCH_AT SILENT_AT DELAY_AT REPLAY_AT END_AT BUDGET_MS\n"
                     "       cellguard-vcan-plc link CONFIG IFACE\n");
        return 2;
    }
    run.switch_at = cycle_arg(argv[3]);
    run.silent_at = cycle_arg(argv[4]);
    run.delay_at = cycle_arg(argv[5]);
    run.replay_at = cycle_arg(argv[6]);
    run.end_at = cycle_arg(argv[7]);
    const ConfigLoad l = load_monitor_config(argv[1]);
    if (!l.ok) {
        std::printf("configuration error: %s\n", l.error.c_str());
        return 2;
    }
    run.cfg = l.config;
    run.cfg.budget_us = static_cast<std::uint64_t>(cycle_arg(argv[8])) * 1000U;  // as the monitor's --budget-ms
    if (!robot_id(run.cfg, run.robot_id)) {
        return 2;
    }
    const int fd = open_socket(argv[2]);
    if (fd < 0) {
        return 2;
    }
    std::printf("PLC: robot id 0x%04X, a sample every %.0f ms on %s\n", run.robot_id,
                static_cast<double>(run.cfg.period_us) / 2000.0, argv[2]);
    std::fflush(stdout);
    const bool ok = exchange(fd, run);
    close(fd);
    return ok ? check(run) : 2;
}
