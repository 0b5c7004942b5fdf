// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the fake GigE Vision depth camera (apps/fake-camera) is a real
// GigE Vision camera to Aravis's own client: opened by address (no
// discovery), it streams the callback's depth bytes with the device time
// stamps, and injects each fault as set: frozen image, time stamp jump, lost
// packets, stop, power-off and reboot, a format it does not offer, a
// resolution change.
//
// The cases that open cameras use 127.0.0.2 and up: they are marked skip, so a
// plain run of the unit tests skips them; the ctest
// fake_gige_camera_unit_tests_in_a_loopback_namespace runs them inside
// tools/netns-run.sh with --no-skip:
//   tools/netns-run.sh build/tests/cellguard_unit_tests --no-skip -tc='fake gige*'
#if defined(CELLGUARD_HAVE_FAKE_GIGE)
#include <doctest/doctest.h>

#include <arv.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cellguard/fake_camera/fake_gige_camera.hpp"

using namespace cellguard::fake_camera;

namespace {

constexpr int kW = 64;
constexpr int kH = 48;

/// The test pattern: pixel 0 holds the frame index, the others depend on it and on the pixel.
std::uint16_t pattern(std::uint64_t frame, int i) {
    return i == 0 ? static_cast<std::uint16_t>(frame) : static_cast<std::uint16_t>(1U + (frame * 7U + i * 3U) % 60000U);
}

/// Remembers the device time stamp the camera gave each frame.
struct Recorder {
    std::mutex mutex;
    std::map<std::uint64_t, std::uint64_t> stamps;

    DepthCallback callback() {
        return [this](const FrameRequest& r, std::uint16_t* image) {
            for (int i = 0; i < r.width * r.height; ++i) {
                image[i] = pattern(r.frame, i);
            }
            const std::lock_guard<std::mutex> lock(mutex);
            stamps[r.frame] = r.device_time_ns;
        };
    }
    std::uint64_t stamp(std::uint64_t frame) {
        const std::lock_guard<std::mutex> lock(mutex);
        const auto it = stamps.find(frame);
        return it == stamps.end() ? 0U : it->second;
    }
};

FakeCameraSettings settings(const std::string& address) {
    FakeCameraSettings s;
    s.address = address;
    s.serial = "UT-" + address.substr(address.rfind('.') + 1U);
    s.width = kW;
    s.height = kH;
    s.frame_rate_hz = 20.0;
    s.focal_length_px = 50.0;
    s.aspect_ratio = 1.25;
    s.principal_point_u = 31.5;
    s.principal_point_v = 23.5;
    s.coordinate_scale = 0.25;
    s.coordinate_offset = 100.0;
    s.clock_offset_ns = 5000000000U;
    return s;
}

/// One frame as Aravis's client received it.
struct Received {
    ArvBufferStatus status = ARV_BUFFER_STATUS_UNKNOWN;
    std::uint64_t timestamp_ns = 0U;
    int width = 0;
    int height = 0;
    std::vector<std::uint16_t> pixels;  ///< decoded little-endian, complete frames only
};

/// Aravis's client with plain calls: the device by address, its stream, buffers.
class Client {
public:
    explicit Client(const std::string& address) {
        GInetAddress* iface = g_inet_address_new_from_string("127.0.0.1");
        GInetAddress* dev = g_inet_address_new_from_string(address.c_str());
        device_ = arv_gv_device_new(iface, dev, &error_);
        g_object_unref(iface);
        g_object_unref(dev);
    }
    ~Client() {
        if (stream_ != nullptr) {
            if (device_ != nullptr) {
                arv_device_execute_command(device_, "AcquisitionStop", nullptr);
            }
            g_object_unref(stream_);
        }
        if (device_ != nullptr) {
            g_object_unref(device_);
        }
        g_clear_error(&error_);
    }
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    bool open() const { return device_ != nullptr; }
    std::string error() const { return error_ != nullptr ? error_->message : ""; }
    ArvDevice* device() { return device_; }

    bool set(const char* feature, const char* value) {
        g_clear_error(&error_);
        arv_device_set_string_feature_value(device_, feature, value, &error_);
        return error_ == nullptr;
    }
    std::string get(const char* feature) {
        g_clear_error(&error_);
        const char* v = arv_device_get_string_feature_value(device_, feature, &error_);
        return v != nullptr ? v : "";
    }
    double get_float(const char* feature) { return arv_device_get_float_feature_value(device_, feature, nullptr); }
    std::int64_t get_int(const char* feature) {
        return arv_device_get_integer_feature_value(device_, feature, nullptr);
    }

    /// Starts streaming into 8 buffers of PayloadSize.
    bool start() {
        g_clear_error(&error_);
        const std::int64_t payload = get_int("PayloadSize");
        stream_ = arv_device_create_stream(device_, nullptr, nullptr, &error_);
        if (stream_ == nullptr || payload <= 0) {
            return false;
        }
        // 1 MiB (the kernel caps it at net.core.rmem_max): a frame burst must not overflow the
        // socket while this thread is late, or the test would count losses of its own.
        g_object_set(stream_, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED, "socket-buffer-size", 1048576,
                     nullptr);
        for (int i = 0; i < 8; ++i) {
            arv_stream_push_buffer(stream_, arv_buffer_new(static_cast<std::size_t>(payload), nullptr));
        }
        arv_device_execute_command(device_, "AcquisitionStart", &error_);
        return error_ == nullptr;
    }
    /// The next frame within @p timeout_ms, or false.
    bool next(Received& r, int timeout_ms = 2000) {
        ArvBuffer* b = arv_stream_timeout_pop_buffer(stream_, static_cast<guint64>(timeout_ms) * 1000U);
        if (b == nullptr) {
            return false;
        }
        r = Received{};
        r.status = arv_buffer_get_status(b);
        r.timestamp_ns = arv_buffer_get_timestamp(b);
        if (r.status == ARV_BUFFER_STATUS_SUCCESS) {
            r.width = arv_buffer_get_image_width(b);
            r.height = arv_buffer_get_image_height(b);
            std::size_t size = 0U;
            const auto* bytes = static_cast<const unsigned char*>(arv_buffer_get_image_data(b, &size));
            r.pixels.resize(size / 2U);
            for (std::size_t i = 0U; i < r.pixels.size(); ++i) {
                r.pixels[i] = static_cast<std::uint16_t>(bytes[2U * i] | (bytes[2U * i + 1U] << 8U));
            }
        }
        arv_stream_push_buffer(stream_, b);
        return true;
    }
    /// Aravis's counts: completed buffers, failures, underruns.
    void statistics(guint64& completed, guint64& failures, guint64& underruns) {
        arv_stream_get_statistics(stream_, &completed, &failures, &underruns);
    }

private:
    GError* error_ = nullptr;
    ArvDevice* device_ = nullptr;
    ArvStream* stream_ = nullptr;
};

/// A camera, its recorder, and Aravis's client once started.
struct Rig {
    Recorder recorder;
    FakeGigeCamera camera;
    std::unique_ptr<Client> client;

    explicit Rig(const FakeCameraSettings& s) : camera(s, recorder.callback()) {}

    /// Starts the camera; opens the client, sets Coord3D_C16 and streams.
    bool start() {
        std::string error;
        if (!camera.start(error)) {
            FAIL_CHECK("the fake did not start (run in tools/netns-run.sh): " << error);
            return false;
        }
        return connect();
    }
    /// A new client that sets Coord3D_C16 and streams.
    bool connect() {
        client.reset();
        client = std::make_unique<Client>(camera.settings().address);
        if (!client->open() || !client->set("PixelFormat", "Coord3D_C16") || !client->start()) {
            FAIL_CHECK("Aravis's client could not open and start " << camera.settings().address << ": "
                                                                   << client->error());
            return false;
        }
        return true;
    }
    /// Up to @p n frames (fewer when none comes within @p timeout_ms).
    std::vector<Received> frames(int n, int timeout_ms = 2000) {
        std::vector<Received> out;
        Received r;
        while (static_cast<int>(out.size()) < n && client->next(r, timeout_ms)) {
            out.push_back(r);
        }
        return out;
    }
};

/// Calls poll() every 20 ms while it lives.
class Poller {
public:
    explicit Poller(FakeGigeCamera& camera)
        : thread_([this, &camera] {
              while (!stop_.load()) {
                  camera.poll();
                  std::this_thread::sleep_for(std::chrono::milliseconds(20));
              }
          }) {}
    ~Poller() {
        stop_.store(true);
        thread_.join();
    }
    Poller(const Poller&) = delete;
    Poller& operator=(const Poller&) = delete;

private:
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

/// True when @p r holds exactly the pattern of frame pixels[0] (or of @p frame when given).
bool holds_pattern(const Received& r, std::int64_t frame = -1) {
    if (r.pixels.size() != static_cast<std::size_t>(kW * kH)) {
        return false;
    }
    const std::uint64_t f = frame >= 0 ? static_cast<std::uint64_t>(frame) : r.pixels[0];
    for (int i = 0; i < kW * kH; ++i) {
        if (r.pixels[static_cast<std::size_t>(i)] != pattern(f, i)) {
            return false;
        }
    }
    return true;
}

}  // namespace

// verifies: SR-CAM-008
TEST_CASE("fake gige: settings off loopback, bad sizes and Scan3d values are refused") {
    FakeCameraSettings s = settings("127.0.0.2");
    CHECK(check_settings(s).empty());
    s.address = "192.0.2.7";
    CHECK(check_settings(s).find("127.0.0.0/8") != std::string::npos);
    s = settings("127.0.0.2");
    s.serial = "a-serial-of-16-c";
    CHECK_FALSE(check_settings(s).empty());
    s = settings("127.0.0.2");
    s.width = 0;
    CHECK_FALSE(check_settings(s).empty());
    s = settings("127.0.0.2");
    s.coordinate_scale = 0.0;
    CHECK_FALSE(check_settings(s).empty());
    s = settings("127.0.0.2");
    s.faults.lost_packets_per_mille = 1001U;
    CHECK_FALSE(check_settings(s).empty());
    std::string error;
    FakeGigeCamera off(settings("10.0.0.1"), nullptr);
    CHECK_FALSE(off.start(error));
    CHECK(error.find("loopback") != std::string::npos);
    CHECK_FALSE(off.running());
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: raw depth rounds to the unit, 0 for no reading and out of range") {
    CHECK(raw_depth(1.2345F, 0.001, 0.0) == 1235U);
    CHECK(raw_depth(1.0F, 0.0005, 0.5) == 1000U);
    CHECK(raw_depth(0.0F, 0.001, 0.0) == 0U);
    CHECK(raw_depth(-1.0F, 0.001, 0.0) == 0U);
    CHECK(raw_depth(std::numeric_limits<float>::quiet_NaN(), 0.001, 0.0) == 0U);
    CHECK(raw_depth(70.0F, 0.001, 0.0) == 0U);    // 70000 units: beyond 16 bits
    CHECK(raw_depth(0.0004F, 0.001, 0.0) == 0U);  // rounds to 0: no reading, not a depth of 0
    CHECK(raw_depth(65.535F, 0.001, 0.0) == 65535U);
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: Aravis's client reads the Scan3d features and gets the callback's depth bytes and time stamps" *
          doctest::skip()) {
    const FakeCameraSettings s = settings("127.0.0.2");
    Rig rig(s);
    REQUIRE(rig.start());
    Client& c = *rig.client;
    CHECK(c.get("PixelFormat") == "Coord3D_C16");
    CHECK(c.get("DeviceSerialNumber") == "UT-2");
    CHECK(c.get("Scan3dDistanceUnit") == "Millimeter");
    CHECK(c.get_int("Width") == kW);
    CHECK(c.get_int("Height") == kH);
    CHECK(c.get_float("Scan3dFocalLength") == doctest::Approx(50.0));
    CHECK(c.get_float("Scan3dAspectRatio") == doctest::Approx(1.25));
    CHECK(c.get_float("Scan3dPrincipalPointU") == doctest::Approx(31.5));
    CHECK(c.get_float("Scan3dPrincipalPointV") == doctest::Approx(23.5));
    CHECK(c.get_float("Scan3dCoordinateScale") == doctest::Approx(0.25));
    CHECK(c.get_float("Scan3dCoordinateOffset") == doctest::Approx(100.0));
    const std::vector<Received> got = rig.frames(10);
    REQUIRE(got.size() == 10U);
    std::uint64_t last_frame = 0U;
    for (std::size_t i = 0U; i < got.size(); ++i) {
        const Received& r = got[i];
        CHECK(r.status == ARV_BUFFER_STATUS_SUCCESS);
        CHECK(r.width == kW);
        CHECK(r.height == kH);
        CHECK(holds_pattern(r));
        const std::uint64_t frame = r.pixels.empty() ? 0U : r.pixels[0];
        CHECK(r.timestamp_ns == rig.recorder.stamp(frame));  // the device's ticks (1 GHz), as the fake sent them
        CHECK(r.timestamp_ns >= s.clock_offset_ns);
        CHECK(r.timestamp_ns < s.clock_offset_ns + 60000000000U);
        if (i > 0U) {
            CHECK(frame > last_frame);
            CHECK(r.timestamp_ns > got[i - 1U].timestamp_ns);
        }
        last_frame = frame;
    }
    guint64 completed = 0U;
    guint64 failures = 0U;
    guint64 underruns = 0U;
    c.statistics(completed, failures, underruns);
    CHECK(completed >= 10U);
    CHECK(failures == 0U);
    CHECK(rig.camera.counts().rendered >= 10U);
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: a frozen image repeats the same bytes from its frame on, with new time stamps" *
          doctest::skip()) {
    FakeCameraSettings s = settings("127.0.0.3");
    s.faults.frozen_from_frame = 4;
    Rig rig(s);
    REQUIRE(rig.start());
    const std::vector<Received> got = rig.frames(10);
    REQUIRE(got.size() == 10U);
    int frozen = 0;
    for (std::size_t i = 0U; i < got.size(); ++i) {
        REQUIRE(got[i].status == ARV_BUFFER_STATUS_SUCCESS);
        CHECK(holds_pattern(got[i]));
        CHECK(got[i].pixels[0] <= 3U);  // frame 3's image, sent again from frame 4 on
        if (got[i].pixels[0] == 3U && i > 0U && got[i - 1U].pixels == got[i].pixels) {
            ++frozen;
            CHECK(got[i].timestamp_ns > got[i - 1U].timestamp_ns);
        }
    }
    CHECK(frozen >= 5);
    CHECK(rig.camera.counts().frozen >= 6U);
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: the device clock jumps forward or backward at its frame" * doctest::skip()) {
    for (const std::int64_t jump_ms : {1000, -2000}) {
        CAPTURE(jump_ms);
        FakeCameraSettings s = settings(jump_ms > 0 ? "127.0.0.4" : "127.0.0.5");
        s.faults.stamp_jump_at_frame = 5;
        s.faults.stamp_jump_ms = jump_ms;
        Rig rig(s);
        REQUIRE(rig.start());
        const std::vector<Received> got = rig.frames(9);
        REQUIRE(got.size() == 9U);
        std::map<std::uint64_t, std::int64_t> stamp;
        for (const Received& r : got) {
            REQUIRE(r.status == ARV_BUFFER_STATUS_SUCCESS);
            stamp[r.pixels[0]] = static_cast<std::int64_t>(r.timestamp_ns);
        }
        REQUIRE(stamp.count(4U) == 1U);
        REQUIRE(stamp.count(5U) == 1U);
        const std::int64_t ms = 1000000;
        const std::int64_t step = stamp[5] - stamp[4];  // the jump plus one period (50 ms; late by up to 250 ms here)
        CHECK(step >= jump_ms * ms);
        CHECK(step <= jump_ms * ms + 900 * ms);
        for (const auto& [frame, t] : stamp) {
            if (frame != 5U && stamp.count(frame - 1U) == 1U) {
                CHECK(t - stamp[frame - 1U] > 0);
                CHECK(t - stamp[frame - 1U] < 900 * ms);
            }
        }
    }
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: lost packets at 0, 1 and 20 per cent make incomplete buffers, counted by Aravis" *
          doctest::skip()) {
    for (const std::uint32_t per_mille : {0U, 10U, 200U}) {
        CAPTURE(per_mille);
        FakeCameraSettings s = settings(per_mille == 0U ? "127.0.0.6" : per_mille == 10U ? "127.0.0.7" : "127.0.0.8");
        s.width = 320;  // 150 KiB: about 110 packets of 1400 bytes a frame
        s.height = 240;
        s.frame_rate_hz = 10.0;  // a burst every 100 ms: the client has time to drain each
        s.faults.lost_packets_per_mille = per_mille;
        Rig rig(s);
        REQUIRE(rig.start());
        const std::vector<Received> got = rig.frames(30);
        int complete = 0;
        int incomplete = 0;
        for (const Received& r : got) {
            complete += r.status == ARV_BUFFER_STATUS_SUCCESS ? 1 : 0;
            incomplete += (r.status == ARV_BUFFER_STATUS_MISSING_PACKETS || r.status == ARV_BUFFER_STATUS_TIMEOUT) ? 1
                                                                                                                   : 0;
        }
        guint64 completed = 0U;
        guint64 failures = 0U;
        guint64 underruns = 0U;
        rig.client->statistics(completed, failures, underruns);
        MESSAGE("loss " << per_mille << " per mille: " << got.size() << " buffers, " << complete << " complete, "
                        << incomplete << " incomplete; Aravis: " << completed << " completed, " << failures
                        << " failures, " << underruns << " underruns");
        CHECK(got.size() >= 25U);
        if (per_mille == 0U) {
            CHECK(incomplete == 0);
            CHECK(failures == 0U);
        } else if (per_mille == 10U) {
            CHECK(complete >= 1);  // P(a frame complete) = 0.99^110 = 0.33
            CHECK(incomplete >= 1);
            CHECK(failures >= 1U);
        } else {
            CHECK(complete == 0);  // 0.8^110
            CHECK(incomplete >= 25);
            CHECK(failures >= 25U);
        }
    }
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: a silent stop ends the stream but not control, sending again resumes it" * doctest::skip()) {
    FakeCameraSettings s = settings("127.0.0.2");
    s.faults.stop_at_frame = 3;
    Rig rig(s);
    REQUIRE(rig.start());
    const std::vector<Received> before = rig.frames(10, 1000);  // frames 0..2, then a 1 s silence
    REQUIRE(before.size() == 3U);
    CHECK(before.back().pixels[0] == 2U);
    CHECK(rig.client->get("DeviceSerialNumber") == "UT-2");  // control still answers
    CHECK(rig.camera.counts().stopped >= 10U);
    rig.camera.set_sending(true);
    const std::vector<Received> after = rig.frames(3);
    REQUIRE(after.size() == 3U);
    CHECK(after[0].status == ARV_BUFFER_STATUS_SUCCESS);
    CHECK(after[0].pixels[0] > 12U);  // the camera kept counting its frames
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: a power-off stop removes the camera, it reboots at its defaults with a new clock" *
          doctest::skip()) {
    FakeCameraSettings s = settings("127.0.0.3");
    s.faults.stop_at_frame = 5;
    s.faults.power_off_at_stop = true;
    s.faults.restart_after_ms = 4000;  // after the failed open below (about 2.5 s)
    s.faults.frozen_from_frame = 2;    // one-shot faults do not come back after the reboot
    Rig rig(s);
    REQUIRE(rig.start());
    const Poller poller(rig.camera);
    const std::vector<Received> before = rig.frames(10, 1000);
    CHECK(before.size() <= 5U);
    CHECK(before.size() >= 3U);
    CHECK_FALSE(rig.camera.running());  // off: the frame count stopped at the stop and GVCP is gone
    Client gone(s.address);
    CHECK_FALSE(gone.open());
    for (int i = 0; i < 150 && !(rig.camera.running() && rig.camera.counts().restarts == 1U); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    REQUIRE(rig.camera.running());
    {
        Client fresh(s.address);
        REQUIRE(fresh.open());
        CHECK(fresh.get("PixelFormat") == "Mono16");  // the power-on default, not the client's Coord3D_C16
        CHECK(fresh.get_float("Scan3dFocalLength") == doctest::Approx(50.0));
    }
    REQUIRE(rig.connect());
    const std::vector<Received> after = rig.frames(6);
    REQUIRE(after.size() == 6U);
    CHECK(holds_pattern(after[0], 0));  // frame 0 of the new camera
    CHECK(holds_pattern(after[5], 5));  // not frozen, not stopped: one-shot faults were the first run's
    // The device clock started again at the reboot: without it, it would read at least the
    // offset + 4.2 s (frames 0-4, then 4 s off); the new camera's first frame comes well within 3.5 s.
    CHECK(after[0].timestamp_ns < s.clock_offset_ns + 3500000000U);
    CHECK(after[0].timestamp_ns > s.clock_offset_ns);
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: a camera without Coord3D_C16 refuses it, Width is read-only" * doctest::skip()) {
    FakeCameraSettings s = settings("127.0.0.4");
    s.offers_coord3d_c16 = false;
    FakeGigeCamera camera(s, nullptr);
    std::string error;
    REQUIRE(camera.start(error));
    Client c(s.address);
    REQUIRE(c.open());
    CHECK_FALSE(c.set("PixelFormat", "Coord3D_C16"));
    CHECK(c.error().find("PixelFormat") != std::string::npos);
    CHECK(c.get("PixelFormat") == "Mono16");
    GError* e = nullptr;
    arv_device_set_integer_feature_value(c.device(), "Width", 32, &e);
    CHECK(e != nullptr);
    g_clear_error(&e);
    CHECK(c.get_int("Width") == kW);
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: a resolution change mid-run reaches the client in the buffers' size" * doctest::skip()) {
    FakeCameraSettings s = settings("127.0.0.5");
    s.faults.resize_at_frame = 4;
    s.faults.resize_width = 32;
    s.faults.resize_height = 24;
    Rig rig(s);
    REQUIRE(rig.start());
    const std::vector<Received> got = rig.frames(8);
    REQUIRE(got.size() == 8U);
    for (const Received& r : got) {
        REQUIRE(r.status == ARV_BUFFER_STATUS_SUCCESS);  // Aravis does not compare the size with the payload
        const bool after = r.pixels[0] >= 4U;
        CHECK(r.width == (after ? 32 : kW));
        CHECK(r.height == (after ? 24 : kH));
        // The stream keeps the payload size of its start; the new image fills its front.
        CHECK(r.pixels.size() == static_cast<std::size_t>(kW * kH));
        for (int i = 0; i < r.width * r.height; ++i) {
            REQUIRE(r.pixels[static_cast<std::size_t>(i)] == pattern(r.pixels[0], i));
        }
    }
    CHECK(rig.client->get_int("Width") == 32);
}

// verifies: SR-CAM-008
TEST_CASE("fake gige: a second camera on an address another holds is refused at start, not silently deaf" *
          doctest::skip()) {
    FakeGigeCamera first(settings("127.0.0.6"), nullptr);
    FakeGigeCamera second(settings("127.0.0.6"), nullptr);
    std::string error;
    REQUIRE(first.start(error));
    CHECK_FALSE(second.start(error));
    CHECK(error.find("another camera holds it") != std::string::npos);
    CHECK_FALSE(second.running());
    first.power_off();
    CHECK(second.start(error));  // the port is free again
}

#endif  // CELLGUARD_HAVE_FAKE_GIGE
