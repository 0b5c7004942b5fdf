// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/prior/morphology.hpp"

#include <algorithm>
#include <functional>

namespace cellguard {

namespace {

struct Minimum {
    template <typename T>
    static T apply(T a, T b) noexcept {
        return std::min(a, b);
    }
};
struct Maximum {
    template <typename T>
    static T apply(T a, T b) noexcept {
        return std::max(a, b);
    }
};

template <typename T>
void check_arguments(const PaddedRegion& region, Span<const T> in, Span<T> out) noexcept {
    CG_ENFORCE(region.valid(), "morphology: region without a surrounding layer inside the array");
    const std::size_t count = region.array_voxel_count();
    CG_ENFORCE(in.size() >= count && out.size() >= count, "morphology: array storage smaller than the array");
    const T* const in_end = in.data() + count;
    const T* const out_end = out.data() + count;
    const std::less<const T*> before;  // a total order, also across arrays
    CG_ENFORCE(!before(out.data(), in_end) || !before(in.data(), out_end), "morphology: input and output overlap");
}

// Values per block of the inner loop: a fixed trip count lets the compiler
// vectorise it even at -O2 (GCC's "very cheap" cost model).
constexpr std::size_t kBlockBytes = 32U;

// One pass with the cross; Op folds two values (min or max). Rows along x
// are contiguous, so the inner loop reads seven rows with unit stride.
template <typename Op, typename T>
void cross_pass(const PaddedRegion& region, Span<const T> in, Span<T> out) noexcept {
    check_arguments(region, in, out);
    constexpr std::size_t kBlock = kBlockBytes / sizeof(T);
    const auto ax = static_cast<std::size_t>(region.array.nx);
    const auto ay = static_cast<std::size_t>(region.array.ny);
    const std::size_t sy = ax;
    const std::size_t sz = ax * ay;
    const auto x0 = static_cast<std::size_t>(region.first.x);
    const auto width = static_cast<std::size_t>(region.size.nx);
    auto fold = [](const T* c, const T* north, const T* south, const T* up, const T* down, std::size_t i) noexcept {
        const T a = Op::apply(Op::apply(c[i - 1U], c[i]), c[i + 1U]);
        const T b = Op::apply(north[i], south[i]);
        const T d = Op::apply(up[i], down[i]);
        return Op::apply(a, Op::apply(b, d));
    };
    for (std::int32_t z = region.first.z; z < region.first.z + region.size.nz; ++z) {
        for (std::int32_t y = region.first.y; y < region.first.y + region.size.ny; ++y) {
            const std::size_t row = x0 + ax * (static_cast<std::size_t>(y) + ay * static_cast<std::size_t>(z));
            // Row pointers start one voxel early so that index i - 1 >= 0.
            const T* const c = in.data() + row - 1U;
            const T* const north = c + sy;
            const T* const south = c - sy;
            const T* const up = c + sz;
            const T* const down = c - sz;
            T* const o = out.data() + row - 1U;
            auto block = [&](std::size_t i) noexcept {
                T values[kBlock];
                for (std::size_t k = 0U; k < kBlock; ++k) {
                    values[k] = fold(c, north, south, up, down, i + k);
                }
                for (std::size_t k = 0U; k < kBlock; ++k) {
                    o[i + k] = values[k];
                }
            };
            if (width < kBlock) {
                for (std::size_t i = 1U; i <= width; ++i) {
                    o[i] = fold(c, north, south, up, down, i);
                }
                continue;
            }
            // Blocks of kBlock; a row that is not a multiple of kBlock ends
            // with a block overlapping the previous one (out is not in).
            for (std::size_t i = 1U; i + kBlock <= width + 1U; i += kBlock) {
                block(i);
            }
            if (width % kBlock != 0U) {
                block(width + 1U - kBlock);
            }
        }
    }
}

}  // namespace

void erode_cross(const PaddedRegion& region, Span<const std::uint8_t> in, Span<std::uint8_t> out) noexcept {
    cross_pass<Minimum>(region, in, out);
}

void dilate_cross(const PaddedRegion& region, Span<const std::uint8_t> in, Span<std::uint8_t> out) noexcept {
    cross_pass<Maximum>(region, in, out);
}

void min_cross(const PaddedRegion& region, Span<const std::uint32_t> in, Span<std::uint32_t> out) noexcept {
    cross_pass<Minimum>(region, in, out);
}

}  // namespace cellguard
