// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the monitor's recorded-frame input (apps/monitor: pcd_input.hpp,
// and `pcd_files` in config.cpp): good frames (ASCII, binary, a real Kinect
// frame) are fused, every bad frame (another sensor's viewpoint, the wrong
// image size, truncated or unreadable data) becomes kFrameInconsistent in the
// controller instead of a crash; the configuration key is checked with its line.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/safety/safety_controller.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

const std::string kFixtures = CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd/";
const std::string kKinect = CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142255.814212.pcd";

/// The fixtures' sensor (make_pcd_fixtures.py).
sim::SensorSpec recorded_spec() {
    return sim::SensorSpec{"recorded", {-1.9, 0.0, 1.9}, {0.0, 0.0, 0.0}, 16, 12, 40.0, 30.0, 10.0F};
}

PcdFrameSource source_for(const std::vector<std::string>& names) {
    std::vector<std::string> files;
    for (const std::string& n : names) {
        files.push_back(n.front() == '/' ? n : kFixtures + n);
    }
    const sim::SensorSpec s = recorded_spec();
    return PcdFrameSource(s.name, files, s.pose(), s.width, s.height, s.max_range);
}

class FixedClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return now += 10U; }
    std::uint64_t now = 1000000U;
};

/// Runs one controller cycle on @p reading alone; returns the faults detected.
std::uint32_t faults_of_one_cycle(const SensorReading& reading) {
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, 0.0), 0.05, GridDims{34, 30, 30}).value();
    std::vector<std::int16_t> lo(g.voxel_count()), prior(g.voxel_count(), -1000);
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
    ZoneConfig z;
    z.box_min = Eigen::Vector3d(0.0, 0.0, 0.0);
    z.box_max = Eigen::Vector3d(0.2, 0.2, 0.2);
    z.max_unseen_voxels = 1000U;
    std::vector<std::uint32_t> mask(g.voxel_count());
    const CompiledZones zones = CompiledZones::compile(g, {&z, 1U}, {mask.data(), mask.size()}).value();
    const SensorModelTable model;
    FixedClock clock;
    ControllerConfig cc;
    cc.sensor_count = 1U;
    std::vector<std::int16_t> scratch(g.voxel_count());
    SafetyController controller(cc, grid, {scratch.data(), scratch.size()}, {prior.data(), prior.size()}, zones, model,
                                clock, nullptr);
    SensorInput in;
    in.reading = reading;
    in.present = true;
    in.captured_us = clock.now;
    return controller.run_cycle({&in, 1U}, false).detected_faults;
}

}  // namespace

// verifies: SR-FUSE-004, SR-CTRL-002
TEST_CASE("pcd input: good ASCII and binary frames are fused, NaN pixels are skipped and counted") {
    PcdFrameSource src = source_for({"recorded-ascii.pcd", "recorded-binary.pcd"});
    SensorReading r;
    const PcdFrameCheck a = src.load(0U, r);
    CAPTURE(a.reason);
    REQUIRE(a.ok);
    CHECK(a.points == 191U);
    CHECK(a.nonfinite == 1U);
    CHECK(r.kind == SensorDataKind::kPointSet);
    CHECK(r.points.size() == 191U);
    CHECK(validate_sensor_reading(r).ok());
    CHECK(r.pose.isApprox(recorded_spec().pose()));
    // The points lie on the floor (z = 0 in the cell) or on the reference scene's background boxes, as recorded.
    std::size_t on_floor = 0U;
    for (const Eigen::Vector3f& p : r.points) {
        const double z = (r.pose * p.cast<double>()).z();
        CHECK(z > -1e-4);
        on_floor += std::abs(z) < 1e-4 ? 1U : 0U;
    }
    CHECK(on_floor < r.points.size());  // the boxes stand in its view
    CHECK(on_floor > r.points.size() / 2U);
    CHECK(faults_of_one_cycle(r) == 0U);

    const PcdFrameCheck b = src.load(1U, r);  // binary, VIEWPOINT = the sensor's pose
    CAPTURE(b.reason);
    REQUIRE(b.ok);
    CHECK(b.points == 192U);
    CHECK(b.nonfinite == 0U);
    const PcdFrameCheck again = src.load(2U, r);  // cycles back to the first file
    CHECK(again.ok);
    CHECK(again.file == a.file);
    CHECK(src.used() == 3U);
    CHECK(src.refused() == 0U);
}

// verifies: SR-FUSE-004, SR-CTRL-002
TEST_CASE("pcd input: a bad frame is refused and the controller reports it as an inconsistent frame") {
    const char* bad[] = {"recorded-other-sensor.pcd", "recorded-wrong-size.pcd", "recorded-truncated.pcd",
                         "does-not-exist.pcd"};
    const char* reasons[] = {"VIEWPOINT", "16 x 12", "", ""};
    for (std::size_t i = 0U; i < 4U; ++i) {
        CAPTURE(bad[i]);
        PcdFrameSource src = source_for({bad[i]});
        SensorReading r;
        const PcdFrameCheck c = src.load(0U, r);
        CAPTURE(c.reason);
        CHECK_FALSE(c.ok);
        CHECK_FALSE(c.reason.empty());
        CHECK(c.reason.find(reasons[i]) != std::string::npos);
        CHECK(src.refused() == 1U);
        CHECK(r.points.empty());
        CHECK_FALSE(validate_sensor_reading(r).ok());
        CHECK(faults_of_one_cycle(r) == fault_bit(Fault::kFrameInconsistent));
    }
}

// verifies: SR-FUSE-004
TEST_CASE("pcd input: the fuzz corpus's PCD files and a real Kinect frame") {
    // A 2 x 2 organised ASCII cloud for a sensor configured 2 x 2: accepted; for 16 x 12: refused.
    const std::string ascii = CELLGUARD_SOURCE_DIR "/tests/fuzz/corpus/fuzz_pcd/ascii.pcd";
    SensorReading r;
    {
        PcdFrameSource src("tiny", {ascii}, Eigen::Isometry3d::Identity(), 2, 2, 10.0F);
        const PcdFrameCheck c = src.load(0U, r);
        CAPTURE(c.reason);
        CHECK(c.ok);
        CHECK(c.points == 3U);
        CHECK(c.nonfinite == 1U);
    }
    {
        PcdFrameSource src = source_for({ascii});
        CHECK_FALSE(src.load(0U, r).ok);
    }
    {
        // More points than the sensor's image holds (its capacity in the work bound).
        PcdFrameSource src("small", {kFixtures + "recorded-ascii.pcd"}, Eigen::Isometry3d::Identity(), 10, 10, 10.0F);
        const PcdFrameCheck c = src.load(0U, r);
        CHECK_FALSE(c.ok);
        CHECK(c.reason.find("192 points, more than sensor 'small' delivers (10 x 10)") != std::string::npos);
    }
    // The real Kinect frame: 640 x 480, binary_compressed, many NaN pixels.
    // The frame ships in the repository (tests/data): its absence is a failure, never a skip.
    REQUIRE_MESSAGE(std::ifstream(kKinect, std::ios::binary).good(), "test data missing: " << kKinect);
    PcdFrameSource kinect("kinect", {kKinect}, Eigen::Isometry3d::Identity(), 640, 480, 10.0F);
    const PcdFrameCheck k = kinect.load(0U, r);
    CAPTURE(k.reason);
    REQUIRE(k.ok);
    CHECK(k.points + k.nonfinite == 640U * 480U);
    CHECK(k.nonfinite > 0U);
    CHECK(k.points > 100000U);
    CHECK(validate_sensor_reading(r).ok());
    // Fused into a grid in front of the camera: no fault, rays counted.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-1.5, -1.5, 0.0), 0.05, GridDims{60, 60, 80}).value();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
    grid.clear();
    std::vector<std::int16_t> scratch(g.voxel_count());
    const Result<FusionStats> f = fuse_sensor(grid, r, SensorModelTable{}, {scratch.data(), scratch.size()});
    REQUIRE(f.ok());
    CHECK(f.value().rays_fused + f.value().skipped() == k.points);
    CHECK(f.value().voxel_updates > 0U);
    // The same frame for a sensor configured 320 x 240 is another sensor's: refused.
    PcdFrameSource small("small", {kKinect}, Eigen::Isometry3d::Identity(), 320, 240, 10.0F);
    CHECK_FALSE(small.load(0U, r).ok);
}

// verifies: SR-CFG-001
TEST_CASE("pcd input: pcd_files is checked when the configuration loads") {
    const std::string base = std::string(demo_config_text());
    const std::string anchor = "max_range = 10.0\n";
    auto with = [&](const std::string& line) {
        std::string t = base;
        t.insert(t.find(anchor) + anchor.size(), line + "\n");
        return t;
    };
    std::string off = with("pcd_files = [\"pcd/recorded-ascii.pcd\"]");
    off.replace(off.find("background_match = 0.5 "), 23, "background_match = 0   ");
    off += "background_view_check = \"a recorded frame without a view of the empty cell\"\n";  // in [opt_out]
    const ConfigLoad good = parse_monitor_config(off, "cell.toml", CELLGUARD_SOURCE_DIR "/apps/monitor/test");
    CAPTURE(good.error);
    REQUIRE(good.ok);
    REQUIRE(good.config.sensors[0].pcd_files.size() == 1U);
    CHECK(good.config.sensors[0].pcd_files[0] == CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd/recorded-ascii.pcd");
    CHECK(good.config.sensors[1].pcd_files.empty());

    // A recorded sensor has a direction-grid view (SR-BKG-009): the background check stays on.
    const ConfigLoad with_view = parse_monitor_config(with("pcd_files = [\"pcd/recorded-ascii.pcd\"]"), "cell.toml",
                                                      CELLGUARD_SOURCE_DIR "/apps/monitor/test");
    CAPTURE(with_view.error);
    CHECK(with_view.ok);
    CHECK(with_view.config.background_match == 0.5F);

    const ConfigLoad empty = parse_monitor_config(with("pcd_files = []"), "cell.toml");
    CHECK_FALSE(empty.ok);
    CHECK(empty.error.find("sensors[0].pcd_files") != std::string::npos);
    const ConfigLoad number = parse_monitor_config(with("pcd_files = [3]"), "cell.toml");
    CHECK_FALSE(number.ok);
    CHECK(number.error.find("sensors[0].pcd_files[0]") != std::string::npos);
    const ConfigLoad missing = parse_monitor_config(with("pcd_files = [\"nope.pcd\"]"), "cell.toml", "/nonexistent");
    CHECK_FALSE(missing.ok);
    CHECK(missing.error.find("sensors[0].pcd_files[0]: cannot open '/nonexistent/nope.pcd'") != std::string::npos);
    CHECK(missing.error.find("cell.toml:") == 0U);

    // The test configuration with a recorded sensor loads.
    const ConfigLoad file = load_monitor_config(CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd-cell.toml");
    CAPTURE(file.error);
    REQUIRE(file.ok);
    CHECK(file.config.sensors.size() == 5U);
    CHECK(file.config.sensors[4].pcd_files.size() == 6U);
}
