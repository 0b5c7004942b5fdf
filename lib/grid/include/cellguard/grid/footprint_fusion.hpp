// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file footprint_fusion.hpp
/// Footprint fusion: the fusion path for dense depth cameras, whose cost grows
/// with voxels x sensors instead of rays x voxels per ray. It writes the
/// opinions of the sensor model (sensor_model.hpp) that fuse_sensor
/// (fusion.hpp) writes, exactly where that is cheap and on the safe side of
/// them where it approximates, then pools them the same way.
///
/// Per sensor and frame:
/// 1. Hit pass, per pixel: the reading is checked and placed exactly as
///    fuse_sensor does (depth_pixel_point, reading_in_cell, the half-open
///    rule), and its voxel gets the hit. The hits are those of the exact
///    path: a reading inside a voxel is never lost. The pass also writes
///    level 0 of the sensor's depth pyramid (depth_pyramid.hpp): a pixel the
///    exact path would skip (NaN, zero, out of range, ...) has no reading.
/// 2. Box pass: the grid is split recursively into boxes (halving every axis
///    longer than one voxel). A box's footprint is the rectangle of pixel
///    centres in the bounding box of its eight projected corners (a ray that
///    crosses the box has its pixel there), its depth interval [z_min, z_max]
///    that of its corners along the optical axis. One pyramid query over the
///    footprint decides:
///    - behind the camera, no pixel centre, no valid reading, or every
///      reading nearer than z_min: no opinion for the whole box. Exact: no
///      ray reaches the box.
///    - every reading at least ramp_length beyond z_max, no pixel without a
///      reading, the box inside the image, and every voxel of it resolved
///      (each voxel's inner square, see below, holds a pixel centre): each
///      voxel of the box gets the constant free value (p_miss). Exact: a ray
///      crosses each voxel and every ray that does passes it by the ramp.
///    - otherwise the box is split; a single voxel goes to step 3.
/// 3. A voxel the box pass could not decide (mixed footprint, readings
///    missing, at the image border) and that holds no hit:
///    - exact, per ray, when its footprint has at most exact_footprint_max
///      pixels and the sensor's exact_pixel_budget is not spent: each valid
///      pixel's ray is intersected with the voxel's box (slab test), and the
///      voxel gets the largest free value of the rays that pass it, as
///      fuse_sensor computes it (free_evidence of the distance from where the
///      ray leaves the voxel to its reading), or no opinion when none passes;
///    - otherwise on the safe side: when a valid reading of its inner square
///      (at most 4 x 4 of its pixels probed) lies beyond z_max, a ray provably
///      crosses the voxel and passes it: free_evidence(min - z_max) when every
///      reading of the footprint lies beyond z_max, else the weakest free
///      value free_evidence(0) (the other rays' values are not known); when
///      none is found, no opinion (unknown, never taken for empty).
///    The inner square is the square of half-width (s / 2) / (D * c) pixels
///    around the projected voxel centre (s: voxel size, D: distance from the
///    camera to the centre, c = sqrt(1/fx^2 + 1/fy^2)): every pixel ray
///    through it passes within s / 2 of the centre, i.e. through the voxel's
///    inscribed sphere.
///
/// So, against fuse_sensor on the same frame, per sensor and voxel:
/// - the hits are the same;
/// - a voxel with no opinion here has none there or a free one there (never a
///   hit);
/// - a free value here is the exact one or weaker (nearer 0.5), and is one
///   only where a ray of the sensor provably passes the voxel; it differs
///   from the exact value only within ramp_length + the voxel's depth extent
///   of a reading of its footprint, and by at most |free_evidence(0) -
///   constant_free_evidence()| log-odds units;
/// - apart from these, float rounding where a ray grazes a voxel edge or a
///   reading lies on a voxel face, as between fuse_sensor and ray_table.hpp.
/// A voxel crossed by the sensor's image plane (a corner at depth <= 1 mm)
/// gets no opinion from it: the camera's own voxel is unknown to itself.
///
/// Work per sensor is bounded by footprint_work_bound: the pixels (hit pass
/// and pyramid), the boxes of the full subdivision (footprint_box_count),
/// and the exact budget. The order of every step is fixed, so the result
/// does not depend on the runner: with a TaskRunner and one workspace per
/// sensor, the sensors run as parallel tasks and the pooling in fixed voxel
/// chunks, and 1, 2 or 4 workers give the grid of one core bit for bit.
#ifndef CELLGUARD_FOOTPRINT_FUSION_HPP
#define CELLGUARD_FOOTPRINT_FUSION_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/task_runner.hpp"
#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/grid/sensor_model.hpp"

namespace cellguard {

/// Limits of the exact per-ray step (step 3 of the file comment).
struct FootprintParams {
    /// Largest footprint (pixels) of a voxel that is evaluated ray by ray.
    std::uint32_t exact_footprint_max = 64U;
    /// Most ray-voxel tests per sensor and frame in step 3; beyond it every
    /// undecided voxel takes the safe-side rule. Bounds the worst case.
    std::uint32_t exact_pixel_budget = 400000U;
};

/// What one sensor's footprint pass did (for diagnostics, benchmarks and the tests).
struct FootprintStats {
    std::uint64_t boxes = 0U;             ///< boxes classified (step 2), single voxels included
    std::uint64_t voxels_filled = 0U;     ///< voxels given a free value by a whole box
    std::uint64_t voxels_exact = 0U;      ///< voxels evaluated ray by ray (step 3)
    std::uint64_t voxels_safe_side = 0U;  ///< voxels decided by the safe-side rule (step 3)
    std::uint64_t pixel_tests = 0U;       ///< ray-voxel tests of step 3
    /// Adds another pass's counts.
    void add(const FootprintStats& other) noexcept;
};

/// Working memory of one sensor's footprint pass: its pyramid (three spans of
/// depth_pyramid_cells(width, height)) and its opinions (one int16 per voxel).
struct FootprintWorkspace {
    Span<float> pyramid_min{};             ///< min pyramid storage
    Span<float> pyramid_max{};             ///< max pyramid storage
    Span<std::uint8_t> pyramid_invalid{};  ///< invalid-flag pyramid storage
    Span<std::int16_t> opinions{};         ///< the sensor's opinion per voxel (kNoOpinion: none)
};

/// Boxes of the full recursive subdivision of @p grid (step 2's most boxes per sensor).
[[nodiscard]] std::uint64_t footprint_box_count(const GridGeometry& grid) noexcept;

/// Bound on one sensor's work units in a frame: 2 x its pixels (hit pass,
/// pyramid) + footprint_box_count + params.exact_pixel_budget +
/// exact_footprint_max (the last voxel may start below the budget).
[[nodiscard]] std::uint64_t footprint_work_bound(const GridGeometry& grid, std::uint64_t pixels,
                                                 const FootprintParams& params) noexcept;

/// One sensor's opinions (steps 1 to 3) into @p work.opinions, which is
/// overwritten. The reading must be a depth image (either kind). Errors:
/// those of validate_sensor_reading, kInvalidArgument for a point set,
/// kStorageTooSmall for short workspace spans. On error the opinions are
/// unspecified and @p stats untouched.
[[nodiscard]] Result<FusionStats> footprint_opinions(const GridGeometry& grid, const SensorReading& reading,
                                                     const SensorModelTable& model, const FootprintParams& params,
                                                     const FootprintWorkspace& work, FootprintStats* stats) noexcept;

/// Fuses every sensor of one frame into @p grid by footprint fusion. With at
/// least as many @p workspaces as sensors, each sensor's pass is one task of
/// @p runner and the pooling runs in fixed voxel chunks; with fewer, the
/// sensors run one after another through workspaces[0]. The result is the
/// same either way. All readings are checked before any evidence is added:
/// on error (kCapacityExceeded for more than kMaxSensors, kStorageTooSmall,
/// a sensor's own error) the grid is untouched. @p stats, when given, gets
/// the sum of the sensors' footprint counts.
[[nodiscard]] Result<FusionStats> fuse_frame_footprint(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                                       const SensorModelTable& model, const FootprintParams& params,
                                                       Span<const FootprintWorkspace> workspaces, TaskRunner& runner,
                                                       FootprintStats* stats = nullptr) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_FOOTPRINT_FUSION_HPP
