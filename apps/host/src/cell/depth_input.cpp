// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Recorded depth images as camera input, each frame checked (depth_input.hpp).
#include "cellguard/host/cell/depth_input.hpp"

#include <cstring>
#include <utility>

#include "cellguard/host/io/depth_npy.hpp"

namespace cellguard::cell {

namespace {

std::size_t pixels_of(const PinholeIntrinsics& k) {
    return static_cast<std::size_t>(k.width > 0 ? k.width : 0) * static_cast<std::size_t>(k.height > 0 ? k.height : 0);
}

}  // namespace

DepthFileFrameSource::DepthFileFrameSource(
    std::string name, std::vector<std::string> files,
    // NOLINTNEXTLINE(modernize-pass-by-value): Eigen fixed-size members, by reference (Eigen's rule)
    const CameraReadingParams& params, bool raw)
    : name_(std::move(name)),
      files_(std::move(files)),
      params_(params),
      raw_(raw),
      bytes_(pixels_of(params.intrinsics) * (raw ? sizeof(std::uint16_t) : sizeof(float)) + kDepthFileHeaderRoom),
      units_(raw ? pixels_of(params.intrinsics) : 0U),
      metres_(raw ? 0U : pixels_of(params.intrinsics)) {}

bool DepthFileFrameSource::load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept {
    status = FrameStatus{};
    if (files_.empty()) {
        ++counts_.refused;
        refuse_reading(reading);
        static_cast<void>(std::snprintf(status.reason, sizeof status.reason, "no depth files"));
        return false;
    }
    const std::string& path = files_[static_cast<std::size_t>(cycle % files_.size())];
    status.file = path.c_str();
    NpyDepthImage image;
    IoStatus st = read_npy_depth(path.c_str(), params_.intrinsics.width, params_.intrinsics.height,
                                 Span<std::uint8_t>(bytes_.data(), bytes_.size()), image);
    if (st && (image.dtype == NpyDtype::kUInt16) != raw_) {
        st = IoStatus::failure(ErrorCode::kUnsupportedType,
                               "%s: a '%s' image where the sensor's recording is '%s' (%s): a file of the other "
                               "unit is not read",
                               path.c_str(), raw_ ? "<f4" : "<u2", raw_ ? "<u2" : "<f4",
                               raw_ ? "raw units with depth_scale and depth_offset" : "metres, no depth_scale");
    }
    if (!st) {
        ++counts_.refused;
        refuse_reading(reading);
        static_cast<void>(std::snprintf(status.reason, sizeof status.reason, "%s", st.message()));
        return false;
    }
    reading = SensorReading{};
    reading.pose = params_.pose;
    reading.intrinsics = params_.intrinsics;
    reading.max_range = params_.max_range;
    if (image.dtype == NpyDtype::kUInt16) {
        std::memcpy(units_.data(), image.pixels, image.count * sizeof(std::uint16_t));
        reading.kind = SensorDataKind::kDepthImageU16;
        reading.depth_u16 = Span<const std::uint16_t>(units_.data(), image.count);
        reading.depth_scale = params_.depth_scale_m;
        reading.depth_offset = params_.depth_offset_m;
    } else {
        std::memcpy(metres_.data(), image.pixels, image.count * sizeof(float));
        reading.kind = SensorDataKind::kDepthImage;
        reading.depth = Span<const float>(metres_.data(), image.count);
    }
    ++counts_.used;
    status.ok = true;
    return true;
}

void DepthFileFrameSource::write_summary(std::FILE* out) const noexcept {
    static_cast<void>(std::fprintf(out,
                                   "summary: sensor '%s': %llu recorded depth images used, %llu refused (frame "
                                   "inconsistent)\n",
                                   name_.c_str(), static_cast<unsigned long long>(counts_.used),
                                   static_cast<unsigned long long>(counts_.refused)));
}

}  // namespace cellguard::cell
