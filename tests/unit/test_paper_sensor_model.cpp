// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The paper's sensor model of the evaluation (apps/host sim/paper_sensor_model.hpp):
// the profile's values along one ray, the sum over rays (where the product's
// model keeps one opinion), the readings it skips (the product's rules, the
// same counts as lib's fusion), refusals, and the background frames it needs.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/sim/paper_sensor_model.hpp"
#include "fusion_stats_check.hpp"

using namespace cellguard;

namespace {

constexpr std::size_t kN = 20U * 4U * 4U;

/// A 20 x 4 x 4 grid of 10 cm voxels from the origin, with the product's scratch beside it.
struct SmallGrid {
    std::array<std::int16_t, kN> lo{};
    std::array<std::uint8_t, kN> ob{};
    std::array<std::int16_t, kN> scratch{};
    EvidenceGrid grid;
    SmallGrid() {
        const GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{20, 4, 4}).value();
        grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), kN), Span<std::uint8_t>(ob.data(), kN)).value();
        grid.clear();
    }
    [[nodiscard]] std::int16_t at(int x) const { return lo[grid.geometry().index_of(VoxelCoord{x, 1, 1})]; }
    [[nodiscard]] bool seen(int x) const { return ob[grid.geometry().index_of(VoxelCoord{x, 1, 1})] != 0U; }
};

/// A sensor at (-0.5, 0.15, 0.15) whose optical axis (z) is world +x.
SensorReading looking_along_x() {
    SensorReading r;
    r.pose.linear() << 0, 0, 1,  //
        1, 0, 0,                 //
        0, 1, 0;
    r.pose.translation() = Eigen::Vector3d(-0.5, 0.15, 0.15);
    r.max_range = 5.0F;
    return r;
}

SensorModelTable paper_table() { return SensorModelTable::make(sim::paper_profile()).value(); }

}  // namespace

// verifies: SR-EVAL-005
TEST_CASE("paper model: one ray gives the trough before the ramp, the ramp, the peak at the reading, nothing beyond") {
    SmallGrid s;
    const SensorModelTable t = paper_table();
    CHECK(t.constant_free_evidence() == log_odds_from_probability(0.44));
    CHECK(t.reading_evidence() == log_odds_from_probability(0.56));
    const Eigen::Vector3f p(0.0F, 0.0F, 1.5625F);  // world x = 1.0625: voxel 10
    SensorReading r = looking_along_x();
    r.points = Span<const Eigen::Vector3f>(&p, 1);
    // The exact traversal: voxel x is left at world x + 0.1, that is 1.5625 - (x + 0.6) metres before the reading.
    const FusionStats st =
        sim::fuse_frame_per_ray(s.grid, Span<const SensorReading>(&r, 1), t, Rasterization::kExact).value();
    CHECK(st.rays_fused == 1U);
    CHECK(st.readings_in_grid == 1U);
    for (int x = 0; x <= 8; ++x) {  // left at x + 0.1 <= 0.9625: at least 10 cm before the reading
        CHECK_MESSAGE(s.at(x) == t.constant_free_evidence(), "voxel " << x);
    }
    CHECK(s.at(9) == t.free_evidence(0.0625));  // on the ramp: weaker than the trough, still free
    CHECK(s.at(9) > t.constant_free_evidence());
    CHECK(s.at(9) < 0);
    CHECK(s.at(10) == t.reading_evidence());
    CHECK(s.seen(10));
    CHECK_FALSE(s.seen(11));  // past the reading: not observed
    CHECK(s.at(11) == 0);
}

// verifies: SR-EVAL-005
TEST_CASE("paper model: rays add up in a voxel, where the product's model keeps one opinion per sensor") {
    SmallGrid paper;
    SmallGrid product;
    const std::vector<Eigen::Vector3f> pts(3, Eigen::Vector3f(0.0F, 0.0F, 1.5625F));  // three rays, one reading voxel
    SensorReading r = looking_along_x();
    r.points = Span<const Eigen::Vector3f>(pts.data(), pts.size());
    const SensorModelTable t = paper_table();
    REQUIRE(sim::fuse_frame_per_ray(paper.grid, Span<const SensorReading>(&r, 1), t, Rasterization::kBresenham3d).ok());
    REQUIRE(fuse_frame(product.grid, Span<const SensorReading>(&r, 1), t,
                       Span<std::int16_t>(product.scratch.data(), kN), Rasterization::kBresenham3d)
                .ok());
    CHECK(paper.at(10) == 3 * t.reading_evidence());
    CHECK(paper.at(2) == 3 * t.constant_free_evidence());
    CHECK(product.at(10) == t.reading_evidence());
    CHECK(product.at(2) == t.constant_free_evidence());
    // A second frame on the same grid adds again: the grid is not cleared by the call.
    REQUIRE(sim::fuse_frame_per_ray(paper.grid, Span<const SensorReading>(&r, 1), t, Rasterization::kBresenham3d).ok());
    CHECK(paper.at(10) == 6 * t.reading_evidence());
}

// verifies: SR-EVAL-005
TEST_CASE("paper model: readings are skipped and counted by the product's rules, and the sums saturate") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // A 4 x 3 depth image: NaN, inf, 0, negative, beyond max_range, nearer than min_range, and valid depths.
    const std::array<float, 12> depth = {nan, inf, 0.0F, -1.0F, 9.0F, 0.05F, 1.0F, 1.2F, 1.5F, 0.8F, 2.0F, -inf};
    SensorReading image = looking_along_x();
    image.kind = SensorDataKind::kDepthImage;
    image.depth = Span<const float>(depth.data(), depth.size());
    image.intrinsics = PinholeIntrinsics{100.0, 100.0, 1.5, 1.0, 4, 3};
    image.min_range = 0.1F;
    const std::array<Eigen::Vector3f, 5> pts = {Eigen::Vector3f(0.0F, 0.0F, 0.0F), Eigen::Vector3f(0.0F, 0.0F, -1.0F),
                                                Eigen::Vector3f(nan, 0.0F, 1.0F), Eigen::Vector3f(0.0F, inf, 1.0F),
                                                Eigen::Vector3f(0.01F, 0.0F, 1.3F)};
    SensorReading cloud = looking_along_x();
    cloud.points = Span<const Eigen::Vector3f>(pts.data(), pts.size());
    const std::array<SensorReading, 2> both = {image, cloud};
    SmallGrid paper;
    SmallGrid product;
    const SensorModelTable t = paper_table();
    const FusionStats a = sim::fuse_frame_per_ray(paper.grid, Span<const SensorReading>(both.data(), 2), t,
                                                  Rasterization::kBresenham3d)
                              .value();
    const FusionStats b = fuse_frame(product.grid, Span<const SensorReading>(both.data(), 2), t,
                                     Span<std::int16_t>(product.scratch.data(), kN), Rasterization::kBresenham3d)
                              .value();
    CHECK(a.rays_fused == 6U);
    CHECK(a.skipped() == 11U);  // 7 pixels and 4 points
    check_same_stats(a, b);
    // Sums saturate at the finite bound instead of wrapping.
    SmallGrid full;
    for (std::int16_t& v : full.lo) {
        v = kLogOddsMax - 10;
    }
    const Eigen::Vector3f p(0.0F, 0.0F, 1.5625F);
    SensorReading one = looking_along_x();
    one.points = Span<const Eigen::Vector3f>(&p, 1);
    REQUIRE(sim::fuse_frame_per_ray(full.grid, Span<const SensorReading>(&one, 1), t, Rasterization::kExact).ok());
    CHECK(full.at(10) == kLogOddsMax);
}

// verifies: SR-EVAL-005
TEST_CASE("paper model: an invalid description or too many sensors leaves the grid untouched") {
    SmallGrid s;
    const SensorModelTable t = paper_table();
    const Eigen::Vector3f p(0.0F, 0.0F, 1.5625F);
    SensorReading good = looking_along_x();
    good.points = Span<const Eigen::Vector3f>(&p, 1);
    SensorReading bad = good;
    bad.max_range = -1.0F;
    const std::array<SensorReading, 2> pair = {good, bad};
    const Result<FusionStats> r = sim::fuse_frame_per_ray(s.grid, Span<const SensorReading>(pair.data(), 2), t,
                                                          Rasterization::kBresenham3d);
    CHECK_FALSE(r.ok());
    CHECK(s.grid.observed_count() == 0U);
    std::vector<SensorReading> many(kMaxSensors + 1U, good);
    CHECK(sim::fuse_frame_per_ray(s.grid, Span<const SensorReading>(many.data(), many.size()), t,
                                  Rasterization::kBresenham3d)
              .error() == ErrorCode::kCapacityExceeded);
    CHECK(s.grid.observed_count() == 0U);
}

// verifies: SR-EVAL-005
TEST_CASE("paper model: the probabilistic method needs ten empty frames before one ray a frame clears a voxel") {
    const SensorModelTable t = paper_table();
    // logit(0.1) = -562 units, the trough -62 a frame: 9.07 frames, so 10.
    CHECK(sim::paper_min_background_frames(0.1, t) == 10U);
    CHECK(sim::paper_min_background_frames(0.4, t) == 2U);
    CHECK(sim::paper_min_background_frames(0.6, t) == 1U);  // above 0.5: nothing to wait for
    CHECK(std::string(sim::model_name(sim::EvalSensorModel::kPaper)) == "paper");
    CHECK(std::string(sim::model_name(sim::EvalSensorModel::kProduct)) == "product");
}
