// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file scene_file.hpp
/// Scenes of the simulated workcell in TOML: sensors with their noise models,
/// boxes marked background or foreground, people made of boxes walking along
/// a path. Deterministic: a scene file and a time give one Scene, and the
/// file's seed fixes the noise of every frame (render_noisy_frame).
///
/// Format (every key optional unless marked; unknown keys are errors):
///
///     name = "large"                # a label
///     description = "..."
///     seed = 1                      # base seed of the sensor noise
///     include = ["background.toml"] # files read first (relative to this one):
///                                   # their boxes and people come first, their
///                                   # sensors apply when this file has none
///     floor = true                  # whether the floor plane z = 0 reflects
///
///     [[sensor]]                    # none: paper_sensors() with paper_noise_models()
///     name = "lidar-a"
///     kind = "flash_lidar"          # "ideal", "flash_lidar" or "stereo" (required)
///     position = [-1.9, -1.9, 1.9]  # metres (required)
///     target = [0.0, 0.0, 0.0]      # a point on the optical axis (required)
///     width = 176                   # pixels (required)
///     height = 144                  # pixels (required)
///     hfov_deg = 43.6               # fields of view, degrees (required unless focal_px)
///     vfov_deg = 34.6
///     focal_px = 277.0              # focal length in pixels, in place of the fields of view
///     max_range = 10.0
///     [sensor.noise]                # the fields of FlashLidarNoise or StereoNoise, by name
///     range_sigma_base_m = 0.004
///
///     [[box]]
///     center = [0.4, -0.25, 0.2]    # metres (required)
///     size = [0.4, 0.6, 0.4]        # edge lengths along the box's own axes (required)
///     yaw_deg = 17.0                # rotation about +z
///     role = "background"           # or "foreground" (required)
///
///     [[person]]                    # always foreground
///     height_m = 1.75
///     speed_mps = 1.0
///     start_s = 0.0                 # stands at the first waypoint until then
///     path = [[-0.8, 0.6], [0.6, 0.6, 2.0]]  # waypoints on the floor (x, y), at least one (required),
///                                   # each optionally with a dwell time: seconds to stand there on arrival
///     loop = false                  # walk the closed path again and again instead of stopping at its end
///
///     [robot]                       # a robot arm (its model comes from the caller: RobotModel)
///     model = "robot-arm.urdf"      # the model's file, relative to this one (the caller loads it)
///     position = [0.0, 0.0, 0.0]    # where its root link stands, metres (required)
///     yaw_deg = 0.0                 # its rotation about +z
///     [[robot.keyframe]]            # at least one; times strictly increasing (trajectory.hpp)
///     t = 0.0                       # seconds (required)
///     joints = [0.0, -1.2, 1.6, 0.0, 0.0, 0.0]  # rad / m by command index, 1..7 (required)
///
///     [[command]]                   # the simulated PLC's schedule; the first at t = 0
///     t = 0.0                       # from then on (required)
///     case = 0                      # the monitoring case, 0..15 (required)
///     speed_class = 0               # the robot's speed class, 0..3
///
/// A keyframe's values are checked here on their own (finite, times
/// increasing, one joint count); against the robot (joint count, limits,
/// speeds) by check_trajectory once the caller has the model.
#ifndef CELLGUARD_HOST_SIM_SCENE_FILE_HPP
#define CELLGUARD_HOST_SIM_SCENE_FILE_HPP

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include <array>

#include "cellguard/host/sim/noise.hpp"
#include "cellguard/host/sim/trajectory.hpp"
#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::sim {

/// A person of simple solids (legs, torso, arms, neck, head: boxes) walking
/// along a polyline at constant speed, facing the direction of travel.
struct PersonSpec {
    double height_m = 1.75;             ///< standing height; every part scales with it
    double speed_mps = 1.0;             ///< walking speed along the path
    double start_s = 0.0;               ///< stands at the first waypoint until this time, seconds
    std::vector<Eigen::Vector2d> path;  ///< waypoints on the floor
    std::vector<double> dwell_s;        ///< seconds to stand at each waypoint on arrival; empty: none
    bool loop = false;                  ///< repeat the closed path instead of stopping at its end
};

/// Boxes of one person.
constexpr std::size_t kPersonBoxCount = 8U;
/// The boxes of one person at one time.
using PersonBoxes = std::array<Box, kPersonBoxCount>;

/// The boxes of @p person at time @p t seconds (foreground, 8 boxes): the
/// position is the point at arc length person_arc_length along the path
/// (clamped to its end, or wrapped when loop), legs and arms swing with the gait.
std::vector<Box> person_boxes(const PersonSpec& person, double t);

/// person_boxes into caller storage: the same boxes, bit for bit; allocates nothing.
void person_boxes_into(const PersonSpec& person, double t, PersonBoxes& out) noexcept;

/// The distance @p person has walked at time @p t: speed * (t - start_s),
/// at least 0, less the time spent standing at waypoints (dwell_s).
double person_arc_length(const PersonSpec& person, double t) noexcept;

/// Where on the floor @p person stands at time @p t (the centre of the boxes' footprint).
Eigen::Vector2d person_position(const PersonSpec& person, double t) noexcept;

/// A robot in the scene: where it stands, how it moves.
struct RobotScenario {
    bool present = false;  ///< the file has a [robot] table
    std::string model;     ///< the model's file (resolved against the scene's folder), may be ""
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< root link position, metres
    double yaw = 0.0;                                    ///< root link rotation about +z, radians
    JointTrajectory trajectory;                          ///< keyframes (values checked, not yet against a model)
};

/// @p model standing where @p robot says: base_xyz = position, base_wxyz =
/// the rotation yaw about +z (replacing the model's own base).
void place_robot_base(const RobotScenario& robot, RobotModel& model) noexcept;

/// A scene as read from a file.
struct SceneFile {
    std::string name;                 ///< label
    std::string description;          ///< free text
    std::uint64_t seed = 1U;          ///< base seed of the noise
    Scene scene;                      ///< floor and boxes (people not included)
    std::vector<PersonSpec> people;   ///< walking people
    std::vector<SensorSpec> sensors;  ///< the sensors
    std::vector<NoiseModel> noise;    ///< one model per sensor
    RobotScenario robot;              ///< the robot, if present
    CommandSchedule commands;         ///< the simulated PLC's case and speed class over time
};

/// The outcome of loading a scene file: ok, or the first error with its place.
struct SceneLoad {
    bool ok = false;    ///< whether scene is valid
    std::string error;  ///< "source:line:column: key: what" when not ok
    SceneFile scene;    ///< the scene when ok
};

/// Parses scene TOML @p text; @p source_name labels errors, @p base_dir
/// resolves includes ("" = the working directory).
SceneLoad parse_scene(const std::string& text, const std::string& source_name, const std::string& base_dir = "");

/// Reads and parses the scene file @p path.
SceneLoad load_scene_file(const std::string& path);

/// The scene at time @p t: the file's boxes plus every person's boxes.
Scene scene_at(const SceneFile& file, double t);

/// The background of @p scene: the floor and the boxes marked background.
Scene background_of(const Scene& scene);

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_SCENE_FILE_HPP
