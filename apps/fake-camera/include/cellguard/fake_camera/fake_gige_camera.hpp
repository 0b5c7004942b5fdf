// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file fake_gige_camera.hpp
/// A fake GigE Vision depth camera for tests: Aravis's in-process
/// ArvGvFakeCamera (real GVCP and GVSP over UDP) with cellguard's GenICam
/// description (genicam/cellguard-fake-depth-camera.xml: Coord3D_C16 and the
/// SFNC Scan3d features), serving the uint16 depth image a caller's callback
/// writes for each frame, with device time stamps and injected faults.
///
/// Loopback only: the camera binds GVCP (UDP 3956) on its address, which must
/// be an address of an interface (127.0.0.1 always is; 127.0.0.2 and up only
/// after `ip addr add 127.0.0.N/8 dev lo`, e.g. in the namespace of
/// tools/netns-run.sh). Addresses outside 127.0.0.0/8 are refused.
///
/// Threads: Aravis's camera thread calls the depth callback, one frame at a
/// time; the other members are for the owner's thread. Heap: this code
/// allocates at construction, start() and restart(), and nothing per frame
/// except when a stop or resume changes Aravis's loss property (not measured
/// inside Aravis, which is a test tool here).
#ifndef CELLGUARD_FAKE_CAMERA_FAKE_GIGE_CAMERA_HPP
#define CELLGUARD_FAKE_CAMERA_FAKE_GIGE_CAMERA_HPP

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace cellguard::fake_camera {

/// GenICam PFNC codes of the formats the fake offers.
enum class PixelFormat : std::uint32_t {
    kMono8 = 0x01080001U,       ///< 8 bits; the fake sends zeros
    kMono16 = 0x01100007U,      ///< 16-bit depth without Scan3d meaning
    kCoord3dC16 = 0x011000B8U,  ///< 16-bit depth along the optical axis, Scan3d scale and offset
};

/// Faults to inject, each off by default. Frames count from 0, every frame the
/// camera has sent (or dropped) since it was (re)started, or, with
/// FakeCameraSettings::faults_from_start false, since arm_faults().
struct FakeCameraFaults {
    /// Each GVSP packet dropped with this probability per thousand (Aravis's
    /// own "gvsp-lost-ratio"; the fake never resends).
    std::uint32_t lost_packets_per_mille = 0U;
    /// From this frame on, the bytes of the frame before it are sent again
    /// (a frozen image; frame 0 freezes from frame 1); -1: off.
    std::int64_t frozen_from_frame = -1;
    /// At this frame the device clock jumps by stamp_jump_ms (and stays
    /// shifted); -1: off.
    std::int64_t stamp_jump_at_frame = -1;
    std::int64_t stamp_jump_ms = 0;  ///< the jump, milliseconds (may be negative)
    /// From this frame on the camera sends nothing (every packet dropped; it
    /// still answers control requests unless power_off_at_stop); -1: off.
    std::int64_t stop_at_frame = -1;
    /// With stop_at_frame: the camera also goes away entirely (no GVCP): the
    /// next poll() destroys it, as a camera that lost power.
    bool power_off_at_stop = false;
    /// After a power-off: the next poll() this many milliseconds later starts
    /// it again as a new camera at its power-on defaults (a reboot); -1: never.
    std::int64_t restart_after_ms = -1;
    /// From this frame on (0 acts as 1) Width and Height are resize_width x
    /// resize_height and the callback's image has that size; -1: off. The
    /// stream keeps the payload size it started with (Aravis's fake): a
    /// smaller image fills the front of each buffer, which Aravis's client
    /// delivers as complete with the new width and height (measured); a larger
    /// one is not made at all (Aravis skips the fill).
    std::int64_t resize_at_frame = -1;
    int resize_width = 0;   ///< width after the change
    int resize_height = 0;  ///< height after the change
};

/// One camera: what it is and what it sends.
struct FakeCameraSettings {
    std::string address = "127.0.0.1";  ///< IPv4 address it binds (127.0.0.0/8)
    std::string serial = "CGFAKE0";     ///< DeviceSerialNumber and DeviceID (at most 15 characters)
    /// The GenICam description; empty: the one built with this library
    /// (default_genicam_file()).
    std::string genicam_file;
    int width = 0;                                       ///< Width and SensorWidth at power-on, 1..2048
    int height = 0;                                      ///< Height and SensorHeight at power-on, 1..2048
    PixelFormat power_on_format = PixelFormat::kMono16;  ///< PixelFormat at power-on (the client sets its own)
    /// Whether PixelFormat offers Coord3D_C16 (false: a camera that cannot
    /// give depth in it, for the wrong-format test).
    bool offers_coord3d_c16 = true;
    double frame_rate_hz = 10.0;     ///< AcquisitionFrameRate at power-on, 0.1..1000
    bool distance_unit_mm = true;    ///< Scan3dDistanceUnit: Millimeter (else Inch)
    double coordinate_scale = 1.0;   ///< Scan3dCoordinateScale, distance unit per raw unit
    double coordinate_offset = 0.0;  ///< Scan3dCoordinateOffset, distance unit
    double focal_length_px = 0.0;    ///< Scan3dFocalLength (fx)
    double aspect_ratio = 1.0;       ///< Scan3dAspectRatio (fy / fx)
    double principal_point_u = 0.0;  ///< Scan3dPrincipalPointU (cx)
    double principal_point_v = 0.0;  ///< Scan3dPrincipalPointV (cy)
    /// Device clock at power-on, nanoseconds (ticks: the fake's tick
    /// frequency is 1 GHz); then it runs with CLOCK_MONOTONIC.
    std::uint64_t clock_offset_ns = 0U;
    FakeCameraFaults faults;  ///< faults to inject
    /// True: the faults' frames count from the first frame. False: no fault
    /// acts until arm_faults(), and their frames count from the first frame
    /// made after it (packet loss acts from the start either way). A reboot
    /// counts from its first frame again.
    bool faults_from_start = true;
};

/// What the depth callback is asked for.
struct FrameRequest {
    std::uint64_t frame = 0U;           ///< frame index since the camera (re)started
    std::uint64_t monotonic_ns = 0U;    ///< CLOCK_MONOTONIC when the frame was made
    std::uint64_t device_time_ns = 0U;  ///< the time stamp the frame is sent with
    int width = 0;                      ///< image columns
    int height = 0;                     ///< image rows
};

/// Writes the depth image of @p request into @p image (width * height values,
/// row-major; raw units, 0 = no reading). Called on Aravis's camera thread;
/// must not block.
using DepthCallback = std::function<void(const FrameRequest& request, std::uint16_t* image)>;

/// Counters, readable from any thread while the camera runs.
struct FakeCameraCounts {
    std::uint64_t frames = 0U;        ///< frames the camera made (sent or dropped) since start()
    std::uint64_t rendered = 0U;      ///< frames whose image the callback wrote
    std::uint64_t frozen = 0U;        ///< frames sent with the frozen image
    std::uint64_t stopped = 0U;       ///< frames dropped whole because the camera stopped
    std::uint64_t other_format = 0U;  ///< frames in a format other than Mono16/Coord3D_C16 (sent as zeros)
    std::uint64_t restarts = 0U;      ///< reboots (restart() or restart_after_ms)
    /// CLOCK_MONOTONIC (ns) when the first stop, freeze or stamp-jump frame
    /// was made; 0: none yet. Tests compare the monitor's reaction with it.
    std::uint64_t fault_ns = 0U;
};

/// A depth in metres as a raw Coord3D_C16 / Mono16 value of a camera whose
/// depth is raw * @p scale_m + @p offset_m: rounded to the nearest raw
/// unit; 0 (no reading) for a depth that is not finite, not positive, or
/// whose raw value falls outside 1..65535.
[[nodiscard]] std::uint16_t raw_depth(float metres, double scale_m, double offset_m) noexcept;

/// The GenICam file built with this library.
[[nodiscard]] const char* default_genicam_file() noexcept;

/// Checks @p settings; empty when they can be served, else what is wrong.
[[nodiscard]] std::string check_settings(const FakeCameraSettings& settings);

/// A fake GigE Vision depth camera.
class FakeGigeCamera {
public:
    /// A camera for @p settings serving @p depth; not started.
    FakeGigeCamera(FakeCameraSettings settings, DepthCallback depth);
    ~FakeGigeCamera();
    FakeGigeCamera(const FakeGigeCamera&) = delete;
    FakeGigeCamera& operator=(const FakeGigeCamera&) = delete;
    FakeGigeCamera(FakeGigeCamera&&) = delete;
    FakeGigeCamera& operator=(FakeGigeCamera&&) = delete;

    /// Powers the camera on: binds its address and answers GVCP. False, with
    /// @p error saying why, for bad settings or an address no interface has.
    [[nodiscard]] bool start(std::string& error);
    /// Powers it off: no GVCP, no stream, the port is freed. Idempotent.
    void power_off();
    /// power_off() then start() at the power-on defaults, counters kept, frame
    /// index and device clock from 0 again (a reboot).
    [[nodiscard]] bool restart(std::string& error);
    /// Stops or resumes sending (control still answered), as stop_at_frame does.
    void set_sending(bool on) noexcept;
    /// With faults_from_start false: the faults' frame 0 is the next frame the
    /// camera makes. Thread-safe; later calls do nothing.
    void arm_faults() noexcept;
    /// Does what the faults schedule outside the camera's thread (power-off at
    /// stop, restart_after_ms); call it every few tens of milliseconds.
    void poll();

    /// True while powered on.
    [[nodiscard]] bool running() const noexcept;
    /// The counters so far.
    [[nodiscard]] FakeCameraCounts counts() const noexcept;
    /// The settings it was made with.
    [[nodiscard]] const FakeCameraSettings& settings() const noexcept;

    struct State;  ///< shared with Aravis's thread (fake_gige_camera.cpp)

private:
    std::unique_ptr<State> state_;
};

}  // namespace cellguard::fake_camera

#endif  // CELLGUARD_FAKE_CAMERA_FAKE_GIGE_CAMERA_HPP
