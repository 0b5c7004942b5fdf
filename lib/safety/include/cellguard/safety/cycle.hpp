// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file cycle.hpp
/// The cycle executive's timing side: fixed stages with measured durations,
/// a deadline monitor, and the worst-case work bound computed from the
/// configuration.
///
/// Time comes from the caller (a port's monotonic clock, microseconds):
/// lib/ makes no OS call. The bound counts operations, not seconds: the
/// number of voxel steps, grid-pass voxels and zone counter updates that a
/// cycle can perform at most. A benchmark turns it into time on a target by
/// measuring the cost of each kind of operation.
#ifndef CELLGUARD_CYCLE_HPP
#define CELLGUARD_CYCLE_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard {

/// The fixed stages of a cycle, in order.
enum class CycleStage : std::uint8_t {
    kFuse = 0,              ///< clear the frame grid, fuse every sensor
    kSubtractAndZones = 1,  ///< add the prior, evaluate every zone
    kLogic = 2,             ///< safety logic
    kOutput = 3,            ///< encode and send the safety message
};
/// Number of stages.
constexpr std::size_t kCycleStages = 4U;

/// Worst-case work of one cycle, from the configuration.
struct CycleWorkBound {
    std::uint64_t rays = 0U;          ///< readings the sensors can deliver (every pixel or point)
    std::uint64_t voxel_steps = 0U;   ///< rays x the most voxels one ray can visit
    std::uint64_t grid_voxels = 0U;   ///< voxels touched by whole-grid passes (clear, subtract, ray tables' hit counts)
    std::uint64_t zone_updates = 0U;  ///< zone counter updates (sum of zone voxel counts)
    std::uint64_t robot_mask_tests = 0U;      ///< voxel tests of the robot mask (robot_mask_work_bound)
    std::uint64_t separation_distances = 0U;  ///< voxel-to-capsule distances of separation (voxels x capsules)
    std::uint64_t footprint_units = 0U;       ///< footprint fusion's work units (footprint_work_bound), when it fuses
};

/// The bound for @p grid, the sensors described by @p sensors (their pixel
/// or point capacities; the data are not read) and @p zones. Rays use
/// max_voxels_per_segment (ray_traversal.hpp); the grid is passed twice
/// (clear, subtract) plus three times per depth-image sensor (a ray table
/// zeroes its corrections, sets its hit counts and adds the sums,
/// ray_table.hpp; counted whether or not the sensor has a table, so the
/// bound holds either way).
[[nodiscard]] CycleWorkBound compute_work_bound(const GridGeometry& grid, Span<const SensorReading> sensors,
                                                const CompiledZones& zones) noexcept;

/// The bound as above for a cell with @p robot, whose capsules are grown by
/// @p mask_margin_m for the robot mask (the controller's RobotCellConfig).
/// Added to it: robot_mask_tests = robot_mask_work_bound(robot,
/// mask_margin_m, voxel size) (the tests of all capsules' grown boxes in
/// the worst orientation); separation_distances = voxels x capsules (the
/// separation computes a distance to every capsule for each voxel that may
/// be a person, at most every voxel); and two more grid passes (the mask's
/// rewrite and the separation's pass over the grid).
[[nodiscard]] CycleWorkBound compute_work_bound(const GridGeometry& grid, Span<const SensorReading> sensors,
                                                const CompiledZones& zones, const RobotModel& robot,
                                                double mask_margin_m) noexcept;

/// The bound @p b for a cycle that fuses its depth images by footprint
/// fusion with @p params: their rays leave voxel_steps (point sets stay),
/// and footprint_units gets footprint_work_bound per depth image (from its
/// pose and intrinsics: the most work footprint fusion does, and exactly
/// its work with exact_footprint_max 0), plus one pass over the grid each
/// (the pooling of its opinions).
[[nodiscard]] CycleWorkBound with_footprint_fusion(CycleWorkBound b, const GridGeometry& grid,
                                                   Span<const SensorReading> sensors,
                                                   const FootprintParams& params) noexcept;

/// Durations of one cycle, microseconds.
struct CycleTiming {
    std::uint64_t stage_us[kCycleStages] = {};  ///< per stage
    std::uint64_t total_us = 0U;                ///< begin to end
};

/// Measures stages and checks the cycle against its budget.
class CycleMonitor {
public:
    /// A monitor for cycles of at most @p budget_us microseconds (> 0, contract).
    explicit CycleMonitor(std::uint64_t budget_us) noexcept;

    /// Marks the start of a cycle at @p now_us.
    void begin(std::uint64_t now_us) noexcept;
    /// Marks the end of @p stage at @p now_us (stages in order; a stage
    /// out of order is a contract violation).
    void end_stage(CycleStage stage, std::uint64_t now_us) noexcept;
    /// Marks the end of the cycle; returns true when it overran its budget
    /// (or the clock went backwards within it).
    [[nodiscard]] bool end(std::uint64_t now_us) noexcept;

    /// The last complete cycle's timing.
    [[nodiscard]] const CycleTiming& last() const noexcept { return last_; }
    /// The largest duration seen per stage and in total.
    [[nodiscard]] const CycleTiming& worst() const noexcept { return worst_; }
    /// Completed cycles.
    [[nodiscard]] std::uint64_t cycles() const noexcept { return cycles_; }
    /// Cycles that overran.
    [[nodiscard]] std::uint64_t overruns() const noexcept { return overruns_; }
    /// The budget, microseconds.
    [[nodiscard]] std::uint64_t budget_us() const noexcept { return budget_us_; }

private:
    std::uint64_t budget_us_;
    std::uint64_t begin_us_ = 0U;
    std::uint64_t stage_start_us_ = 0U;
    std::size_t next_stage_ = 0U;
    bool running_ = false;
    bool clock_backwards_ = false;
    CycleTiming current_{};
    CycleTiming last_{};
    CycleTiming worst_{};
    std::uint64_t cycles_ = 0U;
    std::uint64_t overruns_ = 0U;
};

}  // namespace cellguard

#endif  // CELLGUARD_CYCLE_HPP
