// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The demo scenario's frames for the fake cameras (demo_frames.hpp).
#include "cellguard/fake_camera/demo_frames.hpp"

#include <algorithm>

#include "cellguard/fake_camera/fake_gige_camera.hpp"

namespace cellguard::fake_camera {

std::uint64_t ScenarioClock::cycle(bool first, std::uint64_t now_ns) noexcept {
    if (first && cameras_ > 0U && streaming_.fetch_add(1U) + 1U == cameras_) {
        start(now_ns);
    }
    const std::uint64_t t0 = start_ns_.load();
    return t0 != 0U && now_ns > t0 ? (now_ns - t0) / period_ns_ : 0U;
}

DemoFrames::DemoFrames(const sim::SensorSpec& spec, const std::vector<std::pair<int, int>>& other_sizes, double scale_m,
                       double offset_m, cell::FrameScene scene)
    : scale_m_(scale_m), offset_m_(offset_m) {
    specs_.push_back(spec);
    for (const auto& [w, h] : other_sizes) {
        sim::SensorSpec s = spec;
        s.width = w;
        s.height = h;
        specs_.push_back(s);
    }
    for (const sim::SensorSpec& s : specs_) {
        sources_.push_back(
            std::make_unique<cell::SimulatedFrameSource>(s, cell::FrameDither::kOff, scene));  // --dither is its own
    }
}

void DemoFrames::render(std::uint64_t cycle, int width, int height, std::uint16_t* image) {
    const std::size_t n = static_cast<std::size_t>(width > 0 ? width : 0) *
                          static_cast<std::size_t>(height > 0 ? height : 0);
    int k = -1;
    for (std::size_t i = 0U; i < specs_.size() && k < 0; ++i) {
        k = (specs_[i].width == width && specs_[i].height == height) ? static_cast<int>(i) : -1;
    }
    if (k < 0) {
        std::fill(image, image + n, std::uint16_t{0U});
        return;
    }
    if (k == 0 && !prerendered_.empty()) {
        const std::vector<std::uint16_t>& frame =
            prerendered_[std::min<std::uint64_t>(cycle, prerendered_.size() - 1U)];
        std::copy(frame.begin(), frame.end(), image);
        return;
    }
    if (cycle != cached_cycle_ || k != cached_source_) {
        SensorReading reading;
        cell::FrameStatus status;
        cached_.assign(n, 0U);
        if (sources_[static_cast<std::size_t>(k)]->load_frame(cycle, reading, status) && reading.depth.size() == n) {
            for (std::size_t i = 0U; i < n; ++i) {
                cached_[i] = raw_depth(reading.depth[i], scale_m_, offset_m_);
            }
        }
        ++renders_;
        cached_cycle_ = cycle;
        cached_source_ = k;
    }
    std::copy(cached_.begin(), cached_.end(), image);
}

void DemoFrames::prerender(std::uint64_t cycles) {
    const sim::SensorSpec& spec = specs_.front();
    const std::size_t n = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
    std::vector<std::vector<std::uint16_t>> frames(cycles, std::vector<std::uint16_t>(n));
    for (std::uint64_t c = 0U; c < cycles; ++c) {
        render(c, spec.width, spec.height, frames[c].data());
    }
    prerendered_ = std::move(frames);
}

void dither(std::uint64_t frame, std::size_t pixels, std::uint16_t* image) noexcept {
    if ((frame & 1U) == 0U) {
        return;
    }
    auto* const it = std::find_if(image, image + pixels, [](std::uint16_t v) { return v != 0U; });
    if (it != image + pixels) {
        *it = *it < 65535U ? static_cast<std::uint16_t>(*it + 1U) : static_cast<std::uint16_t>(*it - 1U);
    }
}

}  // namespace cellguard::fake_camera
