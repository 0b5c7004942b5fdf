// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Ray traversal micro-benchmark: nanoseconds per voxel step of the exact
// traversal and of the 3D Bresenham line, on rays from the four upper corners
// of the 4 m x 4 m x 2 m cell to random points in it, into the paper's
// 34 x 30 x 30 grid and the 256 x 256 x 128 grid (5 cm voxels).
// A program that prints figures, not a test with a time limit.
//
// Usage: bench_traversal [rays] [repeats]   (defaults 200000 and 7; best run reported)
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

#include "cellguard/grid/ray_traversal.hpp"

using namespace cellguard;
namespace {

// CPU time of this thread: the machine is shared, wall time would count other processes.
double thread_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e9 + static_cast<double>(ts.tv_nsec);
}

struct Ray {
    Eigen::Vector3d start;
    Eigen::Vector3d end;
};

std::vector<Ray> make_rays(std::size_t count) {
    std::mt19937 rng(12345U);
    std::uniform_real_distribution<double> xy(-2.0, 2.0);
    std::uniform_real_distribution<double> z(0.0, 2.0);
    const Eigen::Vector3d sensors[4] = {Eigen::Vector3d(-1.9, -1.9, 1.9), Eigen::Vector3d(1.9, -1.9, 1.9),
                                        Eigen::Vector3d(1.9, 1.9, 1.9), Eigen::Vector3d(-1.9, 1.9, 1.9)};
    std::vector<Ray> rays(count);
    for (std::size_t i = 0; i < count; ++i) {
        rays[i] = Ray{sensors[i % 4U], Eigen::Vector3d(xy(rng), xy(rng), z(rng))};
    }
    return rays;
}

struct Figures {
    double ns_per_step;
    double ns_per_ray;
    double steps_per_ray;
};

// What fusion does per voxel, minus the sensor model: read-modify-write of the
// voxel's log-odds and its observed flag, with the distance in the update.
template <typename Walk>
Figures run(const GridGeometry& g, const std::vector<Ray>& rays, int repeats, Walk walk) {
    std::vector<std::int16_t> log_odds(g.voxel_count(), 0);
    std::vector<std::uint8_t> observed(g.voxel_count(), 0U);
    double best = 1e300;
    std::size_t steps = 0U;
    for (int r = 0; r < repeats; ++r) {
        std::size_t n = 0U;
        const double t0 = thread_ns();
        for (const Ray& ray : rays) {
            n += walk(g, ray.start, ray.end, [&](const TraversedVoxel& v) {
                log_odds[v.index] = static_cast<std::int16_t>(log_odds[v.index] - (v.t_exit > 0.5 ? 1 : 2));
                observed[v.index] = 1U;
            });
        }
        best = std::min(best, thread_ns() - t0);
        steps = n;
    }
    long checksum = 0;
    for (const std::int16_t v : log_odds)
        checksum += v;
    if (checksum == 1)
        std::puts("");  // keeps the updates alive
    return Figures{best / static_cast<double>(steps), best / static_cast<double>(rays.size()),
                   static_cast<double>(steps) / static_cast<double>(rays.size())};
}

// The traversal alone: a visitor that only sums indices.
template <typename Walk>
Figures run_bare(const GridGeometry& g, const std::vector<Ray>& rays, int repeats, Walk walk) {
    double best = 1e300;
    std::size_t steps = 0U;
    std::size_t sink = 0U;
    for (int r = 0; r < repeats; ++r) {
        std::size_t n = 0U;
        const double t0 = thread_ns();
        for (const Ray& ray : rays) {
            n += walk(g, ray.start, ray.end, [&](const TraversedVoxel& v) { sink += v.index; });
        }
        best = std::min(best, thread_ns() - t0);
        steps = n;
    }
    if (sink == 1U)
        std::puts("");
    return Figures{best / static_cast<double>(steps), best / static_cast<double>(rays.size()),
                   static_cast<double>(steps) / static_cast<double>(rays.size())};
}

// The per-segment set-up alone (clipping, end voxels, fixed-point crossings), ns per ray.
template <typename Plan>
double run_setup(const GridGeometry& g, const std::vector<Ray>& rays, int repeats, Plan plan) {
    double best = 1e300;
    std::size_t sink = 0U;
    for (int r = 0; r < repeats; ++r) {
        const double t0 = thread_ns();
        for (const Ray& ray : rays) {
            sink += static_cast<std::size_t>(plan(g, ray.start, ray.end).first_index);
        }
        best = std::min(best, thread_ns() - t0);
    }
    if (sink == 1U)
        std::puts("");
    return best / static_cast<double>(rays.size());
}

void print(const char* grid, const char* method, const char* visitor, const Figures& f, double setup_ns) {
    std::printf("%-12s %-10s %-12s %7.2f ns/step (loop %5.2f) %8.1f ns/ray (set-up %5.1f) %6.1f steps/ray\n", grid,
                method, visitor, f.ns_per_step, (f.ns_per_ray - setup_ns) / f.steps_per_ray, f.ns_per_ray, setup_ns,
                f.steps_per_ray);
}

}  // namespace

int main(int argc, char** argv) {
    const std::size_t count = argc > 1 ? static_cast<std::size_t>(std::strtoul(argv[1], nullptr, 10)) : 200000U;
    const int repeats = argc > 2 ? std::atoi(argv[2]) : 7;
    const std::vector<Ray> rays = make_rays(count);
    const auto exact = [](const GridGeometry& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b, auto&& v) {
        return traverse_segment(g, a, b, v);
    };
    const auto bres = [](const GridGeometry& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b, auto&& v) {
        return traverse_segment_bresenham(g, a, b, v);
    };
    std::printf("%zu rays from the four upper corners to random points in the cell; best of %d runs, thread CPU time\n",
                count, repeats);
    const struct {
        const char* name;
        GridGeometry g;
    } grids[2] = {{"34x30x30", paper_grid_geometry()}, {"256x256x128", whole_cell_grid_geometry()}};
    std::printf("ns/step: whole walk / voxels visited; loop: (walk - set-up) / voxels visited\n");
    for (const auto& grid : grids) {
        const double setup_exact = run_setup(grid.g, rays, repeats, detail::plan_exact_traversal);
        const double setup_bres = run_setup(grid.g, rays, repeats, detail::plan_bresenham_traversal);
        print(grid.name, "exact", "index sum", run_bare(grid.g, rays, repeats, exact), setup_exact);
        print(grid.name, "exact", "grid update", run(grid.g, rays, repeats, exact), setup_exact);
        print(grid.name, "bresenham", "index sum", run_bare(grid.g, rays, repeats, bres), setup_bres);
        print(grid.name, "bresenham", "grid update", run(grid.g, rays, repeats, bres), setup_bres);
    }
    return 0;
}
