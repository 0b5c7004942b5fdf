// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the real cell of issue 18 (apps/monitor/config/real-cell.toml):
// the monitor's [fusion] table (method, footprint fusion's limits, threads;
// refusals), the simulator's culled rendering with rays computed once (the
// same images, bit for bit, as casting every object for every pixel), and
// the monitor's start-up with footprint fusion (no ray tables, one workspace
// per sensor, the controller configured for it).
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/safety/cycle.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

std::string real_cell_path() { return std::string(CELLGUARD_SOURCE_DIR) + "/apps/monitor/config/real-cell.toml"; }

/// The paper-cell demo text with @p fusion appended.
ConfigLoad with_fusion(const std::string& fusion) {
    return parse_monitor_config(std::string(demo_config_text()) + "\n[fusion]\n" + fusion + "\n", "cell.toml");
}

/// The renderer before culling: every object cast for every pixel (scene.cast()).
std::vector<float> render_every_object(const sim::SensorSpec& sensor, const sim::PreparedScene& scene) {
    const PinholeIntrinsics k = sensor.intrinsics();
    const Eigen::Isometry3d pose = sensor.pose();
    std::vector<float> depth(static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height), 0.0F);
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u) {
            const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
            const Eigen::Vector3d dir = (pose.linear() * ray_cam).normalized();
            const double t = scene.cast(pose.translation(), dir).distance;
            if (std::isfinite(t) && t <= static_cast<double>(sensor.max_range)) {
                depth[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) + static_cast<std::size_t>(u)] =
                    static_cast<float>(t / ray_cam.norm());
            }
        }
    }
    return depth;
}

/// Pixels where @p a and @p b differ in their bits; @p b_hits counts b's readings.
std::size_t differing_pixels(const std::vector<float>& a, const std::vector<float>& b, std::size_t& b_hits) {
    std::size_t n = 0U;
    b_hits = 0U;
    for (std::size_t i = 0U; i < a.size(); ++i) {
        n += std::memcmp(&a[i], &b[i], sizeof(float)) != 0 ? 1U : 0U;
        b_hits += b[i] > 0.0F ? 1U : 0U;
    }
    return n;
}

/// A scene that tests the culling: the reference boxes, the person, a yawed
/// box, a box partly behind the image plane of the camera at @p camera, and robot capsules.
sim::Scene culling_scene(const Eigen::Vector3d& camera) {
    sim::Scene scene = sim::reference_scene();
    scene.boxes.push_back(person_box(demo_person(15)));
    scene.boxes.push_back(sim::Box{{1.5, 1.2, 1.8}, {0.8, 0.2, 1.4}, 0.7, false});
    // Just above a camera, partly behind its image plane: not culled, never met.
    scene.boxes.push_back(sim::Box{camera + Eigen::Vector3d(0.0, 0.0, 0.03), {0.3, 0.3, 0.02}, 0.0, false});
    scene.robot.count = 2U;
    scene.robot.capsules[0] = PlacedCapsule{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.9}, 0.12, 0U};
    scene.robot.capsules[1] = PlacedCapsule{{0.0, 0.0, 0.9}, {0.6, -0.4, 1.3}, 0.08, 1U};
    return scene;
}

}  // namespace

// verifies: SR-CFG-001
TEST_CASE("real cell: real-cell.toml loads: four 640 x 480 cameras, the whole cell in 5 cm voxels, footprint fusion") {
    const ConfigLoad load = load_monitor_config(real_cell_path());
    REQUIRE_MESSAGE(load.ok, load.error);
    const MonitorConfig& c = load.config;
    CHECK(c.grid.dims[0] == 80);
    CHECK(c.grid.dims[1] == 80);
    CHECK(c.grid.dims[2] == 50);
    CHECK(c.grid.voxel_size == doctest::Approx(0.05));
    REQUIRE(c.sensors.size() == 4U);
    for (const SensorSettings& s : c.sensors) {
        CHECK(s.width == 640);
        CHECK(s.height == 480);
        CHECK(s.hfov_deg == doctest::Approx(58.0));
        CHECK(s.vfov_deg == doctest::Approx(45.0));
        CHECK(std::fabs(s.position.x()) == doctest::Approx(1.95));  // a corner of the 4 m x 4 m cell
        CHECK(std::fabs(s.position.y()) == doctest::Approx(1.95));
    }
    CHECK(c.fusion.method == FusionMethod::kFootprint);
    CHECK(c.fusion.threads == 1);
    CHECK(c.period_us == 33333U);
    CHECK(c.background_match > 0.0F);
}

// verifies: SR-CFG-001
TEST_CASE("real cell: the fusion table is optional and ray by default, footprint takes its limit and threads") {
    CHECK(demo_config().fusion.method == FusionMethod::kRay);
    CHECK(robot_cell_demo_config().fusion.method == FusionMethod::kRay);
    const ConfigLoad ray = with_fusion("method = \"ray\"");
    REQUIRE_MESSAGE(ray.ok, ray.error);
    CHECK(ray.config.fusion.method == FusionMethod::kRay);
    const ConfigLoad fp = with_fusion("method = \"footprint\"\nexact_footprint_max = 16\nthreads = 4");
    REQUIRE_MESSAGE(fp.ok, fp.error);
    CHECK(fp.config.fusion.method == FusionMethod::kFootprint);
    CHECK(fp.config.fusion.params.exact_footprint_max == 16U);
    CHECK(fp.config.fusion.threads == 4);
    const ConfigLoad defaults = with_fusion("method = \"footprint\"");
    REQUIRE(defaults.ok);
    CHECK(defaults.config.fusion.params.exact_footprint_max == FootprintParams{}.exact_footprint_max);
    CHECK(defaults.config.fusion.threads == 1);
}

// verifies: SR-CFG-001
TEST_CASE("real cell: the fusion table refuses bad values and unknown keys, naming the key") {
    struct Case {
        const char* text;
        const char* message;
    };
    const Case cases[] = {
        {"method = \"octree\"", R"(fusion.method: expected "ray" or "footprint", got "octree")"},
        {"method = \"footprint\"\nthreads = 0", "fusion.threads"},
        {"method = \"footprint\"\nthreads = 65", "fusion.threads"},
        {"method = \"footprint\"\nthreads = 1.5", "fusion.threads"},
        {"method = \"footprint\"\nexact_footprint_max = -1", "fusion.exact_footprint_max"},
        {"method = \"footprint\"\nexact_footprint_max = 65537", "fusion.exact_footprint_max"},
        {"exact_footprint_max = 10", R"(fusion.exact_footprint_max: applies only to method = "footprint")"},
        // The per-frame budget is gone: a file that sets it is told so.
        {"method = \"footprint\"\nexact_pixel_budget = 200000", "fusion.exact_pixel_budget: no longer exists"},
        {"method = \"footprint\"\nthread = 2", "thread"},
        {"method = \"ray\"\nthreads = 2", R"(fusion.threads: applies only to method = "footprint")"},
    };
    for (const Case& k : cases) {
        CAPTURE(k.text);
        const ConfigLoad load = with_fusion(k.text);
        CHECK_FALSE(load.ok);
        CHECK_MESSAGE(load.error.find(k.message) != std::string::npos, load.error);
        CHECK(load.error.rfind("cell.toml:", 0) == 0);
    }
}

// verifies: SR-SIM-001
TEST_CASE("real cell: culled rendering with rays computed once gives every object's cast, bit for bit") {
    const ConfigLoad load = load_monitor_config(real_cell_path());
    REQUIRE(load.ok);
    std::vector<sim::SensorSpec> sensors;
    for (const SensorSettings& s : load.config.sensors) {
        std::string error;
        sensors.push_back(monitor::to_spec(s, true, error));
        REQUIRE(error.empty());
    }
    for (const sim::SensorSpec& p : sim::paper_sensors()) {
        sensors.push_back(p);
    }
    for (const sim::SensorSpec& sensor : sensors) {
        CAPTURE(sensor.name);
        const sim::PreparedScene scene(culling_scene(sensors[0].position));
        const sim::SensorRays rays(sensor);
        const std::vector<float> expected = render_every_object(sensor, scene);
        std::vector<float> culled(expected.size());
        std::vector<float> precomputed(expected.size());
        REQUIRE(sim::render_depth_into(sensor, scene, {culled.data(), culled.size()}));
        REQUIRE(sim::render_depth_into(rays, scene, {precomputed.data(), precomputed.size()}));
        std::size_t hits = 0U;
        CHECK(differing_pixels(expected, culled, hits) == 0U);
        CHECK(differing_pixels(expected, precomputed, hits) == 0U);
        CHECK(hits > expected.size() / 2U);  // the scene is in view
        std::vector<float> small(3U);
        CHECK_FALSE(sim::render_depth_into(rays, scene, {small.data(), small.size()}));
    }
}

// verifies: SR-SYS-001
TEST_CASE("real cell: with footprint fusion the start-up builds no ray table, one workspace per sensor") {
    ConfigLoad load = with_fusion("method = \"footprint\"\nexact_footprint_max = 5");
    REQUIRE(load.ok);
    monitor::MonitorCell cell;
    REQUIRE_FALSE(cell.configure(load.config).failed());
    REQUIRE_FALSE(cell.build_prior(load.config, nullptr).failed());
    REQUIRE_FALSE(cell.build_tables(load.config, nullptr).failed());
    REQUIRE(cell.footprint_spaces.size() == 4U);
    for (std::size_t s = 0U; s < 4U; ++s) {
        CHECK(cell.tables[s].storage_bytes() == 0U);
        CHECK(cell.footprint_spaces[s].opinions.size() == cell.grid.voxel_count());
        // Every workspace holds the largest image's pyramid (the stereo cameras' 320 x 240).
        CHECK(cell.footprint_spaces[s].pyramid_min.size() == depth_pyramid_cells(320, 240));
    }
    // The work bound counts footprint fusion instead of the depth images' rays.
    const CycleWorkBound ray = compute_work_bound(cell.grid, {cell.layout.readings.data(), cell.layout.readings.size()},
                                                  cell.zones);
    CHECK(cell.work.footprint_units > 0U);
    CHECK(cell.work.voxel_steps < ray.voxel_steps);
    ControllerConfig cc = monitor::controller_config(load.config);
    monitor::attach_fusion(cc, load.config, cell, nullptr);
    CHECK(cc.footprint.method == FusionMethod::kFootprint);
    CHECK(cc.footprint.params.exact_footprint_max == 5U);
    CHECK(cc.footprint.workspaces.size() == 4U);
    CHECK(cc.footprint.runner == nullptr);
    // The ray method: tables, no workspaces, the controller left on kRay.
    monitor::MonitorCell ray_cell;
    const MonitorConfig paper = demo_config();
    REQUIRE_FALSE(ray_cell.configure(paper).failed());
    REQUIRE_FALSE(ray_cell.build_prior(paper, nullptr).failed());
    REQUIRE_FALSE(ray_cell.build_tables(paper, nullptr).failed());
    CHECK(ray_cell.footprint_spaces.empty());
    CHECK(ray_cell.tables[0].storage_bytes() > 0U);
    ControllerConfig rc = monitor::controller_config(paper);
    monitor::attach_fusion(rc, paper, ray_cell, nullptr);
    CHECK(rc.footprint.method == FusionMethod::kRay);
    CHECK(rc.footprint.workspaces.empty());
}

// verifies: SR-SIM-001, SR-SYS-001
TEST_CASE("real cell: a background cast once plus moving objects gives the whole scene's image, bit for bit") {
    const ConfigLoad load = load_monitor_config(real_cell_path());
    REQUIRE(load.ok);
    std::string error;
    const sim::SensorSpec real = monitor::to_spec(load.config.sensors[2], true, error);
    REQUIRE(error.empty());
    for (const sim::SensorSpec& sensor : {real, sim::paper_sensors()[3]}) {
        CAPTURE(sensor.name);
        const sim::BackgroundView view(sensor, sim::reference_scene());
        // The demo's frame source: the reference scene and the person, cycle by cycle.
        SimulatedFrameSource source(sensor, FrameDither::kOff);
        std::size_t changed = 0U;
        for (int k = 0; k <= 50; k += 5) {
            CAPTURE(k);
            sim::Scene whole = sim::reference_scene();
            whole.boxes.push_back(person_box(demo_person(k)));
            const sim::SimulatedFrame expected = sim::render_frame({sensor}, whole);
            SensorReading reading;
            FrameStatus status;
            REQUIRE(source.load_frame(static_cast<std::uint64_t>(k), reading, status));
            std::vector<float> got(reading.depth.begin(), reading.depth.end());
            std::size_t hits = 0U;
            CHECK(differing_pixels(expected.depth[0], got, hits) == 0U);
            // The person changes the image (so the moving pass did something).
            std::vector<float> empty(got.size());
            sim::Scene nobody;
            nobody.floor = false;
            REQUIRE(view.render_into(sim::PreparedScene(nobody), {empty.data(), empty.size()}));
            changed += differing_pixels(empty, got, hits);
        }
        CHECK(changed > 100U);
        // Moving boxes and capsules, one partly behind the image plane, the floor flag ignored.
        sim::Scene moving = culling_scene(sensor.position);
        moving.boxes.erase(moving.boxes.begin(), moving.boxes.begin() + 2);  // the reference boxes are the background
        sim::Scene whole = culling_scene(sensor.position);
        for (const bool floor : {true, false}) {
            moving.floor = floor;
            std::vector<float> got(static_cast<std::size_t>(sensor.width) * static_cast<std::size_t>(sensor.height));
            REQUIRE(view.render_into(sim::PreparedScene(moving), {got.data(), got.size()}));
            std::size_t hits = 0U;
            CHECK(differing_pixels(render_every_object(sensor, sim::PreparedScene(whole)), got, hits) == 0U);
        }
        std::vector<float> small(3U);
        CHECK_FALSE(view.render_into(sim::PreparedScene(moving), {small.data(), small.size()}));
    }
}
