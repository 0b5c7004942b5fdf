// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/grid.hpp"

#include <cmath>

namespace cellguard {

Result<GridGeometry> GridGeometry::make(const Eigen::Vector3d& origin, double voxel_size, GridDims dims) noexcept {
    if (!origin.allFinite() || !std::isfinite(voxel_size)) {
        return ErrorCode::kNonFiniteValue;
    }
    if (!(voxel_size > 0.0)) {
        return ErrorCode::kInvalidArgument;
    }
    const auto dim_ok = [](std::int32_t n) { return n >= 1 && n <= kMaxDimension; };
    if (!dim_ok(dims.nx) || !dim_ok(dims.ny) || !dim_ok(dims.nz)) {
        return ErrorCode::kInvalidArgument;
    }
    GridGeometry g;
    g.origin_ = origin;
    g.voxel_size_ = voxel_size;
    g.dims_ = dims;
    if (g.voxel_count() > kMaxVoxels) {
        return ErrorCode::kCapacityExceeded;
    }
    return g;
}

VoxelCoord GridGeometry::coord_of(std::size_t index) const noexcept {
    CG_ENFORCE(index < voxel_count(), "linear index outside the grid");
    const auto nx = static_cast<std::size_t>(dims_.nx);
    const auto ny = static_cast<std::size_t>(dims_.ny);
    VoxelCoord c;
    c.x = static_cast<std::int32_t>(index % nx);
    c.y = static_cast<std::int32_t>((index / nx) % ny);
    c.z = static_cast<std::int32_t>(index / (nx * ny));
    return c;
}

Result<VoxelCoord> GridGeometry::world_to_voxel(const Eigen::Vector3d& p) const noexcept {
    if (!p.allFinite()) {
        return ErrorCode::kNonFiniteValue;
    }
    const Eigen::Vector3d scaled = (p - origin_) / voxel_size_;
    if ((scaled.array() < 0.0).any() || scaled.x() >= dims_.nx || scaled.y() >= dims_.ny || scaled.z() >= dims_.nz) {
        return ErrorCode::kOutOfGrid;
    }
    return world_to_voxel_unchecked(p);
}

GridGeometry paper_grid_geometry() noexcept {
    return GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, 0.0), 0.05, GridDims{34, 30, 30}).value();
}

GridGeometry whole_cell_grid_geometry() noexcept {
    return GridGeometry::make(Eigen::Vector3d(-6.4, -6.4, -1.6), 0.05, GridDims{256, 256, 128}).value();
}

}  // namespace cellguard
