// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file picture.hpp
/// A picture of the configuration for the integrator to check before a robot
/// moves: the grid, the background (the prior's voxels that an object cannot
/// reach) and the zones, seen from above and from one sensor.
///
/// - Top view (x right, y up): the grid's footprint; per voxel column the
///   highest background voxel in grey (darker = higher); every zone's voxel
///   footprint tinted by kind (protective red, warning yellow) with its
///   border and its number; light lines every 0.5 m.
/// - Sensor view: the chosen sensor's image, ray cast through the grid: the
///   first background voxel along the ray in grey (darker = farther), the
///   zone voxels in front of it tinted (a thicker zone looks more opaque),
///   free grid space white, space outside the grid dark; the grid's edges
///   and the zones' edges drawn over it.
/// - With a robot (PictureRobot): its capsules at one pose (the demo
///   scene's first trajectory keyframe, else all joints 0; the header says
///   which), filled blue in the top view (lighter = higher) and shaded in
///   the sensor view; the outline of its mask margin (capsules grown by the
///   margin) dashed in both views; in the top view the footprints of the
///   separation distances around it as labelled rings: S_p of each speed
///   class and the reduced-speed distance. The top-view footprint of
///   everything within distance D of the capsules (at any height) is the
///   union of each capsule's segment, projected onto the floor, grown by
///   its radius + D: the rings are exactly that outline.
/// - A legend with every zone's number, name, kind, shape, extent, voxels
///   and monitoring cases; every case's number, name and zones; the robot's
///   pose, margin and distances.
/// Text uses a 5 x 7 bitmap font.
#ifndef CELLGUARD_MONITOR_PICTURE_HPP
#define CELLGUARD_MONITOR_PICTURE_HPP

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/io/png.hpp"
#include "cellguard/host/sim/trajectory.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::monitor {

using host::RgbImage;  ///< the picture is an RGB image (written by host::write_png)

/// One sensor as the picture needs it.
struct PictureSensor {
    std::string name;                                        ///< label
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> cell (x right, y down, z forward)
    PinholeIntrinsics intrinsics{};                          ///< its image
    double max_range = 10.0;                                 ///< metres
};

/// Colours of the picture (RGB).
struct PictureColour {
    std::uint8_t r;  ///< red
    std::uint8_t g;  ///< green
    std::uint8_t b;  ///< blue
};
/// Protective zones.
constexpr PictureColour kProtectiveColour{220, 30, 30};
/// Warning zones.
constexpr PictureColour kWarningColour{245, 190, 0};

/// A distance around the robot, drawn as a ring in the top view.
struct PictureRing {
    double distance_m = 0.0;        ///< from the capsules' surfaces, metres
    std::string name;               ///< legend text, e.g. "S_p speed class 0 (full)"
    std::string tag;                ///< short label on the ring, e.g. "S_p0"
    PictureColour colour{0, 0, 0};  ///< line colour
};

/// The robot as the picture draws it.
struct PictureRobot {
    std::string name;                ///< the model's name
    RobotPose pose{};                ///< its capsules in the cell frame
    JointPositions joints{};         ///< the joints of @ref pose
    std::string pose_source;         ///< where the pose comes from (header and legend)
    double margin_m = 0.0;           ///< the mask margin: the dashed outline around the capsules
    std::vector<PictureRing> rings;  ///< the separation distances
};

/// A monitoring case for the legend.
struct PictureCase {
    int number = 0;                ///< its number on CAN
    std::string name;              ///< label
    std::uint32_t zone_mask = 0U;  ///< zone z = bit z
};

/// What to draw.
struct PictureInput {
    std::string title;                         ///< first line (e.g. the config file)
    GridGeometry grid{};                       ///< the grid
    const CompiledZones* zones = nullptr;      ///< compiled for @ref grid (required)
    std::vector<std::string> zone_names;       ///< one per zone
    Span<const std::int16_t> prior{};          ///< one value per voxel
    std::int16_t accessible_min_prior = -754;  ///< below this (or the sentinel) a voxel is background
    std::vector<PictureSensor> sensors;        ///< every sensor
    std::size_t view_sensor = 0U;              ///< index of the sensor whose view is drawn
    const PictureRobot* robot = nullptr;       ///< the robot (nullptr: none)
    std::vector<PictureCase> cases;            ///< the monitoring cases (empty: none configured)
    /// One flag per voxel, nonzero: some sensor observes it in the empty
    /// cell (empty: not known). Zone columns holding an accessible voxel no
    /// sensor observes are hatched in the top view: the zone evaluation
    /// counts such voxels as unseen (unknown space is never taken for empty).
    Span<const std::uint8_t> observed{};
};

/// Where the top view landed in the picture (for tests and tools).
struct PictureLayout {
    int top_x = 0;            ///< pixel column of the top view's left edge (grid x minimum)
    int top_y = 0;            ///< pixel row of the top view's top edge (grid y maximum)
    int voxel_px = 0;         ///< pixels per voxel edge in the top view
    int view_x = 0;           ///< pixel column of the sensor view's left edge
    int view_y = 0;           ///< pixel row of the sensor view's top edge
    int view_w = 0;           ///< sensor view width, pixels
    int view_h = 0;           ///< sensor view height, pixels
    double view_scale = 1.0;  ///< picture pixels per sensor pixel
};

/// The top-view pixel (column, row) of the centre of voxel column (@p ix, @p iy).
void top_view_pixel(const PictureLayout& layout, const GridGeometry& grid, int ix, int iy, int& px, int& py);

/// The hatching of unseen zone parts (PictureInput::observed).
constexpr PictureColour kUnseenColour{200, 120, 0};
/// The robot's capsules (lighter where higher in the top view, shaded in the sensor view).
constexpr PictureColour kRobotColour{40, 90, 190};
/// The mask margin's dashed outline.
constexpr PictureColour kRobotMarginColour{0, 30, 110};

/// The cell point (x, y) at the centre of top-view pixel (@p px, @p py).
Eigen::Vector2d top_view_point(const PictureLayout& layout, const GridGeometry& grid, int px, int py);

/// The robot of @p cfg for the picture: @p model (as loaded, standing at its
/// base) at the first keyframe of @p trajectory when it has one (a demo
/// scene's), else at all joints 0; its mask margin; rings at S_p of every
/// speed class and at the reduced-speed distance (cfg.robot.separation).
PictureRobot picture_robot(const cell::MonitorConfig& cfg, const RobotModel& model,
                           const sim::JointTrajectory& trajectory);

/// Renders the picture; @p layout (optional) receives where things are.
RgbImage render_config_picture(const PictureInput& input, PictureLayout* layout = nullptr);

/// Draws @p text with its top-left corner at (@p x, @p y), each font pixel
/// @p scale x @p scale picture pixels; returns the x after the last character.
int draw_text(RgbImage& image, int x, int y, const std::string& text, PictureColour colour, int scale);

/// The picture's input for the arguments of write_config_picture, into
/// @p in; false with @p error set when the sensor is unknown.
bool config_picture_input(const std::string& title, const cell::MonitorConfig& cfg, const GridGeometry& grid,
                          const CompiledZones& zones, const std::vector<sim::SensorSpec>& specs,
                          Span<const std::int16_t> prior, const std::string& view_sensor, const PictureRobot* robot,
                          PictureInput& in, std::string& error);

/// The monitor's --picture: draws the configuration @p cfg (its grid compiled
/// into @p grid and @p zones, the sensors @p specs, the @p prior in use) as
/// seen by the sensor named or numbered (from 1) @p view_sensor (empty: the
/// first) and writes it as a PNG to @p path. False with @p error set when the
/// sensor is unknown or the file cannot be written. With @p robot (nullptr:
/// none) the robot is drawn too; the cases come from cfg.cases.
bool write_config_picture(const std::string& path, const std::string& title, const cell::MonitorConfig& cfg,
                          const GridGeometry& grid, const CompiledZones& zones,
                          const std::vector<sim::SensorSpec>& specs, Span<const std::int16_t> prior,
                          const std::string& view_sensor, const PictureRobot* robot, std::string& error);

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_PICTURE_HPP
