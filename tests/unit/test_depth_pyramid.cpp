// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the depth pyramid over caller storage: its size checks and
// refusals (each short span, each bad side), and a query over a small image.
#include <doctest/doctest.h>

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
