// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: cycle stage timing, deadline monitor, worst-case work bound
// (with a robot: its mask and the separation distances).
#include <doctest/doctest.h>

#include <vector>

#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/robot/robot_mask.hpp"
#include "cellguard/safety/cycle.hpp"
#include "contract_capture.hpp"
#include "test_robot.hpp"

using namespace cellguard;

// verifies: SR-CTRL-006
TEST_CASE("cycle: stage durations add up and the worst case is kept") {
    CycleMonitor m(5000U);
    m.begin(100U);
    m.end_stage(CycleStage::kFuse, 1100U);
    m.end_stage(CycleStage::kSubtractAndZones, 1300U);
    m.end_stage(CycleStage::kLogic, 1310U);
    m.end_stage(CycleStage::kOutput, 1400U);
    CHECK_FALSE(m.end(1400U));
    CHECK(m.last().stage_us[0] == 1000U);
    CHECK(m.last().stage_us[1] == 200U);
    CHECK(m.last().total_us == 1300U);
    m.begin(2000U);
    m.end_stage(CycleStage::kFuse, 2500U);
    m.end_stage(CycleStage::kSubtractAndZones, 2600U);
    m.end_stage(CycleStage::kLogic, 2601U);
    m.end_stage(CycleStage::kOutput, 2602U);
    CHECK_FALSE(m.end(2602U));
    CHECK(m.worst().stage_us[0] == 1000U);
    CHECK(m.worst().total_us == 1300U);
    CHECK(m.cycles() == 2U);
}

// verifies: SR-CTRL-005
TEST_CASE("cycle: a cycle over its budget is reported as an overrun") {
    CycleMonitor m(5000U);
    m.begin(0U);
    CHECK_FALSE(m.end(5000U));  // exactly the budget is allowed
    m.begin(10000U);
    CHECK(m.end(15001U));
    CHECK(m.overruns() == 1U);
}

// verifies: SR-CTRL-005
TEST_CASE("cycle: a clock that runs backwards within a cycle counts as an overrun") {
    CycleMonitor m(5000U);
    m.begin(1000U);
    m.end_stage(CycleStage::kFuse, 900U);
    CHECK(m.end(1200U));
}

// verifies: SR-CTRL-005
TEST_CASE("cycle: a clock that is behind the cycle's start at its end counts as an overrun of 0 us") {
    CycleMonitor m(5000U);
    m.begin(1000U);
    CHECK(m.end(400U));  // backwards over the whole cycle: an overrun although the duration is short
    CHECK(m.last().total_us == 0U);
    CHECK(m.overruns() == 1U);
    m.begin(2000U);
    CHECK_FALSE(m.end(2100U));  // the next cycle starts afresh
    CHECK(m.overruns() == 1U);
    CHECK(m.worst().total_us == 100U);
}

// verifies: SR-CTRL-005, SR-GEN-003
TEST_CASE("cycle: stages out of order are a contract violation") {
    CycleMonitor m(5000U);
    m.begin(0U);
    CHECK(test::violates_contract([&] { m.end_stage(CycleStage::kLogic, 10U); }));
}

// verifies: SR-CTRL-006
TEST_CASE("cycle: the work bound follows from sensors, grid and zones") {
    const GridGeometry g = paper_grid_geometry();
    std::vector<std::uint32_t> mask(g.voxel_count());
    ZoneConfig z;
    z.box_min = Eigen::Vector3d(-0.5, -0.5, 0.0);
    z.box_max = Eigen::Vector3d(0.5, 0.5, 1.0);
    const ZoneConfig zs[] = {z, z};
    const CompiledZones zones = CompiledZones::compile(g, zs, {mask.data(), mask.size()}).value();
    SensorReading cam;
    cam.kind = SensorDataKind::kDepthImage;
    cam.intrinsics.width = 320;
    cam.intrinsics.height = 240;
    SensorReading points;
    points.kind = SensorDataKind::kPointSet;
    const SensorReading sensors[] = {cam, cam, points};
    const CycleWorkBound b = compute_work_bound(g, sensors, zones);
    CHECK(b.rays == 2U * 320U * 240U);
    CHECK(b.voxel_steps == b.rays * (34U + 30U + 30U - 2U));
    // clear + subtract, and per depth image the ray table's three grid passes
    CHECK(b.grid_voxels == (2U + 3U * 2U) * 30600U);
    CHECK(b.zone_updates == 2U * zones.voxel_count(0));
}

// verifies: SR-CTRL-006, SR-ROB-205
TEST_CASE("cycle: with a robot, the work bound adds the mask's tests, voxels x capsules and two grid passes") {
    const GridGeometry g = paper_grid_geometry();
    std::vector<std::uint32_t> mask(g.voxel_count());
    ZoneConfig z;
    z.box_min = Eigen::Vector3d(-0.5, -0.5, 0.0);
    z.box_max = Eigen::Vector3d(0.5, 0.5, 1.0);
    const CompiledZones zones = CompiledZones::compile(g, {&z, 1U}, {mask.data(), mask.size()}).value();
    SensorReading cam;
    cam.kind = SensorDataKind::kDepthImage;
    cam.intrinsics.width = 320;
    cam.intrinsics.height = 240;
    const SensorReading sensors[] = {cam};
    const RobotModel arm = test::make_test_arm();
    const CycleWorkBound without = compute_work_bound(g, sensors, zones);
    const CycleWorkBound with = compute_work_bound(g, sensors, zones, arm, 0.05);
    CHECK(without.robot_mask_tests == 0U);
    CHECK(without.separation_distances == 0U);
    CHECK(with.rays == without.rays);
    CHECK(with.voxel_steps == without.voxel_steps);
    CHECK(with.zone_updates == without.zone_updates);
    CHECK(with.grid_voxels == without.grid_voxels + 2U * 30600U);
    CHECK(with.robot_mask_tests == robot_mask_work_bound(arm, 0.05, 0.05));
    CHECK(with.robot_mask_tests > 0U);
    CHECK(with.separation_distances == 30600U * 7U);  // the test arm's seven capsules
    // A larger margin never lowers the bound.
    CHECK(compute_work_bound(g, sensors, zones, arm, 0.2).robot_mask_tests >= with.robot_mask_tests);
}

// verifies: SR-FUSE-011
TEST_CASE("cycle: with footprint fusion, depth images cost footprint units instead of ray steps") {
    const GridGeometry g = paper_grid_geometry();
    std::vector<std::uint32_t> mask(g.voxel_count());
    const CompiledZones zones = CompiledZones::compile(g, {}, {mask.data(), mask.size()}).value();
    SensorReading cam;
    cam.kind = SensorDataKind::kDepthImage;
    cam.intrinsics.width = 320;
    cam.intrinsics.height = 240;
    SensorReading empty_cam = cam;  // a depth image without pixels (width 0): no rays, no footprint work
    empty_cam.intrinsics.width = 0;
    SensorReading flat_cam = cam;  // a width but no rows (height 0): no pixels either
    flat_cam.intrinsics.height = 0;
    SensorReading points;
    points.kind = SensorDataKind::kPointSet;
    const SensorReading sensors[] = {cam, empty_cam, flat_cam, points};
    const CycleWorkBound rays = compute_work_bound(g, sensors, zones);
    const FootprintParams params;
    const CycleWorkBound b = with_footprint_fusion(rays, g, sensors, params);
    const std::uint64_t pixels = 320U * 240U;
    CHECK(b.rays == rays.rays);
    CHECK(b.voxel_steps == rays.voxel_steps - pixels * max_voxels_per_segment(g));
    CHECK(b.footprint_units == footprint_work_bound(g, cam, params));  // the images without pixels: no work
    CHECK(footprint_work_bound(g, empty_cam) == 0U);
    CHECK(footprint_work_bound(g, flat_cam) == 0U);
    CHECK(b.footprint_units > 0U);
    CHECK(b.grid_voxels == rays.grid_voxels + 3U * g.voxel_count());  // one pass per depth image
}

// verifies: SR-CTRL-005, SR-GEN-003
TEST_CASE("cycle: a budget of 0 us, or an end without a begin, is a contract violation") {
    CHECK(test::violates_contract([] { const CycleMonitor zero(0U); }));
    CHECK_FALSE(test::violates_contract([] { const CycleMonitor one(1U); }));
    CycleMonitor m(5000U);
    CHECK(test::violates_contract([&] { (void)m.end(10U); }));
    CHECK(test::violates_contract([&] { m.end_stage(CycleStage::kFuse, 10U); }));  // no cycle begun
}
