// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The fake GigE Vision depth camera (fake_gige_camera.hpp) on Aravis's
// ArvGvFakeCamera: the camera's memory is set at power-on (image format,
// Scan3d registers of cellguard-fake-depth-camera.xml), and the fill
// callback, called by Aravis's camera thread before each frame is sent,
// writes the image, the time stamp and the faults.
#include "cellguard/fake_camera/fake_gige_camera.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include <arv.h>

namespace cellguard::fake_camera {

namespace {

// Registers of the GenICam description (genicam/cellguard-fake-depth-camera.xml).
constexpr guint32 kScan3dScale = 0xa000U;
constexpr guint32 kScan3dOffset = 0xa008U;
constexpr guint32 kScan3dFocalLength = 0xa010U;
constexpr guint32 kScan3dAspectRatio = 0xa018U;
constexpr guint32 kScan3dPrincipalU = 0xa020U;
constexpr guint32 kScan3dPrincipalV = 0xa028U;
constexpr guint32 kScan3dInvalidValue = 0xa030U;
constexpr guint32 kScan3dDistanceUnit = 0xa040U;
constexpr guint32 kScan3dSelector = 0xa044U;
constexpr guint32 kCoord3dC16Available = 0xa048U;
constexpr guint32 kScan3dInvalidFlag = 0xa04cU;
constexpr guint32 kModelNameOffset = 0x68U;  // bootstrap DeviceModelName, 32 bytes
constexpr guint32 kGvcpPort = 3956U;
constexpr int kMaxSide = ARV_FAKE_CAMERA_SENSOR_WIDTH;  // 2048, Aravis's sensor size

std::uint64_t monotonic_ns() {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
            .count());
}

bool write_double(ArvFakeCamera* camera, guint32 address, double value) {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &value, sizeof bits);
    unsigned char be[8];
    for (int i = 0; i < 8; ++i) {
        be[i] = static_cast<unsigned char>(bits >> static_cast<unsigned>(56 - 8 * i));
    }
    return arv_fake_camera_write_memory(camera, address, sizeof be, be) != FALSE;
}

/// The first address of @p text as an IPv4 address in 127.0.0.0/8, else false.
bool loopback_address(const std::string& text, in_addr& address) {
    if (inet_pton(AF_INET, text.c_str(), &address) != 1) {
        return false;
    }
    return (ntohl(address.s_addr) >> 24U) == 127U;
}

/// Whether UDP port 3956 of @p address can be bound now (no other camera holds it).
bool gvcp_port_free(const in_addr& address) {
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) {
        return false;
    }
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(static_cast<std::uint16_t>(kGvcpPort));
    sa.sin_addr = address;
    const bool ok = bind(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) == 0;
    static_cast<void>(close(fd));
    return ok;
}

bool depth_format(guint32 format) {
    return format == static_cast<guint32>(PixelFormat::kMono16) ||
           format == static_cast<guint32>(PixelFormat::kCoord3dC16);
}

}  // namespace

/// What the camera thread and the owner share.
struct FakeGigeCamera::State {
    ArvGvFakeCamera* gv = nullptr;
    // The camera thread's own (reset at each power-on, before the thread runs):
    std::uint64_t frame = 0U;
    std::uint64_t power_on_ns = 0U;
    std::int64_t clock_shift_ns = 0;
    double loss_ratio_now = 0.0;
    std::int64_t fault_origin = 0;  ///< the frame that is the faults' frame 0; -1: not armed yet
    // Shared:
    std::atomic<std::uint64_t> frames{0U}, rendered{0U}, frozen{0U}, stopped{0U}, other_format{0U}, restarts{0U};
    std::atomic<std::uint64_t> fault_ns{0U};  ///< the first fault frame's time (FakeCameraCounts::fault_ns)
    // The owner's:
    std::uint64_t off_since_ns = 0U;     ///< when a fault powered it off
    std::int64_t restart_after_ms = -1;  ///< that power-off's restart delay
    std::vector<std::uint16_t> image;    ///< camera thread's: the last image sent (frozen frames resend it)
    DepthCallback depth;
    FakeCameraFaults armed;  ///< the faults of this power-on (one-shot faults on the first only)
    FakeCameraSettings settings;
    bool first_run = true;      ///< owner's: the first power-on is still to come
    bool resized = false;       ///< camera thread's: the resize fault was applied
    bool have_image = false;    ///< camera thread's: image holds a sent image
    bool off_by_fault = false;  ///< owner's: powered off by power_off_at_stop
    std::atomic<bool> sending{true};
    std::atomic<bool> stop_reached{false};
    std::atomic<bool> arm_request{false};  ///< arm_faults() asked; the camera thread takes it
};

namespace {

using State = FakeGigeCamera::State;

void set_loss(State& s, double ratio) {
    if (ratio != s.loss_ratio_now) {
        g_object_set(s.gv, "gvsp-lost-ratio", ratio, nullptr);
        s.loss_ratio_now = ratio;
    }
}

/// The device time stamp of a frame made at @p now_ns, after the jump at fault frame @p frame (-1: none armed).
std::uint64_t device_time(State& s, std::int64_t frame, std::uint64_t now_ns) {
    if (s.armed.stamp_jump_at_frame >= 0 && frame == s.armed.stamp_jump_at_frame) {
        s.clock_shift_ns += s.armed.stamp_jump_ms * 1000000;
    }
    const std::int64_t t = static_cast<std::int64_t>(s.settings.clock_offset_ns) +
                           static_cast<std::int64_t>(now_ns - s.power_on_ns) + s.clock_shift_ns;
    return t < 0 ? 0U : static_cast<std::uint64_t>(t);  // a clock jumping below zero stops at zero
}

/// Faults that act before the image at fault frame @p frame (-1: none armed): stop, resize. False: send nothing.
bool sending_now(State& s, std::int64_t frame, ArvFakeCamera* camera) {
    if (s.armed.stop_at_frame >= 0 && frame == s.armed.stop_at_frame) {
        s.sending.store(false);
        s.stop_reached.store(true);
    }
    const bool on = s.sending.load();
    set_loss(s, on ? s.settings.faults.lost_packets_per_mille / 1000.0 : 1.0);
    if (!s.resized && s.armed.resize_at_frame >= 0 && frame >= 0 && frame + 1 >= s.armed.resize_at_frame) {
        // The registers change now; Aravis makes the next frame with them.
        s.resized = true;
        for (const auto& [reg, v] : {std::pair<guint32, int>{ARV_FAKE_CAMERA_REGISTER_WIDTH, s.armed.resize_width},
                                     {ARV_FAKE_CAMERA_REGISTER_HEIGHT, s.armed.resize_height},
                                     {ARV_FAKE_CAMERA_REGISTER_SENSOR_WIDTH, s.armed.resize_width},
                                     {ARV_FAKE_CAMERA_REGISTER_SENSOR_HEIGHT, s.armed.resize_height}}) {
            static_cast<void>(arv_fake_camera_write_register(camera, reg, static_cast<guint32>(v)));
        }
    }
    return on;
}

/// Aravis's fill callback: runs on the camera thread before each frame is sent.
void fill(ArvBuffer* buffer, void* data, guint32 /*exposure_us*/, guint32 /*gain*/, ArvPixelFormat format) {
    State& s = *static_cast<State*>(data);
    const std::uint64_t frame = s.frame++;
    s.frames.fetch_add(1U);
    const std::uint64_t now = monotonic_ns();
    if (s.arm_request.exchange(false) && s.fault_origin < 0) {
        s.fault_origin = static_cast<std::int64_t>(frame);
    }
    // The faults' frame: -1 while they are not armed (no fault frame matches it).
    const std::int64_t fault_frame = s.fault_origin < 0 ? -1 : static_cast<std::int64_t>(frame) - s.fault_origin;
    const auto at = [fault_frame](std::int64_t n) { return n >= 0 && fault_frame == n; };
    if (s.fault_ns.load() == 0U &&
        (at(s.armed.stop_at_frame) || at(s.armed.frozen_from_frame) || at(s.armed.stamp_jump_at_frame))) {
        s.fault_ns.store(now);
    }
    const std::uint64_t stamp = device_time(s, fault_frame, now);
    arv_buffer_set_timestamp(buffer, stamp);
    if (!sending_now(s, fault_frame, arv_gv_fake_camera_get_fake_camera(s.gv))) {
        s.stopped.fetch_add(1U);
        return;
    }
    const int w = arv_buffer_get_image_width(buffer);
    const int h = arv_buffer_get_image_height(buffer);
    // Aravis calls this only when the image of the current registers fits the buffer.
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-const-cast): Aravis gives the fill callback its buffer only as const data
    auto* bytes = static_cast<unsigned char*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    if (!depth_format(format) || w <= 0 || h <= 0 || pixels > s.image.size()) {
        std::memset(bytes, 0, pixels * ARV_PIXEL_FORMAT_BIT_PER_PIXEL(format) / 8U);
        s.other_format.fetch_add(1U);
        return;
    }
    const bool frozen = s.armed.frozen_from_frame >= 0 && fault_frame >= 1 &&
                        fault_frame >= s.armed.frozen_from_frame && s.have_image;
    if (frozen) {
        s.frozen.fetch_add(1U);
    } else {
        s.depth(FrameRequest{frame, now, stamp, w, h}, s.image.data());
        s.have_image = true;
        s.rendered.fetch_add(1U);
    }
    for (std::size_t i = 0U; i < pixels; ++i) {  // GigE Vision pixel data: little-endian
        bytes[2U * i] = static_cast<unsigned char>(s.image[i] & 0xffU);
        bytes[2U * i + 1U] = static_cast<unsigned char>(s.image[i] >> 8U);
    }
}

/// The camera's memory at power-on: format, rate, Scan3d values, model name.
void write_power_on_registers(const FakeCameraSettings& c, ArvFakeCamera* camera) {
    const auto reg = [camera](guint32 address, guint32 value) {
        static_cast<void>(arv_fake_camera_write_register(camera, address, value));
    };
    reg(ARV_FAKE_CAMERA_REGISTER_SENSOR_WIDTH, static_cast<guint32>(c.width));
    reg(ARV_FAKE_CAMERA_REGISTER_SENSOR_HEIGHT, static_cast<guint32>(c.height));
    reg(ARV_FAKE_CAMERA_REGISTER_WIDTH, static_cast<guint32>(c.width));
    reg(ARV_FAKE_CAMERA_REGISTER_HEIGHT, static_cast<guint32>(c.height));
    reg(ARV_FAKE_CAMERA_REGISTER_PIXEL_FORMAT, static_cast<guint32>(c.power_on_format));
    reg(ARV_FAKE_CAMERA_REGISTER_ACQUISITION_FRAME_PERIOD_US, static_cast<guint32>(std::lround(1e6 / c.frame_rate_hz)));
    reg(kScan3dDistanceUnit, c.distance_unit_mm ? 0U : 1U);
    reg(kScan3dSelector, 2U);  // CoordinateC
    reg(kCoord3dC16Available, c.offers_coord3d_c16 ? 1U : 0U);
    reg(kScan3dInvalidFlag, 1U);
    static_cast<void>(write_double(camera, kScan3dScale, c.coordinate_scale));
    static_cast<void>(write_double(camera, kScan3dOffset, c.coordinate_offset));
    static_cast<void>(write_double(camera, kScan3dFocalLength, c.focal_length_px));
    static_cast<void>(write_double(camera, kScan3dAspectRatio, c.aspect_ratio));
    static_cast<void>(write_double(camera, kScan3dPrincipalU, c.principal_point_u));
    static_cast<void>(write_double(camera, kScan3dPrincipalV, c.principal_point_v));
    static_cast<void>(write_double(camera, kScan3dInvalidValue, 0.0));
    char model[32] = "cellguard fake depth camera";
    static_cast<void>(arv_fake_camera_write_memory(camera, kModelNameOffset, sizeof model, model));
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

std::uint16_t raw_depth(float metres, double scale_m, double offset_m) noexcept {
    if (!std::isfinite(metres) || metres <= 0.0F || !(scale_m > 0.0)) {
        return 0U;
    }
    const double raw = std::nearbyint((static_cast<double>(metres) - offset_m) / scale_m);
    return raw >= 1.0 && raw <= 65535.0 ? static_cast<std::uint16_t>(raw) : std::uint16_t{0U};
}

const char* default_genicam_file() noexcept { return CELLGUARD_FAKE_CAMERA_GENICAM; }

std::string check_settings(const FakeCameraSettings& settings) {
    const FakeCameraSettings& c = settings;
    in_addr a{};
    if (!loopback_address(c.address, a)) {
        return "address '" + c.address + "' is not an IPv4 address in 127.0.0.0/8 (the fake serves loopback only)";
    }
    if (c.serial.empty() || c.serial.size() > 15U) {
        return "serial '" + c.serial + "' must have 1 to 15 characters";
    }
    if (c.width < 1 || c.width > kMaxSide || c.height < 1 || c.height > kMaxSide) {
        return "image size " + std::to_string(c.width) + "x" + std::to_string(c.height) + " is outside 1..2048";
    }
    if (!(c.frame_rate_hz >= 0.1 && c.frame_rate_hz <= 1000.0)) {
        return "frame rate " + std::to_string(c.frame_rate_hz) + " is outside 0.1..1000 Hz";
    }
    if (!finite_positive(c.coordinate_scale) || !std::isfinite(c.coordinate_offset) ||
        !finite_positive(c.aspect_ratio) || !std::isfinite(c.focal_length_px) || c.focal_length_px < 0.0 ||
        !std::isfinite(c.principal_point_u) || !std::isfinite(c.principal_point_v)) {
        return "the Scan3d values must be finite, the scale and aspect ratio positive";
    }
    const FakeCameraFaults& f = c.faults;
    if (f.lost_packets_per_mille > 1000U) {
        return "lost packets " + std::to_string(f.lost_packets_per_mille) + " per mille is above 1000";
    }
    if (f.resize_at_frame >= 0 &&
        (f.resize_width < 1 || f.resize_width > kMaxSide || f.resize_height < 1 || f.resize_height > kMaxSide)) {
        return "the resize fault's size is outside 1..2048";
    }
    return {};
}

FakeGigeCamera::FakeGigeCamera(FakeCameraSettings settings, DepthCallback depth) : state_(std::make_unique<State>()) {
    state_->settings = std::move(settings);
    state_->depth = std::move(depth);
    const FakeCameraSettings& c = state_->settings;
    const int w = std::max(c.width, c.faults.resize_at_frame >= 0 ? c.faults.resize_width : 0);
    const int h = std::max(c.height, c.faults.resize_at_frame >= 0 ? c.faults.resize_height : 0);
    state_->image.assign(
        static_cast<std::size_t>(std::clamp(w, 0, kMaxSide)) * static_cast<std::size_t>(std::clamp(h, 0, kMaxSide)),
        0U);
}

FakeGigeCamera::~FakeGigeCamera() { power_off(); }

bool FakeGigeCamera::start(std::string& error) {
    State& s = *state_;
    if (s.gv != nullptr) {
        return true;
    }
    error = check_settings(s.settings);
    in_addr a{};
    if (!error.empty() || !loopback_address(s.settings.address, a)) {
        return false;
    }
    if (!gvcp_port_free(a)) {
        error = "cannot bind UDP " + s.settings.address +
                ":3956: the address is not on an interface (add it: " + "`ip addr add " + s.settings.address +
                "/8 dev lo`, or run in tools/netns-run.sh) or another " + "camera holds it";
        return false;
    }
    const std::string xml = s.settings.genicam_file.empty() ? default_genicam_file() : s.settings.genicam_file;
    if (access(xml.c_str(), R_OK) != 0) {
        error = "cannot read the GenICam file " + xml;
        return false;
    }
    // Reset the camera thread's state before the camera exists (its thread starts inside _new_full).
    s.frame = 0U;
    s.clock_shift_ns = 0;
    s.resized = false;
    s.have_image = false;
    s.armed = s.first_run ? s.settings.faults : FakeCameraFaults{};
    s.armed.lost_packets_per_mille = s.settings.faults.lost_packets_per_mille;
    s.fault_origin = (s.settings.faults_from_start || !s.first_run) ? 0 : -1;
    s.sending.store(true);
    s.stop_reached.store(false);
    s.off_by_fault = false;
    s.loss_ratio_now = -1.0;
    s.power_on_ns = monotonic_ns();
    s.gv = arv_gv_fake_camera_new_full(s.settings.address.c_str(), s.settings.serial.c_str(), xml.c_str());
    if (s.gv == nullptr || arv_gv_fake_camera_is_running(s.gv) == FALSE) {
        error = "Aravis could not start a fake camera on " + s.settings.address +
                " (no interface has that address: `ip addr add " + s.settings.address +
                "/8 dev lo`, or run in tools/netns-run.sh)";
        power_off();
        return false;
    }
    ArvFakeCamera* camera = arv_gv_fake_camera_get_fake_camera(s.gv);
    write_power_on_registers(s.settings, camera);
    set_loss(s, s.settings.faults.lost_packets_per_mille / 1000.0);
    arv_fake_camera_set_fill_pattern(camera, fill, &s);
    s.first_run = false;
    return true;
}

void FakeGigeCamera::power_off() {
    if (state_ != nullptr && state_->gv != nullptr) {
        g_object_unref(state_->gv);  // joins the camera thread, closes its sockets
        state_->gv = nullptr;
    }
}

bool FakeGigeCamera::restart(std::string& error) {
    power_off();
    state_->restarts.fetch_add(1U);
    return start(error);
}

void FakeGigeCamera::set_sending(bool on) noexcept { state_->sending.store(on); }

void FakeGigeCamera::arm_faults() noexcept { state_->arm_request.store(true); }

void FakeGigeCamera::poll() {
    State& s = *state_;
    if (s.gv != nullptr && s.armed.power_off_at_stop && s.stop_reached.load()) {
        power_off();
        s.off_by_fault = true;
        s.restart_after_ms = s.armed.restart_after_ms;
        s.off_since_ns = monotonic_ns();
    }
    if (s.gv == nullptr && s.off_by_fault && s.restart_after_ms >= 0 &&
        monotonic_ns() - s.off_since_ns >= static_cast<std::uint64_t>(s.restart_after_ms) * 1000000U) {
        std::string error;
        if (!restart(error)) {
            s.off_by_fault = true;  // try again after another interval
            s.off_since_ns = monotonic_ns();
        }
    }
}

bool FakeGigeCamera::running() const noexcept { return state_->gv != nullptr; }

FakeCameraCounts FakeGigeCamera::counts() const noexcept {
    const State& s = *state_;
    return {s.frames.load(),       s.rendered.load(), s.frozen.load(),  s.stopped.load(),
            s.other_format.load(), s.restarts.load(), s.fault_ns.load()};
}

const FakeCameraSettings& FakeGigeCamera::settings() const noexcept { return state_->settings; }

}  // namespace cellguard::fake_camera
