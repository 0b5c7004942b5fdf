// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: multi-sensor fusion with one opinion per sensor, voxel and
// frame ("occupied wins"), skipped readings, validation of sensor
// descriptions, no allocation while fusing.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/sim/workcell.hpp"

using namespace cellguard;

namespace {

// A 20 x 4 x 4 grid of 10 cm voxels from the origin.
struct SmallGrid {
    static constexpr std::size_t kN = 20U * 4U * 4U;
    std::int16_t lo[kN];
    std::uint8_t ob[kN];
    std::int16_t scratch_storage[kN];
    EvidenceGrid grid;
    Span<std::int16_t> scratch{scratch_storage};
    SmallGrid() {
        const GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{20, 4, 4}).value();
        grid = EvidenceGrid::make(g, lo, ob).value();
        grid.clear();
    }
    std::int16_t at(int x, int y, int z) const { return lo[grid.geometry().index_of(VoxelCoord{x, y, z})]; }
    bool seen(int x, int y, int z) const { return ob[grid.geometry().index_of(VoxelCoord{x, y, z})] != 0U; }
};

SensorReading looking_along_x(Span<const Eigen::Vector3f> points) {
    // Sensor at (-0.5, 0.15, 0.15) whose optical axis (z) is world +x.
    SensorReading r;
    r.pose.linear() << 0, 0, 1,  //
        1, 0, 0,                 //
        0, 1, 0;
    r.pose.translation() = Eigen::Vector3d(-0.5, 0.15, 0.15);
    r.kind = SensorDataKind::kPointSet;
    r.points = points;
    r.max_range = 5.0F;
    return r;
}

}  // namespace

// verifies: SR-FUSE-001
TEST_CASE("fusion: a ray clears the voxels before the reading, marks the reading's voxel and stops there") {
    SmallGrid s;
    const SensorModelTable model;
    const Eigen::Vector3f p(0.0F, 0.0F, 1.5625F);  // reaches world x = 1.0625: voxel x = 10
    const SensorReading r = looking_along_x(Span<const Eigen::Vector3f>(&p, 1));
    const FusionStats st = fuse_sensor(s.grid, r, model, s.scratch).value();
    CHECK(st.rays_fused == 1U);
    CHECK(st.readings_in_grid == 1U);
    CHECK(st.voxel_updates == 11U);
    CHECK(s.at(10, 1, 1) == model.reading_evidence());
    CHECK(s.at(0, 1, 1) == model.constant_free_evidence());
    CHECK(s.at(8, 1, 1) == model.constant_free_evidence());  // exits at 0.9, 16 cm before the reading
    CHECK(s.at(9, 1, 1) == model.free_evidence(0.0625));     // exits at 1.0, 6 cm before: on the ramp
    CHECK(s.at(9, 1, 1) > model.constant_free_evidence());
    CHECK_FALSE(s.seen(11, 1, 1));  // past the reading: unobserved
    CHECK(s.at(11, 1, 1) == 0);
    CHECK_FALSE(s.seen(5, 2, 1));  // not on the ray
    CHECK(s.grid.observed_count() == 11U);
}

// verifies: SR-FUSE-002
TEST_CASE("fusion: a sensor gives each voxel one opinion per frame, however many of its rays reach it") {
    SmallGrid s;
    const SensorModelTable model;
    const Eigen::Vector3f pts[3] = {{0.0F, 0.0F, 1.55F}, {0.0F, 0.0F, 1.55F}, {0.0F, 0.0F, 1.55F}};
    const SensorReading r = looking_along_x(pts);
    REQUIRE(fuse_sensor(s.grid, r, model, s.scratch).value().voxel_updates == 33U);  // 3 rays x 11 voxels visited
    CHECK(s.at(10, 1, 1) == model.reading_evidence());                               // not 3 x
    CHECK(s.at(3, 1, 1) == model.constant_free_evidence());
}

// verifies: SR-FUSE-002
TEST_CASE("fusion: a voxel holding N readings stays occupied when M >> N other rays of the frame cross it") {
    SmallGrid s;
    const SensorModelTable model;
    // N = 3 readings in voxel x = 10; M = 2000 rays along the same line to
    // voxel x = 15, each crossing voxel 10 with full free evidence.
    std::vector<Eigen::Vector3f> pts(2000, Eigen::Vector3f(0.0F, 0.0F, 2.05F));
    pts.insert(pts.begin() + 700, 3, Eigen::Vector3f(0.0F, 0.0F, 1.55F));
    const SensorReading r = looking_along_x(Span<const Eigen::Vector3f>(pts.data(), pts.size()));
    REQUIRE(fuse_sensor(s.grid, r, model, s.scratch).ok());
    CHECK(s.at(10, 1, 1) ==
          model.reading_evidence());  // the per-ray sum of the old model: 3 x 62 - 2000 x 61, saturated free
    CHECK(s.at(15, 1, 1) == model.reading_evidence());
    CHECK(s.at(3, 1, 1) == model.constant_free_evidence());  // 2003 crossing rays: one opinion, no saturation
    CHECK(probability_from_log_odds(s.at(10, 1, 1)) == doctest::Approx(model.params().p_hit).epsilon(0.001));
}

// verifies: SR-FUSE-002
TEST_CASE("fusion: of a sensor's free opinions of a voxel the weakest wins: a ray whose reading is near keeps it") {
    SmallGrid s;
    const SensorModelTable model;
    // Both rays cross voxel 9 (x 0.9 .. 1.0): one ends at x = 1.5 (0.5 m on), the
    // other at x = 1.0625 (6.25 cm on, on its ramp); either order gives the ramp value.
    const Eigen::Vector3f far_then_near[2] = {{0.0F, 0.0F, 2.0F}, {0.0F, 0.0F, 1.5625F}};
    const Eigen::Vector3f near_then_far[2] = {{0.0F, 0.0F, 1.5625F}, {0.0F, 0.0F, 2.0F}};
    REQUIRE(fuse_sensor(s.grid, looking_along_x(far_then_near), model, s.scratch).ok());
    CHECK(s.at(9, 1, 1) == model.free_evidence(0.0625));
    CHECK(s.at(10, 1, 1) == model.reading_evidence());  // the near ray's reading: crossed by the far ray, still a hit
    SmallGrid t;
    REQUIRE(fuse_sensor(t.grid, looking_along_x(near_then_far), model, t.scratch).ok());
    CHECK(std::equal(s.lo, s.lo + SmallGrid::kN, t.lo));
}

// verifies: SR-FUSE-002
TEST_CASE("fusion: across the sensors of a frame occupied wins, hits add, frees add, all clamped, in any order") {
    const SensorModelTable model;
    const Eigen::Vector3f hit_at_10(0.0F, 0.0F, 1.55F);  // voxel x = 10
    const Eigen::Vector3f hit_at_15(0.0F, 0.0F, 2.05F);  // crosses voxel 10
    SensorReading a = looking_along_x(Span<const Eigen::Vector3f>(&hit_at_10, 1));
    SensorReading b = looking_along_x(Span<const Eigen::Vector3f>(&hit_at_15, 1));
    const auto fused = [&](std::initializer_list<SensorReading> sensors) {
        auto s = std::make_unique<SmallGrid>();
        const std::vector<SensorReading> v(sensors);
        REQUIRE(fuse_frame(s->grid, Span<const SensorReading>(v.data(), v.size()), model, s->scratch).ok());
        return s;
    };
    const auto ab = fused({a, b});
    const auto ba = fused({b, a});
    CHECK(ab->at(10, 1, 1) == model.reading_evidence());  // b's free opinion does not lower a's hit
    CHECK(ab->at(15, 1, 1) == model.reading_evidence());
    CHECK(std::equal(ab->lo, ab->lo + SmallGrid::kN, ba->lo));
    CHECK(std::equal(ab->ob, ab->ob + SmallGrid::kN, ba->ob));
    // Two sensors hit the voxel: their hits add, clamped to p_clamp_max; two free opinions add, clamped to p_clamp_min.
    const auto aa = fused({a, a});
    CHECK(aa->at(10, 1, 1) == std::min<std::int32_t>(2 * model.reading_evidence(), model.pooled_max()));
    CHECK(aa->at(3, 1, 1) == std::max<std::int32_t>(2 * model.constant_free_evidence(), model.pooled_min()));
    const auto eight = fused({a, a, a, a, a, a, a, a});
    CHECK(eight->at(10, 1, 1) == model.pooled_max());
    CHECK(eight->at(3, 1, 1) == model.pooled_min());
}

// verifies: SR-FUSE-004
TEST_CASE("fusion: a scratch shorter than the grid is refused and the grid stays untouched") {
    SmallGrid s;
    const SensorModelTable model;
    const Eigen::Vector3f p(0.0F, 0.0F, 1.55F);
    const SensorReading r = looking_along_x(Span<const Eigen::Vector3f>(&p, 1));
    CHECK(fuse_sensor(s.grid, r, model, s.scratch.subspan(0U, SmallGrid::kN - 1U)).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(fuse_frame(s.grid, Span<const SensorReading>(&r, 1U), model, Span<std::int16_t>()).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(s.grid.observed_count() == 0U);
}

// verifies: SR-FUSE-003
TEST_CASE("fusion: NaN, infinite, zero, behind-the-sensor and out-of-range readings are skipped and counted") {
    SmallGrid s;
    const SensorModelTable model;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Eigen::Vector3f pts[] = {
        {nan, 0.0F, 1.0F},   {0.0F, inf, 1.0F},  {0.0F, 0.0F, 0.0F},
        {0.0F, 0.0F, -1.0F}, {0.0F, 0.0F, 9.0F},  // beyond max_range 5 m
        {0.0F, 0.0F, 0.05F},                      // nearer than min_range
    };
    SensorReading r = looking_along_x(pts);
    r.min_range = 0.1F;
    const FusionStats st = fuse_sensor(s.grid, r, model, s.scratch).value();
    CHECK(st.skipped_nan == 1U);
    CHECK(st.skipped_infinite == 1U);
    CHECK(st.skipped_zero == 1U);
    CHECK(st.skipped_behind == 1U);
    CHECK(st.skipped_out_of_range == 2U);
    CHECK(st.skipped() == 6U);
    CHECK(st.rays_fused == 0U);
    CHECK(s.grid.observed_count() == 0U);
}

// verifies: SR-FUSE-003
TEST_CASE("fusion: a depth image's invalid pixels are skipped and counted by kind") {
    SmallGrid s;
    const SensorModelTable model;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const float depth[6] = {1.0F, 0.0F, nan, inf, -1.0F, 1.0F};
    SensorReading r = looking_along_x(Span<const Eigen::Vector3f>());
    r.kind = SensorDataKind::kDepthImage;
    r.depth = depth;
    r.intrinsics = PinholeIntrinsics{100.0, 100.0, 1.0, 0.5, 3, 2};
    const FusionStats st = fuse_sensor(s.grid, r, model, s.scratch).value();
    CHECK(st.rays_fused == 2U);
    CHECK(st.skipped_zero == 1U);
    CHECK(st.skipped_nan == 1U);
    CHECK(st.skipped_infinite == 1U);
    CHECK(st.skipped_behind == 1U);
}

// verifies: SR-FUSE-001
TEST_CASE("fusion: a depth pixel is fused along its own ray through the pinhole") {
    SmallGrid s;
    const SensorModelTable model;
    // One pixel at u = 0, v = 0 with cx = 10, fx = 10: ray x/z = -1 in the sensor frame.
    const float depth[1] = {0.4F};
    SensorReading r = looking_along_x(Span<const Eigen::Vector3f>());
    r.pose.translation() = Eigen::Vector3d(0.05, 0.75, 0.15);
    r.kind = SensorDataKind::kDepthImage;
    r.depth = depth;
    r.intrinsics = PinholeIntrinsics{10.0, 10.0, 10.0, 0.0, 1, 1};
    REQUIRE(fuse_sensor(s.grid, r, model, s.scratch).value().readings_in_grid == 1U);
    // Sensor x maps to world y: the reading is at world (0.45, 0.35, 0.15).
    CHECK(s.at(4, 3, 1) == model.reading_evidence());
}

// verifies: SR-FUSE-004
TEST_CASE("fusion: an invalid sensor description is refused and the grid stays untouched") {
    SmallGrid s;
    const SensorModelTable model;
    const Eigen::Vector3f p(0.0F, 0.0F, 1.0F);
    SensorReading good = looking_along_x(Span<const Eigen::Vector3f>(&p, 1));
    SensorReading skewed = good;
    skewed.pose.linear()(0, 0) = 0.5;  // not a rotation
    const SensorReading two[2] = {good, skewed};
    CHECK(fuse_frame(s.grid, Span<const SensorReading>(two), model, s.scratch).error() == ErrorCode::kInvalidArgument);
    CHECK(s.grid.observed_count() == 0U);  // the good sensor was not fused either

    SensorReading bad_range = good;
    bad_range.max_range = 0.0F;
    CHECK(fuse_sensor(s.grid, bad_range, model, s.scratch).error() == ErrorCode::kInvalidArgument);
    SensorReading nan_pose = good;
    nan_pose.pose.translation().x() = std::nan("");
    CHECK(fuse_sensor(s.grid, nan_pose, model, s.scratch).error() == ErrorCode::kNonFiniteValue);
    SensorReading bad_image = good;
    bad_image.kind = SensorDataKind::kDepthImage;
    bad_image.intrinsics = PinholeIntrinsics{100.0, 100.0, 1.0, 1.0, 3, 2};
    const float five[5] = {};
    bad_image.depth = five;
    CHECK(fuse_sensor(s.grid, bad_image, model, s.scratch).error() == ErrorCode::kMalformedInput);
    bad_image.intrinsics.fx = 0.0;
    CHECK(fuse_sensor(s.grid, bad_image, model, s.scratch).error() == ErrorCode::kInvalidArgument);
    SensorReading many[kMaxSensors + 1];
    for (auto& m : many)
        m = good;
    CHECK(fuse_frame(s.grid, Span<const SensorReading>(many), model, s.scratch).error() ==
          ErrorCode::kCapacityExceeded);
    CHECK(s.grid.observed_count() == 0U);
}

// verifies: SR-GEN-002
TEST_CASE("fusion: fusing the simulated four-sensor frame allocates no memory") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()),
                                           Span<std::uint8_t>(ob.data(), ob.size()))
                            .value();
    const SensorModelTable model;
    const Span<const SensorReading> readings(frame.readings.data(), frame.readings.size());
    std::vector<std::int16_t> scratch(g.voxel_count());
    const test::AllocationScope scope;
    grid.clear();
    const Result<FusionStats> st = fuse_frame(grid, readings, model, {scratch.data(), scratch.size()});
    const std::size_t allocations = scope.allocations();
    REQUIRE(st.ok());
    CHECK(allocations == 0U);
    CHECK(st.value().rays_fused == 204288U);  // every pixel of 2 x 176 x 144 + 2 x 320 x 240
    CHECK(st.value().readings_in_grid > 20000U);
    // Most of the paper's grid is seen; the floor under the boxes is not.
    CHECK(grid.observed_count() > g.voxel_count() / 2U);
    CHECK(grid.observed_count() < g.voxel_count());
}

// verifies: SR-FUSE-001, SR-TRAV-002
TEST_CASE("fusion: the exact traversal and the paper's Bresenham option both fuse the simulated frame") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()),
                                           Span<std::uint8_t>(ob.data(), ob.size()))
                            .value();
    const SensorModelTable model;
    const Span<const SensorReading> readings(frame.readings.data(), frame.readings.size());
    std::vector<std::int16_t> scratch(g.voxel_count());
    grid.clear();
    const FusionStats exact =
        fuse_frame(grid, readings, model, {scratch.data(), scratch.size()}, Rasterization::kExact).value();
    grid.clear();
    const FusionStats bres =
        fuse_frame(grid, readings, model, {scratch.data(), scratch.size()}, Rasterization::kBresenham3d).value();
    CHECK(exact.rays_fused == bres.rays_fused);
    CHECK(bres.voxel_updates < exact.voxel_updates);       // Bresenham misses voxels
    CHECK(bres.voxel_updates > exact.voxel_updates / 3U);  // one voxel per dominant-axis step
}

// verifies: SR-FUSE-003
TEST_CASE("fusion: a point with NaN or an infinity in any one coordinate is skipped and counted by kind") {
    SmallGrid s;
    const SensorModelTable model;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Eigen::Vector3f pts[] = {
        {0.0F, nan, 1.0F}, {0.0F, 0.0F, nan}, {inf, 0.0F, 1.0F}, {0.0F, 0.0F, -inf}, {0.0F, 0.0F, inf},
    };
    const SensorReading r = looking_along_x(pts);
    const FusionStats st = fuse_sensor(s.grid, r, model, s.scratch).value();
    CHECK(st.skipped_nan == 2U);
    CHECK(st.skipped_infinite == 3U);
    CHECK(st.rays_fused == 0U);
    CHECK(s.grid.observed_count() == 0U);
}

// verifies: SR-FUSE-001, SR-FUSE-003
TEST_CASE("fusion: a traced ray to a non-finite reading writes nothing, and the reading-in-grid flag is optional") {
    SmallGrid s;
    const SensorModelTable model;
    const GridGeometry& g = s.grid.geometry();
    const Eigen::Vector3d origin(-0.5, 0.15, 0.15);
    const Eigen::Vector3d reading(1.05, 0.15, 0.15);  // voxel x = 10
    for (const Rasterization ras : {Rasterization::kExact, Rasterization::kBresenham3d}) {
        CAPTURE(static_cast<int>(ras));
        std::vector<std::int16_t> with(g.voxel_count(), kNoOpinion);
        std::vector<std::int16_t> without(g.voxel_count(), kNoOpinion);
        bool in_grid = false;
        const std::uint32_t a = trace_ray_opinions({with.data(), with.size()}, g, origin, reading, model, ras,
                                                   &in_grid);
        const std::uint32_t b = trace_ray_opinions({without.data(), without.size()}, g, origin, reading, model, ras,
                                                   nullptr);
        CHECK(in_grid);
        CHECK(a == 11U);
        CHECK(b == a);
        CHECK(with == without);
        CHECK(with[g.index_of(VoxelCoord{10, 1, 1})] == model.reading_evidence());
        // A NaN or infinite reading: nothing written.
        const double nan = std::numeric_limits<double>::quiet_NaN();
        for (const Eigen::Vector3d& bad :
             {Eigen::Vector3d(nan, 0.15, 0.15), Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0.15, 0.15)}) {
            std::vector<std::int16_t> op(g.voxel_count(), kNoOpinion);
            bool flag = false;
            CHECK(trace_ray_opinions({op.data(), op.size()}, g, origin, bad, model, ras, &flag) == 0U);
            CHECK(std::count(op.begin(), op.end(), kNoOpinion) == static_cast<std::ptrdiff_t>(op.size()));
        }
    }
}

// verifies: SR-FUSE-008
TEST_CASE("fusion: a background frame whose fusion or accumulation fails is refused and the background untouched") {
    SmallGrid background;
    SmallGrid frame;
    const SensorModelTable model;
    const Eigen::Vector3f p(0.0F, 0.0F, 1.5625F);
    const SensorReading good = looking_along_x(Span<const Eigen::Vector3f>(&p, 1));
    SensorReading bad = good;
    bad.max_range = -1.0F;  // fails validate_sensor_reading
    CHECK(fuse_background_frame(background.grid, frame.grid, {&bad, 1U}, model, frame.scratch).error() ==
          ErrorCode::kInvalidArgument);
    CHECK(background.grid.observed_count() == 0U);
    // A clamp whose lower end is the never-foreground sentinel is refused after the frame was fused.
    const BackgroundClamp sentinel{kNeverForeground, 0};
    CHECK(fuse_background_frame(background.grid, frame.grid, {&good, 1U}, model, frame.scratch, Rasterization::kExact,
                                sentinel)
              .error() == ErrorCode::kInvalidArgument);
    CHECK(frame.grid.observed_count() > 0U);
    CHECK(background.grid.observed_count() == 0U);
    // The same frame with the default clamp is accumulated.
    REQUIRE(fuse_background_frame(background.grid, frame.grid, {&good, 1U}, model, frame.scratch).ok());
    CHECK(background.grid.observed_count() == frame.grid.observed_count());
}

// verifies: SR-FUSE-001
TEST_CASE(
    "fusion: a reading exactly on the grid's far face is outside it, and the last voxel gets the weakest free value") {
    SmallGrid s;
    const SensorModelTable model;
    const GridGeometry& g = s.grid.geometry();
    const Eigen::Vector3d origin(0.05, 0.15, 0.15);
    const Eigen::Vector3d reading(2.0, 0.15, 0.15);  // x = 2.0: the maximum face (half-open: outside)
    std::vector<std::int16_t> op(g.voxel_count(), kNoOpinion);
    bool in_grid = true;
    CHECK(trace_ray_opinions({op.data(), op.size()}, g, origin, reading, model, Rasterization::kExact, &in_grid) ==
          20U);
    CHECK_FALSE(in_grid);
    CHECK(op[g.index_of(VoxelCoord{19, 1, 1})] == model.free_evidence(0.0));
    CHECK(op[g.index_of(VoxelCoord{0, 1, 1})] == model.constant_free_evidence());
    CHECK(std::count(op.begin(), op.end(), model.reading_evidence()) == 0);
}

// verifies: SR-FUSE-001, SR-EVAL-005
TEST_CASE(
    "fusion: the reading loop hands every valid reading to its visitor as a ray, in pixel order, placed as fusion places it") {
    struct Recorder final : RayVisitor {
        std::vector<Eigen::Vector3d> origins;
        std::vector<Eigen::Vector3d> readings;
        RayOutcome ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& reading) noexcept override {
            origins.push_back(origin);
            readings.push_back(reading);
            return RayOutcome{3U, readings.size() % 2U == 1U};  // odd rays "in the grid"
        }
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> depth = {1.0F, nan, 0.0F, 2.0F, -1.0F, 9.0F};  // 3 x 2: two valid
    SensorReading r = looking_along_x(Span<const Eigen::Vector3f>());
    r.kind = SensorDataKind::kDepthImage;
    r.depth = Span<const float>(depth.data(), depth.size());
    r.intrinsics = PinholeIntrinsics{100.0, 100.0, 1.0, 0.5, 3, 2};
    REQUIRE(validate_sensor_reading(r).ok());
    Recorder rec;
    const FusionStats s = for_each_reading_ray(r, rec);
    REQUIRE(rec.readings.size() == 2U);
    const PinholeIntrinsics& k = r.intrinsics;
    CHECK(rec.readings[0] == reading_in_cell(r.pose, depth_pixel_point(k, 1.0 / k.fx, 1.0 / k.fy, 0, 0, 1.0F)));
    CHECK(rec.readings[1] == reading_in_cell(r.pose, depth_pixel_point(k, 1.0 / k.fx, 1.0 / k.fy, 0, 1, 2.0F)));
    CHECK(rec.origins[0] == r.pose.translation());
    CHECK(s.rays_fused == 2U);
    CHECK(s.readings_in_grid == 1U);
    CHECK(s.voxel_updates == 6U);
    CHECK(s.skipped_nan == 1U);
    CHECK(s.skipped_zero == 1U);
    CHECK(s.skipped_behind == 1U);
    CHECK(s.skipped_out_of_range == 1U);  // 9 m beyond max_range 5 m
}
