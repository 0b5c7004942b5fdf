// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the fake cameras serve the monitor's simulated frame of each
// scenario cycle (cell::SimulatedFrameSource) as raw depth at the configured
// scale and offset; the scenario starts when every camera streams; --dither
// makes consecutive frames differ in one pixel by one unit; --prerender serves
// cycles rendered at start.
#if defined(CELLGUARD_HAVE_FAKE_GIGE)
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "cellguard/fake_camera/demo_frames.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/sim/workcell.hpp"

using namespace cellguard;
using fake_camera::DemoFrames;
using fake_camera::ScenarioClock;

namespace {

/// The simulated source's frame of @p cycle, in units of @p scale after @p offset, computed here.
std::vector<std::uint16_t> expected(const sim::SensorSpec& spec, std::uint64_t cycle, double scale, double offset) {
    cell::SimulatedFrameSource source(spec, cell::FrameDither::kOff);  // as DemoFrames renders
    SensorReading reading;
    cell::FrameStatus status;
    REQUIRE(source.load_frame(cycle, reading, status));
    std::vector<std::uint16_t> raw(reading.depth.size(), 0U);
    for (std::size_t i = 0U; i < raw.size(); ++i) {
        const float d = reading.depth[i];
        const long r = std::isfinite(d) && d > 0.0F ? std::lround((static_cast<double>(d) - offset) / scale) : 0L;
        raw[i] = r >= 1L && r <= 65535L ? static_cast<std::uint16_t>(r) : std::uint16_t{0U};
    }
    return raw;
}

}  // namespace

// verifies: SR-CAM-008
TEST_CASE("demo frames: each cycle is the monitor's simulated frame in raw units, rendered once") {
    const sim::SensorSpec spec = sim::paper_sensors()[2];  // stereo-a, 320 x 240
    const std::size_t n = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
    for (const std::pair<double, double>& scale_offset : {std::pair<double, double>{0.001, 0.0}, {0.002, 0.5}}) {
        const double scale = scale_offset.first;  // not a structured binding: CAPTURE's lambda may not capture one
        const double offset = scale_offset.second;
        CAPTURE(scale);
        DemoFrames frames(spec, {}, scale, offset);
        std::vector<std::uint16_t> image(n, 7U);
        frames.render(15U, spec.width, spec.height, image.data());  // the person in the protective zone
        CHECK(image == expected(spec, 15U, scale, offset));
        std::vector<std::uint16_t> again(n, 7U);
        frames.render(15U, spec.width, spec.height, again.data());
        CHECK(again == image);
        CHECK(frames.renders() == 1U);  // the same cycle is copied, not cast again
        std::vector<std::uint16_t> empty(n, 7U);
        frames.render(0U, spec.width, spec.height, empty.data());
        CHECK(frames.renders() == 2U);
        CHECK(empty == expected(spec, 0U, scale, offset));
        std::size_t differ = 0U;
        for (std::size_t i = 0U; i < n; ++i) {
            differ += image[i] != empty[i] ? 1U : 0U;
        }
        CHECK(differ > 200U);  // the person is seen
    }
}

// verifies: SR-CAM-008
TEST_CASE("demo frames: another size renders the same view over its pixels, an unknown size is zeros") {
    const sim::SensorSpec spec = sim::paper_sensors()[0];
    DemoFrames frames(spec, {{64, 48}}, 0.001, 0.0);
    std::vector<std::uint16_t> small(64U * 48U, 0U);
    frames.render(15U, 64, 48, small.data());
    sim::SensorSpec other = spec;
    other.width = 64;
    other.height = 48;
    CHECK(small == expected(other, 15U, 0.001, 0.0));
    std::vector<std::uint16_t> odd(100U, 9U);
    frames.render(15U, 10, 10, odd.data());
    CHECK(odd == std::vector<std::uint16_t>(100U, 0U));
}

// verifies: SR-CAM-008
TEST_CASE("demo frames: prerendered cycles are served as rendered, the last one for every later cycle") {
    const sim::SensorSpec spec = sim::paper_sensors()[2];
    const std::size_t n = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
    DemoFrames frames(spec, {{64, 48}}, 0.001, 0.0);
    frames.prerender(17U);
    CHECK(frames.renders() == 17U);
    std::vector<std::uint16_t> image(n, 7U);
    frames.render(15U, spec.width, spec.height, image.data());
    CHECK(image == expected(spec, 15U, 0.001, 0.0));
    frames.render(400U, spec.width, spec.height, image.data());
    CHECK(image == expected(spec, 16U, 0.001, 0.0));  // after the prerendered cycles: the last one
    CHECK(frames.renders() == 17U);                   // copied, never cast again
    std::vector<std::uint16_t> small(64U * 48U, 0U);  // another size is rendered as before
    frames.render(15U, 64, 48, small.data());
    CHECK(frames.renders() == 18U);
}

// verifies: SR-CAM-008
TEST_CASE("demo frames: the scenario starts when every camera has streamed, then counts periods") {
    ScenarioClock clock(100000000U, 2U);
    CHECK(clock.cycle(true, 1000U) == 0U);  // one camera streams: not started
    CHECK_FALSE(clock.started());
    CHECK(clock.cycle(false, 900000000U) == 0U);
    CHECK(clock.cycle(true, 1000000000U) == 0U);  // the second: cycle 0 starts now
    CHECK(clock.started());
    CHECK(clock.cycle(false, 1099999999U) == 0U);
    CHECK(clock.cycle(false, 1100000000U) == 1U);
    CHECK(clock.cycle(false, 1250000000U) == 2U);
    CHECK(clock.cycle(true, 1250000000U) == 2U);  // a camera's reboot does not restart the scenario
    ScenarioClock any(50000000U, 1U);
    CHECK(any.cycle(true, 10U) == 0U);
    CHECK(any.cycle(false, 10U + 50000000U) == 1U);
}

// verifies: SR-CAM-008
TEST_CASE("demo frames: the dither changes the first pixel with a reading by one unit in odd frames") {
    std::vector<std::uint16_t> image{0U, 0U, 1200U, 900U};
    fake_camera::dither(4U, image.size(), image.data());
    CHECK(image == std::vector<std::uint16_t>{0U, 0U, 1200U, 900U});
    fake_camera::dither(5U, image.size(), image.data());
    CHECK(image == std::vector<std::uint16_t>{0U, 0U, 1201U, 900U});
    std::vector<std::uint16_t> top{65535U};
    fake_camera::dither(1U, top.size(), top.data());
    CHECK(top[0] == 65534U);
    std::vector<std::uint16_t> none(3U, 0U);
    fake_camera::dither(1U, none.size(), none.data());
    CHECK(none == std::vector<std::uint16_t>(3U, 0U));
}

#endif  // CELLGUARD_HAVE_FAKE_GIGE
