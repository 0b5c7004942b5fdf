// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/footprint_fusion.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "reading_class.hpp"

namespace cellguard {

void FootprintStats::add(const FootprintStats& other) noexcept {
    boxes += other.boxes;
    voxels_filled += other.voxels_filled;
    voxels_exact += other.voxels_exact;
    voxels_safe_side += other.voxels_safe_side;
    pixel_tests += other.pixel_tests;
}

namespace {

/// A corner nearer the image plane than this (metres along the optical axis)
/// makes a box "crossed by the image plane": it has no finite footprint.
constexpr double kMinCornerDepth = 1e-3;
/// Widening of a footprint (pixels) and of a depth interval (metres), so that
/// rounding in the projection can only make a footprint larger.
constexpr double kPixelSlack = 1e-4;
constexpr double kDepthSlack = 1e-6;
/// At most this many pixels of an inner square are probed by the safe-side rule (4 x 4).
constexpr std::int32_t kInnerProbeSide = 4;
/// Depth of the box stack: 12 halvings reach one voxel from kMaxDimension,
/// each level holds at most 7 pending siblings.
constexpr std::size_t kStackSize = 7U * 13U + 8U;

/// A box whose every side is at most this many voxels is evaluated voxel by
/// voxel from its projected lattice (run_small_box).
constexpr std::int32_t kSmallSide = 2;
constexpr std::size_t kSmallLattice = static_cast<std::size_t>(kSmallSide + 1) *
                                      static_cast<std::size_t>(kSmallSide + 1) *
                                      static_cast<std::size_t>(kSmallSide + 1);

/// @p x limited to [lo, hi] (NaN gives lo).
double clamp(double x, double lo, double hi) noexcept { return x > lo ? (x < hi ? x : hi) : lo; }
/// floor and ceil of a value in [-2^30, 2^30], without a library call.
std::int32_t floor_to_int(double x) noexcept {
    const auto t = static_cast<std::int32_t>(x);
    return static_cast<double>(t) > x ? t - 1 : t;
}
std::int32_t ceil_to_int(double x) noexcept {
    const auto t = static_cast<std::int32_t>(x);
    return static_cast<double>(t) < x ? t + 1 : t;
}

/// Index of lattice point (i, j, k) of a box's (n0 x n1 x ...) lattice.
std::size_t lattice_index(std::int32_t i, std::int32_t j, std::int32_t k, std::int32_t n0, std::int32_t n1) noexcept {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n0) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(n1) * static_cast<std::size_t>(k));
}

/// A lattice point (a voxel corner) in the image.
struct Projected {
    double u = 0.0;       ///< column (valid unless behind)
    double v = 0.0;       ///< row (valid unless behind)
    double z = 0.0;       ///< depth along the optical axis
    double dist = 0.0;    ///< squared distance from the camera centre
    bool behind = false;  ///< at or behind the image plane (z <= kMinCornerDepth)
};

/// A box of voxels [lo, hi) per axis.
struct Box {
    std::array<std::int32_t, 3> lo{};
    std::array<std::int32_t, 3> hi{};
    [[nodiscard]] bool is_voxel() const noexcept {
        return hi[0] - lo[0] == 1 && hi[1] - lo[1] == 1 && hi[2] - lo[2] == 1;
    }
};

/// A box's projection into the image.
struct Footprint {
    bool behind = false;    ///< every corner at or behind the image plane
    bool crossed = false;   ///< some corner at or behind it (no finite footprint)
    bool empty = true;      ///< no pixel centre in the image lies in the bounding box
    bool in_image = false;  ///< the unclipped bounding box lies inside the image
    std::int32_t u0 = 0;    ///< pixel-centre rectangle, clipped to the image
    std::int32_t v0 = 0;
    std::int32_t u1 = -1;
    std::int32_t v1 = -1;
    double z_min = 0.0;  ///< nearest corner along the optical axis
    double z_max = 0.0;  ///< farthest corner along the optical axis
    double d_max = 0.0;  ///< farthest corner from the camera centre
};

/// One sensor's geometry against the grid, and its pass's state.
class SensorPass {
public:
    SensorPass(const GridGeometry& g, const SensorReading& r, const SensorModelTable& model,
               const FootprintParams& params, const DepthPyramid& pyramid, Span<std::int16_t> opinions) noexcept
        : grid_(g), reading_(r), model_(model), params_(params), pyramid_(pyramid), opinions_(opinions) {
        const Eigen::Matrix3d rt = r.pose.linear().transpose();
        const double s = g.voxel_size();
        const Eigen::Vector3d base = rt * (g.origin() - r.pose.translation());
        for (Eigen::Index a = 0; a < 3; ++a) {
            base_[static_cast<std::size_t>(a)] = base[a];
            for (Eigen::Index e = 0; e < 3; ++e) {
                axis_[static_cast<std::size_t>(e)][static_cast<std::size_t>(a)] = rt(a, e) * s;
            }
        }
        const Eigen::Vector3d u = (r.pose.translation() - g.origin()) / s;  // as ray_traversal's to_voxel_units
        for (Eigen::Index a = 0; a < 3; ++a) {
            camera_voxel_[static_cast<std::size_t>(a)] = std::floor(u[a]);
        }
        const PinholeIntrinsics& k = r.intrinsics;
        fx_ = k.fx;
        fy_ = k.fy;
        cx_ = k.cx;
        cy_ = k.cy;
        pixel_angle_ = std::sqrt(1.0 / (k.fx * k.fx) + 1.0 / (k.fy * k.fy));
        budget_ = params.exact_pixel_budget;
    }

    /// Steps 2 and 3 of the file comment over the whole grid.
    void run() noexcept;
    [[nodiscard]] const FootprintStats& stats() const noexcept { return stats_; }

private:
    [[nodiscard]] Eigen::Vector3d lattice(double i, double j, double k) const noexcept {
        Eigen::Vector3d p;
        for (std::size_t a = 0U; a < 3U; ++a) {
            p[static_cast<Eigen::Index>(a)] = base_[a] + i * axis_[0][a] + j * axis_[1][a] + k * axis_[2][a];
        }
        return p;
    }
    [[nodiscard]] Projected project_point(double i, double j, double k) const noexcept;
    [[nodiscard]] Projected project_camera(double x, double y, double z) const noexcept;
    [[nodiscard]] Footprint footprint_of(const std::array<const Projected*, 8>& corners) const noexcept;
    [[nodiscard]] Footprint project(const Box& b) const noexcept;
    void classify(const Box& b, const Footprint& f) noexcept;
    /// Evaluates a box of sides <= kSmallSide voxel by voxel; false (nothing
    /// done) when a lattice point lies at or behind the image plane.
    bool run_small_box(const Box& b) noexcept;
    /// True when the box is decided as a whole (none or filled).
    bool decide_box(const Box& b, const Footprint& f, const DepthRange& q) noexcept;
    void decide_voxel(const Box& b, const Footprint& f, const DepthRange& q) noexcept;
    [[nodiscard]] std::int16_t exact_opinion(const Box& b, const Footprint& f) noexcept;
    [[nodiscard]] bool inner_square_passes(const Box& b, double z_max) const noexcept;
    void fill(const Box& b, std::int16_t value) noexcept;
    void raise(std::size_t index, std::int16_t value) noexcept {
        std::int16_t& o = opinions_[index];
        o = value > o ? value : o;
    }

    const GridGeometry& grid_;
    const SensorReading& reading_;
    const SensorModelTable& model_;
    const FootprintParams& params_;
    const DepthPyramid& pyramid_;
    Span<std::int16_t> opinions_;
    std::array<double, 3> base_{};                 ///< lattice point (0, 0, 0) in the camera frame
    std::array<std::array<double, 3>, 3> axis_{};  ///< one voxel along each grid axis, in the camera frame
    /// The camera's voxel coordinate per axis, floor((position - origin) / size) as
    /// ray traversal takes it (a double: the camera may lie any distance outside the grid).
    std::array<double, 3> camera_voxel_{};
    double fx_ = 0.0;
    double fy_ = 0.0;
    double cx_ = 0.0;
    double cy_ = 0.0;
    double pixel_angle_ = 0.0;
    std::uint64_t budget_ = 0U;
    FootprintStats stats_{};
};

Projected SensorPass::project_point(double i, double j, double k) const noexcept {
    return project_camera(base_[0] + i * axis_[0][0] + j * axis_[1][0] + k * axis_[2][0],
                          base_[1] + i * axis_[0][1] + j * axis_[1][1] + k * axis_[2][1],
                          base_[2] + i * axis_[0][2] + j * axis_[1][2] + k * axis_[2][2]);
}

Projected SensorPass::project_camera(double x, double y, double z) const noexcept {
    Projected out;
    out.z = z;
    out.dist = x * x + y * y + z * z;
    out.behind = z <= kMinCornerDepth;
    if (!out.behind) {
        const double inv_z = 1.0 / z;
        out.u = fx_ * x * inv_z + cx_;
        out.v = fy_ * y * inv_z + cy_;
    }
    return out;
}

Footprint SensorPass::footprint_of(const std::array<const Projected*, 8>& corners) const noexcept {
    Footprint f;
    const PinholeIntrinsics& k = reading_.intrinsics;
    // The extremes start empty: min at +inf, max at -inf (one pair per coordinate).
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::array<double, 2> u_range{kInf, -kInf};
    std::array<double, 2> v_range{kInf, -kInf};
    double& u_min = u_range[0];
    double& u_max = u_range[1];
    double& v_min = v_range[0];
    double& v_max = v_range[1];
    f.z_min = kInf;
    f.z_max = -kInf;
    std::int32_t behind = 0;
    for (const Projected* c : corners) {
        const Projected& p = *c;
        f.z_min = p.z < f.z_min ? p.z : f.z_min;
        f.z_max = p.z > f.z_max ? p.z : f.z_max;
        f.d_max = p.dist > f.d_max ? p.dist : f.d_max;  // squared until the end
        behind += p.behind ? 1 : 0;
        u_min = p.u < u_min ? p.u : u_min;
        u_max = p.u > u_max ? p.u : u_max;
        v_min = p.v < v_min ? p.v : v_min;
        v_max = p.v > v_max ? p.v : v_max;
    }
    f.d_max = std::sqrt(f.d_max);
    f.behind = behind == 8;
    f.crossed = behind > 0;
    if (f.crossed) {
        return f;
    }
    const auto w_last = static_cast<double>(k.width - 1);
    const auto h_last = static_cast<double>(k.height - 1);
    f.in_image = u_min >= 0.0 && v_min >= 0.0 && u_max <= w_last && v_max <= h_last;
    // Clamp to the image (one pixel beyond it on each side), then round inwards to pixel centres.
    const std::int32_t u0 = ceil_to_int(clamp(u_min - kPixelSlack, -1.0, w_last + 1.0));
    const std::int32_t u1 = floor_to_int(clamp(u_max + kPixelSlack, -1.0, w_last + 1.0));
    const std::int32_t v0 = ceil_to_int(clamp(v_min - kPixelSlack, -1.0, h_last + 1.0));
    const std::int32_t v1 = floor_to_int(clamp(v_max + kPixelSlack, -1.0, h_last + 1.0));
    f.u0 = u0 > 0 ? u0 : 0;
    f.v0 = v0 > 0 ? v0 : 0;
    f.u1 = u1 < k.width - 1 ? u1 : k.width - 1;
    f.v1 = v1 < k.height - 1 ? v1 : k.height - 1;
    f.empty = f.u0 > f.u1 || f.v0 > f.v1;
    return f;
}

Footprint SensorPass::project(const Box& b) const noexcept {
    // The low corner, then the others by adding the box's edges.
    std::array<double, 3> p0{};
    std::array<std::array<double, 3>, 3> edge{};
    for (std::size_t a = 0U; a < 3U; ++a) {
        p0[a] = base_[a] + b.lo[0] * axis_[0][a] + b.lo[1] * axis_[1][a] + b.lo[2] * axis_[2][a];
        for (std::size_t e = 0U; e < 3U; ++e) {
            edge[e][a] = static_cast<double>(b.hi[e] - b.lo[e]) * axis_[e][a];
        }
    }
    std::array<Projected, 8> points;
    std::array<const Projected*, 8> corners{};
    for (std::size_t c = 0U; c < 8U; ++c) {
        std::array<double, 3> q = p0;
        for (std::size_t e = 0U; e < 3U; ++e) {
            if (((c >> e) & 1U) != 0U) {
                q[0] += edge[e][0];
                q[1] += edge[e][1];
                q[2] += edge[e][2];
            }
        }
        points[c] = project_camera(q[0], q[1], q[2]);
        corners[c] = &points[c];
    }
    return footprint_of(corners);
}

void SensorPass::classify(const Box& b, const Footprint& f) noexcept {
    const DepthRange q = pyramid_.query(f.u0, f.v0, f.u1, f.v1);
    if (!decide_box(b, f, q) && b.is_voxel()) {
        decide_voxel(b, f, q);
    }
}

bool SensorPass::run_small_box(const Box& b) noexcept {
    // The box's lattice, projected once: each voxel's footprint is read off
    // its eight corners (the same numbers project() computes for it).
    const std::int32_t n0 = b.hi[0] - b.lo[0] + 1;
    const std::int32_t n1 = b.hi[1] - b.lo[1] + 1;
    const std::int32_t n2 = b.hi[2] - b.lo[2] + 1;
    std::array<Projected, kSmallLattice> lat;
    for (std::int32_t k = 0; k < n2; ++k) {
        for (std::int32_t j = 0; j < n1; ++j) {
            for (std::int32_t i = 0; i < n0; ++i) {
                const Projected p = project_point(b.lo[0] + i, b.lo[1] + j, b.lo[2] + k);
                if (p.behind) {
                    return false;  // near the camera: the general path handles it
                }
                lat[lattice_index(i, j, k, n0, n1)] = p;
            }
        }
    }
    for (std::int32_t z = 0; z + 1 < n2; ++z) {
        for (std::int32_t y = 0; y + 1 < n1; ++y) {
            for (std::int32_t x = 0; x + 1 < n0; ++x) {
                std::array<const Projected*, 8> corners{};
                for (std::int32_t c = 0; c < 8; ++c) {
                    const auto bits = static_cast<std::uint32_t>(c);
                    const std::int32_t i = x + static_cast<std::int32_t>(bits & 1U);
                    const std::int32_t j = y + static_cast<std::int32_t>((bits >> 1U) & 1U);
                    const std::int32_t k = z + static_cast<std::int32_t>((bits >> 2U) & 1U);
                    corners[static_cast<std::size_t>(c)] = &lat[lattice_index(i, j, k, n0, n1)];
                }
                ++stats_.boxes;
                const Footprint f = footprint_of(corners);
                if (!f.empty) {
                    const Box v{{b.lo[0] + x, b.lo[1] + y, b.lo[2] + z},
                                {b.lo[0] + x + 1, b.lo[1] + y + 1, b.lo[2] + z + 1}};
                    classify(v, f);
                }
            }
        }
    }
    return true;
}

void SensorPass::fill(const Box& b, std::int16_t value) noexcept {
    const GridDims d = grid_.dims();
    for (std::int32_t z = b.lo[2]; z < b.hi[2]; ++z) {
        for (std::int32_t y = b.lo[1]; y < b.hi[1]; ++y) {
            const std::size_t row = static_cast<std::size_t>(d.nx) *
                                    (static_cast<std::size_t>(y) +
                                     static_cast<std::size_t>(d.ny) * static_cast<std::size_t>(z));
            for (std::int32_t x = b.lo[0]; x < b.hi[0]; ++x) {
                raise(row + static_cast<std::size_t>(x), value);
            }
        }
    }
    stats_.voxels_filled += static_cast<std::uint64_t>(b.hi[0] - b.lo[0]) *
                            static_cast<std::uint64_t>(b.hi[1] - b.lo[1]) *
                            static_cast<std::uint64_t>(b.hi[2] - b.lo[2]);
}

bool SensorPass::decide_box(const Box& b, const Footprint& f, const DepthRange& q) noexcept {
    if (q.empty() || static_cast<double>(q.max) < f.z_min - kDepthSlack) {
        return true;  // no valid reading, or every ray ends in front of the box: no opinion
    }
    const double beyond = static_cast<double>(q.min) - f.z_max;
    if (beyond >= model_.ramp_length() + kDepthSlack && !q.any_invalid && f.in_image &&
        grid_.voxel_size() >= f.d_max * pixel_angle_) {
        // Every voxel's inner square (half-width >= 0.5) holds a pixel centre
        // of the image, whose ray crosses the voxel and passes it by at least
        // the ramp: the constant free value, exactly. (A box within the ramp
        // of a reading is split: its voxels get the exact ramp values.)
        fill(b, model_.constant_free_evidence());
        return true;
    }
    return false;
}

/// Where the ray o + t w (t: depth along the optical axis) leaves the box
/// [lo, hi] (given relative to o), or a negative value when it misses it or
/// leaves it before t = 0. Slab test without a library call. A ray parallel
/// to axis a's faces (w[a] == 0) is in the box's slab iff @p in_slab[a]: the
/// caller decides that from the camera's voxel index as ray traversal does,
/// not from lo and hi, whose rounding would put a ray that lies in a face
/// into both voxel columns beside it.
double ray_exit_depth(const Eigen::Vector3d& w, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::array<bool, 3>& in_slab) noexcept {
    double t_in = -std::numeric_limits<double>::infinity();
    double t_out = std::numeric_limits<double>::infinity();
    for (Eigen::Index a = 0; a < 3; ++a) {
        if (w[a] == 0.0) {
            if (!in_slab[static_cast<std::size_t>(a)]) {
                return -1.0;  // parallel to the slab and outside it
            }
            continue;
        }
        const double inv = 1.0 / w[a];
        const double t1 = lo[a] * inv;
        const double t2 = hi[a] * inv;
        const double near = t1 < t2 ? t1 : t2;
        const double far = t1 < t2 ? t2 : t1;
        t_in = near > t_in ? near : t_in;
        t_out = far < t_out ? far : t_out;
    }
    return t_in < t_out ? t_out : -1.0;
}

std::int16_t SensorPass::exact_opinion(const Box& b, const Footprint& f) noexcept {
    const PinholeIntrinsics& k = reading_.intrinsics;
    const Eigen::Matrix3d& r = reading_.pose.linear();
    const double s = grid_.voxel_size();
    const Eigen::Vector3d lo = grid_.origin() + s * Eigen::Vector3d(b.lo[0], b.lo[1], b.lo[2]) -
                               reading_.pose.translation();
    const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(s);
    std::array<bool, 3> in_slab{};  // for rays parallel to an axis's faces: traversal's column
    for (std::size_t a = 0U; a < 3U; ++a) {
        in_slab[a] = camera_voxel_[a] == static_cast<double>(b.lo[a]);
    }
    const double inv_fx = 1.0 / k.fx;
    const double inv_fy = 1.0 / k.fy;
    std::int16_t best = kNoOpinion;
    for (std::int32_t v = f.v0; v <= f.v1; ++v) {
        const double yn = (static_cast<double>(v) - k.cy) * inv_fy;
        const Eigen::Vector3d row = r.col(1) * yn + r.col(2);
        for (std::int32_t u = f.u0; u <= f.u1; ++u) {
            const float d = pyramid_.depth(u, v);
            if (!(d < std::numeric_limits<float>::infinity())) {
                continue;  // no valid reading
            }
            const double xn = (static_cast<double>(u) - k.cx) * inv_fx;
            const double t_out = ray_exit_depth(row + r.col(0) * xn, lo, hi,
                                                in_slab);  // cell frame, per metre of depth
            if (t_out < 0.0 || static_cast<double>(d) < t_out) {
                continue;  // misses the voxel, or ends in front of or inside it (a hit is step 1's)
            }
            const double along = std::sqrt(xn * xn + yn * yn + 1.0);
            const std::int16_t e = model_.free_evidence(along * (static_cast<double>(d) - t_out));
            best = e > best ? e : best;
        }
    }
    return best;
}

bool SensorPass::inner_square_passes(const Box& b, double z_max) const noexcept {
    const PinholeIntrinsics& k = reading_.intrinsics;
    const Eigen::Vector3d c = lattice(b.lo[0] + 0.5, b.lo[1] + 0.5, b.lo[2] + 0.5);
    if (c.z() <= kMinCornerDepth) {
        return false;
    }
    const double half = 0.5 * grid_.voxel_size() / (c.norm() * pixel_angle_);
    const double uc = k.fx * c.x() / c.z() + k.cx;
    const double vc = k.fy * c.y() / c.z() + k.cy;
    const double iu0 = std::fmax(std::ceil(uc - half), 0.0);
    const double iu1 = std::fmin(std::floor(uc + half), static_cast<double>(k.width - 1));
    const double iv0 = std::fmax(std::ceil(vc - half), 0.0);
    const double iv1 = std::fmin(std::floor(vc + half), static_cast<double>(k.height - 1));
    if (!(iu0 <= iu1 && iv0 <= iv1)) {
        return false;
    }
    const auto u0 = static_cast<std::int32_t>(iu0);
    const auto v0 = static_cast<std::int32_t>(iv0);
    const std::int32_t nu = static_cast<std::int32_t>(iu1) - u0 + 1;
    const std::int32_t nv = static_cast<std::int32_t>(iv1) - v0 + 1;
    const std::int32_t su = nu > kInnerProbeSide ? nu / kInnerProbeSide : 1;
    const std::int32_t sv = nv > kInnerProbeSide ? nv / kInnerProbeSide : 1;
    for (std::int32_t j = 0; j < kInnerProbeSide && j * sv < nv; ++j) {
        for (std::int32_t i = 0; i < kInnerProbeSide && i * su < nu; ++i) {
            const float d = pyramid_.depth(u0 + i * su, v0 + j * sv);
            if (d < std::numeric_limits<float>::infinity() && static_cast<double>(d) > z_max + kDepthSlack) {
                return true;
            }
        }
    }
    return false;
}

void SensorPass::decide_voxel(const Box& b, const Footprint& f, const DepthRange& q) noexcept {
    const std::size_t index = grid_.index_of(VoxelCoord{b.lo[0], b.lo[1], b.lo[2]});
    if (opinions_[index] == model_.reading_evidence()) {
        return;  // a hit wins over every free value
    }
    const std::uint64_t area = static_cast<std::uint64_t>(f.u1 - f.u0 + 1) *
                               static_cast<std::uint64_t>(f.v1 - f.v0 + 1);
    if (area <= params_.exact_footprint_max && area <= budget_) {
        budget_ -= area;
        stats_.pixel_tests += area;
        ++stats_.voxels_exact;
        raise(index, exact_opinion(b, f));
        return;
    }
    ++stats_.voxels_safe_side;
    if (inner_square_passes(b, f.z_max)) {
        const bool all_beyond = static_cast<double>(q.min) > f.z_max + kDepthSlack;
        raise(index, model_.free_evidence(all_beyond ? static_cast<double>(q.min) - f.z_max : 0.0));
    }
}

void SensorPass::run() noexcept {
    const GridDims d = grid_.dims();
    std::array<Box, kStackSize> stack{};
    std::size_t top = 0U;
    stack[top++] = Box{{0, 0, 0}, {d.nx, d.ny, d.nz}};
    while (top > 0U) {
        const Box b = stack[--top];
        ++stats_.boxes;
        const Footprint f = project(b);
        if (f.behind || (f.crossed && b.is_voxel()) || (!f.crossed && f.empty)) {
            continue;  // no pixel ray can cross the box (or the camera's own voxel: see the file comment)
        }
        if (!f.crossed) {
            const DepthRange q = pyramid_.query(f.u0, f.v0, f.u1, f.v1);
            if (decide_box(b, f, q)) {
                continue;
            }
            if (b.is_voxel()) {
                decide_voxel(b, f, q);
                continue;
            }
            if (b.hi[0] - b.lo[0] <= kSmallSide && b.hi[1] - b.lo[1] <= kSmallSide && b.hi[2] - b.lo[2] <= kSmallSide &&
                run_small_box(b)) {
                continue;
            }
        }
        // Split every axis longer than one voxel; push the children in reverse
        // so that they are taken in a fixed order (x fastest, low half first).
        std::array<std::int32_t, 3> cuts{};
        std::array<std::int32_t, 3> parts{};
        for (std::size_t a = 0U; a < 3U; ++a) {
            const std::int32_t n = b.hi[a] - b.lo[a];
            parts[a] = n > 1 ? 2 : 1;
            cuts[a] = b.lo[a] + n / 2;
        }
        for (std::int32_t c = parts[0] * parts[1] * parts[2] - 1; c >= 0; --c) {
            const std::array<std::int32_t, 3> pick{c % parts[0], (c / parts[0]) % parts[1], c / (parts[0] * parts[1])};
            Box child;
            for (std::size_t a = 0U; a < 3U; ++a) {
                const bool split = parts[a] == 2;
                child.lo[a] = (split && pick[a] == 1) ? cuts[a] : b.lo[a];
                child.hi[a] = (split && pick[a] == 0) ? cuts[a] : b.hi[a];
            }
            CG_ENFORCE(top < kStackSize, "footprint box stack");
            stack[top++] = child;
        }
    }
}

/// Step 1's placement of a reading in its voxel, by the arithmetic of
/// fuse_sensor (depth_pixel_point, reading_in_cell, world_to_voxel_unchecked)
/// where it matters and by a shorter one where it cannot differ: the short
/// form skips the point's rounding to float, which moves it by at most
/// 2^-24 of its coordinates; a reading whose short-form position lies within
/// `margin_` voxels of a face, or whose range lies within 1e-5 of a range
/// limit, is placed and classified the long way. So both give the same voxel
/// and the same class for every reading.
class HitPlacer {
public:
    HitPlacer(const GridGeometry& g, const SensorReading& r) noexcept
        : g_(g), r_(r), inv_fx_(1.0 / r.intrinsics.fx), inv_fy_(1.0 / r.intrinsics.fy) {
        const double s = g.voxel_size();
        m_ = r.pose.linear() / s;
        b_ = (r.pose.translation() - g.origin()) / s;
        // Float rounding of a point within kMaxSensorRange of the sensor, in voxels, with a factor 16 to spare.
        margin_ = 1e-9 + 16.0 * 0x1.0p-24 * static_cast<double>(kMaxSensorRange) / s;
        const auto lo = static_cast<double>(r.min_range);
        const auto hi = static_cast<double>(r.max_range);
        min2_lo_ = lo * lo * (1.0 - 1e-5);
        min2_hi_ = lo * lo * (1.0 + 1e-5);
        max2_lo_ = hi * hi * (1.0 - 1e-5);
        max2_hi_ = hi * hi * (1.0 + 1e-5);
    }

    /// The class of the reading of pixel (u, v) at raw depth @p d, and its voxel when valid.
    detail::ReadingClass place(std::int32_t u, std::int32_t v, float d, VoxelCoord& voxel) const noexcept {
        if (!(d > 0.0F && d <= kMaxSensorRange)) {
            return place_exactly(u, v, d, voxel);
        }
        const double xn = (static_cast<double>(u) - r_.intrinsics.cx) * inv_fx_;
        const double yn = (static_cast<double>(v) - r_.intrinsics.cy) * inv_fy_;
        const auto dd = static_cast<double>(d);
        const double range2 = dd * dd * (xn * xn + yn * yn + 1.0);
        if ((range2 > min2_lo_ && range2 < min2_hi_) || (range2 > max2_lo_ && range2 < max2_hi_)) {
            return place_exactly(u, v, d, voxel);  // near a range limit
        }
        if (range2 <= min2_lo_ || range2 >= max2_hi_) {
            return detail::ReadingClass::kOutOfRange;
        }
        const Eigen::Vector3d q = m_ * Eigen::Vector3d(xn * dd, yn * dd, dd) + b_;
        std::array<std::int32_t, 3> c{};
        for (Eigen::Index a = 0; a < 3; ++a) {
            if (!(q[a] > -1e9 && q[a] < 1e9)) {
                return place_exactly(u, v, d, voxel);
            }
            const std::int32_t f = floor_to_int(q[a]);
            const double frac = q[a] - static_cast<double>(f);
            if (frac < margin_ || frac > 1.0 - margin_) {
                return place_exactly(u, v, d, voxel);  // near a voxel face
            }
            c[static_cast<std::size_t>(a)] = f;
        }
        voxel = VoxelCoord{c[0], c[1], c[2]};
        return detail::ReadingClass::kValid;
    }

private:
    detail::ReadingClass place_exactly(std::int32_t u, std::int32_t v, float d, VoxelCoord& voxel) const noexcept {
        detail::ReadingClass c = detail::classify_depth(d);
        if (c != detail::ReadingClass::kValid) {
            return c;
        }
        const Eigen::Vector3f p = depth_pixel_point(r_.intrinsics, inv_fx_, inv_fy_, u, v, d);
        c = detail::classify_point(p, r_.min_range, r_.max_range);
        if (c == detail::ReadingClass::kValid) {
            voxel = g_.world_to_voxel_unchecked(reading_in_cell(r_.pose, p));
        }
        return c;
    }

    const GridGeometry& g_;
    const SensorReading& r_;
    Eigen::Matrix3d m_;
    Eigen::Vector3d b_;
    double inv_fx_ = 0.0;
    double inv_fy_ = 0.0;
    double margin_ = 0.0;
    double min2_lo_ = 0.0;
    double min2_hi_ = 0.0;
    double max2_lo_ = 0.0;
    double max2_hi_ = 0.0;
};

/// Step 1: the hits, exactly as fuse_sensor places them, and level 0 of the pyramid.
FusionStats hit_pass(const GridGeometry& g, const SensorReading& r, const SensorModelTable& model,
                     DepthPyramid& pyramid, Span<std::int16_t> opinions) noexcept {
    FusionStats s;
    const HitPlacer placer(g, r);
    const std::int16_t hit = model.reading_evidence();
    std::size_t i = 0U;
    for (std::int32_t v = 0; v < r.intrinsics.height; ++v) {
        for (std::int32_t u = 0; u < r.intrinsics.width; ++u, ++i) {
            const float d = depth_value(r, i);
            VoxelCoord vc;
            const detail::ReadingClass c = placer.place(u, v, d, vc);
            if (c != detail::ReadingClass::kValid) {
                detail::count_skipped(s, c);
                pyramid.set_pixel(u, v, 0.0F, false);
                continue;
            }
            pyramid.set_pixel(u, v, d, true);
            ++s.rays_fused;
            if (g.contains(vc)) {
                opinions[g.index_of(vc)] = hit;
                ++s.readings_in_grid;
            }
        }
    }
    return s;
}

/// The count of intervals after @p levels halvings of an axis of @p n voxels
/// (an interval of one voxel is not halved further). After each halving the
/// intervals have at most two lengths, floor and ceil of the previous
/// lengths' halves: the count is tracked per length, without recursion.
std::uint64_t intervals_after(std::int32_t n, std::int32_t levels) noexcept {
    std::int64_t len_a = n;  // the longer length
    std::uint64_t count_a = 1U;
    std::uint64_t count_b = 0U;  // intervals of length len_a - 1
    for (std::int32_t l = 0; l < levels && len_a > 1; ++l) {
        // An interval of length m becomes m / 2 and m - m / 2 (lengths 1 stay).
        const std::int64_t len_b = len_a - 1;
        std::uint64_t next_hi = 0U;  // count of length ceil(len_a / 2)
        std::uint64_t next_lo = 0U;  // count of length ceil(len_a / 2) - 1
        const std::int64_t hi = len_a - len_a / 2;
        const auto add = [&](std::int64_t m, std::uint64_t count) {
            if (count == 0U) {
                return;
            }
            if (m <= 1) {
                (hi == 1 ? next_hi : next_lo) += count;  // m == 1 keeps its length
                return;
            }
            const std::int64_t parts[2] = {m / 2, m - m / 2};
            for (const std::int64_t p : parts) {
                (p == hi ? next_hi : next_lo) += count;
            }
        };
        add(len_a, count_a);
        add(len_b, count_b);
        len_a = hi;
        count_a = next_hi;
        count_b = next_lo;
    }
    return count_a + count_b;
}

}  // namespace

std::uint64_t footprint_box_count(const GridGeometry& grid) noexcept {
    const GridDims d = grid.dims();
    if (grid.voxel_count() == 0U) {
        return 0U;
    }
    std::int32_t depth = 0;
    const std::int32_t longest = d.nx > d.ny ? (d.nx > d.nz ? d.nx : d.nz) : (d.ny > d.nz ? d.ny : d.nz);
    for (std::uint64_t side = 1U; side < static_cast<std::uint64_t>(longest); side *= 2U) {
        ++depth;  // halvings until the longest axis is one voxel
    }
    // Nodes per level <= product of the axes' intervals at that level (an upper bound:
    // it also counts single voxels that ended on an earlier level).
    std::uint64_t total = 0U;
    for (std::int32_t level = 0; level <= depth; ++level) {
        total += intervals_after(d.nx, level) * intervals_after(d.ny, level) * intervals_after(d.nz, level);
    }
    return total;
}

std::uint64_t footprint_work_bound(const GridGeometry& grid, std::uint64_t pixels,
                                   const FootprintParams& params) noexcept {
    return 2U * pixels + footprint_box_count(grid) + params.exact_pixel_budget + params.exact_footprint_max;
}

Result<FusionStats> footprint_opinions(const GridGeometry& grid, const SensorReading& reading,
                                       const SensorModelTable& model, const FootprintParams& params,
                                       const FootprintWorkspace& work, FootprintStats* stats) noexcept {
    const Status valid = validate_sensor_reading(reading);
    if (!valid.ok()) {
        return valid.error();
    }
    if (!is_depth_image(reading.kind)) {
        return ErrorCode::kInvalidArgument;
    }
    const std::size_t n = grid.voxel_count();
    if (work.opinions.size() < n) {
        return ErrorCode::kStorageTooSmall;
    }
    const Result<DepthPyramid> made = DepthPyramid::make(reading.intrinsics.width, reading.intrinsics.height,
                                                         work.pyramid_min, work.pyramid_max, work.pyramid_invalid);
    if (!made.ok()) {
        return made.error();
    }
    const Span<std::int16_t> opinions = work.opinions.subspan(0U, n);
    for (std::int16_t& e : opinions) {
        e = kNoOpinion;
    }
    DepthPyramid pyramid = made.value();
    const FusionStats s = hit_pass(grid, reading, model, pyramid, opinions);
    pyramid.build_levels();
    SensorPass pass(grid, reading, model, params, pyramid, opinions);
    pass.run();
    if (stats != nullptr) {
        stats->add(pass.stats());
    }
    return s;
}

namespace {

/// Voxels pooled by one task of fuse_frame_footprint's pooling.
constexpr std::size_t kPoolChunk = std::size_t{1} << 16U;

struct FrameJob {
    const GridGeometry* grid = nullptr;
    Span<const SensorReading> sensors{};
    const SensorModelTable* model = nullptr;
    const FootprintParams* params = nullptr;
    Span<const FootprintWorkspace> workspaces{};
    EvidenceGrid* target = nullptr;
    std::array<FusionStats, kMaxSensors> fusion{};
    std::array<FootprintStats, kMaxSensors> footprint{};
    std::array<bool, kMaxSensors> ok{};
};

void sensor_task(void* context, std::size_t i) noexcept {
    auto& job = *static_cast<FrameJob*>(context);
    const Result<FusionStats> r = footprint_opinions(*job.grid, job.sensors[i], *job.model, *job.params,
                                                     job.workspaces[i], &job.footprint[i]);
    job.ok[i] = r.ok();
    if (r.ok()) {
        job.fusion[i] = r.value();
    }
}

void pool_task(void* context, std::size_t chunk) noexcept {
    auto& job = *static_cast<FrameJob*>(context);
    std::int16_t* const lo = job.target->log_odds().data();
    std::uint8_t* const obs = job.target->observed().data();
    const std::size_t n = job.target->voxel_count();
    const std::size_t begin = chunk * kPoolChunk;
    const std::size_t end = begin + kPoolChunk < n ? begin + kPoolChunk : n;
    for (std::size_t s = 0U; s < job.sensors.size(); ++s) {
        const std::int16_t* const op = job.workspaces[s].opinions.data();
        for (std::size_t i = begin; i < end; ++i) {
            if (op[i] != kNoOpinion) {
                lo[i] = job.model->pool(lo[i], op[i]);
                obs[i] = 1U;
            }
        }
    }
}

}  // namespace

Result<FusionStats> fuse_frame_footprint(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                         const SensorModelTable& model, const FootprintParams& params,
                                         Span<const FootprintWorkspace> workspaces, TaskRunner& runner,
                                         FootprintStats* stats) noexcept {
    if (sensors.size() > kMaxSensors) {
        return ErrorCode::kCapacityExceeded;
    }
    if (workspaces.empty()) {
        return ErrorCode::kStorageTooSmall;
    }
    const bool parallel = workspaces.size() >= sensors.size();
    for (std::size_t i = 0U; i < sensors.size(); ++i) {
        const SensorReading& r = sensors[i];
        const Status valid = validate_sensor_reading(r);
        if (!valid.ok()) {
            return valid.error();
        }
        if (!is_depth_image(r.kind)) {
            return ErrorCode::kInvalidArgument;
        }
        // Sensor i uses workspace i when each has its own, else workspace 0.
        const std::size_t cells = depth_pyramid_cells(r.intrinsics.width, r.intrinsics.height);
        const FootprintWorkspace& ws = workspaces[parallel ? i : 0U];
        if (ws.opinions.size() < grid.voxel_count() || ws.pyramid_min.size() < cells || ws.pyramid_max.size() < cells ||
            ws.pyramid_invalid.size() < cells) {
            return ErrorCode::kStorageTooSmall;
        }
    }
    FusionStats total;
    FootprintStats fp;
    if (parallel) {
        FrameJob job;
        job.grid = &grid.geometry();
        job.sensors = sensors;
        job.model = &model;
        job.params = &params;
        job.workspaces = workspaces;
        job.target = &grid;
        runner.run(sensors.size(), &sensor_task, &job);
        for (std::size_t i = 0U; i < sensors.size(); ++i) {
            if (!job.ok[i]) {
                return ErrorCode::kInvalidArgument;  // unreachable: checked above, before any evidence
            }
            total.add(job.fusion[i]);
            fp.add(job.footprint[i]);
        }
        runner.run((grid.voxel_count() + kPoolChunk - 1U) / kPoolChunk, &pool_task, &job);
    } else {
        for (const SensorReading& r : sensors) {
            const Result<FusionStats> s = footprint_opinions(grid.geometry(), r, model, params, workspaces[0], &fp);
            if (!s.ok()) {         // GCOVR_EXCL_BR_LINE: checked above
                return s.error();  // unreachable: checked above GCOVR_EXCL_BR_LINE
            }
            total.add(s.value());
            pool_opinions(grid, Span<const std::int16_t>(workspaces[0].opinions.data(), grid.voxel_count()), model);
        }
    }
    if (stats != nullptr) {
        stats->add(fp);
    }
    return total;
}

}  // namespace cellguard
