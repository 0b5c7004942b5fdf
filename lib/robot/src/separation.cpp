// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/robot/separation.hpp"

#include <cmath>
#include <limits>

#include "cellguard/grid/log_odds.hpp"

namespace cellguard {

namespace {

/// sqrt(3) / 2: half a voxel's diagonal, per metre of voxel edge.
constexpr double kHalfDiagonal = 0.8660254037844386;
/// Slack on the lower bounds and squared thresholds that prune the search,
/// metres: larger than any rounding of the distances (a few ulps of metres),
/// so pruning never drops a voxel the exact computation would keep.
constexpr double kPruneSlack = 1e-9;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Rows whose "holds a candidate" flag the count pass keeps (1 KiB of
/// stack); a grid with more rows (y-z positions) is searched without them.
constexpr std::size_t kRowFlagRows = 8192U;

bool finite_non_negative(double v) noexcept { return std::isfinite(v) && v >= 0.0; }

// Plain minimum and maximum (std::fmin and std::fmax are library calls on
// some targets); the operands here are never NaN.
double min_of(double a, double b) noexcept { return b < a ? b : a; }
double max_of(double a, double b) noexcept { return b > a ? b : a; }

/// Bit 0: the voxel is foreground (frame + prior, add_saturating, >= the
/// threshold); bit 1: it is unseen (not observed, prior not kNeverForeground
/// and >= accessible_min_prior) inside an active zone. The definitions of
/// zone_evaluation.cpp, written without branches.
std::uint32_t kinds_of(const SeparationInputs& in, std::int16_t frame, std::int16_t prior, std::uint8_t observed,
                       std::uint32_t zones) noexcept {
    const std::int32_t f = frame;
    const std::int32_t p = prior;
    const std::int32_t sum = f + p;
    const std::int32_t clamped = sum < kLogOddsMin ? kLogOddsMin : (sum > kLogOddsMax ? kLogOddsMax : sum);
    const bool sentinel = f == kNeverForeground || p == kNeverForeground;
    const std::int32_t value = sentinel ? static_cast<std::int32_t>(kNeverForeground) : clamped;
    const auto fg = static_cast<std::uint32_t>(value >= in.foreground_threshold);
    const std::uint32_t hidden = static_cast<std::uint32_t>(observed == 0U) &
                                 static_cast<std::uint32_t>(p != kNeverForeground) &
                                 static_cast<std::uint32_t>(p >= in.accessible_min_prior) &
                                 static_cast<std::uint32_t>((zones & in.active_zones) != 0U);
    return fg | (hidden << 1U);
}

/// Metres to millimetres, rounded down (a distance) or up (a requirement),
/// saturated at kDistanceFarMm. Rounding up forgives 1e-6 mm (a nanometre),
/// so that the binary64 sum of decimal parameters (0.878 m is
/// 0.87800000000000011 m) does not ask one millimetre more.
std::uint16_t to_mm(double metres, bool round_up) noexcept {
    const double mm = round_up ? std::ceil(metres * 1000.0 - 1e-6) : std::floor(metres * 1000.0);
    if (!(mm < static_cast<double>(kDistanceFarMm))) {
        return kDistanceFarMm;
    }
    return mm <= 0.0 ? std::uint16_t{0} : static_cast<std::uint16_t>(mm);
}

/// The k smallest values offered, as a binary max-heap in a fixed array:
/// threshold() is the k-th smallest so far (infinity until k were offered).
class KSmallest {
public:
    explicit KSmallest(std::uint32_t k) noexcept : k_(k) {}
    [[nodiscard]] double threshold() const noexcept {
        if (n_ < k_) {
            return kInfinity;
        }
        return v_[0];
    }
    [[nodiscard]] bool full() const noexcept { return n_ == k_; }
    void offer(double d) noexcept {
        if (n_ < k_) {
            std::uint32_t i = n_++;
            while (i > 0U && v_[(i - 1U) / 2U] < d) {
                v_[i] = v_[(i - 1U) / 2U];
                i = (i - 1U) / 2U;
            }
            v_[i] = d;
            return;
        }
        if (!(d < v_[0])) {
            return;
        }
        std::uint32_t i = 0U;
        for (;;) {
            const std::uint32_t l = 2U * i + 1U;
            if (l >= n_) {
                break;
            }
            const std::uint32_t c = (l + 1U < n_ && v_[l + 1U] > v_[l]) ? l + 1U : l;
            if (!(v_[c] > d)) {
                break;
            }
            v_[i] = v_[c];
            i = c;
        }
        v_[i] = d;
    }

private:
    double v_[kMaxSeparationVoxelCount] = {};
    std::uint32_t k_;
    std::uint32_t n_ = 0U;
};

/// Visits 0..n-1 outward from c: c, c+1, c-1, c+2, c-2, ... (c clamped into range).
class Outward {
public:
    Outward(std::int32_t c, std::int32_t n) noexcept : lo_(c < 0 ? 0 : (c >= n ? n - 1 : c)), hi_(lo_ + 1), n_(n) {}
    bool next(std::int32_t& v) noexcept {
        if (lo_ >= 0 && (low_turn_ || hi_ >= n_)) {
            v = lo_--;
            low_turn_ = false;
            return true;
        }
        if (hi_ < n_) {
            v = hi_++;
            low_turn_ = lo_ >= 0;
            return true;
        }
        return false;
    }

private:
    std::int32_t lo_;
    std::int32_t hi_;
    std::int32_t n_;
    bool low_turn_ = true;
};

/// A capsule prepared for the search: end a, direction d = b - a, |d|^2, radius + half diagonal.
struct Segment {
    double a[3];
    double d[3];
    double dd;
    double grow;
};

/// Per row of the grid (fixed y, z): each capsule's y-z parts of dot(w, d)
/// and |w|^2, and its lower bound on the distance of any voxel of the row.
struct RowTerms {
    double dot_yz[kMaxRobotCapsules];
    double w2_yz[kMaxRobotCapsules];
    double lower[kMaxRobotCapsules];
};

/// The capsules' y-z terms of the row through (y, z) and the row's lower
/// bound (min over capsules): the distance of (y, z) to the capsule's segment
/// projected onto the y-z plane (projection shortens distances), less radius
/// and half diagonal.
double prepare_row(const Segment* seg, std::size_t count, double y, double z, RowTerms& row) noexcept {
    double lower = kInfinity;
    for (std::size_t c = 0U; c < count; ++c) {
        const Segment& s = seg[c];
        const double wy = y - s.a[1];
        const double wz = z - s.a[2];
        row.dot_yz[c] = wy * s.d[1] + wz * s.d[2];
        row.w2_yz[c] = wy * wy + wz * wz;
        const double dd_yz = s.d[1] * s.d[1] + s.d[2] * s.d[2];
        double dist2 = row.w2_yz[c];
        if (row.dot_yz[c] >= dd_yz) {
            dist2 = row.w2_yz[c] - 2.0 * row.dot_yz[c] + dd_yz;
        } else if (row.dot_yz[c] > 0.0) {
            dist2 = row.w2_yz[c] - row.dot_yz[c] * (row.dot_yz[c] / dd_yz);
        }
        row.lower[c] = std::sqrt(dist2 < 0.0 ? 0.0 : dist2) - s.grow - kPruneSlack;
        lower = min_of(lower, row.lower[c]);
    }
    return lower;
}

/// Distance from the voxel centre at x (of the prepared row) to the nearest
/// capsule surface less half a diagonal, clamped at 0; kInfinity when no
/// capsule is nearer than @p threshold (then it cannot count).
double voxel_distance(const Segment* seg, std::size_t count, const RowTerms& row, double x, double threshold) noexcept {
    double best = kInfinity;
    for (std::size_t c = 0U; c < count; ++c) {
        const double limit = best < threshold ? best : threshold;
        if (row.lower[c] >= limit) {
            continue;
        }
        const Segment& s = seg[c];
        const double wx = x - s.a[0];
        const double dot = wx * s.d[0] + row.dot_yz[c];
        const double w2 = wx * wx + row.w2_yz[c];
        double dist2 = w2;
        if (dot >= s.dd) {
            dist2 = w2 - 2.0 * dot + s.dd;
        } else if (dot > 0.0) {
            dist2 = w2 - dot * (dot / s.dd);
        }
        const double reach = limit + s.grow + kPruneSlack;
        if (std::isfinite(limit) && dist2 >= reach * reach) {
            continue;
        }
        const double d = std::sqrt(dist2 < 0.0 ? 0.0 : dist2) - s.grow;
        best = min_of(best, d < 0.0 ? 0.0 : d);
    }
    return best;
}

/// The search's state: both kinds' k smallest distances and the candidates
/// counted. A kind is active when the grid holds at least k voxels of it
/// (else its distance is kDistanceFarMm and the search ignores it).
struct Search {
    KSmallest foreground;
    KSmallest hidden;
    bool foreground_active = false;
    bool hidden_active = false;
    std::uint32_t candidates = 0U;
    /// The larger of the active kinds' thresholds: a voxel farther cannot count (-infinity: none active).
    [[nodiscard]] double threshold() const noexcept {
        return max_of(foreground_active ? foreground.threshold() : -kInfinity,
                      hidden_active ? hidden.threshold() : -kInfinity);
    }
    /// True when nothing can lower either kind's distance any more (at 0 or not active).
    [[nodiscard]] bool settled() const noexcept { return !(threshold() > 0.0); }
};

/// Each kind's voxels outside the robot's, counted in the one full pass over
/// the grid, and which rows hold any (while the grid has at most
/// kRowFlagRows rows).
struct KindCounts {
    std::uint32_t foreground = 0U;
    std::uint32_t hidden = 0U;
    bool row_flags_valid = false;
    std::uint64_t row_flags[kRowFlagRows / 64U] = {};
    /// False only when the row is known to hold no voxel of either kind.
    [[nodiscard]] bool row_may_hold(std::size_t row) const noexcept {
        return !row_flags_valid || ((row_flags[row / 64U] >> (row % 64U)) & 1U) != 0U;
    }
};

/// Counts the voxels of each kind outside the robot's voxels, row by row.
void count_kinds(const GridGeometry& grid, const SeparationInputs& in, KindCounts& counts) noexcept {
    const std::int16_t* frame = in.frame_log_odds.data();
    const std::int16_t* prior = in.prior.data();
    const std::uint8_t* observed = in.observed.data();
    const std::uint8_t* mask = in.robot_mask.data();
    const std::uint32_t* zones = in.zone_membership.data();
    const auto nx = static_cast<std::size_t>(grid.dims().nx);
    const std::size_t rows = grid.voxel_count() / nx;
    counts.row_flags_valid = rows <= kRowFlagRows;
    std::uint32_t fg = 0U;
    std::uint32_t hid = 0U;
    std::size_t i = 0U;
    for (std::size_t r = 0U; r < rows; ++r) {
        std::uint32_t any = 0U;
        for (const std::size_t end = i + nx; i < end; ++i) {
            const std::uint32_t kinds = mask[i] == 0U ? kinds_of(in, frame[i], prior[i], observed[i], zones[i]) : 0U;
            fg += kinds & 1U;
            hid += kinds >> 1U;
            any |= kinds;
        }
        if (counts.row_flags_valid && any != 0U) {
            counts.row_flags[r / 64U] |= std::uint64_t{1} << (r % 64U);
        }
    }
    counts.foreground = fg;
    counts.hidden = hid;
}

/// The voxels of a row that may lie within @p threshold of a capsule: the
/// hull of the x extents of the capsules whose row bound is below it, each
/// grown by threshold + radius + half diagonal; false when there are none.
/// All of the row when the threshold is infinite.
bool row_range(const GridGeometry& grid, const Segment* seg, std::size_t count, const RowTerms& row, double threshold,
               std::int32_t& lo, std::int32_t& hi) noexcept {
    const std::int32_t nx = grid.dims().nx;
    lo = 0;
    hi = nx - 1;
    if (!std::isfinite(threshold)) {
        return true;
    }
    double min = kInfinity;
    double max = -kInfinity;
    for (std::size_t c = 0U; c < count; ++c) {
        if (row.lower[c] >= threshold) {
            continue;
        }
        const double reach = threshold + seg[c].grow + kPruneSlack;
        const double b = seg[c].a[0] + seg[c].d[0];
        min = min_of(min, min_of(seg[c].a[0], b) - reach);
        max = max_of(max, max_of(seg[c].a[0], b) + reach);
    }
    const double first = std::floor((min - grid.origin()(0)) / grid.voxel_size());
    const double last = std::floor((max - grid.origin()(0)) / grid.voxel_size());
    if (!(last >= 0.0) || !(first <= static_cast<double>(nx - 1))) {
        return false;
    }
    lo = first > 0.0 ? static_cast<std::int32_t>(first) : 0;
    hi = last < static_cast<double>(nx - 1) ? static_cast<std::int32_t>(last) : nx - 1;
    return true;
}

/// One row of the grid: classifies its voxels within reach and offers the candidates' distances.
void search_row(const GridGeometry& grid, const SeparationInputs& in, const Segment* seg, std::size_t count,
                std::size_t row_start, const RowTerms& row, Search& s) noexcept {
    const double th_row = s.threshold();
    std::int32_t lo = 0;
    std::int32_t hi = 0;
    if (!row_range(grid, seg, count, row, th_row, lo, hi)) {
        return;
    }
    const std::int16_t* frame = in.frame_log_odds.data() + row_start;
    const std::int16_t* prior = in.prior.data() + row_start;
    const std::uint8_t* observed = in.observed.data() + row_start;
    const std::uint8_t* mask = in.robot_mask.data() + row_start;
    const std::uint32_t* zones = in.zone_membership.data() + row_start;
    const std::uint32_t active = (s.foreground_active ? 1U : 0U) | (s.hidden_active ? 2U : 0U);
    const double x0 = grid.origin()(0) + 0.5 * grid.voxel_size();
    for (std::int32_t x = lo; x <= hi; ++x) {
        const std::uint32_t kinds = kinds_of(in, frame[x], prior[x], observed[x], zones[x]) & active;
        if (kinds == 0U || mask[x] != 0U) {
            continue;
        }
        const bool fg = (kinds & 1U) != 0U;
        const bool hidden = (kinds & 2U) != 0U;
        const double th_fg = fg ? s.foreground.threshold() : -kInfinity;
        const double th_hidden = hidden ? s.hidden.threshold() : -kInfinity;
        const double threshold = max_of(th_fg, th_hidden);
        if (!(threshold > 0.0)) {
            continue;  // that kind already has k voxels at distance 0
        }
        ++s.candidates;
        const double d = voxel_distance(seg, count, row, x0 + grid.voxel_size() * static_cast<double>(x), threshold);
        if (fg && d < th_fg) {
            s.foreground.offer(d);
        }
        if (hidden && d < th_hidden) {
            s.hidden.offer(d);
        }
    }
}

/// Prepares the capsules and returns the voxel nearest the centre of their bounding box.
VoxelCoord prepare_segments(const GridGeometry& grid, const RobotPose& pose, Segment* seg) noexcept {
    double lo[3] = {kInfinity, kInfinity, kInfinity};
    double hi[3] = {-kInfinity, -kInfinity, -kInfinity};
    const double half_diagonal = kHalfDiagonal * grid.voxel_size();
    for (std::size_t c = 0U; c < pose.count; ++c) {
        const PlacedCapsule& p = pose.capsules[c];
        Segment& s = seg[c];
        for (int k = 0; k < 3; ++k) {
            s.a[k] = p.a[k];
            s.d[k] = p.b[k] - p.a[k];
            lo[k] = min_of(lo[k], min_of(p.a[k], p.b[k]));
            hi[k] = max_of(hi[k], max_of(p.a[k], p.b[k]));
        }
        s.dd = s.d[0] * s.d[0] + s.d[1] * s.d[1] + s.d[2] * s.d[2];
        s.grow = p.radius + half_diagonal;
    }
    VoxelCoord centre;
    std::int32_t* axes[3] = {&centre.x, &centre.y, &centre.z};
    const GridDims dims = grid.dims();
    const std::int32_t n[3] = {dims.nx, dims.ny, dims.nz};
    for (int k = 0; k < 3; ++k) {
        const double v = std::floor((0.5 * (lo[k] + hi[k]) - grid.origin()(k)) / grid.voxel_size());
        *axes[k] = !(v >= 0.0) ? 0 : (v >= static_cast<double>(n[k]) ? n[k] - 1 : static_cast<std::int32_t>(v));
    }
    return centre;
}

bool pose_usable(const RobotPose& pose) noexcept {
    if (pose.count == 0U || pose.count > kMaxRobotCapsules) {
        return false;
    }
    for (std::size_t c = 0U; c < pose.count; ++c) {
        const PlacedCapsule& p = pose.capsules[c];
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(p.a[k]) || !std::isfinite(p.b[k])) {
                return false;
            }
        }
        if (!finite_non_negative(p.radius)) {
            return false;
        }
    }
    return true;
}

}  // namespace

Status check_separation_params(const SeparationParams& p) noexcept {
    if (p.class_count < 1U || p.class_count > kSpeedClasses || p.reduced_class >= p.class_count) {
        return ErrorCode::kInvalidArgument;
    }
    if (p.min_foreground_voxels < 1U || p.min_foreground_voxels > kMaxSeparationVoxelCount ||
        p.min_hidden_voxels < 1U || p.min_hidden_voxels > kMaxSeparationVoxelCount) {
        return ErrorCode::kInvalidArgument;
    }
    const double values[] = {p.human_speed_mps,      p.reaction_time_s,       p.slowdown_time_s,
                             p.intrusion_distance_m, p.sensing_uncertainty_m, p.robot_uncertainty_m};
    for (const double v : values) {
        if (!finite_non_negative(v)) {
            return ErrorCode::kInvalidArgument;
        }
    }
    for (std::size_t c = 0U; c < p.class_count; ++c) {
        const SpeedClassLimits& l = p.classes[c];
        if (!finite_non_negative(l.robot_speed_mps) || !finite_non_negative(l.stopping_time_s) ||
            !finite_non_negative(l.stopping_distance_m)) {
            return ErrorCode::kInvalidArgument;
        }
    }
    // Every distance compared must fit the millimetre field below kDistanceFarMm: at the cap, a
    // voxel inside S_p but 65.535 m or more away would read as far as S_p, and not stop the robot.
    constexpr double kLargestDistanceM = static_cast<double>(kDistanceFarMm - 1U) / 1000.0;
    for (std::uint8_t c = 0U; c < p.class_count; ++c) {
        if (!(protective_separation_distance(p, c) <= kLargestDistanceM)) {
            return ErrorCode::kInvalidArgument;
        }
    }
    if (!(reduced_speed_distance(p) <= kLargestDistanceM)) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

double protective_separation_distance(const SeparationParams& p, std::uint8_t speed_class) noexcept {
    CG_ENFORCE(speed_class < p.class_count && speed_class < kSpeedClasses, "speed class beyond the commissioned");
    const SpeedClassLimits& l = p.classes[speed_class];
    const double human = p.human_speed_mps * (p.reaction_time_s + l.stopping_time_s);
    const double robot = l.robot_speed_mps * p.reaction_time_s;
    return human + robot + l.stopping_distance_m + p.intrusion_distance_m + p.sensing_uncertainty_m +
           p.robot_uncertainty_m;
}

double reduced_speed_distance(const SeparationParams& p) noexcept {
    return protective_separation_distance(p, 0U) +
           (p.human_speed_mps + p.classes[0].robot_speed_mps) * p.slowdown_time_s;
}

Status compute_separation(const GridGeometry& grid, const SeparationInputs& in, const RobotPose& pose,
                          const SeparationParams& params, std::uint8_t speed_class, SeparationResult& out) noexcept {
    out = SeparationResult{};  // distances 0, kProtectiveStop: what every error leaves
    const std::size_t n = grid.voxel_count();
    if (in.frame_log_odds.size() < n || in.observed.size() < n || in.prior.size() < n || in.robot_mask.size() < n ||
        in.zone_membership.size() < n) {
        return ErrorCode::kStorageTooSmall;
    }
    if (!check_separation_params(params).ok() || speed_class >= params.class_count || !pose_usable(pose)) {
        return ErrorCode::kInvalidArgument;
    }
    Segment seg[kMaxRobotCapsules];
    const VoxelCoord centre = prepare_segments(grid, pose, seg);
    KindCounts counts;
    count_kinds(grid, in, counts);
    Search s{KSmallest(params.min_foreground_voxels), KSmallest(params.min_hidden_voxels),
             counts.foreground >= params.min_foreground_voxels, counts.hidden >= params.min_hidden_voxels};
    const GridDims dims = grid.dims();
    const double s_vox = grid.voxel_size();
    RowTerms row{};
    // Rows outward from the robot, so near voxels set the thresholds early and
    // rows that cannot beat them are skipped unread.
    Outward zs(centre.z, dims.nz);
    std::int32_t z = 0;
    while (zs.next(z) && !s.settled()) {
        const double zc = grid.origin()(2) + s_vox * (static_cast<double>(z) + 0.5);
        Outward ys(centre.y, dims.ny);
        std::int32_t y = 0;
        while (ys.next(y) && !s.settled()) {
            const std::size_t row_index = static_cast<std::size_t>(y) +
                                          static_cast<std::size_t>(dims.ny) * static_cast<std::size_t>(z);
            if (!counts.row_may_hold(row_index)) {
                continue;  // no voxel of either kind in this row
            }
            const double yc = grid.origin()(1) + s_vox * (static_cast<double>(y) + 0.5);
            const double lower = prepare_row(seg, pose.count, yc, zc, row);
            if (lower >= s.threshold()) {
                continue;
            }
            search_row(grid, in, seg, pose.count, static_cast<std::size_t>(dims.nx) * row_index, row, s);
        }
    }
    out.candidates = s.candidates;
    out.foreground_mm = s.foreground.full() ? to_mm(s.foreground.threshold(), false) : kDistanceFarMm;
    out.hidden_mm = s.hidden.full() ? to_mm(s.hidden.threshold(), false) : kDistanceFarMm;
    out.distance_mm = out.foreground_mm < out.hidden_mm ? out.foreground_mm : out.hidden_mm;
    out.required_mm = to_mm(protective_separation_distance(params, speed_class), true);
    const std::uint16_t reduced_mm = to_mm(reduced_speed_distance(params), true);
    if (out.distance_mm < out.required_mm) {
        out.request = SpeedRequest::kProtectiveStop;
    } else if (out.distance_mm < reduced_mm) {
        out.request = SpeedRequest::kReduced;
    } else {
        out.request = SpeedRequest::kFull;
    }
    return Status{};
}

}  // namespace cellguard
