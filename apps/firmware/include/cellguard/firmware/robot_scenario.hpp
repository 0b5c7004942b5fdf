// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_scenario.hpp
/// The firmware's robot-cell run (issue 17), the same code on every target,
/// after the zones-only run of scenario.hpp. The robot cell of
/// `cellguard-monitor --demo robot-cell` (apps/evaluation/scenes/robot-cell.toml,
/// apps/monitor/config/robot-cell.toml) on a small grid:
/// - the robot image in flash (generated/robot.cgrobot: the demo arm
///   cellguard_arm6, byte for byte the image cellguard-robot writes from
///   apps/monitor/config/robot-arm.urdf, CRC-32 0xDE60A184) is checked with
///   load_robot_image and its CRC becomes the robot id the commands must carry;
/// - the cell's prior (generated/robot_prior.cgprior) is checked with
///   load_prior_image against robot_cell_grid_geometry();
/// - the canned depth frames (generated/robot_frames.bin, the format of
///   canned_frames.hpp) show the arm rendered as capsules in the pose the
///   script's command reports, and the person walking up to it;
/// - every cycle the PLC's command (case, speed class, joints) is encoded by
///   a PlcCommandSender into its six CAN frames, two samples a cycle 50 ms
///   apart, and fed with their arrival times to a CommandReceiver, whose poll
///   at the cycle's start is the controller's CommandInput;
/// - the controller runs with RobotCellConfig (the demo's margin and
///   separation parameters) and three monitoring cases.
/// The run keeps its own clock (100 ms a cycle, one microsecond per reading
/// within a cycle), so command ages and receiver timing are the same on
/// every target; the caller's clock only times the whole run.
///
/// The digest covers, per cycle in order, what scenario.hpp's does (grid,
/// fusion counts, zones, faults, safety outputs, every CAN frame with the
/// diagnostics timing masked; the separation frame included) and then the
/// robot side of the report: configured, active case, command valid, its
/// counter, age and refusal reason, speed request, distance, required
/// distance, robot voxels, and the robot mask itself.
#ifndef CELLGUARD_FIRMWARE_ROBOT_SCENARIO_HPP
#define CELLGUARD_FIRMWARE_ROBOT_SCENARIO_HPP

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/firmware/scenario.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/robot/separation.hpp"
#include "cellguard/safety/robot_command.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::firmware {

/// Cycles in the robot-cell script.
constexpr std::uint32_t kRobotScenarioCycles = 8U;
/// Zones of the robot cell: station A, station B (protective), approach (warning).
constexpr std::size_t kRobotScenarioZones = 3U;
/// Monitoring cases: 0 work at A, 1 work at B, 2 carry.
constexpr std::size_t kRobotScenarioCases = 3U;
/// Joints of the demo arm (the PLC's order: pan, shoulder lift, elbow, wrist 1, 2, 3).
constexpr std::size_t kRobotScenarioJoints = 6U;
/// The robot image's CRC-32 (the demo arm at the cell's origin, not rotated).
constexpr std::uint32_t kDemoArmImageCrc = 0xDE60A184U;
/// The controller's period in the script, microseconds.
constexpr std::uint64_t kRobotScenarioPeriodUs = 100000U;

/// The robot cell's grid: the demo's 10 cm voxels over x -2.0 .. 3.0 m,
/// y -2.0 .. 2.0 m (50 x 40), but 1.5 m high (15 layers instead of 18):
/// 30,000 voxels, within the firmware's grid storage (grid_config.hpp).
[[nodiscard]] GridGeometry robot_cell_grid_geometry() noexcept;

/// The demo's zones (apps/monitor/config/robot-cell.toml), tops cut to the
/// grid: station-a, station-b (protective), approach (warning).
[[nodiscard]] std::array<ZoneConfig, kRobotScenarioZones> robot_scenario_zone_configs() noexcept;
/// The demo's cases as zone masks: 0 {station-a, approach}, 1 {station-b, approach}, 2 all three.
[[nodiscard]] std::array<std::uint32_t, kRobotScenarioCases> robot_scenario_case_masks() noexcept;
/// The demo's speed and separation parameters: S_p(0) 1.92 m, S_p(1) 1.65 m, reduced below 2.34 m.
[[nodiscard]] SeparationParams robot_scenario_separation() noexcept;
/// The demo's mask margin, metres.
constexpr double kRobotScenarioMaskMargin = 0.25;

/// The arm's poses in the script, as the PLC sends them (raw joint units of
/// robot_command.hpp: 0.2 mrad). The scene's keyframes: UP and DOWN at
/// station A (pan -pi/2), at station B (pan -3pi/2) and over the -x side
/// while carrying (pan -pi).
enum class ArmPose : std::uint8_t { kUpAtA = 0, kCarrying = 1, kDownAtB = 2, kUpAtB = 3 };
/// Number of ArmPose values.
constexpr std::size_t kArmPoses = 4U;
/// The raw joints of @p pose.
[[nodiscard]] std::array<std::int16_t, kRobotScenarioJoints> arm_pose_raw(ArmPose pose) noexcept;

/// A scene of the robot frames blob: the arm's pose and where the person stands.
struct RobotScene {
    const char* name;  ///< scene name in the blob
    ArmPose arm;       ///< the arm's pose in the frames
    bool person;       ///< a person stands at (person_x, person_y)
    double person_x;   ///< metres
    double person_y;   ///< metres
};
/// Scenes in the robot frames blob.
constexpr std::size_t kRobotScenes = 5U;
/// The scenes the generator renders and the script uses, in the blob's order.
[[nodiscard]] std::array<RobotScene, kRobotScenes> robot_scenes() noexcept;

/// Runs the robot-cell script (see the file comment): one line per cycle
/// ("robot cycle N ..."), then "robot digest 0x%08x" to @p text; CAN
/// frames through @p can. Static storage (not re-entrant); shares the grid
/// storage with run_scenario (run one after the other).
[[nodiscard]] ScenarioSummary run_robot_scenario(CanSender& can, TextSink& text) noexcept;

}  // namespace cellguard::firmware

#endif  // CELLGUARD_FIRMWARE_ROBOT_SCENARIO_HPP
