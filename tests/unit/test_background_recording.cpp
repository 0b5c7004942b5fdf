// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Tests of apps/monitor background_recording.hpp: the monitor records the
// sensors' views of the empty cell from its own frame sources (live cameras
// through the same interface), writes them bound to the prior, and loads
// them back; sources that cannot give a view are refused by name.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/monitor/background_recording.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/prior_tool/prior_tool.hpp"

using namespace cellguard;

namespace {

/// A clock that pause() advances: the deadline without real waiting.
class SteppedTime final : public monitor::RecordingTime {
public:
    std::uint64_t now_us() noexcept override { return now; }
    void pause(std::uint64_t us) noexcept override {
        now += us;
        ++pauses;
    }
    std::uint64_t now = 1000U;
    std::size_t pauses = 0U;
};

/// Wraps a source as a live camera would show it: each frame comes
/// @p repeats times with the same capture stamp, and every @p refuse_every-th
/// call is refused (0: never).
class LiveLike final : public cell::FrameSource {
public:
    LiveLike(cell::FrameSource& inner, int repeats, int refuse_every)
        : inner_(&inner), repeats_(repeats), refuse_every_(refuse_every) {}
    bool load_frame(std::uint64_t /*cycle*/, SensorReading& reading, cell::FrameStatus& status) noexcept override {
        ++calls_;
        if (refuse_every_ > 0 && calls_ % refuse_every_ == 0) {
            status = cell::FrameStatus{};
            cell::refuse_reading(reading);
            return false;
        }
        const bool ok = inner_->load_frame(static_cast<std::uint64_t>(frame_), reading, status);
        status.has_stamp = true;
        status.stamp_us = 1000U + static_cast<std::uint64_t>(frame_) * 100000U;
        if (++served_ == repeats_) {
            served_ = 0;
            ++frame_;
        }
        return ok;
    }
    void write_summary(std::FILE* /*out*/) const noexcept override {}

private:
    cell::FrameSource* inner_;
    int repeats_;
    int refuse_every_;
    int calls_ = 0;
    int served_ = 0;
    int frame_ = 0;
};

/// A source that never gives a frame (a camera that does not stream).
class Silent final : public cell::FrameSource {
public:
    bool load_frame(std::uint64_t /*cycle*/, SensorReading& reading, cell::FrameStatus& status) noexcept override {
        status = cell::FrameStatus{};
        cell::refuse_reading(reading);
        return false;
    }
    void write_summary(std::FILE* /*out*/) const noexcept override {}
};

/// The demo's cell with a prior file from the prior tool, configured, its prior and tables built.
struct Commissioned {
    Commissioned() {
        char templ[] = "/tmp/cellguard_test_recording_XXXXXX";
        REQUIRE(::mkdtemp(templ) != nullptr);
        dir = templ;
        std::ostringstream out;
        std::ostringstream err;
        REQUIRE(prior_tool::run_prior_tool({"--simulated", "--background-frames", "8", "--out", dir}, out, err,
                                           false) == prior_tool::kExitOk);
        text = cell::demo_config_text();
        const std::string sim_prior =
            "source = \"simulated-background\"   # or \"file\", with file = \"path/to/prior.cgprior\"\n";
        const std::size_t at = text.find(sim_prior);
        REQUIRE(at != std::string::npos);
        text.replace(at, sim_prior.size(), "source = \"file\"\nfile = \"" + dir + "/prior.cgprior\"\n");
        const cell::ConfigLoad load = cell::parse_monitor_config(text, "cell.toml", dir);
        INFO(load.error);
        REQUIRE(load.ok);
        cfg = load.config;
        REQUIRE_FALSE(cell.configure(cfg).failed());
        REQUIRE_FALSE(cell.build_prior(cfg, nullptr).failed());
        REQUIRE_FALSE(cell.build_tables(cfg, nullptr).failed());
        for (std::size_t i = 0; i < cell.specs.size(); ++i) {
            empty.push_back(std::make_unique<cell::EmptyCellFrameSource>(cell.layout.readings[i]));
            sources.push_back(empty.back().get());
        }
    }
    ~Commissioned() {
        for (const char* f : {"prior.cgprior", "prior_flash.hpp", "p_acc.npy", "p_fore.npy", "views.cgbv"}) {
            std::remove((dir + "/" + f).c_str());
        }
        ::rmdir(dir.c_str());
    }
    Commissioned(const Commissioned&) = delete;
    Commissioned& operator=(const Commissioned&) = delete;

    /// The cell's configuration with background_file naming @p file.
    [[nodiscard]] cell::MonitorConfig with_views(const std::string& file) const {
        cell::MonitorConfig c = cfg;
        c.prior.background_file = file;
        return c;
    }

    std::string dir;
    std::string text;
    cell::MonitorConfig cfg;
    monitor::MonitorCell cell;
    std::vector<std::unique_ptr<cell::EmptyCellFrameSource>> empty;
    std::vector<cell::FrameSource*> sources;
};

}  // namespace

// verifies: SR-CAM-009
TEST_CASE("background recording: the monitor's own sources give the views, which load back as the empty cell") {
    Commissioned c;
    monitor::BackgroundRecording rec;
    rec.path = c.dir + "/views.cgbv";
    rec.frames = 5;
    SteppedTime time;
    std::vector<monitor::RecordedSensor> counts;
    const monitor::SetupError e = monitor::record_background_views(c.cell, c.sources, rec, time, counts, nullptr);
    INFO(e.message);
    REQUIRE_FALSE(e.failed());
    REQUIRE(counts.size() == 4U);
    for (const monitor::RecordedSensor& n : counts) {
        CHECK(n.frames == 5U);
        CHECK(n.refused == 0U);
    }
    CHECK(time.pauses == 0U);  // rendered frames never wait
    // The monitor loads them for this prior; the lower median of dithered frames is the render.
    const cell::MonitorConfig cfg = c.with_views(rec.path);
    monitor::MonitorCell loaded;
    REQUIRE_FALSE(loaded.configure(cfg).failed());
    REQUIRE_FALSE(loaded.build_prior(cfg, nullptr).failed());
    const monitor::SetupError le = loaded.build_tables(cfg, nullptr);
    INFO(le.message);
    REQUIRE_FALSE(le.failed());
    REQUIRE(loaded.background_views.size() == 4U);
    for (std::size_t s = 0; s < 4U; ++s) {
        std::size_t differ = 0U;
        for (std::size_t i = 0; i < loaded.background_views[s].size(); ++i) {
            const float d = loaded.layout.readings[s].depth[i];
            const float render = (std::isfinite(d) && d > 0.0F) ? d : 0.0F;
            const float v = loaded.background_views[s][i];
            differ += v == render ? 0U : 1U;
        }
        CHECK(differ == 0U);  // the lower median of the dithered frames is the render, bit for bit
    }
}

// verifies: SR-CAM-009
TEST_CASE("background recording: a live sensor's repeated frame counts once, refused frames are skipped") {
    Commissioned c;
    LiveLike live(*c.sources[2], 3, 4);  // each frame seen three times, every fourth poll refused
    std::vector<cell::FrameSource*> sources = c.sources;
    sources[2] = &live;
    monitor::BackgroundRecording rec;
    rec.path = c.dir + "/views.cgbv";
    rec.frames = 4;
    SteppedTime time;
    std::vector<monitor::RecordedSensor> counts;
    const monitor::SetupError e = monitor::record_background_views(c.cell, sources, rec, time, counts, nullptr);
    INFO(e.message);
    REQUIRE_FALSE(e.failed());
    CHECK(counts[2].frames == 4U);
    CHECK(counts[2].repeated > 0U);
    CHECK(counts[2].refused > 0U);
    CHECK(time.pauses == counts[2].repeated + counts[2].refused);  // it waited after each poll without a new frame
    CHECK(counts[0].repeated == 0U);
}

// verifies: SR-CAM-009
TEST_CASE("background recording: a silent sensor, a point set, a wrong size and bad arguments are refused by name") {
    Commissioned c;
    monitor::BackgroundRecording rec;
    rec.path = c.dir + "/views.cgbv";
    rec.frames = 3;
    rec.deadline_us = 1000000U;
    std::vector<monitor::RecordedSensor> counts;
    SUBCASE("a sensor that never gives a frame: the deadline") {
        Silent silent;
        std::vector<cell::FrameSource*> sources = c.sources;
        sources[1] = &silent;
        SteppedTime time;
        const monitor::SetupError e = monitor::record_background_views(c.cell, sources, rec, time, counts, nullptr);
        CHECK(e.exit_status == 1);
        CHECK(e.message.find("sensor 'lidar-b' gave too few frames") != std::string::npos);
        CHECK(e.message.find("0 of 3 frames") != std::string::npos);
        CHECK(time.now >= 1000000U);
    }
    SUBCASE("another sensor's images: the wrong size") {
        std::vector<cell::FrameSource*> sources = c.sources;
        sources[0] = c.sources[2];  // a stereo camera's image where a lidar's is configured
        SteppedTime time;
        const monitor::SetupError e = monitor::record_background_views(c.cell, sources, rec, time, counts, nullptr);
        CHECK(e.exit_status == 1);
        CHECK(e.message.find("sensor 'lidar-a'") != std::string::npos);
        CHECK(e.message.find("another size") != std::string::npos);
    }
    SUBCASE("bad arguments") {
        SteppedTime time;
        monitor::BackgroundRecording bad = rec;
        bad.frames = 0;
        CHECK(monitor::record_background_views(c.cell, c.sources, bad, time, counts, nullptr).exit_status == 2);
        bad = rec;
        bad.path.clear();
        CHECK(monitor::record_background_views(c.cell, c.sources, bad, time, counts, nullptr).exit_status == 2);
        std::vector<cell::FrameSource*> three(c.sources.begin(), c.sources.begin() + 3);
        CHECK(monitor::record_background_views(c.cell, three, rec, time, counts, nullptr).exit_status == 2);
    }
    // Nothing was written in any of these cases.
    CHECK(::access(rec.path.c_str(), F_OK) != 0);
}
