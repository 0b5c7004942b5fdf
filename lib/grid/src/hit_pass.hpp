// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file hit_pass.hpp
/// Private to the grid module: step 1 of footprint fusion (the hit pass,
/// footprint_fusion.hpp), every pixel's reading placed by the one rule of
/// placement.hpp, its voxel given the hit and level 0 of the sensor's depth
/// pyramid written. Three pixel kernels (FusionKernel) give the same hits,
/// pyramid and counts bit for bit: the scalar one is the reference, the
/// vector ones place four pixels at a time in IEEE double with the scalar
/// form's operations in its order (the grid module is compiled with
/// -ffp-contract=off: no fused multiply-add on any target) and hand every
/// pixel the short test cannot take to the scalar form.
#ifndef CELLGUARD_GRID_HIT_PASS_HPP
#define CELLGUARD_GRID_HIT_PASS_HPP

#include <cstdint>

#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_frame.hpp"

namespace cellguard::detail {

/// Step 1 over every pixel of the depth image @p r (either kind): each valid
/// reading's voxel in @p opinions (one per voxel of @p g) set to @p hit when
/// it lies in the grid, level 0 of @p pyramid written (a skipped reading has
/// none), the readings counted as fuse_sensor counts them. @p kernel is
/// resolved by resolve_fusion_kernel; every kernel gives the same result.
[[nodiscard]] FusionStats hit_pass(const GridGeometry& g, const SensorReading& r, std::int16_t hit,
                                   DepthPyramid& pyramid, Span<std::int16_t> opinions, FusionKernel kernel) noexcept;

}  // namespace cellguard::detail

#endif  // CELLGUARD_GRID_HIT_PASS_HPP
