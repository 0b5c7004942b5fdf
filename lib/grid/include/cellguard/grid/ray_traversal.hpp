// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file ray_traversal.hpp
/// Rasterising a segment (a sensor ray from its origin to its reading) into
/// the voxels of a grid, the hot path of fusion: the exact traversal of
/// Amanatides & Woo, and the paper's 3D Bresenham line as an option.
///
/// Exact traversal (traverse_segment), precisely:
/// - A point's voxel is GridGeometry's: u = (p - origin) / voxel_size in
///   voxel units, voxel floor(u); cells are half-open (grid.hpp).
/// - Visited: every voxel whose half-open cell holds a part of the segment of
///   positive length, plus the voxel holding the start and the voxel holding
///   the end when they are inside the grid (these two may have t_enter ==
///   t_exit). For a segment crossing cells this is the same as "its
///   intersection with the voxel's closed box has positive length"; a segment
///   lying exactly in a face plane visits only the voxels above the face
///   (none on the grid's maximum faces), one lying on an edge only the voxels
///   above both faces. A segment through an edge or a corner steps there
///   diagonally, so consecutive voxels share a face, an edge or a corner.
/// - Order from start to end. t_enter/t_exit are metres from the start; the
///   t_exit of a voxel equals the t_enter of the next. When the start is in
///   the grid the first voxel holds it (t_enter 0); when the end is in the
///   grid the last voxel holds it (t_exit == length), exactly the voxel of
///   GridGeometry::world_to_voxel(end). A segment from outside enters at the
///   grid's box, one ending outside stops at the box.
/// - Rounding: crossings are compared in a scaled 64-bit fixed-point unit in
///   which whole- and half-voxel coordinates give integers, so a segment
///   between such points (in voxel units) through an edge or corner steps
///   there exactly. Where rounding separates crossings that coincide, or
///   nearly coincide, in real arithmetic, the traversal may visit a voxel the
///   segment only grazes or skip one it grazes, by a length at the rounding
///   level (~1e-16 of the segment; the tests allow 1e-9 m). The first and last
///   voxels are always exact.
/// - Bound: each loop iteration steps at least one axis towards the last
///   voxel and no axis past it, so a segment visits at most
///   max_voxels_per_segment(g) = nx + ny + nz - 2 voxels, whatever the input.
/// - Set-up (clipping, first and last voxel, fixed-point crossings) is done
///   once per segment in double (ray_traversal.cpp); the loop compares and
///   adds integers, steps the coordinates and the linear index by precomputed
///   strides, and has no division and no branch but the loop's exit: the
///   axis choice is integer selects. Per visit, one multiply turns the
///   crossing into metres.
///
/// Input limits (both methods): a non-finite endpoint, or one whose voxel
/// coordinate lies beyond +-kMaxSegmentVoxelCoordinate on an axis, visits
/// nothing, as does a segment that does not reach the grid.
#ifndef CELLGUARD_RAY_TRAVERSAL_HPP
#define CELLGUARD_RAY_TRAVERSAL_HPP

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellguard/base/contract.hpp"
#include "cellguard/grid/grid.hpp"

namespace cellguard {

/// How a ray is rasterised into voxels.
enum class Rasterization : std::uint8_t {
    kExact = 0,        ///< Amanatides & Woo: every voxel the segment passes through
    kBresenham3d = 1,  ///< the paper's 3D Bresenham line between the end voxels (misses voxels)
};

/// One voxel visited by a traversal.
struct TraversedVoxel {
    std::size_t index = 0U;  ///< linear index (GridGeometry::index_of)
    VoxelCoord coord{};      ///< voxel coordinate
    double t_enter =
        0.0;  ///< metres along the segment from its start where it enters this voxel, clipped to [0, length]
    double t_exit = 0.0;  ///< metres along the segment where it leaves this voxel, clipped to [0, length]
};

/// The part of segment start->end inside the grid box, in metres from start.
/// hits is true when that part has positive length (a segment lying in a
/// face plane counts only on the grid's minimum faces, by the half-open
/// rule) or when start or end lies inside the grid; then t_enter <= t_exit
/// (both 0 or both length for a segment that only touches the grid with an
/// endpoint). When hits is false, t_enter = t_exit = 0.
struct ClippedSegment {
    bool hits = false;     ///< the segment reaches the grid
    double t_enter = 0.0;  ///< metres from start where the segment enters the grid (0 when start is inside)
    double t_exit = 0.0;   ///< metres from start where it leaves the grid (length when end is inside)
    double length = 0.0;   ///< |end - start| in metres (0 for rejected input)
};

/// Largest |voxel coordinate| of an endpoint that a traversal accepts,
/// 2^29 voxels (27,000 km at 5 cm): keeps the integer Bresenham set-up in
/// int64 and every set-up value finite. Farther endpoints visit nothing.
constexpr double kMaxSegmentVoxelCoordinate = 536870912.0;

/// Clips segment start->end to the grid box (see ClippedSegment). Non-finite
/// or out-of-limit input gives hits == false and length 0.
[[nodiscard]] ClippedSegment clip_segment_to_grid(const GridGeometry& g, const Eigen::Vector3d& start,
                                                  const Eigen::Vector3d& end) noexcept;

/// Upper bound on the voxels one segment visits in grid @p g with either
/// method: nx + ny + nz - 2 (0 for an empty geometry).
[[nodiscard]] inline std::size_t max_voxels_per_segment(const GridGeometry& g) noexcept {
    const GridDims d = g.dims();
    const std::int64_t n = static_cast<std::int64_t>(d.nx) + d.ny + d.nz - 2;
    return n > 0 ? static_cast<std::size_t>(n) : 0U;
}

namespace detail {

/// tau of an axis with no crossing left (2^62: larger than any real crossing, which stays
/// below ~2^61).
constexpr std::uint64_t kTauNever = std::uint64_t{1} << 62U;

/// Per-segment set-up of the exact traversal (ray_traversal.cpp).
struct ExactTraversalPlan {
    bool visits = false;                   ///< false: the segment visits nothing
    bool end_inside = false;               ///< the end lies in the grid (then last is its voxel)
    VoxelCoord first{};                    ///< first voxel visited
    VoxelCoord last{};                     ///< last voxel visited
    std::ptrdiff_t first_index = 0;        ///< linear index of first
    std::int32_t step[3] = {0, 0, 0};      ///< -1, 0 or +1 per axis
    std::ptrdiff_t stride[3] = {0, 0, 0};  ///< change of the linear index per step on each axis
    /// Next face crossing per axis as tau = f * W * 2^k in fixed point (f: fraction of the
    /// segment, W: product of |du| over the stepping axes, du in voxel units, 2^k puts W just
    /// below 2^61); kTauNever when first == last on the axis. With whole- or half-voxel input
    /// every tau is an integer, so crossings that coincide at an edge or corner compare equal.
    std::uint64_t tau[3] = {0U, 0U, 0U};
    std::uint64_t tau_delta[3] = {0U, 0U, 0U};  ///< tau between crossings per axis (>= 1, < 2^62)
    std::uint64_t tau_last[3] = {0U, 0U, 0U};   ///< tau of the last crossing per axis: tau + k * tau_delta, exactly
    /// Largest tau_last over the stepping axes (0 when none steps): no crossing after it is visited.
    std::uint64_t tau_stop = 0U;
    /// false when every stepping axis's crossing after its last one, tau_last + tau_delta, lies
    /// beyond tau_stop: the loop then needs no per-axis retirement, only tau_next > tau_stop.
    bool retire = true;
    double metres_per_tau = 0.0;  ///< length / (W * 2^k), > 0
    double t_in = 0.0;            ///< metres where the first voxel is entered
    double t_out = 0.0;           ///< metres where the last voxel is left
};

/// Per-segment set-up of the Bresenham line (ray_traversal.cpp).
struct BresenhamPlan {
    std::int32_t count = 0;                 ///< voxels to visit (0: none)
    VoxelCoord first{};                     ///< first voxel visited
    std::ptrdiff_t first_index = 0;         ///< linear index of first
    std::int64_t residual[3] = {0, 0, 0};   ///< error term per axis at first, in [0, modulus)
    std::int64_t increment[3] = {0, 0, 0};  ///< 2 |d| per axis (d: end voxel - start voxel)
    std::int64_t modulus = 1;               ///< 2 max |d|; a carry steps the axis
    std::int32_t step[3] = {0, 0, 0};       ///< -1, 0 or +1 per axis
    std::ptrdiff_t stride[3] = {0, 0, 0};   ///< change of the linear index per step on each axis
    double t_centre = 0.0;                  ///< projection of first's centre on the segment, metres
    double t_step[3] = {0.0, 0.0, 0.0};     ///< change of that projection per step on each axis
    double half_step = 0.0;                 ///< half a step of the dominant axis, metres
    double length = 0.0;                    ///< |end - start|, metres
};

/// Computes the exact traversal's set-up; see traverse_segment.
[[nodiscard]] ExactTraversalPlan plan_exact_traversal(const GridGeometry& g, const Eigen::Vector3d& start,
                                                      const Eigen::Vector3d& end) noexcept;
/// Computes the Bresenham line's set-up, already clipped to the grid; see traverse_segment_bresenham.
[[nodiscard]] BresenhamPlan plan_bresenham_traversal(const GridGeometry& g, const Eigen::Vector3d& start,
                                                     const Eigen::Vector3d& end) noexcept;

}  // namespace detail

namespace detail {

/// The exact traversal's loop over plan @p p (p.visits true): calls visit(index, coord, tau)
/// for every voxel but the last, in order, with tau the fixed-point crossing where the segment
/// leaves it, then visit_last(index, coord) for the last voxel; returns the number of voxels.
/// The plan's fields are copied to locals so that they stay in registers whatever the
/// visitor writes.
template <typename Visitor, typename LastVisitor>
std::size_t walk_exact(const ExactTraversalPlan& p, Visitor&& visit, LastVisitor&& visit_last) noexcept {
    constexpr std::uint64_t kNever = kTauNever;
    const std::uint64_t dx = p.tau_delta[0];
    const std::uint64_t dy = p.tau_delta[1];
    const std::uint64_t dz = p.tau_delta[2];
    const std::uint64_t lx = p.tau_last[0];
    const std::uint64_t ly = p.tau_last[1];
    const std::uint64_t lz = p.tau_last[2];
    const std::ptrdiff_t stride_x = p.stride[0];
    const std::ptrdiff_t stride_y = p.stride[1];
    const std::ptrdiff_t stride_z = p.stride[2];
    VoxelCoord c = p.first;
    std::ptrdiff_t index = p.first_index;
    std::uint64_t tx = p.tau[0];
    std::uint64_t ty = p.tau[1];
    std::uint64_t tz = p.tau[2];
    std::size_t visited = 1U;
    if (!p.retire) {
        // The common case, as a plain Amanatides & Woo: an axis past its last crossing has
        // its tau beyond tau_stop, so it is not stepped again, and the walk ends when the
        // next crossing lies beyond tau_stop. Same voxels and crossings as the loop below.
        const std::uint64_t stop = p.tau_stop;
        for (;;) {
            const std::uint64_t tau_next = std::min(std::min(tx, ty), tz);
            if (tau_next > stop) {
                break;
            }
            visit(static_cast<std::size_t>(index), c, tau_next);
            ++visited;
            const bool sx = tx == tau_next;
            const bool sy = ty == tau_next;
            const bool sz = tz == tau_next;
            tx = sx ? tx + dx : tx;
            ty = sy ? ty + dy : ty;
            tz = sz ? tz + dz : tz;
            c.x += p.step[0] * static_cast<std::int32_t>(sx);
            c.y += p.step[1] * static_cast<std::int32_t>(sy);
            c.z += p.step[2] * static_cast<std::int32_t>(sz);
            index += (sx ? stride_x : 0) + (sy ? stride_y : 0) + (sz ? stride_z : 0);
        }
        visit_last(static_cast<std::size_t>(index), c);
        return visited;
    }
    for (;;) {
        const std::uint64_t tau_next = std::min(std::min(tx, ty), tz);
        if (tau_next == kNever) {  // every axis is at the last voxel
            break;
        }
        visit(static_cast<std::size_t>(index), c, tau_next);
        ++visited;
        // Step every axis whose crossing comes next (two or three at an exact edge or
        // corner). Integer compares and selects only, no data-dependent branch; the
        // coordinate and index updates are off the tau dependency chain.
        const bool sx = tx == tau_next;
        const bool sy = ty == tau_next;
        const bool sz = tz == tau_next;
        tx = sx ? tx + dx : tx;
        ty = sy ? ty + dy : ty;
        tz = sz ? tz + dz : tz;
        // An axis past its last crossing is retired (its tau becomes kNever).
        tx = tx > lx ? kNever : tx;
        ty = ty > ly ? kNever : ty;
        tz = tz > lz ? kNever : tz;
        c.x += p.step[0] * static_cast<std::int32_t>(sx);
        c.y += p.step[1] * static_cast<std::int32_t>(sy);
        c.z += p.step[2] * static_cast<std::int32_t>(sz);
        index += (sx ? stride_x : 0) + (sy ? stride_y : 0) + (sz ? stride_z : 0);
    }
    visit_last(static_cast<std::size_t>(index), c);
    return visited;
}

/// Metres from the segment's start where the voxel left at fixed-point crossing @p tau ends:
/// tau * metres_per_tau clipped to [t_in, t_out] (t_out for kTauNever). Non-decreasing in tau.
[[nodiscard]] inline double exit_metres(const ExactTraversalPlan& p, std::uint64_t tau) noexcept {
    return std::min(std::max(static_cast<double>(static_cast<std::int64_t>(tau)) * p.metres_per_tau, p.t_in), p.t_out);
}

/// A crossing bound of plan @p p: every tau < the result has exit_metres(p, tau) <= @p metres
/// (0 when none is known to; conservative by a few ulps, so callers can take the cheap branch
/// below it and compute exactly above it without changing any result).
[[nodiscard]] std::uint64_t tau_bound_below(const ExactTraversalPlan& p, double metres) noexcept;

}  // namespace detail

/// Calls visit(const TraversedVoxel&) for every voxel of the grid the segment passes
/// through, in order from start to end; returns how many voxels were visited.
/// Non-finite input visits nothing. A zero-length segment visits the voxel holding it (if inside).
/// The exact rules are in the file comment; at most max_voxels_per_segment(g) visits.
template <typename Visitor>
std::size_t traverse_segment(const GridGeometry& g, const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                             Visitor&& visit) noexcept {
    const detail::ExactTraversalPlan p = detail::plan_exact_traversal(g, start, end);
    if (!p.visits) {
        return 0U;
    }
    double t_enter = p.t_in;
    return detail::walk_exact(
        p,
        [&](std::size_t index, const VoxelCoord& c, std::uint64_t tau) {
            const double t_exit = detail::exit_metres(p, tau);
            visit(TraversedVoxel{index, c, t_enter, t_exit});
            t_enter = t_exit;
        },
        [&](std::size_t index, const VoxelCoord& c) {
            visit(TraversedVoxel{index, c, t_enter, detail::exit_metres(p, detail::kTauNever)});
        });
}

/// Same contract with the 3D Bresenham line from voxel(start) to voxel(end) (integer, 26-connected,
/// one voxel per step of the dominant axis), visiting only voxels inside the grid; t_enter/t_exit
/// are the voxel centre's projection onto the segment -+ half a step, clipped to [0, length].
/// Details: d = voxel(end) - voxel(start), D = max |d| (the first such axis is
/// dominant); at step i = 0..D the voxel is voxel(start) + sign(d) *
/// floor((2 i |d| + D) / (2 D)) per axis (i |d| / D rounded, halves away from
/// the start), so a segment inside the grid visits exactly D + 1 voxels,
/// starting at voxel(start) and ending at voxel(end). Outside voxels are
/// skipped by clipping the step range in the set-up, so the loop runs at most
/// max(nx, ny, nz) times. "A step" in metres is the segment length that
/// advances one voxel along the segment's dominant axis.
template <typename Visitor>
std::size_t traverse_segment_bresenham(const GridGeometry& g, const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                                       Visitor&& visit) noexcept {
    const detail::BresenhamPlan p = detail::plan_bresenham_traversal(g, start, end);
    VoxelCoord c = p.first;
    std::ptrdiff_t index = p.first_index;
    std::int64_t rx = p.residual[0];
    std::int64_t ry = p.residual[1];
    std::int64_t rz = p.residual[2];
    double t_centre = p.t_centre;
    for (std::int32_t k = 0; k < p.count; ++k) {
        const double t_enter = std::min(std::max(t_centre - p.half_step, 0.0), p.length);
        const double t_exit = std::min(std::max(t_centre + p.half_step, 0.0), p.length);
        visit(TraversedVoxel{static_cast<std::size_t>(index), c, t_enter, t_exit});
        // Error terms: a carry steps the axis (integer selects, no data-dependent branch).
        const std::int64_t ax = rx + p.increment[0];
        const std::int64_t ay = ry + p.increment[1];
        const std::int64_t az = rz + p.increment[2];
        const bool sx = ax >= p.modulus;
        const bool sy = ay >= p.modulus;
        const bool sz = az >= p.modulus;
        rx = sx ? ax - p.modulus : ax;
        ry = sy ? ay - p.modulus : ay;
        rz = sz ? az - p.modulus : az;
        c.x += p.step[0] * static_cast<std::int32_t>(sx);
        c.y += p.step[1] * static_cast<std::int32_t>(sy);
        c.z += p.step[2] * static_cast<std::int32_t>(sz);
        index += p.stride[0] * static_cast<std::ptrdiff_t>(sx) + p.stride[1] * static_cast<std::ptrdiff_t>(sy) +
                 p.stride[2] * static_cast<std::ptrdiff_t>(sz);
        t_centre += p.t_step[0] * static_cast<double>(sx) + p.t_step[1] * static_cast<double>(sy) +
                    p.t_step[2] * static_cast<double>(sz);
    }
    return static_cast<std::size_t>(p.count);
}

/// Dispatches on `method`; a value outside the enum is a contract violation.
template <typename Visitor>
std::size_t traverse(Rasterization method, const GridGeometry& g, const Eigen::Vector3d& start,
                     const Eigen::Vector3d& end, Visitor&& visit) noexcept {
    switch (method) {
        case Rasterization::kExact: return traverse_segment(g, start, end, visit);
        case Rasterization::kBresenham3d: return traverse_segment_bresenham(g, start, end, visit);
    }
    CG_ENFORCE(false, "unknown Rasterization");
    return 0U;
}

/// Number of voxels traverse() would visit (used for worst-case cycle budgets).
[[nodiscard]] std::size_t count_traversed_voxels(Rasterization method, const GridGeometry& g,
                                                 const Eigen::Vector3d& start, const Eigen::Vector3d& end) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_RAY_TRAVERSAL_HPP
