// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/footprint_fusion.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "hit_pass.hpp"
#include "placement.hpp"
#include "reading_class.hpp"

namespace cellguard {

void FootprintStats::add(const FootprintStats& other) noexcept {
    pixels += other.pixels;
    voxels_visited += other.voxels_visited;
    voxels_filled += other.voxels_filled;
    voxels_exact += other.voxels_exact;
    voxels_safe_side += other.voxels_safe_side;
    pixel_tests += other.pixel_tests;
    table_makes += other.table_makes;
}

namespace {

/// The index of voxel (x, y, z) in a grid of @p nx x @p ny x ... voxels (GridGeometry::index_of).
std::size_t index_of(std::int32_t x, std::int32_t y, std::int32_t z, std::size_t nx, std::size_t ny) noexcept {
    return static_cast<std::size_t>(x) + nx * (static_cast<std::size_t>(y) + ny * static_cast<std::size_t>(z));
}

/// A voxel whose nearest point lies nearer the image plane than this (metres
/// along the optical axis) is "crossed by the image plane": no opinion.
constexpr double kMinCornerDepth = 1e-3;
/// Widening of a footprint (pixels) and of a depth interval (metres), so that
/// rounding in the projection can only make a footprint larger.
constexpr double kPixelSlack = 1e-4;
constexpr double kDepthSlack = 1e-6;
/// At most this many pixels of an inner square are probed by the safe-side rule (4 x 4).
constexpr std::int32_t kInnerProbeSide = 4;
/// The image's four sides as half-spaces of the camera frame (see row_span).
constexpr std::size_t kSides = 4U;

/// @p x limited to [lo, hi], lo < hi (NaN gives lo). Written as a max, then a
/// min (each one instruction, no branch) with the values of the nested form
/// x > lo ? (x < hi ? x : hi) : lo.
double clamp(double x, double lo, double hi) noexcept {
    const double t = x > lo ? x : lo;
    return t < hi ? t : hi;
}
/// floor of a value in [-2^30, 2^30], without a library call: the grid's own
/// (the comparison's 0 or 1 corrects the truncation, no branch).
std::int32_t floor_to_int(double x) noexcept { return GridGeometry::floor_index(x); }
/// ceil of a value in [-2^30, 2^30], the same way.
std::int32_t ceil_to_int(double x) noexcept {
    const auto t = static_cast<std::int32_t>(x);
    return t + static_cast<std::int32_t>(static_cast<double>(t) < x);
}
double min2(double a, double b) noexcept { return a < b ? a : b; }
double max2(double a, double b) noexcept { return a > b ? a : b; }

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
        t_in = max2(t_in, min2(t1, t2));
        t_out = min2(t_out, max2(t1, t2));
    }
    return t_in < t_out ? t_out : -1.0;
}

/// A voxel as one camera sees it: the pixel centres its rays may come from
/// (a superset: the projection of the voxel's bounding box in the camera
/// frame) and its depth interval along the optical axis (exact).
struct VoxelView {
    std::int32_t u0 = 0;  ///< pixel-centre rectangle, clipped to the image
    std::int32_t v0 = 0;
    std::int32_t u1 = -1;
    std::int32_t v1 = -1;
    bool in_image = false;  ///< the unclipped rectangle lies inside the image
    double z_min = 0.0;     ///< nearest corner along the optical axis
    double z_max = 0.0;     ///< farthest corner along the optical axis
};

/// One sensor's geometry against the grid: the voxel pass of steps 2 and 3.
class SensorPass {
public:
    SensorPass(const GridGeometry& g, const SensorReading& r, const FootprintParams& params) noexcept
        : grid_(g), reading_(r), exact_max_(params.exact_footprint_max) {
        const Eigen::Matrix3d rt = r.pose.linear().transpose();
        const double s = g.voxel_size();
        const Eigen::Vector3d base = rt * (g.origin() - r.pose.translation());
        for (std::size_t a = 0U; a < 3U; ++a) {
            base_[a] = base[static_cast<Eigen::Index>(a)];
            for (std::size_t e = 0U; e < 3U; ++e) {
                axis_[e][a] = rt(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(e)) * s;
            }
            // Half the extent of a voxel along camera axis a (its corners: the centre +- half of each edge).
            half_[a] = 0.5 * (std::fabs(axis_[0][a]) + std::fabs(axis_[1][a]) + std::fabs(axis_[2][a]));
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
        w_last_ = static_cast<double>(k.width - 1);
        h_last_ = static_cast<double>(k.height - 1);
        pixel_angle_ = std::sqrt(1.0 / (k.fx * k.fx) + 1.0 / (k.fy * k.fy));
        radius_ = 0.5 * s * std::sqrt(3.0);
        // Resolved (every inner square holds a pixel centre) while the farthest corner's distance
        // D satisfies s >= D * pixel_angle, i.e. |centre| <= s / pixel_angle - radius.
        const double reach = s / pixel_angle_ - radius_;
        resolved_dist2_ = reach > 0.0 ? reach * reach : -1.0;
        // Sides of the image one pixel beyond its pixel centres: u >= -1, u <= width, v >= -1, v <= height.
        side_[0] = {fx_, 0.0, cx_ + 1.0};
        side_[1] = {-fx_, 0.0, static_cast<double>(k.width) - cx_};
        side_[2] = {0.0, fy_, cy_ + 1.0};
        side_[3] = {0.0, -fy_, static_cast<double>(k.height) - cy_};
        // The row spans' constants: a voxel's bounding sphere with a little to spare, and per side
        // that sphere's reach along the side's normal and the normal's change per voxel along x.
        sphere_margin_ = radius_ * (1.0 + 1e-9) + 1e-9;
        for (std::size_t i = 0U; i < kSides; ++i) {
            const std::array<double, 3>& n = side_[i];
            side_reach_[i] = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * sphere_margin_;
            side_step_[i] = n[0] * axis_[0][0] + n[1] * axis_[0][1] + n[2] * axis_[0][2];
        }
    }

    /// The voxels [lo, hi) of row (y, z) whose bounding sphere lies in front of the
    /// image plane and inside the image's four sides: a superset of the voxels
    /// the sensor has an opinion on. A function of the geometry alone.
    void row_span(std::int32_t y, std::int32_t z, std::int32_t& lo, std::int32_t& hi) const noexcept;

    /// Steps 2 and 3 of the file comment over every voxel of every row's span.
    void run(const SensorModelTable& model, const DepthPyramid& pyramid, Span<std::int16_t> opinions) noexcept;
    /// The same as run(), over the voxels of a table made for this geometry.
    void run(Span<const FootprintEntry> table, const SensorModelTable& model, const DepthPyramid& pyramid,
             Span<std::int16_t> opinions) noexcept;
    /// The table's entries into @p out, in run()'s order, with @p layout's cells;
    /// false when @p out is too short. @p count gets the voxels in view either way.
    [[nodiscard]] bool make_table(const DepthPyramid& layout, double ramp, Span<FootprintEntry> out,
                                  std::size_t& count) const noexcept;
    /// Work units of the worst frame: the voxels in view (those run() visits) and,
    /// for those whose corner rectangle has at most exact_footprint_max pixels,
    /// those pixels (the exact step's most tests), without running it.
    [[nodiscard]] std::uint64_t voxel_work_bound() const noexcept;
    [[nodiscard]] const FootprintStats& stats() const noexcept { return stats_; }

private:
    /// The centre of voxel (x, y, z) in the camera frame, coordinate @p a.
    [[nodiscard]] double centre(std::size_t a, double x, double y, double z) const noexcept {
        return base_[a] + (x + 0.5) * axis_[0][a] + (y + 0.5) * axis_[1][a] + (z + 0.5) * axis_[2][a];
    }
    /// The voxel centred at camera-frame @p c; false when it is crossed by the image plane or no pixel centre lies in its rectangle.
    [[nodiscard]] bool view_of(const std::array<double, 3>& c, VoxelView& out) const noexcept;
    /// The table entry of the voxel at @p index, centred at @p c, in view as @p f.
    [[nodiscard]] FootprintEntry entry_of(const DepthPyramid& layout, double ramp, const VoxelCoord& v,
                                          const std::array<double, 3>& c, const VoxelView& f) const noexcept;
    /// Calls @p fn(voxel, index, centre, view) for every voxel in view (a pixel
    /// centre in its footprint), row by row over the rows' spans: the voxels and
    /// the order of run(), of a table and of voxel_work_bound().
    template <typename Fn>
    void for_each_in_view(Fn&& fn) const noexcept {
        const GridDims d = grid_.dims();
        for (std::int32_t z = 0; z < d.nz; ++z) {
            for (std::int32_t y = 0; y < d.ny; ++y) {
                std::int32_t lo = 0;
                std::int32_t hi = 0;
                row_span(y, z, lo, hi);
                const std::size_t row = static_cast<std::size_t>(d.nx) *
                                        (static_cast<std::size_t>(y) +
                                         static_cast<std::size_t>(d.ny) * static_cast<std::size_t>(z));
                for (std::int32_t x = lo; x < hi; ++x) {
                    const std::array<double, 3> c{centre(0U, x, y, z), centre(1U, x, y, z), centre(2U, x, y, z)};
                    VoxelView f;
                    if (view_of(c, f)) {
                        fn(VoxelCoord{x, y, z}, row + static_cast<std::size_t>(x), c, f);
                    }
                }
            }
        }
    }
    /// Steps 2 and 3 for one voxel in view as @p f.
    void visit(const VoxelCoord& voxel, std::size_t index, const std::array<double, 3>& c, const VoxelView& f) noexcept;
    /// The rest of step 2 and step 3 for a voxel in view, centred at @p c, whose
    /// query @p q neither left it without an opinion nor filled it.
    /// @p square: the voxel's inner square when a table holds it, else null (computed here).
    void settle(const VoxelCoord& voxel, std::size_t index, const std::array<double, 3>& c, double z_max,
                const DepthRange& q, const VoxelView* square) noexcept;

    /// The rectangle of pixel centres in the bounding box of the voxel's eight projected
    /// corners, clipped to the image; false when a corner lies at or behind the image plane.
    [[nodiscard]] bool corner_rect(const std::array<double, 3>& c, VoxelView& out) const noexcept;
    /// Step 3: the voxel's free opinion ray by ray over @p f, as fuse_sensor computes it.
    [[nodiscard]] std::int16_t exact_opinion(const VoxelCoord& voxel, const VoxelView& f) const noexcept;
    /// The pixel rectangle of the inner square of the voxel centred at @p c, clipped to the
    /// image; false when it holds no pixel centre.
    [[nodiscard]] bool inner_square(const std::array<double, 3>& c, VoxelView& out) const noexcept;
    /// True when one of the (at most 4 x 4) probed pixels of @p square holds a reading beyond @p z_max.
    [[nodiscard]] bool probe_beyond(const VoxelView& square, double z_max) const noexcept;
    void raise(std::size_t index, std::int16_t value) noexcept {
        std::int16_t& o = opinions_[index];
        // The larger of the two, without a branch (pick is 0 or 1).
        const auto pick = static_cast<std::int32_t>(value > o);
        o = static_cast<std::int16_t>(pick * value + (1 - pick) * o);
    }

    const GridGeometry& grid_;
    const SensorReading& reading_;
    std::int64_t exact_max_ = 0;  ///< FootprintParams::exact_footprint_max
    const SensorModelTable* model_ = nullptr;
    const DepthPyramid* pyramid_ = nullptr;
    Span<std::int16_t> opinions_{};
    std::array<double, 3> base_{};                      ///< lattice point (0, 0, 0) in the camera frame
    std::array<std::array<double, 3>, 3> axis_{};       ///< one voxel along each grid axis, in the camera frame
    std::array<double, 3> half_{};                      ///< a voxel's half extent along each camera axis
    std::array<std::array<double, 3>, kSides> side_{};  ///< inward normals (x, y, z) of the image's sides
    std::array<double, kSides> side_reach_{};           ///< |normal| x sphere_margin_, per side
    std::array<double, kSides> side_step_{};            ///< normal . (one voxel along x), per side
    double sphere_margin_ = 0.0;                        ///< a voxel's bounding sphere, widened for rounding
    /// The camera's voxel coordinate per axis, floor((position - origin) / size) as
    /// ray traversal takes it (a double: the camera may lie any distance outside the grid).
    std::array<double, 3> camera_voxel_{};
    double fx_ = 0.0;
    double fy_ = 0.0;
    double cx_ = 0.0;
    double cy_ = 0.0;
    double w_last_ = 0.0;
    double h_last_ = 0.0;
    double pixel_angle_ = 0.0;
    double radius_ = 0.0;          ///< a voxel's bounding sphere
    double resolved_dist2_ = 0.0;  ///< squared centre distance up to which a voxel is resolved (< 0: none)
    FootprintStats stats_{};
};

void SensorPass::row_span(std::int32_t y, std::int32_t z, std::int32_t& lo, std::int32_t& hi) const noexcept {
    const std::int32_t nx = grid_.dims().nx;
    double first = 0.0;  // the span as real voxel indices, widened by a voxel below
    auto last = static_cast<double>(nx);
    bool none = false;
    // One linear constraint A + B i >= 0 on the row's voxel index i.
    const auto limit = [&](double a, double b) {
        if (b == 0.0) {
            none = none || a < 0.0;
        } else if (b > 0.0) {
            first = max2(first, -a / b);
        } else {
            last = min2(last, -a / b);
        }
    };
    std::array<double, 3> c0{};
    for (std::size_t a = 0U; a < 3U; ++a) {
        c0[a] = centre(a, 0.0, y, z);
    }
    limit(c0[2] + sphere_margin_ - kMinCornerDepth, axis_[0][2]);  // in front of the image plane
    for (std::size_t i = 0U; i < kSides; ++i) {
        const std::array<double, 3>& n = side_[i];
        limit(n[0] * c0[0] + n[1] * c0[1] + n[2] * c0[2] + side_reach_[i], side_step_[i]);
    }
    // One voxel more on each side, for the rounding of the bounds.
    lo = none ? 0 : static_cast<std::int32_t>(clamp(std::floor(first) - 1.0, 0.0, static_cast<double>(nx)));
    hi = none ? 0 : static_cast<std::int32_t>(clamp(std::ceil(last) + 2.0, 0.0, static_cast<double>(nx)));
    hi = hi > lo ? hi : lo;
}

std::uint64_t SensorPass::voxel_work_bound() const noexcept {
    std::uint64_t n = 0U;
    for_each_in_view([this, &n](const VoxelCoord&, std::size_t, const std::array<double, 3>& c, const VoxelView&) {
        ++n;
        VoxelView tight;
        if (exact_max_ > 0 && corner_rect(c, tight)) {
            const std::int64_t area = static_cast<std::int64_t>(tight.u1 - tight.u0 + 1) *
                                      static_cast<std::int64_t>(tight.v1 - tight.v0 + 1);
            n += area <= exact_max_ ? static_cast<std::uint64_t>(area) : 0U;
        }
    });
    return n;
}

bool SensorPass::view_of(const std::array<double, 3>& c, VoxelView& out) const noexcept {
    out.z_min = c[2] - half_[2];
    out.z_max = c[2] + half_[2];
    if (!(out.z_min > kMinCornerDepth)) {
        return false;  // crossed by the image plane or behind it (the camera's own voxel is unknown to it)
    }
    // x / z over the box [x - hx, x + hx] x [z_min, z_max] takes its extremes at z_min or z_max.
    const double near = 1.0 / out.z_min;
    const double far = 1.0 / out.z_max;
    const double xl = c[0] - half_[0];
    const double xh = c[0] + half_[0];
    const double yl = c[1] - half_[1];
    const double yh = c[1] + half_[1];
    const double u_min = fx_ * min2(xl * near, xl * far) + cx_;
    const double u_max = fx_ * max2(xh * near, xh * far) + cx_;
    const double v_min = fy_ * min2(yl * near, yl * far) + cy_;
    const double v_max = fy_ * max2(yh * near, yh * far) + cy_;
    out.in_image = u_min >= 0.0 && v_min >= 0.0 && u_max <= w_last_ && v_max <= h_last_;
    // Clamp to the image (one pixel beyond it on each side), then round inwards to pixel centres.
    const std::int32_t u0 = ceil_to_int(clamp(u_min - kPixelSlack, -1.0, w_last_ + 1.0));
    const std::int32_t u1 = floor_to_int(clamp(u_max + kPixelSlack, -1.0, w_last_ + 1.0));
    const std::int32_t v0 = ceil_to_int(clamp(v_min - kPixelSlack, -1.0, h_last_ + 1.0));
    const std::int32_t v1 = floor_to_int(clamp(v_max + kPixelSlack, -1.0, h_last_ + 1.0));
    const std::int32_t w_top = reading_.intrinsics.width - 1;
    const std::int32_t h_top = reading_.intrinsics.height - 1;
    out.u0 = u0 > 0 ? u0 : 0;
    out.v0 = v0 > 0 ? v0 : 0;
    out.u1 = u1 < w_top ? u1 : w_top;
    out.v1 = v1 < h_top ? v1 : h_top;
    return out.u0 <= out.u1 && out.v0 <= out.v1;
}

void SensorPass::visit(const VoxelCoord& voxel, std::size_t index, const std::array<double, 3>& c,
                       const VoxelView& f) noexcept {
    const DepthRange q = pyramid_->query(f.u0, f.v0, f.u1, f.v1);
    if (q.empty() || static_cast<double>(q.max) < f.z_min - kDepthSlack) {
        return;  // no valid reading, or every ray ends in front of the voxel: no opinion
    }
    const double beyond = static_cast<double>(q.min) - f.z_max;
    const double dist2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    if (beyond >= model_->ramp_length() + kDepthSlack && !q.any_invalid && f.in_image && dist2 <= resolved_dist2_) {
        // The voxel's inner square (half-width >= 0.5) holds a pixel centre of
        // the image, whose ray crosses the voxel, and every ray that may cross
        // it passes it by at least the ramp: the constant free value, exactly.
        raise(index, model_->constant_free_evidence());
        ++stats_.voxels_filled;
        return;
    }
    settle(voxel, index, c, f.z_max, q, nullptr);
}

void SensorPass::settle(const VoxelCoord& voxel, std::size_t index, const std::array<double, 3>& c, double z_max,
                        const DepthRange& q, const VoxelView* square) noexcept {
    if (opinions_[index] == model_->reading_evidence()) {
        return;  // a hit wins over every free value
    }
    VoxelView tight;
    if (exact_max_ > 0 && corner_rect(c, tight)) {
        const std::int64_t area = static_cast<std::int64_t>(tight.u1 - tight.u0 + 1) *
                                  static_cast<std::int64_t>(tight.v1 - tight.v0 + 1);
        if (area <= exact_max_) {
            ++stats_.voxels_exact;
            stats_.pixel_tests += static_cast<std::uint64_t>(area);
            raise(index, exact_opinion(voxel, tight));
            return;
        }
    }
    ++stats_.voxels_safe_side;
    if (static_cast<double>(q.max) <= z_max + kDepthSlack) {
        return;  // no reading of the footprint (a superset of the inner square's) lies beyond the voxel
    }
    const bool all_beyond = static_cast<double>(q.min) > z_max + kDepthSlack;
    // When every pixel of the footprint has a reading beyond the voxel, a pixel centre in the
    // inner square suffices; else one of its probed pixels must hold a reading beyond it.
    VoxelView own;
    const bool has_square = square != nullptr ? square->u0 <= square->u1 : inner_square(c, own);
    const VoxelView& sq = square != nullptr ? *square : own;
    if (has_square && ((all_beyond && !q.any_invalid) || probe_beyond(sq, z_max))) {
        raise(index, model_->free_evidence(all_beyond ? static_cast<double>(q.min) - z_max : 0.0));
    }
}

bool SensorPass::corner_rect(const std::array<double, 3>& c, VoxelView& out) const noexcept {
    double u_min = std::numeric_limits<double>::infinity();
    double u_max = -u_min;
    double v_min = u_min;
    double v_max = -u_min;
    for (std::uint32_t corner = 0U; corner < 8U; ++corner) {
        std::array<double, 3> p = c;
        for (std::size_t e = 0U; e < 3U; ++e) {
            const double sign = ((corner >> e) & 1U) != 0U ? 0.5 : -0.5;
            for (std::size_t a = 0U; a < 3U; ++a) {
                p[a] += sign * axis_[e][a];
            }
        }
        if (!(p[2] > kMinCornerDepth)) {
            return false;
        }
        const double u = fx_ * p[0] / p[2] + cx_;
        const double v = fy_ * p[1] / p[2] + cy_;
        u_min = min2(u_min, u);
        u_max = max2(u_max, u);
        v_min = min2(v_min, v);
        v_max = max2(v_max, v);
    }
    const std::int32_t u0 = ceil_to_int(clamp(u_min - kPixelSlack, -1.0, w_last_ + 1.0));
    const std::int32_t u1 = floor_to_int(clamp(u_max + kPixelSlack, -1.0, w_last_ + 1.0));
    const std::int32_t v0 = ceil_to_int(clamp(v_min - kPixelSlack, -1.0, h_last_ + 1.0));
    const std::int32_t v1 = floor_to_int(clamp(v_max + kPixelSlack, -1.0, h_last_ + 1.0));
    out.u0 = u0 > 0 ? u0 : 0;
    out.v0 = v0 > 0 ? v0 : 0;
    out.u1 = u1 < reading_.intrinsics.width - 1 ? u1 : reading_.intrinsics.width - 1;
    out.v1 = v1 < reading_.intrinsics.height - 1 ? v1 : reading_.intrinsics.height - 1;
    return out.u0 <= out.u1 && out.v0 <= out.v1;
}

std::int16_t SensorPass::exact_opinion(const VoxelCoord& voxel, const VoxelView& f) const noexcept {
    const PinholeIntrinsics& k = reading_.intrinsics;
    const Eigen::Matrix3d& r = reading_.pose.linear();
    const double s = grid_.voxel_size();
    const Eigen::Vector3d lo = grid_.origin() + s * Eigen::Vector3d(voxel.x, voxel.y, voxel.z) -
                               reading_.pose.translation();
    const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(s);
    const std::array<bool, 3> in_slab{camera_voxel_[0] == static_cast<double>(voxel.x),
                                      camera_voxel_[1] == static_cast<double>(voxel.y),
                                      camera_voxel_[2] == static_cast<double>(voxel.z)};
    const double inv_fx = 1.0 / k.fx;
    const double inv_fy = 1.0 / k.fy;
    std::int16_t best = kNoOpinion;
    for (std::int32_t v = f.v0; v <= f.v1; ++v) {
        const double yn = (static_cast<double>(v) - k.cy) * inv_fy;
        const Eigen::Vector3d row = r.col(1) * yn + r.col(2);
        for (std::int32_t u = f.u0; u <= f.u1; ++u) {
            const float d = pyramid_->depth(u, v);
            if (!(d < std::numeric_limits<float>::infinity())) {
                continue;  // no valid reading
            }
            const double xn = (static_cast<double>(u) - k.cx) * inv_fx;
            const double t_out = ray_exit_depth(row + r.col(0) * xn, lo, hi, in_slab);  // per metre of depth
            if (t_out < 0.0 || static_cast<double>(d) < t_out) {
                continue;  // misses the voxel, or ends in front of or inside it (a hit is step 1's)
            }
            const double along = std::sqrt(xn * xn + yn * yn + 1.0);
            const std::int16_t e = model_->free_evidence(along * (static_cast<double>(d) - t_out));
            best = e > best ? e : best;
        }
    }
    return best;
}

bool SensorPass::inner_square(const std::array<double, 3>& c, VoxelView& out) const noexcept {
    const PinholeIntrinsics& k = reading_.intrinsics;
    const double half = 0.5 * grid_.voxel_size() / (std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) * pixel_angle_);
    const double uc = k.fx * c[0] / c[2] + k.cx;
    const double vc = k.fy * c[1] / c[2] + k.cy;
    // ceil and floor in integers (no library call), clipped to the image; the
    // clamp to +-1e9 changes nothing that can lie in the image.
    const std::int32_t iu0 = ceil_to_int(clamp(uc - half, -1e9, 1e9));
    const std::int32_t iu1 = floor_to_int(clamp(uc + half, -1e9, 1e9));
    const std::int32_t iv0 = ceil_to_int(clamp(vc - half, -1e9, 1e9));
    const std::int32_t iv1 = floor_to_int(clamp(vc + half, -1e9, 1e9));
    out.u0 = iu0 > 0 ? iu0 : 0;
    out.v0 = iv0 > 0 ? iv0 : 0;
    out.u1 = iu1 < k.width - 1 ? iu1 : k.width - 1;
    out.v1 = iv1 < k.height - 1 ? iv1 : k.height - 1;
    return out.u0 <= out.u1 && out.v0 <= out.v1;
}

bool SensorPass::probe_beyond(const VoxelView& square, double z_max) const noexcept {
    const std::int32_t nu = square.u1 - square.u0 + 1;
    const std::int32_t nv = square.v1 - square.v0 + 1;
    const std::int32_t su = nu > kInnerProbeSide ? nu / kInnerProbeSide : 1;
    const std::int32_t sv = nv > kInnerProbeSide ? nv / kInnerProbeSide : 1;
    for (std::int32_t j = 0; j < kInnerProbeSide && j * sv < nv; ++j) {
        for (std::int32_t i = 0; i < kInnerProbeSide && i * su < nu; ++i) {
            const float d = pyramid_->depth(square.u0 + i * su, square.v0 + j * sv);
            if (d < std::numeric_limits<float>::infinity() && static_cast<double>(d) > z_max + kDepthSlack) {
                return true;
            }
        }
    }
    return false;
}

void SensorPass::run(const SensorModelTable& model, const DepthPyramid& pyramid, Span<std::int16_t> opinions) noexcept {
    model_ = &model;
    pyramid_ = &pyramid;
    opinions_ = opinions;
    stats_.pixels += static_cast<std::uint64_t>(pyramid.width()) * static_cast<std::uint64_t>(pyramid.height());
    for_each_in_view(
        [this](const VoxelCoord& v, std::size_t index, const std::array<double, 3>& c, const VoxelView& f) {
            ++stats_.voxels_visited;
            visit(v, index, c, f);
        });
}

void SensorPass::run(Span<const FootprintEntry> table, const SensorModelTable& model, const DepthPyramid& pyramid,
                     Span<std::int16_t> opinions) noexcept {
    model_ = &model;
    pyramid_ = &pyramid;
    opinions_ = opinions;
    stats_.pixels += static_cast<std::uint64_t>(pyramid.width()) * static_cast<std::uint64_t>(pyramid.height());
    stats_.voxels_visited += table.size();
    const std::int16_t fill = model.constant_free_evidence();
    const GridDims d = grid_.dims();
    const auto nx = static_cast<std::size_t>(d.nx);
    const auto ny = static_cast<std::size_t>(d.ny);
    for (const FootprintEntry& e : table) {
        const DepthRange q = pyramid.query(e.cells);
        if (q.max < e.front) {
            continue;  // no valid reading, or every ray ends in front of the voxel (front is finite)
        }
        if (!q.any_invalid && q.min >= e.fill) {
            raise(index_of(e.x, e.y, e.z, nx, ny), fill);
            ++stats_.voxels_filled;
            continue;
        }
        // Open: the rest of step 2 and step 3, as without a table (the query is the same:
        // the entry's cells are those of the voxel's footprint).
        const std::int32_t x = e.x;
        const std::int32_t y = e.y;
        const std::int32_t z = e.z;
        const std::array<double, 3> c{centre(0U, x, y, z), centre(1U, x, y, z), centre(2U, x, y, z)};
        VoxelView square;
        square.u0 = e.square_u0;
        square.v0 = e.square_v0;
        square.u1 = e.square_u1;
        square.v1 = e.square_v1;
        settle(VoxelCoord{x, y, z}, index_of(x, y, z, nx, ny), c, c[2] + half_[2], q, &square);
    }
}

namespace {

/// The smallest float f for which @p holds(f) is true, for a predicate that is
/// false below some float and true from it on (and at +inf), when @p guess lies
/// within 4 floats of it: the search starts 4 floats below the guess, where the
/// predicate must be false (checked by CG_ASSERT), and steps up.
template <typename Pred>
float smallest_float_where(float guess, Pred&& holds) noexcept {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    float f = guess;
    for (int i = 0; i < 4; ++i) {
        f = std::nextafter(f, -kInf);
    }
    CG_ASSERT(!holds(f), "footprint table: a threshold more than 4 floats below its guess");
    while (!holds(f)) {
        f = std::nextafter(f, kInf);
    }
    return f;
}

}  // namespace

bool SensorPass::make_table(const DepthPyramid& layout, double ramp, Span<FootprintEntry> out,
                            std::size_t& count) const noexcept {
    std::size_t n = 0U;
    for_each_in_view([&](const VoxelCoord& v, std::size_t, const std::array<double, 3>& c, const VoxelView& f) {
        if (n < out.size()) {
            out[n] = entry_of(layout, ramp, v, c, f);
        }
        ++n;
    });
    count = n;
    return n <= out.size();
}

FootprintEntry SensorPass::entry_of(const DepthPyramid& layout, double ramp, const VoxelCoord& v,
                                    const std::array<double, 3>& c, const VoxelView& f) const noexcept {
    // Grid sides are at most kMaxDimension (4096, checked by GridGeometry::make): they fit 16 bits.
    const std::int32_t x = v.x;
    const std::int32_t y = v.y;
    const std::int32_t z = v.z;
    FootprintEntry e;
    e.x = static_cast<std::uint16_t>(x);
    e.y = static_cast<std::uint16_t>(y);
    e.z = static_cast<std::uint16_t>(z);
    e.cells = layout.cells_of(f.u0, f.v0, f.u1, f.v1);
    // The inner square (settle), clipped to the image: sides of at most 4096 fit 16 bits.
    VoxelView square;
    if (inner_square(c, square)) {
        e.square_u0 = static_cast<std::uint16_t>(square.u0);
        e.square_v0 = static_cast<std::uint16_t>(square.v0);
        e.square_u1 = static_cast<std::uint16_t>(square.u1);
        e.square_v1 = static_cast<std::uint16_t>(square.v1);
    }
    // visit()'s tests in double on a float reading r: (double) r < front_d, and
    // (double) r - z_max >= ramp + slack; each is a threshold on the float r.
    const double front_d = f.z_min - kDepthSlack;
    e.front = smallest_float_where(static_cast<float>(front_d),
                                   [front_d](float r) { return static_cast<double>(r) >= front_d; });
    const double dist2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    const double need = ramp + kDepthSlack;
    const double z_max = f.z_max;
    // Both tests always evaluated (no branch between them).
    const bool fillable = (static_cast<unsigned>(f.in_image) & static_cast<unsigned>(dist2 <= resolved_dist2_)) != 0U;
    e.fill = fillable ? smallest_float_where(static_cast<float>(z_max + need),
                                             [z_max, need](float r) { return static_cast<double>(r) - z_max >= need; })
                      : std::numeric_limits<float>::infinity();
    return e;
}

}  // namespace

std::uint64_t footprint_work_bound(const GridGeometry& grid, const SensorReading& reading,
                                   const FootprintParams& params) noexcept {
    if (!is_depth_image(reading.kind) || reading.intrinsics.width <= 0 || reading.intrinsics.height <= 0 ||
        grid.voxel_count() == 0U) {
        return 0U;
    }
    const std::uint64_t pixels = static_cast<std::uint64_t>(reading.intrinsics.width) *
                                 static_cast<std::uint64_t>(reading.intrinsics.height);
    return 2U * pixels + SensorPass(grid, reading, params).voxel_work_bound();
}

namespace {

/// The checks of validate_sensor_reading that concern a table: a depth image
/// of a valid size, finite positive intrinsics, a finite rotation.
Status check_table_geometry(const GridGeometry& grid, const SensorReading& r) noexcept {
    const PinholeIntrinsics& k = r.intrinsics;
    // Every test evaluated (bitwise and of 0 or 1): one decision, whichever test fails.
    const auto bit = [](bool b) { return static_cast<unsigned>(b); };
    const Eigen::Matrix3d rot = r.pose.linear();
    const unsigned finite = bit(r.pose.matrix().allFinite()) & bit(std::isfinite(k.fx)) & bit(std::isfinite(k.fy)) &
                            bit(std::isfinite(k.cx)) & bit(std::isfinite(k.cy));
    const unsigned ok = finite & bit(is_depth_image(r.kind)) & bit(grid.voxel_count() != 0U) &
                        bit(depth_pyramid_cells(k.width, k.height) != 0U) & bit(k.fx > 0.0) & bit(k.fy > 0.0) &
                        bit((rot.transpose() * rot - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-6);
    return ok != 0U ? Status{} : Status{ErrorCode::kInvalidArgument};
}

/// What a footprint table depends on, as numbers (integers exactly): the grid's
/// origin, voxel size and dimensions, the pose's 3 x 4 matrix, the intrinsics
/// and image size, the model's ramp length.
std::array<double, kFootprintKeySize> footprint_key(const GridGeometry& grid, const SensorReading& r,
                                                    const SensorModelTable& model) noexcept {
    std::array<double, kFootprintKeySize> key{};
    std::size_t n = 0U;
    const auto put = [&key, &n](double v) { key[n++] = v; };
    for (Eigen::Index a = 0; a < 3; ++a) {
        put(grid.origin()[a]);
    }
    put(grid.voxel_size());
    put(grid.dims().nx);
    put(grid.dims().ny);
    put(grid.dims().nz);
    for (Eigen::Index row = 0; row < 3; ++row) {
        for (Eigen::Index col = 0; col < 4; ++col) {
            put(r.pose.matrix()(row, col));
        }
    }
    const PinholeIntrinsics& k = r.intrinsics;
    put(k.fx);
    put(k.fy);
    put(k.cx);
    put(k.cy);
    put(k.width);
    put(k.height);
    put(model.ramp_length());
    return key;
}

}  // namespace

std::size_t footprint_table_entries(const GridGeometry& grid, const SensorReading& reading) noexcept {
    if (!check_table_geometry(grid, reading).ok()) {
        return 0U;
    }
    return static_cast<std::size_t>(SensorPass(grid, reading, FootprintParams{}).voxel_work_bound());
}

Status FootprintTable::make(const GridGeometry& grid, const SensorReading& reading,
                            const SensorModelTable& model) noexcept {
    made_ = false;
    count_ = 0U;
    const Status ok = check_table_geometry(grid, reading);
    if (!ok.ok()) {
        return ok;
    }
    const DepthPyramid layout = DepthPyramid::layout_of(reading.intrinsics.width, reading.intrinsics.height);
    std::size_t count = 0U;
    if (!SensorPass(grid, reading, FootprintParams{}).make_table(layout, model.ramp_length(), storage_, count)) {
        return ErrorCode::kStorageTooSmall;
    }
    count_ = count;
    made_ = true;
    ++makes_;
    key_ = footprint_key(grid, reading, model);
    return Status{};
}

bool FootprintTable::matches(const GridGeometry& grid, const SensorReading& reading,
                             const SensorModelTable& model) const noexcept {
    // Every number equal: a table made for a pose 1 ulp away is another camera's.
    return made_ && is_depth_image(reading.kind) && footprint_key(grid, reading, model) == key_;
}

Result<FusionStats> footprint_opinions(const GridGeometry& grid, const SensorReading& reading,
                                       const SensorModelTable& model, const FootprintWorkspace& work,
                                       FootprintStats* stats, const FootprintParams& params) noexcept {
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
    const FusionStats s = detail::hit_pass(grid, reading, model.reading_evidence(), pyramid, opinions, params.kernel);
    pyramid.build_levels();
    SensorPass pass(grid, reading, params);
    std::uint64_t makes = 0U;
    if (work.table == nullptr) {
        pass.run(model, pyramid, opinions);
    } else {
        if (!work.table->matches(grid, reading, model)) {
            const Status made_table = work.table->make(grid, reading, model);
            if (!made_table.ok()) {
                return made_table.error();
            }
            makes = 1U;
        }
        pass.run(work.table->entries(), model, pyramid, opinions);
    }
    if (stats != nullptr) {
        stats->add(pass.stats());
        stats->table_makes += makes;
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
    Span<const FootprintWorkspace> workspaces{};
    const FootprintParams* params = nullptr;
    FusionKernel kernel = FusionKernel::kScalar;  ///< params->kernel as it runs here (resolve_fusion_kernel)
    EvidenceGrid* target = nullptr;
    std::array<FusionStats, kMaxSensors> fusion{};
    std::array<FootprintStats, kMaxSensors> footprint{};
    std::array<ErrorCode, kMaxSensors> error{};  ///< kOk, or the sensor's error (a table too small)
};

void sensor_task(void* context, std::size_t i) noexcept {
    auto& job = *static_cast<FrameJob*>(context);
    const Result<FusionStats> r = footprint_opinions(*job.grid, job.sensors[i], *job.model, job.workspaces[i],
                                                     &job.footprint[i], *job.params);
    job.error[i] = r.ok() ? ErrorCode::kOk : r.error();
    if (r.ok()) {
        job.fusion[i] = r.value();
    }
}

#if defined(__x86_64__)
/// SensorModelTable::pool of voxels [begin, end) sixteen at a time in AVX2
/// registers, as far as whole groups of 16 go; returns the first voxel not
/// pooled. int16 lanes: the saturating sum clamped to [pooled_min,
/// pooled_max] is the clamped int32 sum (both clamps lie inside int16).
__attribute__((target("avx2"))) std::size_t pool_avx2(std::int16_t* lo, std::uint8_t* obs, const std::int16_t* op,
                                                      std::size_t begin, std::size_t end,
                                                      const SensorModelTable& model) noexcept {
    const __m256i none = _mm256_set1_epi16(kNoOpinion);
    const __m256i zero = _mm256_setzero_si256();
    const __m256i lo_clamp = _mm256_set1_epi16(model.pooled_min());
    const __m256i hi_clamp = _mm256_set1_epi16(model.pooled_max());
    const __m128i one = _mm_set1_epi8(1);
    std::size_t i = begin;
    for (; i + 16U <= end; i += 16U) {
        // Unaligned loads and stores by memcpy (one instruction each, no cast).
        __m256i o;
        __m256i p;
        __m128i ob;
        std::memcpy(&o, op + i, sizeof o);
        std::memcpy(&p, lo + i, sizeof p);
        std::memcpy(&ob, obs + i, sizeof ob);
        const __m256i has = _mm256_xor_si256(_mm256_cmpeq_epi16(o, none), _mm256_set1_epi16(-1));
        const __m256i sum = _mm256_adds_epi16(p, o);
        const __m256i o_pos = _mm256_cmpgt_epi16(o, zero);
        const __m256i p_pos = _mm256_cmpgt_epi16(p, zero);
        // opinion > 0 ? (pooled > 0 ? sum : opinion) : (pooled > 0 ? pooled : sum)
        const __m256i if_pos = _mm256_blendv_epi8(o, sum, p_pos);
        const __m256i if_not = _mm256_blendv_epi8(sum, p, p_pos);
        const __m256i v = _mm256_min_epi16(_mm256_max_epi16(_mm256_blendv_epi8(if_not, if_pos, o_pos), lo_clamp),
                                           hi_clamp);
        const __m256i pooled = _mm256_blendv_epi8(p, v, has);
        // observed: 1 where an opinion came, else unchanged (the lanes' masks packed to bytes, in order).
        const __m128i has8 = _mm_packs_epi16(_mm256_castsi256_si128(has), _mm256_extracti128_si256(has, 1));
        const __m128i observed = _mm_or_si128(ob, _mm_and_si128(has8, one));
        std::memcpy(lo + i, &pooled, sizeof pooled);
        std::memcpy(obs + i, &observed, sizeof observed);
    }
    return i;
}
#endif

void pool_task(void* context, std::size_t chunk) noexcept {
    auto& job = *static_cast<FrameJob*>(context);
    std::int16_t* const lo = job.target->log_odds().data();
    std::uint8_t* const obs = job.target->observed().data();
    const std::size_t n = job.target->voxel_count();
    const std::size_t begin = chunk * kPoolChunk;
    const std::size_t end = begin + kPoolChunk < n ? begin + kPoolChunk : n;
    for (std::size_t s = 0U; s < job.sensors.size(); ++s) {
        const std::int16_t* const op = job.workspaces[s].opinions.data();
        std::size_t first = begin;
#if defined(__x86_64__)
        if (job.kernel == FusionKernel::kAvx2) {
            first = pool_avx2(lo, obs, op, begin, end, *job.model);
        }
#endif
        for (std::size_t i = first; i < end; ++i) {
            if (op[i] != kNoOpinion) {
                lo[i] = job.model->pool(lo[i], op[i]);
                obs[i] = 1U;
            }
        }
    }
}

}  // namespace

Result<FusionStats> fuse_frame_footprint(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                         const SensorModelTable& model, Span<const FootprintWorkspace> workspaces,
                                         TaskRunner& runner, FootprintStats* stats,
                                         const FootprintParams& params) noexcept {
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
        job.workspaces = workspaces;
        job.params = &params;
        job.kernel = resolve_fusion_kernel(params.kernel);
        job.target = &grid;
        runner.run(sensors.size(), &sensor_task, &job);
        for (std::size_t i = 0U; i < sensors.size(); ++i) {
            if (job.error[i] != ErrorCode::kOk) {
                return job.error[i];  // a table that does not fit its storage; no evidence added yet
            }
            total.add(job.fusion[i]);
            fp.add(job.footprint[i]);
        }
        runner.run((grid.voxel_count() + kPoolChunk - 1U) / kPoolChunk, &pool_task, &job);
    } else {
        // One workspace for every sensor: no table (it would be made again for each sensor).
        FootprintWorkspace shared = workspaces[0];
        shared.table = nullptr;
        for (const SensorReading& r : sensors) {
            const Result<FusionStats> s = footprint_opinions(grid.geometry(), r, model, shared, &fp, params);
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
