// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file ray_table.hpp
/// Precomputed rays of a static depth sensor: the fast fusion path.
///
/// Sensors in a workcell do not move. At commissioning, each pixel's ray is
/// traversed once from the sensor origin to the sensor's max_range, and its
/// voxels are stored in order, each with the distance at which the ray leaves
/// it (an entry: 4 bytes in a compact table, see ray_table_is_compact; 8
/// bytes otherwise). A
/// frame then finds, per pixel, how far along its list the reading lies; no
/// traversal set-up and no floating point per voxel.
///
/// How a frame is fused (RayTable::fuse):
/// - Pass 1, per pixel: a ray's voxels up to its reading are a prefix of its
///   pixel's list; the pass finds where the prefix ends (`pixel_walked`).
///   A walked voxel's opinion (`sensor_opinion`, set to the model's constant
///   free evidence first) is raised to a ramp value or to the hit when a
///   ray's ramp or reading lies in it: the largest opinion wins, as in
///   fuse_sensor (fusion.hpp). Finding where the constant part ends
///   costs nothing when the reading lies at least one ramp beyond where the
///   ray leaves the grid; otherwise it is a search of the pixel's entries.
///   In a compact table the search compares integer exit steps: a
///   reading's distance times the power-of-two steps per metre, truncated,
///   is exactly the last step count at or before it. On x86-64 a compact
///   pixel compares a window of 32 keys at once (SSE2), window after
///   window; elsewhere, and for wide tables, a branch-free binary search
///   runs a step at a time over 16 pixels together so that their chains of
///   dependent loads overlap.
/// - Pass 2 counts the walks per voxel (`hit_count`): it counts the walked
///   entries, or, when more than half of the table was walked, starts from
///   the table's full counts (`full_hits`, made by build()) and takes off
///   the entries not walked. The entries of successive pixels are walked as
///   one run where they continue one another. So the counting visits at
///   most half of the table's entries in any frame, and none when every
///   reading lies in its ray's last voxel or beyond the grid.
/// - The working memory is set, and pass 3 visits, only the voxels some ray
///   of the table crosses (`crossed_voxels`, listed by build()): in a grid
///   much larger than the sensor's view the passes do not scale with it.
/// - Pass 3 pools the opinion of each voxel that some walk reached into the
///   grid (SensorModelTable::pool) and sets its observed flag: one opinion
///   per voxel and frame, whatever the number of rays.
///
/// Equivalence with fuse_sensor (fusion.hpp): the same voxels get the same
/// opinion, except where a reading lies within float rounding of a voxel
/// face (the table puts a reading exactly on a face in the voxel the ray
/// enters next; fuse_sensor uses the half-open rule of grid.hpp) or where a
/// ray grazes a voxel edge (the table's ray is the pixel's exact direction,
/// fuse_sensor's ray ends at the float reading; a compact table rounds exit
/// distances to its exit step, 0.12 mm in the paper's cell). Neither path
/// depends on the order of the pixels. The unit tests bound how many voxels
/// differ from fuse_sensor on the simulated workcell and on the real frames.
///
/// Storage is the caller's: `count_ray_steps` sizes it, `RayTable::build`
/// fills it. The table is valid only for the pose, intrinsics, grid and
/// max_range it was built for; `RayTable::fuse` checks the image size.
#ifndef CELLGUARD_RAY_TABLE_HPP
#define CELLGUARD_RAY_TABLE_HPP

#include <array>
#include <cstdint>

#include "cellguard/base/ram_check.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/grid/sensor_model.hpp"

namespace cellguard {

/// What the ray table needs to place a reading near a voxel face by
/// fuse_sensor's own rule (fusion.hpp: depth_pixel_point, reading_in_cell,
/// then the half-open rule of grid.hpp); set by RayTable::build.
struct ReadingPlacement {
    GridGeometry grid{};                                     ///< the table's grid
    PinholeIntrinsics intrinsics{};                          ///< the sensor's intrinsics
    double inv_fx = 0.0;                                     ///< 1 / fx, as fuse_sensor computes it
    double inv_fy = 0.0;                                     ///< 1 / fy, likewise
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> cell
};

/// A table entry is a voxel and where the ray leaves it. A compact table
/// stores it in 4 bytes, as two arrays: a 16-bit voxel index and a 16-bit
/// exit distance from the sensor origin in exit steps (rounded to nearest).
/// The exit step is a power of two metres (compact_exit_step), so the
/// distance is exact in float and a reading's position converts to steps
/// exactly. A wide table stores a 32-bit voxel index and a float exit
/// distance in metres (8 bytes).

/// Grids of at most this many voxels can have compact tables (4 bytes per
/// entry, half the memory traffic of a wide table).
constexpr std::size_t kCompactRayTableVoxels = 65536U;

/// A compact table's exit step may be at most this fraction of a voxel's
/// edge (1/256: 0.2 mm in the paper's 5 cm grid); a coarser step would move
/// readings near a voxel face into the neighbouring voxel too often.
constexpr double kCompactStepsPerVoxelEdge = 256.0;

/// The exit step of a compact table for @p sensor in @p grid, metres: the
/// smallest power of two whose 65535 steps reach the farthest point where a
/// ray can leave the grid (min(max_range, the farthest grid corner)), or 0
/// when @p sensor fails validate_sensor_reading.
[[nodiscard]] float compact_exit_step(const GridGeometry& grid, const SensorReading& sensor) noexcept;

/// True when a table for @p sensor in @p grid is compact: at most
/// kCompactRayTableVoxels voxels and an exit step of at most
/// voxel_size / kCompactStepsPerVoxelEdge. Otherwise it is wide.
[[nodiscard]] bool ray_table_is_compact(const GridGeometry& grid, const SensorReading& sensor) noexcept;

/// Caller storage of a ray table: every pixel's entries, per pixel the
/// offset of its first entry and where its ray enters and leaves the grid,
/// per voxel how many rays cross it, and the working memory of fuse().
/// Either the two `compact_` spans or the two `wide_` spans are used (see
/// ray_table_is_compact); the others may be empty. The working memory
/// (`pixel_walked`, `hit_count`, `sensor_opinion`) may be shared by tables
/// that are fused one after another: fuse() sets it first.
struct RayTableStorage {
    Span<std::uint16_t> compact_voxels{};      ///< count_ray_steps(...) entries if compact: voxel indices
    Span<std::uint16_t> compact_exit_steps{};  ///< count_ray_steps(...) entries if compact: exit distances in steps
    Span<std::uint32_t> wide_voxels{};         ///< count_ray_steps(...) entries if wide: voxel indices
    Span<float> wide_exits{};                  ///< count_ray_steps(...) entries if wide: exit distances, metres
    Span<std::uint32_t> pixel_begin{};         ///< width * height + 1 entries: offset of each pixel's first entry
    Span<float> pixel_enter{};        ///< width * height entries: where the ray enters the grid (+inf: it misses)
    Span<float> pixel_exit{};         ///< width * height entries: where the ray leaves the grid (+inf: it misses)
    Span<float> pixel_norm{};         ///< width * height entries: |((u-cx)/fx, (v-cy)/fy, 1)|
    Span<std::uint32_t> full_hits{};  ///< grid.voxel_count() entries: how many of the table's rays cross each voxel
    Span<std::uint32_t> crossed_voxels{};  ///< grid.voxel_count() entries: build lists the voxels any ray crosses
    Span<std::uint32_t> pixel_walked{};    ///< width * height entries: working memory, where each pixel's walk ends
    Span<std::uint32_t> hit_count{};       ///< grid.voxel_count() entries: working memory, rays per voxel
    Span<std::int16_t>
        sensor_opinion{};  ///< grid.voxel_count() entries: working memory, the sensor's opinion per voxel
};

/// Number of entries (the length of each entry span) the table of this sensor
/// needs in this grid: the sum over pixels of the voxels each ray crosses.
/// The sensor description is checked as by validate_sensor_reading (the
/// depth view itself is not used). Errors: those of validate_sensor_reading;
/// kInvalidArgument unless the sensor is a depth image.
[[nodiscard]] Result<std::size_t> count_ray_steps(const GridGeometry& grid, const SensorReading& sensor,
                                                  Rasterization rasterization = Rasterization::kExact) noexcept;

/// Regions of a ray table's constant RAM, in the order a signature check
/// reads them (RayTable::signature_regions).
constexpr std::size_t kRayTableSignatureRegions = 9U;
static_assert(kRayTableSignatureRegions <= kMaxSignatureRegions, "a SignatureCheck must hold a ray table's regions");

/// A ray table's constant RAM as a SignatureCheck reads it: its limits as
/// words, then its arrays (RayTable::signature_regions).
using RayTableSignatureRegions = std::array<SignatureRegion, kRayTableSignatureRegions>;

/// The precomputed rays of one depth sensor.
///
/// fuse() writes the table's working memory: a table (or tables sharing
/// working memory) must not be fused from two threads at once (the cycle
/// executive fuses one sensor at a time).
///
/// Everything else of the table is constant after build(): the entries, the
/// per-pixel arrays, full_hits, the crossed voxels and the table's own
/// limits, which build() also stores as words. signature_regions() lists
/// that RAM and build() takes its CRC-32 (storage_crc), so a SignatureCheck
/// made from the two (ram_check.hpp) re-reads it a slice at a time and
/// reports a bit that flips in it by the end of the first whole pass after
/// the flip: within 2 x ceil(checked_bytes() / slice bytes) steps.
/// limits_intact() covers the table object itself: the limits fuse() uses
/// against the stored words.
class RayTable {
public:
    /// An empty table (placeholder only; fuse() refuses it).
    RayTable() noexcept = default;

    /// Traverses every pixel's ray to sensor.max_range and stores it.
    /// Errors: those of validate_sensor_reading; kInvalidArgument unless the
    /// sensor is a depth image; kStorageTooSmall when a span is too small;
    /// kCapacityExceeded above 2^32 - 1 voxel entries.
    static Result<RayTable> build(const GridGeometry& grid, const SensorReading& sensor, RayTableStorage storage,
                                  Rasterization rasterization = Rasterization::kExact) noexcept;

    /// Fuses one depth image of this sensor into @p grid (same geometry as
    /// built for). Readings are classified and counted as by fuse_sensor;
    /// `voxel_updates` counts the same (voxel, ray) visits as fuse_sensor.
    /// Errors: kGeometryMismatch, kMalformedInput when the image size
    /// differs, kInvalidArgument for an empty table. On error the grid is
    /// untouched.
    [[nodiscard]] Result<FusionStats> fuse(EvidenceGrid& grid, Span<const float> depth,
                                           const SensorModelTable& model) const noexcept;

    /// Fuses @p reading, a depth image of this sensor of either kind, as
    /// fuse() above: its depths are read in place through depth_value
    /// (a kDepthImageU16 image is not converted to floats first; its raw 0
    /// counts as skipped_nan), so a uint16 image and the float image of the
    /// same depth_value()s give the same grid and the same counts. The
    /// table's own pose, intrinsics and ranges are used, not the reading's.
    /// Errors: those of validate_sensor_reading, kInvalidArgument for a
    /// point set, then those of fuse() above.
    [[nodiscard]] Result<FusionStats> fuse(EvidenceGrid& grid, const SensorReading& reading,
                                           const SensorModelTable& model) const noexcept;

    /// Number of stored entries.
    [[nodiscard]] std::size_t step_count() const noexcept { return step_count_; }
    /// Pixels of the sensor.
    [[nodiscard]] std::size_t pixel_count() const noexcept { return pixels_; }
    /// Offset of pixel @p pixel's first entry; pixel_count() gives the end.
    [[nodiscard]] std::uint32_t pixel_begin(std::size_t pixel) const noexcept { return storage_.pixel_begin.at(pixel); }
    /// Where pixel @p pixel's ray enters the grid, metres (+inf: it misses).
    [[nodiscard]] float pixel_enter(std::size_t pixel) const noexcept { return storage_.pixel_enter.at(pixel); }
    /// Pixel @p pixel's norm factor: range = depth x norm.
    [[nodiscard]] float pixel_norm(std::size_t pixel) const noexcept { return storage_.pixel_norm.at(pixel); }
    /// Voxel of entry @p entry.
    [[nodiscard]] std::uint32_t entry_voxel(std::size_t entry) const noexcept;
    /// Exit distance of entry @p entry of pixel @p pixel, metres, as fuse()
    /// compares it (for a compact table: the stored steps turned back).
    [[nodiscard]] float entry_exit(std::size_t pixel, std::size_t entry) const noexcept;

    /// CRC-32 of the table's constant RAM (signature_regions(), read in
    /// order), taken by build(): the reference of the table's SignatureCheck.
    [[nodiscard]] std::uint32_t storage_crc() const noexcept { return storage_crc_; }
    /// The table's constant RAM in the order a check reads it: the limits'
    /// words that build() stored (a view into this object: a copy's regions
    /// view the copy's words), both entry
    /// arrays, pixel_begin, pixel_enter, pixel_exit, pixel_norm, full_hits
    /// and the crossed voxels, each as far as the table uses it. The working
    /// memory is not included: fuse() writes it. All empty for an empty table.
    [[nodiscard]] RayTableSignatureRegions signature_regions() const noexcept;
    /// Bytes one pass over signature_regions() reads (0 for an empty table).
    [[nodiscard]] std::size_t checked_bytes() const noexcept;
    /// True while the limits fuse() uses (grid, counts, ranges, exit step,
    /// kind, and the sensor's intrinsics and pose with which it places a
    /// reading near a face) still equal the words build() stored: a change to
    /// the table object that the signature of its regions would not see.
    /// Work: the kCheckHeaderWords words recomputed and compared. True for an
    /// empty table.
    [[nodiscard]] bool limits_intact() const noexcept;

private:
    /// The limits (19 words), then the reading placement: fx, fy, cx, cy,
    /// 1/fx and 1/fy as doubles, width and height, the pose's 3 x 4 doubles.
    static constexpr std::size_t kCheckHeaderWords = 19U + 12U + 2U + 24U;
    using CheckHeader = std::array<std::uint32_t, kCheckHeaderWords>;
    /// Both fuse()s: the uint16 image of @p u16 when it is not null, else
    /// the floats of @p depth.
    [[nodiscard]] Result<FusionStats> fuse_image(EvidenceGrid& grid, const SensorReading* u16, Span<const float> depth,
                                                 const SensorModelTable& model) const noexcept;
    /// The table's geometry and limits as words, from the members.
    [[nodiscard]] CheckHeader check_header() const noexcept;

    GridGeometry geometry_{};
    RayTableStorage storage_{};
    std::size_t pixels_ = 0U;
    std::size_t step_count_ = 0U;
    std::size_t crossed_count_ = 0U;
    float min_range_ = 0.0F;
    float max_range_ = 0.0F;
    float exit_step_ = 0.0F;        ///< metres per compact exit step (a power of two)
    float steps_per_metre_ = 0.0F;  ///< 1 / exit_step_ (exact: a power of two)
    bool compact_ = false;
    CheckHeader header_words_{};    ///< check_header() at build(): the first signature region
    ReadingPlacement placement_{};  ///< fuse_sensor's rule for readings near a face
    std::uint32_t storage_crc_ = 0U;
};

}  // namespace cellguard

#endif  // CELLGUARD_RAY_TABLE_HPP
