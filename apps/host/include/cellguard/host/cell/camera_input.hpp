// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file camera_input.hpp
/// A live GigE Vision camera as a FrameSource (library cellguard_host_camera,
/// built when CMake finds Aravis; cellguard/host/gige.hpp then defines
/// CELLGUARD_HOST_GIGE 1). port/linux's cellguard/port/gige_camera.hpp does
/// the camera; this file the policy.
///
/// Each load_frame() hands the cycle the camera's newest complete frame as a
/// kDepthImageU16 reading (the camera's uint16 slot in place, no copy), with
/// the configured or the device's depth scale and offset and the sensor's
/// intrinsics, and its capture time (the device time stamp mapped to
/// CLOCK_MONOTONIC) in FrameStatus::stamp_us, which the loop stamps the
/// reading with. Policy:
/// - any frame lost since the previous cycle (incomplete or corrupt buffer,
///   a wrong size or pixel format, a frame-id gap, a refused time stamp)
///   refuses this cycle's reading: the controller faults and stops. Lost
///   packets are not recovered (no resend): a loss is a fault;
/// - no new frame since the previous cycle (a camera stopped, reconnecting,
///   or slower than the cycle): the previous frame again, with its old
///   stamp, so the controller's frame-age check makes it stale;
/// - no frame yet at all: refused.
/// Never blocks and never allocates (counter reads and one atomic exchange).
#ifndef CELLGUARD_HOST_CELL_CAMERA_INPUT_HPP
#define CELLGUARD_HOST_CELL_CAMERA_INPUT_HPP

#include <Eigen/Geometry>
#include <cstdint>
#include <cstdio>
#include <string>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/port/gige_camera.hpp"

namespace cellguard::cell {

/// port/linux's camera settings for sensor @p s: its [sensors.camera] table
/// (address, serial, id, expected serial, pixel format, frame rate, packet
/// size, socket buffer, reconnect interval, max stamp error), its width and
/// height; the reconnect trigger (no frame for 1 s, at least 5 periods) and
/// the other clock limits are port/linux's defaults.
[[nodiscard]] linux_port::GigeCameraConfig gige_config(const SensorSettings& s);

/// The counts of a CameraFrameSource's cycles.
struct CameraSourceCounts {
    std::uint64_t new_frames = 0U;        ///< cycles given a frame not given before
    std::uint64_t repeated = 0U;          ///< cycles given the previous frame again (no new one)
    std::uint64_t refused_loss = 0U;      ///< cycles refused for frames lost since the previous cycle
    std::uint64_t refused_no_frame = 0U;  ///< cycles refused because no frame had arrived yet
};

/// See the file comment.
class CameraFrameSource final : public FrameSource {
public:
    /// A source for sensor @p name over @p camera (started, must outlive
    /// the source) with @p params.
    CameraFrameSource(std::string name, linux_port::GigeCamera& camera, const CameraReadingParams& params);

    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// True when the camera has published a frame after the one the previous cycle was given.
    [[nodiscard]] bool has_new_frame() const noexcept override;
    /// "camera 'name': N frames received, ... ; cycles: ..." (the camera's counters and the policy's).
    void write_summary(std::FILE* out) const noexcept override;

    /// The cycles' counts so far.
    [[nodiscard]] const CameraSourceCounts& counts() const noexcept { return counts_; }

private:
    std::string name_;
    linux_port::GigeCamera* camera_;
    CameraReadingParams params_;
    std::uint64_t losses_seen_ = 0U;    ///< the camera's loss counters' sum at the previous cycle
    std::uint64_t last_sequence_ = 0U;  ///< the frame given at the previous cycle (0: none)
    CameraSourceCounts counts_{};
};

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_CAMERA_INPUT_HPP
