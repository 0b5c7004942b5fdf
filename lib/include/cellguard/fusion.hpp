/// @file fusion.hpp
/// Multi-sensor ray fusion into a frame evidence grid: the independent
/// opinion pool, in integer log-odds.
///
/// Every valid reading is a ray from the sensor origin to the reading. The
/// ray walks the grid (ray_traversal.hpp) and adds the sensor model's
/// evidence (sensor_model.hpp) to every voxel it passes, saturating
/// (add_finite_saturating), and sets the voxel's observed flag. The evidence
/// of every ray adds: a voxel crossed by n rays gets the sum of n opinions.
///
/// Readings that are NaN, infinite, zero, behind the sensor (z < 0 in the
/// sensor frame), nearer than min_range or beyond max_range are skipped and
/// counted, never fused. A reading beyond the grid still clears the voxels
/// its ray crosses inside the grid, but adds no peak (the reading's voxel is
/// not in the grid).
///
/// fuse_frame adds to the grid; clear the grid first for a fresh frame grid.
/// It allocates nothing and its work is bounded by the sum over readings of
/// the voxels each ray crosses (at most nx + ny + nz per ray).
#ifndef CELLGUARD_FUSION_HPP
#define CELLGUARD_FUSION_HPP

#include <cstdint>

#include "cellguard/evidence_grid.hpp"
#include "cellguard/ray_traversal.hpp"
#include "cellguard/sensor_frame.hpp"
#include "cellguard/sensor_model.hpp"

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
    std::uint64_t voxel_updates = 0;         ///< voxel evidence additions
    /// All skipped readings.
    [[nodiscard]] std::uint32_t skipped() const noexcept {
        return skipped_nan + skipped_infinite + skipped_zero + skipped_behind + skipped_out_of_range;
    }
    /// Adds another call's counts (counts of one frame stay far below 2^32:
    /// kMaxSensors * kMaxReadingsPerSensor < 2.5e6).
    void add(const FusionStats& other) noexcept;
};

/// Fuses one sensor's reading into @p grid. The description is checked
/// first (validate_sensor_reading); on error the grid is untouched.
[[nodiscard]] Result<FusionStats> fuse_sensor(EvidenceGrid& grid, const SensorReading& reading,
                                              const SensorModelTable& model,
                                              Rasterization rasterization = Rasterization::kExact) noexcept;

/// Fuses every sensor of one frame into @p grid. All descriptions are
/// checked before any evidence is added: on error (kCapacityExceeded for
/// more than kMaxSensors sensors, or a sensor's own error) the grid is
/// untouched.
[[nodiscard]] Result<FusionStats> fuse_frame(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                             const SensorModelTable& model,
                                             Rasterization rasterization = Rasterization::kExact) noexcept;

/// Fuses one ray from @p origin to @p reading (workcell frame, metres) with
/// the sensor model; returns the number of voxel updates. The building block
/// of fuse_sensor, public for tests and tools. Non-finite input adds nothing.
std::uint32_t fuse_ray(EvidenceGrid& grid, const Eigen::Vector3d& origin, const Eigen::Vector3d& reading,
                       const SensorModelTable& model, Rasterization rasterization, bool* reading_in_grid) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_FUSION_HPP
