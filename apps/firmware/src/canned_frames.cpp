// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The frames blob's reader (canned_frames.hpp).
#include "cellguard/firmware/canned_frames.hpp"

#include <cstring>
#include <limits>

#include "cellguard/base/contract.hpp"
#include "cellguard/base/crc32.hpp"
#include "cellguard/prior/prior_image.hpp"

namespace cellguard::firmware {
namespace {

static_assert(std::numeric_limits<double>::is_iec559 && std::numeric_limits<float>::is_iec559,
              "the frames blob stores IEEE-754 binary64 and binary32 values");
static_assert(sizeof(float) == 4U, "depth images are read in place as binary32");

namespace L = frames_layout;

double load_double(Span<const std::uint8_t> b, std::size_t offset) noexcept {
    const std::uint64_t bits = load_le_u64(b, offset);
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
}

float load_float(Span<const std::uint8_t> b, std::size_t offset) noexcept {
    const std::uint32_t bits = load_le_u32(b, offset);
    float v = 0.0F;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
}

std::int32_t load_i32(Span<const std::uint8_t> b, std::size_t offset) noexcept {
    const std::uint32_t bits = load_le_u32(b, offset);
    return bits < 0x80000000U ? static_cast<std::int32_t>(bits)
                              : static_cast<std::int32_t>(static_cast<std::int64_t>(bits) - 0x100000000LL);
}

CannedSensor load_sensor(Span<const std::uint8_t> record) noexcept {
    CannedSensor s;
    for (std::size_t i = 0U; i < 12U; ++i) {
        s.pose[i] = load_double(record, L::kPoseOffset + 8U * i);
    }
    s.fx = load_double(record, L::kIntrinsicsOffset);
    s.fy = load_double(record, L::kIntrinsicsOffset + 8U);
    s.cx = load_double(record, L::kIntrinsicsOffset + 16U);
    s.cy = load_double(record, L::kIntrinsicsOffset + 24U);
    s.width = load_i32(record, L::kWidthOffset);
    s.height = load_i32(record, L::kHeightOffset);
    s.max_range = load_float(record, L::kMaxRangeOffset);
    return s;
}

}  // namespace

Result<CannedFrames> CannedFrames::parse(Span<const std::uint8_t> bytes, Span<const float> floats) noexcept {
    if (bytes.size() < L::kHeaderBytes + L::kCrcBytes ||
        static_cast<const void*>(floats.data()) != static_cast<const void*>(bytes.data()) ||
        floats.size() != bytes.size() / sizeof(float)) {
        return ErrorCode::kInvalidArgument;
    }
    if (std::memcmp(bytes.data(), kFramesMagic, sizeof(kFramesMagic)) != 0) {
        return ErrorCode::kBadMagic;
    }
    if (load_le_u32(bytes, L::kVersion) != kFramesFormatVersion) {
        return ErrorCode::kUnsupportedVersion;
    }
    const std::uint32_t sensors = load_le_u32(bytes, L::kSensorCount);
    const std::uint32_t scenes = load_le_u32(bytes, L::kSceneCount);
    if (load_le_u32(bytes, L::kReserved) != 0U || sensors == 0U || sensors > kMaxCannedSensors || scenes == 0U ||
        scenes > kMaxCannedScenes || load_le_u32(bytes, L::kBlobSize) != bytes.size()) {
        return ErrorCode::kMalformedInput;
    }
    const std::size_t crc_at = bytes.size() - L::kCrcBytes;
    if (crc32(bytes.subspan(0U, crc_at)) != load_le_u32(bytes, crc_at)) {
        return ErrorCode::kCrcMismatch;
    }
    const std::size_t names_at = L::kHeaderBytes + L::kSensorBytes * sensors;
    const std::size_t depth_at = names_at + L::kSceneNameBytes * scenes;
    if (depth_at > crc_at) {
        return ErrorCode::kMalformedInput;
    }
    CannedFrames f;
    f.sensor_count_ = sensors;
    f.scene_count_ = scenes;
    f.floats_ = floats;
    std::size_t pixels_per_scene = 0U;
    for (std::size_t s = 0U; s < sensors; ++s) {
        f.sensors_[s] = load_sensor(bytes.subspan(L::kHeaderBytes + L::kSensorBytes * s, L::kSensorBytes));
        const CannedSensor& c = f.sensors_[s];
        if (c.width < 1 || c.width > kMaxCannedImageSide || c.height < 1 || c.height > kMaxCannedImageSide ||
            !(c.max_range > 0.0F)) {
            return ErrorCode::kMalformedInput;
        }
        pixels_per_scene += static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
    }
    for (std::size_t i = 0U; i < scenes; ++i) {
        const Span<const std::uint8_t> name = bytes.subspan(names_at + L::kSceneNameBytes * i, L::kSceneNameBytes);
        if (name[L::kSceneNameBytes - 1U] != 0U) {
            return ErrorCode::kMalformedInput;
        }
        std::memcpy(f.names_[i], name.data(), L::kSceneNameBytes);
    }
    if (crc_at - depth_at != sizeof(float) * pixels_per_scene * scenes) {
        return ErrorCode::kMalformedInput;
    }
    std::size_t next = depth_at / sizeof(float);  // depth_at is a multiple of 8: 24 + 144 S + 32 N
    for (std::size_t i = 0U; i < scenes; ++i) {
        for (std::size_t s = 0U; s < sensors; ++s) {
            f.first_float_[i][s] = next;
            next += static_cast<std::size_t>(f.sensors_[s].width) * static_cast<std::size_t>(f.sensors_[s].height);
        }
    }
    return f;
}

const CannedSensor& CannedFrames::sensor(std::size_t s) const noexcept {
    CG_ENFORCE(s < sensor_count_, "sensor index out of range");
    return sensors_[s];
}

const char* CannedFrames::scene_name(std::size_t i) const noexcept {
    CG_ENFORCE(i < scene_count_, "scene index out of range");
    return names_[i];
}

Span<const float> CannedFrames::depth(std::size_t i, std::size_t s) const noexcept {
    CG_ENFORCE(i < scene_count_ && s < sensor_count_, "scene or sensor index out of range");
    const CannedSensor& c = sensors_[s];
    return floats_.subspan(first_float_[i][s], static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height));
}

}  // namespace cellguard::firmware
