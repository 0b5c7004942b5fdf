// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file background_check.hpp
/// Does a depth sensor still see the cell it was commissioned on? At
/// commissioning each static depth sensor's view of the empty cell is kept
/// as a reference depth image. Every cycle the live image is compared with
/// it pixel by pixel: a pixel matches when both hold a reading and they
/// differ by at most the tolerance. People and objects in front of the
/// background lower the match; a sensor that was bumped, turned or
/// re-mounted lowers it for most pixels at once, and so does a covered or
/// blinded lens. Below the configured fraction the frame is refused
/// (kFrameInconsistent in the controller), so a moved sensor's rays are not
/// fused into the wrong voxels (hazard H-SEN-3).
///
/// A changed background (hazard H-PRI-3): people and objects in front of
/// the background can only make depths shorter, or take readings away. A
/// pixel whose live depth is LONGER than its reference by more than the
/// tolerance sees through where something stood (a background object moved
/// or removed) or past an edge (a moved or tilted sensor). More than
/// max_longer_pixels such pixels in changed_cycles frames in a row mean the
/// prior no longer describes the cell: the controller latches
/// kPriorCheckFailed until restart.
///
/// What it cannot see: a move too small to change depths by more than the
/// tolerance, a change only in pixels that something in front covers, and a
/// cell so full that the fraction drops without a move (that is a false
/// fault, the safe direction). The fraction, the tolerance and the pixel
/// count are set at commissioning (safety manual, section 6).
#ifndef CELLGUARD_BACKGROUND_CHECK_HPP
#define CELLGUARD_BACKGROUND_CHECK_HPP

#include <array>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/direction_grid.hpp"
#include "cellguard/grid/sensor_frame.hpp"

namespace cellguard {

/// A sensor's commissioned view of the empty cell and how much of it a live
/// frame must still show. A depth-image sensor's view is one depth per
/// pixel; a point-set sensor's is per bin of @ref grid (direction_grid.hpp):
/// the farthest range in @ref depth, the nearest in @ref nearest.
struct BackgroundReference {
    Span<const float> depth{};  ///< one depth per pixel, row-major; NaN, infinite or <= 0: no reading there
    /// Point sets only: the direction bins of @ref depth (the farthest
    /// commissioning range per bin, <= 0: no return there) and @ref nearest.
    DirectionGrid grid{};
    Span<const float> nearest{};      ///< point sets only: the nearest commissioning range per bin
    float tolerance_m = 0.05F;        ///< a pixel matches when |live - reference| <= this (metres, > 0)
    float min_match_fraction = 0.5F;  ///< at least this fraction of the reference's readings must match (0..1]
    /// A frame with more pixels than this whose live depth exceeds the
    /// reference by more than tolerance_m shows a changed background.
    std::uint32_t max_longer_pixels = 20U;
    /// That many frames in a row showing a changed background latch the
    /// fault (>= 1; 0 turns the changed-background check off).
    std::uint32_t changed_cycles = 3U;
};

/// The comparison of one live image with its reference.
struct BackgroundMatch {
    std::uint32_t referenced = 0U;  ///< pixels where the reference holds a reading
    std::uint32_t matching = 0U;    ///< of those, pixels whose live reading is within the tolerance
    std::uint32_t longer = 0U;      ///< of those, pixels whose live reading is beyond reference + tolerance
    std::uint32_t outside = 0U;     ///< point sets: points outside the grid's field of view (not compared)
};

/// Compares @p live with @p reference pixel by pixel. Errors:
/// kMalformedInput when the sizes differ, kInvalidArgument for a tolerance
/// that is not finite and positive.
[[nodiscard]] Result<BackgroundMatch> match_background(Span<const float> live,
                                                       const BackgroundReference& reference) noexcept;

/// Compares the depth image @p live, of either kind, with @p reference as
/// the function above does, reading its depths in place through
/// depth_value (a kDepthImageU16 raw 0, NaN, is no reading): a uint16
/// image and the float image of the same depth_value()s match alike.
/// A point set (kPointSet) is compared per point with its direction bin
/// (match_points). Errors: those of match_points for a point set;
/// kInvalidArgument for a depth image against a point-set view (nearest
/// not empty); then
/// those above (the size is that of the kind's view; the reading's other
/// fields are not checked).
[[nodiscard]] Result<BackgroundMatch> match_background(const SensorReading& live,
                                                       const BackgroundReference& reference) noexcept;

/// Compares the live point set @p points (sensor frame) with the
/// direction-grid view in @p reference, point by point: a point whose bin
/// holds a return (farthest > 0) is referenced; it matches when its range
/// lies within [nearest - tolerance, farthest + tolerance] and is longer
/// when it exceeds farthest + tolerance (seen through where something
/// stood, or past an edge of a turned sensor), the same rule as a pixel.
/// Points in bins without a return never count; points outside the grid's
/// field of view are counted in `outside` only; points not finite or at
/// the origin are left out. Errors: those of check_direction_grid for
/// reference.grid, kMalformedInput when depth or nearest is not
/// grid.bin_count() long, kInvalidArgument for a tolerance that is not
/// finite and positive.
[[nodiscard]] Result<BackgroundMatch> match_points(Span<const Eigen::Vector3f> points,
                                                   const BackgroundReference& reference) noexcept;

/// True when @p match shows at least @p min_fraction of the referenced
/// pixels (a reference without any reading never passes: it cannot show
/// that the sensor still sees its cell), and neither does a fraction
/// outside (0, 1]. Passes when matching >= ceil(min_fraction x referenced),
/// with the float @p min_fraction as it is (0.4F is slightly above 0.4).
[[nodiscard]] bool background_seen(const BackgroundMatch& match, float min_fraction) noexcept;

/// True when @p match shows more than @p max_longer_pixels pixels seen
/// beyond their reference: the background changed, or the sensor moved.
[[nodiscard]] constexpr bool background_changed(const BackgroundMatch& match,
                                                std::uint32_t max_longer_pixels) noexcept {
    return match.longer > max_longer_pixels;
}

/// The changed-background check of up to kMaxSensors sensor slots (the
/// controller keeps one): per slot the run of frames in a row that showed a
/// change, and the latch.
struct BackgroundChangeTracker {
    std::array<BackgroundMatch, kMaxSensors> last{};  ///< per slot: its last comparison (zeros before the first)
    std::array<std::uint32_t, kMaxSensors> streak{};  ///< per slot: frames in a row showing a change (saturating)
    std::uint32_t latched = 0U;                       ///< bit i: slot i latched; never cleared

    /// Records @p match of slot @p slot (>= kMaxSensors: ignored): a frame
    /// with background_changed(match, reference.max_longer_pixels) extends
    /// the slot's run, any other ends it; a run of reference.changed_cycles
    /// (> 0; 0 turns the check off) latches the slot for good.
    void track(std::size_t slot, const BackgroundMatch& match, const BackgroundReference& reference) noexcept;
};

}  // namespace cellguard

#endif  // CELLGUARD_BACKGROUND_CHECK_HPP
