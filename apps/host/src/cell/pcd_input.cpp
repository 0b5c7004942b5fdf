// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Recorded PCD frames as sensor input, each frame checked (pcd_input.hpp).
#include "cellguard/host/cell/pcd_input.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include "cellguard/host/io/file.hpp"

namespace cellguard::cell {

bool is_unplaced_viewpoint(const PcdViewpoint& v) {
    constexpr double e = 1e-9;
    return std::fabs(v.tx) < e && std::fabs(v.ty) < e && std::fabs(v.tz) < e;
}

bool viewpoint_matches(const PcdViewpoint& v, const Eigen::Isometry3d& pose, double max_distance,
                       double max_angle_deg) {
    const Eigen::Vector3d t(v.tx, v.ty, v.tz);
    if (!t.allFinite() || (t - pose.translation()).norm() > max_distance) {
        return false;
    }
    const Eigen::Quaterniond q(v.qw, v.qx, v.qy, v.qz);
    const Eigen::Quaterniond p(pose.linear());
    if (!q.coeffs().allFinite() || q.norm() < 0.5) {
        return false;
    }
    const double angle = q.normalized().angularDistance(p.normalized());
    return angle <= max_angle_deg * 3.14159265358979323846 / 180.0;
}

// NOLINTNEXTLINE(modernize-pass-by-value): Eigen's rule: fixed-size types are passed by const reference, not by value
PcdFrameSource::PcdFrameSource(std::string name, std::vector<std::string> files, const Eigen::Isometry3d& pose,
                               int width, int height, float max_range)
    : name_(std::move(name)),
      files_(std::move(files)),
      pose_(pose),
      width_(width),
      height_(height),
      max_range_(max_range),
      buffer_(
          std::min(static_cast<std::size_t>(width > 0 ? width : 0) * static_cast<std::size_t>(height > 0 ? height : 0),
                   kMaxReadingsPerSensor)) {
    points_.reserve(buffer_.size());
    std::size_t largest = 0U;
    for (const std::string& f : files_) {
        struct stat st {};
        if (::stat(f.c_str(), &st) == 0 && st.st_size > 0 &&
            static_cast<std::uint64_t>(st.st_size) <= kPcdMaxFileBytes) {
            largest = std::max(largest, static_cast<std::size_t>(st.st_size));
        }
    }
    bytes_.resize(largest);
}

PcdFrameCheck PcdFrameSource::load(std::uint64_t cycle, SensorReading& reading) {
    FrameStatus status;
    (void)load_frame(cycle, reading, status);
    PcdFrameCheck c;
    c.ok = status.ok;
    c.file = status.file;
    c.reason = status.reason;
    c.points = status.points;
    c.nonfinite = status.nonfinite;
    return c;
}

IoStatus PcdFrameSource::read_file(const char* path, PcdCloudInfo& info) noexcept {
    // read_pcd's steps and messages, into the buffer allocated at start-up
    // (read_pcd allocates one per call).
    info = PcdCloudInfo{};
    std::size_t size = 0U;
    const IoStatus read = host::read_whole_file(path, {bytes_.data(), bytes_.size()}, size);
    if (read.error() == ErrorCode::kStorageTooSmall) {  // the buffer: the largest file at start-up, within the limit
        return IoStatus::failure(ErrorCode::kCapacityExceeded,
                                 "%s: pcd: file larger than the %zu bytes this sensor's files had at start-up "
                                 "(limit %llu)",
                                 path, bytes_.size(), static_cast<unsigned long long>(kPcdMaxFileBytes));
    }
    if (!read) {
        return read;
    }
    return decode_pcd(bytes_.data(), size, {buffer_.data(), buffer_.size()}, info).prefixed(path);
}

bool PcdFrameSource::check_frame(const IoStatus& read, const PcdCloudInfo& info, FrameStatus& status) const noexcept {
    const std::size_t capacity = buffer_.size();
    char* const reason = status.reason;
    const std::size_t size = sizeof status.reason;
    if (info.points > capacity) {  // whether the read failed on it or not
        static_cast<void>(std::snprintf(reason, size, "%llu points, more than sensor '%s' delivers (%d x %d)",
                                        static_cast<unsigned long long>(info.points), name_.c_str(), width_, height_));
    } else if (!read.ok()) {
        static_cast<void>(std::snprintf(reason, size, "%s", read.message()));
    } else if (info.height > 1U && (info.width != static_cast<std::uint32_t>(width_) ||
                                    info.height != static_cast<std::uint32_t>(height_))) {
        static_cast<void>(std::snprintf(reason, size, "organised cloud of %u x %u, but sensor '%s' has %d x %d pixels",
                                        static_cast<unsigned>(info.width), static_cast<unsigned>(info.height),
                                        name_.c_str(), width_, height_));
    } else if (!is_unplaced_viewpoint(info.viewpoint) && !viewpoint_matches(info.viewpoint, pose_)) {
        char buf[160];  // the message as it always was, at most 159 characters
        static_cast<void>(std::snprintf(buf, sizeof buf, "VIEWPOINT (%.3f, %.3f, %.3f) is not the pose of sensor '%s'",
                                        info.viewpoint.tx, info.viewpoint.ty, info.viewpoint.tz, name_.c_str()));
        static_cast<void>(std::snprintf(reason, size, "%s", buf));
    } else {
        return true;
    }
    return false;
}

bool PcdFrameSource::load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept {
    status = FrameStatus{};
    // Until the frame has passed every check, the description is one the
    // controller refuses (kFrameInconsistent): a non-finite pose, no points.
    refuse_reading(reading);
    reading.max_range = max_range_;
    points_.clear();
    if (files_.empty()) {
        static_cast<void>(std::snprintf(status.reason, sizeof status.reason, "no recorded frames"));
        ++refused_;
        return false;
    }
    status.file = files_[static_cast<std::size_t>(cycle % files_.size())].c_str();
    PcdCloudInfo info;
    const IoStatus st = read_file(status.file, info);
    status.nonfinite = info.nonfinite_points;
    if (!check_frame(st, info, status)) {
        ++refused_;
        return false;
    }
    for (std::uint64_t i = 0U; i < info.written; ++i) {
        const PcdPoint& p = buffer_[static_cast<std::size_t>(i)];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
            points_.emplace_back(p.x, p.y, p.z);  // within the capacity reserved: never reallocates
        } else {
            ++status.nonfinite;  // the reader writes finite points only; kept as a second check
        }
    }
    reading.pose = pose_;
    reading.points = Span<const Eigen::Vector3f>(points_.data(), points_.size());
    status.points = points_.size();
    status.ok = true;
    ++used_;
    return true;
}

void PcdFrameSource::write_summary(std::FILE* out) const noexcept {
    static_cast<void>(
        std::fprintf(out, "summary: sensor '%s': %llu recorded frames used, %llu refused (frame inconsistent)\n",
                     name_.c_str(), static_cast<unsigned long long>(used_), static_cast<unsigned long long>(refused_)));
}

}  // namespace cellguard::cell
