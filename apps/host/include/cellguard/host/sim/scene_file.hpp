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
///     path = [[-0.8, 0.6], [0.6, 0.6]]  # waypoints on the floor (x, y), at least one (required)
///     loop = false                  # walk the closed path again and again instead of stopping at its end
#ifndef CELLGUARD_HOST_SIM_SCENE_FILE_HPP
#define CELLGUARD_HOST_SIM_SCENE_FILE_HPP

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/host/sim/noise.hpp"
#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::sim {

/// A person of simple solids (legs, torso, arms, neck, head: boxes) walking
/// along a polyline at constant speed, facing the direction of travel.
struct PersonSpec {
    double height_m = 1.75;             ///< standing height; every part scales with it
    double speed_mps = 1.0;             ///< walking speed along the path
    std::vector<Eigen::Vector2d> path;  ///< waypoints on the floor
    bool loop = false;                  ///< repeat the closed path instead of stopping at its end
};

/// The boxes of @p person at time @p t seconds (foreground, 8 boxes): the
/// position is the point at arc length speed * t along the path (clamped to
/// its end, or wrapped when loop), legs and arms swing with the gait.
std::vector<Box> person_boxes(const PersonSpec& person, double t);

/// A scene as read from a file.
struct SceneFile {
    std::string name;                 ///< label
    std::string description;          ///< free text
    std::uint64_t seed = 1U;          ///< base seed of the noise
    Scene scene;                      ///< floor and boxes (people not included)
    std::vector<PersonSpec> people;   ///< walking people
    std::vector<SensorSpec> sensors;  ///< the sensors
    std::vector<NoiseModel> noise;    ///< one model per sensor
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
