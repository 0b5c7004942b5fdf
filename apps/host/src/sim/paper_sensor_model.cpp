// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/paper_sensor_model.hpp"

#include <cmath>

#include "cellguard/grid/log_odds.hpp"

namespace cellguard::sim {

namespace {

/// Adds each ray's profile to the grid (fuse_frame_per_ray).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class ProfileRays final : public RayVisitor {
public:
    ProfileRays(EvidenceGrid& grid, const SensorModelTable& profile, Rasterization rasterization) noexcept
        : grid_(grid), profile_(profile), rasterization_(rasterization) {}
    RayOutcome ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& reading) noexcept override {
        RayOutcome o;
        o.visits = add_ray_profile(grid_, origin, reading, profile_, rasterization_, &o.reading_in_grid);
        return o;
    }

private:
    EvidenceGrid& grid_;
    const SensorModelTable& profile_;
    Rasterization rasterization_;
};

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
    ProfileRays rays(grid, profile, rasterization);
    FusionStats total;
    for (const SensorReading& r : sensors) {
        total.add(for_each_reading_ray(r, rays));
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
