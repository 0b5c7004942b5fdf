// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/depth_pyramid.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#include <arm_neon.h>
#endif

namespace cellguard {

namespace {

constexpr std::int32_t kMaxImageSide = 4096;

std::int32_t halve_up(std::int32_t n) noexcept { return (n + 1) / 2; }

}  // namespace

std::size_t depth_pyramid_cells(std::int32_t width, std::int32_t height) noexcept {
    if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide) {
        return 0U;
    }
    std::size_t cells = 0U;
    std::int32_t w = width;
    std::int32_t h = height;
    for (std::int32_t level = 0; level < kMaxPyramidLevels; ++level) {
        cells += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        if (w == 1 && h == 1) {
            break;
        }
        w = halve_up(w);
        h = halve_up(h);
    }
    return cells;
}

Result<DepthPyramid> DepthPyramid::make(std::int32_t width, std::int32_t height, Span<float> min_storage,
                                        Span<float> max_storage, Span<std::uint8_t> invalid_storage) noexcept {
    const std::size_t cells = depth_pyramid_cells(width, height);
    if (cells == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (min_storage.size() < cells || max_storage.size() < cells || invalid_storage.size() < cells) {
        return ErrorCode::kStorageTooSmall;
    }
    DepthPyramid p = layout_of(width, height);
    p.min_ = min_storage.subspan(0U, cells);
    p.max_ = max_storage.subspan(0U, cells);
    p.invalid_ = invalid_storage.subspan(0U, cells);
    return p;
}

DepthPyramid DepthPyramid::layout_of(std::int32_t width, std::int32_t height) noexcept {
    DepthPyramid p;
    if (depth_pyramid_cells(width, height) == 0U) {
        return p;
    }
    p.width_ = width;
    p.height_ = height;
    std::int32_t w = width;
    std::int32_t h = height;
    std::size_t offset = 0U;
    for (std::int32_t level = 0; level < kMaxPyramidLevels; ++level) {
        p.level_width_[level] = w;
        p.level_height_[level] = h;
        p.level_offset_[level] = offset;
        p.levels_ = level + 1;
        offset += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        if (w == 1 && h == 1) {
            break;
        }
        w = halve_up(w);
        h = halve_up(h);
    }
    return p;
}

namespace {

/// The or of four invalid flags (each 0 or 1).
std::uint8_t any_of4(std::uint8_t a, std::uint8_t b, std::uint8_t c, std::uint8_t d) noexcept {
    return static_cast<std::uint8_t>(static_cast<unsigned>(a) | static_cast<unsigned>(b) | static_cast<unsigned>(c) |
                                     static_cast<unsigned>(d));
}

/// The rows of one level's cell row and of the two source rows below it.
struct RowSet {
    const float* min0;
    const float* min1;
    const float* max0;
    const float* max1;
    const std::uint8_t* inv0;
    const std::uint8_t* inv1;
    float* min_out;
    float* max_out;
    std::uint8_t* inv_out;
};

/// Cells [@p first, @p pairs) of a row, each from source columns 2i and
/// 2i + 1 of both source rows: min, max, and the or of the invalid flags
/// (each 0 or 1). The reference for the vector forms below.
void reduce_pairs_scalar(const RowSet& r, std::int32_t first, std::int32_t pairs) noexcept {
    for (std::int32_t i = first; i < pairs; ++i) {
        const std::int32_t c0 = 2 * i;
        const std::int32_t c1 = c0 + 1;
        const float mn0 = r.min0[c0] < r.min0[c1] ? r.min0[c0] : r.min0[c1];
        const float mn1 = r.min1[c0] < r.min1[c1] ? r.min1[c0] : r.min1[c1];
        const float mx0 = r.max0[c0] > r.max0[c1] ? r.max0[c0] : r.max0[c1];
        const float mx1 = r.max1[c0] > r.max1[c1] ? r.max1[c0] : r.max1[c1];
        r.min_out[i] = mn0 < mn1 ? mn0 : mn1;
        r.max_out[i] = mx0 > mx1 ? mx0 : mx1;
        r.inv_out[i] = any_of4(r.inv0[c0], r.inv0[c1], r.inv1[c0], r.inv1[c1]);
    }
}

#if defined(__SSE2__) || defined(__ARM_NEON)
/// The or of the invalid flags of columns 2i and 2i + 1 (i = 0..3) of both
/// source rows, into @p out [0..3].
void reduce_flags4(const std::uint8_t* row0, const std::uint8_t* row1, std::uint8_t* out) noexcept {
    for (std::size_t i = 0U; i < 4U; ++i) {
        out[i] = any_of4(row0[2U * i], row0[2U * i + 1U], row1[2U * i], row1[2U * i + 1U]);
    }
}
#endif

/// reduce_pairs_scalar over [0, @p pairs), four cells at a time in vector
/// registers where the target has them (SSE2 on x86-64, NEON on aarch64).
/// min and max of floats that are never NaN (depths or +-inf): the vector
/// instructions give the scalar form's values, bit for bit.
void reduce_pairs(const RowSet& r, std::int32_t pairs) noexcept {
    std::int32_t i = 0;
#if defined(__SSE2__)
    for (; i + 4 <= pairs; i += 4) {
        const std::int32_t c = 2 * i;
        const auto pair_min = [c](const float* p) {
            const __m128 a = _mm_loadu_ps(p + c);
            const __m128 b = _mm_loadu_ps(p + c + 4);
            return _mm_min_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)),
                              _mm_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1)));
        };
        const auto pair_max = [c](const float* p) {
            const __m128 a = _mm_loadu_ps(p + c);
            const __m128 b = _mm_loadu_ps(p + c + 4);
            return _mm_max_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)),
                              _mm_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1)));
        };
        _mm_storeu_ps(r.min_out + i, _mm_min_ps(pair_min(r.min0), pair_min(r.min1)));
        _mm_storeu_ps(r.max_out + i, _mm_max_ps(pair_max(r.max0), pair_max(r.max1)));
        reduce_flags4(r.inv0 + c, r.inv1 + c, r.inv_out + i);
    }
#elif defined(__ARM_NEON)
    for (; i + 4 <= pairs; i += 4) {
        const std::int32_t c = 2 * i;
        const float32x4x2_t mn0 = vld2q_f32(r.min0 + c);  // even and odd columns
        const float32x4x2_t mn1 = vld2q_f32(r.min1 + c);
        const float32x4x2_t mx0 = vld2q_f32(r.max0 + c);
        const float32x4x2_t mx1 = vld2q_f32(r.max1 + c);
        vst1q_f32(r.min_out + i, vminq_f32(vminq_f32(mn0.val[0], mn0.val[1]), vminq_f32(mn1.val[0], mn1.val[1])));
        vst1q_f32(r.max_out + i, vmaxq_f32(vmaxq_f32(mx0.val[0], mx0.val[1]), vmaxq_f32(mx1.val[0], mx1.val[1])));
        reduce_flags4(r.inv0 + c, r.inv1 + c, r.inv_out + i);
    }
#endif
    reduce_pairs_scalar(r, i, pairs);
}

}  // namespace

void DepthPyramid::build_levels() noexcept {
    for (std::int32_t level = 1; level < levels_; ++level) {
        const std::int32_t sw = level_width_[level - 1];
        const std::int32_t sh = level_height_[level - 1];
        const std::size_t src = level_offset_[level - 1];
        const std::size_t dst = level_offset_[level];
        const std::int32_t w = level_width_[level];
        const std::int32_t h = level_height_[level];
        const std::int32_t pairs = sw / 2;  // cells with two source columns; an odd width's last has one
        for (std::int32_t j = 0; j < h; ++j) {
            const std::int32_t r0 = 2 * j;
            const std::int32_t r1 = (r0 + 1 < sh) ? r0 + 1 : r0;
            const std::size_t row0 = src + static_cast<std::size_t>(r0) * static_cast<std::size_t>(sw);
            const std::size_t row1 = src + static_cast<std::size_t>(r1) * static_cast<std::size_t>(sw);
            const std::size_t out = dst + static_cast<std::size_t>(j) * static_cast<std::size_t>(w);
            const RowSet r{&min_[row0],     &min_[row1], &max_[row0], &max_[row1],   &invalid_[row0],
                           &invalid_[row1], &min_[out],  &max_[out],  &invalid_[out]};
            reduce_pairs(r, pairs);
            if (pairs < w) {  // the last source column alone (an odd width)
                const std::size_t c = 2U * static_cast<std::size_t>(pairs);
                const auto o = static_cast<std::size_t>(pairs);
                r.min_out[o] = r.min0[c] < r.min1[c] ? r.min0[c] : r.min1[c];
                r.max_out[o] = r.max0[c] > r.max1[c] ? r.max0[c] : r.max1[c];
                r.inv_out[o] = any_of4(r.inv0[c], r.inv1[c], 0U, 0U);
            }
        }
    }
}

PyramidCells DepthPyramid::cells_of(std::int32_t u0, std::int32_t v0, std::int32_t u1, std::int32_t v1) const noexcept {
    CG_ASSERT(u0 >= 0 && v0 >= 0 && u0 <= u1 && v0 <= v1 && u1 < width_ && v1 < height_, "pyramid query outside");
    // The lowest level whose cells are at least as large as the rectangle:
    // the rectangle then spans at most two cells per axis.
    const std::int32_t extent = (u1 - u0 > v1 - v0 ? u1 - u0 : v1 - v0) + 1;
    // ceil(log2(extent)) by counting the bits of extent - 1, capped at the top level.
    std::int32_t level = 0;
    for (auto e = static_cast<std::uint32_t>(extent - 1); e != 0U; e >>= 1U) {
        ++level;
    }
    level = level < levels_ - 1 ? level : levels_ - 1;
    // Cell indices: the pixel coordinates (>= 0) shifted by the level.
    const auto shift = static_cast<std::uint32_t>(level);
    const std::uint32_t i0 = static_cast<std::uint32_t>(u0) >> shift;
    const std::uint32_t i1 = static_cast<std::uint32_t>(u1) >> shift;
    const std::uint32_t j0 = static_cast<std::uint32_t>(v0) >> shift;
    const std::uint32_t j1 = static_cast<std::uint32_t>(v1) >> shift;
    const auto w = static_cast<std::uint32_t>(level_width_[level]);
    PyramidCells c;
    // At most 4096 x 4096 pixels: fewer than 2^25 cells, a level at most 4096 wide.
    c.first = static_cast<std::uint32_t>(level_offset_[level]) + j0 * w + i0;
    c.col_step = static_cast<std::uint8_t>(i1 - i0);             // 0 or 1
    c.row_step = static_cast<std::uint16_t>(j1 != j0 ? w : 0U);  // one row down, or none
    return c;
}

}  // namespace cellguard
