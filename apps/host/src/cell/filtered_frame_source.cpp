// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/cell/filtered_frame_source.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>

#include "cellguard/grid/sensor_frame.hpp"

namespace cellguard::cell {

FilteredFrameSource::FilteredFrameSource(std::unique_ptr<FrameSource> inner, Span<const float> view, std::int32_t width,
                                         std::int32_t height, const DepthConditioning& filter, std::string sensor)
    : inner_(std::move(inner)),
      view_(view),
      width_(width),
      height_(height),
      filter_(filter),
      sensor_(std::move(sensor)),
      image_(static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0))),
      scratch_(image_.size()) {}

bool FilteredFrameSource::load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept {
    if (!inner_->load_frame(cycle, reading, status)) {
        return false;
    }
    if (!is_depth_image(reading.kind)) {
        return true;  // a point set: the filter works on images
    }
    const std::size_t n = image_.size();
    const std::size_t given = reading.kind == SensorDataKind::kDepthImage ? reading.depth.size()
                                                                          : reading.depth_u16.size();
    const bool fits = reading.intrinsics.width == width_ && reading.intrinsics.height == height_ && given == n &&
                      view_.size() == n;
    if (fits) {
        for (std::size_t i = 0U; i < n; ++i) {
            image_[i] = depth_value(reading, i);
        }
    }
    if (!fits || !condition_depth({image_.data(), n}, view_, {scratch_.data(), scratch_.size()}, width_, height_,
                                  filter_, &counts_)) {
        static_cast<void>(std::snprintf(
            status.reason, sizeof status.reason, "depth filter: a %dx%d image, the sensor's view is %dx%d",
            static_cast<int>(reading.intrinsics.width), static_cast<int>(reading.intrinsics.height),
            static_cast<int>(width_), static_cast<int>(height_)));
        status.ok = false;
        refuse_reading(reading);
        return false;
    }
    ++frames_;
    status.filtered = true;
    status.delivered = reading;
    reading.kind = SensorDataKind::kDepthImage;
    reading.depth = {image_.data(), n};
    reading.depth_u16 = {};
    return true;
}

void FilteredFrameSource::write_summary(std::FILE* out) const noexcept {
    inner_->write_summary(out);
    if (out == nullptr || frames_ == 0U) {
        return;
    }
    static_cast<void>(std::fprintf(
        out,
        "depth filter (%s): %llu frames, %llu readings dropped at edges, %llu put onto the "
        "empty cell's depth, %llu speckles dropped\n",
        sensor_.c_str(), static_cast<unsigned long long>(frames_), static_cast<unsigned long long>(counts_.dropped),
        static_cast<unsigned long long>(counts_.snapped), static_cast<unsigned long long>(counts_.speckles)));
}

}  // namespace cellguard::cell
