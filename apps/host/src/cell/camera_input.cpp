// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A live GigE Vision camera as a FrameSource (camera_input.hpp).
#include "cellguard/host/cell/camera_input.hpp"

#include <algorithm>
#include <utility>

namespace cellguard::cell {
namespace {

/// Frames the camera lost, refused or could not use, in total.
std::uint64_t losses(const linux_port::GigeCounters& c) noexcept {
    return c.incomplete + c.wrong_format + c.missing + c.stamp_refused;
}

}  // namespace

linux_port::GigeCameraConfig gige_config(const SensorSettings& s) {
    const CameraSettings& c = s.camera;
    linux_port::GigeCameraConfig g;
    g.name = s.name;
    g.address = c.address;
    g.serial = c.serial;
    g.device_id = c.device_id;
    g.expected_serial = c.expected_serial;
    g.pixel_format = c.pixel_format == CameraPixelFormat::kMono16 ? linux_port::GigePixelFormat::kMono16
                                                                  : linux_port::GigePixelFormat::kCoord3dC16;
    g.width = s.width;
    g.height = s.height;
    g.frame_rate_hz = c.frame_rate_hz;
    g.packet_size = c.packet_size;
    g.socket_buffer_bytes = c.socket_buffer_bytes;
    g.reconnect_interval_us = c.reconnect_interval_us;
    const double period_us = c.frame_rate_hz > 0.0 ? 1e6 / c.frame_rate_hz : 1e6;
    g.no_frame_timeout_us = std::max<std::uint64_t>(1000000U, static_cast<std::uint64_t>(5.0 * period_us));
    g.clock.max_stamp_error_us = c.max_stamp_error_us;
    return g;
}

CameraFrameSource::CameraFrameSource(
    std::string name, linux_port::GigeCamera& camera,
    // NOLINTNEXTLINE(modernize-pass-by-value): Eigen fixed-size members, by reference (Eigen's rule)
    const CameraReadingParams& params)
    : name_(std::move(name)), camera_(&camera), params_(params), losses_seen_(losses(camera.counters())) {}

bool CameraFrameSource::load_frame(std::uint64_t /*cycle*/, SensorReading& reading, FrameStatus& status) noexcept {
    status = FrameStatus{};
    const linux_port::GigeCounters c = camera_->counters();
    const std::uint64_t lost = losses(c) - losses_seen_;
    losses_seen_ = losses(c);
    linux_port::GigeFrame frame;
    const bool has_frame = camera_->latest(frame);  // also after a loss: the slot is then the newest
    if (lost > 0U) {
        ++counts_.refused_loss;
        refuse_reading(reading);
        static_cast<void>(
            std::snprintf(status.reason, sizeof status.reason,
                          "camera: %llu frames lost since the previous cycle (totals: %llu incomplete, "
                          "%llu wrong format, %llu missing, %llu stamps refused)",
                          static_cast<unsigned long long>(lost), static_cast<unsigned long long>(c.incomplete),
                          static_cast<unsigned long long>(c.wrong_format), static_cast<unsigned long long>(c.missing),
                          static_cast<unsigned long long>(c.stamp_refused)));
        return false;
    }
    if (!has_frame) {
        ++counts_.refused_no_frame;
        refuse_reading(reading);
        static_cast<void>(std::snprintf(status.reason, sizeof status.reason, "camera: no frame received yet"));
        return false;
    }
    if (frame.sequence == last_sequence_) {
        ++counts_.repeated;
    } else {
        ++counts_.new_frames;
    }
    last_sequence_ = frame.sequence;
    reading = SensorReading{};
    reading.pose = params_.pose;
    reading.kind = SensorDataKind::kDepthImageU16;
    reading.depth_u16 = Span<const std::uint16_t>(
        frame.pixels, static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height));
    reading.depth_scale = params_.depth_scale_m;
    reading.depth_offset = params_.depth_offset_m;
    reading.intrinsics = params_.intrinsics;
    reading.max_range = params_.max_range;
    status.ok = true;
    status.has_stamp = true;
    status.stamp_us = frame.stamp_us;
    status.receive_us = frame.receive_us;
    return true;
}

bool CameraFrameSource::has_new_frame() const noexcept { return camera_->published() > last_sequence_; }

void CameraFrameSource::write_summary(std::FILE* out) const noexcept {
    const linux_port::GigeCounters c = camera_->counters();
    const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    static_cast<void>(std::fprintf(
        out,
        "camera '%s': %llu buffers received, %llu complete, %llu incomplete, %llu wrong format, %llu missing, "
        "%llu stamps refused, %llu published; %llu disconnections, %llu reconnections, %llu failed reopens\n",
        name_.c_str(), u(c.received), u(c.complete), u(c.incomplete), u(c.wrong_format), u(c.missing),
        u(c.stamp_refused), u(c.published), u(c.disconnections), u(c.reconnections), u(c.reconnect_failures)));
    static_cast<void>(std::fprintf(out,
                                   "camera '%s': cycles: %llu new frames, %llu repeated (no new frame), %llu refused "
                                   "for lost frames, %llu refused before the first frame\n",
                                   name_.c_str(), u(counts_.new_frames), u(counts_.repeated), u(counts_.refused_loss),
                                   u(counts_.refused_no_frame)));
}

}  // namespace cellguard::cell
