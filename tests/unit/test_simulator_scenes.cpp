// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The workcell simulator's additions for the paper's experiments: prepared
// ray casting, the noise models, scene files, the walking person and the
// ideal ground truth (apps/simulator).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "cellguard/host/sim/ground_truth.hpp"
#include "cellguard/host/sim/noise.hpp"
#include "cellguard/host/sim/scene_file.hpp"

using namespace cellguard;

namespace {

/// A sensor at (0, 0, 1) looking along +x at a wall whose face is at x = @p distance.
struct WallSetup {
    sim::SensorSpec sensor;
    sim::Scene scene;
    explicit WallSetup(double distance) {
        sensor = sim::SensorSpec{"test", {0.0, 0.0, 1.0}, {1.0, 0.0, 1.0}, 176, 144, 43.6, 34.6, 10.0F};
        scene.floor = false;
        scene.boxes.push_back(sim::Box{{distance + 0.5, 0.0, 1.0}, {1.0, 20.0, 20.0}, 0.0, true});
    }
};

/// Standard deviation of noisy - ideal depth over pixels with both readings, and the share of missing pixels.
struct ErrorStats {
    double sigma = 0.0;
    double missing = 0.0;
};

ErrorStats depth_error(const WallSetup& w, const sim::NoiseModel& model, std::uint64_t seed) {
    std::vector<float> ideal;
    sim::render_depth(w.sensor, w.scene, ideal);
    std::vector<float> noisy = ideal;
    sim::Rng rng(seed);
    sim::apply_noise(w.sensor, model, noisy, rng);
    double sum = 0.0;
    double sum2 = 0.0;
    std::size_t n = 0U;
    std::size_t missing = 0U;
    for (std::size_t i = 0; i < ideal.size(); ++i) {
        if (noisy[i] == 0.0F) {
            ++missing;
            continue;
        }
        const double e = static_cast<double>(noisy[i]) - static_cast<double>(ideal[i]);
        sum += e;
        sum2 += e * e;
        ++n;
    }
    ErrorStats s;
    const double mean = sum / static_cast<double>(n);
    s.sigma = std::sqrt(sum2 / static_cast<double>(n) - mean * mean);
    s.missing = static_cast<double>(missing) / static_cast<double>(ideal.size());
    return s;
}

}  // namespace

// verifies: SR-EVAL-001
TEST_CASE("simulator: a prepared scene casts the same distances and renders the same images as the plain one") {
    const sim::Scene scene = sim::reference_scene();
    const sim::PreparedScene prepared(scene);
    for (const sim::SensorSpec& s : sim::paper_sensors()) {
        std::vector<float> a;
        std::vector<float> b;
        sim::render_depth(s, scene, a);
        sim::render_depth(s, prepared, b);
        CHECK(a == b);
    }
    const Eigen::Vector3d origin(1.9, -1.9, 1.9);
    const Eigen::Vector3d dir = (Eigen::Vector3d(0.4, -0.25, 0.2) - origin).normalized();
    const sim::RayHit hit = sim::cast_ray_hit(scene, origin, dir);
    CHECK(hit.distance == sim::cast_ray(scene, origin, dir));
    CHECK(hit.box == 1);
    CHECK(prepared.cast(origin, dir).distance == hit.distance);
    CHECK(sim::cast_ray_hit(scene, origin, Eigen::Vector3d(0.0, 0.0, -1.0)).box == -1);  // the floor
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: noisy frames are deterministic for a seed, and ideal models change nothing") {
    const std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const sim::Scene scene = sim::reference_scene();
    const sim::SimulatedFrame a = sim::render_noisy_frame(sensors, sim::paper_noise_models(), scene, 7U);
    const sim::SimulatedFrame b = sim::render_noisy_frame(sensors, sim::paper_noise_models(), scene, 7U);
    const sim::SimulatedFrame c = sim::render_noisy_frame(sensors, sim::paper_noise_models(), scene, 8U);
    const sim::SimulatedFrame ideal = sim::render_frame(sensors, scene);
    const sim::SimulatedFrame ideal_models = sim::render_noisy_frame(sensors, {}, scene, 7U);
    REQUIRE(a.depth.size() == 4U);
    for (std::size_t i = 0; i < 4U; ++i) {
        CHECK(a.depth[i] == b.depth[i]);
        CHECK(a.depth[i] != c.depth[i]);
        CHECK(a.depth[i] != ideal.depth[i]);
        CHECK(ideal_models.depth[i] == ideal.depth[i]);
    }
    CHECK(sim::sensor_seed(1U, 0U) != sim::sensor_seed(1U, 1U));
    sim::Rng r1(3U);
    sim::Rng r2(3U);
    for (int i = 0; i < 10; ++i) {
        CHECK(r1.normal() == r2.normal());
    }
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: flash-lidar range noise follows sigma = base + per_m * range") {
    sim::NoiseModel m;
    m.kind = sim::SensorKind::kFlashLidar;
    m.lidar.mixed_pixel_probability = 0.0;
    // Depth error = range error / ray scale; the ray scale is at most 1.11
    // over this field of view, so the depth sigma lies between the range
    // sigma at the centre's range and 1/1.11 of the range sigma at the rim.
    for (const double d : {1.5, 3.0, 6.0}) {
        const ErrorStats s = depth_error(WallSetup(d), m, 11U);
        const double at_centre = m.lidar.range_sigma_base_m + m.lidar.range_sigma_per_m * d;
        MESSAGE("wall at " << d << " m: depth sigma " << s.sigma << ", model at the centre " << at_centre);
        CHECK(s.sigma > 0.95 * at_centre);
        CHECK(s.sigma < 1.12 * at_centre);
        CHECK(s.missing == 0.0);
    }
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: stereo depth noise grows with the square of depth, and pixels go missing at the set rate") {
    sim::NoiseModel m;
    m.kind = sim::SensorKind::kStereo;
    const WallSetup near(1.5);
    const WallSetup far(3.0);
    const ErrorStats a = depth_error(near, m, 5U);
    const ErrorStats b = depth_error(far, m, 5U);
    const double fb = near.sensor.intrinsics().fx * m.stereo.baseline_m;
    const double sigma_d = std::sqrt(m.stereo.disparity_sigma_px * m.stereo.disparity_sigma_px +
                                     m.stereo.disparity_quantum_px * m.stereo.disparity_quantum_px / 12.0);
    MESSAGE("stereo depth sigma " << a.sigma << " at 1.5 m, " << b.sigma << " at 3 m; missing " << a.missing << ", "
                                  << b.missing);
    CHECK(a.sigma == doctest::Approx(1.5 * 1.5 * sigma_d / fb).epsilon(0.1));
    CHECK(b.sigma == doctest::Approx(3.0 * 3.0 * sigma_d / fb).epsilon(0.1));
    CHECK(b.sigma / a.sigma == doctest::Approx(4.0).epsilon(0.15));
    // No depth edges on the wall: only the random dropout.
    CHECK(a.missing == doctest::Approx(m.stereo.missing_probability).epsilon(0.15));
    CHECK(b.missing == doctest::Approx(m.stereo.missing_probability).epsilon(0.15));
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: flash-lidar mixed pixels fall between the two surfaces of a depth edge") {
    WallSetup w(3.0);
    w.scene.boxes.push_back(sim::Box{{1.5, 0.0, 1.0}, {0.2, 0.4, 0.4}, 0.0, true});  // a block in front
    sim::NoiseModel m;
    m.kind = sim::SensorKind::kFlashLidar;
    m.lidar.range_sigma_base_m = 0.0;
    m.lidar.range_sigma_per_m = 0.0;
    m.lidar.mixed_pixel_probability = 1.0;
    std::vector<float> ideal;
    sim::render_depth(w.sensor, w.scene, ideal);
    std::vector<float> noisy = ideal;
    sim::Rng rng(1U);
    sim::apply_noise(w.sensor, m, noisy, rng);
    std::size_t between = 0U;
    for (std::size_t i = 0; i < ideal.size(); ++i) {
        if (noisy[i] > 1.45F && noisy[i] < 2.95F) {
            ++between;
        }
    }
    MESSAGE(between << " mixed pixels between 1.4 m and 3 m");
    CHECK(between > 20U);
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: scene files give boxes, sensors, noise and people, and name the first error's place") {
    const std::string text = R"(
name = "t"
seed = 5
[[sensor]]
name = "s"
kind = "stereo"
position = [1.0, 1.0, 2.0]
target = [0.0, 0.0, 0.0]
width = 64
height = 48
focal_px = 50.0
[sensor.noise]
baseline_m = 0.1
[[box]]
center = [0.0, 0.0, 0.5]
size = [1, 1, 1]
yaw_deg = 90
role = "foreground"
[[person]]
path = [[0.0, 0.0], [1.0, 0.0]]
)";
    const sim::SceneLoad l = sim::parse_scene(text, "t.toml");
    REQUIRE_MESSAGE(l.ok, l.error);
    CHECK(l.scene.name == "t");
    CHECK(l.scene.seed == 5U);
    REQUIRE(l.scene.sensors.size() == 1U);
    CHECK(l.scene.sensors[0].intrinsics().fx == doctest::Approx(50.0));
    CHECK(l.scene.noise[0].kind == sim::SensorKind::kStereo);
    CHECK(l.scene.noise[0].stereo.baseline_m == 0.1);
    REQUIRE(l.scene.scene.boxes.size() == 1U);
    CHECK_FALSE(l.scene.scene.boxes[0].background);
    CHECK(l.scene.scene.boxes[0].yaw == doctest::Approx(1.5707963));
    CHECK(l.scene.people.size() == 1U);
    CHECK(sim::scene_at(l.scene, 0.0).boxes.size() == 9U);
    CHECK(sim::background_of(sim::scene_at(l.scene, 0.0)).boxes.empty());

    const sim::SceneLoad defaults = sim::parse_scene("name = \"d\"\n", "d.toml");
    REQUIRE(defaults.ok);
    CHECK(defaults.scene.sensors.size() == 4U);  // the paper's sensors
    CHECK(defaults.scene.noise[0].kind == sim::SensorKind::kFlashLidar);
    CHECK(defaults.scene.noise[2].kind == sim::SensorKind::kStereo);

    const sim::SceneLoad bad_key = sim::parse_scene(
        "[[box]]\ncenter = [0,0,0]\nsize = [1,1,1]\nrole = \"background\"\ncolour = 1\n", "b.toml");
    CHECK_FALSE(bad_key.ok);
    CHECK(bad_key.error.find("b.toml:5") != std::string::npos);
    CHECK(bad_key.error.find("unknown key") != std::string::npos);
    CHECK_FALSE(sim::parse_scene("[[box]]\ncenter = [0,0,0]\nsize = [1,1,1]\nrole = \"wall\"\n", "r.toml").ok);
    CHECK_FALSE(sim::parse_scene("[[box]]\ncenter = [0,0]\nsize = [1,1,1]\nrole = \"background\"\n", "c.toml").ok);
    CHECK_FALSE(sim::parse_scene("seed = [\n", "s.toml").ok);
    CHECK_FALSE(sim::load_scene_file("/nonexistent/scene.toml").ok);
}

// verifies: SR-EVAL-001
TEST_CASE("simulator: the person walks along the path at its speed and stops at its end") {
    sim::PersonSpec p;
    p.height_m = 1.8;
    p.speed_mps = 0.5;
    p.path = {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 1.0)};
    const auto centre = [](const std::vector<sim::Box>& boxes) { return boxes[2].center; };  // the torso
    const std::vector<sim::Box> at0 = sim::person_boxes(p, 0.0);
    REQUIRE(at0.size() == 8U);
    double top = 0.0;
    for (const sim::Box& b : at0) {
        CHECK_FALSE(b.background);
        CHECK(b.center.z() - 0.5 * b.size.z() >= -1e-12);
        top = std::fmax(top, b.center.z() + 0.5 * b.size.z());
    }
    CHECK(top == doctest::Approx(1.8));
    CHECK(centre(at0).x() == doctest::Approx(0.0));
    CHECK(centre(sim::person_boxes(p, 1.0)).x() == doctest::Approx(0.5));
    const Eigen::Vector3d turned = centre(sim::person_boxes(p, 3.0));  // 1.5 m: half way up the second leg
    CHECK(turned.x() == doctest::Approx(1.0));
    CHECK(turned.y() == doctest::Approx(0.5));
    CHECK(sim::person_boxes(p, 3.0)[2].yaw == doctest::Approx(1.5707963));
    const Eigen::Vector3d end = centre(sim::person_boxes(p, 100.0));
    CHECK(end.x() == doctest::Approx(1.0));
    CHECK(end.y() == doctest::Approx(1.0));
}

// verifies: SR-EVAL-001
TEST_CASE(
    "simulator: the ideal ground truth labels the visible surface of a foreground box foreground and its "
    "hidden interior unknown") {
    const GridGeometry g = paper_grid_geometry();
    sim::Scene scene = sim::reference_scene();
    const sim::Box fg{{0.33, 0.43, 0.235}, {0.4, 0.35, 0.47}, 0.0, false};
    scene.boxes.push_back(fg);
    const sim::GroundTruth t = sim::ideal_ground_truth(g, sim::paper_sensors(), scene);
    CHECK(t.foreground + t.not_foreground + t.unknown == g.voxel_count());
    CHECK(t.foreground > 100U);
    CHECK(t.unknown > 100U);
    // The box's centre voxel is unknown; every foreground voxel touches the box.
    const VoxelCoord centre = g.world_to_voxel(fg.center).value();
    CHECK(t.label[g.index_of(centre)] == sim::Truth::kUnknown);
    for (std::size_t i = 0; i < t.label.size(); ++i) {
        if (t.label[i] == sim::Truth::kForeground) {
            const Eigen::Vector3d c = g.voxel_center(g.coord_of(i));
            const Eigen::Vector3d d = (c - fg.center).cwiseAbs() - 0.5 * fg.size;
            CHECK(d.maxCoeff() <= 0.5 * g.voxel_size() + 1e-9);
        }
    }
    // Without foreground nothing is foreground or unknown; the interior mask
    // finds the background boxes' inside.
    const sim::GroundTruth empty = sim::ideal_ground_truth(g, sim::paper_sensors(), sim::reference_scene());
    CHECK(empty.foreground == 0U);
    CHECK(empty.unknown == 0U);
    const std::vector<std::uint8_t> inside = sim::background_interior_mask(g, sim::reference_scene());
    CHECK(inside[g.index_of(g.world_to_voxel(Eigen::Vector3d(-0.35, 0.2, 0.3)).value())] == 1U);
    CHECK(inside[g.index_of(g.world_to_voxel(Eigen::Vector3d(0.0, 0.6, 0.3)).value())] == 0U);
}

// verifies: SR-EVAL-002
TEST_CASE("simulator: precision-recall sweep counts exactly from the histograms") {
    sim::ScoreHistogram h;
    std::vector<std::int16_t> sub = {1000, -1000, 0, kNeverForeground, 500};
    sim::GroundTruth t;
    t.label = {sim::Truth::kForeground, sim::Truth::kForeground, sim::Truth::kNotForeground, sim::Truth::kNotForeground,
               sim::Truth::kUnknown};
    sim::add_scores(h, sub, t);
    const std::vector<sim::PrPoint> c = sim::pr_curve(h, {0.001, 0.5, 0.9});
    CHECK(c[0].tp == 2U);  // -1000 units = -3.9 nats, P 0.02 >= 0.001
    CHECK(c[0].fp == 1U);  // 0 counts, the sentinel never does
    CHECK(c[1].tp == 1U);
    CHECK(c[1].fp == 1U);  // 0 units is P 0.5
    CHECK(c[2].tp == 1U);  // 1000 units = P 0.98
    CHECK(c[2].fp == 0U);
    CHECK(c[2].precision == 1.0);
    CHECK(c[2].recall == 0.5);
    const sim::PrSummary s = sim::summarize(c);
    CHECK(s.max_recall == 1.0);
    CHECK(s.recall_at_precision_90 == 0.5);
    CHECK(s.precision_at_recall_90 == doctest::Approx(2.0 / 3.0));
}

// verifies: SR-EVAL-002
TEST_CASE("simulator: the fine sweep adds a threshold where recall passes each step, and counts as the plain sweep") {
    // 400 foreground scores, two on each value from 0 to 199 units (P 0.5 to 0.68), and 100 not-foreground
    // ones: the default sweep's 0.01 steps give few recall values where the scores crowd.
    sim::ScoreHistogram h;
    std::vector<std::int16_t> sub;
    sim::GroundTruth t;
    for (int i = 0; i < 400; ++i) {
        sub.push_back(static_cast<std::int16_t>(i / 2));
        t.label.push_back(sim::Truth::kForeground);
    }
    for (int i = 0; i < 100; ++i) {
        sub.push_back(static_cast<std::int16_t>(3 * i - 100));
        t.label.push_back(sim::Truth::kNotForeground);
    }
    sim::add_scores(h, sub, t);
    const std::vector<sim::PrPoint> plain = sim::pr_curve(h, sim::default_thresholds());
    const std::vector<sim::PrPoint> fine = sim::fine_pr_curve(h, 200);
    MESSAGE("distinct recalls: plain " << sim::distinct_recalls(plain) << ", fine " << sim::distinct_recalls(fine));
    CHECK(sim::distinct_recalls(plain) < 30U);
    CHECK(sim::distinct_recalls(fine) >= 200U);  // each 1/200 step of recall is 2 scores: one value
    // Every default threshold is on the fine curve with the same counts; t_f ascends.
    for (const sim::PrPoint& p : plain) {
        const auto same = std::find_if(fine.begin(), fine.end(), [&](const sim::PrPoint& q) { return q.t_f == p.t_f; });
        REQUIRE(same != fine.end());
        CHECK(same->tp == p.tp);
        CHECK(same->fp == p.fp);
    }
    for (std::size_t i = 1; i < fine.size(); ++i) {
        CHECK(fine[i - 1].t_f < fine[i].t_f);
    }
    // Every point counts the scores whose probability is at least its t_f, recounted here from the scores.
    for (const sim::PrPoint& p : fine) {
        std::uint64_t tp = 0U;
        std::uint64_t fp = 0U;
        for (std::size_t i = 0; i < sub.size(); ++i) {
            const bool called = probability_from_log_odds(sub[i]) >= p.t_f;
            tp += called && t.label[i] == sim::Truth::kForeground ? 1U : 0U;
            fp += called && t.label[i] == sim::Truth::kNotForeground ? 1U : 0U;
        }
        CHECK_MESSAGE(p.tp == tp, "t_f " << p.t_f);
        CHECK_MESSAGE(p.fp == fp, "t_f " << p.t_f);
    }
    // No foreground scores: the default sweep alone.
    CHECK(sim::fine_pr_curve(sim::ScoreHistogram{}, 200).size() == plain.size());
}

// verifies: SR-EVAL-001, SR-EVAL-004
TEST_CASE(
    "simulator: the time-of-flight camera's noise: 1 % of range, dropouts at the set rate, caller storage alike") {
    const sim::NoiseModel tof = sim::tof_camera_noise();
    CHECK(tof.kind == sim::SensorKind::kFlashLidar);
    CHECK(tof.lidar.range_sigma_base_m == 0.0);
    CHECK(tof.lidar.range_sigma_per_m == 0.01);
    CHECK(tof.lidar.missing_probability == 0.01);
    const WallSetup wall(3.0);
    const ErrorStats s = depth_error(wall, tof, 5U);
    MESSAGE("wall at 3 m: depth sigma " << s.sigma << ", missing " << s.missing);
    CHECK(s.sigma > 0.95 * 0.03);
    CHECK(s.sigma < 1.12 * 0.03);
    CHECK(s.missing > 0.008);
    CHECK(s.missing < 0.012);
    // The caller-storage form gives the vector form's image bit for bit, and refuses a wrong size.
    std::vector<float> ideal;
    sim::render_depth(wall.sensor, wall.scene, ideal);
    std::vector<float> a = ideal;
    std::vector<float> b = ideal;
    std::vector<float> scratch(ideal.size());
    sim::Rng ra(9U);
    sim::Rng rb(9U);
    sim::apply_noise(wall.sensor, tof, a, ra);
    REQUIRE(sim::apply_noise(wall.sensor, tof, {b.data(), b.size()}, {scratch.data(), scratch.size()}, rb));
    CHECK(a == b);
    CHECK_FALSE(sim::apply_noise(wall.sensor, tof, {b.data(), b.size() - 1U}, {scratch.data(), scratch.size()}, rb));
    // Without dropouts the SR4000 model draws the numbers it drew before the field existed.
    sim::NoiseModel lidar;
    lidar.kind = sim::SensorKind::kFlashLidar;
    sim::NoiseModel lidar_drop = lidar;
    lidar_drop.lidar.missing_probability = 1e-300;  // on, but never taken
    std::vector<float> c = ideal;
    std::vector<float> d = ideal;
    sim::Rng rc(4U);
    sim::Rng rd(4U);
    sim::apply_noise(wall.sensor, lidar, c, rc);
    sim::apply_noise(wall.sensor, lidar_drop, d, rd);
    CHECK(c != d);  // one more draw per pixel shifts the sequence
    CHECK(std::count(c.begin(), c.end(), 0.0F) == 0);
}
