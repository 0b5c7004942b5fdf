#include "cellguard/ray_table.hpp"

#include <cmath>
#include <limits>

namespace cellguard {

namespace {

// The far point of pixel (u, v)'s ray at max_range, and the ray's norm factor.
struct PixelRay {
    Eigen::Vector3d far_point;
    double norm;
};

PixelRay pixel_ray(const SensorReading& s, std::int32_t u, std::int32_t v) noexcept {
    const PinholeIntrinsics& k = s.intrinsics;
    const Eigen::Vector3d dir((static_cast<double>(u) - k.cx) / k.fx, (static_cast<double>(v) - k.cy) / k.fy, 1.0);
    const double norm = dir.norm();
    const Eigen::Vector3d far_cam = dir * (static_cast<double>(s.max_range) / norm);
    return PixelRay{s.pose * far_cam, norm};
}

Status check_depth_sensor(const SensorReading& sensor) noexcept {
    const Status valid = validate_sensor_reading(sensor);
    if (!valid.ok()) {
        return valid;
    }
    if (sensor.kind != SensorDataKind::kDepthImage) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

}  // namespace

Result<std::size_t> count_ray_steps(const GridGeometry& grid, const SensorReading& sensor,
                                    Rasterization rasterization) noexcept {
    const Status ok = check_depth_sensor(sensor);
    if (!ok.ok()) {
        return ok.error();
    }
    std::size_t total = 0U;
    const Eigen::Vector3d origin = sensor.pose.translation();
    for (std::int32_t v = 0; v < sensor.intrinsics.height; ++v) {
        for (std::int32_t u = 0; u < sensor.intrinsics.width; ++u) {
            // The pixel's voxels plus its end marker.
            total += 1U + traverse(rasterization, grid, origin, pixel_ray(sensor, u, v).far_point,
                                   [](const TraversedVoxel& /*voxel*/) {});
        }
    }
    return total;
}

Result<RayTable> RayTable::build(const GridGeometry& grid, const SensorReading& sensor, RayTableStorage storage,
                                 Rasterization rasterization) noexcept {
    const Status ok = check_depth_sensor(sensor);
    if (!ok.ok()) {
        return ok.error();
    }
    const std::size_t pixels =
        static_cast<std::size_t>(sensor.intrinsics.width) * static_cast<std::size_t>(sensor.intrinsics.height);
    if (storage.pixel_begin.size() < pixels + 1U || storage.pixel_enter.size() < pixels ||
        storage.pixel_norm.size() < pixels) {
        return ErrorCode::kStorageTooSmall;
    }
    const Eigen::Vector3d origin = sensor.pose.translation();
    std::size_t n = 0U;
    bool overflow = false;
    std::size_t pixel = 0U;
    for (std::int32_t v = 0; v < sensor.intrinsics.height; ++v) {
        for (std::int32_t u = 0; u < sensor.intrinsics.width; ++u, ++pixel) {
            const PixelRay ray = pixel_ray(sensor, u, v);
            storage.pixel_begin[pixel] = static_cast<std::uint32_t>(n);
            storage.pixel_norm[pixel] = static_cast<float>(ray.norm);
            storage.pixel_enter[pixel] = std::numeric_limits<float>::infinity();
            bool first = true;
            (void)traverse(rasterization, grid, origin, ray.far_point, [&](const TraversedVoxel& t) {
                if (first) {
                    storage.pixel_enter[pixel] = static_cast<float>(t.t_enter);
                    first = false;
                }
                if (n < storage.steps.size()) {
                    storage.steps[n] = RayStep{static_cast<std::uint32_t>(t.index), static_cast<float>(t.t_exit)};
                }
                ++n;
            });
            if (n < storage.steps.size()) {
                storage.steps[n] = RayStep{kRayEndMarker, std::numeric_limits<float>::infinity()};
            }
            ++n;
            if (n > std::numeric_limits<std::uint32_t>::max()) {
                overflow = true;
            }
        }
    }
    if (overflow) {
        return ErrorCode::kCapacityExceeded;
    }
    if (n > storage.steps.size()) {
        return ErrorCode::kStorageTooSmall;
    }
    storage.pixel_begin[pixels] = static_cast<std::uint32_t>(n);
    RayTable table;
    table.geometry_ = grid;
    table.storage_ = storage;
    table.pixels_ = pixels;
    table.step_count_ = n;
    table.min_range_ = sensor.min_range;
    table.max_range_ = sensor.max_range;
    return table;
}

Result<FusionStats> RayTable::fuse(EvidenceGrid& grid, Span<const float> depth,
                                   const SensorModelTable& model) const noexcept {
    if (pixels_ == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (!(grid.geometry() == geometry_)) {
        return ErrorCode::kGeometryMismatch;
    }
    if (depth.size() != pixels_) {
        return ErrorCode::kMalformedInput;
    }
    std::int16_t* const lo = grid.log_odds().data();
    std::uint8_t* const obs = grid.observed().data();
    const RayStep* const steps = storage_.steps.data();
    const std::uint32_t* const begin = storage_.pixel_begin.data();
    CG_ENFORCE(step_count_ <= storage_.steps.size(), "ray table storage changed size");
    const std::int16_t constant = model.constant_free_evidence();
    const std::int16_t peak = model.reading_evidence();
    const auto ramp = static_cast<float>(model.ramp_length());
    FusionStats s;
    for (std::size_t i = 0U; i < pixels_; ++i) {
        const float d = depth[i];
        if (std::isnan(d)) {
            ++s.skipped_nan;
            continue;
        }
        if (std::isinf(d)) {
            ++s.skipped_infinite;
            continue;
        }
        if (d == 0.0F) {
            ++s.skipped_zero;
            continue;
        }
        if (d < 0.0F) {
            ++s.skipped_behind;
            continue;
        }
        const float range = d * storage_.pixel_norm[i];
        if (range < min_range_ || range > max_range_) {
            ++s.skipped_out_of_range;
            continue;
        }
        ++s.rays_fused;
        const RayStep* step = steps + begin[i];
        if (range < storage_.pixel_enter[i]) {
            continue;  // the ray misses the grid (enter = +inf), or the reading lies before it
        }
        const RayStep* const first = step;
        // Every pixel's steps end with a marker whose t_exit is +inf, so the
        // loops below need no end check: no finite range passes the marker.
        // The constant part of the profile: voxels left at least one ramp before the reading.
        const float free_until = range - ramp;
        for (; step->t_exit <= free_until; ++step) {
            lo[step->voxel] = add_finite_saturating(lo[step->voxel], constant);
            obs[step->voxel] = 1U;
        }
        // The ramp: voxels left before the reading.
        for (; step->t_exit <= range; ++step) {
            const std::int16_t e = model.free_evidence(static_cast<double>(range - step->t_exit));
            lo[step->voxel] = add_finite_saturating(lo[step->voxel], e);
            obs[step->voxel] = 1U;
        }
        // The voxel holding the reading, if the reading lies inside the grid.
        if (step->voxel != kRayEndMarker) {
            lo[step->voxel] = add_finite_saturating(lo[step->voxel], peak);
            obs[step->voxel] = 1U;
            ++step;
            ++s.readings_in_grid;
        }
        s.voxel_updates += static_cast<std::uint64_t>(step - first);
    }
    return s;
}

}  // namespace cellguard
