// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the stop snapshot (apps/monitor: snapshot.hpp): on the simulated
// demo the stop after the release (cycle 15) gives exactly one snapshot with
// the grid of that cycle (.npy, read back and compared), the picture (PNG
// signature) and the CAN frames before and after it, while every cycle
// allocates nothing; a stop while a snapshot is still collecting is skipped
// and counted; only the newest `keep` snapshots are kept.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/io/npy.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/snapshot.hpp"
#include "monitor_test_doubles.hpp"
#include "temp_dir.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;
using cellguard::test::CountingSender;
using cellguard::test::SteppingClock;

using cellguard::test::TempDir;

namespace {

/// The demo's cell, as main sets it up, with a snapshot recorder into @p dir.
struct Demo {
    Demo(const std::string& dir, std::size_t keep, std::size_t frames_around)
        : cfg(demo_config()), clock(false, source_clock) {
        cfg.budget_us = 60000000U;
        REQUIRE_FALSE(cell.configure(cfg).failed());
        REQUIRE_FALSE(cell.build_prior(cfg, nullptr).failed());
        REQUIRE_FALSE(cell.build_tables(cfg, nullptr).failed());
        for (const sim::SensorSpec& spec : cell.specs) {
            simulated.push_back(std::make_unique<SimulatedFrameSource>(spec));
            sources.push_back(simulated.back().get());
        }
        can.use_sender(sender);
        loop = std::make_unique<MonitorLoop>(cfg, cell, sources, can, clock, nullptr);
        REQUIRE(loop->status().ok());
        PictureInput picture;
        std::string error;
        REQUIRE(config_picture_input("", cfg, cell.grid, cell.zones, cell.specs, {cell.prior.data(), cell.prior.size()},
                                     "", nullptr, picture, error));
        SnapshotSettings settings;
        settings.directory = dir;
        settings.keep = keep;
        settings.frames_around = frames_around;
        recorder = std::make_unique<SnapshotRecorder>(settings, cfg, cell.frame_grid, picture);
        REQUIRE(recorder->start(error));
        can.set_tap(recorder.get());
        loop->set_observer(recorder.get());
    }

    MonitorConfig cfg;
    MonitorCell cell;
    SteppingClock source_clock;
    CycleClock clock;
    CountingSender sender;
    CanPort can;
    std::vector<std::unique_ptr<SimulatedFrameSource>> simulated;
    std::vector<FrameSource*> sources;
    std::unique_ptr<MonitorLoop> loop;
    std::unique_ptr<SnapshotRecorder> recorder;
};

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

int count_lines_not_starting_with_hash(const std::string& text) {
    int n = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        n += !line.empty() && line[0] != '#' ? 1 : 0;
    }
    return n;
}

}  // namespace

// verifies: SR-SYS-009
TEST_CASE(
    "snapshot: the demo's stop in cycle 15 gives one snapshot: its grid, picture and CAN frames, no cycle allocates") {
    const TempDir dir("snapshot");
    Demo demo(dir.path(), 10U, 64U);
    std::vector<std::int16_t> grid_at_stop;
    int cycles_that_allocated = 0;
    for (int k = 0; k < 60; ++k) {
        // This thread's allocations: the snapshot's writer thread allocates (file names, PNG) meanwhile.
        const cellguard::test::ThreadAllocationScope scope;
        (void)demo.loop->run_cycle(k);
        cycles_that_allocated += scope.allocations() != 0U ? 1 : 0;
        if (k == 15) {
            const Span<std::int16_t> lo = demo.cell.frame_grid.log_odds();
            grid_at_stop.assign(lo.begin(), lo.end());
        }
    }
    CHECK(cycles_that_allocated == 0);
    CHECK(demo.loop->stats().first_stop_after_release == 15);
    demo.recorder->finish();
    const SnapshotCounts c = demo.recorder->counts();
    CHECK(c.triggered == 1U);
    CHECK(c.written == 1U);
    CHECK(c.skipped == 0U);
    CHECK(c.failed == 0U);
    REQUIRE(demo.recorder->written_paths().size() == 1U);
    const std::string snap = demo.recorder->written_paths()[0];
    CHECK(snap.find("/stop-") != std::string::npos);
    CHECK(snap.size() > 13U);
    CHECK(snap.compare(snap.size() - 13U, 13U, "-cycle-000015") == 0);
    // The grid as it was at the end of cycle 15.
    std::vector<std::int16_t> read(grid_at_stop.size());
    const IoStatus st = read_npy_int16((snap + "/grid_log_odds.npy").c_str(), demo.cell.grid.dims(),
                                       {read.data(), read.size()});
    CHECK(st.ok());
    CHECK(read == grid_at_stop);
    // The frames: 16 cycles of 4 before (cycles 0-15: safety, copy, link, diagnostics), 64 after.
    const std::string frames = read_text(snap + "/can.log");
    CHECK(count_lines_not_starting_with_hash(frames) == 64 + 64);
    CHECK(frames.rfind("(", 0) == 0);  // candump -L lines only, no comments
    const std::string text = read_text(snap + "/snapshot.txt");
    CHECK(text.find("can_frames_before 64\ncan_frames_after 64\ncan_frames_received 0\n") != std::string::npos);
    const std::string png = read_text(snap + "/picture.png");
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    CHECK(text.find("zone protective INTRUDED") != std::string::npos);
}

// verifies: SR-SYS-009
TEST_CASE("snapshot: a stop while the last snapshot still collects frames is skipped, and only the newest are kept") {
    const TempDir dir("snapshot");
    Demo demo(dir.path(), 2U, 4U);
    CycleReport run;
    run.safety.stop_requested = false;  // the default is the stop
    CycleReport stop;
    stop.safety.stop_requested = true;
    const CanFrame frame{0x101U, 2U, {1, 2}};
    int k = 0;
    const auto cycle = [&](const CycleReport& r, int frames_in_it) {
        for (int i = 0; i < frames_in_it; ++i) {
            demo.recorder->on_frame(frame, TapDirection::kSent);
        }
        demo.recorder->after_cycle(CycleView{k++, &r, 100U, 0U});
    };
    cycle(run, 1);
    cycle(stop, 1);  // triggers: collects 4 frames after
    cycle(run, 1);
    cycle(stop, 1);  // 2 of 4 collected: skipped
    cycle(run, 2);   // complete: written
    // Waits (up to 120 s: an emulator writes the PNG slowly) until the writer has counted every snapshot
    // it took, so that the next stop is normally recorded rather than skipped.
    const auto wait_idle = [&] {
        for (int i = 0; i < 1200; ++i) {
            const SnapshotCounts n = demo.recorder->counts();
            if (n.written + n.skipped + n.failed == n.triggered) {
                return true;
            }
            ::usleep(100000);
        }
        return false;
    };
    for (int i = 0; i < 4; ++i) {
        REQUIRE(wait_idle());
        cycle(stop, 1);
        cycle(run, 4);  // its 4 later frames: complete
    }
    demo.recorder->finish();
    const SnapshotCounts c = demo.recorder->counts();
    CHECK(c.triggered == 6U);
    CHECK(c.skipped + c.written == 6U);
    CHECK(c.skipped >= 1U);  // the second stop, while the first still collected its frames
    CHECK(c.failed == 0U);
    REQUIRE(c.written >= 2U);  // the writer marks itself free just after counting: a later stop may still be skipped
    CHECK(c.removed == c.written - 2U);  // keep = 2
    CHECK(demo.recorder->written_paths().size() == 2U);
    const int status = std::system(("test $(ls '" + dir.path() + "' | grep -c '^stop-') -eq 2").c_str());
    CHECK(status == 0);
}

// verifies: SR-SYS-009
TEST_CASE("snapshot: a directory that cannot be made is refused at start with the reason, not at the stop") {
    const cell::MonitorConfig cfg = demo_config();
    MonitorCell cell;
    REQUIRE_FALSE(cell.configure(cfg).failed());
    SnapshotSettings settings;
    settings.directory = "/dev/null/snapshots";  // below a file: mkdir fails (ENOTDIR), also for root
    SnapshotRecorder recorder(settings, cfg, cell.frame_grid, PictureInput{});
    std::string error;
    CHECK_FALSE(recorder.start(error));
    CHECK(error.find("/dev/null/snapshots") != std::string::npos);
    // Without a writer every stop is counted as skipped, none blocks.
    CycleReport run;
    run.safety.stop_requested = false;
    CycleReport stop;
    stop.safety.stop_requested = true;
    recorder.after_cycle(CycleView{0, &run, 0U, 0U});
    recorder.after_cycle(CycleView{1, &stop, 0U, 0U});
    recorder.finish();
    CHECK(recorder.counts().triggered == 1U);
    CHECK(recorder.counts().skipped == 1U);
    CHECK(recorder.counts().written == 0U);
}
