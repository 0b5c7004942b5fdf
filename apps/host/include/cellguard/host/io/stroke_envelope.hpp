// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file stroke_envelope.hpp
/// A capsule that encloses another capsule over the whole stroke of the
/// joints that move it without the PLC sending their positions: a
/// gripper's fingers, whose joints never go over CAN. Commissioning
/// (urdf_import.hpp) folds such links into the link they hang from (the
/// anchor) and gives the anchor, for each of their capsules, the envelope
/// this file computes. Host side only.
///
/// The chain from the anchor to the capsule's link is a list of steps, each
/// a joint origin (a rigid transform) and a joint: fixed, revolute about its
/// unit axis or prismatic along it, in the child frame as URDF has it. A
/// movable step's position is multiplier * v + offset, where v is one of the
/// stroke variables (an independent joint: multiplier 1, offset 0; a mimic
/// joint: its master's variable with the URDF's multiplier and offset).
///
/// Method: the capsule's two ends are placed at every point of a grid over
/// the variables involved (each range cut into equal steps, both limits
/// included); bounding_capsule() of all those points gives a segment with
/// every sampled end within R0 of it. Between grid points an end moves by
/// at most delta = sum over variables of (step / 2) * sum over the steps it
/// drives of |multiplier| * (1 for prismatic; for revolute, a bound on the
/// end's distance from the joint that holds in every pose: the lengths of
/// the later origins, the later prismatic travels and the end's own
/// distance from its link frame). Distance from a segment is convex, so
/// every point of the capsule in every pose lies within
/// R0 + max(delta_a, delta_b) + radius of the envelope's segment: that is
/// the envelope's radius. It contains the swept capsule as computed; it is
/// not the smallest such capsule.
#ifndef CELLGUARD_HOST_IO_STROKE_ENVELOPE_HPP
#define CELLGUARD_HOST_IO_STROKE_ENVELOPE_HPP

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "cellguard/host/io/io_status.hpp"
#include "cellguard/host/io/urdf_import.hpp"
#include "cellguard/robot/robot_model.hpp"

namespace cellguard::host {

/// Most stroke variables that may move one capsule (a finger and its tip
/// joint are two; a third allows a wrist-mounted slide).
constexpr std::size_t kMaxStrokeVariables = 3U;

/// One joint of the chain from the anchor to the capsule's link.
struct StrokeStep {
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< joint origin in the parent frame
    JointType type = JointType::kFixed;                        ///< fixed, revolute or prismatic
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           ///< movable: unit axis, child frame
    std::size_t variable = 0U;                                 ///< movable: index into the variables
    double multiplier = 1.0;                                   ///< movable: position = multiplier * v + offset
    double offset = 0.0;                                       ///< movable: see multiplier
};

/// The range of one stroke variable (a master joint's limits).
struct StrokeRange {
    double lower = 0.0;  ///< lowest value (rad or m)
    double upper = 0.0;  ///< highest value, >= lower
};

/// What envelope_capsule() made: the envelope and how it was bounded.
struct StrokeEnvelope {
    Capsule capsule{};           ///< in the anchor's frame
    double sample_radius = 0.0;  ///< R0: the sampled ends' largest distance from the segment
    double between = 0.0;        ///< max(delta_a, delta_b): movement between grid points
    std::size_t poses = 0U;      ///< grid points evaluated
};

/// Grid points per variable when @p variables variables move a capsule
/// (1: 1025, 2: 129, 3: 33): at most about 36,000 poses.
[[nodiscard]] std::size_t stroke_samples(std::size_t variables) noexcept;

/// The pose of the link at the end of @p chain (anchor frame) at variable
/// values @p v (indexed as the steps' variable fields).
[[nodiscard]] Eigen::Isometry3d stroke_pose(const std::vector<StrokeStep>& chain, const std::vector<double>& v);

/// The envelope of @p capsule (in the frame of the chain's last link) over
/// every value of @p ranges that the chain's steps use. Errors:
/// kCapacityExceeded when more than kMaxStrokeVariables variables move it;
/// kInvalidArgument for a step's variable outside @p ranges, a range with
/// lower > upper or not finite.
[[nodiscard]] IoStatus envelope_capsule(const std::vector<StrokeStep>& chain, const std::vector<StrokeRange>& ranges,
                                        const Capsule& capsule, StrokeEnvelope& out);

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_STROKE_ENVELOPE_HPP
