// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/paper_sensor_model.hpp"

#include <cmath>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/grid/reading_class.hpp"

namespace cellguard::sim {

namespace {

using detail::classify_depth;
using detail::classify_point;
using detail::count_skipped;
using detail::ReadingClass;

void add_point(EvidenceGrid& grid, const SensorReading& r, const Eigen::Vector3f& p, const SensorModelTable& profile,
               Rasterization rasterization, FusionStats& s) noexcept {
    const ReadingClass c = classify_point(p, r.min_range, r.max_range);
    if (c != ReadingClass::kValid) {
        count_skipped(s, c);
        return;
    }
    bool in_grid = false;
    s.voxel_updates += add_ray_profile(grid, r.pose.translation(), reading_in_cell(r.pose, p), profile, rasterization,
                                       &in_grid);
    ++s.rays_fused;
    s.readings_in_grid += in_grid ? 1U : 0U;
}

FusionStats add_sensor(EvidenceGrid& grid, const SensorReading& r, const SensorModelTable& profile,
                       Rasterization rasterization) noexcept {
    FusionStats s;
    if (r.kind == SensorDataKind::kPointSet) {
        for (const Eigen::Vector3f& p : r.points) {
            add_point(grid, r, p, profile, rasterization, s);
        }
        return s;
    }
    const PinholeIntrinsics& k = r.intrinsics;
    const double inv_fx = 1.0 / k.fx;
    const double inv_fy = 1.0 / k.fy;
    std::size_t i = 0U;
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u, ++i) {
            const float d = depth_value(r, i);
            const ReadingClass raw = classify_depth(d);  // before the point: 0 * inf would hide an infinity
            if (raw != ReadingClass::kValid) {
                count_skipped(s, raw);
                continue;
            }
            add_point(grid, r, depth_pixel_point(k, inv_fx, inv_fy, u, v, d), profile, rasterization, s);
        }
    }
    return s;
}

}  // namespace

const char* model_name(EvalSensorModel model) noexcept {
    switch (model) {
        case EvalSensorModel::kPaper: return "paper";
        case EvalSensorModel::kProduct: return "product";
    }
    return "unknown";
}

SensorModelParams paper_profile() noexcept {
    SensorModelParams p;
    p.p_miss = 0.44;
    p.p_hit = 0.56;
    p.ramp_length = 0.10;
    return p;
}

std::uint32_t add_ray_profile(EvidenceGrid& grid, const Eigen::Vector3d& origin, const Eigen::Vector3d& reading,
                              const SensorModelTable& profile, Rasterization rasterization,
                              bool* reading_in_grid) noexcept {
    const GridGeometry& g = grid.geometry();
    const double length = (reading - origin).norm();
    if (!std::isfinite(length)) {
        return 0U;
    }
    // The voxel holding the reading, by the traversal's half-open rule.
    const VoxelCoord end = g.world_to_voxel_unchecked(reading);
    const bool end_inside = g.contains(end);
    const std::size_t end_index = end_inside ? g.index_of(end) : g.voxel_count();
    if (reading_in_grid != nullptr) {
        *reading_in_grid = end_inside;
    }
    std::int16_t* const lo = grid.log_odds().data();
    std::uint8_t* const obs = grid.observed().data();
    const std::int16_t peak = profile.reading_evidence();
    std::uint32_t visits = 0U;
    const auto visit = [&](const TraversedVoxel& v) {
        const std::int16_t e = v.index == end_index ? peak : profile.free_evidence(length - v.t_exit);
        lo[v.index] = add_finite_saturating(lo[v.index], e);
        obs[v.index] = 1U;
        ++visits;
    };
    static_cast<void>(traverse(rasterization, g, origin, reading, visit));
    return visits;
}

Result<FusionStats> fuse_frame_per_ray(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                       const SensorModelTable& profile, Rasterization rasterization) noexcept {
    if (sensors.size() > kMaxSensors) {
        return ErrorCode::kCapacityExceeded;
    }
    for (const SensorReading& r : sensors) {
        const Status valid = validate_sensor_reading(r);
        if (!valid.ok()) {
            return valid.error();
        }
    }
    FusionStats total;
    for (const SensorReading& r : sensors) {
        total.add(add_sensor(grid, r, profile, rasterization));
    }
    return total;
}

std::uint32_t paper_min_background_frames(double t_e, const SensorModelTable& profile) noexcept {
    const auto need = static_cast<double>(log_odds_from_probability(t_e));
    const auto per_frame = static_cast<double>(profile.constant_free_evidence());
    if (!(per_frame < 0.0) || !(need < 0.0)) {
        return 1U;
    }
    const double frames = std::ceil(need / per_frame);
    return frames < 1.0 ? 1U : static_cast<std::uint32_t>(frames);
}

}  // namespace cellguard::sim
