// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Accessibility benchmark: time to compute the prior with each of the four
// methods (thresholded, probabilistic, and the two section IV baselines) on
// the paper's 34 x 30 x 30 grid and on the 256 x 256 x 128 whole-cell grid,
// filled with a synthetic background (floor, boxes seen on their surfaces
// with unobserved interiors, free space seen many times, a little noise near
// surfaces). Paper's parameters: r = 2 voxels, t_B = 0.51, t_E = 0.1, four
// side faces open. One core; medians over several runs. On the paper's grid
// also the run-time subtraction as the cycle does it (evaluate_zones: frame +
// prior and one zone over the whole grid), against the paper's "under 1 ms".
// A program that prints figures, not a test with a time limit.
//
// Usage: bench_accessibility [runs] [paper]   (default 21 runs on the
// paper's grid and a third of that, at least 3, on the large grid; "paper"
// skips the large grid, e.g. for callgrind)
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/safety/zone_evaluation.hpp"
#include "cellguard/safety/zones.hpp"

using namespace cellguard;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::int16_t kSeenFree = -1768;    // P(occ) = 0.001 (the background clamp)
constexpr std::int16_t kSeenSurface = 1768;  // P(occ) = 0.999
constexpr std::int16_t kNoisyFree = -300;    // P(occ) = 0.24: above t_E, so it costs

struct Box {
    Eigen::Vector3d lo;
    Eigen::Vector3d hi;
    [[nodiscard]] bool contains(const Eigen::Vector3d& p) const {
        return (p.array() >= lo.array()).all() && (p.array() < hi.array()).all();
    }
};

// World-frame scene (metres): the cell is 4 m x 4 m x 2 m, floor at z = 0.
const Box kBoxes[] = {
    {Eigen::Vector3d(-0.40, -0.30, 0.00), Eigen::Vector3d(0.10, 0.30, 0.50)},  // large box
    {Eigen::Vector3d(0.25, -0.55, 0.00), Eigen::Vector3d(0.60, -0.10, 0.80)},  // tall box
    {Eigen::Vector3d(-0.30, -0.10, 0.50), Eigen::Vector3d(0.00, 0.00, 0.60)},  // a 2x4 on top
    {Eigen::Vector3d(1.00, 1.00, 0.00), Eigen::Vector3d(1.60, 1.40, 0.70)},    // outside the paper's grid
};
const Box kCell{Eigen::Vector3d(-2.0, -2.0, 0.0), Eigen::Vector3d(2.0, 2.0, 2.0)};

struct Background {
    explicit Background(const GridGeometry& g) : geometry(g), lo(g.voxel_count()), ob(g.voxel_count()) {}
    GridGeometry geometry;
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid() {
        return EvidenceGrid::make(geometry, Span<std::int16_t>(lo.data(), lo.size()),
                                  Span<std::uint8_t>(ob.data(), ob.size()))
            .value();
    }
};

// Inside a box (or the floor slab): 0 outside, 1 on the surface (some face
// neighbour outside), 2 interior.
int solid(const GridGeometry& g, const VoxelCoord& c) {
    auto inside = [&](const VoxelCoord& v) {
        const Eigen::Vector3d p = g.voxel_center(v);
        if (p.z() < 0.0)
            return true;  // below the floor
        for (const Box& b : kBoxes) {
            if (b.contains(p))
                return true;
        }
        return false;
    };
    if (!inside(c))
        return 0;
    const VoxelCoord n[6] = {{c.x + 1, c.y, c.z}, {c.x - 1, c.y, c.z}, {c.x, c.y + 1, c.z},
                             {c.x, c.y - 1, c.z}, {c.x, c.y, c.z + 1}, {c.x, c.y, c.z - 1}};
    for (const VoxelCoord& v : n) {
        if (!inside(v))
            return 1;
    }
    return 2;
}

Background make_background(const GridGeometry& g) {
    Background bg(g);
    std::mt19937 rng(42U);
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        const VoxelCoord c = g.coord_of(i);
        const Eigen::Vector3d p = g.voxel_center(c);
        const bool in_cell = kCell.contains(p) ||
                             (p.z() < 0.0 && p.z() > -0.05 && std::abs(p.x()) < 2.0 && std::abs(p.y()) < 2.0);
        const int s = solid(g, c);
        if (!in_cell || s == 2) {  // outside the sensors' view, or inside an object
            bg.lo[i] = 0;
            bg.ob[i] = 0U;
            continue;
        }
        bg.ob[i] = 1U;
        if (s == 1) {
            bg.lo[i] = kSeenSurface;
            continue;
        }
        // Free space; noise next to surfaces, and rarely elsewhere.
        bool near_surface = false;
        for (int d = 0; d < 3 && !near_surface; ++d) {
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                VoxelCoord v = c;
                (d == 0 ? v.x : d == 1 ? v.y : v.z) += sgn;
                near_surface = near_surface || solid(g, v) != 0;
            }
        }
        const unsigned u = rng() % 1000U;
        bg.lo[i] = (near_surface && u < 300U) || u < 5U ? kNoisyFree : kSeenFree;
    }
    return bg;
}

const char* name_of(PriorMethod m) {
    switch (m) {
        case PriorMethod::kThresholded: return "thresholded";
        case PriorMethod::kProbabilistic: return "probabilistic";
        case PriorMethod::kThresholdedBaseline: return "thresholded baseline";
        case PriorMethod::kProbabilisticBaseline: return "probabilistic baseline";
    }
    return "?";
}

struct Figures {
    double median_ms;
    double min_ms;
    std::size_t never;    // voxels with the kNeverForeground sentinel
    std::size_t reduced;  // voxels with -inf < prior < 0
};

/// Milliseconds of @p runs calls of @p call (a Status), sorted; exits naming @p what when a call fails.
template <class Call>
std::vector<double> sorted_ms(int runs, const char* what, Call&& call) {
    std::vector<double> ms;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = Clock::now();
        const Status s = call();
        const auto t1 = Clock::now();
        if (!s.ok()) {
            std::fprintf(stderr, "%s failed: %s\n", what, to_string(s.error()));
            std::exit(1);
        }
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms;
}

/// Subtraction at run time, as the cycle does it: evaluate_zones adds the prior to a frame and counts one zone
/// that covers the whole grid (frame: the background itself). Median ms over @p runs, and the paper's figure.
void bench_subtraction(Background& bg, const std::vector<std::int16_t>& prior, int runs) {
    const GridGeometry& g = bg.geometry;
    ZoneConfig zone;
    zone.box_min = g.origin();
    zone.box_max = g.origin() + g.voxel_size() * Eigen::Vector3d(g.dims().nx, g.dims().ny, g.dims().nz);
    zone.max_unseen_voxels = static_cast<std::uint32_t>(g.voxel_count());
    std::vector<std::uint32_t> membership(g.voxel_count());
    const Result<CompiledZones, ZoneError> zones = CompiledZones::compile(
        g, Span<const ZoneConfig>(&zone, 1), Span<std::uint32_t>(membership.data(), membership.size()));
    if (!zones.ok()) {
        std::fprintf(stderr, "zone compile failed\n");
        std::exit(1);
    }
    const EvidenceGrid frame = bg.grid();
    ZoneEvaluation out;
    const std::vector<double> ms = sorted_ms(runs, "evaluate_zones", [&] {
        return evaluate_zones(frame, Span<const std::int16_t>(prior.data(), prior.size()), zones.value(),
                              ZoneEvaluationParams{}, out);
    });
    std::printf("  %-24s %12.4f %12.4f %12s %12s   %s\n", "subtraction + 1 zone", ms[ms.size() / 2], ms.front(), "-",
                "-", "< 1 ms (paper) / -");
}

Figures run(Background& bg, PriorMethod method, int runs, std::vector<std::int16_t>* prior_out = nullptr) {
    AccessibilityParams p;  // the paper's parameters
    p.method = method;
    const AccessibilityScratchSize need = accessibility_scratch_size(bg.geometry.dims(), p);
    std::vector<std::uint32_t> words(need.words);
    std::vector<std::uint8_t> bytes(need.bytes);
    std::vector<std::int16_t> prior(bg.lo.size());
    const EvidenceGrid grid = bg.grid();
    const std::vector<double> ms = sorted_ms(runs, "compute_accessibility_prior", [&] {
        return compute_accessibility_prior(grid, p,
                                           AccessibilityScratch{Span<std::uint32_t>(words.data(), words.size()),
                                                                Span<std::uint8_t>(bytes.data(), bytes.size())},
                                           Span<std::int16_t>(prior.data(), prior.size()), Span<float>());
    });
    if (prior_out != nullptr) {
        *prior_out = prior;
    }
    Figures f{ms[ms.size() / 2], ms.front(), 0U, 0U};
    for (const std::int16_t v : prior) {
        f.never += v == kNeverForeground ? 1U : 0U;
        f.reduced += v != kNeverForeground && v < 0 ? 1U : 0U;
    }
    return f;
}

void bench_grid(const char* title, const GridGeometry& g, int runs, bool paper) {
    Background bg = make_background(g);
    std::size_t observed = 0;
    for (const std::uint8_t o : bg.ob)
        observed += o;
    const GridDims d = g.dims();
    std::printf("\n%s: %d x %d x %d = %zu voxels, %zu observed, %d runs\n", title, d.nx, d.ny, d.nz, g.voxel_count(),
                observed, runs);
    std::printf("  %-24s %12s %12s %12s %12s   %s\n", "method", "median ms", "min ms", "P(fore)=0", "0<P(fore)<.5",
                paper ? "paper (2012 desktop) / goal" : "goal");
    const PriorMethod methods[4] = {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                    PriorMethod::kThresholdedBaseline, PriorMethod::kProbabilisticBaseline};
    std::vector<std::int16_t> probabilistic;
    for (const PriorMethod m : methods) {
        const Figures f = run(bg, m, runs, m == PriorMethod::kProbabilistic ? &probabilistic : nullptr);
        const char* note = "";
        if (paper) {
            note = m == PriorMethod::kThresholded     ? "~20 ms / <= 1 ms"
                   : m == PriorMethod::kProbabilistic ? "~400 ms / <= 10 ms"
                                                      : "- / -";
        } else {
            note = m == PriorMethod::kThresholded || m == PriorMethod::kProbabilistic ? "<= 10000 ms" : "-";
        }
        std::printf("  %-24s %12.3f %12.3f %12zu %12zu   %s\n", name_of(m), f.median_ms, f.min_ms, f.never, f.reduced,
                    note);
    }
    if (paper) {
        bench_subtraction(bg, probabilistic, std::max(runs, 101));
    }
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 21;
    std::printf("cellguard accessibility prior: r = 2 voxels, t_B = 0.51, t_E = 0.1, four side faces open\n");
    bench_grid("paper's grid", paper_grid_geometry(), runs, true);
    if (argc <= 2 || std::string(argv[2]) != "paper") {
        bench_grid("whole-cell grid", whole_cell_grid_geometry(), std::max(3, runs / 3), false);
    }
    return 0;
}
