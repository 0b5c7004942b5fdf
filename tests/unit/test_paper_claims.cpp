// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The paper's claims (section V) as tests that can fail, on the simulated
// workcell of apps/evaluation: the scene files apps/evaluation/scenes/*.toml
// (the paper's four sensors with noise, a 6 m room around the frame), the
// paper's parameters (r = 10 cm, t_B = 0.51, t_E = 0.1, 3D Bresenham) with
// cellguard's sensor model (one opinion per sensor, voxel and frame: p_hit
// 0.90, p_miss 0.30, pooled within [0.12, 0.97]; sensor_model.hpp), the
// ideal 0-1 ground truth (sim/ground_truth.hpp).
//
// Fewer frames than the evaluation, to keep each test case at a few seconds:
// G_B from 20 empty frames (cellguard-eval: 100) and one frame with the
// foreground (cellguard-eval: 5). Every threshold below was set from what
// these tests measure (values in the comments, 2026-11-25) with a margin;
// cellguard-eval's fuller run gives the README's table.
#include <doctest/doctest.h>

#include <string>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "test_tags.hpp"

using namespace cellguard;

namespace {

constexpr int kBackgroundFrames = 20;
constexpr int kForegroundFrames = 1;

std::string scene_path(const char* name) {
    return std::string(CELLGUARD_SOURCE_DIR) + "/apps/evaluation/scenes/" + name + ".toml";
}

sim::ExperimentConfig config() {
    sim::ExperimentConfig cfg;  // the paper's parameters and rasterisation
    cfg.background_frames = kBackgroundFrames;
    cfg.foreground_frames = kForegroundFrames;
    return cfg;
}

/// G_B of background.toml, built once per process.
const sim::OwnedGrid& shared_background() {
    static const sim::OwnedGrid grid = [] {
        const sim::SceneLoad load = sim::load_scene_file(scene_path("background"));
        REQUIRE_MESSAGE(load.ok, load.error);
        sim::OwnedGrid g(config().geometry);
        REQUIRE(sim::build_background(load.scene, config(), g.grid));
        return g;
    }();
    return grid;
}

/// Runs scene @p name against the shared G_B.
void run(const char* name, sim::SceneResult& out) {
    const sim::SceneLoad load = sim::load_scene_file(scene_path(name));
    REQUIRE_MESSAGE(load.ok, load.error);
    std::string error;
    REQUIRE_MESSAGE(sim::run_scene(load.scene, config(), out, error, &shared_background().grid), error);
}

const sim::MethodResult& method(const sim::SceneResult& r, PriorMethod m) {
    for (const sim::MethodResult& x : r.methods) {
        if (x.method == m) {
            return x;
        }
    }
    FAIL("method missing");
    return r.methods[0];
}

/// The point of the curve at t_f (the sweep holds 0.01 steps).
const sim::PrPoint& at(const sim::MethodResult& m, double t_f) {
    for (const sim::PrPoint& p : m.curve) {
        if (std::fabs(p.t_f - t_f) < 1e-9) {
            return p;
        }
    }
    FAIL("t_f not in the sweep");
    return m.curve[0];
}

/// Largest precision with recall >= @p recall; 0 when the curve never gets there.
double precision_at(const sim::MethodResult& m, double recall) {
    const double p = sim::precision_at_recall(m.curve, recall);
    return p < 0.0 ? 0.0 : p;
}

/// Voxels wholly inside the background boxes of @p r, at least @p margin
/// metres under their surfaces.
std::vector<std::uint8_t> interior(const sim::SceneResult& r, double margin) {
    return sim::background_interior_mask(r.background_grid.grid.geometry(), r.background, margin);
}

/// Voxels of @p mask, and how many of them the last frame calls foreground at @p t_f.
struct InteriorCount {
    std::size_t interior = 0U;
    std::size_t foreground = 0U;
};

InteriorCount count_foreground(const std::vector<std::uint8_t>& mask, const sim::MethodResult& m, double t_f) {
    const std::int16_t threshold = threshold_log_odds(t_f);
    InteriorCount c;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] == 0U) {
            continue;
        }
        ++c.interior;
        const std::int16_t v = m.last_subtracted[i];
        c.foreground += (v != kNeverForeground && v >= threshold) ? 1U : 0U;
    }
    return c;
}

}  // namespace

// verifies: SR-EVAL-002
TEST_CASE(
    "paper claim 1: on the large object both methods score well and beat their baselines, which keep the "
    "interiors of background boxes below t_f = 0.5" *
    CELLGUARD_LONG_REPLAY) {
    sim::SceneResult r(config().geometry);
    run("large", r);
    const sim::MethodResult& thr = method(r, PriorMethod::kThresholded);
    const sim::MethodResult& pro = method(r, PriorMethod::kProbabilistic);
    const sim::MethodResult& thr_base = method(r, PriorMethod::kThresholdedBaseline);
    const sim::MethodResult& pro_base = method(r, PriorMethod::kProbabilisticBaseline);
    MESSAGE("best F1: thresholded " << thr.summary.best_f1 << ", probabilistic " << pro.summary.best_f1
                                    << ", baselines " << thr_base.summary.best_f1 << " / " << pro_base.summary.best_f1);

    // A high best F1 for both methods (measured 0.759 and 0.759; the per-ray
    // model of before gave 0.817 and 0.816: one sensor's stray reading now
    // makes its voxel occupied, so the simulated noise costs precision).
    CHECK(thr.summary.best_f1 >= 0.70);
    CHECK(pro.summary.best_f1 >= 0.70);
    // Above the baselines' interior thresholds the priors agree outside the
    // boxes, so the best F1s (reached at t_f ~0.9) differ little (measured
    // baselines 0.759 / 0.759): the methods must not be worse there.
    CHECK(thr.summary.best_f1 >= thr_base.summary.best_f1 - 0.01);
    CHECK(pro.summary.best_f1 >= pro_base.summary.best_f1 - 0.01);

    // The wide margin is where the baselines keep the interiors: t_f < 0.5
    // for the thresholded baseline (prior 0.5 in E, and unobserved interiors
    // are in E), t_f < 0.25 for the probabilistic one (1 - P(occ) = 0.5 there,
    // so P(fore) = 0.25). Same t_f, same recall; precision measured
    // 0.518 vs 0.211 at t_f 0.45 and 0.216 vs 0.123 at t_f 0.2 (the per-ray
    // model: 0.691 vs 0.218 and 0.458 vs 0.181; the noise voxels that both
    // now keep make the ratio at t_f 0.2 smaller).
    const sim::PrPoint& t45 = at(thr, 0.45);
    const sim::PrPoint& b45 = at(thr_base, 0.45);
    MESSAGE("t_f 0.45: thresholded P " << t45.precision << " R " << t45.recall << "; baseline P " << b45.precision
                                       << " R " << b45.recall);
    CHECK(t45.recall >= b45.recall - 1e-12);
    CHECK(t45.precision >= 2.0 * b45.precision);
    CHECK(t45.precision - b45.precision >= 0.3);
    const sim::PrPoint& p20 = at(pro, 0.2);
    const sim::PrPoint& q20 = at(pro_base, 0.2);
    MESSAGE("t_f 0.2: probabilistic P " << p20.precision << " R " << p20.recall << "; baseline P " << q20.precision
                                        << " R " << q20.recall);
    CHECK(p20.recall >= q20.recall - 1e-12);
    CHECK(p20.precision >= 1.5 * q20.precision);
    CHECK(p20.precision - q20.precision >= 0.07);

    // The mechanism: below those thresholds the baselines call the interiors
    // of the background boxes foreground, the methods do not. "Interior" for
    // the baselines: the deep interior, one voxel (5 cm) or more under the
    // surface (485 voxels; measured 475 of them at t_f 0.45 for the
    // thresholded baseline, 484 at t_f 0.2 for the probabilistic one; at
    // least 95% required); the voxels just under a surface can hold noisy
    // readings, which make G_B occupied there and drop them from E.
    // For the methods: every voxel wholly inside a box (measured: none).
    const std::vector<std::uint8_t> inside = interior(r, 0.0);
    const std::vector<std::uint8_t> deep = interior(r, 0.05);
    for (const double t_f : {0.1, 0.3, 0.45, 0.49}) {
        const InteriorCount c = count_foreground(deep, thr_base, t_f);
        REQUIRE(c.interior > 100U);
        CHECK_MESSAGE(c.foreground >= c.interior * 95U / 100U, "thresholded baseline, t_f " << t_f);
        CHECK_MESSAGE(count_foreground(inside, thr, t_f).foreground == 0U, "thresholded, t_f " << t_f);
    }
    for (const double t_f : {0.1, 0.2, 0.24}) {
        const InteriorCount c = count_foreground(deep, pro_base, t_f);
        CHECK_MESSAGE(c.foreground >= c.interior * 95U / 100U, "probabilistic baseline, t_f " << t_f);
        CHECK_MESSAGE(count_foreground(inside, pro, t_f).foreground == 0U, "probabilistic, t_f " << t_f);
    }
    MESSAGE("deep interior " << count_foreground(deep, thr_base, 0.45).interior << " voxels; baselines call "
                             << count_foreground(deep, thr_base, 0.45).foreground << " (t_f 0.45) and "
                             << count_foreground(deep, pro_base, 0.2).foreground << " (t_f 0.2) foreground");
}

// verifies: SR-EVAL-002, SR-FUSE-002
TEST_CASE(
    "paper claim 2, changed by the per-sensor model: on the small object only the probabilistic method's "
    "recall goes past the thresholded one's, and no longer at a useful precision" *
    CELLGUARD_LONG_REPLAY) {
    sim::SceneResult r(config().geometry);
    run("small", r);
    const sim::MethodResult& thr = method(r, PriorMethod::kThresholded);
    const sim::MethodResult& pro = method(r, PriorMethod::kProbabilistic);
    MESSAGE("max recall: thresholded " << thr.summary.max_recall << ", probabilistic " << pro.summary.max_recall);
    for (const double recall : {0.4, 0.5, 0.6, 0.7, 0.8}) {
        MESSAGE("precision at recall >= " << recall << ": thresholded " << precision_at(thr, recall)
                                          << ", probabilistic " << precision_at(pro, recall));
    }
    // The 2x4 lies in voxels that hold the box top in G_B: the thresholded
    // prior removes them for good, so its recall stops early (measured
    // 0.349) while the probabilistic one goes on (measured 1.0).
    CHECK(thr.summary.max_recall <= 0.75);
    CHECK(pro.summary.max_recall >= 0.9);
    CHECK(pro.summary.max_recall - thr.summary.max_recall >= 0.2);
    // The paper's finding (and this project's per-ray model: precision 0.825
    // / 0.342 at recall 0.5 / 0.6) was that the probabilistic method sees
    // those voxels at a useful precision: many rays ending in them summed to
    // evidence above the prior's background term there (about -7.6 nats).
    // One frame's pooled evidence is now at most logit(0.97) = 3.5 nats, by
    // design (a frame of the background itself must not be foreground,
    // SR-FUSE-002), so the probabilistic method reaches those voxels only
    // where t_f <= 0.5 counts every unobserved accessible voxel: measured
    // precision 0.002 at recall 0.5. This check documents the lost finding;
    // it fails if the model's bound on a frame's evidence is lifted again.
    CHECK(precision_at(pro, 0.5) < 0.05);
}

// verifies: SR-FUSE-008
TEST_CASE("evaluation: fewer background frames than the probabilistic method needs are refused with a clear error") {
    sim::ExperimentConfig cfg = config();
    cfg.background_frames = 2;  // min_background_frames: 3 with the default sensor model
    sim::SceneResult r(cfg.geometry);
    const sim::SceneLoad load = sim::load_scene_file(scene_path("large"));
    REQUIRE_MESSAGE(load.ok, load.error);
    std::string error;
    CHECK_FALSE(sim::run_scene(load.scene, cfg, r, error));
    CHECK(error ==
          "2 background frames are too few: the probabilistic method needs at least 3 for space seen free to "
          "fall below t_E (min_background_frames)");
}

// verifies: SR-EVAL-002
TEST_CASE("paper claim 3: with no foreground, no voxel inside a background box is foreground after subtraction" *
          CELLGUARD_LONG_REPLAY) {
    sim::SceneResult r(config().geometry);
    run("empty", r);
    const sim::MethodResult& thr = method(r, PriorMethod::kThresholded);
    const sim::MethodResult& pro = method(r, PriorMethod::kProbabilistic);
    const std::vector<std::uint8_t> inside = interior(r, 0.0);
    const std::vector<std::uint8_t> deep = interior(r, 0.05);
    REQUIRE(count_foreground(inside, thr, 0.5).interior > 500U);
    // Thresholded: interiors are outside A, the prior is "never": at every t_f.
    for (const double t_f : sim::default_thresholds()) {
        CHECK_MESSAGE(count_foreground(inside, thr, t_f).foreground == 0U, "thresholded, t_f " << t_f);
    }
    // Probabilistic: P(acc) inside is small but not 0 (the cheapest path
    // crosses the noisy surface), and the voxels just under a surface can
    // hold noisy readings of the frame; so they are foreground for small t_f
    // (measured: 15 voxels at t_f 0.001, the last one at t_f 0.07). From
    // t_f = 0.25 on (a margin over 0.07; the figures use 0.73) none may be,
    // and the deep interior (5 cm or more under the surface) never.
    double last_bad = 0.0;
    for (const double t_f : sim::default_thresholds()) {
        if (count_foreground(inside, pro, t_f).foreground > 0U) {
            last_bad = t_f;
        }
        CHECK_MESSAGE(count_foreground(deep, pro, t_f).foreground == 0U, "probabilistic, deep, t_f " << t_f);
        if (t_f >= 0.25) {
            CHECK_MESSAGE(count_foreground(inside, pro, t_f).foreground == 0U, "probabilistic, t_f " << t_f);
        }
    }
    MESSAGE("probabilistic: interior voxels foreground at t_f 0.001: "
            << count_foreground(inside, pro, 0.001).foreground << "; largest such t_f " << last_bad);
}
