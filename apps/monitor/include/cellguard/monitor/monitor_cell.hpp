// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file monitor_cell.hpp
/// What the monitor's cycle works on, built once at start-up from its
/// configuration: the sensors, the grid and its storage, the compiled zones,
/// the prior (from a file or from simulated empty frames), the sensors' ray
/// tables (or, with [fusion] method = "footprint", footprint fusion's
/// workspaces, one per sensor) and their commissioned views of the empty cell. The steps run in
/// the order of the monitor's start-up (configure, then the CAN output in
/// main, then build_prior, then build_tables), print what the monitor has
/// always printed, and say why they stop with the monitor's exit status.
#ifndef CELLGUARD_MONITOR_MONITOR_CELL_HPP
#define CELLGUARD_MONITOR_MONITOR_CELL_HPP

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_model.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/host/sim/robot_cell.hpp"
#include "cellguard/host/sim/scene_file.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility_params.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "cellguard/safety/cycle.hpp"
#include "cellguard/safety/monitoring_cases.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::monitor {

/// Why a start-up step stopped: the exit status (0: it did not) and the
/// message, which the monitor prints after "cellguard-monitor: ".
struct SetupError {
    int exit_status = 0;  ///< 1: runtime error, 2: configuration error
    std::string message;  ///< e.g. "configuration error: line 12: zone 'a': ..."
    /// True when the step stopped.
    [[nodiscard]] bool failed() const noexcept { return exit_status != 0; }
};

/// The settings this monitor cannot honour, refused before anything starts
/// (exit status 2): restart_interlock.reset_required = true in a cell
/// without a PLC command (no robot, no monitoring cases), since the reset
/// request travels in the command (ResetRequest) and the monitor has no
/// other reset input, so its restart interlock would hold the stop for good
/// after the first one; the message names opt_out.reset_required and the
/// PLC's restart interlock.
SetupError check_start_settings(const cell::MonitorConfig& cfg);

/// Prints each protection @p cfg turns off ([opt_out]) to @p out: its
/// name, the configuration's reason and what is lost; nothing without one.
void print_opt_outs(const cell::MonitorConfig& cfg, std::FILE* out);

/// The simulator's view of configured sensor @p s (the recorded ones too:
/// their layout, rays and work bound); @p error is set when the simulator
/// cannot take its pose (@p simulated_background: it must also render a
/// recorded sensor's view of the empty cell for the prior).
sim::SensorSpec to_spec(const cell::SensorSettings& s, bool simulated_background, std::string& error);

/// The controller's configuration from @p cfg.
ControllerConfig controller_config(const cell::MonitorConfig& cfg);

class MonitorCell;
/// @p cc with the fusion side of @p cell: with footprint fusion its method,
/// limits, the cell's workspaces and @p runner (nullptr: one core).
void attach_fusion(ControllerConfig& cc, const cell::MonitorConfig& cfg, const MonitorCell& cell, TaskRunner* runner);
/// @p cc with the robot side of @p cell: its cases, robot model, mask
/// storage, margin, separation parameters and command age (nothing when the
/// cell has neither cases nor a robot).
void attach_robot(ControllerConfig& cc, const cell::MonitorConfig& cfg, MonitorCell& cell);

/// See the file comment. Not copyable or movable: the controller keeps
/// references into it.
class MonitorCell {
public:
    MonitorCell() = default;
    MonitorCell(const MonitorCell&) = delete;
    MonitorCell& operator=(const MonitorCell&) = delete;
    MonitorCell(MonitorCell&&) = delete;
    MonitorCell& operator=(MonitorCell&&) = delete;
    ~MonitorCell() = default;

    /// The sensors, the grid and its storage, the zones (exit status 2 for a
    /// sensor or zone the configuration gets wrong).
    SetupError configure(const cell::MonitorConfig& cfg);
    /// The prior, read from its file or computed from simulated empty frames
    /// by @p method (the monitor's: probabilistic; the detection experiment
    /// compares methods); prints "prior: ..." to @p out (nullptr: silent).
    SetupError build_prior(const cell::MonitorConfig& cfg, std::FILE* out,
                           PriorMethod method = PriorMethod::kProbabilistic);
    /// The simulated sensors' ray tables (none with footprint fusion: its
    /// workspaces instead) and views of the empty cell; prints the background
    /// check, the tables or workspaces and the work bound to @p out.
    SetupError build_tables(const cell::MonitorConfig& cfg, std::FILE* out);
    /// The monitoring cases, the robot (its URDF imported, written as a robot
    /// image and loaded back from those bytes, as a controller with the image
    /// in flash does), its mask storage, and the demo scene with its
    /// simulated robot and PLC; prints the robot's summary to @p out. Exit
    /// status 2 for a configuration the cell cannot take. Call after configure().
    SetupError configure_robot(const cell::MonitorConfig& cfg, std::FILE* out);

    std::vector<sim::SensorSpec> specs;            ///< one per configured sensor
    GridGeometry grid;                             ///< the grid
    std::vector<std::uint32_t> zone_mask;          ///< the zones' membership mask
    CompiledZones zones;                           ///< compiled into zone_mask
    SensorModelTable model;                        ///< the sensor model
    std::vector<std::int16_t> frame_log_odds;      ///< the frame grid's log-odds
    std::vector<std::uint8_t> frame_observed;      ///< the frame grid's observed flags
    EvidenceGrid frame_grid;                       ///< the cycle's evidence grid
    std::vector<std::int16_t> fusion_scratch;      ///< fuse_sensor's per-sensor opinions
    std::vector<std::int16_t> prior;               ///< one prior value per voxel
    sim::SimulatedFrame layout;                    ///< every sensor's view of the empty (reference) cell
    std::vector<host::OwnedRayTable> tables;       ///< per sensor; built for the simulated ones
    std::vector<BackgroundReference> backgrounds;  ///< per sensor: its view in layout or in background_views
    /// Per sensor: its commissioned view read from prior.background_file (empty without one).
    std::vector<std::vector<float>> background_views;
    std::uint32_t prior_payload_crc = 0U;  ///< CRC-32 of the prior's payload (the image's field, or computed)
    /// Footprint fusion's storage of one sensor (fusion.method = "footprint").
    struct FootprintStorage {
        std::vector<float> pyramid_min;             ///< depth_pyramid_cells of the sensor's image
        std::vector<float> pyramid_max;             ///< the same
        std::vector<std::uint8_t> pyramid_invalid;  ///< the same
        std::vector<std::int16_t> opinions;         ///< one per voxel
        std::vector<FootprintEntry> entries;        ///< the sensor's footprint table's storage
        FootprintTable table;                       ///< over entries, made at start
    };
    std::vector<FootprintStorage> footprint_storage;   ///< per sensor, with footprint fusion
    std::vector<FootprintWorkspace> footprint_spaces;  ///< per sensor, over footprint_storage
    CycleWorkBound work{};                             ///< the cycle's work bound (build_tables)

    MonitoringCases cases;                  ///< the configured cases (all_zones() when none are)
    bool has_cases = false;                 ///< the configuration has [[cases]]
    std::vector<std::uint8_t> robot_image;  ///< the robot image as written (empty: no robot)
    LoadedRobot robot{};                    ///< the robot, loaded back from robot_image
    std::vector<std::uint8_t> robot_mask;   ///< one byte per voxel, the controller's robot mask
    bool has_scene = false;                 ///< the demo renders a scene file (cfg.demo_scene)
    sim::SceneFile scene;                   ///< that scene (its static boxes are the background)
    sim::RobotCellSimulation simulation;    ///< its people, robot and PLC schedule (with a robot)

    /// The empty cell's observed flags (one per voxel) from the simulated
    /// background; empty with a prior file. The picture's unseen zone parts.
    std::vector<std::uint8_t> background_observed;
    /// The scene the background, the ray tables and the views of the empty
    /// cell come from: the scene file's static boxes, or the paper's reference scene.
    [[nodiscard]] sim::Scene background_scene() const;

    /// With footprint tables: how often they were made (once per camera at
    /// start; more means a reading's geometry differed from the configuration's).
    void write_footprint_summary(std::FILE* out) const;

private:
    SetupError configure_robot_model(const cell::MonitorConfig& cfg, std::FILE* out);
    SetupError attach_backgrounds(const cell::MonitorConfig& cfg, std::FILE* out);
    SetupError allocate_footprint_workspaces(std::FILE* out);
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_MONITOR_CELL_HPP
