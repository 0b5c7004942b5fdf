/// @file ray_table.hpp
/// Precomputed rays of a static depth sensor: the fast fusion path.
///
/// Sensors in a workcell do not move. At commissioning, each pixel's ray is
/// traversed once from the sensor origin to the sensor's max_range and its
/// voxels are stored in order with the distance at which the ray leaves each
/// (a `RayStep`). A frame then walks each pixel's list up to its reading:
/// no traversal set-up and no floating point per voxel beyond one compare.
///
/// Equivalence with fuse_sensor (fusion.hpp): the same voxels get the same
/// evidence, except where a reading lies within float rounding of a voxel
/// face (the table puts a reading exactly on a face in the voxel the ray
/// enters next; fuse_sensor uses the half-open rule of grid.hpp) or where a
/// ray grazes a voxel edge (the table's ray is the pixel's exact direction,
/// fuse_sensor's ray ends at the float reading). The unit tests bound how
/// many voxels differ on the simulated workcell.
///
/// Storage is the caller's: `count_ray_steps` sizes it, `RayTable::build`
/// fills it. The table is valid only for the pose, intrinsics, grid and
/// max_range it was built for; `RayTable::fuse` checks the image size.
#ifndef CELLGUARD_RAY_TABLE_HPP
#define CELLGUARD_RAY_TABLE_HPP

#include <cstdint>

#include "cellguard/evidence_grid.hpp"
#include "cellguard/fusion.hpp"
#include "cellguard/ray_traversal.hpp"
#include "cellguard/sensor_frame.hpp"
#include "cellguard/sensor_model.hpp"

namespace cellguard {

/// One voxel of a precomputed ray.
struct RayStep {
    std::uint32_t voxel;  ///< linear voxel index
    float t_exit;         ///< metres from the sensor origin where the ray leaves the voxel
};

/// The voxel value of the marker that ends every pixel's steps (t_exit = +inf).
constexpr std::uint32_t kRayEndMarker = 0xFFFFFFFFU;

/// Caller storage of a ray table: steps for all pixels, and per pixel the
/// offset of its first step (pixels + 1 entries) and where its ray enters
/// the grid.
struct RayTableStorage {
    Span<RayStep> steps{};                ///< at least count_ray_steps(...) entries
    Span<std::uint32_t> pixel_begin{};    ///< width * height + 1 entries
    Span<float> pixel_enter{};            ///< width * height entries
    Span<float> pixel_norm{};             ///< width * height entries: |((u-cx)/fx, (v-cy)/fy, 1)|
};

/// Number of RayStep entries the table of this sensor needs in this grid:
/// every pixel's voxels plus one end marker per pixel.
/// The sensor description is checked as by validate_sensor_reading (the
/// depth view itself is not used). Errors: those of validate_sensor_reading.
[[nodiscard]] Result<std::size_t> count_ray_steps(const GridGeometry& grid, const SensorReading& sensor,
                                                  Rasterization rasterization = Rasterization::kExact) noexcept;

/// The precomputed rays of one depth sensor.
class RayTable {
public:
    /// An empty table (placeholder only; fuse() refuses it).
    RayTable() noexcept = default;

    /// Traverses every pixel's ray to sensor.max_range and stores it.
    /// Errors: those of validate_sensor_reading; kInvalidArgument unless the
    /// sensor is a depth image; kStorageTooSmall when a span is too small;
    /// kCapacityExceeded above 2^32 - 1 steps.
    static Result<RayTable> build(const GridGeometry& grid, const SensorReading& sensor, RayTableStorage storage,
                                  Rasterization rasterization = Rasterization::kExact) noexcept;

    /// Fuses one depth image of this sensor into @p grid (same geometry as
    /// built for). Readings are classified and counted as by fuse_sensor.
    /// Errors: kGeometryMismatch, kMalformedInput when the image size
    /// differs, kInvalidArgument for an empty table.
    [[nodiscard]] Result<FusionStats> fuse(EvidenceGrid& grid, Span<const float> depth,
                                           const SensorModelTable& model) const noexcept;

    /// Number of stored steps.
    [[nodiscard]] std::size_t step_count() const noexcept { return step_count_; }
    /// Pixels of the sensor.
    [[nodiscard]] std::size_t pixel_count() const noexcept { return pixels_; }

private:
    GridGeometry geometry_{};
    RayTableStorage storage_{};
    std::size_t pixels_ = 0U;
    std::size_t step_count_ = 0U;
    float min_range_ = 0.0F;
    float max_range_ = 0.0F;
};

}  // namespace cellguard

#endif  // CELLGUARD_RAY_TABLE_HPP
