// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The paper's claims (section V) as tests that can fail, on the simulated
// workcell of apps/evaluation: the scene files apps/evaluation/scenes/*.toml
// (the paper's four sensors with noise, a 6 m room around the frame), the
// paper's parameters (r = 10 cm, t_B = 0.51, t_E = 0.1, 3D Bresenham), the
// ideal 0-1 ground truth (sim/ground_truth.hpp), under two sensor models:
//
// - "paper model" cases: the paper's own (section IV, the per-ray profile
//   0.44 / 0.56 summed over rays; sim/paper_sensor_model.hpp), over five
//   seeds, G_B from 30 empty frames and one frame with the foreground;
// - "product model" cases: the monitor's (one opinion per sensor, voxel and
//   frame: p_hit 0.90, p_miss 0.30, pooled within [0.12, 0.97];
//   sensor_model.hpp), one seed, G_B from 20 empty frames, one frame with
//   the foreground: what the claims become under the product's model.
//
// Fewer frames than the evaluation (cellguard-eval: 100 and 5), to keep each
// case at a few seconds. Every threshold below was set from what these
// tests measure (values in the comments; product 2026-11-25, paper
// 2026-12-07) with a margin; cellguard-eval's fuller run gives results.md.
#include <doctest/doctest.h>

#include <memory>
#include <string>
#include <vector>

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
    cfg.model = sim::EvalSensorModel::kProduct;
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
    "product model, paper claim 1: on the large object both methods score well and beat their baselines, which keep the "
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
    "product model, paper claim 2: on the small object only the probabilistic method's "
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

// verifies: SR-FUSE-008, SR-EVAL-005
TEST_CASE("evaluation: the paper's model refuses fewer than ten background frames, and footprint fusion") {
    sim::ExperimentConfig cfg;
    cfg.model = sim::EvalSensorModel::kPaper;
    cfg.background_frames = 9;  // logit(0.1) / logit(0.44): 9.07 frames of one ray
    const sim::SceneLoad load = sim::load_scene_file(scene_path("large"));
    REQUIRE_MESSAGE(load.ok, load.error);
    sim::SceneResult r(cfg.geometry);
    std::string error;
    CHECK_FALSE(sim::run_scene(load.scene, cfg, r, error));
    CHECK(error ==
          "9 background frames are too few: the probabilistic method needs at least 10 for space seen free to "
          "fall below t_E (min_background_frames)");
    cfg.background_frames = 10;
    cfg.footprint = true;
    error.clear();
    CHECK_FALSE(sim::run_scene(load.scene, cfg, r, error));
    CHECK(error == "footprint fusion is the product model's path: the paper's model fuses ray by ray");
    sim::OwnedGrid g(cfg.geometry);
    CHECK_FALSE(sim::build_background(load.scene, cfg, g.grid));
}

// verifies: SR-EVAL-002
TEST_CASE(
    "product model, paper claim 3: with no foreground, no voxel inside a background box is foreground after subtraction" *
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

// ---------------------------------------------------------------------------
// The paper's claims with the paper's own sensor model (section IV; the
// per-ray profile of sim/paper_sensor_model.hpp), over five seeds: each seed
// gives G_B (30 empty frames; the model needs 10) and each scene its own
// noise. The thresholds were set from what these cases measured
// (2026-12-07, values in the comments) with a margin; cellguard-eval's run
// (100 + 5 frames, one seed) gives results.md.

namespace {

constexpr int kSeeds = 5;
constexpr std::uint64_t kSeedStep = 7919U;  // seed k adds k * kSeedStep to each scene file's own seed

sim::ExperimentConfig paper_config() {
    sim::ExperimentConfig cfg;
    cfg.model = sim::EvalSensorModel::kPaper;
    cfg.background_frames = 30;
    cfg.foreground_frames = 1;
    return cfg;
}

sim::SceneFile scene_with_seed(const char* name, int k) {
    sim::SceneLoad load = sim::load_scene_file(scene_path(name));
    REQUIRE_MESSAGE(load.ok, load.error);
    load.scene.seed += static_cast<std::uint64_t>(k) * kSeedStep;
    return load.scene;
}

/// G_B of seed @p k with the paper's model, built once per process and seed.
const sim::OwnedGrid& paper_background(int k) {
    static std::vector<std::unique_ptr<sim::OwnedGrid>> grids(kSeeds);
    if (grids[static_cast<std::size_t>(k)] == nullptr) {
        auto g = std::make_unique<sim::OwnedGrid>(paper_config().geometry);
        REQUIRE(sim::build_background(scene_with_seed("background", k), paper_config(), g->grid));
        grids[static_cast<std::size_t>(k)] = std::move(g);
    }
    return *grids[static_cast<std::size_t>(k)];
}

/// Scene @p name with seed @p k against that seed's G_B, paper model.
void run_paper(const char* name, int k, sim::SceneResult& out) {
    std::string error;
    REQUIRE_MESSAGE(sim::run_scene(scene_with_seed(name, k), paper_config(), out, error, &paper_background(k).grid),
                    error);
}

/// Largest recall among points with precision >= @p precision; 0 when none.
double recall_at(const sim::MethodResult& m, double precision) { return sim::recall_at_precision(m.curve, precision); }

/// Phantom voxels of the last frame at @p t_f: called foreground, not foreground by the ground truth, and
/// background in G_B (P(occ; G_B) >= t_B: a surface of the background, where only a change in the evidence
/// of that surface can make a voxel foreground).
std::size_t phantoms(const sim::SceneResult& r, const sim::MethodResult& m, double t_f) {
    const std::int16_t fg = threshold_log_odds(t_f);
    const std::int16_t occupied = threshold_log_odds(0.51);
    const Span<std::int16_t> bg = r.background_grid.grid.log_odds();
    const Span<std::uint8_t> seen = r.background_grid.grid.observed();
    std::size_t n = 0U;
    for (std::size_t i = 0; i < bg.size(); ++i) {
        const std::int16_t v = m.last_subtracted[i];
        const bool called = v != kNeverForeground && v >= fg;
        n += (called && seen[i] != 0U && bg[i] >= occupied && r.last_truth.label[i] == sim::Truth::kNotForeground) ? 1U
                                                                                                                   : 0U;
    }
    return n;
}

}  // namespace

// verifies: SR-EVAL-002, SR-EVAL-005
TEST_CASE("paper model, claim 1: on the large object the baselines are worse at recall 0.9 over five seeds" *
          CELLGUARD_LONG_REPLAY) {
    for (int k = 0; k < kSeeds; ++k) {
        sim::SceneResult r(paper_config().geometry);
        run_paper("large", k, r);
        const double thr = precision_at(method(r, PriorMethod::kThresholded), 0.9);
        const double thr_base = precision_at(method(r, PriorMethod::kThresholdedBaseline), 0.9);
        const double pro = precision_at(method(r, PriorMethod::kProbabilistic), 0.9);
        const double pro_base = precision_at(method(r, PriorMethod::kProbabilisticBaseline), 0.9);
        MESSAGE("seed " << k << ": precision at recall 0.8: thresholded "
                        << precision_at(method(r, PriorMethod::kThresholded), 0.8) << " / baseline "
                        << precision_at(method(r, PriorMethod::kThresholdedBaseline), 0.8) << "; probabilistic "
                        << precision_at(method(r, PriorMethod::kProbabilistic), 0.8) << " / baseline "
                        << precision_at(method(r, PriorMethod::kProbabilisticBaseline), 0.8));
        MESSAGE("seed " << k << ": precision at recall 0.9: thresholded " << thr << " / baseline " << thr_base
                        << "; probabilistic " << pro << " / baseline " << pro_base << "; best F1 "
                        << method(r, PriorMethod::kThresholded).summary.best_f1 << " / "
                        << method(r, PriorMethod::kProbabilistic).summary.best_f1);
        // The sweep is fine enough to draw a curve (measured 149-173 distinct recalls a method).
        for (const sim::MethodResult& m : r.methods) {
            CHECK_MESSAGE(sim::distinct_recalls(m.curve) >= 30U, sim::method_name(m.method));
        }
        // The form: each baseline's precision at recall 0.9 at least 0.1 below its method's. The
        // probabilistic pair meets it in every seed (measured 0.108-0.118). The thresholded pair falls short at
        // 0.9 (measured 0.047-0.109, 0.1 in one seed of five): recall 0.9 is reached only at t_f of about 0.003,
        // where both thresholded variants already call thousands of noise voxels in free space foreground, and
        // the baseline's box interiors (about a thousand voxels a frame) dilute a precision that is low anyway.
        // Its gap shows at recall 0.8, where the thresholded baseline has just taken in the interiors (its
        // curve drops at recall 0.78, t_f 0.5): measured 0.61-0.70 against 0.21-0.22. Required: the measured
        // gaps with a margin, and each baseline at most 3/4 of its method at 0.9 (measured 0.56-0.68
        // thresholded, 0.50-0.52 probabilistic).
        const double thr_80 = precision_at(method(r, PriorMethod::kThresholded), 0.8);
        const double thr_base_80 = precision_at(method(r, PriorMethod::kThresholdedBaseline), 0.8);
        CHECK(pro - pro_base >= 0.1);
        CHECK(thr - thr_base >= 0.03);
        CHECK(thr_80 - thr_base_80 >= 0.3);
        CHECK(thr_base <= 0.75 * thr);
        CHECK(pro_base <= 0.75 * pro);
        // Both methods find the object (best F1 measured 0.814-0.829).
        CHECK(method(r, PriorMethod::kThresholded).summary.best_f1 >= 0.78);
        CHECK(method(r, PriorMethod::kProbabilistic).summary.best_f1 >= 0.78);
    }
}

// verifies: SR-EVAL-002, SR-EVAL-005
TEST_CASE("paper model, claim 2: on the small object the probabilistic method keeps recall at precision 0.5" *
          CELLGUARD_LONG_REPLAY) {
    for (int k = 0; k < kSeeds; ++k) {
        sim::SceneResult r(paper_config().geometry);
        run_paper("small", k, r);
        const sim::MethodResult& thr = method(r, PriorMethod::kThresholded);
        const sim::MethodResult& pro = method(r, PriorMethod::kProbabilistic);
        MESSAGE("seed " << k << ": recall at precision 0.5: thresholded " << recall_at(thr, 0.5) << ", probabilistic "
                        << recall_at(pro, 0.5) << "; max recall " << thr.summary.max_recall << " / "
                        << pro.summary.max_recall << "; precision at recall 0.5 " << precision_at(thr, 0.5) << " / "
                        << precision_at(pro, 0.5) << ", at 0.7 " << precision_at(thr, 0.7) << " / "
                        << precision_at(pro, 0.7));
        // "Dramatically better, particularly under high recall": at recall 0.5 the probabilistic method keeps
        // precision 0.57-0.74 where the thresholded one has 0.05-0.07 (at least 5 times required); only it
        // reaches recall 0.7 (precision 0.14-0.21) and 1.0, the thresholded one stops at 0.60 (the 2x4's voxels
        // that hold the box top in G_B are outside A). At precision 0.5 its recall is 0.52-0.60 against
        // 0.41-0.43 (at least 0.08 more required).
        CHECK(precision_at(pro, 0.5) >= 0.5);
        CHECK(precision_at(pro, 0.5) >= 5.0 * precision_at(thr, 0.5));
        CHECK(recall_at(pro, 0.5) - recall_at(thr, 0.5) >= 0.08);
        CHECK(thr.summary.max_recall <= 0.7);
        CHECK(pro.summary.max_recall >= 0.95);
        CHECK(precision_at(thr, 0.7) == 0.0);
        CHECK(precision_at(pro, 0.7) >= 0.1);
    }
}

// verifies: SR-EVAL-002, SR-EVAL-005
TEST_CASE(
    "paper model, claim 3: only the probabilistic method calls background surfaces foreground, and the object's "
    "occlusion adds none measurably" *
    CELLGUARD_LONG_REPLAY) {
    std::size_t pro_large = 0U;
    std::size_t pro_empty = 0U;
    for (int k = 0; k < kSeeds; ++k) {
        sim::SceneResult large(paper_config().geometry);
        run_paper("large", k, large);
        // The empty scene with the large scene's noise seed: the frames differ only where the object is.
        sim::SceneFile empty_file = scene_with_seed("empty", k);
        empty_file.seed = scene_with_seed("large", k).seed;
        sim::SceneResult empty(paper_config().geometry);
        std::string error;
        REQUIRE_MESSAGE(sim::run_scene(empty_file, paper_config(), empty, error, &paper_background(k).grid), error);
        // The thresholded prior never lets a voxel outside E be foreground, at any t_f.
        CHECK(phantoms(large, method(large, PriorMethod::kThresholded), 0.001) == 0U);
        CHECK(phantoms(empty, method(empty, PriorMethod::kThresholded), 0.001) == 0U);
        const std::size_t a = phantoms(large, method(large, PriorMethod::kProbabilistic), 0.73);
        const std::size_t b = phantoms(empty, method(empty, PriorMethod::kProbabilistic), 0.73);
        MESSAGE("seed " << k << ": background-surface voxels foreground at t_f 0.73, probabilistic: large " << a
                        << ", empty " << b
                        << "; at t_f 0.5: " << phantoms(large, method(large, PriorMethod::kProbabilistic), 0.5) << " / "
                        << phantoms(empty, method(empty, PriorMethod::kProbabilistic), 0.5));
        pro_large += a;
        pro_empty += b;
    }
    MESSAGE("over " << kSeeds << " seeds: probabilistic, background-surface voxels foreground at t_f 0.73: large "
                    << pro_large << ", empty " << pro_empty);
    // The probabilistic method does call background-surface voxels foreground (the paper's phantoms are of
    // this kind), but as often in the empty scene under the same noise as with the object.
    CHECK(pro_large + pro_empty >= 1U);
    // Noise-free sensors isolate the cause: every frame of the empty scene is then a background frame, and
    // the same surface voxels are foreground with and without the object (measured 5 and 5 at t_f 0.73).
    // One frame's per-ray sum in a surface voxel that many rays end in exceeds the prior's background term
    // there (G_B is clamped at 0.999, 6.9 nats): the cause is the model's unbounded frame evidence, which
    // the product's model bounds (SR-FUSE-002), not the object's occlusion.
    sim::ExperimentConfig ideal = paper_config();
    ideal.ideal_sensors = true;
    sim::OwnedGrid ideal_background(ideal.geometry);
    REQUIRE(sim::build_background(scene_with_seed("background", 0), ideal, ideal_background.grid));
    sim::SceneResult ideal_large(ideal.geometry);
    sim::SceneResult ideal_empty(ideal.geometry);
    std::string error;
    REQUIRE(sim::run_scene(scene_with_seed("large", 0), ideal, ideal_large, error, &ideal_background.grid));
    REQUIRE(sim::run_scene(scene_with_seed("empty", 0), ideal, ideal_empty, error, &ideal_background.grid));
    const std::size_t a = phantoms(ideal_large, method(ideal_large, PriorMethod::kProbabilistic), 0.73);
    const std::size_t b = phantoms(ideal_empty, method(ideal_empty, PriorMethod::kProbabilistic), 0.73);
    MESSAGE("noise-free: background-surface voxels foreground at t_f 0.73, probabilistic: large " << a << ", empty "
                                                                                                  << b);
    CHECK(b >= 1U);
    CHECK(a == b);
    CHECK(phantoms(ideal_large, method(ideal_large, PriorMethod::kThresholded), 0.001) == 0U);
}
