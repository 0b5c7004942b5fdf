// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the prior image loader. No crash, no read outside the input
// (ASan: the image is copied into a heap buffer of exactly its size), the
// fine reason agrees with the ErrorCode, every accepted image re-encodes to
// the identical bytes, and the integrity monitor passes it.
//
// Input: one mode byte, then the image bytes.
// - mode bit 0: recompute both CRCs first, so mutations reach the field
//   checks behind them.
// - mode bit 1: check against the geometry the header itself states (when
//   it is a valid geometry) instead of the fixed one below, so mutations get
//   past the geometry checks.
// - mode bits 2..7: slice size - 1 for the signature check.
// Seeds: tests/fuzz/corpus/fuzz_prior_image/ (valid images for both modes).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/base/ram_check.hpp"
#include "cellguard/prior/prior_image.hpp"

using namespace cellguard;
namespace layout = cellguard::prior_image_layout;

namespace {

void require(bool condition) {
    if (!condition) {
        std::abort();
    }
}

GridGeometry fixed_geometry() {
    return GridGeometry::make(Eigen::Vector3d(-0.25, 0.5, 0.0), 0.05, GridDims{3, 2, 2}).value();
}

double double_at(const std::vector<std::uint8_t>& img, std::size_t offset) {
    const std::uint64_t bits = load_le_u64(Span<const std::uint8_t>(img.data(), img.size()), offset);
    double d = 0.0;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

void put_u32(std::vector<std::uint8_t>& img, std::size_t offset, std::uint32_t v) {
    for (std::size_t i = 0; i < 4; ++i)
        img[offset + i] = static_cast<std::uint8_t>(v >> (8U * i));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1U) {
        return 0;
    }
    const std::uint8_t mode = data[0];
    std::vector<std::uint8_t> img(data + 1, data + size);

    if ((mode & 1U) != 0U && img.size() >= kPriorImageHeaderSize) {
        const Span<const std::uint8_t> s(img.data(), img.size());
        put_u32(img, layout::kPayloadCrc, crc32(s.subspan(kPriorImageHeaderSize, img.size() - kPriorImageHeaderSize)));
        put_u32(img, layout::kHeaderCrc, crc32(s.subspan(0, layout::kHeaderCrc)));
    }

    GridGeometry expected = fixed_geometry();
    if ((mode & 2U) != 0U && img.size() >= kPriorImageHeaderSize) {
        const Span<const std::uint8_t> s(img.data(), img.size());
        const std::uint32_t nx = load_le_u32(s, layout::kNx);
        const std::uint32_t ny = load_le_u32(s, layout::kNy);
        const std::uint32_t nz = load_le_u32(s, layout::kNz);
        if (nx <= 4096U && ny <= 4096U && nz <= 4096U) {
            const Result<GridGeometry> g = GridGeometry::make(
                Eigen::Vector3d(double_at(img, layout::kOriginX), double_at(img, layout::kOriginY),
                                double_at(img, layout::kOriginZ)),
                double_at(img, layout::kVoxelSize),
                GridDims{static_cast<std::int32_t>(nx), static_cast<std::int32_t>(ny), static_cast<std::int32_t>(nz)});
            if (g.ok()) {
                expected = g.value();
            }
        }
    }

    const Result<PriorImageView, PriorImageError> r = load_prior_image(Span<const std::uint8_t>(img.data(), img.size()),
                                                                       expected);
    require(r.ok() == (r.error() == PriorImageError::kNone));
    require(r.ok() == (to_error_code(r.error()) == ErrorCode::kOk));
    if (!r.ok()) {
        return 0;
    }
    const PriorImageView& view = r.value();
    require(view.image().data() == img.data() && view.image().size() == img.size());

    // Re-encode what was accepted: the bytes must come out identical.
    std::vector<std::int16_t> values(view.voxel_count());
    require(view.copy_to(Span<std::int16_t>(values.data(), values.size())).ok());
    for (std::size_t i = 0; i < values.size(); ++i)
        require(values[i] == view.at(i) && values[i] <= 0);
    std::vector<std::uint8_t> again(prior_image_size(values.size()));
    const Result<std::size_t> w = write_prior_image(view.geometry(), view.params(),
                                                    Span<const std::int16_t>(values.data(), values.size()),
                                                    Span<std::uint8_t>(again.data(), again.size()));
    require(w.ok() && w.value() == img.size());
    require(std::memcmp(again.data(), img.data(), img.size()) == 0);

    // A signature check of the image as two regions (header, payload) takes
    // the image's CRC-32 as its reference and passes it, intact, in exactly
    // ceil(size / slice) steps.
    const std::size_t slice = static_cast<std::size_t>(mode >> 2U) + 1U;
    const Span<const std::uint8_t> bytes = view.image();
    const SignatureRegion parts[] = {bytes.subspan(0U, kPriorImageHeaderSize),
                                     bytes.subspan(kPriorImageHeaderSize, bytes.size() - kPriorImageHeaderSize)};
    SignatureCheck check{Span<const SignatureRegion>(parts)};
    require(check.reference() == crc32(bytes));
    require(check.steps_per_pass(slice) == (img.size() + slice - 1U) / slice);
    for (std::size_t i = 0; i < check.steps_per_pass(slice); ++i)
        require(!check.step(slice));
    require(check.position() == 0U && !check.failed());
    return 0;
}
