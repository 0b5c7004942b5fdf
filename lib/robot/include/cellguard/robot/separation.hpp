// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file separation.hpp
/// Speed and separation monitoring (ISO/TS 15066, 5.5.4): the distance
/// between the robot's capsules and the nearest thing that may be a person,
/// compared with the protective separation distance
///   S_p = v_h (T_r + T_s) + v_r T_r + S_s + C + Z_d + Z_r
/// (v_h human speed, 1.6 m/s per ISO 13855; T_r reaction time; T_s, S_s the
/// robot's stopping time and distance and v_r its speed in its current speed
/// class; C the intrusion distance for the detection capability; Z_d, Z_r
/// the position uncertainties of the sensing and of the robot).
///
/// What may be a person: a foreground voxel anywhere in the grid that is not
/// the robot's, and an unseen voxel (not observed this cycle, accessible by
/// the prior) inside a zone of the active monitoring case, since unknown is
/// never empty; a person hidden from every sensor by the robot is such an
/// unseen voxel near the robot. The foreground distance is the smallest d
/// such that at least min_foreground_voxels foreground voxels lie within d;
/// the hidden distance likewise with min_hidden_voxels unseen voxels (the
/// volume of a person's arm, so isolated unseen voxels behind the arm do not
/// stop the robot). Distances are from voxel centres to capsule surfaces,
/// less half a voxel diagonal (conservative), in millimetres, rounded down.
///
/// The speed request, with the robot's current speed class c (from the
/// command) and d the smaller of both distances:
/// - kProtectiveStop when d < S_p(c);
/// - kReduced when d < S_p(0) + (v_h + v_r(0)) t_slowdown, the distance the
///   robot needs to reach its reduced class before S_p(0) is crossed;
/// - kFull otherwise.
/// Work: one pass over the grid counts each kind's voxels (outside the
/// robot's) and notes which rows hold any (grids of up to 8192 rows); a kind
/// with fewer than k is kDistanceFarMm and drops out of the search, and rows
/// without candidates are not visited again. Then at most one pass over the grid's rows, visited outward from the
/// robot (layers outward from the robot's centre in z, rows outward in y), so
/// near voxels set the distances early. Each kind keeps its k smallest
/// distances in a fixed max-heap (k <= kMaxSeparationVoxelCount; no sort, no
/// histogram); its k-th is its threshold (infinite until k were found). A
/// row whose lower bound (for each capsule, the distance from the row's y-z
/// position to the capsule's segment projected onto the y-z plane, less
/// radius and half diagonal) is not below both kinds' thresholds is skipped
/// unread; in the other rows each voxel within the x extent of the capsules
/// that may count (grown by the threshold) is classified, and a candidate's
/// distance is computed against the capsules whose row bound is below its
/// kind's threshold, with squared distances compared first and one square
/// root for a capsule that may count. The search stops when both kinds have
/// k voxels at distance 0. The result equals the brute-force definition
/// (tested); the work is bounded by voxels x capsules, and in practice by the
/// rows near the robot (bench_cycle prints both cases).
#ifndef CELLGUARD_ROBOT_SEPARATION_HPP
#define CELLGUARD_ROBOT_SEPARATION_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Largest min_foreground_voxels and min_hidden_voxels: the k smallest
/// distances of each kind are kept in a fixed array of this many entries.
constexpr std::uint32_t kMaxSeparationVoxelCount = 64U;

/// A distance that means "nothing within range" (and the saturation value).
constexpr std::uint16_t kDistanceFarMm = 65535U;

/// The limits of one speed class (commissioned from the robot's data sheet).
struct SpeedClassLimits {
    double robot_speed_mps = 0.0;      ///< v_r: the fastest any point of the robot moves in this class
    double stopping_time_s = 0.0;      ///< T_s: from the stop command to standstill
    double stopping_distance_m = 0.0;  ///< S_s: the distance travelled meanwhile
};

/// Parameters of speed and separation monitoring.
struct SeparationParams {
    double human_speed_mps = 1.6;  ///< v_h (ISO 13855)
    double reaction_time_s = 0.0;  ///< T_r: detection to the robot starting to stop (response time + PLC + robot)
    SpeedClassLimits classes[kSpeedClasses] = {};  ///< class 0 is full speed
    std::uint8_t class_count = 1U;                 ///< classes commissioned, 1..kSpeedClasses
    std::uint8_t reduced_class = 0U;               ///< the class a kReduced request asks for (< class_count)
    double slowdown_time_s = 0.0;                  ///< time the robot takes from class 0 to reduced_class
    double intrusion_distance_m = 0.0;             ///< C, from the detection capability (ISO 13855)
    double sensing_uncertainty_m = 0.0;            ///< Z_d
    double robot_uncertainty_m = 0.0;              ///< Z_r
    std::uint32_t min_foreground_voxels = 1U;      ///< foreground voxels that make a distance (>= 1)
    std::uint32_t min_hidden_voxels = 1U;          ///< unseen voxels that make a distance (>= 1)
};

/// Checks @p params: finite, non-negative values; 1..4 classes;
/// reduced_class < class_count; counts 1..kMaxSeparationVoxelCount; S_p of
/// every class and the reduced-speed distance at most 65.534 m (below
/// kDistanceFarMm, so no distance is capped to the far value it is compared
/// with). kInvalidArgument if not (classes at and beyond class_count are not read).
[[nodiscard]] Status check_separation_params(const SeparationParams& params) noexcept;

/// S_p for speed class @p speed_class (< params.class_count, a contract), metres.
[[nodiscard]] double protective_separation_distance(const SeparationParams& params, std::uint8_t speed_class) noexcept;

/// The distance below which kReduced is requested, metres.
[[nodiscard]] double reduced_speed_distance(const SeparationParams& params) noexcept;

/// What the separation check reads of one cycle (all spans one entry per voxel).
struct SeparationInputs {
    Span<const std::int16_t> frame_log_odds{};    ///< the fused frame grid's log-odds
    Span<const std::uint8_t> observed{};          ///< the frame grid's observed flags
    Span<const std::int16_t> prior{};             ///< the accessibility prior
    Span<const std::uint8_t> robot_mask{};        ///< mark_robot_voxels' mask
    Span<const std::uint32_t> zone_membership{};  ///< the compiled zones' membership bits
    std::uint32_t active_zones = 0U;              ///< zone bits of the active monitoring case
    std::int16_t foreground_threshold = 255;      ///< t_f, as zone evaluation uses it
    std::int16_t accessible_min_prior = -754;     ///< as zone evaluation uses it for unseen
};

/// The separation check's result of one cycle.
struct SeparationResult {
    std::uint16_t distance_mm = 0U;                        ///< min(foreground_mm, hidden_mm); kDistanceFarMm: none
    std::uint16_t foreground_mm = 0U;                      ///< foreground distance
    std::uint16_t hidden_mm = 0U;                          ///< hidden (unseen) distance
    std::uint16_t required_mm = 0U;                        ///< S_p of the current speed class, rounded up
    SpeedRequest request = SpeedRequest::kProtectiveStop;  ///< the speed request
    std::uint32_t candidates = 0U;                         ///< voxels whose distance was computed
};

/// Computes the separation of this cycle for a robot in @p pose, moving in
/// speed class @p speed_class. Errors (the result then requests a stop):
/// kStorageTooSmall when a span is shorter than the grid, kInvalidArgument
/// for a class beyond params.class_count.
[[nodiscard]] Status compute_separation(const GridGeometry& grid, const SeparationInputs& in, const RobotPose& pose,
                                        const SeparationParams& params, std::uint8_t speed_class,
                                        SeparationResult& out) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ROBOT_SEPARATION_HPP
