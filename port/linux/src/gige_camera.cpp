// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A live GigE Vision depth camera through Aravis 0.8 (gige_camera.hpp).
#include "cellguard/port/gige_camera.hpp"
#include "cellguard/port/clock.hpp"

#include <arpa/inet.h>
#include <arv.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace cellguard::linux_port {
namespace {

constexpr ArvPixelFormat kCoord3dC16 = static_cast<ArvPixelFormat>(0x011000B8U);  // PFNC Coord3D_C16
constexpr std::uint32_t kSlots = 3U;
constexpr std::uint32_t kFresh = 4U;        // the triple buffer's "middle holds a new frame" bit
constexpr guint64 kPopTimeoutUs = 100000U;  // the supervisor looks at its stop flag this often
constexpr std::uint64_t kGvcpPort = 3956U;

ArvPixelFormat arv_format(GigePixelFormat f) noexcept {
    return f == GigePixelFormat::kMono16 ? ARV_PIXEL_FORMAT_MONO_16 : kCoord3dC16;
}

/// Takes a GError's message (and frees it); "" when there is none.
std::string take_error(GError*& e) {
    if (e == nullptr) {
        return {};
    }
    std::string m = e->message != nullptr ? e->message : "unknown error";
    g_clear_error(&e);
    return m.empty() ? std::string("unknown error") : m;
}

/// Missing frames between two block ids: 16-bit GigE Vision 1.x ids wrap
/// from 65535 to 1 (0 is never used); an id that goes back counts one.
std::uint64_t id_gap(std::uint64_t last, std::uint64_t id) noexcept {
    if (id > last) {
        return id - last - 1U;
    }
    if (last <= 0xFFFFU && last >= 0xFF00U && id >= 1U && id < 0x100U) {
        return (0xFFFFU - last) + (id - 1U);
    }
    return 1U;
}

/// The local address the OS routes to @p device (the interface to open it on), or "".
std::string interface_for(const std::string& device) {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(kGvcpPort));
    if (inet_pton(AF_INET, device.c_str(), &to.sin_addr) != 1) {
        return {};
    }
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        return {};
    }
    std::string result;
    sockaddr_in local{};
    socklen_t length = sizeof local;
    // A connected UDP socket sends nothing; it only asks the routing table.
    if (connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) ==
            0 &&  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
        getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) ==
            0) {  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
        std::array<char, INET_ADDRSTRLEN> text{};
        if (inet_ntop(AF_INET, &local.sin_addr, text.data(), text.size()) != nullptr) {
            result = text.data();
        }
    }
    close(fd);
    return result;
}

}  // namespace

const char* to_string(GigePixelFormat f) noexcept { return f == GigePixelFormat::kMono16 ? "Mono16" : "Coord3D_C16"; }

/// One open camera: the device, its stream and the buffers pushed to it.
struct Session {
    ArvDevice* device = nullptr;
    ArvStream* stream = nullptr;
};

struct GigeCamera::Impl {
    explicit Impl(GigeCameraConfig c) : cfg(std::move(c)), clock(cfg.clock) {}

    GigeCameraConfig cfg;
    GigeDeviceInfo info;           ///< read at start(); never written after it
    GigeDeviceInfo reopened;       ///< read at a reconnection (the supervisor thread's), compared with info
    GigeDeviceInfo* fill = &info;  ///< where open() reads the camera's values into
    DeviceClock clock;             ///< the supervisor thread's
    Session session;
    std::vector<std::uint8_t> buffer_memory;    ///< stream_buffers * payload, allocated at the first start
    std::size_t buffer_bytes = 0U;              ///< one buffer's share of buffer_memory
    std::vector<std::uint16_t> slots;           ///< kSlots frames of width * height
    std::array<GigeFrame, kSlots> slot_meta{};  ///< each slot's stamp, ids (pixels point into slots)
    std::uint32_t back = 0U;                    ///< the writer's slot (supervisor thread)
    std::atomic<std::uint32_t> middle{1U};      ///< the exchanged slot, | kFresh when new
    std::uint32_t front = 2U;                   ///< the reader's slot (cycle thread)
    bool has_front = false;
    bool has_last_id = false;
    std::uint64_t last_id = 0U;
    std::uint64_t last_buffer_us = 0U;

    std::atomic<bool> control_lost{false};
    std::atomic<bool> streaming{false};
    std::atomic<bool> stop_requested{false};
    std::mutex mutex;  ///< guards error and wakes the supervisor's waits
    std::condition_variable wake;
    std::string error;
    std::thread supervisor;

    std::atomic<std::uint64_t> received{0U}, complete{0U}, incomplete{0U}, wrong_format{0U}, missing{0U},
        stamp_refused{0U}, published{0U}, disconnections{0U}, reconnect_failures{0U}, reconnections{0U};

    [[nodiscard]] std::string label() const {
        const std::string where = !cfg.address.empty() ? cfg.address : !cfg.serial.empty() ? cfg.serial : cfg.device_id;
        return "camera '" + cfg.name + "' (" + where + ")";
    }

    bool open(std::string& err);
    bool open_device(std::string& err);
    bool check_serial(std::string& err);
    bool configure(std::string& err) const;
    bool set_and_check_int(const char* feature, std::int64_t value, std::string& err) const;
    void read_scan3d() const;
    bool make_stream(std::string& err);
    [[nodiscard]] bool same_as_at_start(std::string& err) const;
    void close(bool camera_lost = false) noexcept;
    void run() noexcept;
    void handle(ArvBuffer* buffer) noexcept;
    void publish(const std::uint16_t* pixels, std::uint64_t stamp, std::uint64_t receive, std::uint64_t id) noexcept;
    void set_error(const std::string& e);
};

namespace {

extern "C" void on_control_lost(ArvDevice* /*device*/, gpointer user_data) {
    static_cast<std::atomic<bool>*>(user_data)->store(true);
}

}  // namespace

bool GigeCamera::Impl::open_device(std::string& err) {
    GError* e = nullptr;
    if (!cfg.address.empty()) {
        const std::string local = interface_for(cfg.address);
        if (local.empty()) {
            err = label() + ": '" + cfg.address + "' is not an IPv4 address this host can reach";
            return false;
        }
        GInetAddress* iface = g_inet_address_new_from_string(local.c_str());
        GInetAddress* dev = g_inet_address_new_from_string(cfg.address.c_str());
        session.device = arv_gv_device_new(iface, dev, &e);
        g_object_unref(iface);
        g_object_unref(dev);
    } else {
        std::string id = cfg.device_id;
        if (id.empty()) {  // by serial: discovery on every interface
            arv_update_device_list();
            for (unsigned i = 0U; i < arv_get_n_devices(); ++i) {
                const char* serial = arv_get_device_serial_nbr(i);
                if (serial != nullptr && cfg.serial == serial && arv_get_device_id(i) != nullptr) {
                    id = arv_get_device_id(i);
                }
            }
            if (id.empty()) {
                err = label() + ": no camera with serial '" + cfg.serial + "' found";
                return false;
            }
        }
        session.device = arv_open_device(id.c_str(), &e);
    }
    if (session.device == nullptr) {
        err = label() + ": cannot open: " + (e != nullptr ? take_error(e) : std::string("no answer"));
        return false;
    }
    g_signal_connect(session.device, "control-lost", G_CALLBACK(on_control_lost), &control_lost);
    // A value outside a feature's range is refused by Aravis, not written (the default writes it).
    arv_device_set_range_check_policy(session.device, ARV_RANGE_CHECK_POLICY_ENABLE);
    return true;
}

bool GigeCamera::Impl::check_serial(std::string& err) {
    GError* e = nullptr;
    const char* feature = arv_device_is_feature_available(session.device, "DeviceSerialNumber", nullptr) != FALSE
                              ? "DeviceSerialNumber"
                              : "DeviceID";
    const char* serial = arv_device_get_string_feature_value(session.device, feature, &e);
    if (serial == nullptr || e != nullptr) {
        err = label() + ": cannot read " + feature + ": " + take_error(e);
        return false;
    }
    fill->serial = serial;
    for (const std::string* want : {&cfg.expected_serial, &cfg.serial}) {
        if (!want->empty() && fill->serial != *want) {
            err = label() + ": " + feature + " is '" + fill->serial + "', expected '" + *want +
                  "' (another camera than configured: refused)";
            return false;
        }
    }
    for (auto [name, out] :
         {std::pair{"DeviceVendorName", &fill->vendor}, std::pair{"DeviceModelName", &fill->model}}) {
        const char* v = arv_device_get_string_feature_value(session.device, name, &e);
        *out = v != nullptr && e == nullptr ? v : "";
        g_clear_error(&e);
    }
    return true;
}

bool GigeCamera::Impl::set_and_check_int(const char* feature, std::int64_t value, std::string& err) const {
    GError* e = nullptr;
    // A camera whose value is already right is not written: fixed-size sensors (time-of-flight cameras,
    // the test's fake) publish Width and Height read-only, and a refused write would stop a good camera.
    const std::int64_t before = arv_device_get_integer_feature_value(session.device, feature, &e);
    if (e == nullptr && before == value) {
        return true;
    }
    g_clear_error(&e);
    arv_device_set_integer_feature_value(session.device, feature, value, &e);
    if (e != nullptr) {
        err = label() + ": " + feature + " = " + std::to_string(value) + " refused: " + take_error(e);
        return false;
    }
    const std::int64_t got = arv_device_get_integer_feature_value(session.device, feature, &e);
    if (e != nullptr || got != value) {
        err = label() + ": " + feature + " is " + std::to_string(got) + " after setting " + std::to_string(value) +
              (e != nullptr ? ": " + take_error(e) : std::string());
        return false;
    }
    return true;
}

bool GigeCamera::Impl::configure(std::string& err) const {
    ArvDevice* d = session.device;
    GError* e = nullptr;
    const auto has = [d](const char* f) { return arv_device_is_feature_available(d, f, nullptr) != FALSE; };
    arv_device_execute_command(d, "AcquisitionStop", &e);  // a camera that still streams refuses size changes
    g_clear_error(&e);
    for (auto [feature, value] : {std::pair{"TriggerMode", "Off"}, std::pair{"AcquisitionMode", "Continuous"}}) {
        if (has(feature)) {
            arv_device_set_string_feature_value(d, feature, value, &e);
            if (e != nullptr) {
                err = label() + ": " + feature + " = " + value + " refused: " + take_error(e);
                return false;
            }
        }
    }
    for (const char* offset : {"OffsetX", "OffsetY"}) {
        if (has(offset) && !set_and_check_int(offset, 0, err)) {
            return false;
        }
    }
    if (!set_and_check_int("Width", cfg.width, err) || !set_and_check_int("Height", cfg.height, err)) {
        return false;
    }
    const char* format = to_string(cfg.pixel_format);
    arv_device_set_string_feature_value(d, "PixelFormat", format, &e);
    const char* got_format = e == nullptr ? arv_device_get_string_feature_value(d, "PixelFormat", &e) : nullptr;
    if (e != nullptr || got_format == nullptr || std::strcmp(got_format, format) != 0) {
        err = label() + ": PixelFormat " + format + " refused" + (e != nullptr ? ": " + take_error(e) : std::string()) +
              (got_format != nullptr ? std::string(" (the camera has ") + got_format + ")" : std::string());
        return false;
    }
    if (has("AcquisitionFrameRateEnable")) {
        arv_device_set_boolean_feature_value(d, "AcquisitionFrameRateEnable", TRUE, &e);
        g_clear_error(&e);
    }
    arv_device_set_float_feature_value(d, "AcquisitionFrameRate", cfg.frame_rate_hz, &e);
    const double rate = e == nullptr ? arv_device_get_float_feature_value(d, "AcquisitionFrameRate", &e) : 0.0;
    if (e != nullptr || std::abs(rate - cfg.frame_rate_hz) > 0.01 * cfg.frame_rate_hz) {
        err = label() + ": AcquisitionFrameRate " + std::to_string(cfg.frame_rate_hz) + " Hz refused" +
              (e != nullptr ? ": " + take_error(e) : " (the camera runs at " + std::to_string(rate) + " Hz)");
        return false;
    }
    if (cfg.packet_size > 0) {
        arv_gv_device_set_packet_size(ARV_GV_DEVICE(d), cfg.packet_size, &e);
        const guint got = e == nullptr ? arv_gv_device_get_packet_size(ARV_GV_DEVICE(d), &e) : 0U;
        if (e != nullptr || static_cast<int>(got) != cfg.packet_size) {
            err = label() + ": packet size " + std::to_string(cfg.packet_size) + " refused" +
                  (e != nullptr ? ": " + take_error(e) : " (the camera has " + std::to_string(got) + ")");
            return false;
        }
    }
    fill->payload_bytes = arv_device_get_integer_feature_value(d, "PayloadSize", &e);
    const auto image_bytes = static_cast<std::int64_t>(cfg.width) * cfg.height * 2;
    if (e != nullptr || fill->payload_bytes < image_bytes || fill->payload_bytes > 4 * image_bytes) {
        err = label() + ": PayloadSize " + std::to_string(fill->payload_bytes) + " does not fit a " +
              std::to_string(cfg.width) + " x " + std::to_string(cfg.height) + " 16-bit image " + take_error(e);
        return false;
    }
    fill->tick_frequency_hz = arv_gv_device_get_timestamp_tick_frequency(ARV_GV_DEVICE(d), &e);
    g_clear_error(&e);
    read_scan3d();
    return true;
}

void GigeCamera::Impl::read_scan3d() const {
    ArvDevice* d = session.device;
    GError* e = nullptr;
    const auto read = [d, &e](const char* f, double& out) {
        if (arv_device_is_feature_available(d, f, nullptr) == FALSE) {
            return false;
        }
        out = arv_device_get_float_feature_value(d, f, &e);
        const bool ok = e == nullptr && std::isfinite(out);
        g_clear_error(&e);
        return ok;
    };
    if (arv_device_is_feature_available(d, "Scan3dCoordinateSelector", nullptr) != FALSE) {
        arv_device_set_string_feature_value(d, "Scan3dCoordinateSelector", "CoordinateC", &e);  // the depth axis
        g_clear_error(&e);
    }
    double unit = 0.001;  // SFNC: Scan3dDistanceUnit defaults to millimetres
    if (arv_device_is_feature_available(d, "Scan3dDistanceUnit", nullptr) != FALSE) {
        const char* u = arv_device_get_string_feature_value(d, "Scan3dDistanceUnit", &e);
        unit = u == nullptr                        ? 0.0
               : std::strcmp(u, "Meter") == 0      ? 1.0
               : std::strcmp(u, "Millimeter") == 0 ? 0.001
                                                   : 0.0;
        g_clear_error(&e);
    }
    double scale = 0.0;
    fill->has_depth_scale = unit > 0.0 && read("Scan3dCoordinateScale", scale) && scale > 0.0;
    if (fill->has_depth_scale) {
        double offset = 0.0;
        fill->depth_scale_m = scale * unit;
        fill->depth_offset_m = read("Scan3dCoordinateOffset", offset) ? offset * unit : 0.0;
    }
    fill->has_intrinsics = read("Scan3dFocalLength", fill->focal_px) && read("Scan3dPrincipalPointU", fill->cx) &&
                           read("Scan3dPrincipalPointV", fill->cy) && fill->focal_px > 0.0;
    // SFNC has one focal length; a camera with non-square pixels states fy / fx as Scan3dAspectRatio.
    fill->aspect_ratio = 1.0;
    if (arv_device_is_feature_available(d, "Scan3dAspectRatio", nullptr) != FALSE &&
        !(read("Scan3dAspectRatio", fill->aspect_ratio) && std::isfinite(fill->aspect_ratio) &&
          fill->aspect_ratio > 0.0)) {
        fill->has_intrinsics = false;  // present but unreadable or not positive: no intrinsics from this camera
        fill->aspect_ratio = 1.0;
    }
}

bool GigeCamera::Impl::make_stream(std::string& err) {
    const auto payload = static_cast<std::size_t>(fill->payload_bytes);
    if (buffer_memory.empty()) {  // the first start: every byte the stream will ever use
        buffer_bytes = payload;
        buffer_memory.assign(payload * cfg.stream_buffers, 0U);
    } else if (payload > buffer_bytes) {
        err = label() + ": PayloadSize grew from " + std::to_string(buffer_bytes) + " to " + std::to_string(payload) +
              " bytes after reconnecting";
        return false;
    }
    GError* e = nullptr;
    session.stream = arv_device_create_stream(session.device, nullptr, nullptr, &e);
    if (session.stream == nullptr) {
        err = label() + ": cannot make the stream: " + take_error(e);
        return false;
    }
    if (ARV_IS_GV_STREAM(session.stream) != FALSE) {
        g_object_set(session.stream, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED, "socket-buffer-size",
                     cfg.socket_buffer_bytes, "packet-resend", ARV_GV_STREAM_PACKET_RESEND_NEVER, nullptr);
    }
    for (std::size_t i = 0U; i < cfg.stream_buffers; ++i) {
        arv_stream_push_buffer(session.stream, arv_buffer_new(payload, buffer_memory.data() + i * buffer_bytes));
    }
    return true;
}

bool GigeCamera::Impl::open(std::string& err) {
    control_lost.store(false);
    if (!open_device(err) || !check_serial(err) || !configure(err) || !same_as_at_start(err) || !make_stream(err)) {
        close();
        return false;
    }
    clock.restart();
    has_last_id = false;
    last_buffer_us = monotonic_now_us();
    GError* e = nullptr;
    arv_device_execute_command(session.device, "AcquisitionStart", &e);
    if (e != nullptr) {
        err = label() + ": AcquisitionStart refused: " + take_error(e);
        close();
        return false;
    }
    streaming.store(true);
    return true;
}

bool GigeCamera::Impl::same_as_at_start(std::string& err) const {
    if (fill == &info) {
        return true;  // the start itself
    }
    const GigeDeviceInfo& a = info;
    const GigeDeviceInfo& b = reopened;
    // The frames are read with the start's values: a camera that comes back with others is refused.
    if (a.payload_bytes != b.payload_bytes || a.has_depth_scale != b.has_depth_scale ||
        a.depth_scale_m != b.depth_scale_m ||
        a.depth_offset_m != b.depth_offset_m ||  // exact: the same camera reports the same values
        a.has_intrinsics != b.has_intrinsics || a.focal_px != b.focal_px || a.aspect_ratio != b.aspect_ratio ||
        a.cx != b.cx || a.cy != b.cy) {
        err = label() +
              ": after reconnecting, PayloadSize or the Scan3d scale, offset or intrinsics differ from the "
              "values read at start";
        return false;
    }
    return true;
}

void GigeCamera::Impl::close(bool camera_lost) noexcept {
    streaming.store(false);
    // A lost camera does not answer: each command would wait out Aravis' GVCP retries.
    if (session.device != nullptr && !camera_lost) {
        GError* e = nullptr;
        arv_device_execute_command(session.device, "AcquisitionStop", &e);
        g_clear_error(&e);
    }
    if (session.stream != nullptr) {
        g_object_unref(session.stream);  // stops its thread; the buffers' memory is ours and stays
        session.stream = nullptr;
    }
    if (session.device != nullptr) {
        g_signal_handlers_disconnect_by_data(session.device, &control_lost);
        g_object_unref(session.device);
        session.device = nullptr;
    }
}

void GigeCamera::Impl::set_error(const std::string& e) {
    const std::lock_guard<std::mutex> lock(mutex);
    error = e;
}

void GigeCamera::Impl::publish(const std::uint16_t* pixels, std::uint64_t stamp, std::uint64_t receive,
                               std::uint64_t id) noexcept {
    const std::size_t n = static_cast<std::size_t>(cfg.width) * static_cast<std::size_t>(cfg.height);
    std::memcpy(slots.data() + back * n, pixels, n * sizeof(std::uint16_t));
    GigeFrame& meta = slot_meta[back];
    meta.stamp_us = stamp;
    meta.receive_us = receive;
    meta.frame_id = id;
    meta.sequence = published.load(std::memory_order_relaxed) + 1U;
    back = middle.exchange(back | kFresh, std::memory_order_acq_rel) & (kFresh - 1U);
    published.fetch_add(1U, std::memory_order_relaxed);
    if (cfg.signal != nullptr) {
        cfg.signal->notify();  // the paced loop may wait for this frame (frame_signal.hpp)
    }
}

void GigeCamera::Impl::handle(ArvBuffer* buffer) noexcept {
    received.fetch_add(1U, std::memory_order_relaxed);
    // The receive time: when this thread has the completed buffer (Aravis
    // runs its buffer-done callback only after queueing the buffer, so the
    // callback's time can come after the pop). Never before the true arrival.
    const std::uint64_t receive = monotonic_now_us();
    last_buffer_us = receive;
    const std::uint64_t id = arv_buffer_get_frame_id(buffer);
    if (id != 0U) {  // block id 0 is never sent (a buffer whose leader was lost carries it): no gap to count
        if (has_last_id) {
            missing.fetch_add(id_gap(last_id, id), std::memory_order_relaxed);
        }
        has_last_id = true;
        last_id = id;
    }
    if (arv_buffer_get_status(buffer) != ARV_BUFFER_STATUS_SUCCESS) {
        incomplete.fetch_add(1U, std::memory_order_relaxed);
        return;
    }
    std::size_t size = 0U;
    const void* data = arv_buffer_get_image_data(buffer, &size);
    const std::size_t n = static_cast<std::size_t>(cfg.width) * static_cast<std::size_t>(cfg.height);
    if (data == nullptr || size < n * 2U || arv_buffer_get_image_width(buffer) != cfg.width ||
        arv_buffer_get_image_height(buffer) != cfg.height ||
        arv_buffer_get_image_pixel_format(buffer) != arv_format(cfg.pixel_format)) {
        wrong_format.fetch_add(1U, std::memory_order_relaxed);
        return;
    }
    complete.fetch_add(1U, std::memory_order_relaxed);
    const std::uint64_t refused_before = clock.refused() + clock.relearning();
    const MappedStamp stamp = clock.map(arv_buffer_get_timestamp(buffer) / 1000U, receive);
    if (stamp.verdict != StampVerdict::kAccepted) {
        // Refusals and the relearning after them; not the learning after a (re)start.
        stamp_refused.fetch_add(clock.refused() + clock.relearning() - refused_before, std::memory_order_relaxed);
        return;
    }
    publish(static_cast<const std::uint16_t*>(data), stamp.mono_us, receive, id);
}

void GigeCamera::Impl::run() noexcept {
    std::uint64_t next_attempt = 0U;
    while (!stop_requested.load()) {
        if (session.stream == nullptr) {
            std::unique_lock<std::mutex> lock(mutex);
            const std::uint64_t now = monotonic_now_us();
            if (now < next_attempt) {
                wake.wait_for(lock, std::chrono::microseconds(next_attempt - now),
                              [this] { return stop_requested.load(); });
                continue;
            }
            lock.unlock();
            try {
                std::string err;
                reopened = GigeDeviceInfo{};
                fill = &reopened;
                if (open(err)) {
                    reconnections.fetch_add(1U);
                    set_error("");
                } else {
                    reconnect_failures.fetch_add(1U);
                    set_error(err);
                }
            } catch (...) {  // out of memory in a message: try again later
                reconnect_failures.fetch_add(1U);
            }
            next_attempt = monotonic_now_us() + cfg.reconnect_interval_us;
            continue;
        }
        ArvBuffer* buffer = arv_stream_timeout_pop_buffer(session.stream, kPopTimeoutUs);
        if (buffer != nullptr) {
            handle(buffer);
            arv_stream_push_buffer(session.stream, buffer);
        }
        if (control_lost.load() || monotonic_now_us() - last_buffer_us > cfg.no_frame_timeout_us) {
            streaming.store(false);
            disconnections.fetch_add(1U);
            close(true);  // blocks while Aravis gives up on the camera (leaving control): measured seconds
            next_attempt = monotonic_now_us() + cfg.reconnect_interval_us;
        }
    }
    close();
}

GigeCamera::GigeCamera(GigeCameraConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {}

GigeCamera::~GigeCamera() { stop(); }

bool GigeCamera::start(std::string& error) {
    Impl& m = *impl_;
    const GigeCameraConfig& c = m.cfg;
    if (m.supervisor.joinable() || m.session.device != nullptr) {
        error = m.label() + ": already started";
        return false;
    }
    const bool by = !c.address.empty() || !c.serial.empty() || !c.device_id.empty();
    if (!by || c.width <= 0 || c.height <= 0 || c.width > 65535 || c.height > 65535 ||
        !std::isfinite(c.frame_rate_hz) || c.frame_rate_hz <= 0.0 || c.stream_buffers < 2U || c.stream_buffers > 64U ||
        c.socket_buffer_bytes <= 0 || c.packet_size < 0 || c.reconnect_interval_us == 0U ||
        c.no_frame_timeout_us == 0U || !valid(c.clock)) {
        error = m.label() + ": invalid settings (address, serial or id; size; frame rate; buffers; clock limits)";
        return false;
    }
    const std::size_t n = static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
    m.slots.assign(kSlots * n, 0U);
    for (std::uint32_t s = 0U; s < kSlots; ++s) {
        m.slot_meta[s].pixels = m.slots.data() + s * n;
        m.slot_meta[s].width = c.width;
        m.slot_meta[s].height = c.height;
    }
    if (!m.open(error)) {
        return false;
    }
    m.stop_requested.store(false);
    m.supervisor = std::thread([&m] { m.run(); });
    return true;
}

void GigeCamera::stop() noexcept {
    Impl& m = *impl_;
    {
        const std::lock_guard<std::mutex> lock(m.mutex);
        m.stop_requested.store(true);
    }
    m.wake.notify_all();
    if (m.supervisor.joinable()) {
        m.supervisor.join();
    }
    m.close();
}

const GigeDeviceInfo& GigeCamera::device() const noexcept { return impl_->info; }

const GigeCameraConfig& GigeCamera::config() const noexcept { return impl_->cfg; }

bool GigeCamera::latest(GigeFrame& frame) noexcept {
    Impl& m = *impl_;
    if ((m.middle.load(std::memory_order_acquire) & kFresh) != 0U) {
        m.front = m.middle.exchange(m.front, std::memory_order_acq_rel) & (kFresh - 1U);
        m.has_front = true;
    }
    if (!m.has_front) {
        return false;
    }
    frame = m.slot_meta[m.front];
    return true;
}

std::uint64_t GigeCamera::published() const noexcept { return impl_->published.load(); }

GigeCounters GigeCamera::counters() const noexcept {
    const Impl& m = *impl_;
    GigeCounters c;
    c.received = m.received.load();
    c.complete = m.complete.load();
    c.incomplete = m.incomplete.load();
    c.wrong_format = m.wrong_format.load();
    c.missing = m.missing.load();
    c.stamp_refused = m.stamp_refused.load();
    c.published = m.published.load();
    c.disconnections = m.disconnections.load();
    c.reconnect_failures = m.reconnect_failures.load();
    c.reconnections = m.reconnections.load();
    return c;
}

bool GigeCamera::connected() const noexcept { return impl_->streaming.load(); }

std::string GigeCamera::last_error() const {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->error;
}

}  // namespace cellguard::linux_port
