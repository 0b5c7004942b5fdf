// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The robot cell's commissioning data (robot_scenario.hpp), shared by the
// firmware's run and the generator that renders its frames.
#include <array>
#include <cstdint>

#include "cellguard/firmware/robot_scenario.hpp"

namespace cellguard::firmware {

GridGeometry robot_cell_grid_geometry() noexcept {
    return GridGeometry::make(Eigen::Vector3d(-2.0, -2.0, 0.0), 0.1, GridDims{50, 40, 15}).value();
}

std::array<ZoneConfig, kRobotScenarioZones> robot_scenario_zone_configs() noexcept {
    ZoneConfig station_a;
    station_a.box_min = Eigen::Vector3d(-0.5, -1.15, 0.0);
    station_a.box_max = Eigen::Vector3d(0.5, -0.55, 1.5);
    station_a.min_foreground_voxels = 2U;
    station_a.max_unseen_voxels = 20U;
    ZoneConfig station_b = station_a;
    station_b.box_min = Eigen::Vector3d(-0.5, 0.55, 0.0);
    station_b.box_max = Eigen::Vector3d(0.5, 1.15, 1.5);
    ZoneConfig approach;
    approach.kind = ZoneKind::kWarning;
    approach.box_min = Eigen::Vector3d(0.9, -0.9, 0.0);
    approach.box_max = Eigen::Vector3d(1.7, 0.9, 1.5);
    approach.min_foreground_voxels = 2U;
    approach.max_unseen_voxels = 40U;
    return {station_a, station_b, approach};
}

std::array<std::uint32_t, kRobotScenarioCases> robot_scenario_case_masks() noexcept { return {0x5U, 0x6U, 0x7U}; }

SeparationParams robot_scenario_separation() noexcept {
    SeparationParams p;
    p.human_speed_mps = 1.6;
    p.reaction_time_s = 0.3;
    p.class_count = 2U;
    p.classes[0] = SpeedClassLimits{0.5, 0.2, 0.05};
    p.classes[1] = SpeedClassLimits{0.25, 0.1, 0.0125};
    p.reduced_class = 1U;
    p.slowdown_time_s = 0.2;
    p.intrusion_distance_m = 0.85;
    p.sensing_uncertainty_m = 0.05;
    p.robot_uncertainty_m = 0.02;
    p.min_foreground_voxels = 2U;
    p.min_hidden_voxels = 8U;
    return p;
}

std::array<std::int16_t, kRobotScenarioJoints> arm_pose_raw(ArmPose pose) noexcept {
    // Radians / 0.0002, rounded: pan -pi/2 -7854, -pi -15708, -3pi/2 -23562;
    // UP 0.1 1.2 1.8416, DOWN 0.45 1.05 1.6416 (the scene file's keyframes).
    switch (pose) {
        case ArmPose::kUpAtA: return {-7854, 500, 6000, 9208, 0, 0};
        case ArmPose::kCarrying: return {-15708, 500, 6000, 9208, 0, 0};
        case ArmPose::kDownAtB: return {-23562, 2250, 5250, 8208, 0, 0};
        case ArmPose::kUpAtB:
        default: return {-23562, 500, 6000, 9208, 0, 0};
    }
}

std::array<RobotScene, kRobotScenes> robot_scenes() noexcept {
    return {RobotScene{"arm-up-at-a", ArmPose::kUpAtA, false, 0.0, 0.0},
            RobotScene{"arm-carrying", ArmPose::kCarrying, false, 0.0, 0.0},
            RobotScene{"arm-down-at-b", ArmPose::kDownAtB, false, 0.0, 0.0},
            RobotScene{"person-approaching", ArmPose::kUpAtB, true, 2.5, 0.0},
            RobotScene{"person-near-the-arm", ArmPose::kUpAtB, true, 1.2, 0.0}};
}

}  // namespace cellguard::firmware
