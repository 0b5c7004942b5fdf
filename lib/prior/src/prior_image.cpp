// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/prior/prior_image.hpp"

#include <cmath>
#include <cstring>

#include "cellguard/base/crc32.hpp"

namespace cellguard {

namespace layout = prior_image_layout;

namespace {

static_assert(layout::kHeaderCrc + 4U == kPriorImageHeaderSize, "the header CRC is the header's last field");
static_assert(prior_image_size(kMaxVoxels) - kPriorImageHeaderSize <= 0xFFFFFFFFU,
              "the payload length of the largest grid fits its u32 field");

std::uint64_t bits_of_double(double d) noexcept {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &d, sizeof bits);
    return bits;
}

double double_of(std::uint64_t bits) noexcept {
    double d = 0.0;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

std::int32_t int32_from_bits(std::uint32_t bits) noexcept {
    return bits <= 0x7FFFFFFFU ? static_cast<std::int32_t>(bits)
                               : static_cast<std::int32_t>(-static_cast<std::int64_t>(~bits) - 1);
}

std::uint32_t bits_of_int32(std::int32_t v) noexcept {
    return v >= 0 ? static_cast<std::uint32_t>(v) : ~static_cast<std::uint32_t>(-(static_cast<std::int64_t>(v) + 1));
}

void store_le(Span<std::uint8_t> out, std::size_t offset, std::uint64_t value, std::size_t bytes) noexcept {
    for (std::size_t i = 0U; i < bytes; ++i) {
        out.at(offset + i) = static_cast<std::uint8_t>((value >> (8U * i)) & 0xFFU);
    }
}

bool unit_interval(double t) noexcept { return t >= 0.0 && t <= 1.0; }  // false for NaN

}  // namespace

ErrorCode to_error_code(PriorImageError error) noexcept {
    switch (error) {
        case PriorImageError::kNone: return ErrorCode::kOk;
        case PriorImageError::kTooShort:
        case PriorImageError::kPayloadTruncated: return ErrorCode::kTruncatedInput;
        case PriorImageError::kBadMagic: return ErrorCode::kBadMagic;
        case PriorImageError::kUnsupportedVersion: return ErrorCode::kUnsupportedVersion;
        case PriorImageError::kHeaderCrcMismatch:
        case PriorImageError::kPayloadCrcMismatch: return ErrorCode::kCrcMismatch;
        case PriorImageError::kDimsMismatch:
        case PriorImageError::kVoxelSizeMismatch:
        case PriorImageError::kOriginMismatch: return ErrorCode::kGeometryMismatch;
        case PriorImageError::kUnknownMethod: return ErrorCode::kUnsupportedType;
        case PriorImageError::kNoExpectedGeometry: return ErrorCode::kInvalidArgument;
        case PriorImageError::kBadHeaderSize:
        case PriorImageError::kReservedNotZero:
        case PriorImageError::kParameterOutOfRange:
        case PriorImageError::kPayloadLengthMismatch:
        case PriorImageError::kTrailingBytes:
        case PriorImageError::kPriorValueOutOfRange: break;
    }
    return ErrorCode::kMalformedInput;
}

const char* to_string(PriorImageError error) noexcept {
    switch (error) {
        case PriorImageError::kNone: return "prior image accepted";
        case PriorImageError::kTooShort: return "prior image shorter than its header";
        case PriorImageError::kBadMagic: return "prior image magic is not CGPI";
        case PriorImageError::kUnsupportedVersion: return "prior image format version not supported";
        case PriorImageError::kBadHeaderSize: return "prior image header size field is wrong";
        case PriorImageError::kHeaderCrcMismatch: return "prior image header CRC mismatch";
        case PriorImageError::kReservedNotZero: return "prior image reserved field is not zero";
        case PriorImageError::kDimsMismatch: return "prior image grid dimensions differ from the controller's grid";
        case PriorImageError::kVoxelSizeMismatch: return "prior image voxel size differs from the controller's grid";
        case PriorImageError::kOriginMismatch: return "prior image grid origin differs from the controller's grid";
        case PriorImageError::kUnknownMethod: return "prior image method is unknown";
        case PriorImageError::kParameterOutOfRange: return "prior image method parameter out of range";
        case PriorImageError::kPayloadLengthMismatch: return "prior image payload length does not match the grid";
        case PriorImageError::kPayloadTruncated: return "prior image payload truncated";
        case PriorImageError::kTrailingBytes: return "prior image has bytes after its payload";
        case PriorImageError::kPayloadCrcMismatch: return "prior image payload CRC mismatch";
        case PriorImageError::kPriorValueOutOfRange: return "prior image value above log-odds 0 (P(fore) > 0.5)";
        case PriorImageError::kNoExpectedGeometry: return "no expected grid geometry to check the prior image against";
    }
    return "unknown prior image error";
}

bool is_known_prior_method(std::uint8_t method) noexcept {
    switch (static_cast<PriorMethod>(method)) {
        case PriorMethod::kThresholded:
        case PriorMethod::kProbabilistic:
        case PriorMethod::kThresholdedBaseline:
        case PriorMethod::kProbabilisticBaseline: return true;
    }
    return false;
}

bool prior_params_in_range(const AccessibilityParams& params) noexcept {
    return is_known_prior_method(static_cast<std::uint8_t>(params.method)) && unit_interval(params.t_b) &&
           unit_interval(params.t_e) && params.radius_voxels >= 0 && params.radius_voxels <= kMaxAccessibilityRadius &&
           (params.open_faces & static_cast<std::uint8_t>(~kAllFaces)) == 0U;
}

double PriorImageHeader::voxel_size() const noexcept { return double_of(voxel_size_bits); }

Eigen::Vector3d PriorImageHeader::origin() const noexcept {
    return {double_of(origin_bits[0]), double_of(origin_bits[1]), double_of(origin_bits[2])};
}

AccessibilityParams PriorImageHeader::params() const noexcept {
    AccessibilityParams p;
    p.method = static_cast<PriorMethod>(method);
    p.t_b = double_of(t_b_bits);
    p.t_e = double_of(t_e_bits);
    p.radius_voxels = radius_voxels;
    p.open_faces = open_faces;
    return p;
}

Result<PriorImageHeader, PriorImageError> read_prior_image_header(Span<const std::uint8_t> image) noexcept {
    if (image.size() < layout::kVersion) {
        return PriorImageError::kTooShort;
    }
    for (std::size_t i = 0U; i < sizeof kPriorImageMagic; ++i) {
        if (image[layout::kMagic + i] != kPriorImageMagic[i]) {
            return PriorImageError::kBadMagic;
        }
    }
    if (image.size() < layout::kNx) {
        return PriorImageError::kTooShort;
    }
    PriorImageHeader h;
    h.format_version = load_le_u16(image, layout::kVersion);
    h.header_size = load_le_u16(image, layout::kHeaderSize);
    if (h.format_version != kPriorImageFormatVersion) {
        return PriorImageError::kUnsupportedVersion;
    }
    if (h.header_size != kPriorImageHeaderSize) {
        return PriorImageError::kBadHeaderSize;
    }
    if (image.size() < kPriorImageHeaderSize) {
        return PriorImageError::kTooShort;
    }
    h.header_crc = load_le_u32(image, layout::kHeaderCrc);
    if (crc32(image.subspan(0U, layout::kHeaderCrc)) != h.header_crc) {
        return PriorImageError::kHeaderCrcMismatch;
    }
    h.reserved = load_le_u16(image, layout::kReserved);
    if (h.reserved != 0U) {
        return PriorImageError::kReservedNotZero;
    }
    h.nx = load_le_u32(image, layout::kNx);
    h.ny = load_le_u32(image, layout::kNy);
    h.nz = load_le_u32(image, layout::kNz);
    h.method = image[layout::kMethod];
    h.open_faces = image[layout::kOpenFaces];
    h.voxel_size_bits = load_le_u64(image, layout::kVoxelSize);
    h.origin_bits[0] = load_le_u64(image, layout::kOriginX);
    h.origin_bits[1] = load_le_u64(image, layout::kOriginY);
    h.origin_bits[2] = load_le_u64(image, layout::kOriginZ);
    h.t_b_bits = load_le_u64(image, layout::kTb);
    h.t_e_bits = load_le_u64(image, layout::kTe);
    h.radius_voxels = int32_from_bits(load_le_u32(image, layout::kRadius));
    h.payload_length = load_le_u32(image, layout::kPayloadLength);
    h.payload_crc = load_le_u32(image, layout::kPayloadCrc);
    return h;
}

Result<PriorImageView, PriorImageError> load_prior_image(Span<const std::uint8_t> image,
                                                         const GridGeometry& expected_geometry) noexcept {
    const std::size_t voxels = expected_geometry.voxel_count();
    if (voxels == 0U) {
        return PriorImageError::kNoExpectedGeometry;
    }
    const Result<PriorImageHeader, PriorImageError> header = read_prior_image_header(image);
    if (!header.ok()) {
        return header.error();
    }
    const PriorImageHeader& h = header.value();

    const GridDims dims = expected_geometry.dims();
    // Expected dims are in [1, kMaxDimension], so the casts are exact.
    if (h.nx != static_cast<std::uint32_t>(dims.nx) || h.ny != static_cast<std::uint32_t>(dims.ny) ||
        h.nz != static_cast<std::uint32_t>(dims.nz)) {
        return PriorImageError::kDimsMismatch;
    }
    if (h.voxel_size_bits != bits_of_double(expected_geometry.voxel_size())) {
        return PriorImageError::kVoxelSizeMismatch;
    }
    const Eigen::Vector3d& origin = expected_geometry.origin();
    if (h.origin_bits[0] != bits_of_double(origin.x()) || h.origin_bits[1] != bits_of_double(origin.y()) ||
        h.origin_bits[2] != bits_of_double(origin.z())) {
        return PriorImageError::kOriginMismatch;
    }
    if (!is_known_prior_method(h.method)) {
        return PriorImageError::kUnknownMethod;
    }
    if (!prior_params_in_range(h.params())) {
        return PriorImageError::kParameterOutOfRange;
    }
    // voxels <= kMaxVoxels, so 2 * voxels cannot overflow.
    const std::size_t payload_length = kPriorImageBytesPerVoxel * voxels;
    if (h.payload_length != payload_length) {
        return PriorImageError::kPayloadLengthMismatch;
    }
    const std::size_t rest = image.size() - kPriorImageHeaderSize;  // header checked: size >= 88
    if (rest < payload_length) {
        return PriorImageError::kPayloadTruncated;
    }
    if (rest > payload_length) {
        return PriorImageError::kTrailingBytes;
    }
    const Span<const std::uint8_t> payload = image.subspan(kPriorImageHeaderSize, payload_length);
    if (crc32(payload) != h.payload_crc) {
        return PriorImageError::kPayloadCrcMismatch;
    }
    PriorImageView view;
    view.geometry_ = expected_geometry;
    view.header_ = h;
    view.image_ = image;
    view.payload_ = payload;
    for (std::size_t i = 0U; i < voxels; ++i) {
        if (view[i] > 0) {
            return PriorImageError::kPriorValueOutOfRange;
        }
    }
    return view;
}

Status PriorImageView::copy_to(Span<std::int16_t> out) const noexcept {
    const std::size_t n = voxel_count();
    if (out.size() < n) {
        return ErrorCode::kStorageTooSmall;
    }
    for (std::size_t i = 0U; i < n; ++i) {
        out[i] = (*this)[i];
    }
    return Status{};
}

Result<std::size_t> write_prior_image(const GridGeometry& geometry, const AccessibilityParams& params,
                                      Span<const std::int16_t> prior, Span<std::uint8_t> out) noexcept {
    const std::size_t voxels = geometry.voxel_count();
    if (voxels == 0U || !prior_params_in_range(params)) {
        return ErrorCode::kInvalidArgument;
    }
    if (prior.size() != voxels) {
        return ErrorCode::kGeometryMismatch;
    }
    for (const std::int16_t v : prior) {
        if (v > 0) {
            return ErrorCode::kInvalidArgument;
        }
    }
    const std::size_t size = prior_image_size(voxels);
    if (out.size() < size) {
        return ErrorCode::kStorageTooSmall;
    }
    const Span<std::uint8_t> image = out.subspan(0U, size);
    for (std::size_t i = 0U; i < sizeof kPriorImageMagic; ++i) {
        image[layout::kMagic + i] = kPriorImageMagic[i];
    }
    const GridDims dims = geometry.dims();
    store_le(image, layout::kVersion, kPriorImageFormatVersion, 2U);
    store_le(image, layout::kHeaderSize, kPriorImageHeaderSize, 2U);
    store_le(image, layout::kNx, static_cast<std::uint32_t>(dims.nx), 4U);
    store_le(image, layout::kNy, static_cast<std::uint32_t>(dims.ny), 4U);
    store_le(image, layout::kNz, static_cast<std::uint32_t>(dims.nz), 4U);
    image[layout::kMethod] = static_cast<std::uint8_t>(params.method);
    image[layout::kOpenFaces] = params.open_faces;
    store_le(image, layout::kReserved, 0U, 2U);
    store_le(image, layout::kVoxelSize, bits_of_double(geometry.voxel_size()), 8U);
    store_le(image, layout::kOriginX, bits_of_double(geometry.origin().x()), 8U);
    store_le(image, layout::kOriginY, bits_of_double(geometry.origin().y()), 8U);
    store_le(image, layout::kOriginZ, bits_of_double(geometry.origin().z()), 8U);
    store_le(image, layout::kTb, bits_of_double(params.t_b), 8U);
    store_le(image, layout::kTe, bits_of_double(params.t_e), 8U);
    store_le(image, layout::kRadius, bits_of_int32(params.radius_voxels), 4U);
    store_le(image, layout::kPayloadLength, kPriorImageBytesPerVoxel * voxels, 4U);
    for (std::size_t i = 0U; i < voxels; ++i) {
        // Two's complement bit pattern of the value, low byte first.
        const auto bits = static_cast<std::uint16_t>(prior[i] < 0 ? 65536 + static_cast<std::int32_t>(prior[i])
                                                                  : static_cast<std::int32_t>(prior[i]));
        image[kPriorImageHeaderSize + 2U * i] = static_cast<std::uint8_t>(bits & 0xFFU);
        image[kPriorImageHeaderSize + 2U * i + 1U] = static_cast<std::uint8_t>(bits >> 8U);
    }
    const Span<const std::uint8_t> written(image.data(), size);
    store_le(image, layout::kPayloadCrc, crc32(written.subspan(kPriorImageHeaderSize, size - kPriorImageHeaderSize)),
             4U);
    store_le(image, layout::kHeaderCrc, crc32(written.subspan(0U, layout::kHeaderCrc)), 4U);
    return size;
}

}  // namespace cellguard
