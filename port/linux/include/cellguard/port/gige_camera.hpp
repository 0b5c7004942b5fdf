// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file gige_camera.hpp
/// A live GigE Vision depth camera through Aravis 0.8 (built when CMake
/// finds aravis-0.8: CELLGUARD_WITH_GIGE; target cellguard_port_linux_gige).
/// Aravis stays inside gige_camera.cpp: this header names none of its types.
///
/// Start (start(), on the caller's thread, before the cycle runs):
/// - open the camera by address (GVCP unicast to it, no discovery; the local
///   interface is the one the OS routes to that address), or else by serial
///   or Aravis device id (discovery on every interface of the host: never in
///   tests);
/// - read DeviceSerialNumber (DeviceID where the camera has no
///   DeviceSerialNumber, as Aravis' fake) and refuse the camera unless it
///   equals expected_serial (and serial, when the camera was opened by
///   address or id), when those are given;
/// - stop acquisition, set TriggerMode Off and AcquisitionMode Continuous
///   where present, OffsetX/OffsetY 0, Width, Height, PixelFormat
///   (Coord3D_C16 or Mono16), AcquisitionFrameRate (after
///   AcquisitionFrameRateEnable where present), the packet size (when
///   configured), with Aravis' range check on, then read every value back: a refusal or another value
///   (frame rate: more than 1 % off) is an error naming the feature;
/// - read the Scan3d features when present (Scan3dCoordinateScale/Offset in
///   Scan3dDistanceUnit, millimetres when absent; Scan3dFocalLength,
///   Scan3dAspectRatio (fy / fx, 1 when absent), Scan3dPrincipalPointU/V in pixels) into device();
/// - allocate `stream_buffers` buffers of PayloadSize and three frame slots
///   of width * height uint16, make the stream (fixed socket buffer of
///   socket_buffer_bytes, packet resend never: a loss is a fault, not
///   something to recover), start acquisition and the supervisor thread.
///
/// Frames (the supervisor thread, which pops Aravis' buffers): every buffer
/// is counted (received); a status other than success is incomplete; a
/// success with another size or pixel format than configured is
/// wrong_format; frame-id gaps (16-bit ids wrap from 65535 to 1) are
/// missing, an id that goes back (not a wrap) counts one missing, id 0 (a
/// buffer whose leader was lost) counts none; a
/// complete frame's device time stamp is mapped to CLOCK_MONOTONIC by
/// DeviceClock (device_clock.hpp; its receive time is when the supervisor
/// thread pops the completed buffer, never before its true arrival) and a
/// refused stamp counts stamp_refused (the relearning frames after a
/// refusal too; not the learning after start or a reconnection). A complete frame with an accepted
/// stamp is copied into the free slot and published (a lock-free triple
/// buffer): latest() on the cycle's thread never blocks and never allocates.
/// Aravis itself allocates inside its own threads for every frame (its
/// per-frame bookkeeping, g_new in arvgvstream.c); the stream test of
/// tests/unit/test_gige_camera.cpp prints the count per frame.
///
/// Reconnect policy: when the device reports control lost (heartbeat
/// failures) or no buffer at all arrives for no_frame_timeout_us, the
/// supervisor thread counts a disconnection, closes the stream and the
/// device (without commands to the lost camera; Aravis still tries to leave
/// control, which blocks this thread for seconds), then every
/// reconnect_interval_us opens the camera again as at start, configures
/// every setting again (a restarted camera comes back at its defaults),
/// checks the serial again (a swapped camera is refused and retried, never
/// streamed), refuses a camera whose PayloadSize or Scan3d scale, offset or
/// intrinsics differ from those read at start (the frames are read with the
/// start's values), restarts the time-stamp mapping and acquisition. An open of an
/// absent camera blocks about 2.5 s inside Aravis: only this thread waits.
/// Meanwhile latest() keeps returning the last frame published, with its old
/// stamp: the cycle sees no new frame (stale -> fault -> stop).
#ifndef CELLGUARD_PORT_GIGE_CAMERA_HPP
#define CELLGUARD_PORT_GIGE_CAMERA_HPP

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "cellguard/port/device_clock.hpp"
#include "cellguard/port/frame_signal.hpp"

namespace cellguard::linux_port {

/// The depth pixel format asked of the camera.
enum class GigePixelFormat : std::uint8_t {
    kCoord3dC16 = 0,  ///< PFNC Coord3D_C16 (0x011000B8)
    kMono16 = 1,      ///< PFNC Mono16 (0x01100007)
};

/// The GenICam name of @p f ("Coord3D_C16", "Mono16").
[[nodiscard]] const char* to_string(GigePixelFormat f) noexcept;

/// One camera's settings (port/ has its own: apps/host converts its config).
struct GigeCameraConfig {
    std::string name;             ///< a label for messages (the sensor's name)
    std::string address;          ///< IPv4 address: opened directly; else serial, else device_id
    std::string serial;           ///< opened by discovery when no address; else checked
    std::string device_id;        ///< Aravis device id ("Vendor-Model-Serial"), by discovery
    std::string expected_serial;  ///< checked at every (re)connection when not empty
    GigePixelFormat pixel_format = GigePixelFormat::kCoord3dC16;  ///< asked of the camera
    int width = 0;                                   ///< Width, must be accepted exactly (the sensor's resolution)
    int height = 0;                                  ///< Height, the same
    double frame_rate_hz = 30.0;                     ///< AcquisitionFrameRate
    int packet_size = 0;                             ///< GevSCPSPacketSize, bytes; 0: the camera's own
    int socket_buffer_bytes = 1048576;               ///< the stream socket's receive buffer
    std::size_t stream_buffers = 8U;                 ///< Aravis buffers, allocated at start (2..64)
    std::uint64_t reconnect_interval_us = 1000000U;  ///< between two reopen attempts
    std::uint64_t no_frame_timeout_us = 1000000U;    ///< no buffer for this long: reconnect
    DeviceClockParams clock{};                       ///< the time-stamp mapping's limits
    /// Notified after each published frame (frame_signal.hpp; not owned, must
    /// outlive the camera); null: none.
    FrameSignal* signal = nullptr;
};

/// What start() read from the camera.
struct GigeDeviceInfo {
    std::string serial;                    ///< DeviceSerialNumber (or DeviceID)
    std::string vendor;                    ///< DeviceVendorName ("" if absent)
    std::string model;                     ///< DeviceModelName ("" if absent)
    std::int64_t payload_bytes = 0;        ///< PayloadSize
    bool has_depth_scale = false;          ///< Scan3dCoordinateScale was read
    double depth_scale_m = 0.0;            ///< metres per raw unit
    double depth_offset_m = 0.0;           ///< metres (Scan3dCoordinateOffset, 0 if absent)
    bool has_intrinsics = false;           ///< Scan3dFocalLength and principal point were read
    double focal_px = 0.0;                 ///< Scan3dFocalLength, pixels: fx
    double aspect_ratio = 1.0;             ///< Scan3dAspectRatio (fy / fx) where the camera has it, else 1
    double cx = 0.0;                       ///< Scan3dPrincipalPointU, pixels
    double cy = 0.0;                       ///< Scan3dPrincipalPointV, pixels
    std::uint64_t tick_frequency_hz = 0U;  ///< GevTimestampTickFrequency (0: not reported)
};

/// The newest published frame, as latest() gives it.
struct GigeFrame {
    const std::uint16_t* pixels = nullptr;  ///< width * height raw values, row-major
    int width = 0;                          ///< columns
    int height = 0;                         ///< rows
    std::uint64_t stamp_us = 0U;            ///< capture time, CLOCK_MONOTONIC microseconds
    std::uint64_t receive_us = 0U;          ///< when its last packet arrived, CLOCK_MONOTONIC
    std::uint64_t frame_id = 0U;            ///< the camera's block id
    std::uint64_t sequence = 0U;            ///< frames published before it + 1 (1, 2, ...)
};

/// The camera's counts since start() (each only grows).
struct GigeCounters {
    std::uint64_t received = 0U;            ///< buffers popped from Aravis
    std::uint64_t complete = 0U;            ///< status success and the configured image
    std::uint64_t incomplete = 0U;          ///< status other than success (lost packets, timeouts)
    std::uint64_t wrong_format = 0U;        ///< success, but another size or pixel format
    std::uint64_t missing = 0U;             ///< frame ids skipped (or going back)
    std::uint64_t stamp_refused = 0U;       ///< complete frames whose stamp the mapping refused
    std::uint64_t published = 0U;           ///< frames handed to latest()
    std::uint64_t disconnections = 0U;      ///< sessions closed (control lost or no frame)
    std::uint64_t reconnect_failures = 0U;  ///< reopen attempts that failed
    std::uint64_t reconnections = 0U;       ///< reopen attempts that succeeded
};

/// See the file comment. One thread calls latest(); counters(), connected()
/// and last_error() may be called from any thread.
class GigeCamera {
public:
    /// A camera to be opened with @p config (nothing is opened yet).
    explicit GigeCamera(GigeCameraConfig config);
    GigeCamera(const GigeCamera&) = delete;
    GigeCamera& operator=(const GigeCamera&) = delete;
    GigeCamera(GigeCamera&&) = delete;
    GigeCamera& operator=(GigeCamera&&) = delete;
    /// Stops the supervisor thread and closes the camera.
    ~GigeCamera();

    /// Opens, checks and configures the camera and starts streaming (see the
    /// file comment); false with @p error saying why (the camera is closed again).
    [[nodiscard]] bool start(std::string& error);
    /// Stops acquisition and the supervisor thread (blocks while an open is under way).
    void stop() noexcept;

    /// What start() read from the camera (never changed after start()).
    [[nodiscard]] const GigeDeviceInfo& device() const noexcept;
    /// The settings it was made with.
    [[nodiscard]] const GigeCameraConfig& config() const noexcept;
    /// The newest published frame into @p frame (valid until the next call);
    /// false before the first. Never blocks, never allocates.
    [[nodiscard]] bool latest(GigeFrame& frame) noexcept;
    /// The counts so far.
    [[nodiscard]] GigeCounters counters() const noexcept;
    /// Frames published so far: the sequence of the newest (counters().published, one atomic load).
    [[nodiscard]] std::uint64_t published() const noexcept;
    /// True while a session streams (false between a loss and the reconnection).
    [[nodiscard]] bool connected() const noexcept;
    /// Why the last reopen attempt failed ("" when none did). Locks; not for the cycle.
    [[nodiscard]] std::string last_error() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_GIGE_CAMERA_HPP
