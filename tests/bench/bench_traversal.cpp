// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Ray traversal micro-benchmark: nanoseconds per voxel step of the exact
// traversal and of the 3D Bresenham line, on rays from the four upper corners
// of the 4 m x 4 m x 2 m cell to random points in it, into the paper's
// 34 x 30 x 30 grid and the 256 x 256 x 128 grid (5 cm voxels).
// A program that prints figures, not a test with a time limit.
//
// It also compares the exact traversal with a plain textbook Amanatides & Woo
// (1987) traversal in double on the same rays, same grid and same work per
// visit, interleaved round by round in the same run: medians over the rounds
// and the median of the per-round ratios exact / plain (shared/BENCHMARKING.md).
// The work per visit is either an index sum (the traversal alone) or what
// fusion does: the max of the sensor's opinion per voxel (trace_ray_opinions
// against the same visitor written around the plain traversal).
//
// Usage: bench_traversal [rays] [repeats] [rounds]
//   defaults 200000, 7 (best run reported in the first table) and 15 (rounds of the comparison)
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "world_readings.hpp"

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

// The rays of the reference frame (shared/BENCHMARKING.md), as bench_fusion makes them.
std::vector<Ray> reference_frame_rays() {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    std::vector<Ray> rays;
    for (const SensorReading& r : frame.readings) {
        bench::for_each_world_reading(r, [&](const Eigen::Vector3d& w) {
            rays.push_back(Ray{r.pose.translation(), w});
        });
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

// A plain textbook Amanatides & Woo traversal in double, the reference: slab
// clipping to the grid box in metres, the entry voxel by floor (clamped), then
// per step the axis with the nearest crossing (one axis at a time, branches),
// t_exit = that crossing clipped to the segment. Not the library's contract
// (edges and corners are stepped one axis at a time, rounding is not
// controlled); only its cost matters here.
template <typename Visit>
std::size_t plain_aw(const GridGeometry& g, const Eigen::Vector3d& a, const Eigen::Vector3d& b, Visit&& visit) {
    const Eigen::Vector3d d = b - a;
    const double length = d.norm();
    if (!(length > 0.0)) {
        return 0U;
    }
    const Eigen::Vector3d dir = d / length;
    const GridDims dims = g.dims();
    const std::int32_t n[3] = {dims.nx, dims.ny, dims.nz};
    const double vs = g.voxel_size();
    const Eigen::Vector3d o = g.origin();
    double t0 = 0.0;
    double t1 = length;
    for (int i = 0; i < 3; ++i) {
        const double lo = o[i];
        const double hi = o[i] + n[i] * vs;
        if (dir[i] == 0.0) {
            if (a[i] < lo || a[i] >= hi) {
                return 0U;
            }
            continue;
        }
        const double ta = (lo - a[i]) / dir[i];
        const double tb = (hi - a[i]) / dir[i];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    if (t0 > t1) {
        return 0U;
    }
    std::int32_t c[3];
    std::int32_t step[3];
    double tmax[3];
    double tdelta[3];
    const std::ptrdiff_t stride[3] = {1, n[0], static_cast<std::ptrdiff_t>(n[0]) * n[1]};
    std::ptrdiff_t sstride[3];
    for (int i = 0; i < 3; ++i) {
        const double u = (a[i] + t0 * dir[i] - o[i]) / vs;
        c[i] = std::min(std::max(static_cast<std::int32_t>(std::floor(u)), 0), n[i] - 1);
        if (dir[i] > 0.0) {
            step[i] = 1;
            tdelta[i] = vs / dir[i];
            tmax[i] = (o[i] + (c[i] + 1) * vs - a[i]) / dir[i];
        } else if (dir[i] < 0.0) {
            step[i] = -1;
            tdelta[i] = -vs / dir[i];
            tmax[i] = (o[i] + c[i] * vs - a[i]) / dir[i];
        } else {
            step[i] = 0;
            tdelta[i] = 0.0;
            tmax[i] = 1e300;
        }
        sstride[i] = step[i] * stride[i];
    }
    std::ptrdiff_t index = c[0] + stride[1] * c[1] + stride[2] * c[2];
    double t_enter = t0;
    std::size_t visited = 0U;
    for (;;) {
        const int axis = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
        const double t_exit = std::min(tmax[axis], t1);
        visit(TraversedVoxel{static_cast<std::size_t>(index), VoxelCoord{c[0], c[1], c[2]}, t_enter, t_exit});
        ++visited;
        if (tmax[axis] >= t1) {
            break;
        }
        c[axis] += step[axis];
        if (c[axis] < 0 || c[axis] >= n[axis]) {
            break;
        }
        index += sstride[axis];
        t_enter = tmax[axis];
        tmax[axis] += tdelta[axis];
    }
    return visited;
}

// trace_ray_opinions's work written around the plain traversal: the voxel
// holding the reading gets the hit, every other one the max of its free
// opinion free_evidence(length - t_exit).
std::uint32_t plain_ray_opinions(std::int16_t* op, const GridGeometry& g, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& reading, const SensorModelTable& model) {
    const double length = (reading - origin).norm();
    const VoxelCoord end = g.world_to_voxel_unchecked(reading);
    const std::size_t end_index = g.contains(end) ? g.index_of(end) : g.voxel_count();
    const std::int16_t hit = model.reading_evidence();
    std::uint32_t visits = 0U;
    (void)plain_aw(g, origin, reading, [&](const TraversedVoxel& v) {
        const std::int16_t e = (v.index == end_index) ? hit : model.free_evidence(length - v.t_exit);
        op[v.index] = e > op[v.index] ? e : op[v.index];
        ++visits;
    });
    return visits;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2U];
}

// One timed pass of @p body over the rays; returns ns per ray and the voxels visited.
template <typename Body>
double timed_pass(const std::vector<Ray>& rays, Body body, std::size_t* visits) {
    std::size_t n = 0U;
    const double t0 = thread_ns();
    for (const Ray& ray : rays) {
        n += body(ray);
    }
    const double ns = thread_ns() - t0;
    *visits = n;
    return ns / static_cast<double>(rays.size());
}

// Exact traversal against the plain A&W on the same rays, interleaved per round.
void compare_with_plain(const char* name, const char* ray_set, const GridGeometry& g, const std::vector<Ray>& rays,
                        int rounds) {
    const SensorModelTable model;
    std::vector<std::int16_t> op_exact(g.voxel_count(), kNoOpinion);
    std::vector<std::int16_t> op_plain(g.voxel_count(), kNoOpinion);
    std::size_t sink = 0U;
    std::vector<double> ns[4];
    std::vector<double> ratio[2];
    std::size_t visits[4] = {0U, 0U, 0U, 0U};
    for (int r = 0; r < rounds; ++r) {
        const double bare_exact = timed_pass(
            rays,
            [&](const Ray& ray) {
                return traverse_segment(g, ray.start, ray.end, [&](const TraversedVoxel& v) { sink += v.index; });
            },
            &visits[0]);
        const double bare_plain = timed_pass(
            rays,
            [&](const Ray& ray) {
                return plain_aw(g, ray.start, ray.end, [&](const TraversedVoxel& v) { sink += v.index; });
            },
            &visits[1]);
        const double op_e = timed_pass(
            rays,
            [&](const Ray& ray) {
                return static_cast<std::size_t>(trace_ray_opinions({op_exact.data(), op_exact.size()}, g, ray.start,
                                                                   ray.end, model, Rasterization::kExact, nullptr));
            },
            &visits[2]);
        const double op_p = timed_pass(
            rays,
            [&](const Ray& ray) {
                return static_cast<std::size_t>(plain_ray_opinions(op_plain.data(), g, ray.start, ray.end, model));
            },
            &visits[3]);
        ns[0].push_back(bare_exact);
        ns[1].push_back(bare_plain);
        ns[2].push_back(op_e);
        ns[3].push_back(op_p);
        ratio[0].push_back(bare_exact / bare_plain);
        ratio[1].push_back(op_e / op_p);
    }
    if (sink == 1U)
        std::puts("");
    const double nr = static_cast<double>(rays.size());
    std::printf(
        "%-12s %-14s %-12s exact %7.1f ns/ray %5.1f vox/ray | plain A&W %7.1f ns/ray %5.1f vox/ray | "
        "exact/plain %.2f\n",
        name, ray_set, "index sum", median(ns[0]), static_cast<double>(visits[0]) / nr, median(ns[1]),
        static_cast<double>(visits[1]) / nr, median(ratio[0]));
    std::printf(
        "%-12s %-14s %-12s exact %7.1f ns/ray %5.1f vox/ray | plain A&W %7.1f ns/ray %5.1f vox/ray | "
        "exact/plain %.2f\n",
        name, ray_set, "max opinion", median(ns[2]), static_cast<double>(visits[2]) / nr, median(ns[3]),
        static_cast<double>(visits[3]) / nr, median(ratio[1]));
}

}  // namespace

int main(int argc, char** argv) {
    const std::size_t count = argc > 1 ? static_cast<std::size_t>(std::strtoul(argv[1], nullptr, 10)) : 200000U;
    const int repeats = argc > 2 ? std::atoi(argv[2]) : 7;
    const int rounds = argc > 3 ? std::max(1, std::atoi(argv[3])) : 15;
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
    std::printf(
        "\nexact traversal against a plain Amanatides & Woo, same rays, interleaved: medians of %d rounds, "
        "median of the per-round ratios\n",
        rounds);
    const std::vector<Ray> frame_rays = reference_frame_rays();
    for (const auto& grid : grids) {
        compare_with_plain(grid.name, "random rays", grid.g, rays, rounds);
        compare_with_plain(grid.name, "ref. frame", grid.g, frame_rays, rounds);
    }
    return 0;
}
