// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file depth_pyramid.hpp
/// Min/max pyramids of one depth image, so that footprint fusion
/// (footprint_fusion.hpp) learns the nearest and farthest reading in any
/// pixel rectangle, and whether it holds a pixel without a reading, in
/// constant time.
///
/// Level 0 is the image: a pixel's depth (metres, along the optical axis) in
/// both pyramids when it holds a valid reading, else +inf in the min pyramid,
/// -inf in the max pyramid and a 1 in the invalid pyramid. Level L + 1 holds
/// per cell the min, the max and the OR of the 2 x 2 cells of level L below
/// it (a cell at an odd edge covers 1 or 2). Level L's cell (i, j) thus
/// covers pixels [i * 2^L, (i + 1) * 2^L) x [j * 2^L, (j + 1) * 2^L).
///
/// query() answers for a superset of the asked rectangle: the at most 2 x 2
/// cells of the lowest level whose cell is at least as large as the
/// rectangle. Its min is at most, and its max at least, the rectangle's
/// own; its invalid flag is set when the rectangle's is. Every decision
/// footprint fusion takes from a query is therefore on the safe side of the
/// rectangle's true values (see there). Storage is the caller's.
#ifndef CELLGUARD_DEPTH_PYRAMID_HPP
#define CELLGUARD_DEPTH_PYRAMID_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "cellguard/base/contract.hpp"
#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"

namespace cellguard {

/// Most levels of a pyramid (level 0 = the image; 2^12 > kMaxDimension of an image side).
constexpr std::int32_t kMaxPyramidLevels = 13;

/// What a pyramid query found over (a superset of) a rectangle.
struct DepthRange {
    float min = 0.0F;          ///< nearest valid reading; +inf when none
    float max = 0.0F;          ///< farthest valid reading; -inf when none
    bool any_invalid = false;  ///< some pixel has no valid reading
    /// True when no pixel has a valid reading.
    [[nodiscard]] bool empty() const noexcept { return !(min <= max); }
};

/// The at most 2 x 2 cells a query reads (see DepthPyramid::cells_of): the
/// first cell's index into the storage, and the steps to the cell on its
/// right (0 or 1) and below it (0 or its level's width). A function of the
/// rectangle and the image size, not of the depths: footprint tables
/// (footprint_fusion.hpp) keep it per voxel.
struct PyramidCells {
    std::uint32_t first = 0U;     ///< storage index of the top-left cell
    std::uint16_t row_step = 0U;  ///< to the cell below: 0 (one row) or the level's width
    std::uint8_t col_step = 0U;   ///< to the cell on the right: 0 (one column) or 1
};

/// Cells of all levels of a pyramid over a @p width x @p height image: the
/// size of each of the three storage spans (0 for a non-positive size).
[[nodiscard]] std::size_t depth_pyramid_cells(std::int32_t width, std::int32_t height) noexcept;

/// Min/max pyramids over caller storage (see the file comment).
class DepthPyramid {
public:
    /// A pyramid with no storage (placeholder only).
    DepthPyramid() noexcept = default;

    /// Binds storage for a @p width x @p height image. Errors:
    /// kInvalidArgument for a non-positive size or a side above 4096,
    /// kStorageTooSmall when a span holds fewer than depth_pyramid_cells().
    static Result<DepthPyramid> make(std::int32_t width, std::int32_t height, Span<float> min_storage,
                                     Span<float> max_storage, Span<std::uint8_t> invalid_storage) noexcept;

    /// The level layout of a @p width x @p height image without storage: only
    /// cells_of(), width() and height() may be called on it (footprint tables
    /// are made from it). A placeholder for an invalid size.
    [[nodiscard]] static DepthPyramid layout_of(std::int32_t width, std::int32_t height) noexcept;

    /// Level 0, written by the caller: pixel (u, v) holds depth @p d (valid
    /// reading) or none (@p valid false).
    void set_pixel(std::int32_t u, std::int32_t v, float d, bool valid) noexcept {
        const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(width_) +
                              static_cast<std::size_t>(u);
        min_[i] = valid ? d : std::numeric_limits<float>::infinity();
        max_[i] = valid ? d : -std::numeric_limits<float>::infinity();
        invalid_[i] = static_cast<std::uint8_t>(valid ? 0U : 1U);
    }
    /// Sets pixels (@p u .. @p u + 3, @p v) of level 0 to four valid readings
    /// @p d, as four calls of set_pixel (u + 3 < width: checked by CG_ASSERT).
    void set_valid4(std::int32_t u, std::int32_t v, const std::array<float, 4>& d) noexcept {
        CG_ASSERT(u >= 0 && u + 3 < width_ && v >= 0 && v < height_, "depth pyramid: four pixels outside the image");
        const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(width_) +
                              static_cast<std::size_t>(u);
        std::memcpy(&min_[i], d.data(), sizeof d);
        std::memcpy(&max_[i], d.data(), sizeof d);
        std::memset(&invalid_[i], 0, 4U);
    }
    /// Builds levels 1.. from level 0. Work: fewer than depth_pyramid_cells() cells.
    void build_levels() noexcept;

    /// Min, max and the invalid flag over a superset of pixel rectangle
    /// [u0, u1] x [v0, v1] (inclusive, 0 <= u0 <= u1 < width, same for v:
    /// checked by CG_ASSERT). Constant time: at most four cells.
    [[nodiscard]] DepthRange query(std::int32_t u0, std::int32_t v0, std::int32_t u1, std::int32_t v1) const noexcept {
        return query(cells_of(u0, v0, u1, v1));
    }
    /// The cells query() reads for pixel rectangle [u0, u1] x [v0, v1] (same
    /// precondition): those of the lowest level whose cells are at least as
    /// large as the rectangle.
    [[nodiscard]] PyramidCells cells_of(std::int32_t u0, std::int32_t v0, std::int32_t u1,
                                        std::int32_t v1) const noexcept;
    /// Min, max and the invalid flag over @p c (from cells_of() of a pyramid of
    /// the same image size). Four cell reads, no branch.
    [[nodiscard]] DepthRange query(const PyramidCells& c) const noexcept {
        const std::size_t a = c.first;
        const std::size_t b = a + c.col_step;
        const std::size_t e = a + c.row_step;
        const std::size_t f = e + c.col_step;
        const float mn0 = min_[a] < min_[b] ? min_[a] : min_[b];
        const float mn1 = min_[e] < min_[f] ? min_[e] : min_[f];
        const float mx0 = max_[a] > max_[b] ? max_[a] : max_[b];
        const float mx1 = max_[e] > max_[f] ? max_[e] : max_[f];
        const unsigned any = static_cast<unsigned>(invalid_[a]) | static_cast<unsigned>(invalid_[b]) |
                             static_cast<unsigned>(invalid_[e]) | static_cast<unsigned>(invalid_[f]);
        return DepthRange{mn0 < mn1 ? mn0 : mn1, mx0 > mx1 ? mx0 : mx1, any != 0U};
    }

    /// Level-0 depth of pixel (u, v), or +inf when it has no valid reading.
    [[nodiscard]] float depth(std::int32_t u, std::int32_t v) const noexcept {
        return min_[static_cast<std::size_t>(v) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(u)];
    }
    /// Image columns.
    [[nodiscard]] std::int32_t width() const noexcept { return width_; }
    /// Image rows.
    [[nodiscard]] std::int32_t height() const noexcept { return height_; }

private:
    static constexpr float kInfinity = std::numeric_limits<float>::infinity();
    std::int32_t width_ = 0;
    std::int32_t height_ = 0;
    std::int32_t levels_ = 0;
    std::int32_t level_width_[kMaxPyramidLevels] = {};
    std::int32_t level_height_[kMaxPyramidLevels] = {};
    std::size_t level_offset_[kMaxPyramidLevels] = {};
    Span<float> min_{};
    Span<float> max_{};
    Span<std::uint8_t> invalid_{};
};

}  // namespace cellguard

#endif  // CELLGUARD_DEPTH_PYRAMID_HPP
