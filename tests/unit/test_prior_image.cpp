// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the prior image format (byte layout, writer, loader), every way the loader refuses an image.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/base/crc32.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/prior/prior_image.hpp"
#include "contract_capture.hpp"

using namespace cellguard;
namespace layout = cellguard::prior_image_layout;

namespace {

GridGeometry small_geometry() {
    return GridGeometry::make(Eigen::Vector3d(-0.1, 0.25, 0.0), 0.05, GridDims{4, 3, 2}).value();
}

// A prior with the sentinel, zero and a spread of negative values.
std::vector<std::int16_t> sample_prior(std::size_t n) {
    std::vector<std::int16_t> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        v[i] = (i % 7U == 0U)   ? kNeverForeground
               : (i % 5U == 0U) ? std::int16_t{0}
                                : static_cast<std::int16_t>(-static_cast<std::int32_t>((i * 977U) % 32768U));
    }
    return v;
}

std::vector<std::uint8_t> encode(const GridGeometry& g, const AccessibilityParams& p,
                                 const std::vector<std::int16_t>& prior) {
    std::vector<std::uint8_t> out(prior_image_size(g.voxel_count()));
    const Result<std::size_t> n = write_prior_image(g, p, Span<const std::int16_t>(prior.data(), prior.size()),
                                                    Span<std::uint8_t>(out.data(), out.size()));
    REQUIRE(n.ok());
    REQUIRE(n.value() == out.size());
    return out;
}

std::vector<std::uint8_t> small_image() { return encode(small_geometry(), AccessibilityParams{}, sample_prior(24)); }

Span<const std::uint8_t> span_of(const std::vector<std::uint8_t>& v) { return {v.data(), v.size()}; }

void put_le(std::vector<std::uint8_t>& img, std::size_t offset, std::uint64_t value, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i)
        img.at(offset + i) = static_cast<std::uint8_t>(value >> (8U * i));
}

std::uint64_t bits(double d) {
    std::uint64_t b = 0;
    std::memcpy(&b, &d, sizeof b);
    return b;
}

// Recomputes the header CRC, so that a test reaches the check after it.
void reseal_header(std::vector<std::uint8_t>& img) {
    put_le(img, layout::kHeaderCrc, crc32(Span<const std::uint8_t>(img.data(), layout::kHeaderCrc)), 4);
}

// Recomputes the payload CRC over everything after the header, then the header CRC.
void reseal_all(std::vector<std::uint8_t>& img) {
    put_le(img, layout::kPayloadCrc,
           crc32(Span<const std::uint8_t>(img.data() + kPriorImageHeaderSize, img.size() - kPriorImageHeaderSize)), 4);
    reseal_header(img);
}

// Loads and returns the refusal's reason (kNone on success); a success holds no error, a refusal never kNone.
PriorImageError why_refused(const std::vector<std::uint8_t>& img, const GridGeometry& g = small_geometry()) {
    const Result<PriorImageView, PriorImageError> r = load_prior_image(span_of(img), g);
    CHECK(r.ok() == (r.error() == PriorImageError::kNone));
    return r.error();
}

// The 2 x 1 x 1 image below, made independently (Python struct + zlib.crc32).
constexpr std::uint8_t kGolden[] = {
    0x43, 0x47, 0x50, 0x49, 0x01, 0x00, 0x58, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
    0x00, 0x02, 0x0f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xc0, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0xe0, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf4, 0xbf, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x40, 0x52,
    0xb8, 0x1e, 0x85, 0xeb, 0x51, 0xe0, 0x3f, 0x9a, 0x99, 0x99, 0x99, 0x99, 0x99, 0xb9, 0x3f, 0x02, 0x00, 0x00, 0x00,
    0x04, 0x00, 0x00, 0x00, 0x9c, 0x1b, 0x20, 0x7f, 0x9d, 0xa5, 0x0f, 0xf4, 0x00, 0x80, 0xd4, 0xfe,
};

}  // namespace

// verifies: SR-PRIOR-010
TEST_CASE("prior image: the size is an 88-byte header plus two bytes per voxel, saturating") {
    CHECK(kPriorImageHeaderSize == 88U);
    CHECK(prior_image_size(0) == 88U);
    CHECK(prior_image_size(30600) == 88U + 61200U);
    static_assert(prior_image_size(24) == 136U, "constexpr");
    constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
    CHECK(prior_image_size(kMax) == kMax);
    CHECK(prior_image_size((kMax - 88U) / 2U) == 88U + 2U * ((kMax - 88U) / 2U));
    CHECK(prior_image_size((kMax - 88U) / 2U + 1U) == kMax);
}

// verifies: SR-PRIOR-010
TEST_CASE("prior image: the writer's bytes equal an independently made golden image") {
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(0.5, -1.25, 2.0), 0.125, GridDims{2, 1, 1}).value();
    AccessibilityParams p;
    p.method = PriorMethod::kProbabilistic;
    p.t_b = 0.51;
    p.t_e = 0.1;
    p.radius_voxels = 2;
    p.open_faces = kPaperOpenFaces;
    const std::vector<std::int16_t> prior = {kNeverForeground, -300};
    const std::vector<std::uint8_t> img = encode(g, p, prior);
    REQUIRE(img.size() == sizeof kGolden);
    CHECK(std::memcmp(img.data(), kGolden, sizeof kGolden) == 0);
    const Result<PriorImageView, PriorImageError> v = load_prior_image(Span<const std::uint8_t>(kGolden), g);
    REQUIRE(v.ok());
    CHECK(v.value()[0] == kNeverForeground);
    CHECK(v.value()[1] == -300);
    CHECK(v.value().header().payload_crc == 0x7f201b9cU);
    CHECK(v.value().header().header_crc == 0xf40fa59dU);
}

// verifies: SR-PRIOR-010
TEST_CASE("prior image: header fields sit at their documented offsets, little-endian") {
    const GridGeometry g = small_geometry();
    AccessibilityParams p;
    p.method = PriorMethod::kThresholded;
    p.t_b = 0.51;
    p.t_e = 0.25;
    p.radius_voxels = 3;
    p.open_faces = kFaceMinX | kFaceMaxZ;
    std::vector<std::int16_t> prior(24, 0);
    prior[0] = kNeverForeground;
    prior[1] = -2;
    prior[23] = -32767;
    const std::vector<std::uint8_t> img = encode(g, p, prior);
    const Span<const std::uint8_t> s = span_of(img);
    CHECK(img[0] == 'C');
    CHECK(img[1] == 'G');
    CHECK(img[2] == 'P');
    CHECK(img[3] == 'I');
    CHECK(img[4] == 0x01);
    CHECK(img[5] == 0x00);
    CHECK(img[6] == 88);
    CHECK(img[7] == 0x00);
    CHECK(load_le_u32(s, 8) == 4U);
    CHECK(img[8] == 4);
    CHECK(load_le_u32(s, 12) == 3U);
    CHECK(load_le_u32(s, 16) == 2U);
    CHECK(img[20] == 1);
    CHECK(img[21] == (kFaceMinX | kFaceMaxZ));
    CHECK(load_le_u16(s, 22) == 0U);
    CHECK(load_le_u64(s, 24) == bits(0.05));
    CHECK(load_le_u64(s, 32) == bits(-0.1));
    CHECK(load_le_u64(s, 40) == bits(0.25));
    CHECK(load_le_u64(s, 48) == bits(0.0));
    CHECK(load_le_u64(s, 56) == bits(0.51));
    CHECK(load_le_u64(s, 64) == bits(0.25));
    CHECK(load_le_u32(s, 72) == 3U);
    CHECK(load_le_u32(s, 76) == 48U);
    CHECK(load_le_u32(s, 80) == crc32(s.subspan(88, 48)));
    CHECK(load_le_u32(s, 84) == crc32(s.subspan(0, 84)));
    // payload: int16 little-endian, linear index order
    CHECK(img[88] == 0x00);
    CHECK(img[89] == 0x80);
    CHECK(img[90] == 0xFE);
    CHECK(img[91] == 0xFF);
    CHECK(img[92] == 0x00);
    CHECK(img[93] == 0x00);
    CHECK(img[88 + 46] == 0x01);
    CHECK(img[88 + 47] == 0x80);
}

// verifies: SR-PRIOR-010
TEST_CASE("prior image: a written image loads back with the same values, geometry and parameters") {
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                PriorMethod::kThresholdedBaseline, PriorMethod::kProbabilisticBaseline}) {
        const GridGeometry g = paper_grid_geometry();
        AccessibilityParams p;
        p.method = m;
        p.t_b = 0.6;
        p.t_e = 0.05;
        p.radius_voxels = 4;
        p.open_faces = kAllFaces;
        const std::vector<std::int16_t> prior = sample_prior(g.voxel_count());
        const std::vector<std::uint8_t> img = encode(g, p, prior);
        const Result<PriorImageView, PriorImageError> r = load_prior_image(span_of(img), g);
        REQUIRE(r.ok());
        CHECK(r.error() == PriorImageError::kNone);
        const PriorImageView& v = r.value();
        CHECK(v.voxel_count() == g.voxel_count());
        CHECK(v.geometry() == g);
        CHECK(v.params().method == m);
        CHECK(v.params().t_b == 0.6);
        CHECK(v.params().t_e == 0.05);
        CHECK(v.params().radius_voxels == 4);
        CHECK(v.params().open_faces == kAllFaces);
        CHECK(v.image().data() == img.data());
        CHECK(v.image().size() == img.size());
        CHECK(v.payload().data() == img.data() + 88);
        bool all_equal = true;
        for (std::size_t i = 0; i < prior.size(); ++i)
            all_equal = all_equal && v[i] == prior[i] && v.at(i) == prior[i];
        CHECK(all_equal);
        std::vector<std::int16_t> copy(prior.size() + 1U, 7);
        CHECK(v.copy_to(Span<std::int16_t>(copy.data(), copy.size())).ok());
        CHECK(std::equal(prior.begin(), prior.end(), copy.begin()));
        CHECK(copy.back() == 7);  // only voxel_count() values are written
    }
}

// verifies: SR-PRIOR-010, SR-GEN-002
TEST_CASE("prior image: loading and writing allocate nothing") {
    const std::vector<std::int16_t> prior = sample_prior(24);
    std::vector<std::uint8_t> img(prior_image_size(24));
    const test::AllocationScope scope;
    const Result<std::size_t> n = write_prior_image(small_geometry(), AccessibilityParams{},
                                                    Span<const std::int16_t>(prior.data(), prior.size()),
                                                    Span<std::uint8_t>(img.data(), img.size()));
    const Result<PriorImageView, PriorImageError> v = load_prior_image(span_of(img), small_geometry());
    CHECK(scope.allocations() == 0U);
    CHECK(n.ok());
    CHECK(v.ok());
}

// verifies: SR-PRIOR-010
TEST_CASE("prior image: the header can be read without a grid to compare with") {
    const std::vector<std::uint8_t> img = small_image();
    const Result<PriorImageHeader, PriorImageError> h = read_prior_image_header(span_of(img));
    REQUIRE(h.ok());
    CHECK(h.value().nx == 4U);
    CHECK(h.value().ny == 3U);
    CHECK(h.value().nz == 2U);
    CHECK(h.value().voxel_size() == 0.05);
    CHECK(h.value().origin() == Eigen::Vector3d(-0.1, 0.25, 0.0));
    CHECK(h.value().payload_length == 48U);
    CHECK(h.value().format_version == 1U);
    CHECK(h.value().header_size == 88U);
    std::vector<std::uint8_t> bad = img;
    bad[30] ^= 0x01U;
    const Result<PriorImageHeader, PriorImageError> refused = read_prior_image_header(span_of(bad));
    CHECK_FALSE(refused.ok());
    const PriorImageError why = refused.error();
    CHECK(why == PriorImageError::kHeaderCrcMismatch);
    CHECK(to_error_code(why) == ErrorCode::kCrcMismatch);
}

// verifies: SR-PRIOR-010
TEST_CASE("prior image: the writer refuses bad input with a clear error and writes nothing") {
    const GridGeometry g = small_geometry();
    std::vector<std::int16_t> prior = sample_prior(24);
    std::vector<std::uint8_t> out(200, 0xAB);
    const auto write = [&](const GridGeometry& geo, const AccessibilityParams& p, std::size_t values,
                           std::size_t out_size) {
        return write_prior_image(geo, p, Span<const std::int16_t>(prior.data(), values),
                                 Span<std::uint8_t>(out.data(), out_size))
            .error();
    };
    const AccessibilityParams ok{};
    CHECK(write(GridGeometry{}, ok, 0, 200) == ErrorCode::kInvalidArgument);
    CHECK(write(g, ok, 23, 200) == ErrorCode::kGeometryMismatch);
    CHECK(write(g, ok, 24, 135) == ErrorCode::kStorageTooSmall);
    AccessibilityParams p = ok;
    p.method = static_cast<PriorMethod>(0);
    CHECK(write(g, p, 24, 200) == ErrorCode::kInvalidArgument);
    p = ok;
    p.t_b = std::numeric_limits<double>::quiet_NaN();
    CHECK(write(g, p, 24, 200) == ErrorCode::kInvalidArgument);
    p = ok;
    p.t_e = 1.5;
    CHECK(write(g, p, 24, 200) == ErrorCode::kInvalidArgument);
    p = ok;
    p.radius_voxels = -1;
    CHECK(write(g, p, 24, 200) == ErrorCode::kInvalidArgument);
    p = ok;
    p.open_faces = 0x40U;
    CHECK(write(g, p, 24, 200) == ErrorCode::kInvalidArgument);
    prior[5] = 1;  // P(fore) > 0.5
    CHECK(write(g, ok, 24, 200) == ErrorCode::kInvalidArgument);
    bool untouched = true;
    for (const auto b : out)
        untouched = untouched && b == 0xAB;
    CHECK(untouched);
    prior[5] = 0;
    CHECK(write_prior_image(g, ok, Span<const std::int16_t>(prior.data(), 24), Span<std::uint8_t>(out.data(), 200))
              .value() == 136U);
    CHECK(out[136] == 0xAB);  // bytes past the image are left alone
}

// verifies: SR-PRIOR-010
TEST_CASE("prior image: parameter ranges are t_B, t_E in [0, 1], r in [0, 4096], faces within the six") {
    AccessibilityParams p;
    CHECK(prior_params_in_range(p));
    p.t_b = 0.0;
    p.t_e = 1.0;
    p.radius_voxels = 0;
    p.open_faces = 0;
    CHECK(prior_params_in_range(p));
    p.radius_voxels = kMaxAccessibilityRadius;
    p.open_faces = kAllFaces;
    CHECK(prior_params_in_range(p));
    p.radius_voxels = kMaxAccessibilityRadius + 1;
    CHECK_FALSE(prior_params_in_range(p));
    p.radius_voxels = 2;
    p.t_b = -1e-300;
    CHECK_FALSE(prior_params_in_range(p));
    p.t_b = 0.5;
    p.t_e = std::numeric_limits<double>::infinity();
    CHECK_FALSE(prior_params_in_range(p));
    CHECK(is_known_prior_method(1));
    CHECK(is_known_prior_method(4));
    CHECK_FALSE(is_known_prior_method(0));
    CHECK_FALSE(is_known_prior_method(5));
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: input shorter than the header is refused as too short") {
    const std::vector<std::uint8_t> img = small_image();
    for (const std::size_t n : {0U, 1U, 3U, 4U, 7U, 8U, 50U, 87U}) {
        const std::vector<std::uint8_t> cut(img.begin(), img.begin() + static_cast<std::ptrdiff_t>(n));
        CHECK(why_refused(cut) == PriorImageError::kTooShort);
    }
    CHECK(to_error_code(load_prior_image(Span<const std::uint8_t>(), small_geometry()).error()) ==
          ErrorCode::kTruncatedInput);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a wrong magic is refused as bad magic") {
    for (std::size_t i = 0; i < 4; ++i) {
        std::vector<std::uint8_t> img = small_image();
        img[i] ^= 0x20U;
        CHECK(why_refused(img) == PriorImageError::kBadMagic);
    }
    const std::vector<std::uint8_t> four = {'C', 'G', 'P', 'X'};
    CHECK(why_refused(four) == PriorImageError::kBadMagic);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: another format version is refused as unsupported") {
    for (const std::uint16_t version : {0, 2, 0x0100, 0xFFFF}) {
        std::vector<std::uint8_t> img = small_image();
        put_le(img, layout::kVersion, version, 2);
        reseal_header(img);
        CHECK(why_refused(img) == PriorImageError::kUnsupportedVersion);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a header size other than 88 is refused") {
    for (const std::uint16_t size : {0, 84, 87, 89, 0x5800}) {
        std::vector<std::uint8_t> img = small_image();
        put_le(img, layout::kHeaderSize, size, 2);
        reseal_header(img);
        CHECK(why_refused(img) == PriorImageError::kBadHeaderSize);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a changed header byte is refused as a header CRC mismatch") {
    const std::vector<std::uint8_t> clean = small_image();
    for (std::size_t i = 8; i < kPriorImageHeaderSize; ++i) {
        std::vector<std::uint8_t> img = clean;
        img[i] ^= 0x10U;
        CHECK(why_refused(img) == PriorImageError::kHeaderCrcMismatch);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a reserved field other than zero is refused") {
    std::vector<std::uint8_t> img = small_image();
    put_le(img, layout::kReserved, 0x0100, 2);
    reseal_header(img);
    CHECK(why_refused(img) == PriorImageError::kReservedNotZero);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: other grid dimensions are refused as a dims mismatch") {
    const std::vector<std::uint8_t> img = small_image();
    const Eigen::Vector3d o(-0.1, 0.25, 0.0);
    for (const GridDims d : {GridDims{5, 3, 2}, GridDims{4, 2, 2}, GridDims{4, 3, 3}, GridDims{3, 4, 2}}) {
        CHECK(why_refused(img, GridGeometry::make(o, 0.05, d).value()) == PriorImageError::kDimsMismatch);
    }
    // Stored dims changed (and resealed) against the right expected grid, incl. values beyond int32.
    for (const std::size_t off : {layout::kNx, layout::kNy, layout::kNz}) {
        std::vector<std::uint8_t> bad = img;
        put_le(bad, off, 0x80000004U, 4);
        reseal_header(bad);
        CHECK(why_refused(bad) == PriorImageError::kDimsMismatch);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: another voxel size is refused as a voxel size mismatch, bit for bit") {
    const std::vector<std::uint8_t> img = small_image();
    const Eigen::Vector3d o(-0.1, 0.25, 0.0);
    const double next = std::nextafter(0.05, 1.0);
    CHECK(why_refused(img, GridGeometry::make(o, next, GridDims{4, 3, 2}).value()) ==
          PriorImageError::kVoxelSizeMismatch);
    CHECK(why_refused(img, GridGeometry::make(o, 0.1, GridDims{4, 3, 2}).value()) ==
          PriorImageError::kVoxelSizeMismatch);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: another origin is refused as an origin mismatch, on every axis, bit for bit") {
    const std::vector<std::uint8_t> img = small_image();
    for (int axis = 0; axis < 3; ++axis) {
        Eigen::Vector3d o(-0.1, 0.25, 0.0);
        o[axis] = std::nextafter(o[axis], 10.0);
        CHECK(why_refused(img, GridGeometry::make(o, 0.05, GridDims{4, 3, 2}).value()) ==
              PriorImageError::kOriginMismatch);
    }
    // -0.0 == 0.0 as doubles, but the bits differ: refused (fail-safe).
    const Eigen::Vector3d negative_zero(-0.1, 0.25, -0.0);
    CHECK(why_refused(img, GridGeometry::make(negative_zero, 0.05, GridDims{4, 3, 2}).value()) ==
          PriorImageError::kOriginMismatch);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: an unknown method is refused") {
    for (const std::uint8_t m : {0, 5, 0x81, 0xFF}) {
        std::vector<std::uint8_t> img = small_image();
        img[layout::kMethod] = m;
        reseal_header(img);
        CHECK(why_refused(img) == PriorImageError::kUnknownMethod);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a parameter out of range is refused, each of t_B, t_E, r and open faces") {
    struct Case {
        std::size_t offset;
        std::uint64_t value;
        std::size_t bytes;
    };
    const Case cases[] = {
        {layout::kTb, bits(1.0000001), 8},
        {layout::kTb, bits(-0.5), 8},
        {layout::kTb, bits(std::numeric_limits<double>::quiet_NaN()), 8},
        {layout::kTe, bits(std::numeric_limits<double>::infinity()), 8},
        {layout::kTe, bits(2.0), 8},
        {layout::kRadius, 0xFFFFFFFFU, 4},  // -1
        {layout::kRadius, 4097U, 4},
        {layout::kRadius, 0x80000000U, 4},  // INT32_MIN
        {layout::kOpenFaces, 0x40U, 1},
        {layout::kOpenFaces, 0xFFU, 1},
    };
    for (const Case& c : cases) {
        std::vector<std::uint8_t> img = small_image();
        put_le(img, c.offset, c.value, c.bytes);
        reseal_header(img);
        CHECK(why_refused(img) == PriorImageError::kParameterOutOfRange);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a payload length that does not fit the grid is refused") {
    for (const std::uint32_t len : {0U, 46U, 47U, 49U, 50U, 0xFFFFFFFFU}) {
        std::vector<std::uint8_t> img = small_image();
        put_le(img, layout::kPayloadLength, len, 4);
        reseal_header(img);
        CHECK(why_refused(img) == PriorImageError::kPayloadLengthMismatch);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: input that ends inside the payload is refused as truncated") {
    const std::vector<std::uint8_t> img = small_image();
    for (std::size_t n = kPriorImageHeaderSize; n < img.size(); ++n) {
        const std::vector<std::uint8_t> cut(img.begin(), img.begin() + static_cast<std::ptrdiff_t>(n));
        CHECK(why_refused(cut) == PriorImageError::kPayloadTruncated);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: bytes after the payload are refused as trailing bytes") {
    for (const std::size_t extra : {1U, 2U, 100U}) {
        std::vector<std::uint8_t> img = small_image();
        img.resize(img.size() + extra, 0U);
        CHECK(why_refused(img) == PriorImageError::kTrailingBytes);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a changed payload byte is refused as a payload CRC mismatch") {
    const std::vector<std::uint8_t> clean = small_image();
    for (std::size_t i = kPriorImageHeaderSize; i < clean.size(); ++i) {
        std::vector<std::uint8_t> img = clean;
        img[i] ^= 0x01U;
        CHECK(why_refused(img) == PriorImageError::kPayloadCrcMismatch);
    }
    std::vector<std::uint8_t> img = clean;
    put_le(img, layout::kPayloadCrc, load_le_u32(span_of(img), layout::kPayloadCrc) ^ 1U, 4);
    reseal_header(img);
    CHECK(why_refused(img) == PriorImageError::kPayloadCrcMismatch);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: a positive prior value (P(fore) > 0.5) is refused even with good CRCs") {
    for (const std::int16_t v : {std::int16_t{1}, kLogOddsMax}) {
        std::vector<std::uint8_t> img = small_image();
        put_le(img, kPriorImageHeaderSize + 2U * 23U, static_cast<std::uint16_t>(v), 2);
        reseal_all(img);
        CHECK(why_refused(img) == PriorImageError::kPriorValueOutOfRange);
    }
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: an empty expected geometry is refused before the input is read") {
    const std::vector<std::uint8_t> img = small_image();
    CHECK(why_refused(img, GridGeometry{}) == PriorImageError::kNoExpectedGeometry);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: every refusal has its own reason, text and a fitting ErrorCode") {
    std::set<std::string> texts;
    for (int i = 0; i <= 17; ++i) {
        const auto e = static_cast<PriorImageError>(i);
        texts.insert(to_string(e));
        CHECK((to_error_code(e) == ErrorCode::kOk) == (e == PriorImageError::kNone));
    }
    CHECK(texts.size() == 18U);
    CHECK(to_error_code(PriorImageError::kHeaderCrcMismatch) == ErrorCode::kCrcMismatch);
    CHECK(to_error_code(PriorImageError::kPayloadCrcMismatch) == ErrorCode::kCrcMismatch);
    CHECK(to_error_code(PriorImageError::kDimsMismatch) == ErrorCode::kGeometryMismatch);
    CHECK(to_error_code(PriorImageError::kOriginMismatch) == ErrorCode::kGeometryMismatch);
    CHECK(to_error_code(PriorImageError::kVoxelSizeMismatch) == ErrorCode::kGeometryMismatch);
    CHECK(to_error_code(PriorImageError::kBadMagic) == ErrorCode::kBadMagic);
    CHECK(to_error_code(PriorImageError::kUnsupportedVersion) == ErrorCode::kUnsupportedVersion);
    CHECK(to_error_code(PriorImageError::kTooShort) == ErrorCode::kTruncatedInput);
    CHECK(to_error_code(PriorImageError::kPayloadTruncated) == ErrorCode::kTruncatedInput);
    CHECK(to_error_code(PriorImageError::kUnknownMethod) == ErrorCode::kUnsupportedType);
    CHECK(std::string(to_string(static_cast<PriorImageError>(200))) == "unknown prior image error");
}

// verifies: SR-PRIOR-011, SR-GEN-003
TEST_CASE("prior image view: an empty view holds nothing and checked access outside it is a contract violation") {
    const PriorImageView empty;
    CHECK(empty.empty());
    CHECK(empty.voxel_count() == 0U);
    CHECK(test::violates_contract([&] { (void)empty.at(0); }));
    const std::vector<std::uint8_t> img = small_image();
    const PriorImageView v = load_prior_image(span_of(img), small_geometry()).value();
    CHECK_FALSE(v.empty());
    CHECK(test::violates_contract([&] { (void)v.at(24); }));
    std::int16_t small[23];
    CHECK(v.copy_to(Span<std::int16_t>(small)).error() == ErrorCode::kStorageTooSmall);
}

// verifies: SR-PRIOR-011
TEST_CASE("prior image loader: an image inside a larger buffer is read only within its span") {
    std::vector<std::uint8_t> buffer = small_image();
    const std::size_t n = buffer.size();
    buffer.push_back(0xEE);  // a byte just past the span must not matter
    CHECK(load_prior_image(Span<const std::uint8_t>(buffer.data(), n), small_geometry()).ok());
    CHECK(load_prior_image(Span<const std::uint8_t>(buffer.data(), n + 1U), small_geometry()).error() ==
          PriorImageError::kTrailingBytes);
}
