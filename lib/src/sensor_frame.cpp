#include "cellguard/sensor_frame.hpp"

#include <cmath>

namespace cellguard {

Status validate_sensor_reading(const SensorReading& reading) noexcept {
    const Eigen::Matrix4d& m = reading.pose.matrix();
    if (!m.allFinite() || !std::isfinite(reading.min_range) || !std::isfinite(reading.max_range)) {
        return ErrorCode::kNonFiniteValue;
    }
    const Eigen::Matrix3d r = reading.pose.linear();
    const double orthonormal_error = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (orthonormal_error > 1e-6 || r.determinant() <= 0.0) {
        return ErrorCode::kInvalidArgument;
    }
    if (!(reading.min_range >= 0.0F && reading.min_range < reading.max_range &&
          reading.max_range <= kMaxSensorRange)) {
        return ErrorCode::kInvalidArgument;
    }
    if (reading.kind == SensorDataKind::kPointSet) {
        if (reading.points.size() > kMaxReadingsPerSensor) {
            return ErrorCode::kCapacityExceeded;
        }
        return Status{};
    }
    if (reading.kind != SensorDataKind::kDepthImage) {
        return ErrorCode::kInvalidArgument;
    }
    const PinholeIntrinsics& k = reading.intrinsics;
    if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
        return ErrorCode::kNonFiniteValue;
    }
    if (!(k.fx > 0.0 && k.fy > 0.0) || k.width <= 0 || k.height <= 0) {
        return ErrorCode::kInvalidArgument;
    }
    const std::size_t pixels = static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height);
    if (pixels > kMaxReadingsPerSensor) {
        return ErrorCode::kCapacityExceeded;
    }
    if (reading.depth.size() != pixels) {
        return ErrorCode::kMalformedInput;
    }
    return Status{};
}

}  // namespace cellguard
