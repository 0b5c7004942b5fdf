// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file canned_frames.hpp
/// The firmware's canned depth frames as one binary blob
/// (apps/firmware/generated/frames.bin, written by cellguard-firmware-gen,
/// embedded into .rodata by src/embedded_data.S) and its checked reader.
///
/// Format version 1, all integers little-endian; doubles and floats as their
/// IEEE-754 binary64 and binary32 bit patterns, so the targets read the
/// exact bits the host rendered.
///
/// | offset | size | field |
/// |---:|---:|---|
/// | 0 | 4 | magic: the ASCII bytes 'C' 'G' 'F' 'R' |
/// | 4 | 4 | format version, u32 = 1 |
/// | 8 | 4 | sensor count S, u32, 1 .. kMaxCannedSensors |
/// | 12 | 4 | scene count N, u32, 1 .. kMaxCannedScenes |
/// | 16 | 4 | blob size in bytes, u32, the trailing CRC included |
/// | 20 | 4 | reserved, u32 = 0 |
/// | 24 | 144 S | per sensor: pose rows (3 x 4 binary64, sensor -> workcell), fx, fy, cx, cy (binary64), width, height (i32), max range (binary32), 4 bytes zero |
/// | 24 + 144 S | 32 N | per scene: its name, ASCII, NUL-padded (at least one NUL) |
/// | 24 + 144 S + 32 N | 4 w h per image | depth images, scene-major (scene 0 sensor 0, scene 0 sensor 1, ...), row-major binary32 |
/// | size - 4 | 4 | CRC-32 (crc32.hpp) of every byte before it |
///
/// Every depth image starts at a multiple of 4 bytes from the blob's start,
/// so a little-endian target with 4-byte-aligned blobs reads them in place.
#ifndef CELLGUARD_FIRMWARE_CANNED_FRAMES_HPP
#define CELLGUARD_FIRMWARE_CANNED_FRAMES_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"

namespace cellguard::firmware {

/// Byte sizes and offsets of the frames blob (see the table above).
namespace frames_layout {
constexpr std::size_t kMagic = 0U;              ///< 4 bytes 'C' 'G' 'F' 'R'
constexpr std::size_t kVersion = 4U;            ///< u32 format version
constexpr std::size_t kSensorCount = 8U;        ///< u32 S
constexpr std::size_t kSceneCount = 12U;        ///< u32 N
constexpr std::size_t kBlobSize = 16U;          ///< u32 total size
constexpr std::size_t kReserved = 20U;          ///< u32, zero
constexpr std::size_t kHeaderBytes = 24U;       ///< first sensor record
constexpr std::size_t kSensorBytes = 144U;      ///< one sensor record
constexpr std::size_t kPoseOffset = 0U;         ///< 12 binary64 in a sensor record
constexpr std::size_t kIntrinsicsOffset = 96U;  ///< fx, fy, cx, cy binary64
constexpr std::size_t kWidthOffset = 128U;      ///< i32 width
constexpr std::size_t kHeightOffset = 132U;     ///< i32 height
constexpr std::size_t kMaxRangeOffset = 136U;   ///< binary32 max range
constexpr std::size_t kSceneNameBytes = 32U;    ///< one scene name field
constexpr std::size_t kCrcBytes = 4U;           ///< the trailing CRC-32
}  // namespace frames_layout

/// The four magic bytes at offset 0.
constexpr std::uint8_t kFramesMagic[4] = {'C', 'G', 'F', 'R'};
/// The format version this build writes and reads.
constexpr std::uint32_t kFramesFormatVersion = 1U;
/// Most sensors a blob may hold (the scenario's input array).
constexpr std::size_t kMaxCannedSensors = 4U;
/// Most scenes a blob may hold.
constexpr std::size_t kMaxCannedScenes = 8U;
/// Largest width or height of a depth image.
constexpr std::int32_t kMaxCannedImageSide = 4096;

/// A depth sensor as stored: pose rows (3 x 4, sensor -> workcell), pinhole
/// intrinsics, image size and range.
struct CannedSensor {
    double pose[12] = {};     ///< rows of the 3 x 4 pose, row-major
    double fx = 0.0;          ///< focal length x, pixels
    double fy = 0.0;          ///< focal length y, pixels
    double cx = 0.0;          ///< principal point x, pixels
    double cy = 0.0;          ///< principal point y, pixels
    std::int32_t width = 0;   ///< image width, pixels
    std::int32_t height = 0;  ///< image height, pixels
    float max_range = 0.0F;   ///< metres
};

/// A checked frames blob: the sensors and scene names decoded, the depth
/// images read in place (zero-copy).
class CannedFrames {
public:
    /// Checks @p bytes (the blob) and returns its reader. @p floats must be
    /// the same memory seen as binary32 values (same address, size / 4
    /// elements; the blob's second symbol): the depth images are spans of
    /// it. Checks, each failing with the ErrorCode named: fewer bytes than
    /// the header or the CRC, floats not the same memory (kInvalidArgument);
    /// magic (kBadMagic); version (kUnsupportedVersion); reserved field not
    /// 0, counts out of range, size field not the blob's size
    /// (kMalformedInput); the CRC (kCrcMismatch); a sensor's width or
    /// height outside 1 .. kMaxCannedImageSide, a max range not positive, a
    /// scene name without its NUL, depth bytes other than the images' sizes
    /// (kMalformedInput).
    [[nodiscard]] static Result<CannedFrames> parse(Span<const std::uint8_t> bytes, Span<const float> floats) noexcept;

    /// Number of sensors.
    [[nodiscard]] std::size_t sensor_count() const noexcept { return sensor_count_; }
    /// Number of scenes.
    [[nodiscard]] std::size_t scene_count() const noexcept { return scene_count_; }
    /// Sensor @p s (checked).
    [[nodiscard]] const CannedSensor& sensor(std::size_t s) const noexcept;
    /// Name of scene @p i (checked), NUL-terminated.
    [[nodiscard]] const char* scene_name(std::size_t i) const noexcept;
    /// Depth image of sensor @p s in scene @p i (checked): width * height values, row-major.
    [[nodiscard]] Span<const float> depth(std::size_t i, std::size_t s) const noexcept;

private:
    CannedSensor sensors_[kMaxCannedSensors] = {};
    char names_[kMaxCannedScenes][frames_layout::kSceneNameBytes] = {};
    std::size_t first_float_[kMaxCannedScenes][kMaxCannedSensors] = {};
    std::size_t sensor_count_ = 0U;
    std::size_t scene_count_ = 0U;
    Span<const float> floats_{};
};

}  // namespace cellguard::firmware

#endif  // CELLGUARD_FIRMWARE_CANNED_FRAMES_HPP
