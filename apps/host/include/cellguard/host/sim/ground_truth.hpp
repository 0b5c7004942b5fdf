// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file ground_truth.hpp
/// Ground truth for the paper's experiments (section IV): the ideal 0-1
/// sensor model on the same sensors without noise. Every pixel's ray runs to
/// the first surface it meets (cast_ray_hit); the voxel holding the reading
/// is occupied (P = 1), the voxels the ray crosses before it are empty
/// (P = 0), rasterised as fusion does. Across rays an occupied reading wins
/// over an empty crossing (a surface voxel is occupied even when another ray
/// grazes it).
///
/// Labels per voxel:
/// - foreground: occupied by a reading on a foreground box;
/// - unknown: never seen by any ray and overlapping a foreground box (the
///   interiors of foreground objects, and their hidden parts): left out of
///   the scores;
/// - robot: no reading on a foreground box, and a reading on the robot's
///   capsules lies in the voxel, or it was never seen and overlaps a capsule
///   (the robot is neither foreground nor empty: left out of the scores, as
///   the robot mask leaves it out of zone evaluation);
/// - not foreground: everything else (seen empty, background surfaces,
///   background interiors, space hidden behind the foreground that holds no
///   foreground).
#ifndef CELLGUARD_HOST_SIM_GROUND_TRUTH_HPP
#define CELLGUARD_HOST_SIM_GROUND_TRUTH_HPP

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::sim {

/// The ground-truth label of one voxel.
enum class Truth : std::uint8_t {
    kNotForeground = 0,  ///< no foreground in the voxel
    kForeground = 1,     ///< a reading on a foreground object lies in the voxel
    kUnknown = 2,        ///< inside a foreground object and never seen: not scored
    kRobot = 3,          ///< the robot's surface, or its unseen inside: not scored
};

/// Labels of every voxel of a grid (linear index order) and their counts.
struct GroundTruth {
    std::vector<Truth> label;         ///< one label per voxel
    std::size_t foreground = 0U;      ///< voxels labelled kForeground
    std::size_t not_foreground = 0U;  ///< voxels labelled kNotForeground
    std::size_t unknown = 0U;         ///< voxels labelled kUnknown
    std::size_t robot = 0U;           ///< voxels labelled kRobot
};

/// The ideal 0-1 ground truth of @p scene seen by @p sensors (their noise
/// models are ignored) on grid @p g. "Overlapping a foreground box" (or a
/// capsule of the robot) is tested on the 27 points of a 3 x 3 x 3 lattice in the voxel (corners,
/// edge and face centres, centre).
GroundTruth ideal_ground_truth(const GridGeometry& g, const std::vector<SensorSpec>& sensors, const Scene& scene,
                               Rasterization rasterization = Rasterization::kExact);

/// 1 for every voxel of @p g that lies wholly inside a background box of
/// @p scene, at least @p margin metres from its surface (the eight corners of
/// the voxel grown by margin inside; boxes are convex), else 0. With margin
/// 0 the voxels just under a surface count; a margin of one voxel keeps
/// only the deep interior, beyond the reach of noisy readings.
std::vector<std::uint8_t> background_interior_mask(const GridGeometry& g, const Scene& scene, double margin = 0.0);

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_GROUND_TRUTH_HPP
