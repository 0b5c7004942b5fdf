// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file owned_ray_table.hpp
/// A ray table (lib/'s ray_table.hpp) with its storage on the host heap: the
/// one way the host programs, benchmarks and tests build one, so the storage
/// layout is written once. lib/ itself never allocates; this is apps/ code.
#ifndef CELLGUARD_HOST_OWNED_RAY_TABLE_HPP
#define CELLGUARD_HOST_OWNED_RAY_TABLE_HPP

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cellguard/grid/ray_table.hpp"

namespace cellguard::host {

/// A RayTable and the vectors it points into. Movable (a moved vector keeps
/// its buffer, so the table's spans stay valid), not copyable.
class OwnedRayTable {
public:
    OwnedRayTable() = default;
    OwnedRayTable(const OwnedRayTable&) = delete;
    OwnedRayTable& operator=(const OwnedRayTable&) = delete;
    OwnedRayTable(OwnedRayTable&&) noexcept = default;
    OwnedRayTable& operator=(OwnedRayTable&&) noexcept = default;
    ~OwnedRayTable() = default;

    /// Sizes the storage with count_ray_steps and builds the table in place
    /// (replacing any table held before). Errors: those of count_ray_steps
    /// and RayTable::build; on error the object holds no table.
    [[nodiscard]] Status build(const GridGeometry& grid, const SensorReading& sensor,
                               Rasterization rasterization = Rasterization::kExact);

    /// The table (empty until built).
    [[nodiscard]] const RayTable& table() const noexcept { return table_; }
    /// Bytes of the table's storage (what a target must provide for it).
    [[nodiscard]] std::size_t storage_bytes() const noexcept;

private:
    std::vector<std::uint16_t> compact_voxels_;
    std::vector<std::uint16_t> compact_exit_steps_;
    std::vector<std::uint32_t> wide_voxels_;
    std::vector<float> wide_exits_;
    std::vector<std::uint32_t> pixel_begin_;
    std::vector<float> pixel_enter_;
    std::vector<float> pixel_exit_;
    std::vector<float> pixel_norm_;
    std::vector<std::uint32_t> full_hits_;
    std::vector<std::uint32_t> crossed_voxels_;
    std::vector<std::uint32_t> pixel_walked_;
    std::vector<std::uint32_t> hit_count_;
    std::vector<std::int16_t> sensor_opinion_;
    RayTable table_;
};

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_OWNED_RAY_TABLE_HPP
