// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file depth_input.hpp
/// Sensor input from recorded depth images (.npy files, depth_npy.hpp): a
/// sensor with `depth_files` in the configuration takes its frames from those
/// files, one per cycle, in order, starting again after the last, through the
/// camera path (the same readings a live camera gives: kDepthImageU16 for
/// '<u2' files with the sensor's depth_scale and depth_offset, kDepthImage for
/// '<f4' files in metres), with the sensor's pose, intrinsics and max_range.
///
/// Every frame is checked before use (depth_npy.hpp's checks: the format, the
/// dtype, the shape (height, width) of the sensor); a file whose dtype is not
/// the recording's (the dtype its files had when the configuration was
/// loaded: '<u2' with depth_scale, '<f4' without) is refused, so a file
/// replaced after the start by one of the other kind is never read in the
/// other unit. A refused frame is not fused: its description
/// is made invalid on purpose, so the controller refuses it and latches
/// kFrameInconsistent, as for any other inconsistent frame.
///
/// Frames are stamped with the cycle's start (FrameStatus::has_stamp false),
/// as simulated and PCD frames are: a recording replays its images, not its
/// timing. Its buffers (the file's bytes and one image of the recording's
/// dtype) are allocated when the source is made; a frame then loads without
/// allocating.
#ifndef CELLGUARD_HOST_CELL_DEPTH_INPUT_HPP
#define CELLGUARD_HOST_CELL_DEPTH_INPUT_HPP

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/cell/frame_source.hpp"

namespace cellguard::cell {

/// The counts of a DepthFileFrameSource's cycles.
struct DepthFileCounts {
    std::uint64_t used = 0U;     ///< frames that passed every check
    std::uint64_t refused = 0U;  ///< frames refused (the controller then stops: frame inconsistent)
};

/// See the file comment.
class DepthFileFrameSource final : public FrameSource {
public:
    /// Frames from @p files (at least one) for the sensor named @p name,
    /// described with @p params (its intrinsics give the image's width and
    /// height); @p raw: the recording is '<u2' raw units (the sensor has a
    /// depth_scale), else '<f4' metres: files of the other dtype are refused.
    DepthFileFrameSource(std::string name, std::vector<std::string> files, const CameraReadingParams& params, bool raw);

    /// Reads and checks file cycle % count and describes it in @p reading
    /// (the image stays in this object until the next call).
    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// "summary: sensor 'NAME': U recorded depth images used, R refused (frame inconsistent)".
    void write_summary(std::FILE* out) const noexcept override;

    /// The cycles' counts so far.
    [[nodiscard]] const DepthFileCounts& counts() const noexcept { return counts_; }

private:
    std::string name_;
    std::vector<std::string> files_;
    CameraReadingParams params_;
    bool raw_;                          ///< the recording's dtype: '<u2' (true) or '<f4'
    std::vector<std::uint8_t> bytes_;   ///< a file's bytes: the largest a depth image of this size takes
    std::vector<std::uint16_t> units_;  ///< raw_: the '<u2' image (else empty)
    std::vector<float> metres_;         ///< not raw_: the '<f4' image (else empty)
    DepthFileCounts counts_{};
};

/// Headroom beyond a depth image's data that a depth file's header may take
/// (numpy writes 128 bytes; version 2.0 headers may be longer).
constexpr std::size_t kDepthFileHeaderRoom = 4096U;

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_DEPTH_INPUT_HPP
