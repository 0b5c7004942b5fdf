// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The check of a demo run's candump log with the PLC receiver, polled on the
// log's clock. See demo_log_check.hpp.
#include "cellguard/monitor/demo_log_check.hpp"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "cellguard/can/separation_frame.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/io/candump_log.hpp"
#include "cellguard/monitor/command_link.hpp"

namespace cellguard::monitor {
namespace {

/// @p us as seconds with six decimals, as candump writes time stamps.
std::string seconds_text(std::uint64_t us) {
    char text[32];
    static_cast<void>(std::snprintf(text, sizeof(text), "%" PRIu64 ".%06" PRIu64, us / 1000000U, us % 1000000U));
    return text;
}

/// @p us as milliseconds ("50 ms", "0.5 ms").
std::string ms_text(std::uint64_t us) {
    char text[32];
    static_cast<void>(std::snprintf(text, sizeof(text), "%g ms", static_cast<double>(us) / 1000.0));
    return text;
}

/// The receiver's fault name, with the time limit it refers to.
std::string fault_text(ReceiverFault fault, const PlcReceiverConfig& rc) {
    std::string text = to_string(fault);
    if (fault == ReceiverFault::kSctExpired) {
        text += " (SCT " + ms_text(rc.sct_us) + ")";
    } else if (fault == ReceiverFault::kInvertedCopyMissing || fault == ReceiverFault::kInvertedCopyLate) {
        text += " (SRVT " + ms_text(rc.srvt_us) + ")";
    } else if (fault == ReceiverFault::kWatchdogExpired) {
        text += " (watchdog " + ms_text(rc.link.watchdog_us) + ")";
    }
    return text;
}

/// The link fields a link frame carries (no check of its CRC or binding).
LinkFields raw_link_fields(const CanFrame& f) noexcept {
    LinkFields l;
    l.sequence = static_cast<std::uint16_t>(get_signal(f, link_layout::kSequence));
    l.echo = static_cast<std::uint16_t>(get_signal(f, link_layout::kEcho));
    l.session = static_cast<std::uint8_t>(get_signal(f, link_layout::kSession));
    l.echo_session = static_cast<std::uint8_t>(get_signal(f, link_layout::kEchoSession));
    return l;
}

/// "sequence S session X echo E of session Y".
std::string link_text(const LinkFields& l) {
    return "sequence " + std::to_string(l.sequence) + " session " + std::to_string(l.session) + " echo " +
           std::to_string(l.echo) + " of session " + std::to_string(l.echo_session);
}

bool same_fields(const LinkFields& a, const LinkFields& b) noexcept {
    return a.sequence == b.sequence && a.echo == b.echo && a.session == b.session && a.echo_session == b.echo_session;
}

/// What the log shows of one cycle of a robot cell.
struct RobotCycle {
    bool stop = true;            ///< the safety frame's ProtectiveStop
    bool reduced = false;        ///< its ReducedSpeed
    std::uint8_t case_echo = 0;  ///< its ActiveCase
    CommandPoll command{};       ///< the log's command receiver, polled at the safety frame
    bool separation = false;     ///< the cycle's separation frame came
};

/// One log, line by line: see the file comment of demo_log_check.hpp.
class LogChecker {
public:
    LogChecker(const cell::MonitorConfig& cfg, const PlcReceiverConfig& rc, const CommandReceiverConfig& cc, int cycles,
               DemoLogCheck& out)
        : cfg_(cfg),
          rc_(rc),
          plc_(rc),
          commands_(cc),
          step_us_(demo_log_poll_interval_us(rc)),
          out_(out),
          cycles_(cycles),
          robot_(cfg.robot.enabled) {}

    void line(const std::string& text);
    void finish();

private:
    void fail(const std::string& what) { out_.failures.push_back(what); }
    void poll_until(std::uint64_t t_us);
    void observe(const ReceiverStatus& rs, const std::string& where);
    void observe_commands(const CommandStatus& cs, const std::string& where);
    void on_safety_frame(const CanFrame& f, std::uint64_t t_us, const std::string& where);
    void on_inverted_copy(const CanFrame& f, const ReceiverStatus& rs, const std::string& where);
    void on_diagnostics_frame(const CanFrame& f, const std::string& where);
    void on_separation_frame(const CanFrame& f, const std::string& where);
    void on_controller_link(const CanFrame& f, const ReceiverStatus& rs, const std::string& where);
    void on_plc_link(const CanFrame& f, std::uint64_t t_us, const std::string& where);
    [[nodiscard]] bool handshake(ReceiverFault fault) const noexcept;
    void check_separation(const SeparationMessage& m, const RobotCycle& c, const std::string& where);
    [[nodiscard]] bool is_command_id(std::uint32_t id) const noexcept;
    int check_entry_cycle();
    std::string check_robot_timeline();
    [[nodiscard]] std::string robot_summary() const;

    const cell::MonitorConfig& cfg_;
    PlcReceiverConfig rc_;
    PlcReceiver plc_;
    CommandReceiver commands_;
    std::uint64_t step_us_;
    DemoLogCheck& out_;
    std::vector<bool> stop_;  // the stop bit of each safety frame
    CanFrame last_safety_{};
    std::uint64_t start_us_ = 0U;  // the first frame's time stamp
    std::uint64_t last_us_ = 0U;   // the latest time stamp so far
    std::uint64_t next_poll_us_ = 0U;
    std::vector<RobotCycle> robot_cycles_;  // a robot cell: one per safety frame
    int cycles_;
    int lines_ = 0;
    int diagnostics_ = 0;
    int valid_pairs_ = 0;
    std::uint32_t faults_seen_ = 0U;
    int separations_ = 0;                     // a robot cell: separation frames so far
    int command_frames_ = 0;                  // a robot cell: command frames so far
    int command_valid_cycles_ = 0;            // cycles whose separation frame says CommandValid
    std::uint32_t command_faults_seen_ = 0U;  // the command receiver's fault events so far
    int command_failures_ = 0;                // those reported as failures (not the start-up handshake)
    int plc_handshakes_ = 0;                  // start-up kNoEchoYet of the PLC receiver: it had sent nothing yet
    int command_handshakes_ = 0;              // the same for the controller's side
    int plc_failures_ = 0;                    // PLC receiver faults reported as failures
    int controller_links_ = 0;                // the controller's link frames
    int plc_links_ = 0;                       // the PLC's link frames
    std::uint64_t safety_time_us_ = 0U;       // the time stamp of the last safety frame
    std::uint64_t sample_start_us_ = 0U;      // the time stamp of the last command part A
    bool robot_;                              // a robot cell: separation frames and command frames
    bool have_safety_ = false;                // a safety frame waits for its copy
    bool have_time_ = false;
    bool separation_due_ = false;  // a robot cell: a diagnostics frame came, its separation frame is due
};

void LogChecker::line(const std::string& text) {
    ++lines_;
    const std::string where = "line " + std::to_string(lines_);
    CandumpRecord rec;
    const IoStatus st = parse_candump_line(text.c_str(), rec);
    if (!st.ok()) {
        fail(where + ": " + st.message());
        return;
    }
    const std::uint64_t t = rec.timestamp_us;
    if (!have_time_) {
        have_time_ = true;
        start_us_ = t;
        last_us_ = t;
        next_poll_us_ = t + step_us_;
    }
    poll_until(t);
    last_us_ = std::max(last_us_, t);
    // on_frame applies the time checks (SRVT, SCT) at the frame's own time stamp.
    const ReceiverStatus rs = plc_.on_frame(rec.frame, t);
    observe(rs, where + " (t = " + seconds_text(t) + " s)");
    const CanFrame& f = rec.frame;
    if (robot_) {
        observe_commands(commands_.on_frame(f, t), where + " (t = " + seconds_text(t) + " s)");
    }
    if (f.id == cfg_.can.channel.safety_can_id) {
        on_safety_frame(f, t, where);
    } else if (f.id == inverted_can_id(cfg_.can.channel)) {
        on_inverted_copy(f, rs, where);
    } else if (f.id == cfg_.can.channel.diagnostics_can_id) {
        on_diagnostics_frame(f, where);
    } else if (robot_ && f.id == cfg_.can.channel.separation_can_id) {
        on_separation_frame(f, where);
    } else if (f.id == plc_.config().link.peer.can_id) {
        on_controller_link(f, rs, where);
    } else if (f.id == plc_.config().link.own.can_id) {
        on_plc_link(f, t, where);
    } else if (robot_ && is_command_id(f.id)) {
        ++command_frames_;
        if (f.id == command_can_id(cfg_.can.command, CommandPart::kA)) {
            sample_start_us_ = t;
        }
    } else {
        fail(where + ": unexpected CAN ID");
    }
}

bool LogChecker::is_command_id(std::uint32_t id) const noexcept {
    const std::uint32_t base = command_can_id(cfg_.can.command, CommandPart::kA);
    return id >= base && id < base + static_cast<std::uint32_t>(kCommandFramesPerSample);
}

// Polls at every grid point before t_us. Once the receiver has gone longer
// than SCT + SRVT without a frame no further poll can find anything new, so a
// long gap (or a corrupt time stamp far ahead) skips to the grid point before t_us.
void LogChecker::poll_until(std::uint64_t t_us) {
    const std::uint64_t quiet_end = last_us_ + rc_.sct_us + rc_.srvt_us + 2U * step_us_;
    while (next_poll_us_ < t_us) {
        if (next_poll_us_ > quiet_end) {
            next_poll_us_ += (t_us - next_poll_us_ - 1U) / step_us_ * step_us_;
        }
        observe(plc_.poll(next_poll_us_), "PLC poll at t = " + seconds_text(next_poll_us_) + " s");
        next_poll_us_ += step_us_;
    }
}

// The start-up handshake of the session link: the other side's first link
// frame cannot echo this side before this side has sent anything.
bool LogChecker::handshake(ReceiverFault fault) const noexcept {
    return fault == ReceiverFault::kNoEchoYet && plc_.link().sequence() == 0U;
}

void LogChecker::observe(const ReceiverStatus& rs, const std::string& where) {
    if (rs.fault_events > faults_seen_) {
        faults_seen_ = rs.fault_events;
        if (handshake(rs.fault)) {
            ++plc_handshakes_;
            return;
        }
        ++plc_failures_;
        fail(where + ": the PLC receiver enters the safe state: " + fault_text(rs.fault, rc_));
    }
}

void LogChecker::observe_commands(const CommandStatus& cs, const std::string& where) {
    if (cs.fault_events > command_faults_seen_) {
        command_faults_seen_ = cs.fault_events;
        if (cs.fault == CommandFault::kNoEchoYet && commands_.link().sequence() == 0U) {
            ++command_handshakes_;  // the start-up handshake (see handshake())
            return;
        }
        ++command_failures_;
        fail(where + ": the controller's command receiver enters the safe state: " + to_string(cs.fault));
    }
}

// The controller's link frame: its fields must be those of the controller's
// endpoint re-run here (its sequence, session and the echo of the PLC's
// latest accepted link frame), stamped at its safety frame's time; the PLC
// receiver checks its binding to the pair, the session, the echo and the round trip.
void LogChecker::on_controller_link(const CanFrame& f, const ReceiverStatus& rs, const std::string& where) {
    ++controller_links_;
    // The pair with its link frame: from the third on (the reference pair and
    // two recovery pairs); after a reported fault the receiver is not valid
    // until it recovers, which says nothing new.
    if (stop_.size() >= 3U + static_cast<std::size_t>(plc_handshakes_) && plc_failures_ == 0 &&
        !rs.communication_valid) {
        fail(where + ": PLC receiver not valid: " + to_string(rs.fault));
    }
    if (rs.communication_valid && !stop_.empty() && rs.stop_requested != stop_.back()) {
        fail(where + ": PLC receiver's stop decision differs from the frame's stop bit");
    }
    valid_pairs_ += rs.communication_valid ? 1 : 0;
    const LinkFields want = commands_.link().next(safety_time_us_);
    const LinkFields got = raw_link_fields(f);
    if (!same_fields(want, got)) {
        fail(where + ": the controller's link frame carries " + link_text(got) + ", its endpoint sends " +
             link_text(want));
    }
}

// The PLC's link frame: its fields must be those of the PLC's endpoint (the
// PLC receiver's, re-run here), stamped when the PLC sent the sample (its
// part A) or the frame alone; the controller's side checks it: closing a
// command sample (a robot cell), or alone (LinkEndpoint::on_standalone_frame).
void LogChecker::on_plc_link(const CanFrame& f, std::uint64_t t_us, const std::string& where) {
    ++plc_links_;
    const LinkFields want = plc_.next_link(robot_ ? sample_start_us_ : t_us);
    const LinkFields got = raw_link_fields(f);
    if (!same_fields(want, got)) {
        fail(where + ": the PLC's link frame carries " + link_text(got) + ", its endpoint sends " + link_text(want));
    }
    if (robot_) {
        return;  // the command receiver got it with the sample (line())
    }
    const bool started = commands_.link().sequence() != 0U;
    const LinkFault lf = commands_.link().on_standalone_frame(f, t_us);
    if (lf == LinkFault::kNoEchoYet && !started) {
        ++command_handshakes_;
    } else if (lf != LinkFault::kNone) {
        ++command_failures_;
        fail(where + ": the controller refuses the PLC's link frame: " + to_string(lf));
    }
}

void LogChecker::on_safety_frame(const CanFrame& f, std::uint64_t t_us, const std::string& where) {
    const Result<SafetyFrameContent> c = decode_safety_frame(f, cfg_.can.channel);
    if (!c.ok()) {
        fail(where + ": safety frame does not decode");
    } else if (c.value().counter != stop_.size() % 15U) {
        fail(where + ": safety counter out of sequence");
    }
    stop_.push_back(c.ok() ? c.value().message.protective_stop : true);
    last_safety_ = f;
    safety_time_us_ = t_us;
    have_safety_ = true;
    if (!robot_) {
        return;
    }
    if (separation_due_) {
        fail(where + ": the previous cycle's separation frame is missing");
    }
    separation_due_ = false;
    RobotCycle rc;
    rc.stop = stop_.back();
    rc.reduced = c.ok() && c.value().message.reduced_speed;
    rc.case_echo = c.ok() ? c.value().message.active_case : 0U;
    // The monitor polled its receiver at the cycle's start, after the cycle's
    // command frames; the log check polls at the cycle's safety frame.
    rc.command = commands_.poll(t_us);
    observe_commands(rc.command.status, where + " (command receiver polled)");
    if (robot_cycles_.size() >= 2U + static_cast<std::size_t>(command_handshakes_) && command_failures_ == 0 &&
        !rc.command.status.valid) {
        fail(where + ": command receiver not valid from the third sample on: " + to_string(rc.command.status.fault));
    }
    robot_cycles_.push_back(rc);
}

void LogChecker::on_inverted_copy(const CanFrame& f, const ReceiverStatus& rs, const std::string& where) {
    const CanFrame want = inverted_copy(last_safety_);
    bool same = have_safety_ && f.dlc == want.dlc;
    for (int k = 0; same && k < 8; ++k) {
        same = f.data[k] == want.data[k];
    }
    if (!same) {
        fail(where + ": inverted copy does not match its safety frame");
    }
    static_cast<void>(rs);  // protocol 0.2: the pair is decided by its link frame (on_controller_link)
    have_safety_ = false;
}

void LogChecker::on_diagnostics_frame(const CanFrame& f, const std::string& where) {
    const Result<DiagnosticsFrameContent> d = decode_diagnostics_frame(f, cfg_.can.channel);
    if (!d.ok()) {
        fail(where + ": diagnostics frame does not decode");
    } else if (d.value().message.prior_crc_page != static_cast<std::uint8_t>(diagnostics_ % 4)) {
        fail(where + ": prior CRC page out of sequence");
    }
    ++diagnostics_;
    separation_due_ = robot_;
}

void LogChecker::on_separation_frame(const CanFrame& f, const std::string& where) {
    SeparationFrameContent c;
    const FrameCheck check = check_separation_frame(f, cfg_.can.channel, c);
    if (check != FrameCheck::kOk) {
        fail(where + ": separation frame does not decode (" + to_string(check) + ")");
    } else if (c.counter != static_cast<std::uint8_t>(separations_ % 15)) {
        fail(where + ": separation counter out of sequence");
    }
    ++separations_;
    if (!separation_due_ || robot_cycles_.empty()) {
        fail(where + ": separation frame not right after its cycle's diagnostics frame");
        return;
    }
    separation_due_ = false;
    RobotCycle& cycle = robot_cycles_.back();
    cycle.separation = true;
    if (check == FrameCheck::kOk) {
        check_separation(c.message, cycle, where);
    }
}

void LogChecker::check_separation(const SeparationMessage& m, const RobotCycle& c, const std::string& where) {
    if (m.active_case != c.case_echo) {
        fail(where + ": separation frame's case " + std::to_string(m.active_case) + " is not the safety frame's " +
             std::to_string(c.case_echo));
    }
    if ((m.speed_request == SpeedRequest::kReduced) != c.reduced ||
        (m.speed_request == SpeedRequest::kProtectiveStop && !c.stop)) {
        fail(where + ": speed request " + std::to_string(static_cast<int>(m.speed_request)) +
             " does not match the safety frame's ReducedSpeed and ProtectiveStop bits");
    }
    if (m.distance_mm < m.required_mm && m.speed_request != SpeedRequest::kProtectiveStop) {
        fail(where + ": distance " + std::to_string(m.distance_mm) + " mm below the required " +
             std::to_string(m.required_mm) + " mm without a stop request");
    }
    if (!m.command_valid) {
        return;
    }
    ++command_valid_cycles_;
    const CommandPoll& p = c.command;
    if (!p.input.valid) {
        fail(where + ": CommandValid, but the log's command receiver holds no valid sample (" +
             to_string(p.status.fault) + ")");
    } else if (p.input.counter != m.command_counter) {
        fail(where + ": the cycle used command " + std::to_string(m.command_counter) + ", the log's latest is " +
             std::to_string(p.input.counter));
    } else if (p.input.command.monitoring_case != c.case_echo) {
        fail(where + ": echoed case " + std::to_string(c.case_echo) + " is not the commanded case " +
             std::to_string(p.input.command.monitoring_case));
    }
}

/// The cycle in which the scripted person first overlaps a protective zone
/// (-1: never); checks the stop bits there and in the cycle before.
int LogChecker::check_entry_cycle() {
    int entry = -1;
    for (const cell::ZoneSettings& z : cfg_.zones) {
        for (int k = 0; z.zone.kind == ZoneKind::kProtective && k < cycles_ && entry < 0; ++k) {
            entry = cell::person_overlaps(z.zone, cell::demo_person(k)) ? k : -1;
        }
    }
    const bool inside = entry > 0 && entry < static_cast<int>(stop_.size());
    if (!inside) {
        fail("the person does not enter the protective zone during the logged run (entry cycle " +
             std::to_string(entry) + ", " + std::to_string(stop_.size()) + " safety frames)");
        return entry;
    }
    if (stop_[static_cast<std::size_t>(entry - 1)]) {
        fail("stop in the cycle before the entry (cycle " + std::to_string(entry - 1) + ")");
    }
    if (!stop_[static_cast<std::size_t>(entry)]) {
        fail("no stop in the entry cycle " + std::to_string(entry));
    }
    return entry;
}

/// A robot cell's decisions over the run: the start-up stop released, then a
/// stop request again (the scene's person comes close). Returns the summary's part.
std::string LogChecker::check_robot_timeline() {
    int released = -1;
    int reduced = -1;
    int stopped = -1;
    for (std::size_t k = 0U; k < robot_cycles_.size() && stopped < 0; ++k) {
        const RobotCycle& c = robot_cycles_[k];
        if (released < 0) {
            released = c.stop ? -1 : static_cast<int>(k);
        } else if (c.stop) {
            stopped = static_cast<int>(k);
        } else if (c.reduced && reduced < 0) {
            reduced = static_cast<int>(k);
        }
    }
    if (released < 0) {
        fail("the start-up stop is never released");
    } else if (stopped < 0) {
        fail("no stop request after the release in cycle " + std::to_string(released));
    }
    return "stop released in cycle " + std::to_string(released) + ", reduced speed first in cycle " +
           std::to_string(reduced) + ", stop again first in cycle " + std::to_string(stopped);
}

std::string LogChecker::robot_summary() const {
    int valid = 0;
    for (const RobotCycle& c : robot_cycles_) {
        valid += c.command.status.valid ? 1 : 0;
    }
    return ", " + std::to_string(separations_) + " separation frames, " + std::to_string(command_frames_) +
           " command frames (" + std::to_string(commands_.status().good_samples) +
           " samples accepted by the command receiver, valid in " + std::to_string(valid) + " cycles, " +
           std::to_string(command_failures_) + " faults; " + std::to_string(command_valid_cycles_) +
           " cycles used a valid command, its case echoed)";
}

void LogChecker::finish() {
    std::string polled = "never polled (no frame)";
    if (!have_time_) {
        fail("the log holds no frame");
    } else {
        // The end of the expected run (or the last frame, if later): the PLC has
        // been polling all along and still expects a pair within the SCT.
        const std::uint64_t t = std::max(start_us_ + static_cast<std::uint64_t>(cycles_) * cfg_.period_us, last_us_);
        poll_until(t);
        observe(plc_.poll(t), "PLC poll at the end of the run, t = " + seconds_text(t) + " s");
        if (robot_) {
            observe_commands(commands_.poll(t).status, "command receiver poll at the end of the run");
        }
        polled = "polled every " + ms_text(step_us_) + " of log time up to t = " + seconds_text(t) + " s";
    }
    // Protocol 0.2: the controller's link frame, and the PLC's (closing its
    // sample of six command frames in a robot cell, alone otherwise); a robot
    // cell also sends the separation frame.
    const int per_cycle = robot_ ? 5 + static_cast<int>(kCommandFramesPerSample) + 1 : 5;
    if (lines_ != per_cycle * cycles_) {
        fail("expected " + std::to_string(per_cycle * cycles_) + " lines, got " + std::to_string(lines_));
    }
    if (static_cast<int>(stop_.size()) != cycles_) {
        fail("expected one safety frame per cycle, " + std::to_string(cycles_) + ", got " +
             std::to_string(stop_.size()));
    }
    if (controller_links_ != cycles_ || plc_links_ != cycles_) {
        fail("expected one link frame of each side per cycle, " + std::to_string(cycles_) + ", got " +
             std::to_string(controller_links_) + " of the controller and " + std::to_string(plc_links_) +
             " of the PLC");
    }
    if (robot_ && (separations_ != cycles_ || separation_due_)) {
        fail("expected one separation frame per cycle after its diagnostics frame, " + std::to_string(cycles_) +
             ", got " + std::to_string(separations_));
    }
    std::string decisions;
    if (robot_) {
        decisions = check_robot_timeline();
    } else {
        const int entry = check_entry_cycle();
        const bool stop_there = entry >= 0 && entry < static_cast<int>(stop_.size()) &&
                                stop_[static_cast<std::size_t>(entry)];
        decisions = "person enters the protective zone in cycle " + std::to_string(entry) +
                    ", stop bit there: " + (stop_there ? "1" : "0");
    }
    out_.summary = std::to_string(lines_) + " lines, " + std::to_string(stop_.size()) + " safety pairs (" +
                   std::to_string(valid_pairs_) + " accepted by the PLC receiver), " + std::to_string(diagnostics_) +
                   " diagnostics frames" + (robot_ ? robot_summary() : std::string()) +
                   "; session link: " + std::to_string(controller_links_) + " controller and " +
                   std::to_string(plc_links_) +
                   " PLC link frames, fields as their endpoints send them, round trip within " +
                   ms_text(rc_.link.watchdog_us) + ", start-up handshake " +
                   std::to_string(plc_handshakes_ + command_handshakes_) + "; PLC receiver " + polled + ", " +
                   std::to_string(plc_failures_) + " faults; " + decisions + "; " +
                   std::to_string(out_.failures.size()) + " failures";
}

}  // namespace

PlcReceiverConfig demo_log_receiver_config(const cell::MonitorConfig& config) { return plc_receiver_config(config); }

std::uint64_t demo_log_poll_interval_us(const PlcReceiverConfig& receiver) noexcept {
    return std::max<std::uint64_t>(1U, std::min<std::uint64_t>(1000U, receiver.srvt_us / 10U));
}

DemoLogCheck check_demo_log(std::istream& log, int cycles, const cell::MonitorConfig& config) {
    DemoLogCheck out;
    const PlcReceiverConfig rc = demo_log_receiver_config(config);
    if (cycles < 1 || cycles > kDemoLogMaxCycles) {
        out.input_ok = false;
        out.failures.push_back("CYCLES must be 1.." + std::to_string(kDemoLogMaxCycles) + ", got " +
                               std::to_string(cycles));
        return out;
    }
    if (!PlcReceiver::check_config(rc).ok()) {
        out.input_ok = false;
        out.failures.push_back("no valid PLC receiver configuration for this monitor configuration (period " +
                               ms_text(config.period_us) + ", " + std::to_string(config.zones.size()) + " zones)");
        return out;
    }
    if (!CommandReceiver::check_config(command_receiver_config(config)).ok()) {
        out.input_ok = false;
        out.failures.emplace_back("no valid command receiver configuration for this monitor configuration");
        return out;
    }
    std::vector<std::string> lines;
    for (std::string line; std::getline(log, line);) {
        lines.push_back(line);
    }
    // Each side's session is chosen at its start: take it from its first link frame in the log.
    PlcReceiverConfig plc = rc;
    CommandReceiverConfig cc = command_receiver_config(config);
    bool have_plc = false;
    bool have_controller = false;
    for (const std::string& l : lines) {
        CandumpRecord rec;
        if (!parse_candump_line(l.c_str(), rec).ok()) {
            continue;
        }
        const auto session = static_cast<std::uint8_t>(get_signal(rec.frame, link_layout::kSession));
        if (!have_plc && rec.frame.id == plc.link.own.can_id && session != 0U) {
            plc.link.session = session;
            have_plc = true;
        } else if (!have_controller && rec.frame.id == cc.link.own.can_id && session != 0U) {
            cc.link.session = session;
            have_controller = true;
        }
    }
    LogChecker checker(config, plc, cc, cycles, out);
    for (const std::string& l : lines) {
        checker.line(l);
    }
    checker.finish();
    return out;
}

DemoLogCheck check_demo_log_file(const std::string& path, int cycles, const cell::MonitorConfig& config) {
    errno = 0;
    std::ifstream in(path);
    if (!in) {
        DemoLogCheck out;
        out.input_ok = false;
        out.failures.push_back(path + ": cannot open: " + (errno != 0 ? std::strerror(errno) : "unknown error"));
        return out;
    }
    return check_demo_log(in, cycles, config);
}

}  // namespace cellguard::monitor
