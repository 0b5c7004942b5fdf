// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-detection: the detection-capability experiment (detection.hpp)
// on a monitor configuration, by default apps/monitor/config/real-cell.toml.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cli.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/gnuplot.hpp"
#include "cellguard/monitor/detection.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

constexpr const char* kProgram = "cellguard-detection";

constexpr const char* kDescription =
    "Places test pieces (cylinders 300 mm long and spheres of 20, 30, 40, 55, 70, 100,\n"
    "150 and 200 mm diameter) at seeded random poses inside one zone of a monitor\n"
    "configuration (free in the zone, lying on the floor, lying on a box's top), renders them into the\n"
    "simulated cameras with time-of-flight noise (1 % of range, flying pixels at depth\n"
    "edges, 1 % dropouts; --noise-percent 0: noise-free), and runs the monitor's cycle\n"
    "on them with the probabilistic and the thresholded prior. A pose is detected when\n"
    "the zone is INTRUDED in one of the --cycles cycles the piece stays. Prints per\n"
    "prior, piece and placement the poses detected and the one-sided 95 % Clopper-\n"
    "Pearson lower bound, the empty cell's cycles with the zone INTRUDED under the same\n"
    "noise, and the smallest diameter detected in every pose (every larger one too).";

constexpr const char* kFooter =
    "Time (the real cell on a 2-core x86-64 machine, one core): about 20 ms a cycle\n"
    "noise-free, 65 ms with noise and the depth filter (the noise's generation and the\n"
    "filter dominate); the default (1,000 poses, 16 pieces, 3 placements, 2 cycles, 2\n"
    "priors) runs up to about 190,000 cycles: about 1 h noise-free, 3.5 h with noise;\n"
    "--jobs 2 runs two shards on two cores (80,024 noisy cycles in 49 min, 2026-12-07).\n"
    "Progress: a line on the standard error at every per cent, with the time left.\n"
    "Exit status: 0 it ran, 1 the cell could not be set up, 2 bad command line or configuration.";

/// The command line's values before they become DetectionSettings.
struct Options {
    std::string config_path = CELLGUARD_REAL_CELL_CONFIG;
    DetectionSettings settings;
    int noise_tenths = 10;
    int flying_percent = 50;
    int dropout_tenths = 10;
    int edge_tenths = -1;  ///< -1: not given (with the three below: the configuration's [depth_filter])
    int tolerance_tenths = -1;
    int edge_radius = 0;
    int speckle_neighbours = -1;
    int seed = 1;
    int smallest_mm = 0;  ///< --smallest-mm: pieces of at least this diameter (0: every size)
    std::string shape = "both";
    std::string prior = "both";
    std::string csv;   ///< --csv: the rows as CSV ("": none, or beside --plot)
    std::string plot;  ///< --plot: the rates against the diameter as PNG, through gnuplot
};

/// Declares the options of @p o on @p cli.
void declare(host::CommandLine& cli, Options& o) {
    DetectionSettings& s = o.settings;
    cli.text("--config", o.config_path, "FILE", "the monitor configuration (default: the real cell)");
    cli.text("--zone", s.zone, "NAME", "the zone the pieces are placed in (default: protective)");
    cli.integer("--poses", s.poses, 1, 1000000, "N", "poses per prior, piece and placement (default 1000)");
    cli.integer("--cycles", s.cycles, 1, 100, "K", "cycles each piece stays (default 2)");
    cli.integer("--empty-cycles", s.empty_cycles, 0, 10000000, "N", "empty-cell cycles per prior (default 200)");
    cli.integer("--noise-tenths", o.noise_tenths, 0, 100, "T",
                "range noise in tenths of a percent of range (default 10: 1 %; 0: noise-free frames)");
    cli.integer("--flying-percent", o.flying_percent, 0, 100, "P",
                "chance that a pixel at a depth edge of more than 5 cm reads a mix of both depths (default 50)");
    cli.integer("--dropout-tenths", o.dropout_tenths, 0, 1000, "T",
                "pixels without a reading, in tenths of a percent (default 10: 1 %)");
    // The depth filter: the configuration's [depth_filter] (what the monitor runs) unless one of
    // these four is given; then these, each one not given off.
    cli.integer("--edge-filter-tenths", o.edge_tenths, 0, 1000, "T",
                "the depth filter's edge filter: drop a reading that differs from a reading --edge-radius pixels "
                "away or nearer by more than T tenths of a percent of its depth (at least 5 cm); 0: off. Without "
                "this and the three below: the configuration's [depth_filter]");
    cli.integer("--edge-radius", o.edge_radius, 1, 4, "R",
                "the edge filter compares readings up to R pixels away along rows and columns (default 1)");
    cli.integer("--background-tolerance-tenths", o.tolerance_tenths, 0, 200, "T",
                "a reading within T tenths of a percent of the empty cell's depth of its pixel reads that depth; "
                "0: off");
    cli.integer("--speckle-neighbours", o.speckle_neighbours, 0, 8, "N",
                "drop a reading in front of the empty cell with fewer than N of its 8 neighbours in front too; "
                "0: off");
    cli.integer("--seed", o.seed, 0, 2000000000, "S", "seed of the poses and the noise (default 1)");
    cli.choice("--prior", o.prior, {"both", "probabilistic", "thresholded"}, "the priors compared (default both)");
    cli.integer("--jobs", s.jobs, 1, kMaxDetectionJobs, "N",
                "threads, each a shard of the poses and empty cycles with noise of its own (default 1)");
    cli.integer("--smallest-mm", o.smallest_mm, 0, 200, "D",
                "only the pieces of at least D mm diameter (default: every size)");
    cli.choice("--shape", o.shape, {"both", "cylinder", "sphere"}, "the pieces tried (default both)");
    cli.text("--csv", o.csv, "FILE", "also write the rows as CSV to FILE");
    cli.text("--plot", o.plot, "FILE.png",
             "also draw the detection rate against the diameter (one line per prior, piece and placement) with "
             "gnuplot, when installed: FILE.gp is its script, the CSV FILE.csv unless --csv names one");
}

/// PATH without its extension (the last '.' after the last '/').
std::string without_extension(const std::string& path) {
    const std::size_t dot = path.rfind('.');
    const std::size_t slash = path.rfind('/');
    return dot != std::string::npos && (slash == std::string::npos || dot > slash) ? path.substr(0, dot) : path;
}

/// --csv and --plot: writes the CSV and the plot of @p result; false when a file cannot be written.
bool write_outputs(const Options& o, const DetectionResult& result) {
    const std::string csv = !o.csv.empty() ? o.csv : !o.plot.empty() ? without_extension(o.plot) + ".csv" : "";
    if (csv.empty()) {
        return true;
    }
    host::FilePtr f = host::open_file(csv.c_str(), "w");
    if (!f) {
        static_cast<void>(std::fprintf(stderr, "%s: cannot write %s\n", kProgram, csv.c_str()));
        return false;
    }
    write_detection_csv(f.get(), o.config_path, result);
    if (!host::close_file(f)) {
        static_cast<void>(std::fprintf(stderr, "%s: cannot write %s\n", kProgram, csv.c_str()));
        return false;
    }
    if (o.plot.empty()) {
        return true;
    }
    char noise[32];
    static_cast<void>(std::snprintf(noise, sizeof noise, "%.1f %% noise", o.noise_tenths / 10.0));
    const std::string title = "detection rate, zone " + o.settings.zone + ", " +
                              (o.noise_tenths > 0 ? noise : "noise-free") +
                              (o.settings.conditioning.on() ? ", depth filter on" : "");
    return host::write_and_run_gnuplot(without_extension(o.plot) + ".gp", detection_plot_script(o.plot, title, result),
                                       kProgram, stderr);
}

/// The depth filter of the run: @p configured (the configuration's) unless
/// one of the filter options is given; then the options', each one not given off.
cell::DepthConditioning depth_filter(const Options& o, const cell::DepthConditioning& configured) {
    if (o.edge_tenths < 0 && o.tolerance_tenths < 0 && o.edge_radius == 0 && o.speckle_neighbours < 0) {
        return configured;  // what the monitor runs with this file
    }
    cell::DepthConditioning f;
    if (o.edge_tenths > 0) {
        f.edge_jump_per_m = o.edge_tenths / 1000.0;
        f.edge_jump_min_m = 0.05;
    }
    f.edge_radius = std::max(o.edge_radius, 1);
    f.background_tolerance_per_m = std::max(o.tolerance_tenths, 0) / 1000.0;
    f.speckle_min_neighbours = std::max(o.speckle_neighbours, 0);
    return f;
}

/// The settings the options of @p o give (in o.settings), the filter of @p cfg unless the options set one.
void settle_settings(Options& o, const cell::MonitorConfig& cfg) {
    DetectionSettings& s = o.settings;
    if (o.noise_tenths > 0) {
        s.noise = sim::tof_camera_noise(o.noise_tenths / 1000.0);
        s.noise.lidar.mixed_pixel_probability = o.flying_percent / 100.0;
        s.noise.lidar.missing_probability = o.dropout_tenths / 1000.0;
    } else {
        s.noise = sim::NoiseModel{};
    }
    s.seed = static_cast<std::uint64_t>(o.seed);
    s.conditioning = depth_filter(o, cfg.depth_filter.filter);
    const sim::PieceShape only = o.shape == "sphere" ? sim::PieceShape::kSphere : sim::PieceShape::kCylinder;
    std::vector<PieceSize> kept;
    for (const PieceSize& size : s.sizes) {
        if ((o.shape == "both" || size.shape == only) && size.diameter * 1000.0 >= o.smallest_mm - 1e-9) {
            kept.push_back(size);
        }
    }
    s.sizes = kept;
    if (o.prior != "both") {
        s.methods = {o.prior == "thresholded" ? PriorMethod::kThresholded : PriorMethod::kProbabilistic};
    }
}

}  // namespace

int main(int argc, char** argv) {
    host::CommandLine cli(kProgram, "cellguard-detection [options]", kDescription, kFooter);
    Options o;
    declare(cli, o);
    if (const int status = cli.parse(argc, argv); status >= 0) {
        return status;
    }
    const cell::ConfigLoad load = cell::load_monitor_config(o.config_path);
    if (!load.ok) {
        static_cast<void>(std::fprintf(stderr, "%s: %s\n", kProgram, load.error.c_str()));
        return host::kExitUsage;
    }
    settle_settings(o, load.config);
    const auto t0 = std::chrono::steady_clock::now();
    const DetectionResult result = run_detection(load.config, o.settings, stderr);
    if (!result.error.empty()) {
        static_cast<void>(std::fprintf(stderr, "%s: %s\n", kProgram, result.error.c_str()));
        return 1;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("detection capability: %s\n", o.config_path.c_str());
    write_detection_table(stdout, o.settings, result, 1e6 / static_cast<double>(load.config.period_us));
    if (!write_outputs(o, result)) {
        return 1;
    }
    std::printf("\n%llu cycles in %.0f s (%.1f ms a cycle)\n", static_cast<unsigned long long>(result.cycles_run),
                seconds, result.cycles_run > 0U ? 1000.0 * seconds / static_cast<double>(result.cycles_run) : 0.0);
    return 0;
}
