// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file filtered_frame_source.hpp
/// The depth filter in the monitor's camera path: a frame source that
/// filters another's depth images (depth_conditioning.hpp) before the
/// controller fuses them, made for each depth sensor when the configuration's
/// [depth_filter] turns a filter on.
#ifndef CELLGUARD_HOST_CELL_FILTERED_FRAME_SOURCE_HPP
#define CELLGUARD_HOST_CELL_FILTERED_FRAME_SOURCE_HPP

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cellguard/base/span.hpp"
#include "cellguard/host/cell/depth_conditioning.hpp"
#include "cellguard/host/cell/frame_source.hpp"

namespace cellguard::cell {

/// A depth camera's frames with the depth filter applied: each frame that
/// @p inner gives is read into the filter's own float image (a uint16 image
/// through depth_value: raw 0 reads NaN, no reading), filtered by
/// condition_depth against the sensor's commissioned view, and given on as a
/// float depth image; FrameStatus::filtered and ::delivered describe the
/// frame as delivered (the frozen-sensor check judges that one). A point set
/// passes unchanged; a depth image of another size than the view is refused.
/// Storage is made at construction: loading allocates nothing.
class FilteredFrameSource final : public FrameSource {
public:
    /// Filters @p inner's frames with @p filter against @p view (width x
    /// height depths of the sensor's empty cell, which must outlive the
    /// source); @p sensor names the sensor in the summary.
    FilteredFrameSource(std::unique_ptr<FrameSource> inner, Span<const float> view, std::int32_t width,
                        std::int32_t height, const DepthConditioning& filter, std::string sensor);

    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// The inner source's: the filter makes no frame of its own.
    [[nodiscard]] bool has_new_frame() const noexcept override { return inner_->has_new_frame(); }
    /// The inner source's line, then the filter's counts under the sensor's name (nothing when it has not run).
    void write_summary(std::FILE* out) const noexcept override;

    /// What the filter changed so far.
    [[nodiscard]] const ConditioningCounts& counts() const noexcept { return counts_; }
    /// Frames filtered so far.
    [[nodiscard]] std::uint64_t frames() const noexcept { return frames_; }

private:
    std::unique_ptr<FrameSource> inner_;
    Span<const float> view_;
    std::int32_t width_;
    std::int32_t height_;
    DepthConditioning filter_;
    std::string sensor_;
    std::vector<float> image_;
    std::vector<float> scratch_;
    ConditioningCounts counts_{};
    std::uint64_t frames_ = 0U;
};

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_FILTERED_FRAME_SOURCE_HPP
