// Requirements: multi-sensor ray fusion (independent opinion pool), skipped
// readings, validation of sensor descriptions, no allocation while fusing.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/fusion.hpp"
#include "cellguard/sim/workcell.hpp"

using namespace cellguard;

namespace {

// A 20 x 4 x 4 grid of 10 cm voxels from the origin.
struct SmallGrid {
    static constexpr std::size_t kN = 20U * 4U * 4U;
    std::int16_t lo[kN];
    std::uint8_t ob[kN];
    EvidenceGrid grid;
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
    const FusionStats st = fuse_sensor(s.grid, r, model).value();
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
    CHECK_FALSE(s.seen(5, 2, 1));   // not on the ray
    CHECK(s.grid.observed_count() == 11U);
}

// verifies: SR-FUSE-002
TEST_CASE("fusion: the evidence of every ray adds (independent opinion pool)") {
    SmallGrid s;
    const SensorModelTable model;
    const Eigen::Vector3f pts[3] = {{0.0F, 0.0F, 1.55F}, {0.0F, 0.0F, 1.55F}, {0.0F, 0.0F, 1.55F}};
    const SensorReading r = looking_along_x(pts);
    REQUIRE(fuse_sensor(s.grid, r, model).ok());
    CHECK(s.at(10, 1, 1) == 3 * model.reading_evidence());
    CHECK(s.at(3, 1, 1) == 3 * model.constant_free_evidence());
}

// verifies: SR-FUSE-002
TEST_CASE("fusion: evidence saturates instead of wrapping when very many rays cross a voxel") {
    SmallGrid s;
    const SensorModelTable model;
    std::vector<Eigen::Vector3f> pts(2000, Eigen::Vector3f(0.0F, 0.0F, 1.55F));
    const SensorReading r = looking_along_x(Span<const Eigen::Vector3f>(pts.data(), pts.size()));
    REQUIRE(fuse_sensor(s.grid, r, model).ok());
    CHECK(s.at(3, 1, 1) == kLogOddsMin);  // 2000 * -61 would wrap an int16
    CHECK(s.at(10, 1, 1) == kLogOddsMax);
}

// verifies: SR-FUSE-003
TEST_CASE("fusion: NaN, infinite, zero, behind-the-sensor and out-of-range readings are skipped and counted") {
    SmallGrid s;
    const SensorModelTable model;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Eigen::Vector3f pts[] = {
        {nan, 0.0F, 1.0F}, {0.0F, inf, 1.0F}, {0.0F, 0.0F, 0.0F}, {0.0F, 0.0F, -1.0F},
        {0.0F, 0.0F, 9.0F},  // beyond max_range 5 m
        {0.0F, 0.0F, 0.05F}, // nearer than min_range
    };
    SensorReading r = looking_along_x(pts);
    r.min_range = 0.1F;
    const FusionStats st = fuse_sensor(s.grid, r, model).value();
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
    const FusionStats st = fuse_sensor(s.grid, r, model).value();
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
    REQUIRE(fuse_sensor(s.grid, r, model).value().readings_in_grid == 1U);
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
    CHECK(fuse_frame(s.grid, two, model).error() == ErrorCode::kInvalidArgument);
    CHECK(s.grid.observed_count() == 0U);  // the good sensor was not fused either

    SensorReading bad_range = good;
    bad_range.max_range = 0.0F;
    CHECK(fuse_sensor(s.grid, bad_range, model).error() == ErrorCode::kInvalidArgument);
    SensorReading nan_pose = good;
    nan_pose.pose.translation().x() = std::nan("");
    CHECK(fuse_sensor(s.grid, nan_pose, model).error() == ErrorCode::kNonFiniteValue);
    SensorReading bad_image = good;
    bad_image.kind = SensorDataKind::kDepthImage;
    bad_image.intrinsics = PinholeIntrinsics{100.0, 100.0, 1.0, 1.0, 3, 2};
    const float five[5] = {};
    bad_image.depth = five;
    CHECK(fuse_sensor(s.grid, bad_image, model).error() == ErrorCode::kMalformedInput);
    bad_image.intrinsics.fx = 0.0;
    CHECK(fuse_sensor(s.grid, bad_image, model).error() == ErrorCode::kInvalidArgument);
    SensorReading many[kMaxSensors + 1];
    for (auto& m : many) m = good;
    CHECK(fuse_frame(s.grid, many, model).error() == ErrorCode::kCapacityExceeded);
    CHECK(s.grid.observed_count() == 0U);
}

// verifies: SR-GEN-002
TEST_CASE("fusion: fusing the simulated four-sensor frame allocates no memory") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()),
                                           Span<std::uint8_t>(ob.data(), ob.size())).value();
    const SensorModelTable model;
    const Span<const SensorReading> readings(frame.readings.data(), frame.readings.size());
    const test::AllocationScope scope;
    grid.clear();
    const Result<FusionStats> st = fuse_frame(grid, readings, model);
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
                                           Span<std::uint8_t>(ob.data(), ob.size())).value();
    const SensorModelTable model;
    const Span<const SensorReading> readings(frame.readings.data(), frame.readings.size());
    grid.clear();
    const FusionStats exact = fuse_frame(grid, readings, model, Rasterization::kExact).value();
    grid.clear();
    const FusionStats bres = fuse_frame(grid, readings, model, Rasterization::kBresenham3d).value();
    CHECK(exact.rays_fused == bres.rays_fused);
    CHECK(bres.voxel_updates < exact.voxel_updates);  // Bresenham misses voxels
    CHECK(bres.voxel_updates > exact.voxel_updates / 3U);  // one voxel per dominant-axis step
}
