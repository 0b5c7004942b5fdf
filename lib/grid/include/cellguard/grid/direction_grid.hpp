// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file direction_grid.hpp
/// A grid of viewing directions in a sensor's own frame, for sensors that
/// deliver point sets (recorded .pcd clouds, lidars): azimuth x elevation
/// bins of one angular size over a stated field of view. A point set has no
/// pixels, so its commissioned view of the empty cell is kept per bin: the
/// nearest and the farthest range any commissioning point had in that bin
/// (0 where no point fell: "no return"). The changed-background check
/// (background_check.hpp) compares each live point with its bin's view.
///
/// Directions in the sensor frame (x right, y down, z along the axis, as
/// sensor_frame.hpp): azimuth = atan2(x, z) (positive to the right),
/// elevation = atan2(-y, sqrt(x^2 + z^2)) (positive up), both in radians;
/// the range is the point's distance from the sensor, sqrt(x^2 + y^2 + z^2).
/// Bin (a, e) covers azimuth [min + a * bin, min + (a + 1) * bin) and
/// elevation likewise; its index is e * azimuth_bins + a.
#ifndef CELLGUARD_DIRECTION_GRID_HPP
#define CELLGUARD_DIRECTION_GRID_HPP

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/sensor_frame.hpp"

namespace cellguard {

/// Most bins of one direction grid: as many as one sensor has readings
/// (kMaxReadingsPerSensor, 640 x 480; e.g. the whole sphere in 0.5 degree
/// bins, 720 x 360 = 259,200). Views are caller storage of at most this
/// many floats each (farthest, nearest).
constexpr std::size_t kMaxDirectionBins = kMaxReadingsPerSensor;

/// Returned by direction_bin for a point outside the grid or without a range.
constexpr std::size_t kNoDirectionBin = SIZE_MAX;

/// The bins of a point-set sensor's view (see the file comment).
struct DirectionGrid {
    float azimuth_min_rad = 0.0F;       ///< left edge of bin column 0, radians, >= -pi
    float elevation_min_rad = 0.0F;     ///< lower edge of bin row 0, radians, >= -pi/2
    float bin_rad = 0.0F;               ///< width and height of one bin, radians (finite, > 0)
    std::uint32_t azimuth_bins = 0U;    ///< bin columns, >= 1; azimuth_min + columns x bin <= pi
    std::uint32_t elevation_bins = 0U;  ///< bin rows, >= 1; elevation_min + rows x bin <= pi/2

    /// azimuth_bins x elevation_bins (no overflow: both are 32-bit).
    [[nodiscard]] std::size_t bin_count() const noexcept {
        return static_cast<std::size_t>(static_cast<std::uint64_t>(azimuth_bins) * elevation_bins);
    }
};

/// Checks @p grid: finite edges and bin size, bin_rad > 0, at least one bin
/// each way, at most kMaxDirectionBins bins, and the field of view inside
/// azimuth [-pi, pi] and elevation [-pi/2, pi/2] (1e-5 rad slack for the
/// rounding of the edges). Errors: kNonFiniteValue, kInvalidArgument,
/// kCapacityExceeded.
[[nodiscard]] Status check_direction_grid(const DirectionGrid& grid) noexcept;

/// The bin of point @p p (sensor frame) in the checked @p grid, and its
/// range in @p range; kNoDirectionBin when the point lies outside the
/// grid's field of view, and also (with @p range = 0) when it is not
/// finite or at the sensor's origin.
[[nodiscard]] std::size_t direction_bin(const DirectionGrid& grid, const Eigen::Vector3f& p, float& range) noexcept;

/// What add_to_direction_view did with one frame.
struct DirectionViewAdded {
    std::uint32_t binned = 0U;   ///< points that widened or confirmed a bin's view
    std::uint32_t outside = 0U;  ///< points outside the grid's field of view (left out)
    std::uint32_t invalid = 0U;  ///< points not finite or at the origin (left out)
};

/// Adds one commissioning frame's @p points to the view of @p grid:
/// per bin, @p farthest and @p nearest (each grid.bin_count() floats, all
/// 0 before the first frame: no return) widen to hold the point's range.
/// Errors: those of check_direction_grid; kMalformedInput when a span is
/// not bin_count() long.
[[nodiscard]] Result<DirectionViewAdded> add_to_direction_view(Span<const Eigen::Vector3f> points,
                                                               const DirectionGrid& grid, Span<float> farthest,
                                                               Span<float> nearest) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_DIRECTION_GRID_HPP
