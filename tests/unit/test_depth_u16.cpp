// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements (issue 18, "depth images as cameras deliver them"): a uint16
// depth image with a scale and an offset (kDepthImageU16) is validated,
// fingerprinted and fused in place, and every path (fuse_sensor in both
// rasterizations, the ray tables, the background check) gives for it what
// it gives for the float image of the same depth_value()s; raw 0 is no
// reading.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_table.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/safety/background_check.hpp"
#include "fusion_stats_check.hpp"

using namespace cellguard;

namespace {

/// A grid of @p n^3 voxels of 5 cm from the origin (32: a compact ray
/// table, 48: a wide one).
GridGeometry cube_grid(int n) { return GridGeometry::make(Eigen::Vector3d::Zero(), 0.05, GridDims{n, n, n}).value(); }

struct OwnedGrid {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    std::vector<std::int16_t> scratch;
    EvidenceGrid grid;
    explicit OwnedGrid(const GridGeometry& g) : lo(g.voxel_count()), ob(g.voxel_count()), scratch(g.voxel_count()) {
        grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        grid.clear();
    }
    Span<std::int16_t> fusion_scratch() { return {scratch.data(), scratch.size()}; }
    bool same_as(const OwnedGrid& other) const { return lo == other.lo && ob == other.ob; }
};

/// A 40 x 30 camera 0.5 m before the grid's x = 0 face, looking along +x
/// at the middle of a 1.6 m cube.
constexpr std::int32_t kWidth = 40;
constexpr std::int32_t kHeight = 30;
constexpr std::size_t kPixels = static_cast<std::size_t>(kWidth) * static_cast<std::size_t>(kHeight);

SensorReading camera() {
    SensorReading r;
    r.pose.linear() << 0, 0, 1,  //
        1, 0, 0,                 //
        0, 1, 0;
    r.pose.translation() = Eigen::Vector3d(-0.5, 0.8, 0.8);
    r.intrinsics = PinholeIntrinsics{30.0, 30.0, 19.5, 14.5, kWidth, kHeight};
    r.min_range = 0.1F;
    r.max_range = 4.0F;
    return r;
}

/// A raw image with every class of reading: raw 0 (no reading) every 7th
/// pixel, 65535 (beyond max_range) every 11th, raw 1 every 13th (behind the
/// sensor with a negative offset), the rest spread over 0.3 to 3.2 m.
std::vector<std::uint16_t> raw_image() {
    std::vector<std::uint16_t> raw(kPixels);
    std::uint32_t x = 12345U;
    for (std::size_t i = 0; i < kPixels; ++i) {
        x = x * 1664525U + 1013904223U;
        raw[i] = static_cast<std::uint16_t>(300U + (x >> 8U) % 2900U);
        raw[i] = (i % 7U == 0U) ? std::uint16_t{0} : (i % 11U == 0U) ? std::uint16_t{65535} : raw[i];
        raw[i] = (i % 13U == 0U) ? std::uint16_t{1} : raw[i];
    }
    return raw;
}

SensorReading u16_reading(const std::vector<std::uint16_t>& raw, float scale, float offset) {
    SensorReading r = camera();
    r.kind = SensorDataKind::kDepthImageU16;
    r.depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size());
    r.depth_scale = scale;
    r.depth_offset = offset;
    return r;
}

/// The float image of the same depths: float(raw * scale + offset) in
/// double, NaN for raw 0 (depth_value's rule written out again).
std::vector<float> float_twin(const std::vector<std::uint16_t>& raw, float scale, float offset) {
    std::vector<float> d(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) {
        d[i] = raw[i] == 0U ? std::numeric_limits<float>::quiet_NaN()
                            : static_cast<float>(static_cast<double>(raw[i]) * static_cast<double>(scale) +
                                                 static_cast<double>(offset));
    }
    return d;
}

SensorReading float_reading(const std::vector<float>& depth) {
    SensorReading r = camera();
    r.kind = SensorDataKind::kDepthImage;
    r.depth = Span<const float>(depth.data(), depth.size());
    return r;
}

/// The scale and offset pairs the equality tests run: millimetres, half
/// millimetres with an offset (scale and offset not exact in binary), and a
/// negative offset that puts raw 1 behind the sensor.
struct ScaleOffset {
    float scale;
    float offset;
};
constexpr ScaleOffset kScales[] = {{0.001F, 0.0F}, {0.0005F, 0.4F}, {0.001F, -0.2F}};

}  // namespace

// verifies: SR-FUSE-013, SR-FUSE-004
TEST_CASE("depth u16: validation refuses each bad field and uses only the kind's view") {
    const std::vector<std::uint16_t> raw = raw_image();
    const SensorReading good = u16_reading(raw, 0.001F, 0.0F);
    CHECK(validate_sensor_reading(good).ok());

    SensorReading r = good;
    r.depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size() - 1U);
    CHECK(validate_sensor_reading(r).error() == ErrorCode::kMalformedInput);
    r = good;
    r.depth_u16 = {};
    CHECK(validate_sensor_reading(r).error() == ErrorCode::kMalformedInput);
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        r = good;
        r.depth_scale = bad;
        CHECK(validate_sensor_reading(r).error() == ErrorCode::kNonFiniteValue);
        r = good;
        r.depth_offset = bad;
        CHECK(validate_sensor_reading(r).error() == ErrorCode::kNonFiniteValue);
    }
    for (const float bad : {0.0F, -0.001F, -0.0F}) {
        r = good;
        r.depth_scale = bad;
        CHECK(validate_sensor_reading(r).error() == ErrorCode::kInvalidArgument);
    }
    r = good;
    r.depth_offset = -5.0F;  // any finite offset: the depths it gives are classified when fused
    CHECK(validate_sensor_reading(r).ok());

    // The other kind's view is ignored either way.
    const std::vector<float> wrong_size(3U, 1.0F);
    r = good;
    r.depth = Span<const float>(wrong_size.data(), wrong_size.size());
    CHECK(validate_sensor_reading(r).ok());
    const std::vector<float> depth = float_twin(raw, 0.001F, 0.0F);
    SensorReading f = float_reading(depth);
    f.depth_u16 = Span<const std::uint16_t>(raw.data(), 5U);
    f.depth_scale = std::numeric_limits<float>::quiet_NaN();  // not used by a float image
    CHECK(validate_sensor_reading(f).ok());
    f.depth = Span<const float>(depth.data(), depth.size() - 1U);
    CHECK(validate_sensor_reading(f).error() == ErrorCode::kMalformedInput);
}

// verifies: SR-FUSE-013
TEST_CASE("depth u16: depth_value reads raw 0 as NaN, the largest raw value and an offset exactly") {
    const std::uint16_t raw[4] = {0U, 65535U, 1000U, 1U};
    SensorReading r = camera();
    r.kind = SensorDataKind::kDepthImageU16;
    r.depth_u16 = Span<const std::uint16_t>(raw, 4U);
    r.depth_scale = 0.001F;
    r.depth_offset = 0.0F;
    CHECK(std::isnan(depth_value(r, 0U)));
    CHECK(depth_value(r, 1U) == static_cast<float>(65535.0 * static_cast<double>(0.001F)));
    CHECK(depth_value(r, 1U) == doctest::Approx(65.535).epsilon(1e-6));
    CHECK(depth_value(r, 2U) == static_cast<float>(1000.0 * static_cast<double>(0.001F)));
    r.depth_offset = -0.5F;
    CHECK(std::isnan(depth_value(r, 0U)));  // the offset does not turn "no reading" into a depth
    CHECK(depth_value(r, 2U) == static_cast<float>(1000.0 * static_cast<double>(0.001F) - 0.5));
    CHECK(depth_value(r, 3U) < 0.0F);  // behind the sensor: fusion counts it as such
    // A float image is read as stored.
    const float d[2] = {0.0F, 1.25F};
    SensorReading f = camera();
    f.kind = SensorDataKind::kDepthImage;
    f.depth = Span<const float>(d, 2U);
    CHECK(depth_value(f, 0U) == 0.0F);
    CHECK(depth_value(f, 1U) == 1.25F);
    CHECK(is_depth_image(SensorDataKind::kDepthImageU16));
    CHECK(is_depth_image(SensorDataKind::kDepthImage));
    CHECK_FALSE(is_depth_image(SensorDataKind::kPointSet));
}

// verifies: SR-FUSE-013
TEST_CASE("depth u16: fuse_sensor gives the float twin's grid bit for bit in both rasterizations") {
    const std::vector<std::uint16_t> raw = raw_image();
    std::size_t zeros = 0U;
    for (const std::uint16_t v : raw) {
        zeros += v == 0U ? 1U : 0U;
    }
    for (const ScaleOffset so : kScales) {
        for (const Rasterization ras : {Rasterization::kExact, Rasterization::kBresenham3d}) {
            CAPTURE(so.scale);
            CAPTURE(so.offset);
            const GridGeometry g = cube_grid(32);
            const std::vector<float> depth = float_twin(raw, so.scale, so.offset);
            OwnedGrid a(g);
            OwnedGrid b(g);
            const FusionStats su = fuse_sensor(a.grid, u16_reading(raw, so.scale, so.offset), SensorModelTable{},
                                               a.fusion_scratch(), ras)
                                       .value();
            const FusionStats sf =
                fuse_sensor(b.grid, float_reading(depth), SensorModelTable{}, b.fusion_scratch(), ras).value();
            check_same_stats(su, sf);
            CHECK(a.same_as(b));
            // Raw 0 is no reading, counted as NaN; the image has them all.
            CHECK(su.skipped_nan == zeros);
            CHECK(su.skipped_zero == 0U);
            CHECK(su.rays_fused + su.skipped() == kPixels);
            CHECK(su.readings_in_grid > 100U);      // the test fuses real readings
            CHECK(su.skipped_out_of_range >= 50U);  // 65535 is beyond max_range
            CHECK((so.offset < 0.0F) == (su.skipped_behind > 0U));
        }
    }
}

// verifies: SR-FUSE-013
TEST_CASE("depth u16: a ray table fuses a uint16 image as it fuses the float twin (compact and wide)") {
    const std::vector<std::uint16_t> raw = raw_image();
    for (const int n : {32, 48}) {
        const GridGeometry g = cube_grid(n);
        for (const ScaleOffset so : kScales) {
            CAPTURE(n);
            CAPTURE(so.offset);
            const std::vector<float> depth = float_twin(raw, so.scale, so.offset);
            const SensorReading f = float_reading(depth);
            const SensorReading u = u16_reading(raw, so.scale, so.offset);
            host::OwnedRayTable from_float;
            host::OwnedRayTable from_u16;
            REQUIRE(from_float.build(g, f).ok());
            REQUIRE(from_u16.build(g, u).ok());  // a table is built from either kind's description
            CHECK(ray_table_is_compact(g, u) == (n == 32));
            OwnedGrid by_span(g);
            OwnedGrid by_float_reading(g);
            OwnedGrid by_u16(g);
            OwnedGrid by_u16_table(g);
            const SensorModelTable model;
            const FusionStats s0 =
                from_float.table().fuse(by_span.grid, Span<const float>(depth.data(), depth.size()), model).value();
            const FusionStats s1 = from_float.table().fuse(by_float_reading.grid, f, model).value();
            const FusionStats s2 = from_float.table().fuse(by_u16.grid, u, model).value();
            const FusionStats s3 = from_u16.table().fuse(by_u16_table.grid, u, model).value();
            check_same_stats(s0, s1);
            check_same_stats(s0, s2);
            check_same_stats(s0, s3);
            CHECK(by_span.same_as(by_float_reading));
            CHECK(by_span.same_as(by_u16));
            CHECK(by_span.same_as(by_u16_table));
            CHECK(s2.readings_in_grid > 100U);
            CHECK(s2.skipped_nan > 0U);
        }
    }
}

// verifies: SR-FUSE-013
TEST_CASE("depth u16: a ray table refuses a point set, a bad description and an image of another size") {
    const std::vector<std::uint16_t> raw = raw_image();
    const GridGeometry g = cube_grid(32);
    host::OwnedRayTable t;
    REQUIRE(t.build(g, u16_reading(raw, 0.001F, 0.0F)).ok());
    OwnedGrid grid(g);
    const SensorModelTable model;
    SensorReading r = u16_reading(raw, 0.001F, 0.0F);
    r.depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size() - 1U);
    CHECK(t.table().fuse(grid.grid, r, model).error() == ErrorCode::kMalformedInput);
    r = u16_reading(raw, std::numeric_limits<float>::infinity(), 0.0F);
    CHECK(t.table().fuse(grid.grid, r, model).error() == ErrorCode::kNonFiniteValue);
    r = u16_reading(raw, 0.001F, 0.0F);
    r.kind = SensorDataKind::kPointSet;
    CHECK(t.table().fuse(grid.grid, r, model).error() == ErrorCode::kInvalidArgument);
    CHECK(std::all_of(grid.ob.begin(), grid.ob.end(), [](std::uint8_t o) { return o == 0U; }));
}

// verifies: SR-FUSE-013
TEST_CASE("depth u16: the background check matches a uint16 image as its float twin") {
    const std::vector<std::uint16_t> raw = raw_image();
    for (const ScaleOffset so : kScales) {
        const std::vector<float> depth = float_twin(raw, so.scale, so.offset);
        // The reference: the same view with every 3rd depth 3 cm nearer and
        // every 5th 10 cm nearer (beyond the 5 cm tolerance).
        std::vector<float> ref = depth;
        for (std::size_t i = 0; i < ref.size(); ++i) {
            ref[i] -= (i % 5U == 0U) ? 0.10F : (i % 3U == 0U) ? 0.03F : 0.0F;
        }
        BackgroundReference reference;
        reference.depth = Span<const float>(ref.data(), ref.size());
        const BackgroundMatch mf = match_background(Span<const float>(depth.data(), depth.size()), reference).value();
        const BackgroundMatch mr = match_background(float_reading(depth), reference).value();
        const BackgroundMatch mu = match_background(u16_reading(raw, so.scale, so.offset), reference).value();
        CHECK(mu.referenced == mf.referenced);
        CHECK(mu.matching == mf.matching);
        CHECK(mr.referenced == mf.referenced);
        CHECK(mr.matching == mf.matching);
        CHECK(mu.matching < mu.referenced);  // the 10 cm pixels do not match
        CHECK(mu.matching > mu.referenced / 2U);
    }
    // Raw 0 is no reading: a live image of zeros matches nothing.
    const std::vector<std::uint16_t> zeros(kPixels, 0U);
    const std::vector<float> ones(kPixels, 1.0F);
    BackgroundReference reference;
    reference.depth = Span<const float>(ones.data(), ones.size());
    const BackgroundMatch none = match_background(u16_reading(zeros, 0.001F, 1.0F), reference).value();
    CHECK(none.referenced == kPixels);
    CHECK(none.matching == 0U);
    // Errors: a point set, an image of another size, a bad tolerance.
    SensorReading r = u16_reading(raw, 0.001F, 0.0F);
    r.kind = SensorDataKind::kPointSet;
    CHECK(match_background(r, reference).error() == ErrorCode::kInvalidArgument);
    r = u16_reading(raw, 0.001F, 0.0F);
    r.depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size() - 1U);
    CHECK(match_background(r, reference).error() == ErrorCode::kMalformedInput);
    reference.tolerance_m = 0.0F;
    CHECK(match_background(u16_reading(raw, 0.001F, 0.0F), reference).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-FUSE-013
TEST_CASE("depth u16: the fingerprint covers every raw value, the scale and the offset") {
    std::vector<std::uint16_t> raw = raw_image();
    const std::uint64_t base = reading_fingerprint(u16_reading(raw, 0.001F, 0.0F));
    CHECK(reading_fingerprint(u16_reading(raw, 0.001F, 0.0F)) == base);  // equal data, equal fingerprint
    for (const std::size_t i : {std::size_t{0}, std::size_t{1}, kPixels / 2U, kPixels - 2U, kPixels - 1U}) {
        CAPTURE(i);
        const std::uint16_t kept = raw[i];
        raw[i] = static_cast<std::uint16_t>(kept ^ 1U);
        CHECK(reading_fingerprint(u16_reading(raw, 0.001F, 0.0F)) != base);
        raw[i] = kept;
    }
    CHECK(reading_fingerprint(u16_reading(raw, 0.001F, 0.0F)) == base);
    CHECK(reading_fingerprint(u16_reading(raw, 0.002F, 0.0F)) != base);
    CHECK(reading_fingerprint(u16_reading(raw, 0.001F, 0.01F)) != base);
    // An odd number of pixels (a tail after the pairs) is covered too.
    const SensorReading odd_a = [&] {
        SensorReading r = u16_reading(raw, 0.001F, 0.0F);
        r.depth_u16 = Span<const std::uint16_t>(raw.data(), 9U);
        return r;
    }();
    SensorReading odd_b = odd_a;
    std::vector<std::uint16_t> other(raw.begin(), raw.begin() + 9);
    other[8] = static_cast<std::uint16_t>(other[8] + 1U);
    odd_b.depth_u16 = Span<const std::uint16_t>(other.data(), other.size());
    CHECK(reading_fingerprint(odd_a) != reading_fingerprint(odd_b));
    // The float view of a u16 reading is not read.
    SensorReading with_float = u16_reading(raw, 0.001F, 0.0F);
    const std::vector<float> noise(kPixels, 3.0F);
    with_float.depth = Span<const float>(noise.data(), noise.size());
    CHECK(reading_fingerprint(with_float) == base);
}
