// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: a real RGB-D frame (PCL's Kinect test data) fuses into a grid
// without surprises: NaN pixels are skipped and counted, every valid reading
// becomes a ray, and fusing allocates nothing.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/io/pcd.hpp"

using namespace cellguard;

// verifies: SR-FUSE-001, SR-FUSE-003
TEST_CASE("fusion: a real Kinect frame with NaN pixels fuses, skipping and counting every invalid pixel") {
    const std::string path = std::string(CELLGUARD_TEST_DATA_DIR) + "/kinect-frames/frame_20121214T142255.814212.pcd";
    std::vector<PcdPoint> raw(640U * 480U);
    PcdCloudInfo info;
    PcdReadOptions keep;
    keep.keep_nonfinite = true;  // fusion must see the NaN pixels itself
    const IoStatus read = read_pcd(path.c_str(), {raw.data(), raw.size()}, info, keep);
    REQUIRE_MESSAGE(read.ok(), read.message());
    REQUIRE(info.written == 307200U);
    std::vector<Eigen::Vector3f> points(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i)
        points[i] = Eigen::Vector3f(raw[i].x, raw[i].y, raw[i].z);

    // The camera at the origin looking along +z; a 4 m x 3 m x 3 m grid in front of it.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-2.0, -1.5, 0.0), 0.05, GridDims{80, 60, 60}).value();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
    grid.clear();
    SensorReading r;
    r.kind = SensorDataKind::kPointSet;
    r.points = Span<const Eigen::Vector3f>(points.data(), points.size());
    r.max_range = 8.0F;
    const SensorModelTable model;
    std::vector<std::int16_t> scratch(g.voxel_count());
    const test::AllocationScope scope;
    const FusionStats s = fuse_sensor(grid, r, model, {scratch.data(), scratch.size()}).value();
    CHECK(scope.allocations() == 0U);
    CHECK(s.skipped_nan == info.nonfinite_points);  // 35,625 NaN pixels in this frame
    CHECK(s.skipped_nan == 35625U);
    CHECK(s.rays_fused + s.skipped() == 307200U);
    CHECK(s.rays_fused == info.finite_points);  // every valid reading lies within 8 m
    CHECK(s.readings_in_grid == s.rays_fused);  // and inside the grid (z 0.67 .. 1.73 m)
    // The office scene: free space in front of the surfaces, occupied at them, nothing behind.
    std::size_t occupied = 0, free_voxels = 0;
    for (std::size_t i = 0; i < lo.size(); ++i) {
        if (ob[i] == 0U)
            continue;
        occupied += lo[i] > 0 ? 1U : 0U;
        free_voxels += lo[i] < 0 ? 1U : 0U;
    }
    MESSAGE("observed " << grid.observed_count() << " voxels: " << occupied << " occupied, " << free_voxels << " free");
    CHECK(occupied > 500U);  // about 800 surface voxels of 5 cm
    CHECK(free_voxels > occupied);
    const std::size_t far_corner = g.index_of(VoxelCoord{79, 59, 59});  // behind every surface (z = 3 m)
    CHECK(ob[far_corner] == 0U);
}
