// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/prior/background_image.hpp"

#include <cmath>
#include <cstring>

#include "cellguard/base/crc32.hpp"
#include "cellguard/prior/prior_image.hpp"

namespace cellguard {

namespace {

// File header fields (background_image.hpp).
constexpr std::size_t kVersionAt = 4U;
constexpr std::size_t kHeaderSizeAt = 6U;
constexpr std::size_t kCountAt = 8U;
constexpr std::size_t kPriorCrcAt = 12U;
constexpr std::size_t kFramesAt = 16U;
constexpr std::size_t kStatisticAt = 20U;
constexpr std::size_t kReservedAt = 24U;
constexpr std::size_t kHeaderCrcAt = 28U;
// Record header fields.
constexpr std::size_t kNameCrcAt = 0U;
constexpr std::size_t kWidthAt = 4U;
constexpr std::size_t kHeightAt = 8U;
constexpr std::size_t kKindAt = 12U;
constexpr std::size_t kPositionAt = 16U;
constexpr std::size_t kRotationAt = 40U;
constexpr std::size_t kIntrinsicsAt = 72U;
constexpr std::size_t kPayloadLengthAt = 104U;
constexpr std::size_t kPayloadCrcAt = 108U;
constexpr std::size_t kRecordReserved2At = 112U;
constexpr std::size_t kRecordCrcAt = 116U;
static_assert(kRecordCrcAt + 4U == kBackgroundRecordHeaderSize, "the record CRC is the record header's last field");
static_assert(kHeaderCrcAt + 4U == kBackgroundImageHeaderSize, "the header CRC is the file header's last field");

void store_le(Span<std::uint8_t> out, std::size_t offset, std::uint64_t value, std::size_t bytes) noexcept {
    for (std::size_t i = 0U; i < bytes; ++i) {
        out.at(offset + i) = static_cast<std::uint8_t>((value >> (8U * i)) & 0xFFU);
    }
}

std::uint64_t bits_of(double d) noexcept {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &d, sizeof bits);
    return bits;
}

float float_of(std::uint32_t bits) noexcept {
    float f = 0.0F;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

std::uint32_t bits_of(float f) noexcept {
    std::uint32_t bits = 0U;
    std::memcpy(&bits, &f, sizeof bits);
    return bits;
}

bool depth_ok(float d) noexcept { return std::isfinite(d) && d >= 0.0F; }

/// Payload bytes of a width x height view of @p kind; 0 when it overflows,
/// is empty or the kind is unknown.
std::size_t payload_bytes(std::uint32_t kind, std::uint64_t width, std::uint64_t height) noexcept {
    if (width == 0U || height == 0U || width > 0xFFFFU || height > 0xFFFFU || kind > kBackgroundViewDirectionGrid) {
        return 0U;
    }
    const std::uint64_t per_value = kind == kBackgroundViewDirectionGrid ? 8U : 4U;
    const std::uint64_t bytes = per_value * width * height;  // < 2^35: no overflow
    return bytes > 0xFFFFFFFFU || bytes > SIZE_MAX ? 0U : static_cast<std::size_t>(bytes);
}

/// True when a kind-1 identity's intrinsics hold a valid direction grid:
/// binary32 values stored exactly, the fourth 0, check_direction_grid passes.
bool grid_ok(const BackgroundSensorIdentity& id) noexcept {
    const DirectionGrid g = direction_grid_of(id);
    return static_cast<double>(g.azimuth_min_rad) == id.intrinsics[0] &&
           static_cast<double>(g.elevation_min_rad) == id.intrinsics[1] &&
           static_cast<double>(g.bin_rad) == id.intrinsics[2] && id.intrinsics[3] == 0.0 &&
           check_direction_grid(g).ok();
}

/// The grid of @p id is writable or readable: a direction grid's is valid, the
/// other kinds have none. The callers check the size (payload_bytes) first.
bool grid_layout_ok(const BackgroundSensorIdentity& id) noexcept {
    return id.kind != kBackgroundViewDirectionGrid || grid_ok(id);
}

/// The values of a view of @p kind are valid: each finite and >= 0, and
/// for a direction grid per bin nearest <= farthest, 0 in both or neither.
template <typename Value>
bool values_ok(std::uint32_t kind, std::size_t count, const Value& value) noexcept {
    for (std::size_t i = 0U; i < count; ++i) {
        if (!depth_ok(value(i))) {
            return false;
        }
    }
    if (kind != kBackgroundViewDirectionGrid) {
        return true;
    }
    const std::size_t bins = count / 2U;
    for (std::size_t i = 0U; i < bins; ++i) {
        const float far = value(i);
        const float near = value(bins + i);
        if (near > far || (far == 0.0F) != (near == 0.0F)) {
            return false;
        }
    }
    return true;
}

void write_record(const BackgroundViewRecord& v, Span<std::uint8_t> rec) noexcept {
    const BackgroundSensorIdentity& id = v.identity;
    store_le(rec, kNameCrcAt, id.name_crc, 4U);
    store_le(rec, kWidthAt, id.width, 4U);
    store_le(rec, kHeightAt, id.height, 4U);
    store_le(rec, kKindAt, id.kind, 4U);
    for (std::size_t i = 0U; i < 3U; ++i) {
        store_le(rec, kPositionAt + 8U * i, bits_of(id.position[i]), 8U);
    }
    for (std::size_t i = 0U; i < 4U; ++i) {
        store_le(rec, kRotationAt + 8U * i, bits_of(id.rotation[i]), 8U);
        store_le(rec, kIntrinsicsAt + 8U * i, bits_of(id.intrinsics[i]), 8U);
    }
    const Span<std::uint8_t> payload = rec.subspan(kBackgroundRecordHeaderSize, 4U * v.depth.size());
    for (std::size_t i = 0U; i < v.depth.size(); ++i) {
        store_le(payload, 4U * i, bits_of(v.depth[i]), 4U);
    }
    store_le(rec, kPayloadLengthAt, payload.size(), 4U);
    store_le(rec, kPayloadCrcAt, crc32(Span<const std::uint8_t>(payload.data(), payload.size())), 4U);
    store_le(rec, kRecordReserved2At, 0U, 4U);
    store_le(rec, kRecordCrcAt, crc32(Span<const std::uint8_t>(rec.data(), kRecordCrcAt)), 4U);
}

BackgroundSensorIdentity read_identity(Span<const std::uint8_t> rec) noexcept {
    BackgroundSensorIdentity id;
    id.name_crc = load_le_u32(rec, kNameCrcAt);
    id.kind = load_le_u32(rec, kKindAt);
    id.width = load_le_u32(rec, kWidthAt);
    id.height = load_le_u32(rec, kHeightAt);
    for (std::size_t i = 0U; i < 3U; ++i) {
        const std::uint64_t b = load_le_u64(rec, kPositionAt + 8U * i);
        std::memcpy(&id.position[i], &b, sizeof b);
    }
    for (std::size_t i = 0U; i < 4U; ++i) {
        const std::uint64_t r = load_le_u64(rec, kRotationAt + 8U * i);
        std::memcpy(&id.rotation[i], &r, sizeof r);
        const std::uint64_t k = load_le_u64(rec, kIntrinsicsAt + 8U * i);
        std::memcpy(&id.intrinsics[i], &k, sizeof k);
    }
    return id;
}

/// Bit-for-bit equality of two identities (a NaN equals only its own bits).
bool same_identity(const BackgroundSensorIdentity& a, const BackgroundSensorIdentity& b) noexcept {
    bool same = a.name_crc == b.name_crc && a.kind == b.kind && a.width == b.width && a.height == b.height;
    for (std::size_t i = 0U; i < 3U; ++i) {
        same = same && bits_of(a.position[i]) == bits_of(b.position[i]);
    }
    for (std::size_t i = 0U; i < 4U; ++i) {
        same = same && bits_of(a.rotation[i]) == bits_of(b.rotation[i]) &&
               bits_of(a.intrinsics[i]) == bits_of(b.intrinsics[i]);
    }
    return same;
}

/// Checks the record starting at @p at; on success @p next is where the next one starts.
BackgroundImageError check_record(Span<const std::uint8_t> image, std::size_t at, std::size_t& next) noexcept {
    if (image.size() - at < kBackgroundRecordHeaderSize) {
        return BackgroundImageError::kRecordTruncated;
    }
    const Span<const std::uint8_t> rec = image.subspan(at, kBackgroundRecordHeaderSize);
    if (crc32(rec.subspan(0U, kRecordCrcAt)) != load_le_u32(rec, kRecordCrcAt)) {
        return BackgroundImageError::kRecordHeaderCrcMismatch;
    }
    const BackgroundSensorIdentity id = read_identity(rec);
    const std::size_t length = payload_bytes(id.kind, id.width, id.height);
    if (length == 0U || !grid_layout_ok(id) || load_le_u32(rec, kPayloadLengthAt) != length ||
        load_le_u32(rec, kRecordReserved2At) != 0U) {
        return BackgroundImageError::kBadRecord;
    }
    const std::size_t start = at + kBackgroundRecordHeaderSize;
    if (image.size() - start < length) {
        return BackgroundImageError::kRecordTruncated;
    }
    const Span<const std::uint8_t> payload = image.subspan(start, length);
    if (crc32(payload) != load_le_u32(rec, kPayloadCrcAt)) {
        return BackgroundImageError::kPayloadCrcMismatch;
    }
    if (!values_ok(id.kind, length / 4U,
                   [&payload](std::size_t i) { return float_of(load_le_u32(payload, 4U * i)); })) {
        return BackgroundImageError::kDepthOutOfRange;
    }
    next = start + length;
    return BackgroundImageError::kNone;
}

BackgroundImageError check_file_header(Span<const std::uint8_t> image, std::uint32_t expected_sensors,
                                       std::uint32_t prior_crc) noexcept {
    if (image.size() < kBackgroundImageHeaderSize) {
        return BackgroundImageError::kTooShort;
    }
    for (std::size_t i = 0U; i < sizeof kBackgroundImageMagic; ++i) {
        if (image[i] != kBackgroundImageMagic[i]) {
            return BackgroundImageError::kBadMagic;
        }
    }
    if (load_le_u16(image, kVersionAt) != kBackgroundImageFormatVersion) {
        return BackgroundImageError::kUnsupportedVersion;
    }
    if (crc32(image.subspan(0U, kHeaderCrcAt)) != load_le_u32(image, kHeaderCrcAt)) {
        return BackgroundImageError::kHeaderCrcMismatch;
    }
    if (load_le_u16(image, kHeaderSizeAt) != kBackgroundImageHeaderSize || load_le_u32(image, kFramesAt) == 0U ||
        load_le_u32(image, kStatisticAt) != kBackgroundStatisticMedian || load_le_u32(image, kReservedAt) != 0U) {
        return BackgroundImageError::kBadHeader;
    }
    const std::uint32_t count = load_le_u32(image, kCountAt);
    if (count == 0U || count > kBackgroundImageMaxSensors || count != expected_sensors) {
        return BackgroundImageError::kSensorCountMismatch;
    }
    if (load_le_u32(image, kPriorCrcAt) != prior_crc) {
        return BackgroundImageError::kPriorCrcMismatch;
    }
    return BackgroundImageError::kNone;
}

}  // namespace

BackgroundSensorIdentity with_direction_grid(BackgroundSensorIdentity id, const DirectionGrid& grid) noexcept {
    id.kind = kBackgroundViewDirectionGrid;
    id.width = grid.azimuth_bins;
    id.height = grid.elevation_bins;
    id.intrinsics[0] = static_cast<double>(grid.azimuth_min_rad);
    id.intrinsics[1] = static_cast<double>(grid.elevation_min_rad);
    id.intrinsics[2] = static_cast<double>(grid.bin_rad);
    id.intrinsics[3] = 0.0;
    return id;
}

DirectionGrid direction_grid_of(const BackgroundSensorIdentity& id) noexcept {
    DirectionGrid g;
    g.azimuth_min_rad = static_cast<float>(id.intrinsics[0]);
    g.elevation_min_rad = static_cast<float>(id.intrinsics[1]);
    g.bin_rad = static_cast<float>(id.intrinsics[2]);
    g.azimuth_bins = id.width;
    g.elevation_bins = id.height;
    return g;
}

std::size_t background_view_values(const BackgroundSensorIdentity& id) noexcept {
    return payload_bytes(id.kind, id.width, id.height) / 4U;
}

const char* to_string(BackgroundImageError error) noexcept {
    switch (error) {
        case BackgroundImageError::kNone: return "background image accepted";
        case BackgroundImageError::kTooShort: return "background image shorter than its header";
        case BackgroundImageError::kBadMagic: return "background image magic is not CGBV";
        case BackgroundImageError::kUnsupportedVersion: return "background image format version not supported";
        case BackgroundImageError::kBadHeader: return "background image header field is wrong";
        case BackgroundImageError::kHeaderCrcMismatch: return "background image header CRC mismatch";
        case BackgroundImageError::kSensorCountMismatch:
            return "background image holds another number of sensors than the configuration";
        case BackgroundImageError::kPriorCrcMismatch:
            return "background image was made for another prior (prior payload CRC differs)";
        case BackgroundImageError::kRecordTruncated: return "background image sensor record truncated";
        case BackgroundImageError::kRecordHeaderCrcMismatch:
            return "background image sensor record header CRC mismatch";
        case BackgroundImageError::kBadRecord: return "background image sensor record field is wrong";
        case BackgroundImageError::kPayloadCrcMismatch: return "background image sensor depths CRC mismatch";
        case BackgroundImageError::kDepthOutOfRange: return "background image depth negative, NaN or infinite";
        case BackgroundImageError::kTrailingBytes: return "background image has bytes after its last record";
        case BackgroundImageError::kWrongSensor:
            return "background view is of another sensor (name, resolution, pose or intrinsics differ)";
        case BackgroundImageError::kStorageTooSmall: return "background view does not fit the storage given";
    }
    return "unknown background image error";
}

std::size_t background_image_size(Span<const BackgroundViewRecord> views) noexcept {
    std::size_t size = kBackgroundImageHeaderSize;
    for (const BackgroundViewRecord& v : views) {
        const std::size_t payload = payload_bytes(v.identity.kind, v.identity.width, v.identity.height);
        if (payload == 0U || size > SIZE_MAX - kBackgroundRecordHeaderSize - payload) {
            return 0U;
        }
        size += kBackgroundRecordHeaderSize + payload;
    }
    return size;
}

Result<std::size_t> write_background_image(Span<const BackgroundViewRecord> views, std::uint32_t prior_crc,
                                           std::uint32_t frames, Span<std::uint8_t> out) noexcept {
    if (views.empty() || views.size() > kBackgroundImageMaxSensors || frames == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    for (const BackgroundViewRecord& v : views) {
        const std::size_t payload = payload_bytes(v.identity.kind, v.identity.width, v.identity.height);
        if (payload == 0U || !grid_layout_ok(v.identity) || v.depth.size() != payload / 4U ||
            !values_ok(v.identity.kind, v.depth.size(), [&v](std::size_t i) { return v.depth[i]; })) {
            return ErrorCode::kInvalidArgument;
        }
    }
    const std::size_t size = background_image_size(views);
    if (size == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (out.size() < size) {
        return ErrorCode::kStorageTooSmall;
    }
    for (std::size_t i = 0U; i < sizeof kBackgroundImageMagic; ++i) {
        out[i] = kBackgroundImageMagic[i];
    }
    store_le(out, kVersionAt, kBackgroundImageFormatVersion, 2U);
    store_le(out, kHeaderSizeAt, kBackgroundImageHeaderSize, 2U);
    store_le(out, kCountAt, views.size(), 4U);
    store_le(out, kPriorCrcAt, prior_crc, 4U);
    store_le(out, kFramesAt, frames, 4U);
    store_le(out, kStatisticAt, kBackgroundStatisticMedian, 4U);
    store_le(out, kReservedAt, 0U, 4U);
    store_le(out, kHeaderCrcAt, crc32(Span<const std::uint8_t>(out.data(), kHeaderCrcAt)), 4U);
    std::size_t at = kBackgroundImageHeaderSize;
    for (const BackgroundViewRecord& v : views) {
        const std::size_t length = kBackgroundRecordHeaderSize + 4U * v.depth.size();
        write_record(v, out.subspan(at, length));
        at += length;
    }
    return at;
}

Result<BackgroundImageInfo, BackgroundImageError> check_background_image(Span<const std::uint8_t> image,
                                                                         std::uint32_t expected_sensors,
                                                                         std::uint32_t prior_crc) noexcept {
    const BackgroundImageError header = check_file_header(image, expected_sensors, prior_crc);
    if (header != BackgroundImageError::kNone) {
        return header;
    }
    BackgroundImageInfo info;
    info.sensor_count = load_le_u32(image, kCountAt);
    info.prior_crc = load_le_u32(image, kPriorCrcAt);
    info.frames = load_le_u32(image, kFramesAt);
    std::size_t at = kBackgroundImageHeaderSize;
    for (std::uint32_t s = 0U; s < info.sensor_count; ++s) {
        const BackgroundImageError e = check_record(image, at, at);
        if (e != BackgroundImageError::kNone) {
            return e;
        }
    }
    if (at != image.size()) {
        return BackgroundImageError::kTrailingBytes;
    }
    return info;
}

Result<std::size_t, BackgroundImageError> load_background_view(Span<const std::uint8_t> image,
                                                               std::uint32_t expected_sensors, std::uint32_t prior_crc,
                                                               std::uint32_t index,
                                                               const BackgroundSensorIdentity& expected,
                                                               Span<float> out) noexcept {
    const Result<BackgroundImageInfo, BackgroundImageError> info = check_background_image(image, expected_sensors,
                                                                                          prior_crc);
    if (!info.ok()) {
        return info.error();
    }
    if (index >= info.value().sensor_count) {
        return BackgroundImageError::kSensorCountMismatch;
    }
    std::size_t at = kBackgroundImageHeaderSize;
    for (std::uint32_t s = 0U; s < index; ++s) {
        at += kBackgroundRecordHeaderSize + load_le_u32(image, at + kPayloadLengthAt);  // checked above
    }
    const Span<const std::uint8_t> rec = image.subspan(at, kBackgroundRecordHeaderSize);
    if (!same_identity(read_identity(rec), expected)) {
        return BackgroundImageError::kWrongSensor;
    }
    const std::size_t n = load_le_u32(rec, kPayloadLengthAt) / 4U;
    if (out.size() < n) {
        return BackgroundImageError::kStorageTooSmall;
    }
    const Span<const std::uint8_t> payload = image.subspan(at + kBackgroundRecordHeaderSize, 4U * n);
    for (std::size_t i = 0U; i < n; ++i) {
        out[i] = float_of(load_le_u32(payload, 4U * i));
    }
    return n;
}

}  // namespace cellguard
