// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The cameras' own filters as the detection experiment models them
// (apps/host cell/depth_conditioning.hpp): the edge filter drops flying
// pixels, the background tolerance puts readings near the empty cell's
// depth onto it; both off by default.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "cellguard/host/cell/depth_conditioning.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

constexpr std::int32_t kW = 8;
constexpr std::int32_t kH = 4;

/// A flat image at @p depth.
std::vector<float> flat(float depth) { return std::vector<float>(static_cast<std::size_t>(kW * kH), depth); }

float& at(std::vector<float>& img, std::int32_t u, std::int32_t v) { return img[static_cast<std::size_t>(v * kW + u)]; }

}  // namespace

// verifies: SR-EVAL-004
TEST_CASE("depth conditioning: off changes nothing, a wrong size is refused and changes nothing") {
    std::vector<float> img = flat(3.0F);
    at(img, 3, 1) = 1.0F;
    const std::vector<float> before = img;
    std::vector<float> scratch(img.size());
    const std::vector<float> bg = flat(3.0F);
    ConditioningCounts n;
    CHECK_FALSE(DepthConditioning{}.on());
    REQUIRE(condition_depth({img.data(), img.size()}, {bg.data(), bg.size()}, {scratch.data(), scratch.size()}, kW, kH,
                            DepthConditioning{}, &n));
    CHECK(img == before);
    CHECK(n.dropped == 0U);
    CHECK(n.snapped == 0U);
    DepthConditioning on;
    on.edge_jump_min_m = 0.05;
    on.background_tolerance_per_m = 0.05;
    CHECK(on.on());
    CHECK_FALSE(condition_depth({img.data(), img.size() - 1U}, {bg.data(), bg.size()}, {scratch.data(), scratch.size()},
                                kW, kH, on));
    CHECK_FALSE(condition_depth({img.data(), img.size()}, {bg.data(), bg.size() - 1U}, {scratch.data(), scratch.size()},
                                kW, kH, on));
    CHECK_FALSE(condition_depth({img.data(), img.size()}, {bg.data(), bg.size()}, {scratch.data(), 3U}, kW, kH, on));
    CHECK(img == before);
}

// verifies: SR-EVAL-004
TEST_CASE("depth conditioning: the edge filter drops a flying pixel and the edge's pixels, not a plane's noise") {
    std::vector<float> img = flat(3.0F);
    for (std::int32_t v = 0; v < kH; ++v) {  // an object 1 m nearer in columns 0..2, a flying pixel in column 3
        for (std::int32_t u = 0; u < 3; ++u) {
            at(img, u, v) = 2.0F;
        }
    }
    at(img, 3, 1) = 2.5F;   // between both
    at(img, 6, 2) = 3.04F;  // plane noise: 4 cm, under the jump of max(5 cm, 2 % of 3 m = 6 cm)
    std::vector<float> scratch(img.size());
    DepthConditioning c;
    c.edge_jump_min_m = 0.05;
    c.edge_jump_per_m = 0.02;
    ConditioningCounts n;
    REQUIRE(condition_depth({img.data(), img.size()}, {}, {scratch.data(), scratch.size()}, kW, kH, c, &n));
    CHECK(at(img, 3, 1) == 0.0F);   // the flying pixel
    CHECK(at(img, 2, 1) == 0.0F);   // the object's edge column
    CHECK(at(img, 3, 0) == 0.0F);   // the background's edge column
    CHECK(at(img, 1, 1) == 2.0F);   // the object's inside stays
    CHECK(at(img, 4, 1) == 0.0F);   // beside the flying pixel (0.5 m from it)
    CHECK(at(img, 6, 2) == 3.04F);  // the plane's noise stays
    CHECK(at(img, 7, 3) == 3.0F);
    CHECK(n.dropped == 2U * kH + 1U);  // columns 2 and 3, and (4, 1)
}

// verifies: SR-EVAL-004
TEST_CASE("depth conditioning: readings within the tolerance of the empty cell read its depth, others stay") {
    const std::vector<float> bg = flat(3.0F);
    std::vector<float> img = flat(3.0F);
    at(img, 0, 0) = 2.9F;  // 10 cm nearer: within 5 % of 3 m (15 cm): snapped
    at(img, 1, 0) = 3.1F;  // 10 cm deeper: snapped
    at(img, 2, 0) = 2.8F;  // 20 cm nearer: an object, stays
    at(img, 3, 0) = 3.3F;  // 30 cm deeper: a changed background, stays (its check must see it)
    at(img, 4, 0) = 0.0F;  // no reading stays none
    std::vector<float> bg_hole = bg;
    at(bg_hole, 5, 0) = 0.0F;  // no background reading: no tolerance there
    at(img, 5, 0) = 2.95F;
    std::vector<float> scratch(img.size());
    DepthConditioning c;
    c.background_tolerance_per_m = 0.05;
    ConditioningCounts n;
    REQUIRE(condition_depth({img.data(), img.size()}, {bg_hole.data(), bg_hole.size()},
                            {scratch.data(), scratch.size()}, kW, kH, c, &n));
    CHECK(at(img, 0, 0) == 3.0F);
    CHECK(at(img, 1, 0) == 3.0F);
    CHECK(at(img, 2, 0) == 2.8F);
    CHECK(at(img, 3, 0) == 3.3F);
    CHECK(at(img, 4, 0) == 0.0F);
    CHECK(at(img, 5, 0) == 2.95F);
    // Every pixel but the four left as they were (those at 3 m count too: put on the same depth).
    CHECK(n.snapped == static_cast<std::uint64_t>(kW * kH) - 4U);
}

// verifies: SR-EVAL-004
TEST_CASE(
    "depth conditioning: a two-pixel band of flying pixels goes with radius 2, an isolated reading in front "
    "of the empty cell goes by the speckle filter, a blob stays") {
    // Radius: columns 3 and 4 both mix the 2 m object (columns 0..2) with the 3 m wall.
    std::vector<float> img = flat(3.0F);
    for (std::int32_t v = 0; v < kH; ++v) {
        for (std::int32_t u = 0; u < 3; ++u) {
            at(img, u, v) = 2.0F;
        }
        at(img, 3, v) = 2.45F;
        at(img, 4, v) = 2.5F;
    }
    std::vector<float> one = img;
    std::vector<float> scratch(img.size());
    DepthConditioning c;
    c.edge_jump_min_m = 0.05;
    c.edge_jump_per_m = 0.02;
    REQUIRE(condition_depth({one.data(), one.size()}, {}, {scratch.data(), scratch.size()}, kW, kH, c));
    CHECK(at(one, 3, 1) == 0.0F);  // next to the object: its 4-neighbour jumps
    CHECK(at(one, 4, 1) == 0.0F);  // next to the wall
    c.edge_radius = 2;
    std::vector<float> two = img;
    REQUIRE(condition_depth({two.data(), two.size()}, {}, {scratch.data(), scratch.size()}, kW, kH, c));
    CHECK(at(two, 5, 1) == 0.0F);  // the wall two pixels from the band's 2.45 m: dropped with radius 2
    CHECK(at(one, 5, 1) == 0.0F);  // (and already its 4-neighbour, 2.5 m, with radius 1)
    CHECK(at(two, 6, 1) == 0.0F);  // two from 2.5 m
    CHECK(at(one, 6, 1) == 3.0F);  // not with radius 1
    CHECK(at(two, 7, 1) == 3.0F);
    // Speckles: one reading 1 m in front of the wall alone, and a 2 x 2 blob.
    const std::vector<float> bg = flat(3.0F);
    std::vector<float> spk = flat(3.0F);
    at(spk, 1, 1) = 2.0F;
    at(spk, 4, 1) = 2.0F;
    at(spk, 5, 1) = 2.01F;
    at(spk, 4, 2) = 2.0F;
    at(spk, 5, 2) = 2.0F;
    DepthConditioning s;
    s.speckle_min_neighbours = 2;
    ConditioningCounts n;
    REQUIRE(condition_depth({spk.data(), spk.size()}, {bg.data(), bg.size()}, {scratch.data(), scratch.size()}, kW, kH,
                            s, &n));
    CHECK(at(spk, 1, 1) == 0.0F);
    CHECK(at(spk, 4, 1) == 2.0F);
    CHECK(at(spk, 5, 1) == 2.01F);
    CHECK(at(spk, 4, 2) == 2.0F);
    CHECK(at(spk, 5, 2) == 2.0F);
    CHECK(n.speckles == 1U);
    // Without a background the speckle filter does nothing (it needs to know what lies in front).
    std::vector<float> alone = flat(3.0F);
    at(alone, 1, 1) = 2.0F;
    REQUIRE(condition_depth({alone.data(), alone.size()}, {}, {scratch.data(), scratch.size()}, kW, kH, s));
    CHECK(at(alone, 1, 1) == 2.0F);
}

// verifies: SR-EVAL-004
TEST_CASE("depth conditioning: the edge filter drops exactly the readings a neighbour-by-neighbour compare drops") {
    // The reference: every neighbour up to the radius along the row and the
    // column compared on its own, in double, readings only (0, NaN and
    // infinities are none), on random images with holes, ramps and jumps.
    const auto reference = [](const std::vector<float>& img, std::int32_t w, std::int32_t h,
                              const DepthConditioning& c) {
        const auto valid = [](float d) { return d > 0.0F && std::isfinite(d); };
        std::vector<bool> drop(img.size(), false);
        for (std::int32_t v = 0; v < h; ++v) {
            for (std::int32_t u = 0; u < w; ++u) {
                const float d = img[static_cast<std::size_t>(v * w + u)];
                if (!valid(d)) {
                    continue;
                }
                const double jump = std::max(c.edge_jump_min_m, c.edge_jump_per_m * static_cast<double>(d));
                for (std::int32_t k = 1; k <= c.edge_radius; ++k) {
                    const std::int32_t nu[4] = {u - k, u + k, u, u};
                    const std::int32_t nv[4] = {v, v, v - k, v + k};
                    for (int j = 0; j < 4; ++j) {
                        if (nu[j] < 0 || nv[j] < 0 || nu[j] >= w || nv[j] >= h) {
                            continue;
                        }
                        const float n = img[static_cast<std::size_t>(nv[j] * w + nu[j])];
                        if (valid(n) && std::fabs(static_cast<double>(n) - static_cast<double>(d)) > jump) {
                            drop[static_cast<std::size_t>(v * w + u)] = true;
                        }
                    }
                }
            }
        }
        return drop;
    };
    std::mt19937 rng(35U);
    std::uniform_real_distribution<float> depth(0.5F, 4.0F);
    std::uniform_int_distribution<int> kind(0, 19);
    constexpr std::int32_t w = 23;
    constexpr std::int32_t h = 17;
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<float> img(static_cast<std::size_t>(w * h));
        float level = depth(rng);
        for (float& d : img) {
            const int k = kind(rng);
            if (k == 0) {
                level = depth(rng);  // a jump
            }
            d = k == 1   ? 0.0F
                : k == 2 ? std::numeric_limits<float>::quiet_NaN()
                : k == 3 ? std::numeric_limits<float>::infinity()
                : k == 4 ? -1.0F
                         : level + 0.01F * depth(rng);  // noise on a level
        }
        DepthConditioning c;
        c.edge_jump_min_m = 0.02 * (trial % 4);
        c.edge_jump_per_m = 0.01 * (trial % 5);
        if (!(c.edge_jump_min_m > 0.0 || c.edge_jump_per_m > 0.0)) {
            c.edge_jump_min_m = 0.05;
        }
        c.edge_radius = 1 + trial % 4;
        const std::vector<bool> expected = reference(img, w, h, c);
        std::vector<float> out = img;
        std::vector<float> scratch(img.size());
        ConditioningCounts n;
        REQUIRE(condition_depth({out.data(), out.size()}, {}, {scratch.data(), scratch.size()}, w, h, c, &n));
        std::uint64_t dropped = 0U;
        for (std::size_t i = 0U; i < img.size(); ++i) {
            CAPTURE(trial);
            CAPTURE(i);
            if (expected[i]) {
                CHECK(out[i] == 0.0F);
                ++dropped;
            } else {
                CHECK((out[i] == img[i] || (std::isnan(out[i]) && std::isnan(img[i]))));
            }
        }
        CHECK(n.dropped == dropped);
    }
}
