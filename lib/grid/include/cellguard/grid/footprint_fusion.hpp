// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file footprint_fusion.hpp
/// Footprint fusion: the fusion path for dense depth cameras. Its work per
/// frame is a function of the configuration alone (the grid, the cameras'
/// poses and image sizes), not of what the cameras see: a fixed pass over
/// the pixels and a fixed pass over the voxels in each camera's view. It
/// writes the opinions of the sensor model (sensor_model.hpp) that
/// fuse_sensor (fusion.hpp) writes, exactly where that is cheap and on the
/// safe side of them elsewhere, then pools them the same way.
///
/// Per sensor and frame:
/// 1. Hit pass, per pixel: the reading is checked and placed exactly as
///    fuse_sensor does (depth_pixel_point, reading_in_cell, the half-open
///    rule), and its voxel gets the hit. The hits are those of the exact
///    path: a reading inside a voxel is never lost. The pass also writes
///    level 0 of the sensor's depth pyramid (depth_pyramid.hpp): a pixel the
///    exact path would skip (NaN, zero, out of range, ...) has no reading.
///    On x86-64 CPUs with AVX2 four pixels at a time (FusionKernel), with
///    the same hits, pyramid and counts as the scalar reference.
/// 2. Voxel pass, per voxel in view: the voxels of each grid row whose
///    bounding sphere lies in front of the image plane and inside the
///    image's sides (one pixel beyond its pixel centres) are visited in
///    order; the span of each row is computed from the geometry alone. A
///    voxel's footprint is the rectangle of pixel centres in the projection
///    of its bounding box in the camera frame (a superset of the pixels
///    whose rays cross it), its depth interval [z_min, z_max] that of its
///    corners along the optical axis. One pyramid query over the footprint
///    decides:
///    - no pixel centre, no valid reading, or every reading nearer than
///      z_min: no opinion. Exact: no ray reaches the voxel.
///    - every reading at least ramp_length beyond z_max, no pixel without a
///      reading, the footprint inside the image, and the voxel resolved (its
///      inner square, see below, holds a pixel centre): the constant free
///      value (p_miss). Exact: a ray crosses the voxel and every ray that
///      does passes it by the ramp.
///    - otherwise, unless it holds a hit, step 3.
/// 3. An undecided voxel without a hit:
///    - exact, per ray, when the rectangle of its eight projected corners
///      has at most params.exact_footprint_max pixels (a function of the
///      geometry, not of the frame): each valid pixel's ray is intersected
///      with the voxel's box (slab test), and the voxel gets the largest
///      free value of the rays that pass it, as fuse_sensor computes it, or
///      no opinion when none passes;
///    - otherwise the safe-side rule: when a valid
///      reading of its inner square (at most 4 x 4 of its pixels probed) lies
///      beyond z_max, a ray provably crosses the voxel and passes it:
///      free_evidence(min - z_max) when every reading of the footprint lies
///      beyond z_max, else the weakest free value free_evidence(0) (the other
///      rays' values are not known); when none is found, no opinion
///      (unknown, never taken for empty).
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
///   of a reading of its footprint, or where its footprint mixes readings
///   nearer and farther than the voxel (a depth edge), or pixels without a
///   reading;
/// - apart from these, float rounding where a ray grazes a voxel edge or a
///   reading lies on a voxel face, as between fuse_sensor and ray_table.hpp.
/// A voxel crossed by the sensor's image plane (a corner at depth <= 1 mm)
/// gets no opinion from it: the camera's own voxel is unknown to itself.
///
/// Footprint tables (FootprintTable): the cameras do not move, so what step 2
/// needs of each voxel in view (the pyramid cells over its footprint, the
/// depths at which a query leaves it without an opinion or fills it, and its
/// inner square for step 3) is made once from the configuration and read
/// every frame; a voxel the table's thresholds leave open is settled as
/// without a table. The opinions are the same bit for bit.
///
/// Work per sensor is at most footprint_work_bound, and equal to it with
/// exact_footprint_max 0: twice the pixels (hit pass and pyramid) and the
/// voxels in view, each visited once in a fixed order with at most one
/// pyramid query and 16 probed pixels, plus the ray tests of step 3, which
/// only undecided voxels take (at most their footprint's pixels). With a
/// TaskRunner and one workspace per sensor, the sensors run as parallel
/// tasks and the pooling in fixed voxel chunks, and 1, 2 or 4 workers give
/// the grid of one core bit for bit.
#ifndef CELLGUARD_FOOTPRINT_FUSION_HPP
#define CELLGUARD_FOOTPRINT_FUSION_HPP

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/base/task_runner.hpp"
#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/grid/sensor_model.hpp"

namespace cellguard {

/// How the hit pass (step 1) runs through a row of pixels and the pooling
/// through the voxels. Every kernel gives the same hits, pyramid, counts and
/// grid bit for bit; the scalar one is the reference. The AVX2 kernel places
/// four pixels at a time with the scalar form's IEEE operations in its order
/// (a group with a reading the short test cannot take, missing, non-finite
/// or near a range limit, goes the scalar way) and pools 16 voxels at a time
/// in 16-bit lanes (a saturating sum, then the clamps: the clamped 32-bit sum).
enum class FusionKernel : std::uint8_t {
    kFastest = 0,  ///< the fastest this CPU and build run: kAvx2 where it can, else kScalar
    kScalar = 1,   ///< one pixel at a time: the reference
    kAvx2 = 2,     ///< four at a time in AVX2 registers (x86-64 CPUs that have AVX2)
};

/// The kernel @p requested runs as here: kAvx2 (and kFastest) need an x86-64
/// CPU with AVX2, else kScalar.
[[nodiscard]] FusionKernel resolve_fusion_kernel(FusionKernel requested) noexcept;

/// The exact step (step 3 of the file comment) and the kernel.
struct FootprintParams {
    /// Largest footprint (pixels of the rectangle of a voxel's eight projected
    /// corners) of an undecided voxel that is evaluated ray by ray. 0 (the
    /// default): none, every undecided voxel takes the safe-side rule and the
    /// work is the same in every frame. 64 gives the exact path's figures on the
    /// paper's experiments, at a cost that grows with the undecided voxels.
    std::uint32_t exact_footprint_max = 0U;
    /// The hit pass's and the pooling's kernel (the same result with each).
    FusionKernel kernel = FusionKernel::kFastest;
};

/// What footprint passes did (for diagnostics, benchmarks and the tests).
struct FootprintStats {
    std::uint64_t pixels = 0U;            ///< pixels of the hit pass (step 1)
    std::uint64_t voxels_visited = 0U;    ///< voxels in view (a pixel centre in the footprint), step 2
    std::uint64_t voxels_filled = 0U;     ///< voxels given the constant free value
    std::uint64_t voxels_exact = 0U;      ///< voxels evaluated ray by ray (step 3)
    std::uint64_t voxels_safe_side = 0U;  ///< voxels decided by the safe-side rule
    std::uint64_t pixel_tests = 0U;       ///< ray-voxel tests of step 3
    std::uint64_t table_makes = 0U;       ///< footprint tables made (not counted as work units)
    /// The work units: 2 x pixels + voxels visited + ray-voxel tests (at most footprint_work_bound, summed).
    [[nodiscard]] std::uint64_t work_units() const noexcept { return 2U * pixels + voxels_visited + pixel_tests; }
    /// Adds another pass's counts.
    void add(const FootprintStats& other) noexcept;
};

/// One voxel in a sensor's view as its footprint table keeps it (32 bytes):
/// step 2's fast decisions, taken from one pyramid query and two float
/// comparisons, and the inner square the safe-side rule probes (step 3).
/// Each threshold is the float for which the comparison with a float
/// reading gives exactly the answer of step 2's double comparison.
struct FootprintEntry {
    PyramidCells cells{};  ///< the pyramid cells over its footprint
    std::uint16_t x = 0U;  ///< the voxel (a grid side is at most kMaxDimension)
    std::uint16_t y = 0U;  ///< the voxel's row
    std::uint16_t z = 0U;  ///< the voxel's layer
    /// The pixel rectangle of its inner square, clipped to the image (an image
    /// side is at most 4096, DepthPyramid::make); u0 > u1 when it holds no pixel centre.
    std::uint16_t square_u0 = 1U;
    std::uint16_t square_v0 = 0U;
    std::uint16_t square_u1 = 0U;
    std::uint16_t square_v1 = 0U;
    /// No opinion when every reading of the footprint is nearer than this.
    float front = 0.0F;
    /// The constant free value when every reading is at least this far and no
    /// pixel lacks one; +inf for a voxel that may not be filled (not resolved,
    /// or its footprint leaves the image).
    float fill = 0.0F;
};

/// Numbers a footprint table is made from: the grid's origin (3), voxel size,
/// dimensions (3), the pose's 3 x 4 matrix (12), intrinsics (4), image size
/// (2) and the model's ramp length.
constexpr std::size_t kFootprintKeySize = 26U;

/// A sensor's footprint table, over caller storage: its voxels in view in the
/// order step 2 visits them, made from the grid, the sensor's pose and
/// intrinsics and the model's ramp length (the configuration, not a frame).
/// Read every frame in place of step 2's projection; a voxel that the fast
/// decisions leave open is projected as without a table, so the opinions
/// are the same bit for bit.
class FootprintTable {
public:
    /// An empty table (footprint fusion then projects every voxel).
    FootprintTable() noexcept = default;
    /// A table over @p storage, not yet made.
    explicit FootprintTable(Span<FootprintEntry> storage) noexcept : storage_(storage) {}

    /// Makes the table for @p grid, the pose, intrinsics and image size of
    /// @p reading (its depths are not read) and @p model's ramp length.
    /// Errors: kInvalidArgument for a point set or an invalid reading,
    /// kStorageTooSmall when the storage holds fewer entries than
    /// footprint_table_entries(); the table is then empty.
    [[nodiscard]] Status make(const GridGeometry& grid, const SensorReading& reading,
                              const SensorModelTable& model) noexcept;
    /// True when made for exactly this grid, the reading's pose, intrinsics and
    /// image size and this model's ramp length.
    [[nodiscard]] bool matches(const GridGeometry& grid, const SensorReading& reading,
                               const SensorModelTable& model) const noexcept;
    /// The entries made last (empty before make()).
    [[nodiscard]] Span<const FootprintEntry> entries() const noexcept { return {storage_.data(), count_}; }
    /// How often make() filled the table (fusion makes it when it does not match).
    [[nodiscard]] std::uint64_t makes() const noexcept { return makes_; }

private:
    Span<FootprintEntry> storage_{};
    std::size_t count_ = 0U;
    std::uint64_t makes_ = 0U;
    bool made_ = false;
    std::array<double, kFootprintKeySize> key_{};  ///< what it was made for (footprint_fusion.cpp's footprint_key)
};

/// Entries of a footprint table for @p reading's geometry over @p grid: its
/// voxels in view (0 for a point set or an empty grid).
[[nodiscard]] std::size_t footprint_table_entries(const GridGeometry& grid, const SensorReading& reading) noexcept;

/// Working memory of one sensor's footprint pass: its pyramid (three spans of
/// depth_pyramid_cells(width, height)) and its opinions (one int16 per voxel).
struct FootprintWorkspace {
    Span<float> pyramid_min{};             ///< min pyramid storage
    Span<float> pyramid_max{};             ///< max pyramid storage
    Span<std::uint8_t> pyramid_invalid{};  ///< invalid-flag pyramid storage
    Span<std::int16_t> opinions{};         ///< the sensor's opinion per voxel (kNoOpinion: none)
    /// The sensor's table, or none (every voxel projected each frame). Made
    /// on first use, and again whenever it does not match the reading; with
    /// fewer workspaces than sensors, fuse_frame_footprint uses no table.
    FootprintTable* table = nullptr;
};

/// One sensor's work units in a frame: 2 x its pixels (hit pass, pyramid)
/// + the voxels of @p grid in its view (step 2) + the pixels of the exact
/// step's footprints if every voxel in view with a footprint of at most
/// params.exact_footprint_max pixels were undecided (step 3). A function of
/// the grid and the reading's pose, intrinsics and image size alone; 0 for a
/// point set or an empty grid. With exact_footprint_max 0 the work
/// footprint_opinions does is exactly this in every frame.
[[nodiscard]] std::uint64_t footprint_work_bound(const GridGeometry& grid, const SensorReading& reading,
                                                 const FootprintParams& params = FootprintParams{}) noexcept;

/// One sensor's opinions (steps 1 and 2) into @p work.opinions, which is
/// overwritten. The reading must be a depth image (either kind). Errors:
/// those of validate_sensor_reading, kInvalidArgument for a point set,
/// kStorageTooSmall for short workspace spans. On error the opinions are
/// unspecified and @p stats untouched.
[[nodiscard]] Result<FusionStats> footprint_opinions(const GridGeometry& grid, const SensorReading& reading,
                                                     const SensorModelTable& model, const FootprintWorkspace& work,
                                                     FootprintStats* stats,
                                                     const FootprintParams& params = FootprintParams{}) noexcept;

/// Fuses every sensor of one frame into @p grid by footprint fusion. With at
/// least as many @p workspaces as sensors, each sensor's pass is one task of
/// @p runner and the pooling runs in fixed voxel chunks; with fewer, the
/// sensors run one after another through workspaces[0]. The result is the
/// same either way. All readings are checked before any evidence is added:
/// on error (kCapacityExceeded for more than kMaxSensors, kStorageTooSmall,
/// a sensor's own error) the grid is untouched. @p stats, when given, gets
/// the sum of the sensors' footprint counts.
[[nodiscard]] Result<FusionStats> fuse_frame_footprint(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                                       const SensorModelTable& model,
                                                       Span<const FootprintWorkspace> workspaces, TaskRunner& runner,
                                                       FootprintStats* stats = nullptr,
                                                       const FootprintParams& params = FootprintParams{}) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_FOOTPRINT_FUSION_HPP
