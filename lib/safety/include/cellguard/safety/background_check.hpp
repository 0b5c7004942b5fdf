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
/// What it cannot see: a move too small to change depths by more than the
/// tolerance, and a cell so full that the fraction drops without a move
/// (that is a false fault, the safe direction). The fraction and the
/// tolerance are set at commissioning (safety manual, section 6).
#ifndef CELLGUARD_BACKGROUND_CHECK_HPP
#define CELLGUARD_BACKGROUND_CHECK_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/sensor_frame.hpp"

namespace cellguard {

/// A depth sensor's commissioned view of the empty cell and how much of it
/// a live frame must still show.
struct BackgroundReference {
    Span<const float> depth{};        ///< one depth per pixel, row-major; NaN, infinite or <= 0: no reading there
    float tolerance_m = 0.05F;        ///< a pixel matches when |live - reference| <= this (metres, > 0)
    float min_match_fraction = 0.5F;  ///< at least this fraction of the reference's readings must match (0..1]
};

/// The comparison of one live image with its reference.
struct BackgroundMatch {
    std::uint32_t referenced = 0U;  ///< pixels where the reference holds a reading
    std::uint32_t matching = 0U;    ///< of those, pixels whose live reading is within the tolerance
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
/// Errors: kInvalidArgument for a point set, then those above (the size is
/// that of the kind's view; the reading's other fields are not checked).
[[nodiscard]] Result<BackgroundMatch> match_background(const SensorReading& live,
                                                       const BackgroundReference& reference) noexcept;

/// True when @p match shows at least @p min_fraction of the referenced
/// pixels (a reference without any reading never passes: it cannot show
/// that the sensor still sees its cell), and neither does a fraction
/// outside (0, 1]. Passes when matching >= ceil(min_fraction x referenced),
/// with the float @p min_fraction as it is (0.4F is slightly above 0.4).
[[nodiscard]] bool background_seen(const BackgroundMatch& match, float min_fraction) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_BACKGROUND_CHECK_HPP
