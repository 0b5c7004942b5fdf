// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's live cameras at start-up (camera_startup.hpp).
#include "cellguard/monitor/camera_startup.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/port/clock.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <string>

#include "cellguard/host/gige.hpp"

#if CELLGUARD_HOST_GIGE
#include "cellguard/host/cell/camera_input.hpp"
#include "cellguard/port/gige_camera.hpp"
#endif

namespace cellguard::monitor {
bool has_cameras(const cell::MonitorConfig& cfg) noexcept {
    return std::any_of(cfg.sensors.begin(), cfg.sensors.end(),
                       [](const cell::SensorSettings& s) { return s.camera.enabled; });
}

#if CELLGUARD_HOST_GIGE

struct MonitorCameras::Cameras {
    std::vector<std::unique_ptr<linux_port::GigeCamera>> cameras;  ///< per sensor (nullptr: no camera)
    std::vector<float> scale;                                      ///< per sensor: metres per raw unit
    std::vector<float> offset;                                     ///< per sensor: metres
    linux_port::FrameSignal signal;                                ///< notified by every camera
};

namespace {

/// The sensor's depth scale and offset: configured, else the camera's; false when neither.
bool depth_scale(const cell::SensorSettings& s, const linux_port::GigeDeviceInfo& d, float& scale, float& offset) {
    if (s.camera.has_depth_scale) {
        scale = static_cast<float>(s.camera.depth_scale_m);
        offset = static_cast<float>(s.camera.depth_offset_m);
        return true;
    }
    if (!d.has_depth_scale) {
        return false;
    }
    scale = static_cast<float>(d.depth_scale_m);
    offset = static_cast<float>(d.depth_offset_m);
    return std::isfinite(scale) && scale > 0.0F && std::isfinite(offset);
}

/// Intrinsics "device" into @p s, or the configured ones checked against the
/// camera's; "" or why not.
std::string take_intrinsics(cell::SensorSettings& s, const linux_port::GigeDeviceInfo& d) {
    const std::string who = "sensor '" + s.name + "' (line " + std::to_string(s.line) + "): ";
    if (s.intrinsics_source == cell::IntrinsicsSource::kDevice) {
        if (!d.has_intrinsics) {
            return who +
                   "intrinsics = \"device\", but the camera has no Scan3dFocalLength and "
                   "Scan3dPrincipalPointU/V: configure intrinsics = { fx, fy, cx, cy }";
        }
        cell::set_sensor_intrinsics(s, d.focal_px, d.focal_px * d.aspect_ratio, d.cx, d.cy);
        return {};
    }
    if (!d.has_intrinsics) {
        return {};  // nothing to compare with
    }
    std::string spec_error;  // the sensor model the cell will use (to_spec): the one source of its intrinsics
    const PinholeIntrinsics k = to_spec(s, false, spec_error).intrinsics();
    const double device_fy = d.focal_px * d.aspect_ratio;
    const bool focal_ok = std::abs(k.fx - d.focal_px) <= kFocalTolerance * d.focal_px &&
                          std::abs(k.fy - device_fy) <= kFocalTolerance * device_fy;
    const bool centre_ok = std::abs(k.cx - d.cx) <= kPrincipalTolerancePx &&
                           std::abs(k.cy - d.cy) <= kPrincipalTolerancePx;
    if (focal_ok && centre_ok) {
        return {};
    }
    char text[320];
    static_cast<void>(std::snprintf(text, sizeof text,
                                    "configured intrinsics fx %.2f fy %.2f cx %.2f cy %.2f differ from the camera's "
                                    "(fx %.2f fy %.2f, cx %.2f, cy %.2f) by more than %.0f %% or %.1f px: "
                                    "use intrinsics = \"device\" or correct them",
                                    k.fx, k.fy, k.cx, k.cy, d.focal_px, device_fy, d.cx, d.cy, kFocalTolerance * 100.0,
                                    kPrincipalTolerancePx));
    return who + text;
}

/// Waits for the camera's first published frame; false after kFirstFrameTimeoutUs.
bool wait_first_frame(const linux_port::GigeCamera& camera) {
    const std::uint64_t until = linux_port::monotonic_now_us() + kFirstFrameTimeoutUs;
    while (linux_port::monotonic_now_us() < until) {
        if (camera.counters().published > 0U) {
            return true;
        }
        const timespec pause{0, 10000000L};
        nanosleep(&pause, nullptr);
    }
    return false;
}

}  // namespace

MonitorCameras::MonitorCameras() : cameras_(std::make_unique<Cameras>()) {}

MonitorCameras::~MonitorCameras() = default;

SetupError MonitorCameras::open(cell::MonitorConfig& cfg, bool paced, std::FILE* out) {
    if (!has_cameras(cfg)) {
        return {};
    }
    if (!paced) {
        return SetupError{2,
                          "configuration error: sensors with [sensors.camera] need --paced (their frames carry "
                          "real capture times, which only the paced clock shares)"};
    }
    Cameras& c = *cameras_;
    c.cameras.resize(cfg.sensors.size());
    c.scale.assign(cfg.sensors.size(), 0.0F);
    c.offset.assign(cfg.sensors.size(), 0.0F);
    for (std::size_t i = 0U; i < cfg.sensors.size(); ++i) {
        cell::SensorSettings& s = cfg.sensors[i];
        if (!s.camera.enabled) {
            continue;
        }
        linux_port::GigeCameraConfig camera_config = cell::gige_config(s);
        camera_config.signal = &c.signal;
        auto camera = std::make_unique<linux_port::GigeCamera>(camera_config);
        std::string error;
        if (!camera->start(error)) {
            return SetupError{1, error};
        }
        const linux_port::GigeDeviceInfo& d = camera->device();
        if (!depth_scale(s, d, c.scale[i], c.offset[i])) {
            return SetupError{2, "configuration error: sensor '" + s.name +
                                     "': the camera has no Scan3dCoordinateScale: configure camera.depth_scale"};
        }
        if (const std::string e = take_intrinsics(s, d); !e.empty()) {
            return SetupError{2, "configuration error: " + e};
        }
        if (!wait_first_frame(*camera)) {
            return SetupError{1, "camera '" + s.name + "': no frame with an accepted time stamp within " +
                                     std::to_string(kFirstFrameTimeoutUs / 1000000U) + " s (" +
                                     std::to_string(camera->counters().received) + " buffers received)"};
        }
        if (out != nullptr) {
            static_cast<void>(std::fprintf(
                out, "camera '%s': serial %s (%s %s), %d x %d %s at %.1f Hz, depth scale %.6g m offset %.6g m (%s)%s\n",
                s.name.c_str(), d.serial.c_str(), d.vendor.c_str(), d.model.c_str(), s.width, s.height,
                linux_port::to_string(camera->config().pixel_format), s.camera.frame_rate_hz,
                static_cast<double>(c.scale[i]), static_cast<double>(c.offset[i]),
                s.camera.has_depth_scale ? "configured" : "Scan3d",
                s.intrinsics_source == cell::IntrinsicsSource::kDevice ? ", intrinsics from the camera" : ""));
        }
        c.cameras[i] = std::move(camera);
    }
    return {};
}

bool MonitorCameras::has(std::size_t s) const noexcept {
    return s < cameras_->cameras.size() && cameras_->cameras[s] != nullptr;
}

std::unique_ptr<cell::FrameSource> MonitorCameras::make_source(std::size_t s, const cell::SensorSettings& settings,
                                                               const sim::SensorSpec& spec) {
    cell::CameraReadingParams p;
    p.pose = cell::sensor_pose(settings);
    p.intrinsics = spec.intrinsics();  // the cell's sensor model (to_spec): configured, device or field of view
    p.depth_scale_m = cameras_->scale[s];
    p.depth_offset_m = cameras_->offset[s];
    p.max_range = spec.max_range;
    return std::make_unique<cell::CameraFrameSource>(settings.name, *cameras_->cameras[s], p);
}

linux_port::FrameSignal* MonitorCameras::frame_signal() noexcept {
    const bool any = std::any_of(cameras_->cameras.begin(), cameras_->cameras.end(),
                                 [](const std::unique_ptr<linux_port::GigeCamera>& c) { return c != nullptr; });
    return any ? &cameras_->signal : nullptr;
}

#else  // built without Aravis

struct MonitorCameras::Cameras {};

MonitorCameras::MonitorCameras() : cameras_(std::make_unique<Cameras>()) {}

MonitorCameras::~MonitorCameras() = default;

SetupError MonitorCameras::open(cell::MonitorConfig& cfg, bool /*paced*/, std::FILE* /*out*/) {
    if (!has_cameras(cfg)) {
        return {};
    }
    return SetupError{2,
                      "configuration error: live cameras ([sensors.camera]) need a build with Aravis "
                      "(CELLGUARD_WITH_GIGE; this one has none)"};
}

bool MonitorCameras::has(std::size_t /*s*/) const noexcept { return false; }

std::unique_ptr<cell::FrameSource> MonitorCameras::make_source(std::size_t /*s*/,
                                                               const cell::SensorSettings& /*settings*/,
                                                               const sim::SensorSpec& /*spec*/) {
    return nullptr;
}

linux_port::FrameSignal* MonitorCameras::frame_signal() noexcept { return nullptr; }

#endif

}  // namespace cellguard::monitor
