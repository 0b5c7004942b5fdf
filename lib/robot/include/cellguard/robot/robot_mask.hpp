// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_mask.hpp
/// The robot's own voxels in one cycle: every voxel that the robot's
/// capsules, each grown by a margin, may touch. Those voxels are the
/// robot's: zone evaluation counts them neither as foreground nor as unseen
/// (they are never taken for empty space either), and the separation
/// distance is measured from the capsules to what lies outside them.
///
/// A voxel is marked when its cube may intersect a grown capsule: its centre
/// lies within radius + margin + half the voxel's diagonal of the capsule's
/// segment. That over-approximates (conservative for "the robot is not
/// foreground"); the margin itself is derived in the safety manual from the
/// robot's speed, the command's age, the cycle time and the sensors'
/// uncertainty, and checked against the separation distance there.
///
/// Work: for each capsule, the voxels of its grown axis-aligned bounding box
/// inside the grid; robot_mask_work_bound gives the most over all poses,
/// from the capsules' sizes alone, for the cycle's work bound.
#ifndef CELLGUARD_ROBOT_MASK_HPP
#define CELLGUARD_ROBOT_MASK_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_model.hpp"

namespace cellguard {

/// Counts of one marking pass.
struct RobotMaskStats {
    std::uint32_t marked = 0U;  ///< voxels marked as the robot's
    std::uint64_t tested = 0U;  ///< voxel tests made (<= robot_mask_work_bound)
};

/// Rewrites @p mask (one byte per voxel of @p grid: 1 = the robot's, 0 =
/// not) for @p pose grown by @p margin_m (finite, >= 0). Capsules partly or
/// wholly outside the grid mark what lies inside. Errors: kStorageTooSmall
/// when @p mask holds fewer bytes than the grid has voxels,
/// kInvalidArgument for a bad margin, or a pose with a coordinate or radius
/// that is not finite (or a negative radius, or more than kMaxRobotCapsules
/// capsules): the mask is then all 1, the whole grid counts as the robot's,
/// and the separation check sees no space. Work: stats.tested voxel tests,
/// each a few multiplications and one comparison of squared distances.
[[nodiscard]] Status mark_robot_voxels(const GridGeometry& grid, const RobotPose& pose, double margin_m,
                                       Span<std::uint8_t> mask, RobotMaskStats& stats) noexcept;

/// The most voxel tests mark_robot_voxels makes for @p model in any pose on
/// a grid of voxel size @p voxel_size_m with margin @p margin_m: per capsule,
/// the voxels of the bounding box of a segment of its length in the worst
/// orientation (equal on all three axes: L / sqrt(3) each), grown by radius +
/// margin + half a voxel diagonal, plus two voxels per axis for the cells the
/// box's ends fall in; (L / sqrt(3) + 2 R) / s + 2, cubed, summed over the
/// capsules and rounded up. 0 for a margin or voxel size that
/// mark_robot_voxels would refuse (it then tests no voxel).
[[nodiscard]] std::uint64_t robot_mask_work_bound(const RobotModel& model, double margin_m,
                                                  double voxel_size_m) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ROBOT_MASK_HPP
