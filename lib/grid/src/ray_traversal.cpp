// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/ray_traversal.hpp"

#include <array>
#include <cmath>
#include <cstring>

namespace cellguard {

namespace {

using detail::kTauNever;
using Vec3 = std::array<double, 3>;
using Int3 = std::array<std::int32_t, 3>;

/// A segment in voxel units (u = (p - origin) / voxel_size, as GridGeometry).
struct VoxelSegment {
    Vec3 u0{};            ///< start
    Vec3 u1{};            ///< end
    Vec3 du{};            ///< u1 - u0
    double length = 0.0;  ///< |end - start| in metres
};

/// The grid box [0, n) in fractions of the segment (0 = start, 1 = end).
struct BoxClip {
    double f_in = 0.0;          ///< where the segment enters the box
    double f_out = 1.0;         ///< where it leaves the box
    bool positive = false;      ///< the part inside has positive length (half-open faces for parallel axes)
    bool start_inside = false;  ///< start lies in the grid (half-open)
    bool end_inside = false;    ///< end lies in the grid (half-open)
};

bool within_limits(const Eigen::Vector3d& u) noexcept {
    // Written so that NaN fails.
    return std::fabs(u.x()) <= kMaxSegmentVoxelCoordinate && std::fabs(u.y()) <= kMaxSegmentVoxelCoordinate &&
           std::fabs(u.z()) <= kMaxSegmentVoxelCoordinate;
}

/// Converts the segment to voxel units; false for non-finite or out-of-limit input.
bool to_voxel_units(const GridGeometry& g, const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                    VoxelSegment& out) noexcept {
    // Non-finite input needs no test of its own: it gives a non-finite u0 or u1, which
    // within_limits rejects (NaN fails its comparisons).
    // The same expression as GridGeometry::world_to_voxel, so that the end
    // voxels agree with it bit for bit.
    const Eigen::Vector3d u0 = (start - g.origin()) / g.voxel_size();
    const Eigen::Vector3d u1 = (end - g.origin()) / g.voxel_size();
    if (!within_limits(u0) || !within_limits(u1)) {
        return false;
    }
    const double length = (end - start).norm();
    if (!std::isfinite(length)) {
        return false;
    }
    for (std::size_t a = 0U; a < 3U; ++a) {
        const auto i = static_cast<Eigen::Index>(a);
        out.u0[a] = u0[i];
        out.u1[a] = u1[i];
        out.du[a] = u1[i] - u0[i];
    }
    out.length = length;
    return true;
}

Int3 dims_of(const GridGeometry& g) noexcept {
    const GridDims d = g.dims();
    return Int3{d.nx, d.ny, d.nz};
}

bool inside(const Vec3& u, const Int3& n) noexcept {
    return u[0] >= 0.0 && u[1] >= 0.0 && u[2] >= 0.0 && u[0] < n[0] && u[1] < n[1] && u[2] < n[2];
}

/// Slab clipping of the segment against the box [0, n] in voxel units.
/// An axis along which the segment does not move must hold it in [0, n)
/// (half-open: on the maximum face it is outside).
BoxClip clip_to_box(const VoxelSegment& s, const Int3& n) noexcept {
    BoxClip c;
    c.start_inside = inside(s.u0, n);
    c.end_inside = inside(s.u1, n);
    bool parallel_outside = false;
    for (std::size_t a = 0U; a < 3U; ++a) {
        const double na = n[a];
        if (s.du[a] == 0.0) {
            parallel_outside = parallel_outside || !(s.u0[a] >= 0.0 && s.u0[a] < na);
        } else {
            const double f0 = (0.0 - s.u0[a]) / s.du[a];
            const double f1 = (na - s.u0[a]) / s.du[a];
            c.f_in = std::max(c.f_in, std::min(f0, f1));
            c.f_out = std::min(c.f_out, std::max(f0, f1));
        }
    }
    // An endpoint in the grid pins its end of the range (no rounding there).
    if (c.start_inside) {
        c.f_in = 0.0;
    }
    if (c.end_inside) {
        c.f_out = 1.0;
    }
    c.positive = !parallel_outside && c.f_in < c.f_out;
    return c;
}

/// floor(u) for u known to lie in [0, 4096].
std::int32_t floor_index(double u) noexcept { return static_cast<std::int32_t>(std::floor(u)); }

std::int32_t clamp_index(std::int32_t i, std::int32_t n) noexcept {
    return std::min<std::int32_t>(std::max<std::int32_t>(i, 0), n - 1);
}

/// Voxel along one axis that holds the segment just after (entering) or just
/// before (leaving) the point u on the box surface, moving up or down.
std::int32_t boundary_voxel(double u, std::int32_t n, bool up, bool entering) noexcept {
    const double p = std::min(std::max(u, 0.0), static_cast<double>(n));
    const bool take_floor = (up == entering);
    const std::int32_t i = take_floor ? floor_index(p) : static_cast<std::int32_t>(std::ceil(p)) - 1;
    return clamp_index(i, n);
}

/// Fraction of the segment at which it crosses face @p face of axis @p a (du[a] != 0).
/// One correctly rounded division, as in clip_to_box: crossings that coincide exactly
/// (an entry or exit through an edge or corner of the box) give equal fractions.
double face_fraction(const VoxelSegment& s, std::size_t a, std::int32_t face) noexcept {
    return (static_cast<double>(face) - s.u0[a]) / s.du[a];
}

/// First voxel along axis @p a of a segment entering the box at fraction f_in.
std::int32_t entry_voxel(const VoxelSegment& s, std::size_t a, std::int32_t n, double f_in) noexcept {
    const bool up = s.du[a] > 0.0;
    const std::int32_t step = up ? 1 : -1;
    const std::int32_t i = boundary_voxel(s.u0[a] + f_in * s.du[a], n, up, true);
    // The entry point is rounded; the face fractions, one correctly rounded division each,
    // decide: a face ahead of i crossed at (or before) f_in has been passed (an entry exactly
    // through an edge or corner compares equal), a face behind i crossed after f_in has not
    // been reached yet.
    if (i + step >= 0 && i + step < n && face_fraction(s, a, up ? i + 1 : i) <= f_in) {
        return i + step;
    }
    if (i - step >= 0 && i - step < n && face_fraction(s, a, up ? i : i + 1) > f_in) {
        return i - step;
    }
    return i;
}

/// Last voxel along axis @p a of a segment leaving the box at fraction f_out.
std::int32_t exit_voxel(const VoxelSegment& s, std::size_t a, std::int32_t n, double f_out) noexcept {
    const bool up = s.du[a] > 0.0;
    const std::int32_t step = up ? 1 : -1;
    const std::int32_t i = boundary_voxel(s.u0[a] + f_out * s.du[a], n, up, false);
    // As for the entry: a face ahead of i crossed before f_out is passed; a voxel whose face
    // behind is crossed at (or after) f_out is only touched (an exit exactly through an edge
    // or corner compares equal).
    if (i + step >= 0 && i + step < n && face_fraction(s, a, up ? i + 1 : i) < f_out) {
        return i + step;
    }
    if (i - step >= 0 && i - step < n && face_fraction(s, a, up ? i : i + 1) >= f_out) {
        return i - step;
    }
    return i;
}

/// Rounds a non-negative tau to fixed point (half up), saturating below kTauNever.
/// Doubles from 2^52 up are integers already; below, tau + 0.5 is exact.
std::uint64_t to_fixed(double tau) noexcept {
    constexpr double kIntegral = 4503599627370496.0;           // 2^52
    constexpr double kLimit = 4611686018427387904.0 - 1024.0;  // just below 2^62 = kTauNever
    if (!(tau < kLimit)) {
        return kTauNever - 1U;
    }
    return static_cast<std::uint64_t>(tau >= kIntegral ? tau : tau + 0.5);
}

std::array<std::ptrdiff_t, 3> strides_of(const Int3& n) noexcept {
    return {1, static_cast<std::ptrdiff_t>(n[0]), static_cast<std::ptrdiff_t>(n[0]) * n[1]};
}

VoxelCoord to_coord(const Int3& c) noexcept { return VoxelCoord{c[0], c[1], c[2]}; }

/// ceil(a / b) for b > 0.
std::int64_t ceil_div(std::int64_t a, std::int64_t b) noexcept { return a >= 0 ? (a + b - 1) / b : -((-a) / b); }

/// The first and last voxel of the clipped segment @p s (clip @p c, grid
/// @p n) on each axis, and where it enters and leaves the grid (plan.t_in,
/// plan.t_out).
void plan_end_voxels(const VoxelSegment& s, const BoxClip& c, const Int3& n, Int3& first, Int3& last,
                     detail::ExactTraversalPlan& plan) noexcept {
    if (!c.positive) {
        // Only an endpoint touches the grid (or the segment has zero length).
        const Vec3& u = c.start_inside ? s.u0 : s.u1;
        for (std::size_t a = 0U; a < 3U; ++a) {
            first[a] = floor_index(u[a]);
            last[a] = first[a];
        }
        plan.t_in = c.start_inside ? 0.0 : s.length;
        plan.t_out = plan.t_in;
    } else {
        for (std::size_t a = 0U; a < 3U; ++a) {
            if (s.du[a] == 0.0) {
                first[a] = floor_index(s.u0[a]);  // in [0, n) by clip_to_box
                last[a] = first[a];
                continue;
            }
            const bool up = s.du[a] > 0.0;
            first[a] = c.start_inside ? floor_index(s.u0[a]) : entry_voxel(s, a, n[a], c.f_in);
            last[a] = c.end_inside ? floor_index(s.u1[a]) : exit_voxel(s, a, n[a], c.f_out);
            // Rounding at a clipped end can put last behind first; the
            // endpoint in the grid (if any) keeps its exact voxel.
            if (up ? last[a] < first[a] : last[a] > first[a]) {
                if (c.end_inside) {
                    first[a] = last[a];
                } else {
                    last[a] = first[a];
                }
            }
        }
        plan.t_in = c.f_in * s.length;
        plan.t_out = c.end_inside ? s.length : c.f_out * s.length;
    }
}

/// 2^(61 - e) for w = m * 2^e, m in [0.5, 1) (frexp's exponent), so that w * scale lies in
/// [2^60, 2^61). Read from the bits for a normal w (every W of plan_crossings, which lies
/// between ~2^-156 and 2^90), with frexp and ldexp otherwise.
double power_of_two_scale(double w) noexcept {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &w, sizeof bits);
    const auto biased = static_cast<std::int32_t>((bits >> 52U) & 0x7FFU);
    const std::int32_t shift = 61 - (biased - 1022);  // 61 - e
    if (biased == 0 || biased == 0x7FF || shift < -1022 || shift > 1023) {
        int exponent = 0;
        (void)std::frexp(w, &exponent);
        return std::ldexp(1.0, 61 - exponent);
    }
    const std::uint64_t scale_bits = static_cast<std::uint64_t>(shift + 1023) << 52U;
    double scale = 0.0;
    std::memcpy(&scale, &scale_bits, sizeof scale);
    return scale;
}

/// The exact traversal's fixed-point crossings of @p s from voxel @p first
/// to @p last: plan.step, stride, tau, tau_delta, tau_last and metres_per_tau.
void plan_crossings(const VoxelSegment& s, const Int3& n, const Int3& first, const Int3& last,
                    detail::ExactTraversalPlan& plan) noexcept {
    // Crossings are compared as tau = f * W, W = product of |du| over the stepping axes: the
    // crossing of face k on axis a is at tau = |k - u0| * (W / |du_a|). For whole (or
    // half) voxel coordinates every tau is an integer, so crossings that coincide at an
    // edge or a corner compare equal. A stepping axis crosses an inner face, so its |du| is
    // at least ~2^-52 and W stays far from under- and overflow. tau is then scaled by 2^k
    // (exact) so that W * 2^k < 2^61 and rounded to 64-bit fixed point: the loop adds and
    // compares integers, exactly. Crossings lie within the segment (tau <= ~W * 2^k), and an
    // axis with two or more steps has |du| >= ~1, so tau_delta <= ~W * 2^k: no sum reaches
    // 2^63.
    Vec3 w{};
    for (std::size_t a = 0U; a < 3U; ++a) {
        w[a] = first[a] != last[a] ? std::fabs(s.du[a]) : 1.0;
    }
    const double big_w = w[0] * w[1] * w[2];
    const double scale = power_of_two_scale(big_w);
    // Kept positive (also for a zero-length segment) so that kTauNever maps beyond t_out.
    plan.metres_per_tau = std::max(s.length / (big_w * scale), std::numeric_limits<double>::min());
    const std::array<std::ptrdiff_t, 3> stride = strides_of(n);
    for (std::size_t a = 0U; a < 3U; ++a) {
        const std::int32_t step = s.du[a] > 0.0 ? 1 : (s.du[a] < 0.0 ? -1 : 0);
        plan.step[a] = step;
        plan.stride[a] = step * stride[a];
        const std::int32_t steps = step * (last[a] - first[a]);
        if (steps == 0) {
            plan.tau[a] = kTauNever;
            plan.tau_delta[a] = 1U;
            plan.tau_last[a] = 0U;
        } else {
            const double delta = w[(a + 1U) % 3U] * w[(a + 2U) % 3U];
            const auto face = static_cast<double>(first[a] + (step > 0 ? 1 : 0));
            plan.tau[a] = to_fixed(std::fabs(face - s.u0[a]) * delta * scale);
            // delta * scale >= 2^30 (|du| <= 2^30); to_fixed saturates below 2^62, so with a
            // single step (|du| possibly tiny) tau + tau_delta stays below 2^63.
            plan.tau_delta[a] = std::max(to_fixed(delta * scale), std::uint64_t{1});
            plan.tau_last[a] = plan.tau[a] + static_cast<std::uint64_t>(steps - 1) * plan.tau_delta[a];
            plan.tau_stop = std::max(plan.tau_stop, plan.tau_last[a]);
        }
    }
    // Retirement is needed only where rounding or an end on a face puts an axis's next
    // crossing at or before another axis's last one.
    plan.retire = false;
    for (std::size_t a = 0U; a < 3U; ++a) {
        if (plan.tau[a] != kTauNever && plan.tau_last[a] + plan.tau_delta[a] <= plan.tau_stop) {
            plan.retire = true;
        }
    }
}

}  // namespace

ClippedSegment clip_segment_to_grid(const GridGeometry& g, const Eigen::Vector3d& start,
                                    const Eigen::Vector3d& end) noexcept {
    ClippedSegment r{false, 0.0, 0.0, 0.0};
    VoxelSegment s;
    if (!to_voxel_units(g, start, end, s)) {
        return r;
    }
    r.length = s.length;
    const BoxClip c = clip_to_box(s, dims_of(g));
    if (c.positive) {
        r.hits = true;
        r.t_enter = c.f_in * s.length;
        r.t_exit = c.end_inside ? s.length : c.f_out * s.length;
    } else if (c.start_inside || c.end_inside) {
        r.hits = true;
        r.t_enter = c.start_inside ? 0.0 : s.length;
        r.t_exit = r.t_enter;
    }
    return r;
}

namespace detail {

ExactTraversalPlan plan_exact_traversal(const GridGeometry& g, const Eigen::Vector3d& start,
                                        const Eigen::Vector3d& end) noexcept {
    ExactTraversalPlan plan;
    VoxelSegment s;
    if (!to_voxel_units(g, start, end, s)) {
        return plan;
    }
    const Int3 n = dims_of(g);
    const BoxClip c = clip_to_box(s, n);
    if (!c.positive && !c.start_inside && !c.end_inside) {
        return plan;
    }
    Int3 first{};
    Int3 last{};
    plan_end_voxels(s, c, n, first, last, plan);
    plan.first = to_coord(first);
    plan.last = to_coord(last);
    CG_ENFORCE(g.contains(plan.first) && g.contains(plan.last), "traversal end voxels outside the grid");
    plan.first_index = static_cast<std::ptrdiff_t>(g.index_of(plan.first));
    plan_crossings(s, n, first, last, plan);
    plan.end_inside = c.end_inside;
    plan.visits = true;
    return plan;
}

std::uint64_t tau_bound_below(const ExactTraversalPlan& p, double metres) noexcept {
    // exit_metres(p, tau) = min(max(fl(fl(tau) * mpt), t_in), t_out): at most metres for every
    // tau when t_out <= metres, for none when t_in > metres; otherwise when fl(fl(tau) * mpt)
    // <= metres. Each of the two roundings and the division below is within a factor
    // (1 + 2^-53) of the exact value, so tau < q * (1 - 2^-50) with q = fl(metres / mpt)
    // gives fl(fl(tau) * mpt) <= metres * (1 + 2^-53)^3 * (1 - 2^-50) < metres.
    if (!(p.t_in <= metres) || !(metres > 0.0)) {
        return 0U;
    }
    if (p.t_out <= metres) {
        return kTauNever;
    }
    const double q = metres / p.metres_per_tau * (1.0 - 0x1p-50);
    constexpr double kNeverAsDouble = 4611686018427387904.0;  // 2^62
    if (!(q < kNeverAsDouble)) {
        return kTauNever;
    }
    return static_cast<std::uint64_t>(q);  // floor, q >= 0
}

BresenhamPlan plan_bresenham_traversal(const GridGeometry& g, const Eigen::Vector3d& start,
                                       const Eigen::Vector3d& end) noexcept {
    BresenhamPlan plan;
    VoxelSegment s;
    if (!to_voxel_units(g, start, end, s)) {
        return plan;
    }
    const Int3 n = dims_of(g);
    // |coordinates| <= 2^29 voxels: every product below stays under 2^61.
    std::array<std::int64_t, 3> v0{};
    std::array<std::int64_t, 3> e{};
    std::array<std::int32_t, 3> sign{};
    std::int64_t dominant = 0;
    for (std::size_t a = 0U; a < 3U; ++a) {
        v0[a] = static_cast<std::int64_t>(std::floor(s.u0[a]));
        const std::int64_t d = static_cast<std::int64_t>(std::floor(s.u1[a])) - v0[a];
        e[a] = d < 0 ? -d : d;
        sign[a] = d > 0 ? 1 : (d < 0 ? -1 : 0);
        dominant = std::max(dominant, e[a]);
    }
    // Step i in [0, D] puts axis a at v0 + sign * q(i), q(i) = floor((2 i e + D) / (2 D)).
    // Keep the steps whose voxel is inside on every axis (an interval, q is monotone).
    const std::int64_t big_d = dominant;
    std::int64_t lo = 0;
    std::int64_t hi = big_d;
    for (std::size_t a = 0U; a < 3U; ++a) {
        const std::int64_t na = n[a];
        if (e[a] == 0) {
            if (v0[a] < 0 || v0[a] >= na) {
                return plan;
            }
            continue;
        }
        const std::int64_t q_lo = sign[a] > 0 ? -v0[a] : v0[a] - (na - 1);
        const std::int64_t q_hi = sign[a] > 0 ? na - 1 - v0[a] : v0[a];
        lo = std::max(lo, ceil_div(2 * big_d * q_lo - big_d, 2 * e[a]));
        hi = std::min(hi, ceil_div(2 * big_d * (q_hi + 1) - big_d, 2 * e[a]) - 1);
    }
    if (lo > hi) {
        return plan;
    }
    const std::int64_t modulus = big_d > 0 ? 2 * big_d : 1;
    const auto voxel_at = [&](std::int64_t i, std::size_t a, std::int64_t& residual) {
        const std::int64_t num = big_d > 0 ? 2 * i * e[a] + big_d : 0;
        const std::int64_t q = num / modulus;
        residual = num - q * modulus;
        return static_cast<std::int32_t>(v0[a] + sign[a] * q);
    };
    Int3 first{};
    Int3 last{};
    for (std::size_t a = 0U; a < 3U; ++a) {
        std::int64_t unused = 0;
        first[a] = voxel_at(lo, a, plan.residual[a]);
        last[a] = voxel_at(hi, a, unused);
    }
    plan.first = to_coord(first);
    CG_ENFORCE(g.contains(plan.first) && g.contains(to_coord(last)), "Bresenham clipping left the grid");
    plan.first_index = static_cast<std::ptrdiff_t>(g.index_of(plan.first));
    plan.count = static_cast<std::int32_t>(hi - lo + 1);
    plan.modulus = modulus;
    const std::array<std::ptrdiff_t, 3> stride = strides_of(n);
    const Eigen::Vector3d dir = s.length > 0.0 ? Eigen::Vector3d((end - start) / s.length) : Eigen::Vector3d::Zero();
    for (std::size_t a = 0U; a < 3U; ++a) {
        plan.increment[a] = 2 * e[a];
        plan.step[a] = sign[a];
        plan.stride[a] = sign[a] * stride[a];
        plan.t_step[a] = g.voxel_size() * sign[a] * dir[static_cast<Eigen::Index>(a)];
    }
    plan.length = s.length;
    plan.t_centre = (g.voxel_center(plan.first) - start).dot(dir);
    const double dominant_cosine = dir.cwiseAbs().maxCoeff();
    plan.half_step = dominant_cosine > 0.0 ? 0.5 * g.voxel_size() / dominant_cosine : 0.0;
    return plan;
}

}  // namespace detail

std::size_t count_traversed_voxels(Rasterization method, const GridGeometry& g, const Eigen::Vector3d& start,
                                   const Eigen::Vector3d& end) noexcept {
    return traverse(method, g, start, end, [](const TraversedVoxel& /*voxel*/) {});
}

}  // namespace cellguard
