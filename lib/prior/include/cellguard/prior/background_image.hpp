// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file background_image.hpp
/// The background view image: every depth sensor's commissioned view of the
/// empty cell, written at commissioning beside the prior image and bound to
/// it by the prior's payload CRC-32, so that at run time each live frame can
/// be compared with the view the prior was made from (background_check.hpp,
/// hazards H-PRI-3, H-SEN-3, H-SEN-11).
///
/// Format version 1, all integers little-endian, written and read byte by
/// byte (no dependence on the host's byte order or alignment); doubles and
/// floats as their IEEE-754 bit patterns. Full description:
/// certification/background-image-format.md.
///
/// File header, 32 bytes:
/// | offset | size | field                                                   |
/// |-------:|-----:|---------------------------------------------------------|
/// |      0 |    4 | magic: the ASCII bytes 'C' 'G' 'B' 'V'                  |
/// |      4 |    2 | format version, u16 = 1                                 |
/// |      6 |    2 | file header size, u16 = 32                              |
/// |      8 |    4 | sensor count, u32, 1..kMaxSensors                       |
/// |     12 |    4 | the prior image's payload CRC-32 (PriorImageHeader)     |
/// |     16 |    4 | frames the views were taken from, u32 >= 1              |
/// |     20 |    4 | statistic, u32: 1 = per-pixel median                    |
/// |     24 |    4 | reserved, u32 = 0                                       |
/// |     28 |    4 | CRC-32 of bytes 0 .. 27                                 |
///
/// Then one record per sensor, in the configuration's order: a 120-byte
/// record header, then width x height binary32 depths (metres along the
/// optical axis, row-major; 0 = no reading; never negative, NaN or infinite).
/// | offset | size | record field                                            |
/// |-------:|-----:|---------------------------------------------------------|
/// |      0 |    4 | CRC-32 of the sensor's name (its UTF-8 bytes)           |
/// |      4 |    4 | width, u32, >= 1                                        |
/// |      8 |    4 | height, u32, >= 1                                       |
/// |     12 |    4 | view kind, u32: 0 depth image, 1 direction grid         |
/// |     16 |   24 | position x, y, z, metres, binary64                      |
/// |     40 |   32 | rotation sensor -> cell, quaternion w, x, y, z, binary64 |
/// |     72 |   32 | intrinsics fx, fy, cx, cy, pixels, binary64             |
/// |    104 |    4 | payload length, u32 = 4 (kind 1: 8) x width x height    |
/// |    108 |    4 | CRC-32 of the payload                                   |
/// |    112 |    4 | reserved, u32 = 0                                       |
/// |    116 |    4 | CRC-32 of record bytes 0 .. 115                         |
/// The image ends with the last record's payload (no trailing bytes).
///
/// View kind 1, a point-set sensor's direction grid (direction_grid.hpp):
/// width = azimuth bins, height = elevation bins (at most
/// kMaxDirectionBins), the intrinsics fields hold azimuth_min_rad,
/// elevation_min_rad and bin_rad (binary32 values stored as binary64, a
/// valid grid) and 0; the payload is width x height farthest ranges, then
/// width x height nearest ranges (metres, per bin; 0 = no return, in both
/// or in neither; nearest <= farthest), the extremes of all the
/// commissioning frames' points (the header's statistic names the depth
/// images' median).
#ifndef CELLGUARD_BACKGROUND_IMAGE_HPP
#define CELLGUARD_BACKGROUND_IMAGE_HPP

#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/direction_grid.hpp"

namespace cellguard {

static_assert(std::numeric_limits<float>::is_iec559, "the background image stores IEEE-754 binary32 depths");

/// The four magic bytes at offset 0.
constexpr std::uint8_t kBackgroundImageMagic[4] = {'C', 'G', 'B', 'V'};
/// The format version this build writes and reads.
constexpr std::uint16_t kBackgroundImageFormatVersion = 1U;
/// File header size, bytes.
constexpr std::size_t kBackgroundImageHeaderSize = 32U;
/// Record header size, bytes.
constexpr std::size_t kBackgroundRecordHeaderSize = 120U;
/// The statistic this build writes: the per-pixel median of the frames.
constexpr std::uint32_t kBackgroundStatisticMedian = 1U;
/// View kind of a depth-image sensor's record: a depth per pixel.
constexpr std::uint32_t kBackgroundViewDepthImage = 0U;
/// View kind of a point-set sensor's record: farthest and nearest range per direction bin.
constexpr std::uint32_t kBackgroundViewDirectionGrid = 1U;
/// Most sensors one image holds (the controller's kMaxSensors).
constexpr std::uint32_t kBackgroundImageMaxSensors = 8U;

/// Who a view belongs to: compared bit for bit with the configuration's
/// sensor at load, so a view of another sensor, resolution, pose or
/// calibration is refused.
struct BackgroundSensorIdentity {
    std::uint32_t name_crc = 0U;                     ///< crc32 of the sensor's name
    std::uint32_t kind = kBackgroundViewDepthImage;  ///< kBackgroundViewDepthImage or kBackgroundViewDirectionGrid
    std::uint32_t width = 0U;                        ///< pixels per row (direction grid: azimuth bins)
    std::uint32_t height = 0U;                       ///< rows (direction grid: elevation bins)
    double position[3] = {0.0, 0.0, 0.0};            ///< metres, in the cell
    double rotation[4] = {1.0, 0.0, 0.0, 0.0};       ///< sensor -> cell quaternion w, x, y, z
    double intrinsics[4] = {0.0, 0.0, 0.0, 0.0};     ///< fx, fy, cx, cy, pixels (direction grid: see the file comment)
};

/// The identity of a point-set sensor's direction-grid view: kind 1,
/// @p grid's bins and edges in width, height and intrinsics; the name and
/// pose are left as in @p id.
[[nodiscard]] BackgroundSensorIdentity with_direction_grid(BackgroundSensorIdentity id,
                                                           const DirectionGrid& grid) noexcept;

/// The direction grid a kind-1 identity describes (meaningless for kind 0).
[[nodiscard]] DirectionGrid direction_grid_of(const BackgroundSensorIdentity& id) noexcept;

/// Floats in the payload of a view of @p id: width x height, twice for a
/// direction grid (farthest, then nearest); 0 for an unknown kind.
[[nodiscard]] std::size_t background_view_values(const BackgroundSensorIdentity& id) noexcept;

/// One sensor's view to write: who, and its background_view_values() values.
struct BackgroundViewRecord {
    BackgroundSensorIdentity identity{};  ///< the sensor
    Span<const float> depth{};            ///< row-major metres; 0 = no reading (grid: farthest, then nearest)
};

/// Why an image was refused. Values are stable (they appear in logs): append only.
enum class BackgroundImageError : std::uint8_t {
    kNone = 0,                     ///< accepted
    kTooShort = 1,                 ///< fewer bytes than the file header
    kBadMagic = 2,                 ///< not 'C' 'G' 'B' 'V'
    kUnsupportedVersion = 3,       ///< format version other than 1
    kBadHeader = 4,                ///< header size, reserved or statistic field wrong, or 0 frames
    kHeaderCrcMismatch = 5,        ///< file header CRC differs
    kSensorCountMismatch = 6,      ///< sensor count 0, above the maximum, or not the configuration's
    kPriorCrcMismatch = 7,         ///< made for another prior image
    kRecordTruncated = 8,          ///< input ends inside a record header or payload
    kRecordHeaderCrcMismatch = 9,  ///< a record header's CRC differs
    kBadRecord = 10,               ///< zero size, wrong payload length, reserved not 0, unknown kind, bad grid
    kPayloadCrcMismatch = 11,      ///< a record's payload CRC differs
    kDepthOutOfRange =
        12,               ///< a depth negative, NaN or infinite; a grid bin's nearest above its farthest or only one 0
    kTrailingBytes = 13,  ///< bytes after the last record
    kWrongSensor = 14,    ///< a record's name, size, pose or intrinsics differ from the configuration's
    kStorageTooSmall = 15,  ///< the caller's depth storage is smaller than the view
};

/// A short, static, human-readable description (never nullptr).
[[nodiscard]] const char* to_string(BackgroundImageError error) noexcept;
/// True for kNone: what Result<T, BackgroundImageError> asks of its error type.
[[nodiscard]] constexpr bool is_no_error(BackgroundImageError error) noexcept {
    return error == BackgroundImageError::kNone;
}

/// What the file header says, once checked.
struct BackgroundImageInfo {
    std::uint32_t sensor_count = 0U;  ///< records in the image
    std::uint32_t prior_crc = 0U;     ///< the prior image's payload CRC-32
    std::uint32_t frames = 0U;        ///< frames the views were taken from
};

/// Bytes of the image of @p views (header, records, payloads); 0 when a
/// size would overflow.
[[nodiscard]] std::size_t background_image_size(Span<const BackgroundViewRecord> views) noexcept;

/// Serialises @p views (1..kBackgroundImageMaxSensors, each with
/// width x height finite, non-negative depths) for the prior whose payload
/// CRC-32 is @p prior_crc, taken from @p frames frames, into @p out; returns
/// the bytes written. Nothing is promised of @p out on failure. Errors:
/// kInvalidArgument (no views or too many, bad sizes, a bad depth, 0
/// frames), kStorageTooSmall.
[[nodiscard]] Result<std::size_t> write_background_image(Span<const BackgroundViewRecord> views,
                                                         std::uint32_t prior_crc, std::uint32_t frames,
                                                         Span<std::uint8_t> out) noexcept;

/// Start-up check of a whole image: the file header (size, magic, version,
/// header fields, header CRC), its sensor count against @p expected_sensors
/// and its prior CRC against @p prior_crc, then every record (header CRC,
/// fields, payload length within the input, payload CRC, every depth
/// finite and >= 0) and no trailing bytes. Never reads outside @p image.
[[nodiscard]] Result<BackgroundImageInfo, BackgroundImageError> check_background_image(
    Span<const std::uint8_t> image, std::uint32_t expected_sensors, std::uint32_t prior_crc) noexcept;

/// Copies the view of record @p index of an image that passed
/// check_background_image into @p out (at least width x height floats),
/// after comparing the record's identity with @p expected bit for bit
/// (kWrongSensor otherwise); returns the number of depths written. Checks
/// the whole image again first (same arguments as check_background_image,
/// with index < sensor count).
[[nodiscard]] Result<std::size_t, BackgroundImageError> load_background_view(
    Span<const std::uint8_t> image, std::uint32_t expected_sensors, std::uint32_t prior_crc, std::uint32_t index,
    const BackgroundSensorIdentity& expected, Span<float> out) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_BACKGROUND_IMAGE_HPP
