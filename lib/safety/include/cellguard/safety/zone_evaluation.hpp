// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file zone_evaluation.hpp
/// Background subtraction and zone evaluation, once per cycle.
///
/// For every voxel of a zone, the frame's fused log-odds and the
/// accessibility prior are added (the independent opinion pool, eq. 6 of the
/// paper used at run time; add_saturating keeps the never-foreground
/// sentinel). A voxel is foreground when the sum is at or above the
/// foreground threshold t_f. A voxel is unseen when no ray observed it this
/// cycle and the prior says it is accessible (prior at or above
/// accessible_min_prior): unknown space that an object could have reached,
/// which is never taken for empty.
///
/// Zone states, most severe first:
/// - FAULT: the zone cannot be evaluated (set by the caller's fault logic,
///   never by this evaluation);
/// - INTRUDED: at least min_foreground_voxels foreground voxels;
/// - UNSEEN: more than max_unseen_voxels unseen voxels (it cannot be called clear);
/// - CLEAR: otherwise.
///
/// With a robot in the cell (robot_mask.hpp), the voxels of this cycle's
/// robot mask are the robot's: neither foreground nor unseen (and never
/// empty space either: speed and separation monitoring measures from the
/// robot's capsules). They are counted per zone as `robot`, for the display.
/// Zones outside the active monitoring case (monitoring_cases.hpp) are not
/// evaluated: CLEAR with zero counts, in no mask.
#ifndef CELLGUARD_ZONE_EVALUATION_HPP
#define CELLGUARD_ZONE_EVALUATION_HPP

#include <cstdint>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard {

/// State of one zone in one cycle. Values appear on CAN: append only.
enum class ZoneState : std::uint8_t {
    kClear = 0,     ///< no foreground, enough of it seen
    kIntruded = 1,  ///< foreground inside
    kUnseen = 2,    ///< too much accessible space inside was not observed
    kFault = 3,     ///< cannot be evaluated
};

/// Static name of a zone state ("CLEAR", "INTRUDED", "UNSEEN", "FAULT").
const char* to_string(ZoneState state) noexcept;

/// Thresholds shared by all zones (per-zone counts are in ZoneConfig).
struct ZoneEvaluationParams {
    /// t_f in log-odds: foreground when frame + prior >= this. Default: the paper's figures' t_f = 0.73.
    std::int16_t foreground_threshold = 255;
    /// Unseen counts only voxels whose prior is at least this (default: P(fore) >= 0.05, i.e. P(acc) >= 0.1).
    std::int16_t accessible_min_prior = -754;
};

/// One zone's result.
struct ZoneReport {
    ZoneState state = ZoneState::kFault;  ///< the zone's state
    std::uint32_t foreground = 0U;        ///< foreground voxels in the zone
    std::uint32_t unseen = 0U;            ///< unseen accessible voxels in the zone
    std::uint32_t robot = 0U;             ///< voxels of the zone that were the robot's (neither of the above)
};

/// All zones' results of one cycle.
struct ZoneEvaluation {
    ZoneReport zones[kMaxZones] = {};   ///< per zone, in configuration order
    std::size_t count = 0U;             ///< number of zones
    std::uint32_t intruded_mask = 0U;   ///< bit z: zone z INTRUDED
    std::uint32_t unseen_mask = 0U;     ///< bit z: zone z UNSEEN
    std::uint32_t not_clear_mask = 0U;  ///< bit z: zone z not CLEAR
    std::uint32_t active_mask = 0U;     ///< bit z: zone z was evaluated (in the active monitoring case)
};

/// What one cycle's zone evaluation leaves out: the zones outside the active
/// monitoring case and the robot's voxels. The default leaves out nothing.
struct ZoneEvaluationScope {
    /// Zones evaluated (bit z: zone z); bits beyond the zone count are ignored.
    std::uint32_t active_zones = 0xFFFFFFFFU;
    /// One byte per voxel, nonzero: the robot's (mark_robot_voxels). Empty: no robot.
    Span<const std::uint8_t> robot_mask{};
};

/// Subtracts @p prior from @p frame and evaluates every zone of @p zones.
/// Work: one pass over the grid plus zones.total_memberships() counter
/// updates. @p subtracted_out, when not empty, receives frame + prior for
/// every voxel (for rendering and tests). Errors: kGeometryMismatch when the
/// zones were compiled for another grid, kStorageTooSmall when prior (or a
/// non-empty subtracted_out) holds fewer values than the grid.
[[nodiscard]] Status evaluate_zones(const EvidenceGrid& frame, Span<const std::int16_t> prior,
                                    const CompiledZones& zones, const ZoneEvaluationParams& params, ZoneEvaluation& out,
                                    Span<std::int16_t> subtracted_out = {}) noexcept;

/// As above, within @p scope: only the zones of scope.active_zones are
/// evaluated, and voxels of a non-empty scope.robot_mask count only as
/// `robot`. Work as above (the mask is read in the same pass). Errors as
/// above, and kStorageTooSmall for a non-empty robot mask shorter than the grid.
[[nodiscard]] Status evaluate_zones(const EvidenceGrid& frame, Span<const std::int16_t> prior,
                                    const CompiledZones& zones, const ZoneEvaluationParams& params,
                                    const ZoneEvaluationScope& scope, ZoneEvaluation& out,
                                    Span<std::int16_t> subtracted_out = {}) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ZONE_EVALUATION_HPP
