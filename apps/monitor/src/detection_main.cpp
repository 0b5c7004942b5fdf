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
    "Time (the real cell on a 2-core x86-64 machine): about 20 ms a cycle noise-free,\n"
    "80 ms with noise (its generation dominates); the default (1,000 poses, 16 pieces,\n"
    "3 placements, 2 cycles, 2 priors) runs up to about 190,000 cycles.\n"
    "Exit status: 0 it ran, 1 the cell could not be set up, 2 bad command line or configuration.";

/// The command line's values before they become DetectionSettings.
struct Options {
    std::string config_path = CELLGUARD_REAL_CELL_CONFIG;
    DetectionSettings settings;
    int noise_tenths = 10;
    int flying_percent = 50;
    int dropout_tenths = 10;
    int edge_tenths = -1;      ///< -1: not given (with the three below: the configuration's [depth_filter])
    int tolerance_tenths = -1;
    int edge_radius = 0;
    int speckle_neighbours = -1;
    int seed = 1;
    std::string shape = "both";
    std::string prior = "both";
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
    cli.choice("--shape", o.shape, {"both", "cylinder", "sphere"}, "the pieces tried (default both)");
}

/// The settings the options of @p o give (in o.settings).
void settle_settings(Options& o) {
    DetectionSettings& s = o.settings;
    if (o.noise_tenths > 0) {
        s.noise = sim::tof_camera_noise(o.noise_tenths / 1000.0);
        s.noise.lidar.mixed_pixel_probability = o.flying_percent / 100.0;
        s.noise.lidar.missing_probability = o.dropout_tenths / 1000.0;
    } else {
        s.noise = sim::NoiseModel{};
    }
    s.seed = static_cast<std::uint64_t>(o.seed);
    if (o.edge_tenths > 0) {
        s.conditioning.edge_jump_per_m = o.edge_tenths / 1000.0;
        s.conditioning.edge_jump_min_m = 0.05;
    }
    s.conditioning.edge_radius = std::max(o.edge_radius, 1);
    s.conditioning.background_tolerance_per_m = std::max(o.tolerance_tenths, 0) / 1000.0;
    s.conditioning.speckle_min_neighbours = std::max(o.speckle_neighbours, 0);
    if (o.shape != "both") {
        const sim::PieceShape keep = o.shape == "sphere" ? sim::PieceShape::kSphere : sim::PieceShape::kCylinder;
        std::vector<PieceSize> kept;
        for (const PieceSize& size : s.sizes) {
            if (size.shape == keep) {
                kept.push_back(size);
            }
        }
        s.sizes = kept;
    }
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
    settle_settings(o);
    const cell::ConfigLoad load = cell::load_monitor_config(o.config_path);
    if (!load.ok) {
        static_cast<void>(std::fprintf(stderr, "%s: %s\n", kProgram, load.error.c_str()));
        return host::kExitUsage;
    }
    if (o.edge_tenths < 0 && o.tolerance_tenths < 0 && o.edge_radius == 0 && o.speckle_neighbours < 0) {
        o.settings.conditioning = load.config.depth_filter.filter;  // what the monitor runs with this file
    }
    const auto t0 = std::chrono::steady_clock::now();
    const DetectionResult result = run_detection(load.config, o.settings, stderr);
    if (!result.error.empty()) {
        static_cast<void>(std::fprintf(stderr, "%s: %s\n", kProgram, result.error.c_str()));
        return 1;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("detection capability: %s\n", o.config_path.c_str());
    write_detection_table(stdout, o.settings, result);
    std::printf("\n%llu cycles in %.0f s (%.1f ms a cycle)\n", static_cast<unsigned long long>(result.cycles_run),
                seconds, result.cycles_run > 0U ? 1000.0 * seconds / static_cast<double>(result.cycles_run) : 0.0);
    return 0;
}
