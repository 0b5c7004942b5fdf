// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-sim: the simulated workcell of the paper, fused frame by frame.
// Builds the background grid G_B from empty-cell frames, then fuses a frame
// with a foreground box and reports what the grid holds. Prints figures only
// (the zone monitor and its demo come with the monitor).
#include <chrono>
#include <cstdio>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/sim/workcell.hpp"

using namespace cellguard;

namespace {

struct Options {
    int frames = 20;
    bool bresenham = false;
};

/// Reads the command line into @p o: -1 to run, else the exit status (0
/// after --help or --version, 2 after a usage error).
int parse_args(int argc, char** argv, Options& o) {
    host::CommandLine cli("cellguard-sim", "cellguard-sim [--frames N] [--bresenham]",
                          "Fuses the paper's simulated workcell (4 sensors, reference scene) into the paper's\n"
                          "34 x 30 x 30 grid: N background frames into G_B, then one frame with a person-sized box.",
                          "Exit status: 0 done, 1 fusion failed, 2 bad command line.");
    cli.integer("--frames", o.frames, 1, 10000, "N", "background frames to accumulate (default 20)");
    cli.flag("--bresenham", o.bresenham, "rasterise rays with the paper's 3D Bresenham instead of the exact traversal");
    return cli.parse(argc, argv);
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (const int status = parse_args(argc, argv, opt); status >= 0) {
        return status;
    }
    const int frames = opt.frames;
    const Rasterization raster = opt.bresenham ? Rasterization::kBresenham3d : Rasterization::kExact;

    const GridGeometry g = paper_grid_geometry();
    std::vector<std::int16_t> bg_lo(g.voxel_count());
    std::vector<std::int16_t> fr_lo(g.voxel_count());
    std::vector<std::uint8_t> bg_ob(g.voxel_count());
    std::vector<std::uint8_t> fr_ob(g.voxel_count());
    EvidenceGrid background = EvidenceGrid::make(g, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    EvidenceGrid frame_grid = EvidenceGrid::make(g, {fr_lo.data(), fr_lo.size()}, {fr_ob.data(), fr_ob.size()}).value();
    background.clear();
    const SensorModelTable model;
    const auto sensors = sim::paper_sensors();

    const sim::SimulatedFrame empty = sim::render_frame(sensors, sim::reference_scene());
    double fuse_ms = 0.0;
    FusionStats stats;
    std::vector<std::int16_t> scratch(g.voxel_count());
    for (int f = 0; f < frames; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        const Result<FusionStats> r = fuse_background_frame(background, frame_grid,
                                                            {empty.readings.data(), empty.readings.size()}, model,
                                                            {scratch.data(), scratch.size()}, raster);
        fuse_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (!r.ok()) {
            static_cast<void>(
                std::fprintf(stderr, "cellguard-sim: fusing the background failed: %s\n", to_string(r.error())));
            return 1;
        }
        stats = r.value();
    }
    std::printf("background: %d frames, %u rays/frame (%u skipped), %.2f M voxel updates/frame, %.2f ms/frame mean\n",
                frames, stats.rays_fused, stats.skipped(), static_cast<double>(stats.voxel_updates) / 1e6,
                fuse_ms / frames);
    std::size_t occupied = 0;
    std::size_t free_seen = 0;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        if (bg_ob[i] == 0U) {
            continue;
        }
        occupied += bg_lo[i] > 0 ? 1U : 0U;
        free_seen += bg_lo[i] < 0 ? 1U : 0U;
    }
    std::printf("G_B: %zu voxels, %zu observed (%zu occupied, %zu free), %zu never observed\n", g.voxel_count(),
                background.observed_count(), occupied, free_seen, g.voxel_count() - background.observed_count());

    sim::Scene with_person = sim::reference_scene();
    with_person.boxes.push_back(sim::Box{{0.3, 0.45, 0.85}, {0.3, 0.3, 1.7}, 0.0, false});
    const sim::SimulatedFrame person = sim::render_frame(sensors, with_person);
    frame_grid.clear();
    const FusionStats ps = fuse_frame(frame_grid, {person.readings.data(), person.readings.size()}, model,
                                      {scratch.data(), scratch.size()}, raster)
                               .value();
    std::size_t new_occupied = 0;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        new_occupied += (fr_ob[i] != 0U && fr_lo[i] > 0 && bg_lo[i] <= 0) ? 1U : 0U;
    }
    std::printf(
        "frame with a 0.3 x 0.3 x 1.7 m box: %u readings in the grid, %zu voxels occupied that are free or unknown in G_B\n",
        ps.readings_in_grid, new_occupied);
    return 0;
}
