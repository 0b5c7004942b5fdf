// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-eval: the paper's experiments (sections IV-V) on the simulated
// workcell. Four methods (thresholded, probabilistic and their baselines
// without accessibility analysis) on the scenes "large" and "small", with
// the paper's parameters; writes precision-recall CSVs, a markdown table,
// precision-recall plots (gnuplot, when installed) and voxel renders like
// the paper's Figs. 4-7. Optionally the same on a 256 x 256 x 128 cell, with
// its fusion, prior and subtraction times.
#include <sys/stat.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/gnuplot.hpp"
#include "cellguard/host/io/png.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "render.hpp"

using namespace cellguard;

namespace {

#ifndef CELLGUARD_EVAL_SCENES_DIR
#define CELLGUARD_EVAL_SCENES_DIR "scenes"
#endif

struct Options {
    std::string scenes_dir = CELLGUARD_EVAL_SCENES_DIR;
    std::string out_dir = "eval-results";
    int background_frames = 100;
    int foreground_frames = 5;
    int scale_background_frames = 10;
    bool ideal = false;
    bool exact = false;
    bool footprint = false;
    bool plots = true;
    bool paper_scenes = true;
    bool scale = false;
    std::string model = "both";  ///< paper, product or both (paper first)
};

/// The file-name suffix of a model's outputs: none for the paper's (the paper's figures), "-product" for the
/// monitor's.
std::string suffix_of(sim::EvalSensorModel model) {
    return model == sim::EvalSensorModel::kPaper ? std::string() : std::string("-product");
}

/// A model's name in headings.
const char* title_of(sim::EvalSensorModel model) {
    return model == sim::EvalSensorModel::kPaper ? "the paper's sensor model" : "the product's sensor model";
}

std::string fmt(double v, int digits = 3) {
    if (v < 0.0) {
        return "n/a";
    }
    char buf[32];
    static_cast<void>(std::snprintf(buf, sizeof buf, "%.*f", digits, v));
    return buf;
}

/// Writes @p text to the file @p path; false (and says so) when that fails.
[[nodiscard]] bool write_text(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    f.close();
    if (!f) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: cannot write %s\n", path.c_str()));
        return false;
    }
    return true;
}

std::string csv_of(const sim::SceneResult& r) {
    std::ostringstream s;
    s << "method,t_f,tp,fp,fn,precision,recall,f1\n";
    for (const sim::MethodResult& m : r.methods) {
        for (const sim::PrPoint& p : m.curve) {
            char line[256];
            static_cast<void>(std::snprintf(line, sizeof line, "%s,%.3f,%llu,%llu,%llu,%.6f,%.6f,%.6f\n",
                                            sim::method_name(m.method), p.t_f, static_cast<unsigned long long>(p.tp),
                                            static_cast<unsigned long long>(p.fp),
                                            static_cast<unsigned long long>(p.fn), p.precision, p.recall, p.f1));
            s << line;
        }
    }
    return s.str();
}

std::string table_of(const sim::SceneResult& r) {
    std::ostringstream s;
    s << "| method | best F1 (at t_f) | precision at recall 0.9 | recall at precision 0.9 | max recall | "
         "precision at recall 0.6 | P / R at t_f 0.45 | P / R at t_f 0.2 | prior time (ms) |\n"
      << "|---|---|---|---|---|---|---|---|---|\n";
    for (const sim::MethodResult& m : r.methods) {
        const sim::PrSummary& q = m.summary;
        std::string at45;
        std::string at20;
        for (const sim::PrPoint& p : m.curve) {
            if (std::fabs(p.t_f - 0.45) < 1e-9) {
                at45 = fmt(p.precision) + " / " + fmt(p.recall);
            }
            if (std::fabs(p.t_f - 0.2) < 1e-9) {
                at20 = fmt(p.precision) + " / " + fmt(p.recall);
            }
        }
        s << "| " << sim::method_name(m.method) << " | " << fmt(q.best_f1) << " (" << fmt(q.best_f1_t_f, 2) << ") | "
          << fmt(q.precision_at_recall_90) << " | " << fmt(q.recall_at_precision_90) << " | " << fmt(q.max_recall)
          << " | " << fmt(sim::precision_at_recall(m.curve, 0.6)) << " | " << at45 << " | " << at20 << " | "
          << fmt(m.prior_ms, 1) << " |\n";
    }
    return s.str();
}

/// @p text for a single-quoted gnuplot string: each ' doubled.
std::string gnuplot_quoted(const std::string& text) {
    std::string out;
    for (const char c : text) {
        out += c;
        if (c == '\'') {
            out += '\'';
        }
    }
    return out;
}

/// Writes pr-<scene>.gp and runs gnuplot on it (@p scene: the scene's name and the model's suffix); false when
/// the script cannot be written.
[[nodiscard]] bool write_plot(const Options& o, const std::string& scene, const std::string& title) {
    const std::string gp = o.out_dir + "/pr-" + scene + ".gp";
    std::ostringstream s;
    s << "# gnuplot script written by cellguard-eval: precision-recall curves of pr-" << scene << ".csv\n"
      << "set terminal pngcairo size 720,540 font 'sans,11'\n"
      << "set output '" << gnuplot_quoted(o.out_dir) << "/pr-" << scene << ".png'\n"
      << "set datafile separator ','\n"
      << "set title '" << gnuplot_quoted(title) << "'\n"
      << "set xlabel 'recall'\nset ylabel 'precision'\n"
      << "set xrange [0:1]\nset yrange [0:1.02]\nset grid\nset key bottom left\n"
      << "f(m) = '" << gnuplot_quoted(o.out_dir) << "/pr-" << scene << ".csv'\n";
    const char* names[4] = {"thresholded", "probabilistic", "thresholded-baseline", "probabilistic-baseline"};
    const char* styles[4] = {"lw 2 pt 7 ps 0.5 lc rgb '#1f77b4'", "lw 2 pt 5 ps 0.5 lc rgb '#d62728'",
                             "lw 1.5 dt 2 pt 6 ps 0.5 lc rgb '#1f77b4'", "lw 1.5 dt 2 pt 4 ps 0.5 lc rgb '#d62728'"};
    s << "plot ";
    for (int i = 0; i < 4; ++i) {
        s << (i > 0 ? ", \\\n     " : "") << "f(0) skip 1 using (stringcolumn(1) eq '" << names[i]
          << "' ? $7 : 1/0):(stringcolumn(1) eq '" << names[i] << "' ? $6 : 1/0) with linespoints " << styles[i]
          << " title '" << names[i] << "'";
    }
    s << "\n";
    return host::write_and_run_gnuplot(gp, s.str(), "cellguard-eval", stderr);
}

std::vector<eval::VoxelClass> classes_for(const sim::SceneResult& r, const std::vector<std::int16_t>* subtracted,
                                          const sim::GroundTruth* truth, double t_f) {
    const GridGeometry& g = r.background_grid.grid.geometry();
    const std::int16_t fg = threshold_log_odds(t_f);
    std::vector<eval::VoxelClass> c(g.voxel_count(), eval::VoxelClass::kEmpty);
    const Span<std::int16_t> bg = r.background_grid.grid.log_odds();
    const Span<std::uint8_t> seen = r.background_grid.grid.observed();
    for (std::size_t i = 0; i < c.size(); ++i) {
        const bool is_fg = subtracted != nullptr ? (*subtracted)[i] != kNeverForeground && (*subtracted)[i] >= fg
                                                 : truth->label[i] == sim::Truth::kForeground;
        if (is_fg) {
            c[i] = eval::VoxelClass::kForeground;
        } else if (seen[i] != 0U && bg[i] > 0) {
            c[i] = g.coord_of(i).z == 0 ? eval::VoxelClass::kFloor : eval::VoxelClass::kBackground;
        }
    }
    return c;
}

void write_renders(const Options& o, const sim::SceneResult& r, const sim::SensorSpec& sensor) {
    const GridGeometry& g = r.background_grid.grid.geometry();
    // From the sensor's position, zoomed on the boxes (the lower part of the
    // grid) so that single voxels stay visible: 36 x 27 degrees, 640 x 480.
    sim::SensorSpec camera = sensor;
    camera.target = Eigen::Vector3d(0.0, 0.0, 0.3);
    camera.hfov_deg = 36.0;
    camera.vfov_deg = 27.0;
    for (const sim::MethodResult& m : r.methods) {
        const std::string path = o.out_dir + "/render-" + r.name + "-" + sim::method_name(m.method) + ".png";
        std::string error;
        if (!host::write_png(
                path, eval::render_voxels(g, classes_for(r, &m.last_subtracted, nullptr, 0.73), camera, 640, 480),
                error)) {
            static_cast<void>(std::fprintf(stderr, "cellguard-eval: cannot write %s\n", path.c_str()));
        }
    }
    const std::string path = o.out_dir + "/render-" + r.name + "-truth.png";
    std::string error;
    if (!host::write_png(path, eval::render_voxels(g, classes_for(r, nullptr, &r.last_truth, 0.73), camera, 640, 480),
                         error)) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: cannot write %s\n", path.c_str()));
    }
}

/// Foreground voxels of the last frame inside background boxes at t_f, and in the whole grid.
struct EmptyCheck {
    std::size_t inside = 0U;
    std::size_t anywhere = 0U;
};

EmptyCheck empty_check(const sim::SceneResult& r, const sim::MethodResult& m, double t_f) {
    const std::vector<std::uint8_t> interior = sim::background_interior_mask(r.background_grid.grid.geometry(),
                                                                             r.background);
    const std::int16_t fg = threshold_log_odds(t_f);
    EmptyCheck c;
    for (std::size_t i = 0; i < interior.size(); ++i) {
        const bool is_fg = m.last_subtracted[i] != kNeverForeground && m.last_subtracted[i] >= fg;
        c.anywhere += is_fg ? 1U : 0U;
        c.inside += is_fg && interior[i] != 0U ? 1U : 0U;
    }
    return c;
}

bool run(const Options& o, const std::string& scene_name, const sim::ExperimentConfig& cfg, sim::SceneFile& file,
         sim::SceneResult& result, const EvidenceGrid* background = nullptr) {
    const std::string path = o.scenes_dir + "/" + scene_name + ".toml";
    const sim::SceneLoad load = sim::load_scene_file(path);
    if (!load.ok) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: %s\n", load.error.c_str()));
        return false;
    }
    file = load.scene;
    std::printf("scene %s: %s\n", file.name.c_str(), file.description.c_str());
    static_cast<void>(std::fflush(stdout));
    std::string error;
    if (!sim::run_scene(file, cfg, result, error, background)) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: scene %s: %s\n", scene_name.c_str(), error.c_str()));
        return false;
    }
    std::printf("  truth: %zu foreground, %zu not foreground, %zu unknown voxels (last frame)\n",
                result.last_truth.foreground, result.last_truth.not_foreground, result.last_truth.unknown);
    std::printf("  per frame: simulation %.1f ms, fusion %.1f ms; subtraction %.3f ms; ground truth %.0f ms\n",
                result.render_ms_per_frame, result.fuse_ms_per_frame, result.subtract_ms_per_frame, result.truth_ms);
    for (const sim::MethodResult& m : result.methods) {
        std::printf("  %-24s prior %8.1f ms  best F1 %.3f (t_f %.2f)  P@R0.9 %s  R@P0.9 %s  max recall %.3f\n",
                    sim::method_name(m.method), m.prior_ms, m.summary.best_f1, m.summary.best_f1_t_f,
                    fmt(m.summary.precision_at_recall_90).c_str(), fmt(m.summary.recall_at_precision_90).c_str(),
                    m.summary.max_recall);
    }
    static_cast<void>(std::fflush(stdout));
    return true;
}

int run_scale(const Options& o, const sim::ExperimentConfig& base, std::ostringstream& md) {
    sim::ExperimentConfig cfg = base;
    // The whole 4 m x 4 m x 2 m cell at 1/64 m (1.5625 cm): r = 10 cm is 6.4 voxels, taken as 6.
    cfg.geometry = GridGeometry::make(Eigen::Vector3d(-2.0, -2.0, 0.0), 4.0 / 256.0, GridDims{256, 256, 128}).value();
    cfg.params.radius_voxels = 6;
    cfg.background_frames = o.scale_background_frames;
    cfg.foreground_frames = 2;
    sim::SceneFile file;
    sim::SceneResult result(cfg.geometry);
    std::printf(
        "scale run: 256 x 256 x 128 voxels of 1.5625 cm over the whole cell, r = 6 voxels, %d background frames\n",
        cfg.background_frames);
    if (!run(o, "large", cfg, file, result)) {
        return 1;
    }
    md << "## Scale: the large scene on a 256 x 256 x 128 grid\n\n"
       << "The whole 4 m x 4 m x 2 m cell at 1.5625 cm (8,388,608 voxels, 274 times the paper's grid), r = 6 voxels "
          "(9.4 cm), "
       << cfg.background_frames << " background frames, " << cfg.foreground_frames
       << " foreground frames; one thread, wall-clock times on a 2-core machine shared with other jobs (they vary "
          "by up to 2x between runs).\n\n"
       << "| step | time (ms) |\n|---|---|\n"
       << "| simulation of one frame (4 sensors, ray casting and noise) | " << fmt(result.render_ms_per_frame, 1)
       << " |\n"
       << "| fusion of one frame (204,288 rays) | " << fmt(result.fuse_ms_per_frame, 1) << " |\n";
    for (const sim::MethodResult& m : result.methods) {
        md << "| prior, " << sim::method_name(m.method) << " | " << fmt(m.prior_ms, 1) << " |\n";
    }
    md << "| subtraction of one frame (one method) | " << fmt(result.subtract_ms_per_frame, 2) << " |\n\n"
       << "Scores, for completeness; they are not comparable with the paper grid's: at 1.6 cm a voxel is as "
          "small as the sensor noise and the pixel footprint, so surfaces smear over several voxels and few rays "
          "cross each voxel; this run measures how the times grow.\n\n"
       << table_of(result) << "\n";
    return 0;
}

/// Reads the command line into @p o: -1 to run, else the exit status
/// (0 after --help or --version, 2 after a usage error).
int parse_args(int argc, char** argv, Options& o) {
    host::CommandLine cli(
        "cellguard-eval", "cellguard-eval [options]",
        "Runs the paper's experiments on the simulated workcell, with the paper's sensor model and the\n"
        "product's, and writes, into the output folder: pr-<scene>[-product].csv (precision and recall over a\n"
        "sweep of t_f, four methods), results.md (the models side by side; a table per scene: best F1,\n"
        "precision at recall 0.9, recall at precision 0.9; timings; the empty-scene check),\n"
        "pr-<scene>[-product].png (gnuplot, when installed) and render-<scene>-<method>.png (the paper's model:\n"
        "foreground red over the background grey at t_f = 0.73, from the sensor stereo-a, zoomed on the boxes).",
        "Exit status: 0 done, 1 an experiment or an output failed, 2 bad command line.");
    cli.text("--scenes", o.scenes_dir, "DIR",
             "scene files large.toml, small.toml, empty.toml, person.toml (default: the source tree's)");
    cli.text("--out", o.out_dir, "DIR", "output folder, created if missing (default eval-results)");
    cli.integer("--background-frames", o.background_frames, 1, 100000, "N",
                "empty frames summed into G_B (default 100)");
    cli.integer("--foreground-frames", o.foreground_frames, 1, 10000, "N",
                "frames with the foreground, scores summed (default 5)");
    cli.choice("--model", o.model, {"paper", "product", "both"},
               "sensor model of fusion: the paper's per-ray profile, the product's (the monitor's),\n"
               "or both, one after the other (default both; the product's files end in -product)");
    cli.flag("--ideal", o.ideal, "ideal sensors instead of the scenes' noise models");
    cli.flag("--exact", o.exact, "rasterise rays with the exact traversal (default: the paper's 3D Bresenham)");
    cli.flag("--footprint", o.footprint,
             "fuse depth images by footprint fusion (the product's model only; the ground truth stays\n"
             "ray by ray; compare with --exact)");
    bool no_plots = false;
    cli.flag("--no-plots", no_plots, "do not call gnuplot");
    cli.flag("--scale", o.scale,
             "also run the large scene on a 256 x 256 x 128 grid over the whole cell and\n"
             "print fusion, prior and subtraction times (scale.md)");
    bool scale_only = false;
    cli.flag("--scale-only", scale_only, "only that");
    cli.integer("--scale-background-frames", o.scale_background_frames, 1, 10000, "N",
                "G_B frames of the scale run (default 10)");
    const int status = cli.parse(argc, argv);
    if (status < 0 && o.footprint && o.model == "paper") {
        static_cast<void>(std::fprintf(
            stderr, "cellguard-eval: --footprint fuses with the product's model, not the paper's (see --help)\n"));
        return 2;
    }
    if (o.footprint) {
        o.model = "product";  // footprint fusion is the product model's path
    }
    o.plots = !no_plots;
    o.scale = o.scale || scale_only;
    o.paper_scenes = !scale_only;
    return status;
}

/// Creates the output folder @p dir if missing; false when it is not a folder afterwards.
bool make_output_folder(const std::string& dir) {
    static_cast<void>(::mkdir(dir.c_str(), 0777));  // EEXIST is fine: the stat below decides
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: cannot create the output folder %s\n", dir.c_str()));
        return false;
    }
    return true;
}

sim::ExperimentConfig experiment_config(const Options& o, sim::EvalSensorModel model) {
    sim::ExperimentConfig cfg;
    cfg.model = model;
    cfg.background_frames = o.background_frames;
    cfg.foreground_frames = o.foreground_frames;
    cfg.ideal_sensors = o.ideal;
    cfg.rasterization = o.exact ? Rasterization::kExact : Rasterization::kBresenham3d;
    cfg.footprint = o.footprint;
    return cfg;
}

/// The opening paragraph of results.md: grid, parameters, sensors, models, how the scores are read.
void write_results_intro(const Options& o, const sim::ExperimentConfig& cfg, std::ostringstream& md) {
    const SensorModelParams paper = sim::paper_profile();
    md << "# cellguard-eval results\n\n"
       << "Written by `cellguard-eval` (apps/evaluation). Grid: the paper's 34 x 30 x 30 voxels of 5 cm; r = 10 cm "
          "(2 voxels), t_B = "
       << cfg.params.t_b << ", t_E = " << cfg.params.t_e
       << "; sensors: " << (o.ideal ? "ideal" : "2 flash lidars and 2 stereo cameras with noise")
       << "; rasterisation: " << (o.exact ? "exact traversal" : "3D Bresenham")
       << (o.footprint ? "; fusion: footprint" : "") << "; one G_B (background.toml) from " << cfg.background_frames
       << " empty frames; scores summed over " << cfg.foreground_frames
       << " frames with the foreground. Two sensor models: **the paper's** (section IV: every ray adds its "
          "profile, trough "
       << paper.p_miss << " up to " << paper.ramp_length * 100.0 << " cm before the reading, peak " << paper.p_hit
       << " at it; files without a suffix) and **the product's** (the monitor's: one opinion per sensor, voxel "
          "and frame, p_miss "
       << cfg.sensor_model.p_miss << ", p_hit " << cfg.sensor_model.p_hit << ", pooled frame evidence clamped to ["
       << cfg.sensor_model.p_clamp_min << ", " << cfg.sensor_model.p_clamp_max
       << "]; files with the suffix -product). Each curve holds the t_f sweep 0.001, 0.005, 0.01 ... 0.99, 0.995, "
          "0.999 and the t_f where recall passes each 1/200. Precision at recall 0.9 is the largest precision "
          "among those t_f with recall >= 0.9 (n/a: recall 0.9 is never reached); recall at precision 0.9 "
          "likewise. P / R at t_f 0.45 and 0.2: precision and recall where the thresholded (below 0.5) and the "
          "probabilistic (below 0.25) baselines keep the interiors of the background boxes.\n\n";
}

/// Whether the plots are drawn: asked for and gnuplot installed (else says so).
bool plots_wanted(const Options& o) {
    const bool plots = o.plots && host::have_gnuplot();
    if (o.plots && !plots) {
        static_cast<void>(std::fprintf(
            stderr,
            "cellguard-eval: gnuplot not found: the precision-recall plots (pr-<scene>.png) are NOT drawn; "
            "the CSVs, tables and renders are written. Install gnuplot-nox (tools/install-deps.sh does) "
            "or pass --no-plots.\n"));
    }
    return plots;
}

/// Builds the one G_B every paper scene shares, from the background file they all include.
bool build_shared_background(const Options& o, const sim::ExperimentConfig& cfg, sim::OwnedGrid& background,
                             std::ostringstream& md) {
    const sim::SceneLoad bg_file = sim::load_scene_file(o.scenes_dir + "/background.toml");
    if (!bg_file.ok) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: %s\n", bg_file.error.c_str()));
        return false;
    }
    double fuse_ms = 0.0;
    double render_ms = 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    if (!sim::build_background(bg_file.scene, cfg, background.grid, &fuse_ms, &render_ms)) {
        static_cast<void>(std::fprintf(stderr, "cellguard-eval: building G_B failed\n"));
        return false;
    }
    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    static_cast<void>(std::printf(
        "G_B: %d frames in %.1f s (simulation %.1f ms/frame, fusion %.1f ms/frame), %zu of %zu voxels observed\n",
        cfg.background_frames, total_s, render_ms / cfg.background_frames, fuse_ms / cfg.background_frames,
        background.grid.observed_count(), background.grid.voxel_count()));
    md << "G_B: " << cfg.background_frames << " frames; " << background.grid.observed_count() << " of "
       << background.grid.voxel_count() << " voxels observed.\n\n";
    return true;
}

/// The paper grid's timings of one scene, for results.md.
void write_timing(const sim::SceneResult& result, std::ostringstream& md) {
    md << "Timing (paper grid, one core): simulation " << fmt(result.render_ms_per_frame, 1) << " ms/frame, fusion "
       << fmt(result.fuse_ms_per_frame, 1) << " ms/frame, subtraction " << fmt(result.subtract_ms_per_frame, 3)
       << " ms/frame, priors: ";
    for (const sim::MethodResult& m : result.methods) {
        md << sim::method_name(m.method) << " " << fmt(m.prior_ms, 1) << " ms; ";
    }
    md << "ground truth " << fmt(result.truth_ms, 0) << " ms.\n\n";
}

/// One method's figures on one scene under one model, for the comparison table.
struct ComparisonRow {
    std::string scene;
    sim::EvalSensorModel model = sim::EvalSensorModel::kPaper;
    PriorMethod method = PriorMethod::kThresholded;
    sim::PrSummary summary;
    double precision_at_recall_80 = -1.0;
    double precision_at_recall_50 = -1.0;
    double recall_at_precision_50 = 0.0;
    std::size_t distinct_recalls = 0U;
};

/// Appends the rows of @p r under @p model to @p rows.
void add_rows(const sim::SceneResult& r, sim::EvalSensorModel model, std::vector<ComparisonRow>& rows) {
    for (const sim::MethodResult& m : r.methods) {
        ComparisonRow row;
        row.scene = r.name;
        row.model = model;
        row.method = m.method;
        row.summary = m.summary;
        row.precision_at_recall_80 = sim::precision_at_recall(m.curve, 0.8);
        row.precision_at_recall_50 = sim::precision_at_recall(m.curve, 0.5);
        row.recall_at_precision_50 = sim::recall_at_precision(m.curve, 0.5);
        row.distinct_recalls = sim::distinct_recalls(m.curve);
        rows.push_back(row);
    }
}

/// The scenes with a foreground: CSV, table, plot, renders (large and small, the paper's model), the timing
/// (large); false when a scene fails. Clears @p written when an output file cannot be written.
bool run_foreground_scenes(const Options& o, const sim::ExperimentConfig& cfg, const EvidenceGrid& background,
                           bool plots, std::ostringstream& md, bool& written, std::vector<ComparisonRow>& rows) {
    const char* scenes[] = {"large", "small", "person"};
    const char* titles[] = {"large object (one more box)", "small object (a 2x4 on a box)",
                            "a walking person (not in the paper)"};
    const std::string suffix = suffix_of(cfg.model);
    for (int s = 0; s < 3; ++s) {
        sim::SceneFile file;
        sim::SceneResult result(cfg.geometry);
        if (!run(o, scenes[s], cfg, file, result, &background)) {
            return false;
        }
        add_rows(result, cfg.model, rows);
        written = write_text(o.out_dir + "/pr-" + result.name + suffix + ".csv", csv_of(result)) && written;
        md << "### Scene \"" << result.name << "\": " << file.description << "\n\n"
           << "Ground truth (last frame): " << result.last_truth.foreground << " foreground, "
           << result.last_truth.not_foreground << " not foreground, " << result.last_truth.unknown
           << " unknown (not scored) voxels.\n\n"
           << table_of(result) << "\n";
        if (plots) {
            const std::string title = std::string("Precision-recall, ") + titles[s] + ", " + title_of(cfg.model);
            written = write_plot(o, result.name + suffix, title) && written;
        }
        if (s < 2 && cfg.model == sim::EvalSensorModel::kPaper) {
            write_renders(o, result, file.sensors.size() > 2 ? file.sensors[2] : file.sensors.front());
        }
        if (s == 0) {
            write_timing(result, md);
        }
    }
    return true;
}

/// The empty scene: after subtraction nothing inside a background box may be foreground.
bool run_empty_scene(const Options& o, const sim::ExperimentConfig& cfg, const EvidenceGrid& background,
                     std::ostringstream& md) {
    sim::SceneFile file;
    sim::SceneResult result(cfg.geometry);
    if (!run(o, "empty", cfg, file, result, &background)) {
        return false;
    }
    md << "### Scene \"empty\": the background alone\n\n"
       << "Foreground voxels of the last frame after subtraction, inside background boxes (voxels wholly inside) "
          "and anywhere, at t_f = 0.001 and at the figures' t_f = 0.73.\n\n"
       << "| method | inside, t_f 0.001 | anywhere, t_f 0.001 | inside, t_f 0.73 | anywhere, t_f 0.73 |\n"
       << "|---|---|---|---|---|\n";
    for (const sim::MethodResult& m : result.methods) {
        const EmptyCheck lo = empty_check(result, m, 0.001);
        const EmptyCheck hi = empty_check(result, m, 0.73);
        md << "| " << sim::method_name(m.method) << " | " << lo.inside << " | " << lo.anywhere << " | " << hi.inside
           << " | " << hi.anywhere << " |\n";
        static_cast<void>(
            std::printf("  empty %-24s foreground inside boxes %zu (t_f 0.001) %zu (t_f 0.73), anywhere %zu / %zu\n",
                        sim::method_name(m.method), lo.inside, hi.inside, lo.anywhere, hi.anywhere));
    }
    md << "\n";
    return true;
}

/// The paper's scenes on one shared G_B under @p cfg's model, as a section of @p md; false when one fails.
bool run_paper_scenes(const Options& o, const sim::ExperimentConfig& cfg, bool plots, std::ostringstream& md,
                      bool& written, std::vector<ComparisonRow>& rows) {
    static_cast<void>(std::printf("== %s\n", title_of(cfg.model)));
    md << "## With " << title_of(cfg.model) << "\n\n";
    sim::OwnedGrid background(cfg.geometry);
    return build_shared_background(o, cfg, background, md) &&
           run_foreground_scenes(o, cfg, background.grid, plots, md, written, rows) &&
           run_empty_scene(o, cfg, background.grid, md);
}

/// The two models side by side: the plots, then per scene and method the figures of each model.
void write_comparison(const std::vector<sim::EvalSensorModel>& models, bool plots,
                      const std::vector<ComparisonRow>& rows, std::ostringstream& md) {
    md << "## The two sensor models side by side\n\n";
    if (plots && models.size() == 2U) {
        md << "| scene | " << title_of(models[0]) << " | " << title_of(models[1]) << " |\n|---|---|---|\n";
        for (const char* scene : {"large", "small", "person"}) {
            md << "| " << scene << " | ![" << scene << ", paper](pr-" << scene << ".png) | ![" << scene
               << ", product](pr-" << scene << "-product.png) |\n";
        }
        md << "\n";
    }
    md << "| scene | method | model | best F1 (t_f) | precision at recall 0.9 | at recall 0.8 | at recall 0.5 | "
          "recall at precision 0.5 | max recall | distinct recalls |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const char* scene : {"large", "small", "person"}) {
        for (const PriorMethod m : sim::kAllMethods) {
            for (const ComparisonRow& r : rows) {
                if (r.scene == scene && r.method == m) {
                    md << "| " << scene << " | " << sim::method_name(m) << " | " << sim::model_name(r.model) << " | "
                       << fmt(r.summary.best_f1) << " (" << fmt(r.summary.best_f1_t_f, 2) << ") | "
                       << fmt(r.summary.precision_at_recall_90) << " | " << fmt(r.precision_at_recall_80) << " | "
                       << fmt(r.precision_at_recall_50) << " | " << fmt(r.recall_at_precision_50) << " | "
                       << fmt(r.summary.max_recall) << " | " << r.distinct_recalls << " |\n";
                }
            }
        }
    }
    md << "\n";
}

/// The models --model names, the paper's first.
std::vector<sim::EvalSensorModel> models_of(const Options& o) {
    std::vector<sim::EvalSensorModel> m;
    if (o.model != "product") {
        m.push_back(sim::EvalSensorModel::kPaper);
    }
    if (o.model != "paper") {
        m.push_back(sim::EvalSensorModel::kProduct);
    }
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    const int parse_status = parse_args(argc, argv, o);
    if (parse_status >= 0) {
        return parse_status;
    }
    if (!make_output_folder(o.out_dir)) {
        return 1;
    }
    const std::vector<sim::EvalSensorModel> models = models_of(o);
    std::ostringstream md;
    write_results_intro(o, experiment_config(o, models.front()), md);
    const bool plots = plots_wanted(o);
    bool written = true;  // every output file written
    std::ostringstream sections;
    std::vector<ComparisonRow> rows;
    for (const sim::EvalSensorModel model : models) {
        if (o.paper_scenes && !run_paper_scenes(o, experiment_config(o, model), plots, sections, written, rows)) {
            return 1;
        }
    }
    int status = 0;
    if (o.scale) {
        std::ostringstream scale_md;
        status = run_scale(o, experiment_config(o, models.back()), scale_md);  // the product's, when run
        written = write_text(o.out_dir + "/scale.md", scale_md.str()) && written;
    }
    if (o.paper_scenes) {
        write_comparison(models, plots, rows, md);
        md << sections.str();
        written = write_text(o.out_dir + "/results.md", md.str()) && written;
        static_cast<void>(std::printf("wrote %s/results.md, pr-*.csv%s, render-*.png\n", o.out_dir.c_str(),
                                      plots ? ", pr-*.png" : ""));
    }
    return written ? status : 1;
}
