// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file frame_source.hpp
/// Where the monitor's sensor frames come from, one frame per sensor and
/// cycle, each into a buffer the source allocated when it was made: the
/// simulated cell (SimulatedFrameSource, below) or recorded PCD files
/// (PcdFrameSource, pcd_input.hpp). Loading a frame allocates nothing, so the
/// monitor's cycle (monitor_loop.hpp) runs without the heap.
#ifndef CELLGUARD_HOST_CELL_FRAME_SOURCE_HPP
#define CELLGUARD_HOST_CELL_FRAME_SOURCE_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/sim/robot_cell.hpp"
#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::cell {

/// Capacity of FrameStatus::reason, NUL included (longer reasons are cut).
constexpr std::size_t kFrameReasonCapacity = 512U;

/// What loading one frame found.
struct FrameStatus {
    bool ok = false;        ///< true: the frame is fused
    const char* file = "";  ///< the file it came from ("" for a rendered frame); valid until the source changes
    char reason[kFrameReasonCapacity] = {};  ///< why it was refused (empty when ok)
    std::uint64_t points = 0U;               ///< recorded frames: finite points fused
    std::uint64_t nonfinite = 0U;            ///< recorded frames: points skipped as NaN or infinite
    /// A live camera's frame: true when stamp_us holds its capture time,
    /// which the monitor's loop uses as the reading's time instead of the
    /// cycle's start (false: simulated and recorded frames, stamped with the cycle's start).
    bool has_stamp = false;
    std::uint64_t stamp_us = 0U;  ///< has_stamp: the capture time, CLOCK_MONOTONIC microseconds
    /// has_stamp: when the frame's last packet arrived, CLOCK_MONOTONIC microseconds (0: not known).
    std::uint64_t receive_us = 0U;
    /// True when a depth filter changed the reading (FilteredFrameSource,
    /// depth_conditioning.hpp): @ref delivered then describes the frame as the
    /// sensor delivered it, which the frozen-sensor check judges (SensorInput::delivered).
    bool filtered = false;
    SensorReading delivered{};  ///< filtered: the frame before the filter (valid until the source's next load)
};

/// How a depth camera's readings are described: a live camera's
/// (CameraFrameSource, camera_input.hpp) and a recorded one's (DepthFileFrameSource, depth_input.hpp).
struct CameraReadingParams {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> cell
    PinholeIntrinsics intrinsics{};                          ///< the sensor's (width and height too)
    float depth_scale_m = 0.001F;                            ///< metres per raw unit
    float depth_offset_m = 0.0F;                             ///< metres
    float max_range = 10.0F;                                 ///< metres
};

/// One sensor's frames.
class FrameSource {
public:
    /// Puts the frame of cycle @p cycle (from 0) into the source's own buffer
    /// and describes it in @p reading (valid until the next call). A refused
    /// frame leaves @p reading with a non-finite pose, which the controller
    /// reports as kFrameInconsistent, and returns false with @p status saying
    /// why. Allocates nothing.
    virtual bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept = 0;
    /// True when load_frame() would now give a frame it has not given before.
    /// The paced loop starts a cycle early once every source has one
    /// (monitor_loop.hpp, run_cycles). A source that makes its frame when it is
    /// loaded (simulated, recorded) always has one: true. Never blocks.
    [[nodiscard]] virtual bool has_new_frame() const noexcept { return true; }
    /// Writes the source's line of the run's summary to @p out, if it has one.
    virtual void write_summary(std::FILE* out) const noexcept = 0;
    /// Sources are owned through this interface.
    virtual ~FrameSource() = default;

protected:
    FrameSource() = default;
    FrameSource(const FrameSource&) = default;
    FrameSource& operator=(const FrameSource&) = default;
    FrameSource(FrameSource&&) = default;
    FrameSource& operator=(FrameSource&&) = default;
};

/// Makes @p reading the description the controller refuses as
/// kFrameInconsistent: an empty point set with a non-finite pose. How every
/// source reports a frame it refused (FrameSource::load_frame).
void refuse_reading(SensorReading& reading) noexcept;

/// Whether a simulated source varies its frames: the simulator is noise-free,
/// so with nothing moving its frames are bit-identical and the frozen-sensor
/// check (cycle.max_repeated_frames) would take it for frozen.
enum class FrameDither : std::uint8_t {
    kOff = 0,  ///< the render, bit for bit
    kOn = 1,   ///< in odd cycles the first pixel with a reading one float step (ulp) deeper
};

/// What a simulated demo sensor shows.
enum class FrameScene : std::uint8_t {
    kDemo = 0,   ///< the reference scene with the demo's scripted person (scenario.hpp)
    kEmpty = 1,  ///< the reference scene alone: the empty cell, as at commissioning
};

/// The dither of FrameDither::kOn on @p depth for @p cycle (nothing in even
/// cycles): deterministic, far below any depth tolerance (about 0.24 um at 2 m).
void dither_depth(std::uint64_t cycle, Span<float> depth) noexcept;

/// A simulated sensor of the demo cell: every cycle it ray casts the demo's
/// scene of that cycle, the reference scene (sim::reference_scene) with the
/// scripted person (scenario.hpp) added, into its depth image
/// (sim::BackgroundView: the reference scene is cast once, then each frame
/// only the pixels whose ray may meet the person): the image render_frame
/// gives for that scene, bit for bit (with FrameDither::kOff; kOn, the
/// default, adds dither_depth).
class SimulatedFrameSource final : public FrameSource {
public:
    /// A source for @p spec showing @p scene; allocates its image (width x height) and scene.
    explicit SimulatedFrameSource(const sim::SensorSpec& spec, FrameDither dither = FrameDither::kOn,
                                  FrameScene scene = FrameScene::kDemo);

    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// A simulated sensor has no summary line.
    void write_summary(std::FILE* out) const noexcept override;

    /// Images rendered so far.
    [[nodiscard]] std::uint64_t renders() const noexcept { return renders_; }

private:
    sim::SensorSpec spec_;
    FrameDither dither_;
    FrameScene scene_;
    sim::BackgroundView background_;  ///< the reference scene's view, cast once
    sim::Scene moving_;               ///< this cycle's person, room for one box
    sim::PreparedScene prepared_;     ///< moving_, prepared
    std::vector<float> depth_;
    std::uint64_t renders_ = 0U;
};

/// A simulated sensor's view of the empty cell, for commissioning
/// (`cellguard-monitor --write-background`): the render @p view of the cell's
/// background alone (MonitorCell's layout: no scripted person, no scene's
/// robot or persons), every cycle, with dither_depth unless FrameDither::kOff,
/// so that the recorded views are the empty cell's, as the prior's are.
class EmptyCellFrameSource final : public FrameSource {
public:
    /// A source of @p view (a depth image; copied, with its description).
    explicit EmptyCellFrameSource(const SensorReading& view, FrameDither dither = FrameDither::kOn);

    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// A simulated sensor has no summary line.
    void write_summary(std::FILE* out) const noexcept override;

private:
    SensorReading view_;
    FrameDither dither_;
    std::vector<float> depth_;
};

/// A simulated sensor of a scene-file cell (the robot-cell demo): every
/// cycle it ray casts the scene that @p simulation holds at that moment (the
/// monitor's loop moves the simulation before it loads the frames) into its
/// depth image (with dither_depth unless FrameDither::kOff).
class SceneFrameSource final : public FrameSource {
public:
    /// A source for @p spec of @p simulation (which must outlive it); allocates its image.
    SceneFrameSource(const sim::SensorSpec& spec, const sim::RobotCellSimulation& simulation,
                     FrameDither dither = FrameDither::kOn);

    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// A simulated sensor has no summary line.
    void write_summary(std::FILE* out) const noexcept override;

private:
    sim::SensorSpec spec_;
    FrameDither dither_;
    sim::SensorRays rays_;  ///< the pixels' rays, computed once
    const sim::RobotCellSimulation* simulation_;
    std::vector<float> depth_;
};

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_FRAME_SOURCE_HPP
