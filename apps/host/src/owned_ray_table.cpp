// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/owned_ray_table.hpp"

namespace cellguard::host {

Status OwnedRayTable::build(const GridGeometry& grid, const SensorReading& sensor, Rasterization rasterization) {
    table_ = RayTable{};
    const Result<std::size_t> n = count_ray_steps(grid, sensor, rasterization);
    if (!n.ok()) {
        return n.error();
    }
    const std::size_t pixels = static_cast<std::size_t>(sensor.intrinsics.width) *
                               static_cast<std::size_t>(sensor.intrinsics.height);
    const bool compact = ray_table_is_compact(grid, sensor);
    compact_voxels_.assign(compact ? n.value() : 0U, 0U);
    compact_exit_steps_.assign(compact ? n.value() : 0U, 0U);
    wide_voxels_.assign(compact ? 0U : n.value(), 0U);
    wide_exits_.assign(compact ? 0U : n.value(), 0.0F);
    pixel_begin_.resize(pixels + 1U);
    pixel_enter_.resize(pixels);
    pixel_exit_.resize(pixels);
    pixel_norm_.resize(pixels);
    full_hits_.resize(grid.voxel_count());
    crossed_voxels_.resize(grid.voxel_count());
    pixel_walked_.resize(pixels);
    hit_count_.resize(grid.voxel_count());
    sensor_opinion_.resize(grid.voxel_count());
    const Result<RayTable> built = RayTable::build(
        grid, sensor,
        RayTableStorage{{compact_voxels_.data(), compact_voxels_.size()},
                        {compact_exit_steps_.data(), compact_exit_steps_.size()},
                        {wide_voxels_.data(), wide_voxels_.size()},
                        {wide_exits_.data(), wide_exits_.size()},
                        {pixel_begin_.data(), pixel_begin_.size()},
                        {pixel_enter_.data(), pixel_enter_.size()},
                        {pixel_exit_.data(), pixel_exit_.size()},
                        {pixel_norm_.data(), pixel_norm_.size()},
                        {full_hits_.data(), full_hits_.size()},
                        {crossed_voxels_.data(), crossed_voxels_.size()},
                        {pixel_walked_.data(), pixel_walked_.size()},
                        {hit_count_.data(), hit_count_.size()},
                        {sensor_opinion_.data(), sensor_opinion_.size()}},
        rasterization);
    if (!built.ok()) {
        return built.error();
    }
    table_ = built.value();
    return Status{};
}

std::size_t OwnedRayTable::storage_bytes() const noexcept {
    return (compact_voxels_.size() + compact_exit_steps_.size()) * sizeof(std::uint16_t) +
           wide_voxels_.size() * sizeof(std::uint32_t) + wide_exits_.size() * sizeof(float) +
           (pixel_begin_.size() + full_hits_.size() + crossed_voxels_.size() + pixel_walked_.size() +
            hit_count_.size()) *
               sizeof(std::uint32_t) +
           (pixel_enter_.size() + pixel_exit_.size() + pixel_norm_.size()) * sizeof(float) +
           sensor_opinion_.size() * sizeof(std::int16_t);
}

}  // namespace cellguard::host
