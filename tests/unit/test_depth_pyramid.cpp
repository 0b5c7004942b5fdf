// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the depth pyramid over caller storage: its size checks and
// refusals (each short span, each bad side), a query over a small image, and
// queries against a scan of the pixels (the levels' vector forms included).
#include <doctest/doctest.h>

#include <array>
#include <limits>
#include <random>
#include <vector>

#include "cellguard/grid/depth_pyramid.hpp"

using namespace cellguard;

// verifies: SR-FUSE-010
TEST_CASE("depth pyramid: sizes outside 1..4096 have no cells and are refused") {
    CHECK(depth_pyramid_cells(1, 1) == 1U);
    CHECK(depth_pyramid_cells(4, 4) == 16U + 4U + 1U);
    CHECK(depth_pyramid_cells(4096, 1) > 4096U);
    CHECK(depth_pyramid_cells(0, 4) == 0U);
    CHECK(depth_pyramid_cells(4, 0) == 0U);
    CHECK(depth_pyramid_cells(-1, 4) == 0U);
    CHECK(depth_pyramid_cells(4097, 4) == 0U);
    CHECK(depth_pyramid_cells(4, 4097) == 0U);
    std::vector<float> lo(64), hi(64);
    std::vector<std::uint8_t> inv(64);
    const Result<DepthPyramid> bad = DepthPyramid::make(0, 4, {lo.data(), lo.size()}, {hi.data(), hi.size()},
                                                        {inv.data(), inv.size()});
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-FUSE-010
TEST_CASE("depth pyramid: each span shorter than its cells is refused") {
    const std::size_t n = depth_pyramid_cells(4, 4);
    std::vector<float> lo(n), hi(n);
    std::vector<std::uint8_t> inv(n);
    CHECK(DepthPyramid::make(4, 4, {lo.data(), n - 1U}, {hi.data(), n}, {inv.data(), n}).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(DepthPyramid::make(4, 4, {lo.data(), n}, {hi.data(), n - 1U}, {inv.data(), n}).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(DepthPyramid::make(4, 4, {lo.data(), n}, {hi.data(), n}, {inv.data(), n - 1U}).error() ==
          ErrorCode::kStorageTooSmall);
    Result<DepthPyramid> ok = DepthPyramid::make(4, 4, {lo.data(), n}, {hi.data(), n}, {inv.data(), n});
    REQUIRE(ok.ok());
    DepthPyramid p = ok.value();
    for (std::int32_t v = 0; v < 4; ++v) {
        for (std::int32_t u = 0; u < 4; ++u) {
            p.set_pixel(u, v, 1.0F + static_cast<float>(u + 4 * v), !(u == 3 && v == 3));
        }
    }
    p.build_levels();
    const DepthRange all = p.query(0, 0, 3, 3);
    CHECK(all.min == doctest::Approx(1.0));
    CHECK(all.max == doctest::Approx(15.0));
    CHECK(all.any_invalid);
    const DepthRange one = p.query(1, 1, 1, 1);
    CHECK(one.min <= 6.0F);
    CHECK(one.max >= 6.0F);
}

// verifies: SR-FUSE-014
TEST_CASE("depth pyramid: a layout without storage has the levels' cells, and none for an invalid size") {
    const DepthPyramid layout = DepthPyramid::layout_of(13, 7);
    CHECK(layout.width() == 13);
    CHECK(layout.height() == 7);
    std::vector<float> mn(depth_pyramid_cells(13, 7));
    std::vector<float> mx(mn.size());
    std::vector<std::uint8_t> inv(mn.size());
    const DepthPyramid real =
        DepthPyramid::make(13, 7, {mn.data(), mn.size()}, {mx.data(), mx.size()}, {inv.data(), inv.size()}).value();
    for (std::int32_t v0 = 0; v0 < 7; ++v0) {
        for (std::int32_t u0 = 0; u0 < 13; u0 += 3) {
            const PyramidCells a = layout.cells_of(u0, v0, 12, 6);
            const PyramidCells b = real.cells_of(u0, v0, 12, 6);
            CHECK(a.first == b.first);
            CHECK(a.row_step == b.row_step);
            CHECK(a.col_step == b.col_step);
        }
    }
    for (const auto& size : {std::array<std::int32_t, 2>{0, 7}, std::array<std::int32_t, 2>{13, -1},
                             std::array<std::int32_t, 2>{5000, 7}}) {
        const DepthPyramid none = DepthPyramid::layout_of(size[0], size[1]);
        CHECK(none.width() == 0);
        CHECK(none.height() == 0);
    }
}

// verifies: SR-FUSE-010
TEST_CASE(
    "depth pyramid: every query covers its rectangle's min, max and gaps, and an aligned block gives them exactly") {
    // Sizes with odd sides at several levels (the last column or row of a level alone),
    // and one wider than the vector forms' four cells; a third of the pixels without a reading.
    std::mt19937 rng(34U);
    std::uniform_real_distribution<float> depth(0.3F, 9.0F);
    for (const auto& size :
         {std::array<std::int32_t, 2>{37, 23}, std::array<std::int32_t, 2>{64, 48}, std::array<std::int32_t, 2>{13, 1},
          std::array<std::int32_t, 2>{1, 9}, std::array<std::int32_t, 2>{97, 31}}) {
        const std::int32_t w = size[0];
        const std::int32_t h = size[1];
        CAPTURE(w);
        CAPTURE(h);
        std::vector<float> mn(depth_pyramid_cells(w, h));
        std::vector<float> mx(mn.size());
        std::vector<std::uint8_t> inv(mn.size());
        DepthPyramid p =
            DepthPyramid::make(w, h, {mn.data(), mn.size()}, {mx.data(), mx.size()}, {inv.data(), inv.size()}).value();
        std::vector<float> image(static_cast<std::size_t>(w * h));
        for (std::int32_t v = 0; v < h; ++v) {
            for (std::int32_t u = 0; u < w; ++u) {
                const bool valid = rng() % 3U != 0U;
                const float d = depth(rng);
                image[static_cast<std::size_t>(v * w + u)] = valid ? d : -1.0F;
                p.set_pixel(u, v, d, valid);
            }
        }
        p.build_levels();
        const auto truth = [&](std::int32_t u0, std::int32_t v0, std::int32_t u1, std::int32_t v1) {
            DepthRange t{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), false};
            for (std::int32_t v = v0; v <= v1; ++v) {
                for (std::int32_t u = u0; u <= u1; ++u) {
                    const float d = image[static_cast<std::size_t>(v * w + u)];
                    t.any_invalid = t.any_invalid || d < 0.0F;
                    t.min = d >= 0.0F && d < t.min ? d : t.min;
                    t.max = d >= 0.0F && d > t.max ? d : t.max;
                }
            }
            return t;
        };
        for (int k = 0; k < 400; ++k) {
            const auto u0 = static_cast<std::int32_t>(rng() % static_cast<unsigned>(w));
            const auto v0 = static_cast<std::int32_t>(rng() % static_cast<unsigned>(h));
            const auto u1 = u0 + static_cast<std::int32_t>(rng() % static_cast<unsigned>(w - u0));
            const auto v1 = v0 + static_cast<std::int32_t>(rng() % static_cast<unsigned>(h - v0));
            const DepthRange q = p.query(u0, v0, u1, v1);
            const DepthRange t = truth(u0, v0, u1, v1);
            CHECK(q.min <= t.min);
            CHECK(q.max >= t.max);
            CHECK((q.any_invalid || !t.any_invalid));
        }
        // A block of 2^L x 2^L pixels aligned to level L is one cell of that level: exactly its values.
        for (std::int32_t side = 1; side <= w && side <= h; side *= 2) {
            for (std::int32_t v0 = 0; v0 + side <= h; v0 += side) {
                for (std::int32_t u0 = 0; u0 + side <= w; u0 += side) {
                    const DepthRange q = p.query(u0, v0, u0 + side - 1, v0 + side - 1);
                    const DepthRange t = truth(u0, v0, u0 + side - 1, v0 + side - 1);
                    CHECK(q.min == t.min);
                    CHECK(q.max == t.max);
                    CHECK(q.any_invalid == t.any_invalid);
                }
            }
        }
    }
}

// verifies: SR-FUSE-015
TEST_CASE("depth pyramid: four valid readings set at once are four set_pixel calls, bit for bit") {
    // Over pixels that held gaps and readings before, at the row's start, middle and end.
    const std::int32_t w = 11;
    const std::int32_t h = 3;
    const std::size_t cells = depth_pyramid_cells(w, h);
    std::vector<float> mn_a(cells), mx_a(cells), mn_b(cells), mx_b(cells);
    std::vector<std::uint8_t> inv_a(cells), inv_b(cells);
    DepthPyramid a =
        DepthPyramid::make(w, h, {mn_a.data(), cells}, {mx_a.data(), cells}, {inv_a.data(), cells}).value();
    DepthPyramid b =
        DepthPyramid::make(w, h, {mn_b.data(), cells}, {mx_b.data(), cells}, {inv_b.data(), cells}).value();
    for (std::int32_t v = 0; v < h; ++v) {
        for (std::int32_t u = 0; u < w; ++u) {
            a.set_pixel(u, v, 0.5F + 0.01F * static_cast<float>(u), (u + v) % 2 == 0);
            b.set_pixel(u, v, 0.5F + 0.01F * static_cast<float>(u), (u + v) % 2 == 0);
        }
    }
    const std::array<float, 4> d{1.25F, 7.5F, 0.3F, 2.0F};
    for (const std::array<std::int32_t, 2> at :
         {std::array<std::int32_t, 2>{0, 0}, std::array<std::int32_t, 2>{3, 1}, std::array<std::int32_t, 2>{7, 2}}) {
        a.set_valid4(at[0], at[1], d);
        for (std::int32_t k = 0; k < 4; ++k) {
            b.set_pixel(at[0] + k, at[1], d[static_cast<std::size_t>(k)], true);
        }
    }
    a.build_levels();
    b.build_levels();
    CHECK(mn_a == mn_b);
    CHECK(mx_a == mx_b);
    CHECK(inv_a == inv_b);
    for (std::int32_t k = 0; k < 4; ++k) {
        CHECK(a.depth(7 + k, 2) == d[static_cast<std::size_t>(k)]);  // where set_pixel had left gaps too
    }
}
