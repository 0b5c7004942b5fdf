// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: trace_ray_opinions with the exact traversal (its per-ray shortcuts: the
// constant free value below a crossing bound, the hit only at the last voxel) gives the
// opinions of the straightforward visitor over traverse_segment, bit for bit.
#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_traversal.hpp"

using namespace cellguard;

namespace {

using V3 = Eigen::Vector3d;

/// The reference: every visited voxel gets max(its opinion, hit if it holds the reading else
/// free_evidence(length - t_exit)), as trace_ray_opinions was first written.
std::uint32_t reference_opinions(std::vector<std::int16_t>& op, const GridGeometry& g, const V3& a, const V3& b,
                                 const SensorModelTable& model, bool* in_grid) {
    const double length = (b - a).norm();
    if (!std::isfinite(length)) {
        return 0U;
    }
    const VoxelCoord end = g.world_to_voxel_unchecked(b);
    const bool inside = g.contains(end);
    const std::size_t end_index = inside ? g.index_of(end) : g.voxel_count();
    *in_grid = inside;
    std::uint32_t visits = 0U;
    (void)traverse_segment(g, a, b, [&](const TraversedVoxel& v) {
        const std::int16_t e = v.index == end_index ? model.reading_evidence() : model.free_evidence(length - v.t_exit);
        op[v.index] = e > op[v.index] ? e : op[v.index];
        ++visits;
    });
    return visits;
}

/// Random rays of several kinds against the paper's grid: from outside corners, between
/// whole- and half-voxel points (through edges and corners), axis-parallel, zero-length,
/// ending on faces, and with readings just before and after the ramp.
V3 random_point(std::mt19937& rng, const GridGeometry& g, int kind) {
    std::uniform_real_distribution<double> any(-1.5, 2.5);
    std::uniform_int_distribution<int> half(-8, 2 * 34 + 8);
    V3 p;
    for (int k = 0; k < 3; ++k) {
        p[k] = kind == 0 ? any(rng) : g.origin()[k] + 0.5 * half(rng) * g.voxel_size();
    }
    return p;
}

void compare_on(const GridGeometry& g, const SensorModelTable& model, int rays, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<std::int16_t> got(g.voxel_count(), kNoOpinion);
    std::vector<std::int16_t> want(g.voxel_count(), kNoOpinion);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int mismatched_rays = 0;
    std::uint64_t visits = 0U;
    for (int i = 0; i < rays; ++i) {
        const V3 a = random_point(rng, g, i % 2);
        V3 b = random_point(rng, g, (i / 2) % 2);
        if (i % 7 == 0) {
            b[i % 3] = a[i % 3];  // parallel to a face
        }
        if (i % 11 == 0) {
            b = a;  // zero length
        }
        if (i % 5 == 0) {  // a reading just past a crossing bound: a few ulps around the ramp's start
            b = a + (b - a) * (1.0 + (unit(rng) - 0.5) * 1e-12);
        }
        bool in_got = false;
        bool in_want = false;
        const std::uint32_t n_got = trace_ray_opinions({got.data(), got.size()}, g, a, b, model, Rasterization::kExact,
                                                       &in_got);
        const std::uint32_t n_want = reference_opinions(want, g, a, b, model, &in_want);
        visits += n_got;
        mismatched_rays += (n_got != n_want || in_got != in_want) ? 1 : 0;
        if (i % 64 == 63) {
            mismatched_rays += got == want ? 0 : 1;
        }
    }
    CHECK(mismatched_rays == 0);
    CHECK(got == want);
    CHECK(visits > static_cast<std::uint64_t>(rays));  // the rays do cross the grid
}

}  // namespace

// verifies: SR-TRAV-001, SR-FUSE-002
TEST_CASE("trace_ray_opinions (exact) equals the straightforward visitor over traverse_segment, bit for bit") {
    const GridGeometry g = paper_grid_geometry();
    compare_on(g, SensorModelTable(), 20000, 1U);
    // A ramp longer than most segments (every voxel on the ramp) and none at all.
    SensorModelParams long_ramp;
    long_ramp.ramp_length = 3.0;
    compare_on(g, SensorModelTable::make(long_ramp).value(), 5000, 2U);
    SensorModelParams no_ramp;
    no_ramp.ramp_length = 0.0;
    compare_on(g, SensorModelTable::make(no_ramp).value(), 5000, 3U);
}

// verifies: SR-TRAV-001
TEST_CASE("tau_bound_below: every crossing below the bound ends at or before the given metres") {
    std::mt19937 rng(9U);
    std::uniform_real_distribution<double> any(-1.5, 2.5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const GridGeometry g = paper_grid_geometry();
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        const V3 a(any(rng), any(rng), any(rng));
        const V3 b(any(rng), any(rng), any(rng));
        const detail::ExactTraversalPlan p = detail::plan_exact_traversal(g, a, b);
        if (!p.visits) {
            continue;
        }
        const double metres = (b - a).norm() * unit(rng);
        const std::uint64_t bound = detail::tau_bound_below(p, metres);
        // The walk's crossings below the bound, and the largest tau below it.
        bool ok = true;
        (void)detail::walk_exact(
            p,
            [&](std::size_t, const VoxelCoord&, std::uint64_t tau) {
                ok = ok && (tau >= bound || detail::exit_metres(p, tau) <= metres);
            },
            [](std::size_t, const VoxelCoord&) {});
        if (bound > 0U && bound < detail::kTauNever) {
            ok = ok && detail::exit_metres(p, bound - 1U) <= metres;
            // Not far off: a crossing 1e-9 of the segment above the bound is past metres
            // unless clipped there.
            const std::uint64_t above = bound + bound / 1000000000U + 2U;
            ok = ok && (detail::exit_metres(p, above) > metres || detail::exit_metres(p, above) == p.t_out);
        }
        CHECK(ok);
        ++checked;
    }
    CHECK(checked > 200);
}
