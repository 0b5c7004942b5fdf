// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/depth_pyramid.hpp"

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

void DepthPyramid::build_levels() noexcept {
    for (std::int32_t level = 1; level < levels_; ++level) {
        const std::int32_t sw = level_width_[level - 1];
        const std::int32_t sh = level_height_[level - 1];
        const std::size_t src = level_offset_[level - 1];
        const std::size_t dst = level_offset_[level];
        const std::int32_t w = level_width_[level];
        const std::int32_t h = level_height_[level];
        for (std::int32_t j = 0; j < h; ++j) {
            const std::int32_t r0 = 2 * j;
            const std::int32_t r1 = (r0 + 1 < sh) ? r0 + 1 : r0;
            const std::size_t row0 = src + static_cast<std::size_t>(r0) * static_cast<std::size_t>(sw);
            const std::size_t row1 = src + static_cast<std::size_t>(r1) * static_cast<std::size_t>(sw);
            const std::size_t out = dst + static_cast<std::size_t>(j) * static_cast<std::size_t>(w);
            for (std::int32_t i = 0; i < w; ++i) {
                const auto c0 = static_cast<std::size_t>(i) * 2U;
                const std::size_t c1 = (2 * i + 1 < sw) ? c0 + 1U : c0;
                const float mn0 = min_[row0 + c0] < min_[row0 + c1] ? min_[row0 + c0] : min_[row0 + c1];
                const float mn1 = min_[row1 + c0] < min_[row1 + c1] ? min_[row1 + c0] : min_[row1 + c1];
                const float mx0 = max_[row0 + c0] > max_[row0 + c1] ? max_[row0 + c0] : max_[row0 + c1];
                const float mx1 = max_[row1 + c0] > max_[row1 + c1] ? max_[row1 + c0] : max_[row1 + c1];
                const std::size_t o = out + static_cast<std::size_t>(i);
                min_[o] = mn0 < mn1 ? mn0 : mn1;
                max_[o] = mx0 > mx1 ? mx0 : mx1;
                const bool any = invalid_[row0 + c0] != 0U || invalid_[row0 + c1] != 0U || invalid_[row1 + c0] != 0U ||
                                 invalid_[row1 + c1] != 0U;
                invalid_[o] = static_cast<std::uint8_t>(any ? 1U : 0U);
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
