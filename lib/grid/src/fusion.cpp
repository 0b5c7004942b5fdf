// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/fusion.hpp"

#include <cmath>

#include "placement.hpp"
#include "reading_class.hpp"

namespace cellguard {

void FusionStats::add(const FusionStats& other) noexcept {
    rays_fused += other.rays_fused;
    readings_in_grid += other.readings_in_grid;
    skipped_nan += other.skipped_nan;
    skipped_infinite += other.skipped_infinite;
    skipped_zero += other.skipped_zero;
    skipped_behind += other.skipped_behind;
    skipped_out_of_range += other.skipped_out_of_range;
    voxel_updates += other.voxel_updates;
}

namespace {

/// trace_ray_opinions for the exact traversal, the same opinions as its generic visitor with
/// less work per voxel:
/// - the reading's voxel can only be the last one visited: the traversal ends in
///   world_to_voxel(end) when the end is in the grid (plan.end_inside, the same half-open test)
///   and visits no voxel twice; so only the last voxel can take the hit;
/// - free_evidence(length - t_exit) is the constant p_miss value while length - t_exit >=
///   ramp_length, i.e. for every crossing below a per-ray bound (detail::tau_bound_below, a
///   few ulps on the safe side): those voxels take the constant without the crossing in metres.
std::uint32_t trace_exact_opinions(std::int16_t* op, const GridGeometry& g, const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& reading, double length, const SensorModelTable& model,
                                   bool* reading_in_grid) noexcept {
    const detail::ExactTraversalPlan p = detail::plan_exact_traversal(g, origin, reading);
    if (reading_in_grid != nullptr) {
        *reading_in_grid = p.visits ? p.end_inside : g.contains(g.world_to_voxel_unchecked(reading));
    }
    if (!p.visits) {
        return 0U;
    }
    // fl(length - t) >= ramp for every t <= far (fl is monotone); tried at length - ramp, then
    // a few ulps lower, else no shortcut.
    const double ramp = model.ramp_length();
    double far = length - ramp;
    if (!(length - far >= ramp)) {
        far -= std::fabs(far) * 0x1p-50;
    }
    const std::uint64_t tau_far = (length - far >= ramp) ? detail::tau_bound_below(p, far) : 0U;
    const std::int16_t constant_free = model.constant_free_evidence();
    const auto keep_max = [op](std::size_t index, std::int16_t e) { op[index] = e > op[index] ? e : op[index]; };
    const std::size_t visits = detail::walk_exact(
        p,
        [&](std::size_t index, const VoxelCoord& /*c*/, std::uint64_t tau) {
            keep_max(index, tau < tau_far ? constant_free : model.free_evidence(length - detail::exit_metres(p, tau)));
        },
        [&](std::size_t index, const VoxelCoord& /*c*/) {
            keep_max(index, p.end_inside ? model.reading_evidence()
                                         : model.free_evidence(length - detail::exit_metres(p, detail::kTauNever)));
        });
    return static_cast<std::uint32_t>(visits);
}

}  // namespace

std::uint32_t trace_ray_opinions(Span<std::int16_t> opinions, const GridGeometry& g, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& reading, const SensorModelTable& model,
                                 Rasterization rasterization, bool* reading_in_grid) noexcept {
    const double length = (reading - origin).norm();
    if (!std::isfinite(length)) {
        return 0U;
    }
    if (rasterization == Rasterization::kExact) {
        return trace_exact_opinions(opinions.data(), g, origin, reading, length, model, reading_in_grid);
    }
    // The voxel holding the reading, by the same half-open rule as the traversal.
    const VoxelCoord end = g.world_to_voxel_unchecked(reading);
    const bool end_inside = g.contains(end);
    const std::size_t end_index = end_inside ? g.index_of(end) : g.voxel_count();
    if (reading_in_grid != nullptr) {
        *reading_in_grid = end_inside;
    }
    std::int16_t* const op = opinions.data();
    const std::int16_t hit = model.reading_evidence();
    std::uint32_t visits = 0U;
    const auto visit = [&](const TraversedVoxel& v) {
        const std::int16_t e = (v.index == end_index) ? hit : model.free_evidence(length - v.t_exit);
        op[v.index] = e > op[v.index] ? e : op[v.index];
        ++visits;
    };
    (void)traverse(rasterization, g, origin, reading, visit);
    return visits;
}

Eigen::Vector3f depth_pixel_point(const PinholeIntrinsics& k, double inv_fx, double inv_fy, std::int32_t u,
                                  std::int32_t v, float d) noexcept {
    return detail::pixel_point(k, inv_fx, inv_fy, u, v, d);
}

Eigen::Vector3d reading_in_cell(const Eigen::Isometry3d& pose, const Eigen::Vector3f& p) noexcept {
    return detail::cell_point(pose, p);
}

// cppcheck-suppress constParameter ; the grid is written through its views: const would hide that
void pool_opinions(EvidenceGrid& grid, Span<const std::int16_t> opinions, const SensorModelTable& model) noexcept {
    std::int16_t* const lo = grid.log_odds().data();
    std::uint8_t* const obs = grid.observed().data();
    const std::size_t n = grid.voxel_count();
    for (std::size_t i = 0U; i < n; ++i) {
        const std::int16_t e = opinions[i];
        if (e != kNoOpinion) {
            lo[i] = model.pool(lo[i], e);
            obs[i] = 1U;
        }
    }
}

namespace {

using detail::classify_point;
using detail::count_skipped;
using detail::ReadingClass;

void visit_point(const SensorReading& r, const Eigen::Vector3f& p, RayVisitor& visitor, FusionStats& s) noexcept {
    const ReadingClass c = classify_point(p, r.min_range, r.max_range);
    if (c != ReadingClass::kValid) {
        count_skipped(s, c);
        return;
    }
    const RayOutcome o = visitor.ray(r.pose.translation(), detail::cell_point(r.pose, p));
    s.voxel_updates += o.visits;
    ++s.rays_fused;
    s.readings_in_grid += o.reading_in_grid ? 1U : 0U;
}

/// The opinions of one sensor's rays, written into its scratch (fuse_sensor).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class OpinionRays final : public RayVisitor {
public:
    OpinionRays(Span<std::int16_t> opinions, const GridGeometry& g, const SensorModelTable& model,
                Rasterization rasterization) noexcept
        : opinions_(opinions), g_(g), model_(model), rasterization_(rasterization) {}
    RayOutcome ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& reading) noexcept override {
        RayOutcome o;
        o.visits = trace_ray_opinions(opinions_, g_, origin, reading, model_, rasterization_, &o.reading_in_grid);
        return o;
    }

private:
    Span<std::int16_t> opinions_;
    const GridGeometry& g_;
    const SensorModelTable& model_;
    Rasterization rasterization_;
};

}  // namespace

FusionStats for_each_reading_ray(const SensorReading& reading, RayVisitor& visitor) noexcept {
    FusionStats s;
    if (reading.kind == SensorDataKind::kPointSet) {
        for (const Eigen::Vector3f& p : reading.points) {
            visit_point(reading, p, visitor, s);
        }
        return s;
    }
    const PinholeIntrinsics& k = reading.intrinsics;
    const double inv_fx = 1.0 / k.fx;
    const double inv_fy = 1.0 / k.fy;
    std::size_t i = 0U;
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u, ++i) {
            const float d = depth_value(reading, i);  // either kind, read in place
            // Classify the raw depth first: 0 * inf would hide an infinity as NaN.
            const ReadingClass raw = detail::classify_depth(d);
            if (raw != ReadingClass::kValid) {
                count_skipped(s, raw);
                continue;
            }
            visit_point(reading, detail::pixel_point(k, inv_fx, inv_fy, u, v, d), visitor, s);
        }
    }
    return s;
}

Result<FusionStats> fuse_sensor(EvidenceGrid& grid, const SensorReading& reading, const SensorModelTable& model,
                                Span<std::int16_t> scratch, Rasterization rasterization) noexcept {
    const Status valid = validate_sensor_reading(reading);
    if (!valid.ok()) {
        return valid.error();
    }
    const std::size_t n = grid.voxel_count();
    if (scratch.size() < n) {
        return ErrorCode::kStorageTooSmall;
    }
    const Span<std::int16_t> opinions = scratch.subspan(0U, n);
    for (std::int16_t& e : opinions) {
        e = kNoOpinion;
    }
    OpinionRays rays(opinions, grid.geometry(), model, rasterization);
    const FusionStats s = for_each_reading_ray(reading, rays);
    pool_opinions(grid, Span<const std::int16_t>(opinions), model);
    return s;
}

Result<FusionStats> fuse_frame(EvidenceGrid& grid, Span<const SensorReading> sensors, const SensorModelTable& model,
                               Span<std::int16_t> scratch, Rasterization rasterization) noexcept {
    if (sensors.size() > kMaxSensors) {
        return ErrorCode::kCapacityExceeded;
    }
    if (scratch.size() < grid.voxel_count()) {
        return ErrorCode::kStorageTooSmall;
    }
    for (const SensorReading& r : sensors) {
        const Status valid = validate_sensor_reading(r);
        if (!valid.ok()) {
            return valid.error();
        }
    }
    FusionStats total;
    for (const SensorReading& r : sensors) {
        const Result<FusionStats> s = fuse_sensor(grid, r, model, scratch, rasterization);
        if (!s.ok()) {         // GCOVR_EXCL_BR_LINE: validated above
            return s.error();  // unreachable: validated above GCOVR_EXCL_BR_LINE
        }
        total.add(s.value());
    }
    return total;
}

Result<FusionStats> fuse_background_frame(EvidenceGrid& background, EvidenceGrid& frame,
                                          Span<const SensorReading> sensors, const SensorModelTable& model,
                                          Span<std::int16_t> scratch, Rasterization rasterization,
                                          BackgroundClamp clamp) noexcept {
    frame.clear();
    const Result<FusionStats> fused = fuse_frame(frame, sensors, model, scratch, rasterization);
    if (!fused.ok()) {
        return fused.error();
    }
    const Status acc = accumulate_background(background, frame, clamp);
    if (!acc.ok()) {
        return acc.error();
    }
    return fused.value();
}

}  // namespace cellguard
