// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file grid.hpp
/// Geometry of a dense, axis-aligned 3D voxel grid: dimensions, index math,
/// world <-> voxel conversion. Holds no voxel data (see evidence_grid.hpp).
///
/// Conventions, used everywhere in cellguard:
/// - World coordinates in metres (double), in the workcell frame.
/// - `origin` is the world position of the grid's minimum corner (the
///   corner of voxel (0,0,0)), not a voxel centre.
/// - Voxel (x, y, z) covers [origin + s*(x,y,z), origin + s*(x+1,y+1,z+1)),
///   half-open: a point on a shared face belongs to the voxel above it.
/// - Linear index = x + nx * (y + ny * z): x varies fastest.
/// One type serves the paper's 34 x 30 x 30 grid at 5 cm and a
/// 256 x 256 x 128 grid alike; limits are kMaxDimension per axis and
/// kMaxVoxels in total.
#ifndef CELLGUARD_GRID_HPP
#define CELLGUARD_GRID_HPP

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"

namespace cellguard {

/// Integer voxel coordinate; may lie outside a grid (check with contains()).
struct VoxelCoord {
    std::int32_t x = 0;  ///< column, along world x
    std::int32_t y = 0;  ///< row, along world y
    std::int32_t z = 0;  ///< layer, along world z (up)
    /// Component-wise equality, without a branch: the components' differing
    /// bits are or-ed and compared once (no short-circuit per component).
    friend constexpr bool operator==(const VoxelCoord& a, const VoxelCoord& b) noexcept {
        return (bits(a.x, b.x) | bits(a.y, b.y) | bits(a.z, b.z)) == 0U;
    }
    /// Component-wise inequality.
    friend constexpr bool operator!=(const VoxelCoord& a, const VoxelCoord& b) noexcept { return !(a == b); }
    /// The bits in which @p u and @p v differ (0 when equal).
    static constexpr std::uint32_t bits(std::int32_t u, std::int32_t v) noexcept {
        return static_cast<std::uint32_t>(u) ^ static_cast<std::uint32_t>(v);
    }
};

/// Number of voxels along each axis.
struct GridDims {
    std::int32_t nx = 0;  ///< voxels along x
    std::int32_t ny = 0;  ///< voxels along y
    std::int32_t nz = 0;  ///< voxels along z
    /// Component-wise equality, without a branch (as VoxelCoord's).
    friend constexpr bool operator==(const GridDims& a, const GridDims& b) noexcept {
        return (VoxelCoord::bits(a.nx, b.nx) | VoxelCoord::bits(a.ny, b.ny) | VoxelCoord::bits(a.nz, b.nz)) == 0U;
    }
};

/// Largest number of voxels along one axis.
constexpr std::int32_t kMaxDimension = 4096;
/// Largest number of voxels in one grid (2^27, 128 Mi voxels).
constexpr std::size_t kMaxVoxels = std::size_t{1} << 27U;

/// Position, voxel size and dimensions of a grid. Construct with make(),
/// which validates; a default-constructed geometry is empty (0 voxels).
class GridGeometry {
public:
    /// An empty geometry (no voxels); only useful as a placeholder.
    GridGeometry() noexcept = default;

    /// Validates and builds a geometry. Errors: kNonFiniteValue (origin or
    /// voxel size not finite), kInvalidArgument (voxel size <= 0, a dimension
    /// < 1 or > kMaxDimension), kCapacityExceeded (more than kMaxVoxels).
    static Result<GridGeometry> make(const Eigen::Vector3d& origin, double voxel_size, GridDims dims) noexcept;

    /// World position of the grid's minimum corner.
    [[nodiscard]] const Eigen::Vector3d& origin() const noexcept { return origin_; }
    /// Edge length of one voxel, metres.
    [[nodiscard]] double voxel_size() const noexcept { return voxel_size_; }
    /// Voxels per axis.
    [[nodiscard]] GridDims dims() const noexcept { return dims_; }
    /// Total number of voxels.
    [[nodiscard]] std::size_t voxel_count() const noexcept {
        return static_cast<std::size_t>(dims_.nx) * static_cast<std::size_t>(dims_.ny) *
               static_cast<std::size_t>(dims_.nz);
    }
    /// World position of the grid's maximum corner.
    [[nodiscard]] Eigen::Vector3d max_corner() const noexcept {
        return origin_ + voxel_size_ * Eigen::Vector3d(dims_.nx, dims_.ny, dims_.nz);
    }

    /// True when @p c lies inside the grid.
    [[nodiscard]] bool contains(const VoxelCoord& c) const noexcept {
        return c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < dims_.nx && c.y < dims_.ny && c.z < dims_.nz;
    }
    /// Linear index of @p c; @p c must be inside (checked in debug builds).
    [[nodiscard]] std::size_t index_of(const VoxelCoord& c) const noexcept {
        CG_ASSERT(contains(c), "voxel outside the grid");
        return static_cast<std::size_t>(c.x) +
               static_cast<std::size_t>(dims_.nx) *
                   (static_cast<std::size_t>(c.y) + static_cast<std::size_t>(dims_.ny) * static_cast<std::size_t>(c.z));
    }
    /// Voxel coordinate of linear index @p index (< voxel_count(), checked always).
    [[nodiscard]] VoxelCoord coord_of(std::size_t index) const noexcept;

    /// The voxel holding world point @p p (half-open cells), or kOutOfGrid,
    /// or kNonFiniteValue for NaN/infinite input.
    [[nodiscard]] Result<VoxelCoord> world_to_voxel(const Eigen::Vector3d& p) const noexcept;
    /// The voxel coordinate of @p p without a range check (floor of the
    /// scaled position (p - origin) / voxel size); the caller checks
    /// contains(). p must be finite and within +-2^30 voxels of the origin.
    /// Inline: every fusion path places its readings with it, per pixel.
    [[nodiscard]] VoxelCoord world_to_voxel_unchecked(const Eigen::Vector3d& p) const noexcept {
        return VoxelCoord{floor_index((p.x() - origin_.x()) / voxel_size_),
                          floor_index((p.y() - origin_.y()) / voxel_size_),
                          floor_index((p.z() - origin_.z()) / voxel_size_)};
    }
    /// std::floor of @p s as an integer, for |s| < 2^31: truncation, one
    /// less where truncation rounded up (a negative non-integer); no call.
    [[nodiscard]] static std::int32_t floor_index(double s) noexcept {
        const auto t = static_cast<std::int32_t>(s);
        return t - static_cast<std::int32_t>(static_cast<double>(t) > s);
    }
    /// World position of the centre of voxel @p c (c need not be inside).
    [[nodiscard]] Eigen::Vector3d voxel_center(const VoxelCoord& c) const noexcept {
        return origin_ + voxel_size_ * (Eigen::Vector3d(c.x, c.y, c.z) + Eigen::Vector3d::Constant(0.5));
    }
    /// Exact equality of origin, voxel size and dimensions.
    [[nodiscard]] bool operator==(const GridGeometry& other) const noexcept {
        return origin_ == other.origin_ && voxel_size_ == other.voxel_size_ && dims_ == other.dims_;
    }

private:
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    double voxel_size_ = 1.0;
    GridDims dims_{};
};

/// The paper's grid: 1.7 m x 1.5 m x 1.5 m at 5 cm (34 x 30 x 30), centred
/// horizontally in the 4 m x 4 m cell and standing on the floor: origin
/// (-0.85, -0.75, 0). The cell's world frame has x and y in [-2, 2] m and
/// the floor at z = 0, the ceiling at z = 2 m.
GridGeometry paper_grid_geometry() noexcept;

/// The large benchmark grid: 256 x 256 x 128 voxels at 5 cm (12.8 m x 12.8 m
/// x 6.4 m, origin (-6.4, -6.4, -1.6)), which holds the whole 4 m x 4 m x 2 m
/// cell with every ray of its sensors.
GridGeometry whole_cell_grid_geometry() noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_GRID_HPP
