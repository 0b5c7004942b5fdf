// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fusion benchmark: the reference frame of shared/BENCHMARKING.md (four
// sensors, 204,288 rays) into the paper's 34 x 30 x 30 grid and into the
// 256 x 256 x 128 grid, against OctoMap on the same rays in the same run.
// A program that prints figures, not a test with a time limit.
//
// Usage: bench_fusion [frames] [--no-octomap]
//   frames: default 20; medians and max over frames.
//   --no-octomap: skip OctoMap (for callgrind runs, which count instructions).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_table.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "world_readings.hpp"

#ifdef CELLGUARD_HAVE_OCTOMAP
#include <octomap/octomap.h>
#endif

using namespace cellguard;
using Clock = std::chrono::steady_clock;

namespace {

struct Timing {
    double median_ms;
    double max_ms;
};

Timing summarise(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    return Timing{ms[ms.size() / 2], ms.back()};
}

struct GridRun {
    Timing t;
    FusionStats stats;
};

GridRun run_cellguard(const GridGeometry& g, const std::vector<SensorReading>& readings, int frames,
                      Rasterization raster) {
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()),
                                           Span<std::uint8_t>(ob.data(), ob.size()))
                            .value();
    const SensorModelTable model;
    std::vector<double> ms;
    std::vector<std::int16_t> scratch(g.voxel_count());
    FusionStats stats;
    for (int f = 0; f < frames; ++f) {
        const auto t0 = Clock::now();
        grid.clear();
        stats = fuse_frame(grid, Span<const SensorReading>(readings.data(), readings.size()), model,
                           {scratch.data(), scratch.size()}, raster)
                    .value();
        const auto t1 = Clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    return GridRun{summarise(ms), stats};
}

// The same frames through precomputed ray tables (built once, outside the timing).
GridRun run_ray_tables(const GridGeometry& g, const std::vector<SensorReading>& readings, int frames,
                       std::size_t* table_bytes) {
    std::vector<host::OwnedRayTable> tables(readings.size());
    *table_bytes = 0;
    for (std::size_t s = 0; s < readings.size(); ++s) {
        if (!tables[s].build(g, readings[s]).ok()) {
            std::fprintf(stderr, "bench_fusion: ray table of sensor %zu refused\n", s);
            std::exit(2);
        }
        *table_bytes += tables[s].storage_bytes();
    }
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()),
                                           Span<std::uint8_t>(ob.data(), ob.size()))
                            .value();
    const SensorModelTable model;
    std::vector<double> ms;
    FusionStats stats;
    for (int f = 0; f < frames; ++f) {
        const auto t0 = Clock::now();
        grid.clear();
        stats = FusionStats{};
        for (std::size_t s = 0; s < readings.size(); ++s) {
            stats.add(tables[s].table().fuse(grid, readings[s].depth, model).value());
        }
        const auto t1 = Clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    return GridRun{summarise(ms), stats};
}

// World-frame rays (origin, reading) of every valid pixel, as fusion sees them.
struct Ray {
    Eigen::Vector3d origin;
    Eigen::Vector3d end;
};

std::vector<Ray> world_rays(const std::vector<SensorReading>& readings) {
    std::vector<Ray> rays;
    for (const SensorReading& r : readings) {
        bench::for_each_world_reading(r, [&](const Eigen::Vector3d& w) {
            rays.push_back(Ray{r.pose.translation(), w});
        });
    }
    return rays;
}

#ifdef CELLGUARD_HAVE_OCTOMAP
// Whole rays: OctoMap's own insertPointCloud, one call per sensor, fresh map per frame.
Timing run_octomap_whole(const std::vector<SensorReading>& readings, int frames, std::size_t* nodes) {
    std::vector<octomap::Pointcloud> clouds(readings.size());
    std::vector<octomap::point3d> origins;
    const std::vector<Ray> rays = world_rays(readings);
    for (const SensorReading& r : readings) {
        const Eigen::Vector3d o = r.pose.translation();
        origins.emplace_back(static_cast<float>(o.x()), static_cast<float>(o.y()), static_cast<float>(o.z()));
    }
    for (const Ray& ray : rays) {
        for (std::size_t s = 0; s < readings.size(); ++s) {
            if ((ray.origin - readings[s].pose.translation()).norm() < 1e-9) {
                clouds[s].push_back(static_cast<float>(ray.end.x()), static_cast<float>(ray.end.y()),
                                    static_cast<float>(ray.end.z()));
                break;
            }
        }
    }
    std::vector<double> ms;
    for (int f = 0; f < frames; ++f) {
        octomap::OcTree tree(0.05);
        const auto t0 = Clock::now();
        for (std::size_t s = 0; s < clouds.size(); ++s) {
            tree.insertPointCloud(clouds[s], origins[s], -1.0, false, false);
        }
        const auto t1 = Clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        *nodes = tree.size();
    }
    return summarise(ms);
}

// Clipped segments: the same rays clipped to the paper's grid box, with
// OctoMap's insertPointCloud semantics (free key set, occupied key set, each
// key updated at most once per sensor scan); the reading counts as occupied
// only when it lies inside the box.
Timing run_octomap_clipped(const std::vector<SensorReading>& readings, const GridGeometry& g, int frames) {
    const std::vector<Ray> rays = world_rays(readings);
    const Eigen::Vector3d lo = g.origin();
    const Eigen::Vector3d hi = g.max_corner();
    struct Seg {
        octomap::point3d a, b;
        bool occupied_end;
        std::size_t sensor;
    };
    std::vector<Seg> segs;
    for (const Ray& r : rays) {
        const Eigen::Vector3d d = r.end - r.origin;
        double t0 = 0.0, t1 = 1.0;
        bool hit = true;
        for (int a = 0; a < 3 && hit; ++a) {
            if (std::abs(d[a]) < 1e-15) {
                hit = r.origin[a] >= lo[a] && r.origin[a] < hi[a];
                continue;
            }
            double ta = (lo[a] - r.origin[a]) / d[a], tb = (hi[a] - r.origin[a]) / d[a];
            if (ta > tb)
                std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
            hit = t0 < t1;
        }
        if (!hit)
            continue;
        const Eigen::Vector3d a = r.origin + t0 * d, b = r.origin + t1 * d;
        std::size_t s = 0;
        while (s + 1 < readings.size() && (r.origin - readings[s].pose.translation()).norm() > 1e-9)
            ++s;
        segs.push_back(Seg{octomap::point3d(float(a.x()), float(a.y()), float(a.z())),
                           octomap::point3d(float(b.x()), float(b.y()), float(b.z())), t1 >= 1.0, s});
    }
    std::vector<double> ms;
    for (int f = 0; f < frames; ++f) {
        octomap::OcTree tree(0.05);
        const auto t0 = Clock::now();
        for (std::size_t s = 0; s < readings.size(); ++s) {
            octomap::KeySet free_cells, occupied_cells;
            octomap::KeyRay keyray;
            for (const Seg& seg : segs) {
                if (seg.sensor != s)
                    continue;
                if (tree.computeRayKeys(seg.a, seg.b, keyray))
                    free_cells.insert(keyray.begin(), keyray.end());
                octomap::OcTreeKey k;
                if (seg.occupied_end && tree.coordToKeyChecked(seg.b, k))
                    occupied_cells.insert(k);
            }
            for (const auto& k : occupied_cells)
                free_cells.erase(k);
            for (const auto& k : free_cells)
                tree.updateNode(k, false);
            for (const auto& k : occupied_cells)
                tree.updateNode(k, true);
        }
        const auto t1 = Clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    return summarise(ms);
}
#endif

void print_run(const char* label, const GridRun& r) {
    const double rays = r.stats.rays_fused;
    const double upd = static_cast<double>(r.stats.voxel_updates);
    std::printf("%-44s median %8.2f ms  max %8.2f ms  %7.2f Mrays/s  %8.1f Mupdates/s  (%u rays, %.2f M updates)\n",
                label, r.t.median_ms, r.t.max_ms, rays / r.t.median_ms / 1e3, upd / r.t.median_ms / 1e3,
                r.stats.rays_fused, upd / 1e6);
}

}  // namespace

int main(int argc, char** argv) {
    const int frames = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
    bool with_octomap = true;
    for (int i = 1; i < argc; ++i) {
        if (std::string(argv[i]) == "--no-octomap")
            with_octomap = false;
    }
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    std::printf(
        "cellguard fusion benchmark: 4 sensors (2 x 176x144, 2 x 320x240), %d frames, one thread, fresh grid per frame\n",
        frames);
    const GridRun paper = run_cellguard(paper_grid_geometry(), frame.readings, frames, Rasterization::kExact);
    const GridRun large = run_cellguard(whole_cell_grid_geometry(), frame.readings, frames, Rasterization::kExact);
    const GridRun paper_b = run_cellguard(paper_grid_geometry(), frame.readings, frames, Rasterization::kBresenham3d);
    std::size_t paper_table_bytes = 0, large_table_bytes = 0;
    const GridRun paper_t = run_ray_tables(paper_grid_geometry(), frame.readings, frames, &paper_table_bytes);
    const GridRun large_t = run_ray_tables(whole_cell_grid_geometry(), frame.readings, frames, &large_table_bytes);
    print_run("cellguard, paper grid 34x30x30, exact", paper);
    print_run("cellguard, paper grid, precomputed rays", paper_t);
    print_run("cellguard, large grid, precomputed rays", large_t);
    std::printf("precomputed ray tables: %.1f MiB for the paper grid, %.1f MiB for the large grid\n",
                paper_table_bytes / 1048576.0, large_table_bytes / 1048576.0);
    print_run("cellguard, paper grid 34x30x30, Bresenham", paper_b);
    print_run("cellguard, large grid 256x256x128, exact", large);
    const double best_paper = std::min(paper.t.median_ms, paper_t.t.median_ms);
    const double best_large = std::min(large.t.median_ms, large_t.t.median_ms);
    std::printf("goal: a full frame in the paper's grid within 5 ms on one core: %s (%.2f ms median, best mode)\n",
                best_paper <= 5.0 ? "met" : "NOT met", best_paper);
#ifdef CELLGUARD_HAVE_OCTOMAP
    if (!with_octomap)
        return 0;
    std::size_t nodes = 0;
    const Timing oct_whole = run_octomap_whole(frame.readings, std::max(3, frames / 4), &nodes);
    const Timing oct_clip = run_octomap_clipped(frame.readings, paper_grid_geometry(), std::max(3, frames / 4));
    std::printf("%-44s median %8.2f ms  max %8.2f ms  (%zu nodes)\n", "OctoMap insertPointCloud, whole rays",
                oct_whole.median_ms, oct_whole.max_ms, nodes);
    std::printf("%-44s median %8.2f ms  max %8.2f ms\n", "OctoMap, same segments clipped to paper grid",
                oct_clip.median_ms, oct_clip.max_ms);
    std::printf(
        "ratio (same whole rays, large grid vs OctoMap):        %.1fx exact traversal, %.1fx precomputed rays\n",
        oct_whole.median_ms / large.t.median_ms, oct_whole.median_ms / large_t.t.median_ms);
    std::printf(
        "ratio (same clipped segments, paper grid vs OctoMap):  %.1fx exact traversal, %.1fx precomputed rays\n",
        oct_clip.median_ms / paper.t.median_ms, oct_clip.median_ms / paper_t.t.median_ms);
    std::printf(
        "note: OctoMap applies a voxel at most once per scan and stops at its clamping limits; the evidence grid adds every ray.\n");
    std::printf("goal: at least 20x OctoMap on the same rays: %s\n",
                oct_whole.median_ms / best_large >= 20.0 ? "met" : "NOT met");
#else
    std::printf("OctoMap not found at configure time: no ratio (install liboctomap-dev)\n");
#endif
    return 0;
}
