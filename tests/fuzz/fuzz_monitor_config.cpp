// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the monitor's TOML configuration loader (parse_monitor_config,
// with toml++ underneath). No crash, no exception escaping, no read outside
// the input; a refusal always says where ("fuzz.toml:line:column: key: what",
// or the TOML syntax error); an accepted configuration holds what the
// loader promises: sensors with a valid image and either a field of view,
// intrinsics inside the image or "device" with a camera; unit rotations;
// cameras opened by exactly one of address, serial and ID; thresholds in the
// converted ranges.
//
// Input: the bytes are the file's text. Relative paths resolve against a
// folder that does not exist, so pcd_files and the like are refused
// without reading any file.
// Seeds: tests/fuzz/corpus/fuzz_monitor_config/ (the shipped configurations
// and one with every camera key).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/cell/config.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

void require(bool condition) {
    if (!condition) {
        __builtin_trap();
    }
}

void check_camera(const SensorSettings& s) {
    const CameraSettings& c = s.camera;
    if (!c.enabled) {
        require(s.intrinsics_source != IntrinsicsSource::kDevice);
        return;
    }
    require(static_cast<int>(!c.address.empty()) + static_cast<int>(!c.serial.empty()) +
                static_cast<int>(!c.device_id.empty()) ==
            1);
    require(s.pcd_files.empty());
    require(c.pixel_format != CameraPixelFormat::kMono16 || c.has_depth_scale);
    require(!c.has_depth_scale || (c.depth_scale_m > 0.0 && c.depth_scale_m <= 1.0));
    require(c.frame_rate_hz >= 0.1 && c.frame_rate_hz <= 1000.0);
    require(c.packet_size == 0 || (c.packet_size >= 576 && c.packet_size <= 9000));
    require(c.socket_buffer_bytes >= 64 * 1024 && c.socket_buffer_bytes <= 65536 * 1024);
    require(c.reconnect_interval_us >= 100000U && c.max_stamp_error_us >= 1000U);
}

void check_sensor(const SensorSettings& s) {
    require(s.width >= 1 && s.height >= 1 &&
            static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height) <= kMaxReadingsPerSensor);
    require(s.has_target || std::fabs(s.rotation.norm() - 1.0) < 1e-12);
    require(s.max_range > 0.0 && s.max_range <= static_cast<double>(kMaxSensorRange));
    switch (s.intrinsics_source) {
        case IntrinsicsSource::kFieldOfView:
            require(s.hfov_deg > 0.0 && s.hfov_deg < 180.0 && s.vfov_deg > 0.0 && s.vfov_deg < 180.0);
            break;
        case IntrinsicsSource::kConfig:
            require(std::isfinite(s.fx) && std::isfinite(s.fy) && s.fx > 0.0 && s.fy > 0.0);
            require(s.cx >= 0.0 && s.cx < static_cast<double>(s.width) && s.cy >= 0.0 &&
                    s.cy < static_cast<double>(s.height));
            require(s.hfov_deg > 0.0 && s.hfov_deg <= 180.0 && s.vfov_deg > 0.0 && s.vfov_deg <= 180.0);
            break;
        case IntrinsicsSource::kDevice: require(s.camera.enabled); break;
    }
    check_camera(s);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const ConfigLoad l = parse_monitor_config(text, "fuzz.toml", "/nonexistent-cellguard-fuzz");
    if (!l.ok) {
        require(l.error.rfind("fuzz.toml:", 0) == 0);
        return 0;
    }
    const MonitorConfig& c = l.config;
    require(!c.sensors.empty() && c.sensors.size() <= kMaxSensors);
    for (const SensorSettings& s : c.sensors) {
        check_sensor(s);
    }
    require(c.foreground_threshold >= kLogOddsMin && c.foreground_threshold <= kLogOddsMax);
    require(c.accessible_min_prior >= kLogOddsMin && c.accessible_min_prior <= 0);
    return 0;
}
