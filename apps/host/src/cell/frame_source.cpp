// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The simulated sensors of the demo cell as frame sources (frame_source.hpp).
#include "cellguard/host/cell/frame_source.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cellguard/host/cell/scenario.hpp"

namespace cellguard::cell {

void refuse_reading(SensorReading& reading) noexcept {
    reading = SensorReading{};
    reading.pose.translation().setConstant(std::numeric_limits<double>::quiet_NaN());
}

void dither_depth(std::uint64_t cycle, Span<float> depth) noexcept {
    if ((cycle & 1U) == 0U) {
        return;
    }
    float* const first = std::find_if(depth.begin(), depth.end(), [](float d) { return std::isfinite(d) && d > 0.0F; });
    if (first != depth.end()) {
        *first = std::nextafter(*first, std::numeric_limits<float>::infinity());
    }
}

SimulatedFrameSource::SimulatedFrameSource(const sim::SensorSpec& spec, FrameDither dither, FrameScene scene)
    : spec_(spec),
      dither_(dither),
      scene_(scene),
      background_(spec, sim::reference_scene()),
      prepared_(1U),
      depth_(static_cast<std::size_t>(spec.width > 0 ? spec.width : 0) *
             static_cast<std::size_t>(spec.height > 0 ? spec.height : 0)) {
    moving_.floor = false;  // the floor is the background's
    moving_.boxes.reserve(1U);
}

bool SimulatedFrameSource::load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept {
    status = FrameStatus{};
    // The scene of the cycle, as the demo always made it: the reference
    // scene (cast once, background_) plus the person. Within the reserved
    // capacity nothing allocates.
    const int k = cycle > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ? std::numeric_limits<int>::max()
                                                                                      : static_cast<int>(cycle);
    moving_.boxes.clear();
    if (scene_ == FrameScene::kDemo) {
        moving_.boxes.push_back(person_box(demo_person(k)));
    }
    if (!prepared_.assign(moving_) || !background_.render_into(prepared_, Span<float>(depth_.data(), depth_.size()))) {
        // Not reached: the buffers were sized for this scene and image.
        reading = SensorReading{};
        reading.pose.translation().setConstant(std::numeric_limits<double>::quiet_NaN());
        static_cast<void>(
            std::snprintf(status.reason, sizeof status.reason, "the simulated frame does not fit its buffer"));
        return false;
    }
    ++renders_;
    if (dither_ == FrameDither::kOn) {
        dither_depth(cycle, Span<float>(depth_.data(), depth_.size()));
    }
    reading = sim::depth_reading(spec_, Span<const float>(depth_.data(), depth_.size()));
    status.ok = true;
    return true;
}

void SimulatedFrameSource::write_summary(std::FILE* /*out*/) const noexcept {}

SceneFrameSource::SceneFrameSource(const sim::SensorSpec& spec, const sim::RobotCellSimulation& simulation,
                                   FrameDither dither)
    : spec_(spec),
      dither_(dither),
      rays_(spec),
      simulation_(&simulation),
      depth_(static_cast<std::size_t>(spec.width > 0 ? spec.width : 0) *
             static_cast<std::size_t>(spec.height > 0 ? spec.height : 0)) {}

bool SceneFrameSource::load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept {
    status = FrameStatus{};
    if (!sim::render_depth_into(rays_, simulation_->scene(), Span<float>(depth_.data(), depth_.size()))) {
        // Not reached: the image was sized for the sensor.
        reading = SensorReading{};
        reading.pose.translation().setConstant(std::numeric_limits<double>::quiet_NaN());
        static_cast<void>(
            std::snprintf(status.reason, sizeof status.reason, "the simulated frame does not fit its buffer"));
        return false;
    }
    if (dither_ == FrameDither::kOn) {
        dither_depth(cycle, Span<float>(depth_.data(), depth_.size()));
    }
    reading = sim::depth_reading(spec_, Span<const float>(depth_.data(), depth_.size()));
    status.ok = true;
    return true;
}

void SceneFrameSource::write_summary(std::FILE* /*out*/) const noexcept {}

EmptyCellFrameSource::EmptyCellFrameSource(const SensorReading& view, FrameDither dither)
    : view_(view), dither_(dither), depth_(view.depth.data(), view.depth.data() + view.depth.size()) {}

bool EmptyCellFrameSource::load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept {
    status = FrameStatus{};
    std::copy(view_.depth.data(), view_.depth.data() + view_.depth.size(), depth_.begin());
    if (dither_ == FrameDither::kOn) {
        dither_depth(cycle, Span<float>(depth_.data(), depth_.size()));
    }
    reading = view_;
    reading.depth = Span<const float>(depth_.data(), depth_.size());
    status.ok = true;
    return true;
}

void EmptyCellFrameSource::write_summary(std::FILE* /*out*/) const noexcept {}

}  // namespace cellguard::cell
