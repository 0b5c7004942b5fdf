// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file camera_startup.hpp
/// The monitor's live cameras: opened before the cell is configured, one per
/// sensor with a [sensors.camera] table, then turned into frame sources
/// (cellguard/host/cell/camera_input.hpp).
///
/// open() for each such sensor, in configuration order:
/// - refuses the run unless it is paced (--paced): a camera frame carries its
///   real capture time on CLOCK_MONOTONIC, which only the paced clock shares;
/// - starts the camera (port/linux GigeCamera: opened, serial checked,
///   configured, streaming) and waits up to kFirstFrameTimeoutUs for its
///   first frame with an accepted time stamp;
/// - takes the depth scale and offset from the configuration when given,
///   else from the camera's Scan3d features (none: an error);
/// - intrinsics "device": fills the sensor's fx (the camera's
///   Scan3dFocalLength), fy (times Scan3dAspectRatio), cx, cy and the fields of view derived from them
///   into the configuration; configured intrinsics (fx/fy/cx/cy, or a field
///   of view's) that differ from a camera's Scan3d values by more than
///   kFocalTolerance (relative) or kPrincipalTolerancePx: an error;
/// - the sensor's model (sim::SensorSpec, to_spec) carries fx, fy, cx, cy,
///   so ray tables, footprint fusion and the views use the camera's own
///   principal point.
/// Built without Aravis (cellguard/host/gige.hpp: CELLGUARD_HOST_GIGE 0), a configuration with a
/// camera is refused with a message saying so.
#ifndef CELLGUARD_MONITOR_CAMERA_STARTUP_HPP
#define CELLGUARD_MONITOR_CAMERA_STARTUP_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/port/frame_signal.hpp"

namespace cellguard::monitor {

/// Most a configured focal length may differ from the camera's, relative (1 %).
constexpr double kFocalTolerance = 0.01;
/// Most a configured principal point may differ from the camera's, pixels.
constexpr double kPrincipalTolerancePx = 2.0;
/// How long open() waits for a camera's first frame, microseconds.
constexpr std::uint64_t kFirstFrameTimeoutUs = 5000000U;

/// True when some sensor of @p cfg has a live camera.
[[nodiscard]] bool has_cameras(const cell::MonitorConfig& cfg) noexcept;

/// See the file comment. Stops its cameras when destroyed (after the frame
/// sources made from it are gone).
class MonitorCameras {
public:
    MonitorCameras();
    MonitorCameras(const MonitorCameras&) = delete;
    MonitorCameras& operator=(const MonitorCameras&) = delete;
    MonitorCameras(MonitorCameras&&) = delete;
    MonitorCameras& operator=(MonitorCameras&&) = delete;
    ~MonitorCameras();

    /// Opens the cameras of @p cfg (see the file comment), updating its
    /// sensors' intrinsics "device"; says what it found on @p out (nullptr: silent).
    SetupError open(cell::MonitorConfig& cfg, bool paced, std::FILE* out);
    /// True when sensor @p s has a camera that open() started.
    [[nodiscard]] bool has(std::size_t s) const noexcept;
    /// The frame source of camera sensor @p s (has(s)), described by @p spec
    /// (its range) and @p settings (its pose and intrinsics).
    [[nodiscard]] std::unique_ptr<cell::FrameSource> make_source(std::size_t s, const cell::SensorSettings& settings,
                                                                 const sim::SensorSpec& spec);
    /// The signal every started camera notifies on each frame, for the paced
    /// loop's frame-triggered start (monitor_loop.hpp); nullptr when open()
    /// started no camera.
    [[nodiscard]] linux_port::FrameSignal* frame_signal() noexcept;

private:
    struct Cameras;
    std::unique_ptr<Cameras> cameras_;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_CAMERA_STARTUP_HPP
