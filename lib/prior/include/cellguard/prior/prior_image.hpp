// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file prior_image.hpp
/// The prior image: the accessibility prior (int16 log-odds of P(fore), one
/// per voxel, kNeverForeground for "never foreground") as a checked,
/// versioned byte string, written on the commissioning host and loaded by the
/// controller, from a file (port/linux) or from flash (generated source).
///
/// Format version 1, all integers little-endian, written and read byte by
/// byte (no dependence on the host's byte order or alignment). Doubles are
/// stored as their IEEE-754 binary64 bit patterns, so equality is exact.
/// Full description: certification/prior-image-format.md.
///
/// | offset | size | field                                                  |
/// |-------:|-----:|--------------------------------------------------------|
/// |      0 |    4 | magic: the ASCII bytes 'C' 'G' 'P' 'I'                 |
/// |      4 |    2 | format version, u16 = 1                                |
/// |      6 |    2 | header size in bytes, u16 = 88                         |
/// |      8 |    4 | nx, u32                                                |
/// |     12 |    4 | ny, u32                                                |
/// |     16 |    4 | nz, u32                                                |
/// |     20 |    1 | method, u8 (PriorMethod: 1..4)                         |
/// |     21 |    1 | open faces, u8 (GridFace bits, within kAllFaces)       |
/// |     22 |    2 | reserved, u16 = 0                                      |
/// |     24 |    8 | voxel size, metres, binary64 bits                      |
/// |     32 |    8 | origin x, metres, binary64 bits                        |
/// |     40 |    8 | origin y, metres, binary64 bits                        |
/// |     48 |    8 | origin z, metres, binary64 bits                        |
/// |     56 |    8 | t_B, binary64 bits, in [0, 1]                          |
/// |     64 |    8 | t_E, binary64 bits, in [0, 1]                          |
/// |     72 |    4 | r, voxels, i32 two's complement, in [0, kMaxDimension] |
/// |     76 |    4 | payload length in bytes, u32 = 2 * nx * ny * nz       |
/// |     80 |    4 | CRC-32 of the payload (bytes 88 .. end)                |
/// |     84 |    4 | CRC-32 of the header bytes 0 .. 83                     |
/// |     88 |  2 n | payload: n int16 values, linear index order            |
///
/// Every payload value is <= 0: P(fore) = P(acc) / 2 <= 0.5 for every
/// method (eq. 6), and log-odds(0.5) = 0. The writer refuses, and the loader
/// rejects, a positive value.
#ifndef CELLGUARD_PRIOR_IMAGE_HPP
#define CELLGUARD_PRIOR_IMAGE_HPP

#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/prior/accessibility_params.hpp"

namespace cellguard {

static_assert(std::numeric_limits<double>::is_iec559, "the prior image stores IEEE-754 binary64 doubles");

/// Byte offsets of the fields of a version-1 header (see the table above).
namespace prior_image_layout {
constexpr std::size_t kMagic = 0U;           ///< 4 bytes 'C' 'G' 'P' 'I'
constexpr std::size_t kVersion = 4U;         ///< u16 format version
constexpr std::size_t kHeaderSize = 6U;      ///< u16 header size
constexpr std::size_t kNx = 8U;              ///< u32 voxels along x
constexpr std::size_t kNy = 12U;             ///< u32 voxels along y
constexpr std::size_t kNz = 16U;             ///< u32 voxels along z
constexpr std::size_t kMethod = 20U;         ///< u8 PriorMethod
constexpr std::size_t kOpenFaces = 21U;      ///< u8 GridFace bits
constexpr std::size_t kReserved = 22U;       ///< u16, zero
constexpr std::size_t kVoxelSize = 24U;      ///< binary64 voxel size
constexpr std::size_t kOriginX = 32U;        ///< binary64 origin x
constexpr std::size_t kOriginY = 40U;        ///< binary64 origin y
constexpr std::size_t kOriginZ = 48U;        ///< binary64 origin z
constexpr std::size_t kTb = 56U;             ///< binary64 t_B
constexpr std::size_t kTe = 64U;             ///< binary64 t_E
constexpr std::size_t kRadius = 72U;         ///< i32 r in voxels
constexpr std::size_t kPayloadLength = 76U;  ///< u32 payload bytes
constexpr std::size_t kPayloadCrc = 80U;     ///< u32 CRC-32 of the payload
constexpr std::size_t kHeaderCrc = 84U;      ///< u32 CRC-32 of bytes [0, kHeaderCrc)
constexpr std::size_t kPayload = 88U;        ///< first payload byte
}  // namespace prior_image_layout

/// The four magic bytes at offset 0.
constexpr std::uint8_t kPriorImageMagic[4] = {'C', 'G', 'P', 'I'};
/// The format version this build writes and reads.
constexpr std::uint16_t kPriorImageFormatVersion = 1U;
/// Header size of format version 1, bytes.
constexpr std::size_t kPriorImageHeaderSize = prior_image_layout::kPayload;
/// Bytes per payload value.
constexpr std::size_t kPriorImageBytesPerVoxel = 2U;

/// Size in bytes of the image of a grid of @p voxels voxels: header plus two
/// bytes per voxel. Saturates at SIZE_MAX instead of wrapping.
constexpr std::size_t prior_image_size(std::size_t voxels) noexcept {
    constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
    return voxels > (kMax - kPriorImageHeaderSize) / kPriorImageBytesPerVoxel
               ? kMax
               : kPriorImageHeaderSize + kPriorImageBytesPerVoxel * voxels;
}

/// Little-endian u16 at @p offset of @p bytes (range checked always).
constexpr std::uint16_t load_le_u16(Span<const std::uint8_t> bytes, std::size_t offset) noexcept {
    return static_cast<std::uint16_t>(static_cast<std::uint32_t>(bytes.at(offset)) |
                                      (static_cast<std::uint32_t>(bytes.at(offset + 1U)) << 8U));
}
/// Little-endian u32 at @p offset of @p bytes (range checked always).
constexpr std::uint32_t load_le_u32(Span<const std::uint8_t> bytes, std::size_t offset) noexcept {
    return static_cast<std::uint32_t>(load_le_u16(bytes, offset)) |
           (static_cast<std::uint32_t>(load_le_u16(bytes, offset + 2U)) << 16U);
}
/// Little-endian u64 at @p offset of @p bytes (range checked always).
constexpr std::uint64_t load_le_u64(Span<const std::uint8_t> bytes, std::size_t offset) noexcept {
    return static_cast<std::uint64_t>(load_le_u32(bytes, offset)) |
           (static_cast<std::uint64_t>(load_le_u32(bytes, offset + 4U)) << 32U);
}
/// The int16 whose two's complement bit pattern is @p bits (no
/// implementation-defined narrowing).
constexpr std::int16_t int16_from_bits(std::uint16_t bits) noexcept {
    return bits < 0x8000U ? static_cast<std::int16_t>(bits)
                          : static_cast<std::int16_t>(static_cast<std::int32_t>(bits) - 65536);
}

/// Why an image was refused; finer than ErrorCode (see to_error_code).
/// Values are stable (they appear in logs): append only.
enum class PriorImageError : std::uint8_t {
    kNone = 0,                    ///< accepted
    kTooShort = 1,                ///< fewer bytes than the header (kTruncatedInput)
    kBadMagic = 2,                ///< first four bytes are not 'C' 'G' 'P' 'I' (kBadMagic)
    kUnsupportedVersion = 3,      ///< format version other than 1 (kUnsupportedVersion)
    kBadHeaderSize = 4,           ///< header size field other than 88 (kMalformedInput)
    kHeaderCrcMismatch = 5,       ///< CRC of bytes 0..83 differs from the stored one (kCrcMismatch)
    kReservedNotZero = 6,         ///< the reserved u16 at offset 22 is not 0 (kMalformedInput)
    kDimsMismatch = 7,            ///< nx, ny or nz differs from the expected grid (kGeometryMismatch)
    kVoxelSizeMismatch = 8,       ///< voxel size bits differ from the expected grid (kGeometryMismatch)
    kOriginMismatch = 9,          ///< an origin coordinate's bits differ (kGeometryMismatch)
    kUnknownMethod = 10,          ///< method byte is not a PriorMethod (kUnsupportedType)
    kParameterOutOfRange = 11,    ///< t_B, t_E, r or open faces out of range (kMalformedInput)
    kPayloadLengthMismatch = 12,  ///< payload length field is not 2 * voxels (kMalformedInput)
    kPayloadTruncated = 13,       ///< input ends before the payload does (kTruncatedInput)
    kTrailingBytes = 14,          ///< bytes after the payload (kMalformedInput)
    kPayloadCrcMismatch = 15,     ///< CRC of the payload differs from the stored one (kCrcMismatch)
    kPriorValueOutOfRange = 16,   ///< a payload value > 0, i.e. P(fore) > 0.5 (kMalformedInput)
    kNoExpectedGeometry = 17,     ///< the expected geometry is empty (kInvalidArgument)
};

/// The ErrorCode a refusal maps to (kOk for kNone).
[[nodiscard]] ErrorCode to_error_code(PriorImageError error) noexcept;
/// A short, static, human-readable description (never nullptr).
[[nodiscard]] const char* to_string(PriorImageError error) noexcept;
/// True for kNone: what Result<T, PriorImageError> asks of its error type.
[[nodiscard]] constexpr bool is_no_error(PriorImageError error) noexcept { return error == PriorImageError::kNone; }

/// True when @p method is one of the PriorMethod values this build knows.
[[nodiscard]] bool is_known_prior_method(std::uint8_t method) noexcept;
/// True when the method is known and t_B, t_E in [0, 1] (NaN fails), r in
/// [0, kMaxAccessibilityRadius] and open_faces within kAllFaces.
[[nodiscard]] bool prior_params_in_range(const AccessibilityParams& params) noexcept;

/// The fields of a version-1 header as stored, before they are compared
/// with a grid. Doubles are kept as bit patterns; accessors convert them.
struct PriorImageHeader {
    std::uint16_t format_version = 0U;            ///< offset 4
    std::uint16_t header_size = 0U;               ///< offset 6
    std::uint32_t nx = 0U;                        ///< offset 8
    std::uint32_t ny = 0U;                        ///< offset 12
    std::uint32_t nz = 0U;                        ///< offset 16
    std::uint8_t method = 0U;                     ///< offset 20, raw PriorMethod value
    std::uint8_t open_faces = 0U;                 ///< offset 21
    std::uint16_t reserved = 0U;                  ///< offset 22
    std::uint64_t voxel_size_bits = 0U;           ///< offset 24
    std::uint64_t origin_bits[3] = {0U, 0U, 0U};  ///< offsets 32, 40, 48 (x, y, z)
    std::uint64_t t_b_bits = 0U;                  ///< offset 56
    std::uint64_t t_e_bits = 0U;                  ///< offset 64
    std::int32_t radius_voxels = 0;               ///< offset 72
    std::uint32_t payload_length = 0U;            ///< offset 76
    std::uint32_t payload_crc = 0U;               ///< offset 80
    std::uint32_t header_crc = 0U;                ///< offset 84

    /// The voxel size as a double (bit-exact).
    [[nodiscard]] double voxel_size() const noexcept;
    /// The origin as doubles (bit-exact).
    [[nodiscard]] Eigen::Vector3d origin() const noexcept;
    /// Method and parameters as stored (check them with prior_params_in_range).
    [[nodiscard]] AccessibilityParams params() const noexcept;
};

/// Reads and checks the header alone, without a grid to compare with: too
/// short, magic, version, header size, header CRC, reserved field, in that
/// order. Tools use it to learn what grid an image is for. A refusal
/// carries its PriorImageError (to_error_code gives the ErrorCode).
[[nodiscard]] Result<PriorImageHeader, PriorImageError> read_prior_image_header(
    Span<const std::uint8_t> image) noexcept;

class PriorImageView;

/// Start-up check of a prior image against the grid the controller was
/// built or configured for. Checks, in this order, each with its own
/// PriorImageError: expected geometry non-empty; read_prior_image_header's
/// checks; nx, ny, nz; voxel size bits; origin bits; method; parameters;
/// payload length = 2 * voxels; input length = 88 + payload length (shorter:
/// truncated, longer: trailing bytes); payload CRC; every value <= 0.
/// Never reads outside @p image. A refusal carries its PriorImageError
/// (to_error_code gives the ErrorCode). Work: two passes over the payload
/// (CRC, value range).
[[nodiscard]] Result<PriorImageView, PriorImageError> load_prior_image(Span<const std::uint8_t> image,
                                                                       const GridGeometry& expected_geometry) noexcept;

/// A validated image in caller memory (a file's bytes or a const array in
/// flash); zero-copy: values are decoded from the little-endian payload on
/// access, byte by byte, so neither the host's byte order nor the image's
/// alignment matters (on x86-64, g++ 12 and clang++ 14 compile the decode to
/// one 16-bit load). Valid while the image bytes live. Only
/// load_prior_image makes a non-empty view.
class PriorImageView {
public:
    /// An empty view (no image); a placeholder only.
    PriorImageView() noexcept = default;

    /// The grid the image was checked against (bit-equal to the stored one).
    [[nodiscard]] const GridGeometry& geometry() const noexcept { return geometry_; }
    /// The header as stored.
    [[nodiscard]] const PriorImageHeader& header() const noexcept { return header_; }
    /// Method and parameters the prior was computed with.
    [[nodiscard]] AccessibilityParams params() const noexcept { return header_.params(); }
    /// Number of prior values (the grid's voxel count; 0 for an empty view).
    [[nodiscard]] std::size_t voxel_count() const noexcept { return payload_.size() / kPriorImageBytesPerVoxel; }
    /// True for a default-constructed view.
    [[nodiscard]] bool empty() const noexcept { return image_.empty(); }
    /// Prior of voxel @p index (linear index order); checked in debug builds.
    [[nodiscard]] std::int16_t operator[](std::size_t index) const noexcept {
        CG_ASSERT(index < voxel_count(), "prior index out of range");
        // Through one base pointer: g++ 12 and clang++ 14 then merge the two
        // byte loads into one 16-bit load on x86-64 (checked in the assembly).
        const std::uint8_t* const b = payload_.data() + kPriorImageBytesPerVoxel * index;
        return int16_from_bits(
            static_cast<std::uint16_t>(static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8U)));
    }
    /// Prior of voxel @p index; checked in every build.
    [[nodiscard]] std::int16_t at(std::size_t index) const noexcept {
        CG_ENFORCE(index < voxel_count(), "prior index out of range");
        return (*this)[index];
    }
    /// Copies every value into @p out (at least voxel_count() elements, else
    /// kStorageTooSmall; only the first voxel_count() are written).
    [[nodiscard]] Status copy_to(Span<std::int16_t> out) const noexcept;
    /// The whole image: header and payload (what the integrity monitor re-checks).
    [[nodiscard]] Span<const std::uint8_t> image() const noexcept { return image_; }
    /// The payload bytes only.
    [[nodiscard]] Span<const std::uint8_t> payload() const noexcept { return payload_; }

private:
    friend Result<PriorImageView, PriorImageError> load_prior_image(Span<const std::uint8_t> image,
                                                                    const GridGeometry& expected_geometry) noexcept;
    GridGeometry geometry_{};
    PriorImageHeader header_{};
    Span<const std::uint8_t> image_{};
    Span<const std::uint8_t> payload_{};
};

/// Serialises @p prior (one value per voxel of @p geometry, linear index
/// order) with its geometry and @p params into @p out, and returns the
/// number of bytes written, prior_image_size(voxel count); bytes of @p out
/// beyond that are left untouched. Nothing is written on failure. Errors:
/// kInvalidArgument (empty geometry, parameters out of range, a prior value
/// > 0), kGeometryMismatch (prior.size() != voxel count), kStorageTooSmall.
[[nodiscard]] Result<std::size_t> write_prior_image(const GridGeometry& geometry, const AccessibilityParams& params,
                                                    Span<const std::int16_t> prior, Span<std::uint8_t> out) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_PRIOR_IMAGE_HPP
