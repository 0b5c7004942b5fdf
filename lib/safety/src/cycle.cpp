// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/cycle.hpp"

#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/robot/robot_mask.hpp"

namespace cellguard {

CycleWorkBound compute_work_bound(const GridGeometry& grid, Span<const SensorReading> sensors,
                                  const CompiledZones& zones) noexcept {
    CycleWorkBound b;
    std::uint64_t depth_images = 0U;
    for (const SensorReading& s : sensors) {
        depth_images += is_depth_image(s.kind) ? 1U : 0U;
        const std::uint64_t n = is_depth_image(s.kind)
                                    ? static_cast<std::uint64_t>(s.intrinsics.width > 0 ? s.intrinsics.width : 0) *
                                          static_cast<std::uint64_t>(s.intrinsics.height > 0 ? s.intrinsics.height : 0)
                                    : static_cast<std::uint64_t>(s.points.size());
        b.rays += n;
    }
    b.voxel_steps = b.rays * static_cast<std::uint64_t>(max_voxels_per_segment(grid));
    b.grid_voxels = (2U + 3U * depth_images) * static_cast<std::uint64_t>(grid.voxel_count());
    b.zone_updates = static_cast<std::uint64_t>(zones.total_memberships());
    return b;
}

CycleWorkBound compute_work_bound(const GridGeometry& grid, Span<const SensorReading> sensors,
                                  const CompiledZones& zones, const RobotModel& robot, double mask_margin_m) noexcept {
    CycleWorkBound b = compute_work_bound(grid, sensors, zones);
    const auto voxels = static_cast<std::uint64_t>(grid.voxel_count());
    b.grid_voxels += 2U * voxels;  // the mask's rewrite, the separation's pass
    b.robot_mask_tests = robot_mask_work_bound(robot, mask_margin_m, grid.voxel_size());
    b.separation_distances = voxels * static_cast<std::uint64_t>(robot.capsule_count);
    return b;
}

CycleWorkBound with_footprint_fusion(CycleWorkBound b, const GridGeometry& grid, Span<const SensorReading> sensors,
                                     const FootprintParams& params) noexcept {
    const std::uint64_t per_ray = max_voxels_per_segment(grid);
    for (const SensorReading& s : sensors) {
        if (!is_depth_image(s.kind)) {
            continue;
        }
        const std::uint64_t pixels = s.intrinsics.width > 0 && s.intrinsics.height > 0
                                         ? static_cast<std::uint64_t>(s.intrinsics.width) *
                                               static_cast<std::uint64_t>(s.intrinsics.height)
                                         : 0U;
        b.voxel_steps -= pixels * per_ray;
        b.footprint_units += footprint_work_bound(grid, s, params);
        b.grid_voxels += static_cast<std::uint64_t>(grid.voxel_count());
    }
    return b;
}

CycleMonitor::CycleMonitor(std::uint64_t budget_us) noexcept : budget_us_(budget_us) {
    CG_ENFORCE(budget_us > 0U, "cycle budget must be positive");
}

void CycleMonitor::begin(std::uint64_t now_us) noexcept {
    begin_us_ = now_us;
    stage_start_us_ = now_us;
    next_stage_ = 0U;
    running_ = true;
    clock_backwards_ = false;
    current_ = CycleTiming{};
}

void CycleMonitor::end_stage(CycleStage stage, std::uint64_t now_us) noexcept {
    const auto s = static_cast<std::size_t>(stage);
    CG_ENFORCE(running_ && s == next_stage_, "cycle stages out of order");
    if (now_us < stage_start_us_) {
        clock_backwards_ = true;
        now_us = stage_start_us_;
    }
    current_.stage_us[s] = now_us - stage_start_us_;
    stage_start_us_ = now_us;
    ++next_stage_;
}

bool CycleMonitor::end(std::uint64_t now_us) noexcept {
    CG_ENFORCE(running_, "cycle ended without begin");
    running_ = false;
    if (now_us < begin_us_) {
        clock_backwards_ = true;
        now_us = begin_us_;
    }
    current_.total_us = now_us - begin_us_;
    last_ = current_;
    for (std::size_t s = 0U; s < kCycleStages; ++s) {
        worst_.stage_us[s] = current_.stage_us[s] > worst_.stage_us[s] ? current_.stage_us[s] : worst_.stage_us[s];
    }
    worst_.total_us = current_.total_us > worst_.total_us ? current_.total_us : worst_.total_us;
    ++cycles_;
    const bool overrun = clock_backwards_ || current_.total_us > budget_us_;
    overruns_ += overrun ? 1U : 0U;
    return overrun;
}

}  // namespace cellguard
