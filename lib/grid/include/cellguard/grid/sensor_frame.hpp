// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file sensor_frame.hpp
/// One cycle's sensor input at fixed capacity: per sensor a pose and either a
/// point set in the sensor's own frame or a depth image with pinhole
/// intrinsics. The data stay in caller storage (a driver's buffers); these
/// types only describe them, and `validate_sensor_reading` checks the
/// description before fusion touches it.
///
/// Sensor frame convention (the camera convention): x right, y down, z along
/// the optical axis. A reading "behind the sensor" has z < 0.
#ifndef CELLGUARD_SENSOR_FRAME_HPP
#define CELLGUARD_SENSOR_FRAME_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"

namespace cellguard {

/// Most sensors fused in one frame.
constexpr std::size_t kMaxSensors = 8U;
/// Most readings (points or pixels) of one sensor in one frame (a 640 x 480 image).
constexpr std::size_t kMaxReadingsPerSensor = std::size_t{640U} * std::size_t{480U};
/// Largest accepted maximum range of a sensor, metres.
constexpr float kMaxSensorRange = 100.0F;

/// Pinhole camera intrinsics of a depth image. Pixel (u, v) (column, row,
/// from 0) looks along ((u - cx) / fx, (v - cy) / fy, 1).
struct PinholeIntrinsics {
    double fx = 0.0;          ///< focal length along u, pixels
    double fy = 0.0;          ///< focal length along v, pixels
    double cx = 0.0;          ///< principal point, column
    double cy = 0.0;          ///< principal point, row
    std::int32_t width = 0;   ///< image columns
    std::int32_t height = 0;  ///< image rows
};

/// What a sensor delivered.
enum class SensorDataKind : std::uint8_t {
    kPointSet = 0,    ///< 3D points in the sensor frame, metres
    kDepthImage = 1,  ///< depth along the optical axis (z), metres, row-major; 0 or NaN = no reading
    /// Raw uint16 depth along the optical axis as cameras deliver it (GenICam
    /// Coord3D_C16, RealSense Z16), row-major: depth = raw * depth_scale +
    /// depth_offset metres (depth_value); raw 0 = no reading (read as NaN,
    /// so fusion counts it in FusionStats::skipped_nan).
    kDepthImageU16 = 2,
};

/// One sensor's reading in one frame: where the sensor is and what it saw.
struct SensorReading {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor frame -> workcell frame
    SensorDataKind kind = SensorDataKind::kPointSet;         ///< which of the views below is used
    Span<const Eigen::Vector3f> points{};                    ///< kPointSet: the points
    Span<const float> depth{};                               ///< kDepthImage: width * height depths
    Span<const std::uint16_t> depth_u16{};                   ///< kDepthImageU16: width * height raw depths
    float depth_scale = 0.001F;                              ///< kDepthImageU16: metres per raw unit (finite, > 0)
    float depth_offset = 0.0F;       ///< kDepthImageU16: metres added to raw * depth_scale (finite)
    PinholeIntrinsics intrinsics{};  ///< depth images: the camera
    float min_range = 0.0F;          ///< readings nearer than this (metres, along the ray) are skipped
    float max_range = 10.0F;         ///< readings farther than this are skipped
};

/// Checks a reading's description (not its values, which fusion counts):
/// pose finite with an orthonormal rotation (|R^T R - I| <= 1e-6,
/// det R > 0), ranges 0 <= min_range < max_range <= kMaxSensorRange, at most
/// kMaxReadingsPerSensor readings, for a depth image positive finite focal
/// lengths, finite principal point, positive size and the kind's view
/// (depth, or depth_u16 for kDepthImageU16; the other view is ignored) of
/// width * height values; for kDepthImageU16 a finite depth_scale > 0 and a
/// finite depth_offset. Errors: kNonFiniteValue, kInvalidArgument,
/// kCapacityExceeded, kMalformedInput (size mismatch).
[[nodiscard]] Status validate_sensor_reading(const SensorReading& reading) noexcept;

/// True for the two depth-image kinds (kDepthImage, kDepthImageU16).
[[nodiscard]] constexpr bool is_depth_image(SensorDataKind kind) noexcept {
    return kind == SensorDataKind::kDepthImage || kind == SensorDataKind::kDepthImageU16;
}

/// Depth of pixel @p i (row-major) of a validated depth-image reading, in
/// metres, as every fusion path reads it: kDepthImage the float as stored;
/// kDepthImageU16 NaN for raw 0 (no reading), else float(raw * scale +
/// offset) computed in double (one rounding, the same on every target).
/// Reads the caller's buffer in place: no converted copy of the image.
[[nodiscard]] inline float depth_value(const SensorReading& reading, std::size_t i) noexcept {
    if (reading.kind == SensorDataKind::kDepthImageU16) {
        const std::uint16_t raw = reading.depth_u16[i];
        if (raw == 0U) {
            return std::numeric_limits<float>::quiet_NaN();
        }
        return static_cast<float>(static_cast<double>(raw) * static_cast<double>(reading.depth_scale) +
                                  static_cast<double>(reading.depth_offset));
    }
    return reading.depth[i];
}

/// A 64-bit fingerprint of a reading's data: the bit patterns of every depth
/// value (kDepthImage) or point coordinate (kPointSet), in order, and their
/// count; for kDepthImageU16 the bits of depth_scale and depth_offset, then
/// every raw value as stored, and their count. Equal data give equal fingerprints on every platform. Different
/// data can share one (the function is fast, not cryptographic); for the
/// frozen-sensor check that can only raise a false fault, never hide a
/// frozen image. Used to see a frozen sensor: a new frame (a fresh time
/// stamp) whose data are bit-identical to the previous frame's, which a
/// live sensor's noise makes practically impossible. Reads every value once.
[[nodiscard]] std::uint64_t reading_fingerprint(const SensorReading& reading) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_SENSOR_FRAME_HPP
