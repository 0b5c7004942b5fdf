// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the comparison of a live depth image with the sensor's
// commissioned view of the empty cell (H-SEN-3: a moved or blinded sensor).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cellguard/safety/background_check.hpp"

using namespace cellguard;

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
}  // namespace

// verifies: SR-CTRL-011
TEST_CASE(
    "background check: a pixel matches when both hold a reading within the tolerance, and only referenced pixels count") {
    const std::vector<float> ref = {1.0F, 2.0F, 3.0F, kNaN, 0.0F, -1.0F, kInf, 4.0F};
    BackgroundReference r;
    r.depth = Span<const float>(ref.data(), ref.size());
    r.tolerance_m = 0.25F;
    // Within (1.0 + 0.25 exactly, a tolerance that is a power of two), beyond, a
    // person in front, no reading, and anything where the reference has none.
    const std::vector<float> live = {1.25F, 2.3F, 1.0F, 1.0F, 1.0F, 1.0F, 1.0F, kNaN};
    const Result<BackgroundMatch> m = match_background(Span<const float>(live.data(), live.size()), r);
    REQUIRE(m.ok());
    CHECK(m.value().referenced == 4U);  // 1, 2, 3, 4 m; not NaN, 0, negative, infinite
    CHECK(m.value().matching == 1U);    // only the first
    const std::vector<float> same = ref;
    const Result<BackgroundMatch> all = match_background(Span<const float>(same.data(), same.size()), r);
    CHECK(all.value().matching == 4U);
    const std::vector<float> inf_live = {kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf};
    CHECK(match_background(Span<const float>(inf_live.data(), inf_live.size()), r).value().matching == 0U);
}

// verifies: SR-CTRL-011
TEST_CASE("background check: images of another size and a tolerance that is not finite and positive are refused") {
    const std::vector<float> ref(6U, 1.0F);
    const std::vector<float> live(5U, 1.0F);
    BackgroundReference r;
    r.depth = Span<const float>(ref.data(), ref.size());
    CHECK(match_background(Span<const float>(live.data(), live.size()), r).error() == ErrorCode::kMalformedInput);
    const std::vector<float> same(6U, 1.0F);
    for (const float bad : {0.0F, -0.1F, kNaN, kInf}) {
        r.tolerance_m = bad;
        CHECK(match_background(Span<const float>(same.data(), same.size()), r).error() == ErrorCode::kInvalidArgument);
    }
}

// verifies: SR-CTRL-011
TEST_CASE(
    "background check: the fraction is exact in integers, and a reference without readings or a bad fraction never passes") {
    BackgroundMatch m;
    m.referenced = 10U;
    m.matching = 5U;
    CHECK(background_seen(m, 0.5F));
    m.matching = 4U;
    CHECK_FALSE(background_seen(m, 0.5F));
    CHECK(background_seen(m, 0.375F));  // ceil(3.75) = 4
    // The float is taken as it is: 0.4F is slightly above 0.4, so 4 of 10 are not enough.
    CHECK_FALSE(background_seen(m, 0.4F));
    m.referenced = 3U;
    m.matching = 1U;
    CHECK_FALSE(background_seen(m, 0.34F));  // ceil(1.02) = 2
    CHECK(background_seen(m, 0.33F));        // ceil(0.99) = 1
    m.matching = 3U;
    CHECK(background_seen(m, 1.0F));
    for (const float bad : {0.0F, -0.5F, 1.01F, kNaN}) {
        CHECK_FALSE(background_seen(m, bad));
    }
    const BackgroundMatch none;
    CHECK_FALSE(background_seen(none, 0.5F));
}

// verifies: SR-CTRL-011
TEST_CASE(
    "background check: the counts equal a pixel-by-pixel count for every length 0 to 40 and every kind of value") {
    // Values that probe each comparison: readings near and far, the
    // tolerance's edge, no reading (0, negative, NaN, infinite).
    const float kinds[] = {1.0F, 1.0625F, 1.1F, 0.9375F, 3.0F, 0.0F, -1.0F, kNaN, kInf, -kInf, 1e-30F, 99.0F};
    constexpr std::size_t n_kinds = sizeof(kinds) / sizeof(kinds[0]);
    BackgroundReference r;
    r.tolerance_m = 0.0625F;  // a power of two: 1.0 +- 0.0625 are exact
    for (std::size_t len = 0; len <= 40; ++len) {
        std::vector<float> ref(len);
        std::vector<float> live(len);
        for (std::size_t i = 0; i < len; ++i) {
            ref[i] = (i % 5U == 4U) ? kinds[(i * 7U) % n_kinds] : 1.0F;
            live[i] = kinds[(i * 5U + len) % n_kinds];
        }
        std::uint32_t referenced = 0U;
        std::uint32_t matching = 0U;
        for (std::size_t i = 0; i < len; ++i) {
            const bool r_ok = std::isfinite(ref[i]) && ref[i] > 0.0F;
            const bool d_ok = std::isfinite(live[i]) && live[i] > 0.0F;
            referenced += r_ok ? 1U : 0U;
            matching += (r_ok && d_ok && std::fabs(live[i] - ref[i]) <= r.tolerance_m) ? 1U : 0U;
        }
        r.depth = Span<const float>(ref.data(), ref.size());
        const Result<BackgroundMatch> m = match_background(Span<const float>(live.data(), live.size()), r);
        CAPTURE(len);
        REQUIRE(m.ok());
        CHECK(m.value().referenced == referenced);
        CHECK(m.value().matching == matching);
    }
}

// verifies: SR-BKG-003
TEST_CASE("background check: pixels deeper than the reference by more than the tolerance are counted, in both paths") {
    const float kinds[] = {1.0F, 1.0625F, 1.07F, 0.9F, 3.0F, 0.0F, -1.0F, kNaN, kInf, 1e-30F, 99.0F};
    constexpr std::size_t n_kinds = sizeof(kinds) / sizeof(kinds[0]);
    BackgroundReference r;
    r.tolerance_m = 0.0625F;  // 1.0 + 0.0625 is exactly on the edge: not longer
    for (std::size_t len = 0; len <= 23; ++len) {
        std::vector<float> ref(len);
        std::vector<float> live(len);
        std::uint32_t longer = 0U;
        for (std::size_t i = 0; i < len; ++i) {
            ref[i] = (i % 7U == 6U) ? kinds[(i * 3U) % n_kinds] : 1.0F;
            live[i] = kinds[(i * 5U + len) % n_kinds];
            const bool r_ok = std::isfinite(ref[i]) && ref[i] > 0.0F;
            const bool d_ok = std::isfinite(live[i]) && live[i] > 0.0F;
            longer += (r_ok && d_ok && live[i] - ref[i] > r.tolerance_m) ? 1U : 0U;
        }
        r.depth = Span<const float>(ref.data(), ref.size());
        const Result<BackgroundMatch> m = match_background(Span<const float>(live.data(), live.size()), r);
        CAPTURE(len);
        REQUIRE(m.ok());
        CHECK(m.value().longer == longer);
    }
    // A person (shorter) or a missing reading is never longer; the limit is "more than".
    const std::vector<float> ref = {2.0F, 2.0F, 2.0F, 2.0F, 2.0F};
    const std::vector<float> live = {1.0F, kNaN, 0.0F, 2.5F, 2.0625F};
    r.depth = Span<const float>(ref.data(), ref.size());
    const BackgroundMatch m = match_background(Span<const float>(live.data(), live.size()), r).value();
    CHECK(m.longer == 1U);
    CHECK(background_changed(m, 0U));
    CHECK_FALSE(background_changed(m, 1U));
}

// verifies: SR-CTRL-011
TEST_CASE(
    "background check: a point-set view whose depth or nearest ranges do not fill its direction grid is refused") {
    const DirectionGrid g{-0.5F, -0.5F, 0.5F, 2U, 2U};  // 4 bins
    const std::vector<float> four(4U, 2.0F);
    const std::vector<float> three(3U, 2.0F);
    BackgroundReference r;
    r.grid = g;
    r.depth = Span<const float>(three.data(), three.size());
    r.nearest = Span<const float>(four.data(), four.size());
    const Span<const Eigen::Vector3f> none{};
    CHECK(match_points(none, r).error() == ErrorCode::kMalformedInput);
    r.depth = Span<const float>(four.data(), four.size());
    r.nearest = Span<const float>(three.data(), three.size());
    CHECK(match_points(none, r).error() == ErrorCode::kMalformedInput);
    r.nearest = Span<const float>(four.data(), four.size());
    REQUIRE(match_points(none, r).ok());
    CHECK(match_points(none, r).value().referenced == 0U);
}

// verifies: SR-CTRL-011
TEST_CASE("background check: a depth image against a point-set view, or a reading of unknown kind, is refused") {
    const std::vector<float> four(4U, 2.0F);
    BackgroundReference r;
    r.grid = DirectionGrid{-0.5F, -0.5F, 0.5F, 2U, 2U};
    r.depth = Span<const float>(four.data(), four.size());
    r.nearest = Span<const float>(four.data(), four.size());
    SensorReading live;
    live.kind = SensorDataKind::kDepthImage;
    live.depth = Span<const float>(four.data(), four.size());
    CHECK(match_background(live, r).error() == ErrorCode::kInvalidArgument);
    r.nearest = Span<const float>{};  // a depth image's own reference
    CHECK(match_background(live, r).ok());
    live.kind = static_cast<SensorDataKind>(7);
    CHECK(match_background(live, r).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-BKG-004
TEST_CASE("background check: the change tracker ignores a slot beyond the sensor slots") {
    BackgroundReference r;
    r.changed_cycles = 1U;
    BackgroundMatch changed;
    changed.referenced = 100U;
    changed.longer = r.max_longer_pixels + 1U;
    REQUIRE(background_changed(changed, r.max_longer_pixels));
    BackgroundChangeTracker t;
    t.track(kMaxSensors, changed, r);
    CHECK(t.latched == 0U);
    for (std::size_t s = 0U; s < kMaxSensors; ++s) {
        CHECK(t.streak[s] == 0U);
        CHECK(t.last[s].referenced == 0U);
    }
    t.track(0U, changed, r);  // a slot in range latches at once with changed_cycles 1
    CHECK(t.latched == 1U);
}
