// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: one pass with the 6-neighbour cross computes min / max over
// the cross on the region only; r passes equal the L1 ball of radius r.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

#include "cellguard/prior/morphology.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

PaddedRegion region_of(GridDims array, VoxelCoord first, GridDims size) {
    PaddedRegion r;
    r.array = array;
    r.first = first;
    r.size = size;
    return r;
}

std::size_t index(const PaddedRegion& r, int x, int y, int z) {
    return static_cast<std::size_t>(x + r.array.nx * (y + r.array.ny * z));
}

bool in_region(const PaddedRegion& r, int x, int y, int z) {
    return x >= r.first.x && y >= r.first.y && z >= r.first.z && x < r.first.x + r.size.nx &&
           y < r.first.y + r.size.ny && z < r.first.z + r.size.nz;
}

}  // namespace

// verifies: SR-PRIOR-001
TEST_CASE("morphology: a cross pass is min or max over the voxel and its six neighbours, on the region only") {
    std::mt19937 rng(3U);
    // Rows shorter than a block, a multiple of the uint32 block, and longer
    // than the uint8 block with an overlapping last block.
    for (const PaddedRegion& r : {region_of(GridDims{9, 7, 6}, VoxelCoord{2, 1, 1}, GridDims{5, 4, 3}),
                                  region_of(GridDims{19, 5, 4}, VoxelCoord{1, 1, 1}, GridDims{16, 3, 2}),
                                  region_of(GridDims{45, 5, 4}, VoxelCoord{2, 1, 1}, GridDims{41, 3, 2})}) {
        REQUIRE(r.valid());
        const std::size_t n = r.array_voxel_count();
        std::vector<std::uint8_t> in8(n);
        std::vector<std::uint32_t> in32(n);
        for (std::size_t i = 0; i < n; ++i) {
            in8[i] = static_cast<std::uint8_t>(rng() % 4U);
            in32[i] = rng();
        }
        std::vector<std::uint8_t> eroded(n, 99U);
        std::vector<std::uint8_t> dilated(n, 99U);
        std::vector<std::uint32_t> minimum(n, 99U);
        erode_cross(r, Span<const std::uint8_t>(in8.data(), n), Span<std::uint8_t>(eroded.data(), n));
        dilate_cross(r, Span<const std::uint8_t>(in8.data(), n), Span<std::uint8_t>(dilated.data(), n));
        min_cross(r, Span<const std::uint32_t>(in32.data(), n), Span<std::uint32_t>(minimum.data(), n));
        const int d[7][3] = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (int z = 0; z < r.array.nz; ++z) {
            for (int y = 0; y < r.array.ny; ++y) {
                for (int x = 0; x < r.array.nx; ++x) {
                    const std::size_t i = index(r, x, y, z);
                    if (!in_region(r, x, y, z)) {
                        CHECK(eroded[i] == 99U);
                        CHECK(dilated[i] == 99U);
                        CHECK(minimum[i] == 99U);
                        continue;
                    }
                    std::uint8_t lo = 255U;
                    std::uint8_t hi = 0U;
                    std::uint32_t lo32 = 0xFFFFFFFFU;
                    for (const auto& o : d) {
                        const std::size_t j = index(r, x + o[0], y + o[1], z + o[2]);
                        lo = std::min(lo, in8[j]);
                        hi = std::max(hi, in8[j]);
                        lo32 = std::min(lo32, in32[j]);
                    }
                    CHECK(eroded[i] == lo);
                    CHECK(dilated[i] == hi);
                    CHECK(minimum[i] == lo32);
                }
            }
        }
    }
}

// verifies: SR-PRIOR-001
TEST_CASE("morphology: r cross passes give the minimum over the L1 ball of radius r") {
    std::mt19937 rng(11U);
    const PaddedRegion r = region_of(GridDims{14, 13, 12}, VoxelCoord{1, 1, 1}, GridDims{12, 11, 10});
    const std::size_t n = r.array_voxel_count();
    for (int radius = 1; radius <= 3; ++radius) {
        std::vector<std::uint32_t> in(n);
        for (auto& v : in)
            v = rng() % 1000U;
        std::vector<std::uint32_t> a = in;
        std::vector<std::uint32_t> b = in;
        for (int k = 0; k < radius; ++k) {
            min_cross(r, Span<const std::uint32_t>(a.data(), n), Span<std::uint32_t>(b.data(), n));
            std::swap(a, b);
        }
        for (int z = 0; z < r.array.nz; ++z) {
            for (int y = 0; y < r.array.ny; ++y) {
                for (int x = 0; x < r.array.nx; ++x) {
                    // Only voxels whose whole ball lies in the region.
                    if (!in_region(r, x - radius, y, z) || !in_region(r, x + radius, y, z) ||
                        !in_region(r, x, y - radius, z) || !in_region(r, x, y + radius, z) ||
                        !in_region(r, x, y, z - radius) || !in_region(r, x, y, z + radius)) {
                        continue;
                    }
                    std::uint32_t lo = 0xFFFFFFFFU;
                    for (int dz = -radius; dz <= radius; ++dz) {
                        for (int dy = -radius; dy <= radius; ++dy) {
                            for (int dx = -radius; dx <= radius; ++dx) {
                                if (std::abs(dx) + std::abs(dy) + std::abs(dz) <= radius) {
                                    lo = std::min(lo, in[index(r, x + dx, y + dy, z + dz)]);
                                }
                            }
                        }
                    }
                    CHECK(a[index(r, x, y, z)] == lo);
                }
            }
        }
    }
}

// verifies: SR-PRIOR-001, SR-GEN-003
TEST_CASE("morphology: a region without a surrounding layer, small storage or overlapping arrays violate contracts") {
    std::vector<std::uint8_t> a(5U * 5U * 5U);
    std::vector<std::uint8_t> b(5U * 5U * 5U);
    const Span<const std::uint8_t> in(a.data(), a.size());
    const Span<std::uint8_t> out(b.data(), b.size());
    const PaddedRegion good = region_of(GridDims{5, 5, 5}, VoxelCoord{1, 1, 1}, GridDims{3, 3, 3});
    const PaddedRegion touching = region_of(GridDims{5, 5, 5}, VoxelCoord{0, 1, 1}, GridDims{3, 3, 3});
    const PaddedRegion too_wide = region_of(GridDims{5, 5, 5}, VoxelCoord{1, 1, 1}, GridDims{4, 3, 3});
    CHECK_FALSE(touching.valid());
    CHECK_FALSE(too_wide.valid());
    CHECK_FALSE(test::violates_contract([&] { erode_cross(good, in, out); }));
    CHECK(test::violates_contract([&] { erode_cross(touching, in, out); }));
    CHECK(test::violates_contract([&] { dilate_cross(too_wide, in, out); }));
    CHECK(test::violates_contract([&] { erode_cross(good, in, Span<std::uint8_t>(b.data(), 124U)); }));
    std::vector<std::uint8_t> c(260U);
    CHECK(test::violates_contract(
        [&] { erode_cross(good, Span<const std::uint8_t>(c.data(), 125U), Span<std::uint8_t>(c.data() + 1, 125U)); }));
    CHECK_FALSE(test::violates_contract([&] {
        erode_cross(good, Span<const std::uint8_t>(c.data(), 125U), Span<std::uint8_t>(c.data() + 125, 125U));
    }));
}

// verifies: SR-PRIOR-001
TEST_CASE("morphology: a region is valid only with a box of at least one voxel and a layer on all six sides") {
    const GridDims array{6, 6, 6};
    CHECK(region_of(array, {1, 1, 1}, {4, 4, 4}).valid());
    CHECK_FALSE(region_of(array, {1, 1, 1}, {0, 4, 4}).valid());
    CHECK_FALSE(region_of(array, {1, 1, 1}, {4, 0, 4}).valid());
    CHECK_FALSE(region_of(array, {1, 1, 1}, {4, 4, 0}).valid());
    CHECK_FALSE(region_of(array, {0, 1, 1}, {4, 4, 4}).valid());
    CHECK_FALSE(region_of(array, {1, 0, 1}, {4, 4, 4}).valid());
    CHECK_FALSE(region_of(array, {1, 1, 0}, {4, 4, 4}).valid());
    CHECK_FALSE(region_of(array, {2, 1, 1}, {4, 4, 4}).valid());  // no layer beyond x
    CHECK_FALSE(region_of(array, {1, 2, 1}, {4, 4, 4}).valid());  // no layer beyond y
    CHECK_FALSE(region_of(array, {1, 1, 2}, {4, 4, 4}).valid());  // no layer beyond z
    CHECK(region_of(array, {1, 1, 1}, {4, 4, 4}).array_voxel_count() == 216U);
    CHECK(region_of({0, 6, 6}, {1, 1, 1}, {4, 4, 4}).array_voxel_count() == 0U);
    CHECK(region_of({6, -1, 6}, {1, 1, 1}, {4, 4, 4}).array_voxel_count() == 0U);
    CHECK(region_of({6, 6, 0}, {1, 1, 1}, {4, 4, 4}).array_voxel_count() == 0U);
}

// verifies: SR-PRIOR-001, SR-GEN-003
TEST_CASE("morphology: an input smaller than the array violates the contract, for 8-bit and 32-bit values") {
    const PaddedRegion good = region_of(GridDims{5, 5, 5}, VoxelCoord{1, 1, 1}, GridDims{3, 3, 3});
    std::vector<std::uint8_t> a(125U);
    std::vector<std::uint8_t> b(125U);
    CHECK(test::violates_contract(
        [&] { dilate_cross(good, Span<const std::uint8_t>(a.data(), 124U), Span<std::uint8_t>(b.data(), 125U)); }));
    std::vector<std::uint32_t> w(125U, 7U);
    std::vector<std::uint32_t> v(125U, 0U);
    CHECK(test::violates_contract(
        [&] { min_cross(good, Span<const std::uint32_t>(w.data(), 124U), Span<std::uint32_t>(v.data(), 125U)); }));
    CHECK(test::violates_contract(
        [&] { min_cross(good, Span<const std::uint32_t>(w.data(), 125U), Span<std::uint32_t>(v.data(), 124U)); }));
    CHECK_FALSE(test::violates_contract(
        [&] { min_cross(good, Span<const std::uint32_t>(w.data(), 125U), Span<std::uint32_t>(v.data(), 125U)); }));
    CHECK(v[static_cast<std::size_t>(2 + 5 * (2 + 5 * 2))] == 7U);  // the box's centre: the minimum of sevens
}
