// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file render.hpp
/// Voxel renders in the spirit of the paper's Figs. 4-7: foreground voxels in
/// red over the background in grey, seen through a pinhole camera (a
/// sensor's viewpoint). Each pixel's ray walks the grid (the exact
/// traversal) to the first voxel of a non-empty class; the face it enters
/// sets the shade (top, x or y side) and voxel edges are drawn darker.
#ifndef CELLGUARD_EVAL_RENDER_HPP
#define CELLGUARD_EVAL_RENDER_HPP

#include <cstdint>
#include <vector>

#include "cellguard/grid/grid.hpp"
#include "cellguard/host/io/png.hpp"
#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::eval {

using host::IndexedImage;  ///< the renders are indexed-colour images

/// What a voxel shows as.
enum class VoxelClass : std::uint8_t {
    kEmpty = 0,       ///< transparent
    kBackground = 1,  ///< grey
    kForeground = 2,  ///< red
    kFloor = 3,       ///< light grey (background voxels of the bottom layer)
};

/// Renders @p classes (one per voxel of @p g) seen from @p camera (its
/// pose and fields of view; its resolution is replaced by @p width x
/// @p height).
IndexedImage render_voxels(const GridGeometry& g, const std::vector<VoxelClass>& classes, const sim::SensorSpec& camera,
                           int width, int height);

}  // namespace cellguard::eval

#endif  // CELLGUARD_EVAL_RENDER_HPP
