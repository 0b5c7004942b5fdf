// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The direction grid of a point-set sensor (direction_grid.hpp): which grids
// check_direction_grid refuses and with which error, which points
// direction_bin leaves out (outside each edge of the field of view, without
// a finite range), and add_to_direction_view's refusals.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cellguard/grid/direction_grid.hpp"

using namespace cellguard;

namespace {

constexpr float kDegree = 0.017453292F;

// 10 x 10 bins of one degree around the axis (as test_background_points' SmallView).
DirectionGrid small_grid() { return DirectionGrid{-5.0F * kDegree, -5.0F * kDegree, kDegree, 10U, 10U}; }

// A point at @p range along azimuth @p az_deg and elevation @p el_deg (sensor frame).
Eigen::Vector3f along(float az_deg, float el_deg, float range) {
    const float az = az_deg * kDegree;
    const float el = el_deg * kDegree;
    return {range * std::cos(el) * std::sin(az), -range * std::sin(el), range * std::cos(el) * std::cos(az)};
}

}  // namespace

// verifies: SR-BKG-007
TEST_CASE("direction grid: each non-finite edge or bin size is refused as a non-finite value") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    REQUIRE(check_direction_grid(small_grid()).ok());
    DirectionGrid g = small_grid();
    g.azimuth_min_rad = -inf;
    CHECK(check_direction_grid(g).error() == ErrorCode::kNonFiniteValue);
    g = small_grid();
    g.elevation_min_rad = nan;
    CHECK(check_direction_grid(g).error() == ErrorCode::kNonFiniteValue);
    g = small_grid();
    g.bin_rad = inf;
    CHECK(check_direction_grid(g).error() == ErrorCode::kNonFiniteValue);
    g = small_grid();
    g.bin_rad = nan;
    CHECK(check_direction_grid(g).error() == ErrorCode::kNonFiniteValue);
}

// verifies: SR-BKG-007
TEST_CASE("direction grid: no bins either way, a negative bin or a field of view beyond any edge is refused") {
    DirectionGrid g = small_grid();
    g.bin_rad = -kDegree;
    CHECK(check_direction_grid(g).error() == ErrorCode::kInvalidArgument);
    g = small_grid();
    g.azimuth_bins = 0U;
    CHECK(check_direction_grid(g).error() == ErrorCode::kInvalidArgument);
    g = small_grid();
    g.elevation_bins = 0U;
    CHECK(check_direction_grid(g).error() == ErrorCode::kInvalidArgument);
    // Azimuth starts left of -pi.
    g = small_grid();
    g.azimuth_min_rad = -3.2F;
    CHECK(check_direction_grid(g).error() == ErrorCode::kInvalidArgument);
    // Elevation starts below -pi/2, or ends above pi/2.
    g = small_grid();
    g.elevation_min_rad = -1.6F;
    CHECK(check_direction_grid(g).error() == ErrorCode::kInvalidArgument);
    g = small_grid();
    g.elevation_min_rad = 1.5F;  // + 10 degrees > pi/2
    CHECK(check_direction_grid(g).error() == ErrorCode::kInvalidArgument);
    // The whole sphere in 0.5 degree bins is accepted (the edges' rounding within the slack).
    const DirectionGrid sphere{-3.14159265F, -1.57079633F, 0.5F * kDegree, 720U, 360U};
    CHECK(check_direction_grid(sphere).ok());
}

// verifies: SR-BKG-007
TEST_CASE("direction grid: a point beyond each edge of the field of view has no bin but keeps its range") {
    const DirectionGrid g = small_grid();
    float range = -1.0F;
    CHECK(direction_bin(g, along(0.5F, 0.5F, 2.0F), range) == 55U);
    CHECK(range == doctest::Approx(2.0F));
    struct Case {
        float az;
        float el;
    };
    for (const Case c : {Case{-5.5F, 0.5F}, Case{5.5F, 0.5F}, Case{0.5F, -5.5F}, Case{0.5F, 5.5F}}) {
        CAPTURE(c.az);
        CAPTURE(c.el);
        range = -1.0F;
        CHECK(direction_bin(g, along(c.az, c.el, 3.0F), range) == kNoDirectionBin);
        CHECK(range == doctest::Approx(3.0F));
    }
    // The first and last bin of each axis.
    CHECK(direction_bin(g, along(-4.5F, -4.5F, 1.0F), range) == 0U);
    CHECK(direction_bin(g, along(4.5F, 4.5F, 1.0F), range) == 99U);
}

// verifies: SR-BKG-007
TEST_CASE("direction grid: a point whose range overflows a float has no bin and no range") {
    const DirectionGrid g = small_grid();
    float range = -1.0F;
    // Finite coordinates whose squares overflow: the range is not finite.
    CHECK(direction_bin(g, Eigen::Vector3f(0.0F, 0.0F, 3e38F), range) == kNoDirectionBin);
    CHECK(range == 0.0F);
    range = -1.0F;
    CHECK(direction_bin(g, Eigen::Vector3f(0.0F, std::numeric_limits<float>::infinity(), 1.0F), range) ==
          kNoDirectionBin);
    CHECK(range == 0.0F);
    // Counted as invalid by add_to_direction_view, the view untouched.
    std::vector<float> far(100U, 0.0F);
    std::vector<float> near(100U, 0.0F);
    const std::vector<Eigen::Vector3f> pts = {Eigen::Vector3f(0.0F, 0.0F, 3e38F)};
    const Result<DirectionViewAdded> added = add_to_direction_view(
        {pts.data(), pts.size()}, g, {far.data(), far.size()}, {near.data(), near.size()});
    REQUIRE(added.ok());
    CHECK(added.value().invalid == 1U);
    CHECK(added.value().binned == 0U);
    CHECK(far == std::vector<float>(100U, 0.0F));
}

// verifies: SR-BKG-007
TEST_CASE("direction grid: adding to a view refuses a bad grid and a nearest span of the wrong size") {
    std::vector<float> far(100U, 0.0F);
    std::vector<float> near(100U, 0.0F);
    const std::vector<Eigen::Vector3f> pts = {along(0.5F, 0.5F, 2.0F)};
    DirectionGrid bad = small_grid();
    bad.azimuth_bins = 0U;
    CHECK(add_to_direction_view({pts.data(), pts.size()}, bad, {far.data(), 0U}, {near.data(), 0U}).error() ==
          ErrorCode::kInvalidArgument);
    bad = small_grid();
    bad.bin_rad = std::numeric_limits<float>::quiet_NaN();
    CHECK(add_to_direction_view({pts.data(), pts.size()}, bad, {far.data(), 100U}, {near.data(), 100U}).error() ==
          ErrorCode::kNonFiniteValue);
    CHECK(
        add_to_direction_view({pts.data(), pts.size()}, small_grid(), {far.data(), 100U}, {near.data(), 99U}).error() ==
        ErrorCode::kMalformedInput);
    CHECK(far == std::vector<float>(100U, 0.0F));
    CHECK(near == std::vector<float>(100U, 0.0F));
}
