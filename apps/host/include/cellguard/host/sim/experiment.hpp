// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file experiment.hpp
/// The paper's experiment (sections IV-V) as a library, shared by the
/// evaluation program (apps/evaluation) and the claim tests
/// (tests/unit/test_paper_claims.cpp):
///
/// 1. G_B: `background_frames` noisy frames of the scene's background
///    (background_of) fused one by one with the configured sensor model
///    (the paper's per-ray profile, paper_sensor_model.hpp, or the
///    product's, fusion.hpp) and summed into G_B (accumulate_background,
///    default clamp).
/// 2. The prior of each of the four methods (compute_accessibility_prior).
/// 3. `foreground_frames` noisy frames of the full scene, each fused into a
///    fresh frame grid; subtraction adds the prior (add_saturating, the
///    independent opinion pool); a voxel is foreground at t_f when the sum is
///    at least threshold_log_odds(t_f).
/// 4. Scores against the ideal ground truth (ground_truth.hpp), unknown
///    voxels left out, summed over the foreground frames: histograms of the
///    subtracted log-odds of foreground and not-foreground voxels give the
///    counts at every t_f exactly; the curve holds the default sweep and the
///    thresholds where recall passes each 1/200 (fine_pr_curve).
///
/// Frame seeds: background frame i uses seed * 1000003 + i, foreground frame
/// j uses seed * 1000003 + 500000 + j (seed = the scene file's; with a
/// shared G_B, that of the file G_B was built from). Foreground
/// frame j shows the scene at time j * frame_interval_s (people walk).
#ifndef CELLGUARD_HOST_SIM_EXPERIMENT_HPP
#define CELLGUARD_HOST_SIM_EXPERIMENT_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/sim/ground_truth.hpp"
#include "cellguard/host/sim/paper_sensor_model.hpp"
#include "cellguard/host/sim/scene_file.hpp"
#include "cellguard/prior/accessibility.hpp"

namespace cellguard::sim {

/// An evidence grid that owns its storage (host code). Not copyable: the
/// grid's views point into the vectors; moving keeps them valid.
struct OwnedGrid {
    /// A cleared grid of geometry @p g (aborts on an invalid geometry).
    explicit OwnedGrid(const GridGeometry& g);
    OwnedGrid(const OwnedGrid&) = delete;
    OwnedGrid& operator=(const OwnedGrid&) = delete;
    /// Moves the storage; the views stay valid.
    OwnedGrid(OwnedGrid&&) noexcept = default;
    /// Moves the storage; the views stay valid.
    OwnedGrid& operator=(OwnedGrid&&) noexcept = default;
    ~OwnedGrid() = default;
    std::vector<std::int16_t> log_odds;  ///< storage of the log-odds
    std::vector<std::uint8_t> observed;  ///< storage of the observed flags
    std::vector<std::int16_t> scratch;   ///< fusion's per-sensor working memory (fuse_frame), one per voxel
    EvidenceGrid grid;                   ///< the grid over that storage
    /// The scratch as fuse_frame takes it.
    [[nodiscard]] Span<std::int16_t> fusion_scratch() { return {scratch.data(), scratch.size()}; }
};

/// The four methods in the order of every result array.
constexpr std::array<PriorMethod, 4> kAllMethods = {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                                    PriorMethod::kThresholdedBaseline,
                                                    PriorMethod::kProbabilisticBaseline};

/// Short name of a method for files and tables ("thresholded", "probabilistic",
/// "thresholded-baseline", "probabilistic-baseline").
const char* method_name(PriorMethod method);

/// How to run one scene.
struct ExperimentConfig {
    GridGeometry geometry = paper_grid_geometry();  ///< the grid
    AccessibilityParams params{};  ///< t_B, t_E, r, A_0 (the paper's by default; method is set per run)
    /// Which model fuses the frames: the paper's per-ray profile (the
    /// default of the paper's experiments) or the monitor's.
    EvalSensorModel model = EvalSensorModel::kPaper;
    SensorModelParams sensor_model{};  ///< the product model's parameters (model kProduct)
    /// Ray rasterisation of fusion and of the ground truth: the paper's 3D
    /// Bresenham by default (the exact traversal visits every voxel a ray
    /// grazes and so clears more of the voxels that a surface only clips).
    Rasterization rasterization = Rasterization::kBresenham3d;
    /// Fuse depth images by footprint fusion (footprint_fusion.hpp) instead
    /// of ray by ray; the ground truth stays ray by ray with rasterization.
    /// The product model's path only: refused with the paper's model.
    bool footprint = false;
    int background_frames = 100;    ///< empty frames summed into G_B
    int foreground_frames = 5;      ///< frames with the foreground, scores summed
    double frame_interval_s = 0.1;  ///< time between foreground frames
    bool ideal_sensors = false;     ///< ignore the scene's noise models
};

/// Counts of subtracted log-odds values (index value + 32768, the sentinel
/// at 0) over scored voxels, by ground truth.
struct ScoreHistogram {
    std::vector<std::uint64_t> foreground = std::vector<std::uint64_t>(65536U, 0U);      ///< truth foreground
    std::vector<std::uint64_t> not_foreground = std::vector<std::uint64_t>(65536U, 0U);  ///< truth not foreground
};

/// One point of a precision-recall curve.
struct PrPoint {
    double t_f = 0.0;        ///< foreground threshold (probability)
    std::uint64_t tp = 0U;   ///< foreground voxels called foreground
    std::uint64_t fp = 0U;   ///< not-foreground voxels called foreground
    std::uint64_t fn = 0U;   ///< foreground voxels missed
    double precision = 1.0;  ///< tp / (tp + fp); 1 when nothing is called foreground
    double recall = 0.0;     ///< tp / (tp + fn)
    double f1 = 0.0;         ///< harmonic mean of precision and recall
};

/// The curve summarised.
struct PrSummary {
    double best_f1 = 0.0;                  ///< largest F1 over the sweep
    double best_f1_t_f = 0.0;              ///< t_f where it occurs (the smallest such t_f)
    double precision_at_recall_90 = -1.0;  ///< largest precision among points with recall >= 0.9; -1 when none
    double recall_at_precision_90 = -1.0;  ///< largest recall among points with precision >= 0.9; -1 when none
    double max_recall = 0.0;               ///< largest recall over the sweep
};

/// Largest precision among points of @p curve with recall >= @p recall
/// (interpolated precision); -1 when no point reaches that recall.
double precision_at_recall(const std::vector<PrPoint>& curve, double recall);

/// Largest recall among points of @p curve with precision >= @p precision
/// that call something foreground (tp > 0); 0 when none.
double recall_at_precision(const std::vector<PrPoint>& curve, double precision);

/// The default sweep of t_f: 0.001, 0.005, 0.01 to 0.99 by 0.01, 0.995,
/// 0.999, and 0.73 (the paper's figures' value, already in the grid).
std::vector<double> default_thresholds();

/// The curve at every threshold of @p thresholds.
std::vector<PrPoint> pr_curve(const ScoreHistogram& h, const std::vector<double>& thresholds);

/// The curve at default_thresholds() and, for k = 1 .. @p steps, at the
/// largest scored log-odds value where recall reaches k / steps (its t_f is
/// probability_from_log_odds of that value): where the scores take enough
/// values, recall takes up to @p steps distinct values. Ascending t_f.
std::vector<PrPoint> fine_pr_curve(const ScoreHistogram& h, int steps = 200);

/// Number of distinct recall values on @p curve.
std::size_t distinct_recalls(const std::vector<PrPoint>& curve);

/// Summary of @p curve.
PrSummary summarize(const std::vector<PrPoint>& curve);

/// Subtraction: out[i] = add_saturating(frame[i], prior[i]) for every voxel.
void subtract_prior(const EvidenceGrid& frame, const std::vector<std::int16_t>& prior, std::vector<std::int16_t>& out);

/// Adds the scored voxels of @p subtracted to @p h by @p truth.
void add_scores(ScoreHistogram& h, const std::vector<std::int16_t>& subtracted, const GroundTruth& truth);

/// Results of one method on one scene.
struct MethodResult {
    PriorMethod method = PriorMethod::kThresholded;  ///< which method
    std::vector<std::int16_t> prior;                 ///< its prior (log-odds of P(fore))
    std::vector<std::int16_t> last_subtracted;       ///< frame + prior of the last foreground frame
    double prior_ms = 0.0;                           ///< time to compute the prior
    ScoreHistogram scores;                           ///< summed over the foreground frames
    std::vector<PrPoint> curve;                      ///< fine_pr_curve of the scores
    PrSummary summary;                               ///< of the curve
};

/// Results of one scene.
struct SceneResult {
    std::string name;                     ///< the scene's name
    Scene background;                     ///< what G_B was built from
    Scene last_scene;                     ///< the scene of the last foreground frame
    OwnedGrid background_grid;            ///< G_B
    OwnedGrid last_frame;                 ///< the fused last foreground frame
    GroundTruth last_truth;               ///< ground truth of the last foreground frame
    std::array<MethodResult, 4> methods;  ///< in kAllMethods order
    double fuse_ms_per_frame = 0.0;       ///< mean fusion time of one frame (background and foreground)
    double render_ms_per_frame = 0.0;     ///< mean simulation (ray casting and noise) time of one frame
    double truth_ms = 0.0;                ///< time for the ground truth (all foreground frames)
    double subtract_ms_per_frame = 0.0;   ///< mean time of one subtraction (one method, whole grid)
    /// Scene result for grids of geometry @p g.
    explicit SceneResult(const GridGeometry& g) : background_grid(g), last_frame(g) {}
};

/// Runs the experiment on @p file with @p cfg. G_B is built from the
/// file's background (step 1) unless @p background is given (same
/// geometry), which is then copied: one G_B can serve several scenes, as
/// one background model serves every frame at run time. Returns false and
/// sets @p error when fusion or the analysis refuses its input.
bool run_scene(const SceneFile& file, const ExperimentConfig& cfg, SceneResult& out, std::string& error,
               const EvidenceGrid* background = nullptr);

/// Builds only G_B (step 1) into @p background; returns false on an error.
bool build_background(const SceneFile& file, const ExperimentConfig& cfg, EvidenceGrid& background,
                      double* fuse_ms_total = nullptr, double* render_ms_total = nullptr);

/// Computes the prior of @p background with @p params (scratch allocated
/// here); returns false on an error.
bool compute_prior(const EvidenceGrid& background, const AccessibilityParams& params, std::vector<std::int16_t>& prior);

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_EXPERIMENT_HPP
