// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: a camera's device time stamps map to CLOCK_MONOTONIC through a
// min-filtered offset; jumps forward and back, a device time that does not
// increase and a skew beyond the limit refuse frames, and the estimate is
// learnt again from a stated number of consistent frames (issue 19).
#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/port/device_clock.hpp"

using namespace cellguard::linux_port;

namespace {

constexpr std::uint64_t kPeriodUs = 33333U;            // 30 fps
constexpr std::uint64_t kDevice0 = 1700000000000000U;  // a wall-clock device time, microseconds
constexpr std::uint64_t kMono0 = 5000000000U;          // CLOCK_MONOTONIC at the first frame

/// A synthetic camera: frame i captured at device time kDevice0 + i periods
/// (times (1 + skew)), received after a latency that cycles 1..4 ms.
struct Camera {
    double skew_ppm = 0.0;
    std::int64_t device_step_us = 0;  ///< added to every device time from frame `step_at`
    int step_at = -1;
    [[nodiscard]] std::uint64_t true_capture(int i) const { return kMono0 + static_cast<std::uint64_t>(i) * kPeriodUs; }
    [[nodiscard]] std::uint64_t receive(int i) const {
        return true_capture(i) + 1000U + static_cast<std::uint64_t>(i % 4) * 1000U;
    }
    [[nodiscard]] std::uint64_t device(int i) const {
        const double elapsed = static_cast<double>(i) * static_cast<double>(kPeriodUs) * (1.0 + skew_ppm * 1e-6);
        std::int64_t d = static_cast<std::int64_t>(kDevice0) + static_cast<std::int64_t>(elapsed);
        if (step_at >= 0 && i >= step_at) {
            d += device_step_us;
        }
        return static_cast<std::uint64_t>(d);
    }
};

/// Feeds frames [from, to) of @p cam; returns their verdicts.
std::vector<StampVerdict> feed(DeviceClock& clock, const Camera& cam, int from, int to,
                               std::vector<std::uint64_t>* stamps = nullptr) {
    std::vector<StampVerdict> v;
    for (int i = from; i < to; ++i) {
        const MappedStamp m = clock.map(cam.device(i), cam.receive(i));
        v.push_back(m.verdict);
        if (stamps != nullptr) {
            stamps->push_back(m.mono_us);
        }
    }
    return v;
}

}  // namespace

// verifies: SR-CAM-002
TEST_CASE(
    "gige device clock: learns the offset from restart_frames frames, then maps every stamp before its receive time") {
    DeviceClockParams p;
    p.restart_frames = 4U;
    DeviceClock clock(p);
    const Camera cam;
    std::vector<std::uint64_t> stamps;
    const std::vector<StampVerdict> v = feed(clock, cam, 0, 300, &stamps);
    for (int i = 0; i < 3; ++i) {
        CHECK(v[static_cast<std::size_t>(i)] == StampVerdict::kLearning);
    }
    for (std::size_t i = 3U; i < v.size(); ++i) {
        REQUIRE(v[i] == StampVerdict::kAccepted);
        const int frame = static_cast<int>(i);
        CHECK(stamps[i] <= cam.receive(frame));
        // The min filter finds the least latency (1 ms) once a 1 ms frame is in its window.
        CHECK(stamps[i] >= cam.true_capture(frame) + 1000U);
        CHECK(stamps[i] <= cam.true_capture(frame) + 4000U);
    }
    CHECK(stamps.back() == cam.true_capture(299) + 1000U);
    CHECK(clock.refused() == 0U);
    CHECK(clock.relearning() == 0U);
    CHECK(clock.locks() == 1U);
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: a jump forward of the device clock is refused, then learnt again") {
    DeviceClockParams p;
    p.restart_frames = 5U;
    DeviceClock clock(p);
    Camera cam;
    cam.step_at = 100;
    cam.device_step_us = 50000;  // 50 ms forward: mapped stamps would lie after the frames' arrival
    const std::vector<StampVerdict> v = feed(clock, cam, 0, 120);
    CHECK(v[99] == StampVerdict::kAccepted);
    CHECK(v[100] == StampVerdict::kJumpForward);
    for (std::size_t i = 101U; i < 105U; ++i) {
        CHECK(v[i] == StampVerdict::kLearning);
    }
    CHECK(v[105] == StampVerdict::kAccepted);
    CHECK(clock.refused() == 1U);
    CHECK(clock.relearning() == 4U);
    CHECK(clock.locks() == 2U);
    // After the jump the new offset maps the frames to their true capture times again.
    const MappedStamp m = clock.map(cam.device(120), cam.receive(120));
    REQUIRE(m.verdict == StampVerdict::kAccepted);
    CHECK(m.mono_us <= cam.receive(120));
    CHECK(m.mono_us + 4000U >= cam.true_capture(120));
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: a jump back is refused (outside the error, or not increasing)") {
    DeviceClockParams p;
    DeviceClock clock(p);
    Camera cam;
    cam.step_at = 60;
    cam.device_step_us = -25000;  // back by 25 ms, less than a period: still increasing, but 25 ms > 20 ms error
    std::vector<StampVerdict> v = feed(clock, cam, 0, 80);
    CHECK(v[59] == StampVerdict::kAccepted);
    // restart_frames (4) refused, their offset then taken as the new estimate.
    for (std::size_t i = 60U; i < 64U; ++i) {
        CHECK(v[i] == StampVerdict::kOutsideError);
    }
    for (std::size_t i = 64U; i < 80U; ++i) {
        CHECK(v[i] == StampVerdict::kAccepted);
    }
    CHECK(clock.refused() == 4U);
    CHECK(clock.locks() == 2U);
    CHECK(clock.offset_us() == static_cast<std::int64_t>(cam.receive(60)) - static_cast<std::int64_t>(cam.device(60)));

    DeviceClock clock2(p);
    cam.device_step_us = -100000;  // back by three periods: the device time goes back
    v = feed(clock2, cam, 0, 61);
    CHECK(v[60] == StampVerdict::kNotIncreasing);
    CHECK(clock2.refused() == 1U);
    // A smaller step than the error allowed is accepted (delivery jitter).
    DeviceClock clock3(p);
    cam.device_step_us = -10000;
    v = feed(clock3, cam, 0, 80);
    CHECK(v[60] == StampVerdict::kAccepted);
    CHECK(clock3.refused() == 0U);
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: one late frame is refused alone, the estimate is kept") {
    DeviceClock clock(DeviceClockParams{});
    const Camera cam;
    static_cast<void>(feed(clock, cam, 0, 30));
    const std::int64_t estimate = clock.offset_us();
    CHECK(clock.map(cam.device(30), cam.receive(30) + 100000U).verdict == StampVerdict::kOutsideError);
    CHECK(clock.offset_us() == estimate);
    const std::vector<StampVerdict> v = feed(clock, cam, 31, 40);
    for (const StampVerdict x : v) {
        CHECK(x == StampVerdict::kAccepted);
    }
    CHECK(clock.refused() == 1U);
    CHECK(clock.locks() == 1U);
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: a frame repeated with the same device time is refused") {
    DeviceClock clock(DeviceClockParams{});
    const Camera cam;
    static_cast<void>(feed(clock, cam, 0, 20));
    CHECK(clock.map(cam.device(19), cam.receive(19) + 100U).verdict == StampVerdict::kNotIncreasing);
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: a skew of 2000 ppm is refused at the first skew check, 300 ppm is accepted") {
    DeviceClockParams p;
    p.max_skew_ppm = 1000.0;
    p.skew_interval_us = 5000000U;
    for (const double ppm : {2000.0, -2000.0}) {
        CAPTURE(ppm);
        DeviceClock clock(p);
        Camera cam;
        cam.skew_ppm = ppm;
        const std::vector<StampVerdict> v = feed(clock, cam, 0, 400);  // 13.3 s
        std::size_t first_skew = v.size();
        for (std::size_t i = 0U; i < v.size() && first_skew == v.size(); ++i) {
            if (v[i] == StampVerdict::kSkew) {
                first_skew = i;
            }
        }
        // The first check comes 5 s of device time after the lock (frame 3):
        // frame 153 (device clock fast) or 154 (slow).
        CHECK(first_skew == (ppm > 0.0 ? 153U : 154U));
        // The drift of (monotonic - device): a fast device clock makes it fall.
        CHECK(clock.last_skew_ppm() == doctest::Approx(-ppm).epsilon(0.1));
        CHECK(clock.refused() >= 1U);
    }
    DeviceClock fine(p);
    Camera fast;
    fast.skew_ppm = 300.0;
    const std::vector<StampVerdict> v = feed(fine, fast, 0, 900);  // 30 s
    for (std::size_t i = 3U; i < v.size(); ++i) {
        REQUIRE(v[i] == StampVerdict::kAccepted);
    }
    CHECK(fine.last_skew_ppm() == doctest::Approx(-300.0).epsilon(0.15));
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: restart() learns anew (a reconnected camera), counters kept") {
    DeviceClockParams p;
    p.restart_frames = 3U;
    DeviceClock clock(p);
    const Camera cam;
    static_cast<void>(feed(clock, cam, 0, 10));
    REQUIRE(clock.locked());
    clock.restart();
    CHECK_FALSE(clock.locked());
    // The restarted camera's clock starts from 0: no jump is seen, it is learnt.
    const std::uint64_t r = cam.receive(10);
    CHECK(clock.map(1000U, r).verdict == StampVerdict::kLearning);
    CHECK(clock.map(1000U + kPeriodUs, r + kPeriodUs).verdict == StampVerdict::kLearning);
    const MappedStamp m = clock.map(1000U + 2U * kPeriodUs, r + 2U * kPeriodUs);
    CHECK(m.verdict == StampVerdict::kAccepted);
    CHECK(m.mono_us == r + 2U * kPeriodUs);
    CHECK(clock.locks() == 2U);
    CHECK(clock.refused() == 0U);
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: inconsistent frames while learning start the candidates anew") {
    DeviceClockParams p;
    p.restart_frames = 3U;
    DeviceClock clock(p);
    CHECK(clock.map(1000000U, 2000000U).verdict == StampVerdict::kLearning);
    CHECK(clock.map(1033333U, 2033333U).verdict == StampVerdict::kLearning);
    CHECK(clock.map(1066666U, 2166666U).verdict == StampVerdict::kLearning);  // 100 ms late: anew
    CHECK(clock.map(1100000U, 2200000U).verdict == StampVerdict::kLearning);
    CHECK(clock.map(1133333U, 2233333U).verdict == StampVerdict::kAccepted);
    CHECK(clock.offset_us() == 1100000);
}

// verifies: SR-CAM-002
TEST_CASE("gige device clock: invalid parameters refuse every frame") {
    DeviceClockParams p;
    p.window = 0U;
    CHECK_FALSE(valid(p));
    p = DeviceClockParams{};
    p.window = kMaxDeviceClockWindow + 1U;
    CHECK_FALSE(valid(p));
    p = DeviceClockParams{};
    p.restart_frames = 0U;
    CHECK_FALSE(valid(p));
    DeviceClock clock(p);
    for (int i = 0; i < 10; ++i) {
        CHECK(clock
                  .map(1000U + static_cast<std::uint64_t>(i) * kPeriodUs,
                       5000U + static_cast<std::uint64_t>(i) * kPeriodUs)
                  .verdict == StampVerdict::kLearning);
    }
    CHECK(valid(DeviceClockParams{}));
    CHECK(std::string(to_string(StampVerdict::kJumpForward)) == "device time jumped forward");
}
