// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: grid geometry, index math, world <-> voxel conversion.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cellguard/grid/grid.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

// verifies: SR-GRID-001
TEST_CASE("grid: the paper's grid has 34 x 30 x 30 voxels of 5 cm") {
    const GridGeometry g = paper_grid_geometry();
    CHECK(g.voxel_count() == 30600U);
    CHECK(g.voxel_size() == doctest::Approx(0.05));
    CHECK(g.max_corner().x() == doctest::Approx(0.85));
    CHECK(whole_cell_grid_geometry().voxel_count() == 256U * 256U * 128U);
}

// verifies: SR-GRID-001
TEST_CASE("grid: linear index and coordinate are inverse, x fastest") {
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 1.0, GridDims{5, 4, 3}).value();
    CHECK(g.index_of(VoxelCoord{1, 0, 0}) == 1U);
    CHECK(g.index_of(VoxelCoord{0, 1, 0}) == 5U);
    CHECK(g.index_of(VoxelCoord{0, 0, 1}) == 20U);
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        CHECK(g.index_of(g.coord_of(i)) == i);
    }
    CHECK(test::violates_contract([&] { (void)g.coord_of(g.voxel_count()); }));
}

// verifies: SR-GRID-001
TEST_CASE("grid: world to voxel uses half-open cells and rejects points outside") {
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-1.0, -1.0, 0.0), 0.5, GridDims{4, 4, 2}).value();
    CHECK(g.world_to_voxel(Eigen::Vector3d(-1.0, -1.0, 0.0)).value() == VoxelCoord{0, 0, 0});
    CHECK(g.world_to_voxel(Eigen::Vector3d(-0.5, -1.0, 0.0)).value() ==
          VoxelCoord{1, 0, 0});  // on a face: the voxel above
    CHECK(g.world_to_voxel(Eigen::Vector3d(0.99, 0.99, 0.99)).value() == VoxelCoord{3, 3, 1});
    CHECK(g.world_to_voxel(Eigen::Vector3d(1.0, 0.0, 0.0)).error() == ErrorCode::kOutOfGrid);  // max face is outside
    CHECK(g.world_to_voxel(Eigen::Vector3d(0.0, 0.0, -1e-9)).error() == ErrorCode::kOutOfGrid);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(g.world_to_voxel(Eigen::Vector3d(nan, 0.0, 0.0)).error() == ErrorCode::kNonFiniteValue);
    const Eigen::Vector3d c = g.voxel_center(VoxelCoord{1, 2, 1});
    CHECK(c.x() == doctest::Approx(-0.25));
    CHECK(c.y() == doctest::Approx(0.25));
    CHECK(c.z() == doctest::Approx(0.75));
}

// verifies: SR-GRID-001
TEST_CASE("grid: invalid geometries are rejected with a clear error") {
    const Eigen::Vector3d o = Eigen::Vector3d::Zero();
    CHECK(GridGeometry::make(o, 0.0, GridDims{1, 1, 1}).error() == ErrorCode::kInvalidArgument);
    CHECK(GridGeometry::make(o, -1.0, GridDims{1, 1, 1}).error() == ErrorCode::kInvalidArgument);
    CHECK(GridGeometry::make(o, std::numeric_limits<double>::infinity(), GridDims{1, 1, 1}).error() ==
          ErrorCode::kNonFiniteValue);
    CHECK(GridGeometry::make(Eigen::Vector3d(0.0, std::nan(""), 0.0), 0.1, GridDims{1, 1, 1}).error() ==
          ErrorCode::kNonFiniteValue);
    CHECK(GridGeometry::make(o, 0.1, GridDims{0, 1, 1}).error() == ErrorCode::kInvalidArgument);
    CHECK(GridGeometry::make(o, 0.1, GridDims{1, 1, -2}).error() == ErrorCode::kInvalidArgument);
    CHECK(GridGeometry::make(o, 0.1, GridDims{1, kMaxDimension + 1, 1}).error() == ErrorCode::kInvalidArgument);
    CHECK(GridGeometry::make(o, 0.1, GridDims{4096, 4096, 16}).error() == ErrorCode::kCapacityExceeded);
}

// verifies: SR-GRID-001
TEST_CASE("grid: voxel coordinates and dimensions are equal exactly when every component is") {
    constexpr VoxelCoord a{3, -4, 5};
    static_assert(a == VoxelCoord{3, -4, 5}, "equal components");
    CHECK(a == VoxelCoord{3, -4, 5});
    CHECK(a != VoxelCoord{2, -4, 5});
    CHECK(a != VoxelCoord{3, 4, 5});
    CHECK(a != VoxelCoord{3, -4, -5});
    CHECK_FALSE(a == VoxelCoord{3, -4, -5});
    CHECK_FALSE(a != VoxelCoord{3, -4, 5});
    constexpr std::int32_t lo = std::numeric_limits<std::int32_t>::min();
    constexpr std::int32_t hi = std::numeric_limits<std::int32_t>::max();
    CHECK(VoxelCoord{lo, hi, 0} == VoxelCoord{lo, hi, 0});
    CHECK(VoxelCoord{lo, hi, 0} != VoxelCoord{hi, lo, 0});
    CHECK(VoxelCoord{0, 0, lo} != VoxelCoord{0, 0, hi});
    CHECK_FALSE(VoxelCoord{lo, hi, 0} == VoxelCoord{hi, lo, 0});
    CHECK_FALSE(VoxelCoord{0, 0, lo} != VoxelCoord{0, 0, lo});
    CHECK(GridDims{4, 5, 6} == GridDims{4, 5, 6});
    CHECK_FALSE(GridDims{4, 5, 6} == GridDims{5, 5, 6});
    CHECK_FALSE(GridDims{4, 5, 6} == GridDims{4, 6, 6});
    CHECK_FALSE(GridDims{4, 5, 6} == GridDims{4, 5, 7});
}

// verifies: SR-GRID-001
TEST_CASE("grid: world_to_voxel_unchecked takes the floor of every scaled coordinate, faces and negatives included") {
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, 0.0), 0.05, GridDims{34, 30, 30}).value();
    std::uint64_t state = 0x9E3779B97F4A7C15ULL;
    const auto next = [&state]() {
        state ^= state << 13U;
        state ^= state >> 7U;
        state ^= state << 17U;
        return static_cast<double>(state >> 11U) * 0x1.0p-53;  // [0, 1)
    };
    std::vector<double> xs{0.0, -0.0, 0.05, -0.05, 1e-17, -1e-17, 0.049999999999999996, 1e6, -1e6, 0.25, -0.85};
    for (int i = 0; i < 20000; ++i) {
        const double r = (next() - 0.5) * 20.0;                                               // metres, +-10 m
        xs.push_back(i % 2 == 0 ? r : std::round(r * 20.0) / 20.0 + (next() - 0.5) * 1e-15);  // near faces
    }
    for (const double x : xs) {
        const Eigen::Vector3d p(x, -x, x + 0.5);
        const Eigen::Vector3d scaled = (p - g.origin()) / g.voxel_size();
        const VoxelCoord c = g.world_to_voxel_unchecked(p);
        CHECK(c.x == static_cast<std::int32_t>(std::floor(scaled.x())));
        CHECK(c.y == static_cast<std::int32_t>(std::floor(scaled.y())));
        CHECK(c.z == static_cast<std::int32_t>(std::floor(scaled.z())));
    }
}
