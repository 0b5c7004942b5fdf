// Recorded PCD frames as sensor input, each frame checked (pcd_input.hpp).
#include "cellguard/monitor/pcd_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace cellguard::monitor {

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

PcdFrameSource::PcdFrameSource(std::string name, std::vector<std::string> files, const Eigen::Isometry3d& pose,
                               int width, int height, float max_range)
    : name_(std::move(name)),
      files_(std::move(files)),
      pose_(pose),
      width_(width),
      height_(height),
      max_range_(max_range),
      buffer_(kMaxReadingsPerSensor) {
    points_.reserve(kMaxReadingsPerSensor);
}

PcdFrameCheck PcdFrameSource::load(std::uint64_t cycle, SensorReading& reading) {
    PcdFrameCheck c;
    // Until the frame has passed every check, the description is one the
    // controller refuses (kFrameInconsistent): a non-finite pose, no points.
    reading = SensorReading{};
    reading.kind = SensorDataKind::kPointSet;
    reading.pose.translation().setConstant(std::numeric_limits<double>::quiet_NaN());
    reading.max_range = max_range_;
    points_.clear();
    if (files_.empty()) {
        c.reason = "no recorded frames";
        ++refused_;
        return c;
    }
    c.file = files_[static_cast<std::size_t>(cycle % files_.size())];
    const std::size_t capacity = std::min(
        static_cast<std::size_t>(width_ > 0 ? width_ : 0) * static_cast<std::size_t>(height_ > 0 ? height_ : 0),
        buffer_.size());
    PcdCloudInfo info;
    const IoStatus st = read_pcd(c.file.c_str(), {buffer_.data(), capacity}, info);
    c.nonfinite = info.nonfinite_points;
    if (!st.ok() && info.points > capacity) {
        c.reason = std::to_string(info.points) + " points, more than sensor '" + name_ + "' delivers (" +
                   std::to_string(width_) + " x " + std::to_string(height_) + ")";
    } else if (!st.ok()) {
        c.reason = st.message();
    } else if (info.points > capacity) {
        c.reason = std::to_string(info.points) + " points, more than sensor '" + name_ + "' delivers (" +
                   std::to_string(width_) + " x " + std::to_string(height_) + ")";
    } else if (info.height > 1U && (info.width != static_cast<std::uint32_t>(width_) ||
                                    info.height != static_cast<std::uint32_t>(height_))) {
        c.reason = "organised cloud of " + std::to_string(info.width) + " x " + std::to_string(info.height) +
                   ", but sensor '" + name_ + "' has " + std::to_string(width_) + " x " + std::to_string(height_) +
                   " pixels";
    } else if (!is_unplaced_viewpoint(info.viewpoint) && !viewpoint_matches(info.viewpoint, pose_)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "VIEWPOINT (%.3f, %.3f, %.3f) is not the pose of sensor '%s'",
                      info.viewpoint.tx, info.viewpoint.ty, info.viewpoint.tz, name_.c_str());
        c.reason = buf;
    } else {
        for (std::uint64_t i = 0U; i < info.written; ++i) {
            const PcdPoint& p = buffer_[static_cast<std::size_t>(i)];
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
                points_.emplace_back(p.x, p.y, p.z);
            } else {
                ++c.nonfinite;  // the reader writes finite points only; kept as a second check
            }
        }
        reading.pose = pose_;
        reading.points = Span<const Eigen::Vector3f>(points_.data(), points_.size());
        c.points = points_.size();
        c.ok = true;
        ++used_;
        return c;
    }
    ++refused_;
    return c;
}

}  // namespace cellguard::monitor
