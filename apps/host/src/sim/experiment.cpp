// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/experiment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <set>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/owned_footprint.hpp"

namespace cellguard::sim {

namespace {
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/// The histogram bin of a log-odds value: -32768 .. 32767 to 0 .. 65535 (no overflow in int32).
std::size_t bin_of(std::int16_t v) {
    const std::int32_t shifted = static_cast<std::int32_t>(v) + 32768;
    return static_cast<std::size_t>(shifted);
}

constexpr std::uint64_t kSeedStride = 1000003U;
constexpr std::uint64_t kForegroundSeedOffset = 500000U;

SimulatedFrame render(const SceneFile& file, const ExperimentConfig& cfg, const Scene& scene, std::uint64_t seed) {
    if (cfg.ideal_sensors) {
        return render_frame(file.sensors, scene);
    }
    return render_noisy_frame(file.sensors, file.noise, scene, seed);
}

/// The integer table of the profile @p cfg fuses with: paper_profile() for the paper's model, cfg.sensor_model for
/// the product's.
Result<SensorModelTable> model_table(const ExperimentConfig& cfg) {
    return SensorModelTable::make(cfg.model == EvalSensorModel::kPaper ? paper_profile() : cfg.sensor_model);
}

/// Clears @p frame and fuses @p f into it with @p cfg's model (footprint fusion through @p footprint, made on the
/// first call, when cfg.footprint).
Result<FusionStats> fuse_experiment_frame(const ExperimentConfig& cfg, const SensorModelTable& table, OwnedGrid& frame,
                                          const SimulatedFrame& f,
                                          std::unique_ptr<host::OwnedFootprintWorkspaces>& footprint) {
    frame.grid.clear();
    const Span<const SensorReading> readings(f.readings.data(), f.readings.size());
    if (cfg.model == EvalSensorModel::kPaper) {
        return fuse_frame_per_ray(frame.grid, readings, table, cfg.rasterization);
    }
    if (cfg.footprint && footprint == nullptr) {
        footprint = std::make_unique<host::OwnedFootprintWorkspaces>(frame.grid.geometry(), f.readings);
    }
    return host::fuse_frame_by(frame.grid, readings, table, frame.fusion_scratch(), cfg.rasterization, footprint.get());
}
}  // namespace

OwnedGrid::OwnedGrid(const GridGeometry& g)
    : log_odds(g.voxel_count(), 0), observed(g.voxel_count(), 0U), scratch(g.voxel_count(), 0) {
    Result<EvidenceGrid> r = EvidenceGrid::make(g, Span<std::int16_t>(log_odds.data(), log_odds.size()),
                                                Span<std::uint8_t>(observed.data(), observed.size()));
    if (!r.ok()) {
        static_cast<void>(std::fprintf(stderr, "OwnedGrid: invalid geometry (%s)\n", to_string(r.error())));
        std::abort();
    }
    grid = r.value();
    grid.clear();
}

std::vector<double> default_thresholds() {
    std::vector<double> t = {0.001, 0.005};
    for (int i = 1; i <= 99; ++i) {
        t.push_back(i / 100.0);
    }
    t.push_back(0.995);
    t.push_back(0.999);
    return t;
}

namespace {

/// Counts of scores at or above each histogram bin, for the points of a curve.
struct AtLeast {
    std::vector<std::uint64_t> fg = std::vector<std::uint64_t>(65537U, 0U);
    std::vector<std::uint64_t> bg = std::vector<std::uint64_t>(65537U, 0U);
    explicit AtLeast(const ScoreHistogram& h) {
        for (std::size_t i = 65536U; i-- > 0U;) {
            fg[i] = fg[i + 1U] + h.foreground[i];
            bg[i] = bg[i + 1U] + h.not_foreground[i];
        }
    }
    /// The point where every score >= @p raw is called foreground, labelled @p t_f. The sentinel bin (0) is never
    /// foreground: thresholds are >= kLogOddsMin.
    [[nodiscard]] PrPoint at(std::int16_t raw, double t_f) const {
        const std::size_t b = bin_of(raw);
        const std::uint64_t fg_total = fg[0];
        PrPoint p;
        p.t_f = t_f;
        p.tp = fg[b];
        p.fp = bg[b];
        p.fn = fg_total - p.tp;
        p.precision = (p.tp + p.fp) > 0U ? static_cast<double>(p.tp) / static_cast<double>(p.tp + p.fp) : 1.0;
        p.recall = fg_total > 0U ? static_cast<double>(p.tp) / static_cast<double>(fg_total) : 0.0;
        p.f1 = (p.precision + p.recall) > 0.0 ? 2.0 * p.precision * p.recall / (p.precision + p.recall) : 0.0;
        return p;
    }
};

}  // namespace

std::vector<PrPoint> pr_curve(const ScoreHistogram& h, const std::vector<double>& thresholds) {
    const AtLeast counts(h);
    std::vector<PrPoint> curve;
    curve.reserve(thresholds.size());
    for (const double t : thresholds) {
        curve.push_back(counts.at(threshold_log_odds(t), t));
    }
    return curve;
}

std::vector<PrPoint> fine_pr_curve(const ScoreHistogram& h, int steps) {
    // Raw thresholds: the default sweep's (with their exact t_f) and, per recall step, the largest raw value whose
    // count of foreground scores at or above it reaches the step (points made at the raw value itself: the round
    // trip through a probability may be off by one unit, threshold_log_odds).
    const AtLeast counts(h);
    std::map<std::int16_t, double> at;
    for (const double t : default_thresholds()) {
        at.emplace(threshold_log_odds(t), t);
    }
    const std::uint64_t fg_total = counts.fg[0];  // recall's denominator: the sentinel bin's too
    if (fg_total > 0U && steps > 0) {
        const auto n = static_cast<std::uint64_t>(steps);
        std::uint64_t step = 1U;
        for (std::size_t b = 65536U; b-- > 1U && step <= n;) {
            for (; step <= n && counts.fg[b] * n >= step * fg_total; ++step) {
                const auto raw = static_cast<std::int16_t>(static_cast<std::int32_t>(b) - 32768);
                at.emplace(raw, probability_from_log_odds(raw));
            }
        }
    }
    std::vector<PrPoint> curve;
    curve.reserve(at.size());
    for (const auto& [raw, t] : at) {
        curve.push_back(counts.at(raw, t));
    }
    return curve;
}

std::size_t distinct_recalls(const std::vector<PrPoint>& curve) {
    std::set<std::uint64_t> tps;
    for (const PrPoint& p : curve) {
        tps.insert(p.tp);
    }
    return tps.size();
}

double precision_at_recall(const std::vector<PrPoint>& curve, double recall) {
    double best = -1.0;
    for (const PrPoint& p : curve) {
        if (p.recall >= recall && p.precision > best) {
            best = p.precision;
        }
    }
    return best;
}

double recall_at_precision(const std::vector<PrPoint>& curve, double precision) {
    double best = 0.0;
    for (const PrPoint& p : curve) {
        if (p.tp > 0U && p.precision >= precision && p.recall > best) {
            best = p.recall;
        }
    }
    return best;
}

PrSummary summarize(const std::vector<PrPoint>& curve) {
    PrSummary s;
    for (const PrPoint& p : curve) {
        if (p.f1 > s.best_f1) {
            s.best_f1 = p.f1;
            s.best_f1_t_f = p.t_f;
        }
        if (p.precision >= 0.9 && p.recall > s.recall_at_precision_90) {
            s.recall_at_precision_90 = p.recall;
        }
        if (p.recall > s.max_recall) {
            s.max_recall = p.recall;
        }
    }
    s.precision_at_recall_90 = precision_at_recall(curve, 0.9);
    return s;
}

void subtract_prior(const EvidenceGrid& frame, const std::vector<std::int16_t>& prior, std::vector<std::int16_t>& out) {
    const Span<std::int16_t> lo = frame.log_odds();
    out.resize(lo.size());
    for (std::size_t i = 0; i < lo.size(); ++i) {
        out[i] = add_saturating(lo[i], prior[i]);
    }
}

void add_scores(ScoreHistogram& h, const std::vector<std::int16_t>& subtracted, const GroundTruth& truth) {
    for (std::size_t i = 0; i < subtracted.size(); ++i) {
        switch (truth.label[i]) {
            case Truth::kForeground: ++h.foreground[bin_of(subtracted[i])]; break;
            case Truth::kNotForeground: ++h.not_foreground[bin_of(subtracted[i])]; break;
            case Truth::kUnknown:  // neither is scored
            case Truth::kRobot: break;
        }
    }
}

bool build_background(const SceneFile& file, const ExperimentConfig& cfg, EvidenceGrid& background,
                      double* fuse_ms_total, double* render_ms_total) {
    const Result<SensorModelTable> table = model_table(cfg);
    if (!table.ok() || (cfg.footprint && cfg.model == EvalSensorModel::kPaper)) {
        return false;
    }
    OwnedGrid frame(background.geometry());
    background.clear();
    const Scene bg = background_of(file.scene);
    std::unique_ptr<host::OwnedFootprintWorkspaces> footprint;
    for (int i = 0; i < cfg.background_frames; ++i) {
        const Clock::time_point t0 = Clock::now();
        const SimulatedFrame f = render(file, cfg, bg, file.seed * kSeedStride + static_cast<std::uint64_t>(i));
        const Clock::time_point t1 = Clock::now();
        // The product's ray-by-ray path builds G_B as the monitor and the commissioning tool do.
        const bool direct = cfg.model == EvalSensorModel::kProduct && !cfg.footprint;
        const Result<FusionStats> r = direct ? fuse_background_frame(
                                                   background, frame.grid, {f.readings.data(), f.readings.size()},
                                                   table.value(), frame.fusion_scratch(), cfg.rasterization)
                                             : fuse_experiment_frame(cfg, table.value(), frame, f, footprint);
        if (!r.ok() || (!direct && !accumulate_background(background, frame.grid).ok())) {
            return false;
        }
        if (fuse_ms_total != nullptr) {
            *fuse_ms_total += ms_since(t1);
        }
        if (render_ms_total != nullptr) {
            *render_ms_total += std::chrono::duration<double, std::milli>(t1 - t0).count();
        }
    }
    return true;
}

bool compute_prior(const EvidenceGrid& background, const AccessibilityParams& params,
                   std::vector<std::int16_t>& prior) {
    const AccessibilityScratchSize size = accessibility_scratch_size(background.geometry().dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    prior.assign(background.voxel_count(), 0);
    AccessibilityScratch scratch;
    scratch.words = Span<std::uint32_t>(words.data(), words.size());
    scratch.bytes = Span<std::uint8_t>(bytes.data(), bytes.size());
    return compute_accessibility_prior(background, params, scratch, Span<std::int16_t>(prior.data(), prior.size()), {})
        .ok();
}

namespace {

/// Milliseconds spent in each phase of a scene, summed over its frames.
struct SceneTimes {
    double fuse_ms = 0.0;
    double render_ms = 0.0;
    double subtract_ms = 0.0;
    int subtractions = 0;
};

/// The scene's background grid: a copy of @p background if given, else fused from the scene's background frames
/// (@p fused_frames counts them).
bool prepare_background(const SceneFile& file, const ExperimentConfig& cfg, const EvidenceGrid* background,
                        SceneResult& out, SceneTimes& times, int& fused_frames, std::string& error) {
    if (background != nullptr) {
        if (!(background->geometry() == cfg.geometry)) {
            error = "the given background grid has another geometry";
            return false;
        }
        std::copy(background->log_odds().begin(), background->log_odds().end(), out.background_grid.log_odds.begin());
        std::copy(background->observed().begin(), background->observed().end(), out.background_grid.observed.begin());
        return true;
    }
    const Result<SensorModelTable> model = model_table(cfg);
    std::uint32_t need = 1U;
    for (const PriorMethod m : kAllMethods) {
        AccessibilityParams p = cfg.params;
        p.method = m;
        const std::uint32_t frames = !model.ok() ? 1U
                                     : cfg.model == EvalSensorModel::kPaper
                                         ? paper_min_background_frames(p.t_e, model.value())
                                         : min_background_frames(p, model.value());
        need = std::max(need, frames);
    }
    if (cfg.background_frames < 0 || static_cast<std::uint32_t>(cfg.background_frames) < need) {
        error = std::to_string(cfg.background_frames);
        error += " background frames are too few: the probabilistic method needs at least ";
        error += std::to_string(need);
        error += " for space seen free to fall below t_E (min_background_frames)";
        return false;
    }
    if (!build_background(file, cfg, out.background_grid.grid, &times.fuse_ms, &times.render_ms)) {
        error = "building the background grid failed";
        return false;
    }
    fused_frames += cfg.background_frames;
    return true;
}

/// Every method's prior from the scene's background grid, timed.
bool compute_priors(const ExperimentConfig& cfg, SceneResult& out, std::string& error) {
    for (std::size_t m = 0; m < kAllMethods.size(); ++m) {
        MethodResult& r = out.methods[m];
        r.method = kAllMethods[m];
        AccessibilityParams p = cfg.params;
        p.method = r.method;
        const Clock::time_point t0 = Clock::now();
        if (!compute_prior(out.background_grid.grid, p, r.prior)) {
            error = std::string("computing the prior failed: ") + method_name(r.method);
            return false;
        }
        r.prior_ms = ms_since(t0);
    }
    return true;
}

/// The foreground frames: each rendered, fused, and scored against the ground truth after each method's subtraction.
bool run_foreground(const SceneFile& file, const ExperimentConfig& cfg, const SensorModelTable& model, SceneResult& out,
                    SceneTimes& times, std::string& error) {
    const bool moving = !file.people.empty();
    std::unique_ptr<host::OwnedFootprintWorkspaces> footprint;
    for (int j = 0; j < cfg.foreground_frames; ++j) {
        const double t = j * cfg.frame_interval_s;
        const Scene scene = scene_at(file, t);
        if (j == 0 || moving) {
            const Clock::time_point t0 = Clock::now();
            out.last_truth = ideal_ground_truth(cfg.geometry, file.sensors, scene, cfg.rasterization);
            out.truth_ms += ms_since(t0);
        }
        const Clock::time_point t0 = Clock::now();
        const SimulatedFrame f = render(
            file, cfg, scene, file.seed * kSeedStride + kForegroundSeedOffset + static_cast<std::uint64_t>(j));
        const Clock::time_point t1 = Clock::now();
        times.render_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
        if (!fuse_experiment_frame(cfg, model, out.last_frame, f, footprint).ok()) {
            error = "fusing a foreground frame failed";
            return false;
        }
        times.fuse_ms += ms_since(t1);
        for (MethodResult& r : out.methods) {
            const Clock::time_point t2 = Clock::now();
            subtract_prior(out.last_frame.grid, r.prior, r.last_subtracted);
            times.subtract_ms += ms_since(t2);
            ++times.subtractions;
            add_scores(r.scores, r.last_subtracted, out.last_truth);
        }
        out.last_scene = scene;
    }
    return true;
}

}  // namespace

bool run_scene(const SceneFile& file, const ExperimentConfig& cfg, SceneResult& out, std::string& error,
               const EvidenceGrid* background) {
    out.name = file.name;
    out.background = background_of(file.scene);
    if (cfg.footprint && cfg.model == EvalSensorModel::kPaper) {
        error = "footprint fusion is the product model's path: the paper's model fuses ray by ray";
        return false;
    }
    SceneTimes times;
    int fused_frames = cfg.foreground_frames;
    if (!prepare_background(file, cfg, background, out, times, fused_frames, error)) {
        return false;
    }
    if (!compute_priors(cfg, out, error)) {
        return false;
    }
    const Result<SensorModelTable> model = model_table(cfg);
    if (!model.ok()) {
        error = "invalid sensor model";
        return false;
    }
    if (!run_foreground(file, cfg, model.value(), out, times, error)) {
        return false;
    }
    const int frames = fused_frames;
    out.fuse_ms_per_frame = frames > 0 ? times.fuse_ms / frames : 0.0;
    out.render_ms_per_frame = frames > 0 ? times.render_ms / frames : 0.0;
    out.subtract_ms_per_frame = times.subtractions > 0 ? times.subtract_ms / times.subtractions : 0.0;
    for (MethodResult& r : out.methods) {
        r.curve = fine_pr_curve(r.scores);
        r.summary = summarize(r.curve);
    }
    return true;
}

}  // namespace cellguard::sim
