// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/sensor_frame.hpp"

#include <cmath>
#include <cstring>

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
    if (!(reading.min_range >= 0.0F && reading.min_range < reading.max_range && reading.max_range <= kMaxSensorRange)) {
        return ErrorCode::kInvalidArgument;
    }
    if (reading.kind == SensorDataKind::kPointSet) {
        if (reading.points.size() > kMaxReadingsPerSensor) {
            return ErrorCode::kCapacityExceeded;
        }
        return Status{};
    }
    if (!is_depth_image(reading.kind)) {
        return ErrorCode::kInvalidArgument;
    }
    const bool u16 = reading.kind == SensorDataKind::kDepthImageU16;
    if (u16 && !(std::isfinite(reading.depth_scale) && std::isfinite(reading.depth_offset))) {
        return ErrorCode::kNonFiniteValue;
    }
    if (u16 && !(reading.depth_scale > 0.0F)) {
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
    // Only the kind's own view counts: the other one may hold anything.
    if ((u16 ? reading.depth_u16.size() : reading.depth.size()) != pixels) {
        return ErrorCode::kMalformedInput;
    }
    return Status{};
}

namespace {

/// An odd 64-bit multiplier (the golden ratio's bits) for the fingerprint lanes.
constexpr std::uint64_t kFingerprintMultiplier = 0x9E3779B97F4A7C15ULL;

std::uint32_t bits_of(float value) noexcept {
    std::uint32_t bits = 0U;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
}

/// Four lanes of multiply-xor over 32-bit words, so that their multiplies
/// overlap; value i goes to lane i mod 4.
class FingerprintLanes {
public:
    void add(std::uint32_t word) noexcept {
        std::uint64_t& h = lanes_[next_];
        h = (h ^ word) * kFingerprintMultiplier;
        next_ = (next_ + 1U) & 3U;
    }
    void add4(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) noexcept {
        lanes_[0] = (lanes_[0] ^ a) * kFingerprintMultiplier;
        lanes_[1] = (lanes_[1] ^ b) * kFingerprintMultiplier;
        lanes_[2] = (lanes_[2] ^ c) * kFingerprintMultiplier;
        lanes_[3] = (lanes_[3] ^ d) * kFingerprintMultiplier;
    }
    /// The lanes and @p count mixed into one value (a variant of splitmix64's finaliser).
    [[nodiscard]] std::uint64_t finish(std::uint64_t count) const noexcept {
        std::uint64_t h = count * kFingerprintMultiplier;
        for (const std::uint64_t lane : lanes_) {
            h = (h ^ lane ^ (lane >> 29U)) * kFingerprintMultiplier;
            h ^= h >> 32U;
        }
        return h;
    }

private:
    std::uint64_t lanes_[4] = {1U, 2U, 3U, 4U};
    std::uint32_t next_ = 0U;
};

}  // namespace

std::uint64_t reading_fingerprint(const SensorReading& reading) noexcept {
    FingerprintLanes lanes;
    if (reading.kind == SensorDataKind::kDepthImage) {
        const Span<const float> d = reading.depth;
        std::size_t i = 0U;
        for (; i + 4U <= d.size(); i += 4U) {
            lanes.add4(bits_of(d[i]), bits_of(d[i + 1U]), bits_of(d[i + 2U]), bits_of(d[i + 3U]));
        }
        for (; i < d.size(); ++i) {
            lanes.add(bits_of(d[i]));
        }
        return lanes.finish(d.size());
    }
    if (reading.kind == SensorDataKind::kDepthImageU16) {
        // The scale and offset (they change every depth) first, then the raw
        // values as they are, two to a word.
        const Span<const std::uint16_t> d = reading.depth_u16;
        lanes.add(bits_of(reading.depth_scale));
        lanes.add(bits_of(reading.depth_offset));
        std::size_t i = 0U;
        const auto pair = [&d](std::size_t j) noexcept {
            return static_cast<std::uint32_t>(d[j]) | (static_cast<std::uint32_t>(d[j + 1U]) << 16U);
        };
        for (; i + 8U <= d.size(); i += 8U) {
            lanes.add4(pair(i), pair(i + 2U), pair(i + 4U), pair(i + 6U));
        }
        for (; i < d.size(); ++i) {
            lanes.add(d[i]);
        }
        return lanes.finish(d.size());
    }
    for (const Eigen::Vector3f& p : reading.points) {
        lanes.add(bits_of(p.x()));
        lanes.add(bits_of(p.y()));
        lanes.add(bits_of(p.z()));
    }
    return lanes.finish(reading.points.size() * 3U);
}

}  // namespace cellguard
