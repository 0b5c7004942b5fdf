// cellguard-monitor-check-log: checks a candump log written by
// `cellguard-monitor --demo` with the PLC-side receiver: every frame decodes,
// every inverted copy matches, the receiver accepts every pair once recovered,
// and the stop request appears in the cycle in which the scripted person
// enters the protective zone (and not in the cycle before).
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "cellguard/linux/candump_log.hpp"
#include "cellguard/monitor/config.hpp"
#include "cellguard/monitor/scenario.hpp"
#include "cellguard/plc_receiver.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

int failures = 0;

void expect(bool ok, const std::string& what) {
    if (!ok) {
        ++failures;
        std::fprintf(stderr, "FAIL: %s\n", what.c_str());
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: cellguard-monitor-check-log LOG CYCLES\n");
        return 2;
    }
    const int cycles = std::atoi(argv[2]);
    const MonitorConfig cfg = demo_config();
    const SafetyChannelConfig& ch = cfg.can.channel;
    PlcReceiverConfig rc;
    rc.channel = ch;
    rc.srvt_us = cfg.period_us / 2U;
    rc.sct_us = 3U * cfg.period_us;
    rc.expected_zone_count = static_cast<std::uint8_t>(cfg.zones.size());
    if (!PlcReceiver::check_config(rc).ok()) {
        std::fprintf(stderr, "receiver config invalid\n");
        return 2;
    }
    PlcReceiver plc(rc);

    std::ifstream in(argv[1]);
    if (!in) {
        std::fprintf(stderr, "cannot open %s\n", argv[1]);
        return 2;
    }
    std::vector<bool> stop;
    int lines = 0, diagnostics = 0, valid_pairs = 0;
    CanFrame last_safety{};
    bool have_safety = false;
    for (std::string line; std::getline(in, line);) {
        ++lines;
        linux_port::CandumpRecord rec;
        const IoStatus st = linux_port::parse_candump_line(line.c_str(), rec);
        expect(st.ok(), "line " + std::to_string(lines) + ": " + st.message());
        if (!st.ok()) {
            continue;
        }
        const CanFrame& f = rec.frame;
        const ReceiverStatus rs = plc.on_frame(f, rec.timestamp_us);
        if (f.id == ch.safety_can_id) {
            const Result<SafetyFrameContent> c = decode_safety_frame(f, ch);
            expect(c.ok(), "line " + std::to_string(lines) + ": safety frame does not decode");
            expect(!c.ok() || c.value().counter == stop.size() % 15U,
                   "line " + std::to_string(lines) + ": safety counter out of sequence");
            stop.push_back(c.ok() ? c.value().message.protective_stop : true);
            last_safety = f;
            have_safety = true;
        } else if (f.id == inverted_can_id(ch)) {
            const CanFrame want = inverted_copy(last_safety);
            bool same = have_safety && f.dlc == want.dlc;
            for (int k = 0; same && k < 8; ++k) {
                same = f.data[k] == want.data[k];
            }
            expect(same, "line " + std::to_string(lines) + ": inverted copy does not match its safety frame");
            if (stop.size() >= 3U) {  // the reference pair and two recovery pairs
                expect(rs.communication_valid, "line " + std::to_string(lines) + ": receiver not valid: " +
                                                   to_string(rs.fault));
                expect(rs.stop_requested == stop.back(),
                       "line " + std::to_string(lines) + ": receiver stop differs from the frame");
            }
            valid_pairs += rs.communication_valid ? 1 : 0;
            have_safety = false;
        } else if (f.id == ch.diagnostics_can_id) {
            const Result<DiagnosticsFrameContent> d = decode_diagnostics_frame(f, ch);
            expect(d.ok(), "line " + std::to_string(lines) + ": diagnostics frame does not decode");
            expect(!d.ok() || d.value().message.prior_crc_page == static_cast<std::uint8_t>(diagnostics % 4),
                   "line " + std::to_string(lines) + ": prior CRC page out of sequence");
            ++diagnostics;
        } else {
            expect(false, "line " + std::to_string(lines) + ": unexpected CAN ID");
        }
    }
    expect(lines == 3 * cycles, "expected " + std::to_string(3 * cycles) + " lines, got " + std::to_string(lines));
    expect(static_cast<int>(stop.size()) == cycles, "one safety frame per cycle");

    int entry = -1;
    for (const ZoneSettings& z : cfg.zones) {
        if (z.zone.kind != ZoneKind::kProtective) {
            continue;
        }
        for (int k = 0; k < cycles && entry < 0; ++k) {
            if (person_overlaps(z.zone, demo_person(k))) {
                entry = k;
            }
        }
    }
    expect(entry > 0 && entry < static_cast<int>(stop.size()), "the person enters the protective zone during the run");
    if (entry > 0 && entry < static_cast<int>(stop.size())) {
        expect(!stop[static_cast<std::size_t>(entry - 1)], "no stop in the cycle before the entry (cycle " +
                                                               std::to_string(entry - 1) + ")");
        expect(stop[static_cast<std::size_t>(entry)], "stop in the entry cycle " + std::to_string(entry));
    }
    std::printf("%d lines, %zu safety pairs (%d accepted by the PLC receiver), %d diagnostics frames; "
                "person enters the protective zone in cycle %d, stop bit there: %s; %d failures\n",
                lines, stop.size(), valid_pairs, diagnostics, entry,
                entry >= 0 && entry < static_cast<int>(stop.size()) && stop[static_cast<std::size_t>(entry)] ? "1" : "0",
                failures);
    return failures == 0 ? 0 : 1;
}
