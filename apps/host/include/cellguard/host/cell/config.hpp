// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file config.hpp
/// The monitor's configuration, loaded from one TOML file, and the built-in
/// demo configuration (the same as apps/monitor/config/paper-cell.toml).
///
/// Every error message names the file, the line and column, and the key
/// (e.g. "cell.toml:12:1: zones[1].kind: expected \"protective\" or
/// \"warning\""); a missing key names the line of the table that lacks it.
/// Unknown keys are errors too (a typo must not silently fall back to a default).
#ifndef CELLGUARD_HOST_CELL_CONFIG_HPP
#define CELLGUARD_HOST_CELL_CONFIG_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/can/clock_rate_check.hpp"
#include "cellguard/can/command_frame.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/host/cell/depth_conditioning.hpp"
#include "cellguard/robot/separation.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::cell {

/// The voxel grid.
struct GridSettings {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< minimum corner, metres
    double voxel_size = 0.05;                          ///< edge, metres
    int dims[3] = {0, 0, 0};                           ///< voxels along x, y, z
};

/// The depth pixel format a live camera is set to.
enum class CameraPixelFormat : std::uint8_t {
    kCoord3dC16 = 0,  ///< GenICam Coord3D_C16: depth along the optical axis, scale and offset from Scan3d
    kMono16 = 1,      ///< Mono16 read as depth; scale and offset must be configured
};

/// Where a sensor's pinhole intrinsics come from.
enum class IntrinsicsSource : std::uint8_t {
    kFieldOfView = 0,  ///< sensors.fov: centred principal point, focal lengths from the angles
    kConfig = 1,       ///< sensors.intrinsics = { fx, fy, cx, cy }
    kDevice = 2,       ///< sensors.intrinsics = "device": a live camera's Scan3d features, read at start
};

/// camera.max_stamp_error_ms when absent, microseconds: the widest device
/// time stamp error accepted without opt_out.camera_stamp_tolerance.
constexpr std::uint64_t kDefaultMaxStampErrorUs = 20000U;

/// A live GigE Vision camera ([sensors.camera], optional; absent: the
/// simulator or recorded frames). Exactly one of address, serial and id opens it.
struct CameraSettings {
    bool enabled = false;  ///< the sensor has a [sensors.camera] table
    /// camera.address: IPv4 address, opened directly, no discovery (tests use 127.0.0.N).
    std::string address;
    /// camera.serial: opened by discovery on the host's networks (the
    /// opened camera's DeviceSerialNumber must equal it).
    std::string serial;
    std::string device_id;  ///< camera.id: an Aravis device ID ("Vendor-Model-Serial")
    /// camera.expected_serial: checked against DeviceSerialNumber at every
    /// (re)connection whichever key opened it (a camera swapped for another is refused).
    std::string expected_serial;
    CameraPixelFormat pixel_format = CameraPixelFormat::kCoord3dC16;  ///< camera.pixel_format
    /// camera.depth_scale / depth_offset present: these, metres per unit and
    /// metres (Mono16 must give them); absent: the Scan3d features (Coord3D_C16 only).
    bool has_depth_scale = false;
    double depth_scale_m = 0.001;                    ///< camera.depth_scale, metres per raw unit
    double depth_offset_m = 0.0;                     ///< camera.depth_offset, metres
    double frame_rate_hz = 30.0;                     ///< camera.frame_rate, AcquisitionFrameRate
    int packet_size = 0;                             ///< camera.packet_size, bytes; 0: the camera's
    int socket_buffer_bytes = 1048576;               ///< camera.socket_buffer_kib * 1024
    std::uint64_t reconnect_interval_us = 1000000U;  ///< camera.reconnect_interval_ms: between reopen attempts
    /// camera.max_stamp_error_ms: most a frame's mapped device time stamp may
    /// differ from the offset estimate (device clock jump or skew beyond it:
    /// the frame is refused). Above kDefaultMaxStampErrorUs only with
    /// opt_out.camera_stamp_tolerance.
    std::uint64_t max_stamp_error_us = kDefaultMaxStampErrorUs;
    int line = 0;  ///< line of the [sensors.camera] table
};

/// Recorded depth images of one sensor (`depth_files`, depth_input.hpp).
struct DepthRecordingSettings {
    /// .npy files (relative paths resolved against the config file's
    /// directory), one per cycle in order, cycled; empty: not a recording.
    std::vector<std::string> files;
    bool raw = false;              ///< the files are '<u2' raw units; false: '<f4' metres
    double depth_scale_m = 0.001;  ///< raw: depth_scale, metres per raw unit
    double depth_offset_m = 0.0;   ///< raw: depth_offset, metres
};

/// One static depth sensor.
struct SensorSettings {
    std::string name;                                    ///< label
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< optical centre, metres
    bool has_target = false;                             ///< aimed at `target` (else `rotation`)
    Eigen::Vector3d target = Eigen::Vector3d::Zero();    ///< point on the optical axis
    /// sensor -> cell rotation, from rotation = { w, x, y, z } (named keys: no order to mistake)
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    int width = 0;                                                        ///< image columns
    int height = 0;                                                       ///< image rows
    IntrinsicsSource intrinsics_source = IntrinsicsSource::kFieldOfView;  ///< fov, intrinsics table or "device"
    double hfov_deg = 0.0;    ///< horizontal field of view (kFieldOfView; otherwise derived from fx and width)
    double vfov_deg = 0.0;    ///< vertical field of view (kFieldOfView; otherwise derived from fy and height)
    double fx = 0.0;          ///< kConfig / kDevice: focal length along columns, pixels
    double fy = 0.0;          ///< kConfig / kDevice: focal length along rows, pixels
    double cx = 0.0;          ///< kConfig / kDevice: principal point, column
    double cy = 0.0;          ///< kConfig / kDevice: principal point, row
    CameraSettings camera;    ///< a live camera (camera.enabled), else simulated or recorded
    double max_range = 10.0;  ///< metres
    /// Recorded frames (PCD files, relative paths resolved against the config
    /// file's directory), one per cycle in order, cycled; empty: the simulator.
    std::vector<std::string> pcd_files;
    DepthRecordingSettings recording;  ///< recorded depth images (depth_files), through the camera path
    int line = 0;                      ///< line of its table in the file
};

/// One zone and where it was configured.
struct ZoneSettings {
    std::string name;  ///< label
    ZoneConfig zone;   ///< kind, shape, thresholds
    int line = 0;      ///< line of its table in the file
};

/// One monitoring case: a number the PLC selects and the zones it activates.
struct CaseSettings {
    std::string name;                ///< label
    int number = 0;                  ///< case number on CAN, 0..15
    std::vector<std::string> zones;  ///< names of its zones (each configured)
    std::uint32_t zone_mask = 0U;    ///< the same as bits, zone z = bit z (configuration order)
    int line = 0;                    ///< line of its table in the file
};

/// The robot in the cell, its command from the PLC, and speed and separation monitoring.
struct RobotSettings {
    bool enabled = false;                            ///< a [robot] table is present
    std::string urdf;                                ///< robot description (relative: to the config file's directory)
    std::vector<std::string> joints;                 ///< movable joints in the PLC's command order
    std::vector<std::string> stroke_joints;          ///< a gripper's finger joints (urdf_import.hpp), not sent
    Eigen::Vector3d base = Eigen::Vector3d::Zero();  ///< robot base position in the cell, metres
    double base_yaw_deg = 0.0;                       ///< rotation of the base about the cell's z axis
    double margin_m = 0.0;                           ///< growth of every capsule for the robot's voxel mask
    std::uint64_t max_command_age_us = 0U;           ///< a command older than this at a cycle's start is stale
    SeparationParams separation{};                   ///< speed and separation monitoring
    /// separation.detection_capability_mm: the measured detection capability
    /// d the intrusion distance rests on (0: not stated; then C >= 850 mm).
    double detection_capability_mm = 0.0;
    int line = 0;  ///< line of the [robot] table
};

/// The smallest intrusion distance C (metres) ISO 13855 gives for a
/// detection capability of @p d_mm (0: not stated): max(0, 8 (d - 14)) mm up
/// to 40 mm, else (and when not stated) 850 mm, the reach of an arm.
double minimum_intrusion_distance(double d_mm);

/// The smallest mask margin that covers the robot's motion between its
/// command and the sensors' frames: the fastest robot point (class 0) over
/// the command's age limit plus one period, the sensing uncertainty Z_d,
/// and the joints' raw resolution (half a unit per joint over a reach of
/// 2 m). certification/safety-manual.md derives it.
double minimum_mask_margin(const RobotSettings& robot, std::uint64_t period_us);

struct MonitorConfig;
/// The oldest PLC command a cycle of @p cfg accepts, microseconds: the
/// robot's max_command_age_ms, or two periods in a cell with cases but no robot.
std::uint64_t command_age_limit_us(const MonitorConfig& cfg);

/// Where the prior comes from.
enum class PriorSource : std::uint8_t {
    kFile = 0,                 ///< a prior image file (certification/prior-image-format.md)
    kSimulatedBackground = 1,  ///< computed at start-up from simulated empty frames (demo)
};

/// The prior.
struct PriorSettings {
    PriorSource source = PriorSource::kSimulatedBackground;  ///< where it comes from
    std::string file;           ///< kFile: path (relative paths: to the config file's directory)
    int background_frames = 8;  ///< kSimulatedBackground: empty frames accumulated
    /// kFile: the sensors' commissioned views (background_files.hpp), bound
    /// to the prior by its CRC; empty: none (simulated sensors then use
    /// their render of the empty scene)
    std::string background_file;
};

/// cycle.max_repeated_frames when absent: a sensor whose data are
/// bit-identical in 3 new frames in a row is frozen.
constexpr std::uint32_t kDefaultMaxRepeatedFrames = 3U;
/// cycle.background_match when absent: a frame must show half its view of the empty cell.
constexpr double kDefaultBackgroundMatch = 0.5;
/// cycle.background_changed_pixels when absent: more pixels than this
/// beyond the view (by background_tolerance_m) show a changed background.
constexpr std::uint32_t kDefaultBackgroundChangedPixels = 20U;
/// cycle.background_changed_cycles when absent: that many frames in a row
/// showing a changed background latch kPriorCheckFailed (0 = off).
constexpr std::uint32_t kDefaultBackgroundChangedCycles = 3U;

/// The CAN output: an interface, or a candump log file.
struct CanSettings {
    std::string interface_name;  ///< SocketCAN interface; empty: write the log
    std::string log_file =
        "monitor-demo.log";  ///< candump log path when no interface is given (relative: to the working directory)
    std::string log_interface_name = "vcan0";  ///< interface name written in the log lines
    SafetyChannelConfig channel{};             ///< CAN IDs, data IDs, data ID mode
    CommandChannelConfig command{};            ///< the PLC's command: CAN IDs, data IDs (can.command_id, ...)
    /// The controller clock's rate against the PLC's samples (clock_rate_check.hpp):
    /// can.command_period_ms (the PLC's nominal sample period; 0 or absent: off),
    /// can.clock_rate_tolerance_percent (default 2), can.clock_rate_window (PLC periods, default 50).
    ClockRateConfig clock_rate{};
};

/// How the cycle fuses its depth images ([fusion], optional).
struct FusionSettings {
    FusionMethod method = FusionMethod::kRay;  ///< fusion.method: "ray" (default) or "footprint"
    FootprintParams params{};                  ///< fusion.exact_footprint_max
    /// fusion.threads: cores for footprint fusion; 1 (default): the calling
    /// thread alone, no worker pool.
    int threads = 1;
    int line = 0;  ///< line of the [fusion] table (0: absent)
};

/// Most fusion.threads (a worker per core of an industrial PC).
constexpr int kMaxFusionThreads = 16;  // port/linux WorkerPool's kMaxWorkers

/// A protection the configuration can turn off, by its [opt_out] key.
struct Protection {
    const char* name;     ///< the key in [opt_out], e.g. "frozen_sensor_check"
    const char* setting;  ///< the setting that turns it off, e.g. "cycle.max_repeated_frames = 0"
    const char* loses;    ///< what the user loses with it off (printed at start, the safety manual's table)
};

/// Every protection the configuration can turn off (fixed, compiled in):
/// reset_required, clock_rate_check, frozen_sensor_check,
/// background_view_check, background_change_check, camera_stamp_tolerance,
/// camera_identity_check, watchdog_device. @p count receives their number.
const Protection* protections(std::size_t& count);

/// One protection turned off by the configuration: [opt_out] NAME = "REASON".
struct OptOut {
    std::string name;     ///< Protection::name
    std::string reason;   ///< the configuration's stated reason (non-empty)
    std::string setting;  ///< Protection::setting
    std::string loses;    ///< Protection::loses
};

/// The depth filter before fusion ([depth_filter], optional; depth_conditioning.hpp):
/// every filter off by default. A filter removes readings, so it costs
/// detection capability: the table needs a stated reason when one is on.
struct DepthFilterSettings {
    DepthConditioning filter{};  ///< the filters (depth_filter.edge_jump_percent, ...; all off by default)
    std::string reason;          ///< depth_filter.reason: why it is on (non-empty when filter.on())
};

/// Everything the monitor needs.
struct MonitorConfig {
    GridSettings grid;                         ///< the grid
    std::vector<SensorSettings> sensors;       ///< 1..kMaxSensors sensors
    std::vector<ZoneSettings> zones;           ///< 1..16 zones
    std::vector<CaseSettings> cases;           ///< monitoring cases; empty: one case 0 with every zone
    RobotSettings robot;                       ///< the robot (robot.enabled false: none)
    PriorSettings prior;                       ///< the prior
    FusionSettings fusion;                     ///< how depth images are fused
    DepthFilterSettings depth_filter;          ///< the depth filter before fusion (off)
    CanSettings can;                           ///< the CAN output
    std::uint64_t period_us = 100000U;         ///< cycle period
    std::uint64_t budget_us = 100000U;         ///< cycle deadline
    std::uint64_t max_frame_age_us = 200000U;  ///< older frames are stale
    std::size_t table_check_bytes = 1048576U;  ///< ray-table bytes CRC-checked per cycle (cycle.table_check_kib)
    std::uint32_t max_repeated_frames =
        kDefaultMaxRepeatedFrames;          ///< frozen-sensor limit, 0 = off (cycle.max_repeated_frames)
    std::size_t zone_check_bytes = 16384U;  ///< zone-mask bytes CRC-checked per cycle (cycle.zone_check_kib)
    float background_match = static_cast<float>(
        kDefaultBackgroundMatch);  ///< fraction of the commissioned view a frame must show, 0 = off (cycle.background_match)
    float background_tolerance_m = 0.05F;  ///< depth tolerance of that comparison (cycle.background_tolerance_m)
    /// changed background: more pixels beyond the view than this (cycle.background_changed_pixels)
    std::uint32_t background_changed_pixels = kDefaultBackgroundChangedPixels;
    /// ... in this many frames in a row latch the prior fault, 0 = off (cycle.background_changed_cycles)
    std::uint32_t background_changed_cycles = kDefaultBackgroundChangedCycles;
    std::uint64_t restart_delay_us = 500000U;  ///< restart interlock delay
    /// restart_interlock.reset_required: the restart also needs a reset edge
    /// (default true; false only with opt_out.reset_required).
    bool reset_required = true;
    std::uint32_t fault_recovery_cycles = 10U;  ///< clean cycles before a recoverable fault clears
    std::int16_t foreground_threshold = 255;    ///< t_f, log-odds (from thresholds.foreground_probability)
    /// unseen counts voxels whose prior is at least this (log-odds of thresholds.accessible_min_p_fore)
    std::int16_t accessible_min_prior = -754;
    int demo_cycles = 60;  ///< cycles the simulated run lasts
    /// A scene file (apps/host/sim/scene_file.hpp) the simulated sensors
    /// render instead of the paper's reference scene with the scripted
    /// person, and whose robot trajectory and command schedule the simulated
    /// PLC sends (demo.scene; relative: to the config file's directory;
    /// "builtin:NAME": a text built into the program). Empty: the paper's demo.
    std::string demo_scene;
    /// The protections this configuration turns off, each with its stated
    /// reason ([opt_out]; every one is checked against the settings).
    std::vector<OptOut> opt_outs;
    /// Where the configuration came from, for messages: the file's path, or
    /// "<built-in ...>" for a built-in text (parse_monitor_config's source_name).
    std::string source;
};

/// True when @p cfg's [opt_out] names the protection @p name.
[[nodiscard]] bool opted_out(const MonitorConfig& cfg, const char* name);

/// Outcome of loading: the config, or a message naming file, line and key.
struct ConfigLoad {
    bool ok = false;       ///< true when `config` is valid
    MonitorConfig config;  ///< the loaded configuration
    std::string error;     ///< "file:line:column: key: what is wrong"
};

/// Parses @p text (named @p source_name in messages; relative prior paths
/// resolve against @p base_dir) and checks every value.
ConfigLoad parse_monitor_config(const std::string& text, const std::string& source_name,
                                const std::string& base_dir = ".");
/// Reads and parses the file at @p path.
ConfigLoad load_monitor_config(const std::string& path);

/// The sensor -> cell pose of @p s as configured: from position and target
/// by the simulator's convention (x axis horizontal; undefined for a target
/// straight above or below), or from position and rotation exactly, whatever
/// the roll. The monitor and the commissioning tool both take recorded
/// sensors' poses from here.
Eigen::Isometry3d sensor_pose(const SensorSettings& s);
/// Sensor @p s's pinhole intrinsics as the cell's sensor model has them (sim::SensorSpec::intrinsics):
/// configured or read from the device (fx..cy), else from the fields of view with a centred principal point.
PinholeIntrinsics sensor_intrinsics(const SensorSettings& s);
/// Sets @p s's pinhole intrinsics (pixels) and the fields of view derived
/// from them as the simulator derives them (sim::SensorSpec::set_intrinsics):
/// for a configured intrinsics table and for a camera's Scan3d values alike.
void set_sensor_intrinsics(SensorSettings& s, double fx, double fy, double cx, double cy);
/// The built-in demo configuration (paper-cell.toml's content).
MonitorConfig demo_config();
/// The TOML text of the demo configuration.
const char* demo_config_text();
/// The robot-cell demo's configuration (apps/monitor/config/robot-cell.toml's content).
MonitorConfig robot_cell_demo_config();
/// The text built into the program under @p name ("robot-cell.toml",
/// "robot-cell-scene.toml", "robot-arm.urdf"), or nullptr.
const char* builtin_text(const std::string& name);
/// The text of @p path: a file, or with the prefix "builtin:" a text built
/// into the program. False (and @p text untouched) when it cannot be read.
bool read_config_text(const std::string& path, std::string& text);

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_CONFIG_HPP
