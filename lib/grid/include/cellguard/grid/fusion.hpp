// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file fusion.hpp
/// Multi-sensor fusion into a frame evidence grid, in integer log-odds, with
/// the sensor model of sensor_model.hpp: one opinion per sensor, voxel and
/// frame, pooled across the sensors with "occupied wins".
///
/// Every valid reading is a ray from the sensor origin to the reading. For
/// one sensor, the rays walk the grid (ray_traversal.hpp) and write the
/// sensor's opinion of each voxel they reach into caller scratch memory, one
/// int16 per voxel: the maximum of what the rays say (a hit is above every
/// free value, and of two free values the weaker one, nearer 0.5, is
/// larger). Then every voxel the sensor has an opinion of is pooled into the
/// grid (SensorModelTable::pool) and its observed flag is set. A voxel that
/// holds a reading is therefore occupied in that frame however many rays
/// cross it, its evidence does not grow with the number of rays, and the
/// grid does not depend on the order of the rays or of the sensors.
///
/// Readings that are NaN, infinite, zero, behind the sensor (z < 0 in the
/// sensor frame), nearer than min_range or beyond max_range are skipped and
/// counted, never fused. A reading beyond the grid still clears the voxels
/// its ray crosses inside the grid, but adds no hit (the reading's voxel is
/// not in the grid).
///
/// The grid must hold the pooled opinions of one frame only: clear it
/// before the frame's first sensor. Fusion allocates nothing; its work is
/// bounded by the sum over readings of the voxels each ray crosses (at most
/// nx + ny + nz per ray) plus two passes over the scratch per sensor.
#ifndef CELLGUARD_FUSION_HPP
#define CELLGUARD_FUSION_HPP

#include <cstdint>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/grid/sensor_model.hpp"

namespace cellguard {

/// What one fusion call did, for diagnostics and for the tests.
struct FusionStats {
    std::uint32_t rays_fused = 0;            ///< readings turned into rays (whether or not they cross the grid)
    std::uint32_t readings_in_grid = 0;      ///< rays whose reading lies in the grid (got the peak)
    std::uint32_t skipped_nan = 0;           ///< NaN readings
    std::uint32_t skipped_infinite = 0;      ///< infinite readings
    std::uint32_t skipped_zero = 0;          ///< depth 0 or a point at the sensor origin
    std::uint32_t skipped_behind = 0;        ///< readings behind the sensor (z < 0)
    std::uint32_t skipped_out_of_range = 0;  ///< nearer than min_range or beyond max_range
    std::uint64_t voxel_updates = 0;         ///< (voxel, ray) visits: the rays' work, not the number of opinions
    /// All skipped readings.
    [[nodiscard]] std::uint32_t skipped() const noexcept {
        return skipped_nan + skipped_infinite + skipped_zero + skipped_behind + skipped_out_of_range;
    }
    /// Adds another call's counts (counts of one frame stay far below 2^32:
    /// kMaxSensors * kMaxReadingsPerSensor < 2.5e6).
    void add(const FusionStats& other) noexcept;
};

/// One frame of the empty cell into the background grid G_B: clears
/// @p frame, fuses @p sensors into it (fuse_frame, through @p scratch) and
/// accumulates it into @p background (accumulate_background with @p clamp).
/// The one path by which the commissioning tool, the monitor and the
/// simulator build G_B. Errors: those of fuse_frame and
/// accumulate_background; on a fusion error the background is untouched.
[[nodiscard]] Result<FusionStats> fuse_background_frame(EvidenceGrid& background, EvidenceGrid& frame,
                                                        Span<const SensorReading> sensors,
                                                        const SensorModelTable& model, Span<std::int16_t> scratch,
                                                        Rasterization rasterization = Rasterization::kExact,
                                                        BackgroundClamp clamp = BackgroundClamp{}) noexcept;

/// The scratch value of a voxel the sensor has no opinion of (below every opinion).
constexpr std::int16_t kNoOpinion = -32768;

/// Fuses one sensor's reading into @p grid, using @p scratch (at least
/// grid.voxel_count() elements; overwritten) for the sensor's opinions. The
/// description is checked first (validate_sensor_reading). Errors: those of
/// validate_sensor_reading, kStorageTooSmall for a short scratch; on error
/// the grid is untouched.
[[nodiscard]] Result<FusionStats> fuse_sensor(EvidenceGrid& grid, const SensorReading& reading,
                                              const SensorModelTable& model, Span<std::int16_t> scratch,
                                              Rasterization rasterization = Rasterization::kExact) noexcept;

/// Fuses every sensor of one frame into @p grid, one after another through
/// @p scratch (as fuse_sensor). All descriptions are checked before any
/// evidence is added: on error (kCapacityExceeded for more than kMaxSensors
/// sensors, kStorageTooSmall, or a sensor's own error) the grid is untouched.
[[nodiscard]] Result<FusionStats> fuse_frame(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                             const SensorModelTable& model, Span<std::int16_t> scratch,
                                             Rasterization rasterization = Rasterization::kExact) noexcept;

/// The point of depth pixel (@p u, @p v) at depth @p d in the sensor frame,
/// as every fusion path computes it: x = (u - cx) * inv_fx * d and y =
/// (v - cy) * inv_fy * d in double, rounded to float, z = d. The paths run
/// one inline definition of it (lib/grid/src/placement.hpp, compiled
/// without floating-point contraction); this is that definition, for tests
/// and tools.
[[nodiscard]] Eigen::Vector3f depth_pixel_point(const PinholeIntrinsics& k, double inv_fx, double inv_fy,
                                                std::int32_t u, std::int32_t v, float d) noexcept;

/// A sensor-frame reading @p p in the cell frame (@p pose * p in double,
/// each coordinate summed left to right, the translation last), as every
/// fusion path computes it (the same inline definition as depth_pixel_point).
[[nodiscard]] Eigen::Vector3d reading_in_cell(const Eigen::Isometry3d& pose, const Eigen::Vector3f& p) noexcept;

/// Writes one ray's opinions, from @p origin to @p reading (workcell frame,
/// metres), into a sensor's @p opinions over the voxels of @p grid (each
/// voxel keeps the maximum of its opinions, see the file comment); returns
/// the number of voxels the ray reaches. The building block of fuse_sensor,
/// public for tests and tools. Non-finite input writes nothing.
std::uint32_t trace_ray_opinions(Span<std::int16_t> opinions, const GridGeometry& grid, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& reading, const SensorModelTable& model,
                                 Rasterization rasterization, bool* reading_in_grid) noexcept;

/// What one ray did, as the receiver of for_each_reading_ray reports it.
struct RayOutcome {
    std::uint32_t visits = 0U;     ///< voxels the ray reached
    bool reading_in_grid = false;  ///< the reading's voxel lies in the grid
};

/// Receives the rays of a sensor's valid readings (for_each_reading_ray).
class RayVisitor {
public:
    /// One valid reading's ray, from the sensor's @p origin to @p reading (cell frame, metres).
    virtual RayOutcome ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& reading) noexcept = 0;

protected:
    RayVisitor() = default;
    ~RayVisitor() = default;
    RayVisitor(const RayVisitor&) = default;
    RayVisitor& operator=(const RayVisitor&) = default;
    RayVisitor(RayVisitor&&) = default;
    RayVisitor& operator=(RayVisitor&&) = default;
};

/// The one reading loop of every per-ray path: hands each valid reading of
/// @p reading (already validated: validate_sensor_reading) to @p visitor as a
/// ray, points in order and depth pixels row by row, placed as every path
/// places them (depth_pixel_point, reading_in_cell); skips and counts the
/// readings fusion skips (the file comment), and counts the rays, the
/// readings in the grid and the voxel visits the visitor reports.
[[nodiscard]] FusionStats for_each_reading_ray(const SensorReading& reading, RayVisitor& visitor) noexcept;

/// Pools a sensor's @p opinions (kNoOpinion: none) into @p grid and sets the
/// observed flag of every voxel with an opinion; shared by fuse_sensor and
/// tools that gather opinions themselves. The spans must hold at least
/// grid.voxel_count() elements (checked by the caller).
void pool_opinions(EvidenceGrid& grid, Span<const std::int16_t> opinions, const SensorModelTable& model) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_FUSION_HPP
