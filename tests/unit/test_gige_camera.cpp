// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: port/linux's GigeCamera opens a GigE Vision camera by
// address, checks its serial, configures it and refuses a setting it does
// not take, streams complete frames into storage allocated at start, counts
// incomplete frames, and reconnects (and reconfigures) after the camera
// restarts (issue 19). Against Aravis' fake camera program
// (arv-fake-gv-camera-0.8, Mono16, no Coord3D) on 127.0.0.1: these cases are
// marked skip and run by the ctest `gige_camera_against_the_aravis_fake`,
// inside a network namespace of their own (tools/netns-run.sh):
// the fake binds GVCP port 3956, which only one fake per address may hold.
#include <doctest/doctest.h>

#include "cellguard/host/gige.hpp"
#if CELLGUARD_HOST_GIGE
#include <cstdint>
#include <cstdio>
#include <string>

#include "alloc_counter.hpp"
#include "aravis_fake_program.hpp"
#include "cellguard/port/gige_camera.hpp"

using namespace cellguard::linux_port;
using cellguard::test::FakeGigeCamera;
using cellguard::test::sleep_ms;
using cellguard::test::wait_for;

namespace {

std::uint64_t now_us() { return cellguard::test::monotonic_now_us(); }

GigeCameraConfig fake_config() {
    GigeCameraConfig c;
    c.name = "fake";
    c.address = cellguard::test::kFakeCameraAddress;
    c.pixel_format = GigePixelFormat::kMono16;
    c.width = 640;
    c.height = 480;
    c.frame_rate_hz = 30.0;
    c.reconnect_interval_us = 500000U;
    c.no_frame_timeout_us = 1000000U;
    // This 2-core host delays threads by up to 250 ms under load (FIELD-NOTES): a wide error here.
    c.clock.max_stamp_error_us = 300000U;
    return c;
}

}  // namespace

// verifies: SR-CAM-001, SR-CAM-006
TEST_CASE("gige camera: opens the fake by address, streams complete 640 x 480 Mono16 frames at the set rate" *
          doctest::skip()) {
    FakeGigeCamera fake("GIGE-A");
    REQUIRE_MESSAGE(fake.started(), "arv-fake-gv-camera-0.8 did not start (aravis-tools)");
    GigeCamera camera(fake_config());
    std::string error;
    REQUIRE_MESSAGE(camera.start(error), error);
    CHECK(camera.device().serial == "GIGE-A");
    CHECK(camera.device().payload_bytes == 640 * 480 * 2);
    CHECK_FALSE(camera.device().has_depth_scale);  // the fake has no Scan3d
    REQUIRE(wait_for([&] { return camera.counters().published > 0U; }, 3000));
    // Three seconds of streaming: the cycle's side reads the newest frame every 10 ms.
    const GigeCounters before = camera.counters();
    const std::size_t all_before = cellguard::test::allocation_count();
    const std::size_t mine_before = cellguard::test::thread_allocation_count();
    const std::uint64_t t0 = now_us();
    std::uint64_t reads = 0U;
    std::uint64_t last_sequence = 0U;
    bool stamps_ok = true;
    GigeFrame frame;
    while (now_us() - t0 < 3000000U) {
        if (camera.latest(frame)) {
            ++reads;
            const std::uint64_t now = now_us();
            stamps_ok = stamps_ok && frame.stamp_us <= now && frame.stamp_us <= frame.receive_us + 1000U &&
                        frame.sequence >= last_sequence;
            last_sequence = frame.sequence;
        }
        sleep_ms(10);
    }
    const double seconds = static_cast<double>(now_us() - t0) * 1e-6;
    const std::size_t mine = cellguard::test::thread_allocation_count() - mine_before;
    const std::size_t all = cellguard::test::allocation_count() - all_before;
    const GigeCounters after = camera.counters();
    const auto published = static_cast<double>(after.published - before.published);
    const auto received = static_cast<double>(after.received - before.received);
    std::printf(
        "gige fake stream: %.1f frames/s published (%.1f buffers/s received), %llu incomplete, %llu missing, "
        "%llu stamps refused; allocations: %zu on the reading thread over %llu reads, %.1f per received "
        "frame in the other threads (Aravis' stream and heartbeat threads, the supervisor)\n",
        published / seconds, received / seconds, static_cast<unsigned long long>(after.incomplete),
        static_cast<unsigned long long>(after.missing), static_cast<unsigned long long>(after.stamp_refused), mine,
        static_cast<unsigned long long>(reads), static_cast<double>(all - mine) / received);
    CHECK(stamps_ok);
    CHECK(mine == 0U);  // latest() never allocates
    CHECK(after.incomplete == 0U);
    CHECK(after.wrong_format == 0U);
    CHECK(after.stamp_refused == 0U);
    // 30 frames/s set; the fake's timer runs late on a loaded 2-core host: a wide band.
    CHECK(published / seconds > 15.0);
    CHECK(published / seconds < 33.0);
    REQUIRE(camera.latest(frame));
    CHECK(frame.width == 640);
    CHECK(frame.height == 480);
    bool varied = false;  // the fake's ramp image
    for (int i = 1; i < 640 && !varied; ++i) {
        varied = frame.pixels[i] != frame.pixels[0];
    }
    CHECK(varied);
    CHECK(camera.connected());
    camera.stop();
    CHECK_FALSE(camera.connected());
}

// verifies: SR-CAM-001
TEST_CASE("gige camera: a resolution or pixel format the camera refuses is a clear error at start" * doctest::skip()) {
    FakeGigeCamera fake("GIGE-B");
    REQUIRE_MESSAGE(fake.started(), "arv-fake-gv-camera-0.8 did not start (aravis-tools)");
    GigeCameraConfig c = fake_config();
    c.width = 4096;  // the fake's Width goes to 2048
    std::string error;
    {
        GigeCamera camera(c);
        CHECK_FALSE(camera.start(error));
        CHECK_MESSAGE(error.find("Width = 4096 refused") != std::string::npos, error);
        CHECK_FALSE(camera.connected());
    }
    c = fake_config();
    c.pixel_format = GigePixelFormat::kCoord3dC16;  // the fake has no Coord3D
    {
        GigeCamera camera(c);
        CHECK_FALSE(camera.start(error));
        CHECK_MESSAGE(error.find("PixelFormat Coord3D_C16 refused") != std::string::npos, error);
    }
    c = fake_config();
    c.frame_rate_hz = 5000.0;  // the fake's AcquisitionFrameRate goes to 1000
    {
        GigeCamera camera(c);
        CHECK_FALSE(camera.start(error));
        CHECK_MESSAGE(error.find("AcquisitionFrameRate") != std::string::npos, error);
    }
}

// verifies: SR-CAM-001
TEST_CASE("gige camera: a wrong expected serial is refused at start" * doctest::skip()) {
    FakeGigeCamera fake("GIGE-C");
    REQUIRE_MESSAGE(fake.started(), "arv-fake-gv-camera-0.8 did not start (aravis-tools)");
    GigeCameraConfig c = fake_config();
    c.expected_serial = "SOMEONE-ELSE";
    GigeCamera camera(c);
    std::string error;
    CHECK_FALSE(camera.start(error));
    CHECK_MESSAGE(error.find("is 'GIGE-C', expected 'SOMEONE-ELSE'") != std::string::npos, error);
}

// verifies: SR-CAM-003
TEST_CASE("gige camera: lost packets (the fake's -r) count incomplete frames, none is published" * doctest::skip()) {
    for (const int per_thousand : {10, 200}) {
        CAPTURE(per_thousand);
        FakeGigeCamera fake("GIGE-D", per_thousand);
        REQUIRE_MESSAGE(fake.started(), "arv-fake-gv-camera-0.8 did not start (aravis-tools)");
        GigeCamera camera(fake_config());
        std::string error;
        REQUIRE_MESSAGE(camera.start(error), error);
        CHECK(wait_for([&] { return camera.counters().incomplete >= 20U; }, 5000));
        const GigeCounters c = camera.counters();
        std::printf(
            "gige fake with %d per thousand packets lost: %llu buffers, %llu complete, %llu incomplete, "
            "%llu missing\n",
            per_thousand, static_cast<unsigned long long>(c.received), static_cast<unsigned long long>(c.complete),
            static_cast<unsigned long long>(c.incomplete), static_cast<unsigned long long>(c.missing));
        CHECK(c.incomplete >= 20U);
        CHECK(c.incomplete > c.complete);
        CHECK(c.published <= c.complete);
        if (per_thousand == 200) {
            CHECK(c.complete == 0U);
        }
    }
}

// verifies: SR-CAM-005
TEST_CASE("gige camera: after the camera is killed and restarted it reconnects and configures it again" *
          doctest::skip()) {
    FakeGigeCamera fake("GIGE-E");
    REQUIRE_MESSAGE(fake.started(), "arv-fake-gv-camera-0.8 did not start (aravis-tools)");
    GigeCamera camera(fake_config());
    std::string error;
    REQUIRE_MESSAGE(camera.start(error), error);
    REQUIRE(wait_for([&] { return camera.counters().published >= 5U; }, 3000));
    fake.kill_now();
    const std::uint64_t killed = now_us();
    REQUIRE(wait_for([&] { return camera.counters().disconnections >= 1U; }, 6000));
    const double detect_ms = static_cast<double>(now_us() - killed) / 1000.0;
    CHECK_FALSE(camera.connected());
    GigeFrame stale;
    REQUIRE(camera.latest(stale));
    const std::uint64_t stale_stamp = stale.stamp_us;
    sleep_ms(300);
    GigeFrame again;
    REQUIRE(camera.latest(again));
    CHECK(again.stamp_us == stale_stamp);  // the cycle sees no new frame

    REQUIRE(fake.start("GIGE-E", 0));  // the same camera back, at its defaults (512 x 512 Mono8)
    const std::uint64_t restarted = now_us();
    REQUIRE(wait_for([&] { return camera.counters().reconnections >= 1U; }, 15000));
    const double reconnect_ms = static_cast<double>(now_us() - restarted) / 1000.0;
    const std::uint64_t published = camera.counters().published;
    REQUIRE(wait_for([&] { return camera.counters().published >= published + 5U; }, 5000));
    REQUIRE(camera.latest(again));
    CHECK(again.stamp_us > stale_stamp);
    CHECK(again.width == 640);
    CHECK(camera.counters().wrong_format == 0U);  // reconfigured: 640 x 480 Mono16 again
    std::printf(
        "gige fake killed: loss detected after %.0f ms; restarted: streaming again after %.0f ms "
        "(%llu failed reopens)\n",
        detect_ms, reconnect_ms, static_cast<unsigned long long>(camera.counters().reconnect_failures));
}

// verifies: SR-CAM-005, SR-CAM-001
TEST_CASE("gige camera: a camera swapped for another one is refused at reconnection" * doctest::skip()) {
    FakeGigeCamera fake("GIGE-F");
    REQUIRE_MESSAGE(fake.started(), "arv-fake-gv-camera-0.8 did not start (aravis-tools)");
    GigeCameraConfig c = fake_config();
    c.expected_serial = "GIGE-F";
    GigeCamera camera(c);
    std::string error;
    REQUIRE_MESSAGE(camera.start(error), error);
    REQUIRE(wait_for([&] { return camera.counters().published >= 3U; }, 3000));
    fake.kill_now();
    REQUIRE(wait_for([&] { return camera.counters().disconnections >= 1U; }, 6000));
    REQUIRE(fake.start("GIGE-SWAPPED", 0));
    REQUIRE(wait_for([&] { return camera.last_error().find("GIGE-SWAPPED") != std::string::npos; }, 15000));
    CHECK_MESSAGE(camera.last_error().find("expected 'GIGE-F'") != std::string::npos, camera.last_error());
    CHECK(camera.counters().reconnections == 0U);
    CHECK_FALSE(camera.connected());
}

#endif  // CELLGUARD_HOST_GIGE
