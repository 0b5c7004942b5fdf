// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the robot's own voxels of a cycle: every voxel a grown capsule may touch is marked, nothing else,
// the mask is rewritten each call, bad input marks the whole grid, and the work stays within its bound.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/robot/robot_mask.hpp"
#include "test_robot.hpp"

using namespace cellguard;
using cellguard::test::make_test_arm;
using cellguard::test::test_arm_joints;
using cellguard::test::test_arm_pose;

namespace {

constexpr double kHalfDiag = 0.8660254037844386;

GridGeometry small_grid() { return GridGeometry::make(Eigen::Vector3d(0.0, 0.0, 0.0), 0.05, {20, 16, 12}).value(); }

PlacedCapsule capsule(Eigen::Vector3d a, Eigen::Vector3d b, double r) {
    PlacedCapsule c;
    for (int k = 0; k < 3; ++k) {
        c.a[k] = a(k);
        c.b[k] = b(k);
    }
    c.radius = r;
    return c;
}

double segment_distance(const Eigen::Vector3d& p, const PlacedCapsule& c) {
    const Eigen::Vector3d a(c.a[0], c.a[1], c.a[2]);
    const Eigen::Vector3d b(c.b[0], c.b[1], c.b[2]);
    const Eigen::Vector3d d = b - a;
    const double dd = d.squaredNorm();
    const double t = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (p - (a + t * d)).norm();
}

// Checks @p mask against the definition: marked exactly when the voxel centre lies within
// radius + margin + half diagonal of some capsule's segment (voxels within 1e-9 m of that boundary are not judged).
void check_against_definition(const GridGeometry& g, const RobotPose& pose, double margin,
                              const std::vector<std::uint8_t>& mask, std::uint32_t marked) {
    std::uint32_t ones = 0;
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        const Eigen::Vector3d p = g.voxel_center(g.coord_of(i));
        double slack = std::numeric_limits<double>::infinity();
        bool inside = false;
        for (std::size_t c = 0; c < pose.count; ++c) {
            const double reach = pose.capsules[c].radius + margin + kHalfDiag * g.voxel_size();
            const double gap = segment_distance(p, pose.capsules[c]) - reach;
            inside = inside || gap <= 0.0;
            slack = std::min(slack, std::fabs(gap));
        }
        ones += mask[i];
        if (slack > 1e-9 && mask[i] != (inside ? 1U : 0U)) {
            ++wrong;
        }
        CHECK(mask[i] <= 1U);
    }
    CHECK(wrong == 0U);
    CHECK(ones == marked);
}

RobotPose one(const PlacedCapsule& c) {
    RobotPose p;
    p.count = 1U;
    p.capsules[0] = c;
    return p;
}

}  // namespace

// verifies: SR-ROB-020
TEST_CASE("a sphere and a slanted capsule mark exactly the voxels whose centres lie within reach") {
    const GridGeometry g = small_grid();
    std::vector<std::uint8_t> mask(g.voxel_count(), 7U);
    RobotMaskStats stats;
    const RobotPose sphere = one(capsule({0.5, 0.4, 0.3}, {0.5, 0.4, 0.3}, 0.1));
    REQUIRE(mark_robot_voxels(g, sphere, 0.05, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
    CHECK(stats.marked > 0U);
    check_against_definition(g, sphere, 0.05, mask, stats.marked);
    // The sphere's own centre voxel and its 6 neighbours are marked; a voxel 0.3 m away is not.
    CHECK(mask[g.index_of({10, 8, 6})] == 1U);
    CHECK(mask[g.index_of({9, 8, 6})] == 1U);
    CHECK(mask[g.index_of({16, 8, 6})] == 0U);

    RobotPose slanted = one(capsule({0.2, 0.1, 0.15}, {0.8, 0.6, 0.45}, 0.06));
    slanted.count = 2U;
    slanted.capsules[1] = capsule({0.9, 0.1, 0.1}, {0.9, 0.7, 0.1}, 0.03);
    REQUIRE(mark_robot_voxels(g, slanted, 0.02, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
    check_against_definition(g, slanted, 0.02, mask, stats.marked);
}

// verifies: SR-ROB-020
TEST_CASE("every voxel that a grown capsule touches is marked (conservative)") {
    const GridGeometry g = small_grid();
    std::vector<std::uint8_t> mask(g.voxel_count());
    RobotMaskStats stats;
    const PlacedCapsule c = capsule({0.13, 0.21, 0.17}, {0.71, 0.52, 0.33}, 0.045);
    const double margin = 0.03;
    REQUIRE(mark_robot_voxels(g, one(c), margin, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_real_distribution<double> t01(0.0, 1.0);
    const Eigen::Vector3d a(c.a[0], c.a[1], c.a[2]);
    const Eigen::Vector3d b(c.b[0], c.b[1], c.b[2]);
    std::size_t tested = 0;
    for (int i = 0; i < 20000; ++i) {
        // A point within radius + margin of the segment (rejection sampling in the ball).
        Eigen::Vector3d off(u(rng), u(rng), u(rng));
        if (off.norm() > 1.0) {
            continue;
        }
        const Eigen::Vector3d p = a + t01(rng) * (b - a) + (c.radius + margin) * off;
        const Result<VoxelCoord> v = g.world_to_voxel(p);
        REQUIRE(v.ok());
        CHECK(mask[g.index_of(v.value())] == 1U);
        ++tested;
    }
    CHECK(tested > 10000U);
}

// verifies: SR-ROB-021
TEST_CASE("capsules partly or wholly outside the grid mark what lies inside") {
    const GridGeometry g = small_grid();
    std::vector<std::uint8_t> mask(g.voxel_count());
    RobotMaskStats stats;
    // Crosses the x = 0 and z = max faces.
    const RobotPose across = one(capsule({-0.3, 0.4, 0.3}, {0.3, 0.4, 0.9}, 0.08));
    REQUIRE(mark_robot_voxels(g, across, 0.01, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
    CHECK(stats.marked > 0U);
    check_against_definition(g, across, 0.01, mask, stats.marked);
    // Wholly outside: nothing marked, nothing tested.
    const RobotPose outside = one(capsule({-1.0, -1.0, -1.0}, {-0.5, -2.0, -0.5}, 0.1));
    REQUIRE(mark_robot_voxels(g, outside, 0.01, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
    CHECK(stats.marked == 0U);
    CHECK(stats.tested == 0U);
    CHECK(std::count(mask.begin(), mask.end(), 0U) == static_cast<std::ptrdiff_t>(mask.size()));
    // Far beyond every face (10 m): still nothing, no overflow.
    const RobotPose far = one(capsule({1e6, 1e6, 1e6}, {-1e6, 1e6, 1e6}, 1.0));
    REQUIRE(mark_robot_voxels(g, far, 0.01, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
    CHECK(stats.marked == 0U);
}

// verifies: SR-ROB-022
TEST_CASE("the mask is rewritten each call: the robot's former voxels are cleared") {
    const GridGeometry g = small_grid();
    std::vector<std::uint8_t> mask(g.voxel_count() + 5U, 0xFFU);
    RobotMaskStats stats;
    const Span<std::uint8_t> span(mask.data(), mask.size());
    REQUIRE(mark_robot_voxels(g, one(capsule({0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}, 0.05)), 0.0, span, stats).ok());
    const std::uint32_t first = stats.marked;
    CHECK(mask[g.index_of({4, 4, 4})] == 1U);
    const RobotPose moved = one(capsule({0.8, 0.6, 0.4}, {0.8, 0.6, 0.4}, 0.05));
    REQUIRE(mark_robot_voxels(g, moved, 0.0, span, stats).ok());
    CHECK(stats.marked == first);
    CHECK(mask[g.index_of({4, 4, 4})] == 0U);
    std::vector<std::uint8_t> exact(mask.begin(), mask.begin() + static_cast<std::ptrdiff_t>(g.voxel_count()));
    check_against_definition(g, moved, 0.0, exact, stats.marked);
    CHECK(mask[g.voxel_count()] == 0xFFU);  // bytes beyond the grid are not touched
}

// verifies: SR-ROB-023
TEST_CASE("a bad margin or pose marks the whole grid as the robot's, a short mask is refused") {
    const GridGeometry g = small_grid();
    std::vector<std::uint8_t> mask(g.voxel_count(), 0U);
    RobotMaskStats stats;
    const Span<std::uint8_t> span(mask.data(), mask.size());
    const RobotPose good = one(capsule({0.2, 0.2, 0.2}, {0.4, 0.2, 0.2}, 0.05));
    for (const double margin :
         {-0.001, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        std::fill(mask.begin(), mask.end(), 0U);
        CHECK(mark_robot_voxels(g, good, margin, span, stats).error() == ErrorCode::kInvalidArgument);
        CHECK(std::count(mask.begin(), mask.end(), 1U) == static_cast<std::ptrdiff_t>(mask.size()));
        CHECK(stats.marked == g.voxel_count());
    }
    RobotPose bad = good;
    bad.capsules[0].b[1] = std::numeric_limits<double>::quiet_NaN();
    std::fill(mask.begin(), mask.end(), 0U);
    CHECK(mark_robot_voxels(g, bad, 0.01, span, stats).error() == ErrorCode::kInvalidArgument);
    CHECK(std::count(mask.begin(), mask.end(), 1U) == static_cast<std::ptrdiff_t>(mask.size()));
    bad = good;
    bad.capsules[0].radius = -0.1;
    CHECK(mark_robot_voxels(g, bad, 0.01, span, stats).error() == ErrorCode::kInvalidArgument);
    std::fill(mask.begin(), mask.end(), 9U);
    CHECK(mark_robot_voxels(g, good, 0.01, Span<std::uint8_t>(mask.data(), mask.size() - 1U), stats).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(mask[0] == 9U);
}

// verifies: SR-ROB-024
TEST_CASE("the test arm's mask covers its capsules, and the work stays within robot_mask_work_bound") {
    const RobotModel arm = make_test_arm(0.0, 0.0, 0.0);
    const double margin = 0.1;
    // A grid that holds the arm in every pose (no clipping: the bound is reached most closely).
    const GridGeometry big = GridGeometry::make(Eigen::Vector3d(-2.0, -2.0, -2.0), 0.05, {80, 80, 80}).value();
    const GridGeometry paper = paper_grid_geometry();
    const std::uint64_t bound = robot_mask_work_bound(arm, margin, 0.05);
    CHECK(bound > 0U);
    CHECK(robot_mask_work_bound(arm, -1.0, 0.05) == 0U);
    CHECK(robot_mask_work_bound(arm, margin, 0.0) == 0U);
    std::vector<std::uint8_t> mask(big.voxel_count());
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> q(-3.14, 3.14);
    std::uint64_t most = 0;
    for (int i = 0; i < 300; ++i) {
        const RobotPose pose = test_arm_pose(arm, test_arm_joints(q(rng), q(rng), q(rng), q(rng), q(rng), q(rng)));
        RobotMaskStats stats;
        const GridGeometry& g = (i % 2 == 0) ? big : paper;
        const cellguard::test::AllocationScope scope;
        REQUIRE(mark_robot_voxels(g, pose, margin, Span<std::uint8_t>(mask.data(), mask.size()), stats).ok());
        CHECK(scope.allocations() == 0U);
        CHECK(stats.tested <= bound);
        most = std::max(most, stats.tested);
        if (i % 2 == 0) {
            // Points along every capsule's axis lie in marked voxels.
            for (std::size_t c = 0; c < pose.count; ++c) {
                for (double t = 0.0; t <= 1.0; t += 0.125) {
                    const Eigen::Vector3d p(
                        pose.capsules[c].a[0] + t * (pose.capsules[c].b[0] - pose.capsules[c].a[0]),
                        pose.capsules[c].a[1] + t * (pose.capsules[c].b[1] - pose.capsules[c].a[1]),
                        pose.capsules[c].a[2] + t * (pose.capsules[c].b[2] - pose.capsules[c].a[2]));
                    CHECK(mask[big.index_of(big.world_to_voxel(p).value())] == 1U);
                }
            }
        }
    }
    MESSAGE("robot mask work: most tests " << most << ", bound " << bound);
    CHECK(most * 3U > bound);  // the bound is not absurdly loose
}

// verifies: SR-ROB-023
TEST_CASE("a pose with more capsules than capacity or a NaN or infinite radius marks the whole grid") {
    const GridGeometry g = small_grid();
    std::vector<std::uint8_t> mask(g.voxel_count(), 0U);
    RobotMaskStats stats;
    const Span<std::uint8_t> span(mask.data(), mask.size());
    RobotPose bad = one(capsule({0.2, 0.2, 0.2}, {0.4, 0.2, 0.2}, 0.05));
    bad.count = kMaxRobotCapsules + 1U;
    CHECK(mark_robot_voxels(g, bad, 0.01, span, stats).error() == ErrorCode::kInvalidArgument);
    CHECK(std::count(mask.begin(), mask.end(), 1U) == static_cast<std::ptrdiff_t>(mask.size()));
    for (const double r : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        bad = one(capsule({0.2, 0.2, 0.2}, {0.4, 0.2, 0.2}, 0.05));
        bad.capsules[0].radius = r;
        std::fill(mask.begin(), mask.end(), 0U);
        CHECK(mark_robot_voxels(g, bad, 0.01, span, stats).error() == ErrorCode::kInvalidArgument);
        CHECK(stats.marked == g.voxel_count());
    }
    bad = one(capsule({0.2, 0.2, 0.2}, {0.4, 0.2, 0.2}, 0.05));
    bad.capsules[0].a[0] = -std::numeric_limits<double>::infinity();
    CHECK(mark_robot_voxels(g, bad, 0.01, span, stats).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-ROB-024
TEST_CASE("robot_mask_work_bound is 0 for inputs it cannot bound and saturates for huge ones") {
    RobotModel arm = make_test_arm(0.0, 0.0, 0.0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(robot_mask_work_bound(arm, nan, 0.05) == 0U);
    CHECK(robot_mask_work_bound(arm, inf, 0.05) == 0U);
    CHECK(robot_mask_work_bound(arm, 0.1, nan) == 0U);
    CHECK(robot_mask_work_bound(arm, 0.1, inf) == 0U);
    CHECK(robot_mask_work_bound(arm, 0.1, -0.05) == 0U);
    CHECK(robot_mask_work_bound(arm, 0.0, 0.05) > 0U);           // margin 0 is allowed
    CHECK(robot_mask_work_bound(arm, 0.1, 1e-9) == UINT64_MAX);  // more tests than 64 bits: saturated
    arm.capsule_count = kMaxRobotCapsules + 1U;
    CHECK(robot_mask_work_bound(arm, 0.1, 0.05) == 0U);
}
