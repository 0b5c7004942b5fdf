// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file demo_frames.hpp
/// What cellguard-fake-camera serves: each camera's depth image of the demo
/// scenario at the moment of the frame, rendered by the monitor's own
/// simulated source (cell::SimulatedFrameSource, the same image bit for bit
/// as `cellguard-monitor --demo` fuses in that cycle) and converted to raw
/// uint16 depth (raw_depth(), fake_gige_camera.hpp).
///
/// The scenario's clock (ScenarioClock) is shared by the cameras of one
/// program: cycle 0 until it starts, then one cycle per period. It starts with
/// the first frame after every camera has streamed (the monitor opens its
/// cameras one after the other and starts its cycles when all are open), or
/// with the first frame of any camera.
#ifndef CELLGUARD_FAKE_CAMERA_DEMO_FRAMES_HPP
#define CELLGUARD_FAKE_CAMERA_DEMO_FRAMES_HPP

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::fake_camera {

/// The demo scenario's cycle at a moment, shared by a program's cameras.
class ScenarioClock {
public:
    /// A clock of @p period_ns per cycle that starts when @p cameras cameras
    /// have streamed; 0: only start() starts it.
    ScenarioClock(std::uint64_t period_ns, std::size_t cameras) noexcept
        : period_ns_(period_ns > 0U ? period_ns : 1U), cameras_(cameras) {}

    /// Starts the scenario at CLOCK_MONOTONIC @p now_ns unless it has started. Thread-safe.
    void start(std::uint64_t now_ns) noexcept {
        std::uint64_t unset = 0U;
        static_cast<void>(start_ns_.compare_exchange_strong(unset, now_ns == 0U ? 1U : now_ns));
    }

    /// The cycle at CLOCK_MONOTONIC @p now_ns of a frame; @p first: it is its camera's first
    /// frame. Thread-safe (each camera's thread calls it).
    [[nodiscard]] std::uint64_t cycle(bool first, std::uint64_t now_ns) noexcept;
    /// Whether the scenario has started.
    [[nodiscard]] bool started() const noexcept { return start_ns_.load() != 0U; }

private:
    std::uint64_t period_ns_;
    std::size_t cameras_;
    std::atomic<std::size_t> streaming_{0U};
    std::atomic<std::uint64_t> start_ns_{0U};
};

/// One camera's frames of the demo scenario, at its configured size and at
/// the size of a resize fault (another camera model at the same place: the
/// same fields of view over other pixels).
class DemoFrames {
public:
    /// Frames of @p spec, also at each of @p other_sizes (width, height);
    /// raw depth = metres / @p scale_m after @p offset_m; @p scene the demo's
    /// (with its person) or the empty cell. Allocates the sources.
    DemoFrames(const sim::SensorSpec& spec, const std::vector<std::pair<int, int>>& other_sizes, double scale_m,
               double offset_m, cell::FrameScene scene = cell::FrameScene::kDemo);

    /// Writes the raw image of scenario cycle @p cycle at @p width x @p
    /// height into @p image; zeros when no source has that size. Renders each
    /// cycle once and copies it for the frames of the same cycle. Not
    /// thread-safe: one camera thread calls it.
    void render(std::uint64_t cycle, int width, int height, std::uint16_t* image);
    /// Renders scenario cycles 0 .. @p cycles - 1 at the configured size
    /// now; render() then copies them, and serves the last for every later
    /// cycle (for scenes that are still from then on: the demo scenes after
    /// their person's path ends). So a camera thread only copies while
    /// the monitor runs beside it. Allocates @p cycles images.
    void prerender(std::uint64_t cycles);
    /// Images rendered so far.
    [[nodiscard]] std::uint64_t renders() const noexcept { return renders_; }

private:
    std::vector<sim::SensorSpec> specs_;
    std::vector<std::unique_ptr<cell::SimulatedFrameSource>> sources_;
    double scale_m_;
    double offset_m_;
    std::uint64_t cached_cycle_ = ~std::uint64_t{0U};
    int cached_source_ = -1;
    std::vector<std::uint16_t> cached_;
    std::vector<std::vector<std::uint16_t>> prerendered_;  ///< cycles 0.. at the configured size
    std::uint64_t renders_ = 0U;
};

/// The dither of cellguard-fake-camera --dither: in odd frames the first
/// pixel with a reading is one raw unit deeper (shallower at 65535), so that
/// no two frames are bit-identical, as with a real sensor's noise.
void dither(std::uint64_t frame, std::size_t pixels, std::uint16_t* image) noexcept;

}  // namespace cellguard::fake_camera

#endif  // CELLGUARD_FAKE_CAMERA_DEMO_FRAMES_HPP
