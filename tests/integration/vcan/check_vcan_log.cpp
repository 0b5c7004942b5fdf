// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-vcan-check: checks what `candump -L` recorded on a real kernel CAN
// interface while cellguard-monitor sent on it (tools/vcan-integration.sh,
// tests/integration/vcan/vcan-test.sh). Every frame goes through the
// PLC-side receiver with the timestamps the kernel gave it. Protocol 0.2:
// the recording also holds the link frames cellguard-vcan-plc (link mode)
// sent alone in reply to each of the monitor's link frames; the check
// re-runs that PLC's link endpoint (each PLC link frame must carry the
// sequence, session and echo it sends), so the receiver checks the
// monitor's link frames (binding, echo, round trip within the watchdog time)
// as that PLC did. The k-th reply is matched to the k-th link frame of the
// monitor, whichever the log records first (the kernel may hand candump the
// reply a few microseconds before the frame it answers; CI saw it once).
//
//   cellguard-vcan-check normal CONFIG LOG CYCLES
//     An undisturbed run of CYCLES cycles: every frame recorded, every frame
//     valid, every inverted copy exact, the receiver valid once its start-up
//     recovery is over and never silent (SCT) after that, no fault bit, and the
//     stop request in the cycle in which the scripted person enters the
//     protective zone, not in the cycle before.
//
//   In both runs the receiver may refuse a pair for time alone (data older
//   than the watchdog time, no good pair within the SCT) where the recording
//   shows why: a frame of the monitor, or the PLC's reply, more than half a
//   period late in that cycle or the recovery_good_pairs + 1 before it. The
//   emulated VM on a loaded CI machine stalls for a second now and then (CI
//   saw it before the outage); the receiver must refuse and recover by its
//   rule, as it does. Every other refusal fails, and so does a run in which
//   under half the pairs checked are valid.
//
//   cellguard-vcan-check fault CONFIG LOG STATUS CYCLES
//     A run during which the interface was taken down and brought up again;
//     STATUS is the monitor's stdout (one status line per cycle). Checks that
//     every recorded frame is valid, that exactly one stretch of cycles is
//     missing, that the monitor latched "CAN error" with a stop in the cycle
//     after its first failed send, that the first cycle back on the bus
//     carries stop + fault and the diagnostics bits kCanError and
//     kCanNetworkDown, that the receiver went to its safe state over the gap
//     (SCT expired or counter jump) and recovered by its rule, and that the
//     monitor cleared the fault after fault_recovery_cycles and released the
//     stop after the restart delay.
//
// Exit status: 0 all checks passed, 1 a check failed, 2 usage or input error.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/io/candump_log.hpp"
#include "cellguard/monitor/command_link.hpp"

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

/// What the log holds for one cycle of the monitor.
struct CycleFrames {
    bool safety = false;       // safety frame recorded
    bool copy = false;         // its inverted copy recorded (and exact)
    bool link = false;         // the monitor's link frame recorded after the copy
    bool diagnostics = false;  // diagnostics frame recorded
    SafetyMessage message;
    DiagnosticsMessage diag;
    std::uint64_t t_us = 0U;        // timestamp of the safety frame
    ReceiverStatus after_copy;      // receiver status after the pair's link frame (the pair complete)
    std::uint64_t link_t_us = 0U;   // timestamp of the monitor's link frame
    std::uint64_t reply_t_us = 0U;  // timestamp of the PLC's reply to it (0: none recorded)
};

struct Parsed {
    std::vector<CycleFrames> cycles;  // index = monitor cycle
    int lines = 0;
    int plc_links = 0;  // the PLC's link frames
    std::uint32_t prior_crc = 0U;
    bool silence_seen = false;               // a poll found the SCT expired or the data older than the watchdog time
    std::uint64_t silence_at_us = 0U;        // time of the first such poll
    int invalid_polls_after_valid = 0;       // polls reporting a fault after the first valid status
    std::vector<ReceiverFault> faults_seen;  // distinct receiver faults after the first valid status
};

void note_fault(Parsed& p, ReceiverFault fault) {
    for (ReceiverFault k : p.faults_seen) {
        if (k == fault) {
            return;
        }
    }
    p.faults_seen.push_back(fault);
}

// As cellguard-monitor-check-log: SRVT half a period, SCT three periods, the watchdog time three periods.
PlcReceiverConfig receiver_config(const MonitorConfig& cfg) { return monitor::plc_receiver_config(cfg); }

/// The session of the first PLC link frame in the log at @p path (1 when there is none).
std::uint8_t plc_session(const char* path, const PlcReceiverConfig& rc) {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        CandumpRecord rec;
        if (parse_candump_line(line.c_str(), rec).ok() && rec.frame.id == rc.link.own.can_id) {
            const auto s = static_cast<std::uint8_t>(get_signal(rec.frame, link_layout::kSession));
            return s != 0U ? s : 1U;
        }
    }
    return 1U;
}

/// Reads the log, checks every frame, assigns frames to monitor cycles by the
/// E2E counter (cycle 0 = counter 0; a counter step of d = d cycles later) and
/// runs the receiver, polling it every 10 ms of log time between frames.
bool parse_log(const char* path, const MonitorConfig& cfg, Parsed& out) {
    const SafetyChannelConfig& ch = cfg.can.channel;
    PlcReceiverConfig rc = receiver_config(cfg);
    rc.link.session = plc_session(path, rc);
    if (!PlcReceiver::check_config(rc).ok()) {
        std::printf("receiver configuration invalid\n");
        return false;
    }
    PlcReceiver plc(rc);
    std::ifstream in(path);
    if (!in) {
        std::printf("cannot open %s\n", path);
        return false;
    }
    int cycle = -1;       // cycle of the last safety frame
    int expect_next = 0;  // 0: safety frame, 1: copy, 3: link frame, 2: diagnostics
    CanFrame last_safety{};
    std::uint64_t last_t = 0U;
    bool was_valid = false;
    std::uint8_t crc_bytes[4] = {};
    bool crc_page_seen[4] = {};
    // Per link frame of the monitor not yet answered: the echo its reply carries, and the frame's cycle.
    struct AnswerDue {
        LinkFields echo;
        int cycle;
    };
    std::vector<AnswerDue> answers_due;
    std::vector<CandumpRecord> early_replies;  // replies logged before the link frame they answer
    // One reply of the PLC: the sequence and session its endpoint (re-run here) sends, the echo due.
    const auto check_reply = [&plc, &answers_due, &out](const CandumpRecord& reply, const std::string& where) {
        const LinkFields want = plc.next_link(reply.timestamp_us);
        const AnswerDue answer = answers_due.front();
        answers_due.erase(answers_due.begin());
        const LinkFields& due = answer.echo;
        if (answer.cycle >= 0 && static_cast<std::size_t>(answer.cycle) < out.cycles.size()) {
            out.cycles[static_cast<std::size_t>(answer.cycle)].reply_t_us = reply.timestamp_us;
        }
        const auto got = [&reply](const SignalLayout& s) { return get_signal(reply.frame, s); };
        const bool same = got(link_layout::kSequence) == want.sequence && got(link_layout::kSession) == want.session &&
                          got(link_layout::kEcho) == due.echo && got(link_layout::kEchoSession) == due.echo_session;
        expect(same, where + "the PLC's link frame is not what its endpoint sends (sequence " +
                         std::to_string(want.sequence) + ", echo " + std::to_string(due.echo) + "; recorded " +
                         std::to_string(got(link_layout::kSequence)) + ", echo " +
                         std::to_string(got(link_layout::kEcho)) + ")");
    };
    for (std::string line; std::getline(in, line);) {
        ++out.lines;
        const std::string where = "log line " + std::to_string(out.lines) + ": ";
        CandumpRecord rec;
        const IoStatus st = parse_candump_line(line.c_str(), rec);
        expect(st.ok(), where + st.message());
        if (!st.ok()) {
            continue;
        }
        if (rec.frame.id == rc.link.own.can_id) {
            // The PLC's link frame, sent alone in reply to the monitor's link frame. The k-th reply answers the
            // k-th link frame and echoes what the PLC held right after it. The log's order of the two is not
            // causal: the kernel may hand the reply to candump a few microseconds before the frame it answers
            // (then the check waits for that frame), and a PLC that lags (a loaded VM) may reply after later
            // frames of the monitor.
            ++out.plc_links;
            if (answers_due.empty()) {
                early_replies.push_back(rec);
            } else {
                check_reply(rec, where);
            }
            continue;
        }
        // The PLC polls every 10 ms; between frames that is where silence shows.
        for (std::uint64_t t = last_t + 10000U; last_t != 0U && t < rec.timestamp_us; t += 10000U) {
            const ReceiverStatus ps = plc.poll(t);
            if ((ps.fault == ReceiverFault::kSctExpired || ps.fault == ReceiverFault::kWatchdogExpired) &&
                !out.silence_seen) {
                out.silence_seen = true;
                out.silence_at_us = t;
            }
            if (was_valid && !ps.communication_valid) {
                ++out.invalid_polls_after_valid;
                note_fault(out, ps.fault);
            }
            expect(ps.communication_valid || ps.stop_requested, where + "receiver not valid but no stop (poll)");
        }
        expect(rec.timestamp_us >= last_t, where + "timestamp went back");
        last_t = rec.timestamp_us;
        const CanFrame& f = rec.frame;
        const ReceiverStatus rs = plc.on_frame(f, rec.timestamp_us);
        expect(rs.communication_valid || rs.stop_requested, where + "receiver not valid but no stop");
        if (rs.communication_valid) {
            was_valid = true;
        } else if (was_valid) {
            note_fault(out, rs.fault);
        }
        if (f.id == ch.safety_can_id) {
            const Result<SafetyFrameContent> c = decode_safety_frame(f, ch);
            SafetyFrameContent ignored;
            expect(c.ok(),
                   where + "safety frame does not decode (" + to_string(check_safety_frame(f, ch, ignored)) + ")");
            expect(!c.ok() || c.value().message.zone_count == cfg.zones.size(), where + "zone count differs");
            if (!c.ok()) {
                continue;
            }
            const int counter = c.value().counter;
            if (cycle < 0) {
                expect(counter == 0, where + "the first safety frame has counter " + std::to_string(counter) +
                                         ", not 0 (frames before it were lost)");
                cycle = counter;
            } else {
                const int delta = (counter - cycle % 15 + 15) % 15;
                expect(delta != 0, where + "safety counter repeated");
                cycle += delta == 0 ? 1 : delta;
            }
            if (static_cast<std::size_t>(cycle) >= out.cycles.size()) {
                out.cycles.resize(static_cast<std::size_t>(cycle) + 1U);
            }
            CycleFrames& cf = out.cycles[static_cast<std::size_t>(cycle)];
            cf.safety = true;
            cf.message = c.value().message;
            cf.t_us = rec.timestamp_us;
            last_safety = f;
            expect_next = 1;
        } else if (f.id == inverted_can_id(ch)) {
            expect(expect_next == 1, where + "inverted copy without its safety frame just before it");
            const CanFrame want = inverted_copy(last_safety);
            bool same = f.dlc == want.dlc;
            for (int k = 0; same && k < 8; ++k) {
                same = f.data[k] == want.data[k];
            }
            expect(same, where + "inverted copy does not match its safety frame");
            if (expect_next == 1 && cycle >= 0) {
                out.cycles[static_cast<std::size_t>(cycle)].copy = same;
            }
            expect_next = 3;
        } else if (f.id == rc.link.peer.can_id) {
            expect(expect_next == 3, where + "the monitor's link frame not right after a safety pair");
            PlcReceiver peek = plc;  // what the PLC's reply to this frame echoes, without advancing the model
            answers_due.push_back({peek.next_link(rec.timestamp_us), expect_next == 3 ? cycle : -1});
            if (!early_replies.empty()) {
                check_reply(early_replies.front(), where);
                early_replies.erase(early_replies.begin());
            }
            if (expect_next == 3 && cycle >= 0) {
                CycleFrames& cf = out.cycles[static_cast<std::size_t>(cycle)];
                cf.link = true;
                cf.after_copy = rs;
                cf.link_t_us = rec.timestamp_us;
            }
            expect_next = 2;
        } else if (f.id == ch.diagnostics_can_id) {
            expect(expect_next == 2, where + "diagnostics frame not right after a safety pair");
            const Result<DiagnosticsFrameContent> d = decode_diagnostics_frame(f, ch);
            expect(d.ok(), where + "diagnostics frame does not decode");
            if (d.ok() && cycle >= 0) {
                const DiagnosticsFrameContent& dc = d.value();
                // Both counters and the CRC page advance once per cycle, sent or not.
                expect(dc.counter == cycle % 15, where + "diagnostics counter " + std::to_string(dc.counter) +
                                                     " is not cycle " + std::to_string(cycle) + " mod 15");
                expect(dc.message.prior_crc_page == cycle % 4, where + "prior CRC page " +
                                                                   std::to_string(dc.message.prior_crc_page) +
                                                                   " is not cycle " + std::to_string(cycle) + " mod 4");
                const std::uint8_t page = dc.message.prior_crc_page & 3U;
                expect(!crc_page_seen[page] || crc_bytes[page] == dc.message.prior_crc_part,
                       where + "prior CRC byte changed");
                crc_page_seen[page] = true;
                crc_bytes[page] = dc.message.prior_crc_part;
                CycleFrames& cf = out.cycles[static_cast<std::size_t>(cycle)];
                cf.diagnostics = expect_next == 2;
                cf.diag = dc.message;
            }
            expect_next = 0;
        } else {
            expect(false, where + "unexpected CAN ID 0x" + std::to_string(f.id));
        }
    }
    expect(early_replies.empty(), std::to_string(early_replies.size()) +
                                      " link frame(s) of the PLC at the log's end answer no link frame of the monitor");
    out.prior_crc = static_cast<std::uint32_t>(crc_bytes[0]) | (static_cast<std::uint32_t>(crc_bytes[1]) << 8U) |
                    (static_cast<std::uint32_t>(crc_bytes[2]) << 16U) |
                    (static_cast<std::uint32_t>(crc_bytes[3]) << 24U);
    return true;
}

bool complete(const CycleFrames& c) { return c.safety && c.copy && c.link && c.diagnostics; }

/// A refusal for time alone: data older than the watchdog time, no good pair within the SCT, a copy after the SRVT.
bool time_fault(ReceiverFault f) {
    return f == ReceiverFault::kWatchdogExpired || f == ReceiverFault::kSctExpired ||
           f == ReceiverFault::kInvertedCopyLate;
}

std::uint64_t late_by(std::uint64_t t, std::uint64_t due) { return t > due ? t - due : 0U; }

/// How late cycle k is in the recording: its safety frame beyond one period after cycle k-1's, or the PLC's
/// reply to its link frame after that frame (the larger; 0 when neither is recorded).
std::uint64_t lateness_us(const Parsed& p, const MonitorConfig& cfg, int k) {
    const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
    std::uint64_t late = 0U;
    if (k > 0 && c.safety && p.cycles[static_cast<std::size_t>(k - 1)].safety) {
        late = late_by(c.t_us, p.cycles[static_cast<std::size_t>(k - 1)].t_us + cfg.period_us);
    }
    if (c.link && c.reply_t_us != 0U) {
        late = std::max(late, late_by(c.reply_t_us, c.link_t_us));
    }
    return late;
}

/// The host's stalls the receiver answered as it must. Under emulation on a loaded machine the VM (or one of its
/// processes) may not run for a second: the monitor's next frames, or the PLC's reply, come that much late, and
/// the receiver rightly refuses the pair (the data older than the watchdog time) and recovers by its rule. The
/// checks accept such a refusal only where the recording shows the delay; anything else fails.
struct Stalls {
    std::vector<int> refused;     // cycles refused for a stall the recording shows
    std::uint64_t worst_us = 0U;  // the largest lateness that explained one
    int valid = 0;                // cycles checked and valid
};

/// Expects the receiver valid after cycle @p k's pair, or its refusal explained by a stall of the host: a time
/// fault, and a cycle at most recovery_good_pairs + 1 before it (or @p k itself) more than half a period late.
void expect_valid_or_stall(const Parsed& p, const MonitorConfig& cfg, const PlcReceiverConfig& rc, int k,
                           const std::string& what, Stalls& stalls) {
    const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
    if (c.after_copy.communication_valid) {
        ++stalls.valid;
        return;
    }
    std::uint64_t late = 0U;
    for (int j = std::max(0, k - static_cast<int>(rc.recovery_good_pairs) - 1); j <= k; ++j) {
        late = std::max(late, lateness_us(p, cfg, j));
    }
    const bool stall = time_fault(c.after_copy.fault) && late > cfg.period_us / 2U;
    expect(stall, "cycle " + std::to_string(k) + ": receiver not valid " + what + ": " + to_string(c.after_copy.fault) +
                      " (no frame of this or the " + std::to_string(rc.recovery_good_pairs + 1U) +
                      " cycles before it more than half a period late: " + std::to_string(late / 1000U) + " ms)");
    if (stall) {
        stalls.refused.push_back(k);
        stalls.worst_us = std::max(stalls.worst_us, late);
    }
}

/// A stall must leave enough of the run: at least half the pairs checked valid.
void expect_mostly_valid(const Stalls& stalls, const std::string& what) {
    const int checked = stalls.valid + static_cast<int>(stalls.refused.size());
    expect(2 * stalls.valid >= checked, "the host stalled so often that " + std::to_string(stalls.refused.size()) +
                                            " of " + std::to_string(checked) + " pairs " + what +
                                            " were refused: the run shows nothing");
}

/// The stalls for the summary line ("" when none).
std::string stalls_text(const Stalls& stalls) {
    if (stalls.refused.empty()) {
        return "";
    }
    std::string cycles;
    for (int k : stalls.refused) {
        cycles += (cycles.empty() ? "" : ",") + std::to_string(k);
    }
    return "; the host stalled (a frame up to " + std::to_string(stalls.worst_us / 1000U) +
           " ms late): the receiver refused the pairs of cycles " + cycles + " for time and recovered by its rule";
}

/// The first cycle in which the scripted person overlaps a protective zone (-1: none).
int entry_cycle(const MonitorConfig& cfg, int cycles) {
    for (int k = 0; k < cycles; ++k) {
        for (const ZoneSettings& z : cfg.zones) {
            if (z.zone.kind == ZoneKind::kProtective && person_overlaps(z.zone, demo_person(k))) {
                return k;
            }
        }
    }
    return -1;
}

std::string faults_text(std::uint16_t bits) {
    std::string s;
    for (unsigned b = 0U; b < 16U; ++b) {
        if ((bits & (1U << b)) != 0U) {
            s += (s.empty() ? "" : ",") + std::to_string(b);
        }
    }
    return s.empty() ? "-" : s;
}

int check_normal(const MonitorConfig& cfg, const char* log, int cycles) {
    Parsed p;
    if (!parse_log(log, cfg, p)) {
        return 2;
    }
    const PlcReceiverConfig rc = receiver_config(cfg);
    // Four frames of the monitor a cycle and the PLC's link frame in reply to each of its link frames.
    expect(p.lines == 5 * cycles,
           "expected " + std::to_string(5 * cycles) + " frames, recorded " + std::to_string(p.lines));
    expect(p.plc_links == cycles,
           "expected " + std::to_string(cycles) + " PLC link frames, recorded " + std::to_string(p.plc_links));
    expect(static_cast<int>(p.cycles.size()) == cycles,
           "expected " + std::to_string(cycles) + " cycles, the counters span " + std::to_string(p.cycles.size()));
    int valid_pairs = 0;
    Stalls stalls;
    for (std::size_t k = 0U; k < p.cycles.size(); ++k) {
        const CycleFrames& c = p.cycles[k];
        const std::string where = "cycle " + std::to_string(k) + ": ";
        expect(complete(c), where + "not every frame recorded");
        valid_pairs += c.after_copy.communication_valid ? 1 : 0;
        // Cycle 0's link frame echoes nothing (the PLC replies to it: the start-up handshake); then the
        // reference pair and the recovery pairs.
        if (k >= rc.recovery_good_pairs + 1U) {
            expect_valid_or_stall(p, cfg, rc, static_cast<int>(k), "after start-up", stalls);
            expect(c.after_copy.stop_requested == c.message.protective_stop || !c.after_copy.communication_valid,
                   where + "receiver's stop differs from the frame's");
        }
        expect(!c.message.fault, where + "fault bit set");
        expect(c.diag.active_faults == 0U, where + "diagnostics report faults " + faults_text(c.diag.active_faults));
    }
    expect_mostly_valid(stalls, "after start-up");
    bool time_faults_only = true;
    for (ReceiverFault f : p.faults_seen) {
        time_faults_only = time_faults_only && time_fault(f);
    }
    expect((p.invalid_polls_after_valid == 0 && p.faults_seen.empty()) || (!stalls.refused.empty() && time_faults_only),
           "the receiver left the valid state after start-up (" + std::to_string(p.invalid_polls_after_valid) +
               " polls) other than for a stall the recording shows");
    const int entry = entry_cycle(cfg, cycles);
    expect(entry > 0 && entry < static_cast<int>(p.cycles.size()),
           "the person enters the protective zone during the run");
    double latency_ms = -1.0;
    bool entry_stop = false;
    if (entry > 0 && entry < static_cast<int>(p.cycles.size())) {
        const CycleFrames& before = p.cycles[static_cast<std::size_t>(entry - 1)];
        const CycleFrames& at = p.cycles[static_cast<std::size_t>(entry)];
        expect(!before.message.protective_stop,
               "no stop in the cycle before the entry (cycle " + std::to_string(entry - 1) + ")");
        expect(at.message.protective_stop, "stop in the entry cycle " + std::to_string(entry));
        expect(at.after_copy.stop_requested, "the receiver reports the stop with the entry cycle's pair");
        latency_ms = static_cast<double>(at.t_us - before.t_us) / 1000.0;
        entry_stop = at.message.protective_stop;
    }
    std::printf(
        "normal run: %d frames (%d of them the PLC's link frames), %zu cycles, %d pairs valid at the PLC "
        "receiver (session link, watchdog %.0f ms), prior CRC 0x%08X; person "
        "enters the protective zone in cycle %d, stop bit in that cycle's frame: %d, sent %.1f ms after the "
        "previous cycle's (period %.0f ms, SCT %.0f ms)%s; %d failures\n",
        p.lines, p.plc_links, p.cycles.size(), valid_pairs, static_cast<double>(rc.link.watchdog_us) / 1000.0,
        p.prior_crc, entry, entry_stop ? 1 : 0, latency_ms, static_cast<double>(cfg.period_us) / 1000.0,
        static_cast<double>(rc.sct_us) / 1000.0, stalls_text(stalls).c_str(), g_failures);
    return g_failures == 0 ? 0 : 1;
}

/// One status line of the monitor: "t=...s cycle  N person ... | STOP WARN | faults X | cycle ...".
struct StatusLine {
    bool present = false;
    bool stop = false;
    bool can_error = false;
    std::string faults;
};

bool parse_status(const char* path, int cycles, std::vector<StatusLine>& out, std::string& summary_faults) {
    std::ifstream in(path);
    if (!in) {
        std::printf("cannot open %s\n", path);
        return false;
    }
    out.assign(static_cast<std::size_t>(cycles), StatusLine{});
    for (std::string line; std::getline(in, line);) {
        const std::string kSummary = "summary: faults latched during the run: ";
        if (line.compare(0, kSummary.size(), kSummary) == 0) {
            summary_faults = line.substr(kSummary.size(), line.find(';') - kSummary.size());
            continue;
        }
        if (line.compare(0, 2, "t=") != 0) {
            continue;
        }
        const std::size_t c = line.find(" cycle ");
        const std::size_t f = line.find("| faults ");
        if (c == std::string::npos || f == std::string::npos) {
            continue;
        }
        const int k = std::atoi(line.c_str() + c + 7);
        if (k < 0 || k >= cycles) {
            expect(false, "status line for cycle " + std::to_string(k) + " beyond the run");
            continue;
        }
        StatusLine& s = out[static_cast<std::size_t>(k)];
        expect(!s.present, "two status lines for cycle " + std::to_string(k));
        s.present = true;
        s.stop = line.find("| STOP ") != std::string::npos;
        const std::size_t e = line.find(" | ", f + 9);
        s.faults = line.substr(f + 9, e == std::string::npos ? std::string::npos : e - (f + 9));
        s.can_error = s.faults.find(to_string(Fault::kCanError)) != std::string::npos;
    }
    return true;
}

int check_fault(const MonitorConfig& cfg, const char* log, const char* status, int cycles) {
    Parsed p;
    std::vector<StatusLine> sl;
    std::string summary_faults;
    if (!parse_log(log, cfg, p) || !parse_status(status, cycles, sl, summary_faults)) {
        return 2;
    }
    const PlcReceiverConfig rc = receiver_config(cfg);
    const int n = static_cast<int>(p.cycles.size());
    for (int k = 0; k < cycles; ++k) {
        expect(sl[static_cast<std::size_t>(k)].present, "no status line for cycle " + std::to_string(k));
    }
    expect(summary_faults.find(to_string(Fault::kCanError)) != std::string::npos,
           "the monitor's summary lists the CAN error (it says: " + summary_faults + ")");
    expect(n == cycles, "the last recorded cycle is " + std::to_string(n - 1) + ", not " + std::to_string(cycles - 1));

    // The outage: first cycle not completely on the bus (F), first cycle back (R).
    int first_missing = -1, resumed = -1;
    for (int k = 0; k < n; ++k) {
        const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
        if (first_missing < 0 && !complete(c)) {
            first_missing = k;
        } else if (first_missing >= 0 && resumed < 0 && c.safety) {
            resumed = k;
        }
        if (resumed >= 0) {
            expect(complete(c), "cycle " + std::to_string(k) + " after the outage: not every frame recorded");
        } else if (first_missing >= 0 && k > first_missing) {
            expect(!c.safety && !c.copy && !c.link && !c.diagnostics,
                   "cycle " + std::to_string(k) + ": frames inside the outage");
        }
    }
    expect(first_missing > 0, "frames are missing (the interface went down)");
    expect(resumed > first_missing + 1, "at least one whole cycle is missing and frames come back after it");
    if (first_missing <= 0 || resumed <= first_missing + 1) {
        std::printf("fault run: %d frames, %d cycles; %d failures\n", p.lines, n, g_failures);
        return 1;
    }
    const int f = first_missing, r = resumed;
    const CycleFrames& last_before = p.cycles[static_cast<std::size_t>(f - 1)];
    const CycleFrames& back = p.cycles[static_cast<std::size_t>(r)];

    // Before the outage: valid, no fault, and the machine was running.
    Stalls stalls;
    for (int k = 0; k < f; ++k) {
        const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
        expect(!c.message.fault, "cycle " + std::to_string(k) + ": fault bit before the outage");
        if (k >= static_cast<int>(rc.recovery_good_pairs) + 1) {  // after the start-up handshake (check_normal)
            expect_valid_or_stall(p, cfg, rc, k, "before the outage", stalls);
        }
    }
    expect_mostly_valid(stalls, "before the outage");
    expect(!last_before.message.protective_stop, "no stop in the last cycle before the outage (cycle " +
                                                     std::to_string(f - 1) + "): the outage must cause the stop");

    // The monitor's view: fault latched in the cycle after the first failed send.
    for (int k = 0; k <= f && k < cycles; ++k) {
        expect(!sl[static_cast<std::size_t>(k)].can_error,
               "cycle " + std::to_string(k) + ": CAN error before any send failed");
    }
    for (int k = f + 1; k <= r && k < cycles; ++k) {
        const StatusLine& s = sl[static_cast<std::size_t>(k)];
        expect(s.can_error && s.stop, "cycle " + std::to_string(k) + " (outage from cycle " + std::to_string(f) +
                                          "): monitor shows STOP with CAN error (it shows " +
                                          (s.stop ? "STOP" : "run") + ", faults " + s.faults + ")");
    }
    // The bus carries what the monitor decided.
    for (int k = 0; k < n && k < cycles; ++k) {
        const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
        if (c.safety) {
            expect(c.message.protective_stop == sl[static_cast<std::size_t>(k)].stop,
                   "cycle " + std::to_string(k) + ": stop bit on the bus differs from the monitor's status line");
            expect(c.message.fault == !(sl[static_cast<std::size_t>(k)].faults == "-"),
                   "cycle " + std::to_string(k) + ": fault bit on the bus differs from the monitor's status line");
        }
    }

    // First cycle back on the bus: stop, fault, and why.
    expect(back.message.protective_stop && back.message.fault,
           "cycle " + std::to_string(r) + " (first back on the bus): stop and fault set");
    const std::uint16_t need = static_cast<std::uint16_t>(fault_bit(FaultCode::kCanError) |
                                                          fault_bit(FaultCode::kCanNetworkDown));
    expect((back.diag.active_faults & need) == need,
           "cycle " + std::to_string(r) + ": diagnostics carry kCanError (5) and kCanNetworkDown (10); they carry " +
               faults_text(back.diag.active_faults));
    if (r + 1 < n) {
        const std::uint16_t after = p.cycles[static_cast<std::size_t>(r + 1)].diag.active_faults;
        expect((after & fault_bit(FaultCode::kCanNetworkDown)) == 0U,
               "cycle " + std::to_string(r + 1) + ": kCanNetworkDown cleared by the accepted send; diagnostics carry " +
                   faults_text(after));
    }

    // The PLC's view: safe state over the gap, then recovery by its rule.
    const std::uint64_t gap_us = back.t_us - last_before.t_us;
    expect(!back.after_copy.communication_valid && back.after_copy.stop_requested,
           "receiver in the safe state at the first pair after the outage");
    // Two ways in: a gap longer than the watchdog time (or the SCT) is
    // silence, seen by the PLC's poll before the next frame comes (the data
    // in use too old, or no pair within the SCT); a shorter gap shows as a
    // counter jump on the first pair back (frames lost). Either way the
    // first pair back is refused: the monitor's link sequence advanced in
    // every cycle of the outage (a sequence jump) and its echo names a PLC
    // link frame from before the outage; the PLC replies to its link frame,
    // the pair after it echoes that reply and is the reference; then
    // recovery_good_pairs more good pairs are needed.
    const bool silence_first = p.silence_seen && p.silence_at_us < back.t_us;
    if (gap_us > std::min(rc.sct_us, rc.link.watchdog_us) + 10000U) {
        expect(silence_first,
               "receiver reported silence (watchdog or SCT) during the " + std::to_string(gap_us / 1000U) + " ms gap");
    }
    bool jump_seen = false;
    for (ReceiverFault k : p.faults_seen) {
        jump_seen = jump_seen || k == ReceiverFault::kCounterJump || k == ReceiverFault::kSctExpired ||
                    k == ReceiverFault::kSequenceJump || k == ReceiverFault::kWatchdogExpired;
    }
    expect(silence_first || jump_seen, "receiver saw the outage as silence or as a counter or sequence jump");
    const int reference = r + 1;
    for (int k = r; k < n; ++k) {
        const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
        const bool want_valid = k >= reference + rc.recovery_good_pairs;
        if (want_valid) {
            expect_valid_or_stall(p, cfg, rc, k, "after the recovery", stalls);
            continue;
        }
        expect(!c.after_copy.communication_valid,
               "cycle " + std::to_string(k) + ": receiver valid before its recovery (reference pair in cycle " +
                   std::to_string(reference) + ", " + std::to_string(rc.recovery_good_pairs) + " recovery pairs)");
    }

    // Recovery of the monitor: the fault clears after fault_recovery_cycles,
    // then the stop is released after the restart delay.
    int cleared = -1, released = -1;
    for (int k = r; k < n; ++k) {
        const CycleFrames& c = p.cycles[static_cast<std::size_t>(k)];
        if (cleared < 0 && !c.message.fault) {
            cleared = k;
        }
        if (cleared >= 0) {
            expect(!c.message.fault, "cycle " + std::to_string(k) + ": fault bit again after it cleared");
        }
        if (released < 0 && !c.message.protective_stop) {
            released = k;
        }
        if (released >= 0) {
            expect(!c.message.protective_stop, "cycle " + std::to_string(k) + ": stop again after the release");
        }
    }
    // The send of cycle r-1 failed, so cycle r still detects the CAN error;
    // cycles r+1 .. r+N are the N clean cycles that clear it.
    const int want_cleared = r + static_cast<int>(cfg.fault_recovery_cycles);
    expect(cleared == want_cleared, "fault bit clears in cycle " + std::to_string(want_cleared) + " (cycle back " +
                                        std::to_string(r) + " + fault_recovery_cycles " +
                                        std::to_string(cfg.fault_recovery_cycles) + "); it cleared in cycle " +
                                        std::to_string(cleared));
    expect(released > cleared && cleared >= 0, "stop released after the fault cleared (cleared " +
                                                   std::to_string(cleared) + ", released " + std::to_string(released) +
                                                   ")");
    double held_ms = -1.0;
    if (released > cleared && cleared >= 0) {
        // Restart interlock: held restart_delay after the fault cleared (the
        // controller's clock is the real one in paced mode; the bus time
        // differs from it by the cycle's computing time, which varies by up
        // to ~0.1 s under emulation on a loaded machine: tolerance half a
        // period before, a period after).
        const std::uint64_t tol = cfg.period_us / 2U;
        const std::uint64_t t_clear = p.cycles[static_cast<std::size_t>(cleared)].t_us;
        const std::uint64_t t_rel = p.cycles[static_cast<std::size_t>(released)].t_us;
        const std::uint64_t t_prev = p.cycles[static_cast<std::size_t>(released - 1)].t_us;
        held_ms = static_cast<double>(t_rel - t_clear) / 1000.0;
        expect(t_rel - t_clear + tol >= cfg.restart_delay_us, "stop held at least the restart delay");
        expect(t_prev - t_clear < cfg.restart_delay_us + cfg.period_us,
               "stop released in the first cycle after the delay");
    }
    const CycleFrames& last = p.cycles.back();
    // The receiver's validity at the end is checked above (valid, or refused for a stall the recording shows).
    expect(!last.message.protective_stop && !last.message.fault &&
               (!last.after_copy.communication_valid || !last.after_copy.stop_requested),
           "at the end: no stop, no fault");

    std::string rfaults;
    for (ReceiverFault k : p.faults_seen) {
        rfaults += (rfaults.empty() ? "" : ",") + std::string(to_string(k));
    }
    std::printf(
        "fault run: %d frames over %d cycles; first send failed in cycle %d, monitor STOP + CAN error from "
        "cycle %d; %d cycles lost; back on the bus in cycle %d after %.0f ms with stop+fault, diagnostics "
        "faults %s; receiver: %s%s, valid again in cycle %d; fault cleared in cycle %d, stop released in "
        "cycle %d (%.0f ms after)%s; %d failures\n",
        p.lines, n, f, f + 1, r - f, r, static_cast<double>(gap_us) / 1000.0,
        faults_text(back.diag.active_faults).c_str(), rfaults.empty() ? "-" : rfaults.c_str(),
        silence_first ? " (silence in the gap)" : " (no silence: counter jump)", reference + rc.recovery_good_pairs,
        cleared, released, held_ms, stalls_text(stalls).c_str(), g_failures);
    return g_failures == 0 ? 0 : 1;
}

bool load(const char* path, MonitorConfig& cfg) {
    const ConfigLoad l = load_monitor_config(path);
    if (!l.ok) {
        std::printf("configuration error: %s\n", l.error.c_str());
        return false;
    }
    cfg = l.config;
    return true;
}

int cycles_arg(const char* s) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    return end != s && *end == '\0' && v > 0 && v < 100000 ? static_cast<int>(v) : -1;
}

}  // namespace

int main(int argc, char** argv) {
    MonitorConfig cfg;
    if (argc == 5 && std::strcmp(argv[1], "normal") == 0 && cycles_arg(argv[4]) > 0) {
        return load(argv[2], cfg) ? check_normal(cfg, argv[3], cycles_arg(argv[4])) : 2;
    }
    if (argc == 6 && std::strcmp(argv[1], "fault") == 0 && cycles_arg(argv[5]) > 0) {
        return load(argv[2], cfg) ? check_fault(cfg, argv[3], argv[4], cycles_arg(argv[5])) : 2;
    }
    std::fprintf(stderr,
                 "usage: cellguard-vcan-check normal CONFIG LOG CYCLES\n"
                 "       cellguard-vcan-check fault CONFIG LOG STATUS CYCLES\n");
    return 2;
}
