// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file depth_conditioning.hpp
/// The depth filter: what a time-of-flight camera's own filters do to its
/// depth image, applied before the monitor fuses it when the configuration's
/// [depth_filter] turns it on (filtered_frame_source.hpp), and by the
/// detection experiment (detection.hpp), which measures what it costs in
/// detection capability. Every filter is off by default and changes nothing then.
///
/// - Edge filter (flying pixels): a reading that differs from a reading up
///   to edge_radius pixels away along its row or column (1: its 4-neighbours) by more than max(edge_jump_min_m, edge_jump_per_m
///   x its depth) is dropped (reads 0, no reading). A pixel that mixes a
///   foreground edge with what lies behind it lies between both, so it
///   differs from both sides; the silhouette of every object shrinks by about
///   a pixel on each side.
/// - Background tolerance: a reading within background_tolerance_per_m x
///   the empty cell's depth of its pixel of that depth (nearer or deeper)
///   reads the empty cell's depth; one deeper than that stays (the
///   changed-background check must still see it). Range noise on the background then adds no reading
///   in front of it; an object thinner than the tolerance (along the ray) in
///   front of a background surface is not seen, which the experiment measures
///   as detection capability on that surface.
/// - Speckle filter: after both, a reading nearer than the empty cell's
///   depth (not put onto it) with fewer than speckle_min_neighbours of its
///   8 neighbours nearer than the empty cell too is dropped: an isolated reading in front of the background (a range
///   noise tail beyond the tolerance) makes no foreground; an object of a few
///   pixels across keeps its inner readings.
/// Depths are along the optical axis (z), as the images hold them; 0 or
/// non-finite: no reading (a pixel of the empty cell without one has no
/// tolerance applied).
#ifndef CELLGUARD_HOST_CELL_DEPTH_CONDITIONING_HPP
#define CELLGUARD_HOST_CELL_DEPTH_CONDITIONING_HPP

#include <cstdint>

#include "cellguard/base/span.hpp"

namespace cellguard::cell {

/// The two filters' settings (both off by default).
struct DepthConditioning {
    double edge_jump_per_m = 0.0;             ///< edge filter: per metre of depth; 0 with edge_jump_min_m 0: off
    double edge_jump_min_m = 0.0;             ///< edge filter: the smallest jump that drops a reading, metres
    int edge_radius = 1;                      ///< edge filter: pixels compared up to this far along rows and columns
    double background_tolerance_per_m = 0.0;  ///< background tolerance per metre of the empty cell's depth; 0: off
    int speckle_min_neighbours = 0;           ///< speckle filter (needs a background): 1..8; 0: off
    /// True when a filter is on.
    [[nodiscard]] bool on() const noexcept {
        return edge_jump_per_m > 0.0 || edge_jump_min_m > 0.0 || background_tolerance_per_m > 0.0 ||
               speckle_min_neighbours > 0;
    }
};

/// What condition_depth changed.
struct ConditioningCounts {
    std::uint64_t dropped = 0U;   ///< readings dropped by the edge filter
    std::uint64_t snapped = 0U;   ///< readings set to the empty cell's depth
    std::uint64_t speckles = 0U;  ///< readings dropped by the speckle filter
};

/// Applies @p c to the @p width x @p height image @p depth in place (the edge
/// filter first, on the image as given, then the background tolerance
/// against @p background, the empty cell's image of the same size, then the
/// speckle filter; empty @p background: neither of the last two). @p scratch holds at least width x height
/// values. False, with nothing changed, when a size does not fit. Allocates nothing.
[[nodiscard]] bool condition_depth(Span<float> depth, Span<const float> background, Span<float> scratch,
                                   std::int32_t width, std::int32_t height, const DepthConditioning& c,
                                   ConditioningCounts* counts = nullptr) noexcept;

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_DEPTH_CONDITIONING_HPP
