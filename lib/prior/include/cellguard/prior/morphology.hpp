// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file morphology.hpp
/// Grey-scale morphology with the 6-neighbour cross on a box region of a 3-D
/// array: the building block of the accessibility analysis (accessibility.hpp).
///
/// - The cross is a voxel and its six face neighbours: the L1 ball of
///   radius 1. The L1 ball of radius r is the r-fold Minkowski sum of the
///   cross, so r passes with the cross give exactly the erosion (minimum),
///   dilation (maximum) or minimum filter over the L1 ball of radius r (the
///   paper's structuring element R, eq. 10) for every voxel whose lattice
///   paths of length <= r stay inside the array.
/// - Arrays are stored x fastest (index = x + ax * (y + ay * z)), like grids.
///   A pass writes only the voxels of the region; it reads the region and the
///   one-voxel layer around it, which must lie inside the array. That layer
///   is the boundary condition: the caller sets it (e.g. to "empty" beyond an
///   open face and "occupied" beyond a closed one before an erosion, to 0
///   before a dilation, to the largest value before a minimum filter) and it
///   is never written, so ping-pong passes keep it.
/// - Input and output must be different arrays (checked always). No heap.
#ifndef CELLGUARD_MORPHOLOGY_HPP
#define CELLGUARD_MORPHOLOGY_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"

namespace cellguard {

/// A box of voxels inside a 3-D array, with at least one array voxel on
/// every side of the box.
struct PaddedRegion {
    GridDims array{};    ///< voxels of the whole array along x, y, z
    VoxelCoord first{};  ///< array coordinate of the box's minimum corner
    GridDims size{};     ///< voxels of the box along x, y, z

    /// Number of voxels of the whole array.
    [[nodiscard]] constexpr std::size_t array_voxel_count() const noexcept {
        return array.nx <= 0 || array.ny <= 0 || array.nz <= 0
                   ? 0U
                   : static_cast<std::size_t>(array.nx) * static_cast<std::size_t>(array.ny) *
                         static_cast<std::size_t>(array.nz);
    }
    /// True when the box is non-empty and a layer of at least one voxel of
    /// the array surrounds it on all six sides.
    [[nodiscard]] constexpr bool valid() const noexcept {
        return size.nx >= 1 && size.ny >= 1 && size.nz >= 1 && first.x >= 1 && first.y >= 1 && first.z >= 1 &&
               array.nx - first.x - size.nx >= 1 && array.ny - first.y - size.ny >= 1 &&
               array.nz - first.z - size.nz >= 1;
    }
};

/// Erosion by the cross: for every voxel v of the region,
/// out[v] = min of in[] over v and its six neighbours (for 0/1 values: AND).
/// Contracts (always checked): region.valid(), both spans hold at least
/// region.array_voxel_count() elements, and they do not overlap.
void erode_cross(const PaddedRegion& region, Span<const std::uint8_t> in, Span<std::uint8_t> out) noexcept;

/// Dilation by the cross: for every voxel v of the region,
/// out[v] = max of in[] over v and its six neighbours (for 0/1 values: OR).
/// Contracts as erode_cross.
void dilate_cross(const PaddedRegion& region, Span<const std::uint8_t> in, Span<std::uint8_t> out) noexcept;

/// Minimum filter by the cross on 32-bit values: for every voxel v of the
/// region, out[v] = min of in[] over v and its six neighbours. Contracts as
/// erode_cross.
void min_cross(const PaddedRegion& region, Span<const std::uint32_t> in, Span<std::uint32_t> out) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_MORPHOLOGY_HPP
