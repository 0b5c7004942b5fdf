// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: speed and separation monitoring: S_p per ISO/TS 15066, the distance from the robot's capsules to
// foreground voxels and to unseen voxels of the active zones, the minimum counts, the speed request's thresholds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/robot/robot_mask.hpp"
#include "cellguard/robot/separation.hpp"
#include "contract_capture.hpp"
#include "test_robot.hpp"

using namespace cellguard;
using cellguard::test::make_test_arm;
using cellguard::test::test_arm_joints;
using cellguard::test::test_arm_pose;

namespace {

constexpr double kHalfDiag = 0.8660254037844386;

// Demo-like parameters: a 100 ms cycle plus PLC and robot make T_r = 0.2 s; class 0 full speed, class 1 reduced;
// C = 208 mm (ISO 13855, detection capability 40 mm: 8 (40 - 14) mm).
SeparationParams demo_params() {
    SeparationParams p;
    p.human_speed_mps = 1.6;
    p.reaction_time_s = 0.2;
    p.class_count = 2U;
    p.classes[0] = SpeedClassLimits{1.0, 0.3, 0.2};
    p.classes[1] = SpeedClassLimits{0.25, 0.1, 0.02};
    p.reduced_class = 1U;
    p.slowdown_time_s = 0.5;
    p.intrusion_distance_m = 0.208;
    p.sensing_uncertainty_m = 0.1;
    p.robot_uncertainty_m = 0.02;
    return p;
}

// A grid with every voxel observed, empty and accessible (prior -100), no zones, no robot voxels.
struct Cell {
    GridGeometry g;
    std::vector<std::int16_t> frame;
    std::vector<std::uint8_t> observed;
    std::vector<std::int16_t> prior;
    std::vector<std::uint8_t> mask;
    std::vector<std::uint32_t> zones;
    std::uint32_t active = 0U;

    explicit Cell(const GridGeometry& geometry)
        : g(geometry),
          frame(g.voxel_count(), 0),
          observed(g.voxel_count(), 1U),
          prior(g.voxel_count(), -100),
          mask(g.voxel_count(), 0U),
          zones(g.voxel_count(), 0U) {}

    SeparationInputs inputs() const {
        SeparationInputs in;
        in.frame_log_odds = {frame.data(), frame.size()};
        in.observed = {observed.data(), observed.size()};
        in.prior = {prior.data(), prior.size()};
        in.robot_mask = {mask.data(), mask.size()};
        in.zone_membership = {zones.data(), zones.size()};
        in.active_zones = active;
        return in;
    }
    std::size_t at(std::int32_t x, std::int32_t y, std::int32_t z) const { return g.index_of({x, y, z}); }
    void foreground(std::int32_t x, std::int32_t y, std::int32_t z) { frame[at(x, y, z)] = 1000; }
    void unseen(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t zone_bits) {
        observed[at(x, y, z)] = 0U;
        zones[at(x, y, z)] = zone_bits;
    }
};

GridGeometry small_grid() { return GridGeometry::make(Eigen::Vector3d(0.0, 0.0, 0.0), 0.05, {40, 10, 10}).value(); }

// A sphere of radius 0.1 m centred on voxel (5, 5, 5) of the small grid.
RobotPose sphere_pose() {
    RobotPose p;
    p.count = 1U;
    for (int k = 0; k < 3; ++k) {
        p.capsules[0].a[k] = 0.275;
        p.capsules[0].b[k] = 0.275;
    }
    p.capsules[0].radius = 0.1;
    return p;
}

SeparationResult run(const Cell& cell, const RobotPose& pose, const SeparationParams& params,
                     std::uint8_t speed_class = 0U) {
    SeparationResult out;
    REQUIRE(compute_separation(cell.g, cell.inputs(), pose, params, speed_class, out).ok());
    return out;
}

double segment_distance(const Eigen::Vector3d& p, const PlacedCapsule& c) {
    const Eigen::Vector3d a(c.a[0], c.a[1], c.a[2]);
    const Eigen::Vector3d d = Eigen::Vector3d(c.b[0], c.b[1], c.b[2]) - a;
    const double dd = d.squaredNorm();
    const double t = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (p - (a + t * d)).norm();
}

// The definition, by brute force: every candidate's distance, sorted, the k-th in mm (rounded down).
std::uint16_t reference_mm(const Cell& cell, const RobotPose& pose, bool hidden_kind, std::uint32_t k) {
    std::vector<double> d;
    for (std::size_t i = 0; i < cell.g.voxel_count(); ++i) {
        if (cell.mask[i] != 0U) {
            continue;
        }
        const bool fg = add_saturating(cell.frame[i], cell.prior[i]) >= 255;
        const bool hidden = cell.observed[i] == 0U && cell.prior[i] != kNeverForeground && cell.prior[i] >= -754 &&
                            (cell.zones[i] & cell.active) != 0U;
        if (hidden_kind ? !hidden : !fg) {
            continue;
        }
        const Eigen::Vector3d p = cell.g.voxel_center(cell.g.coord_of(i));
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < pose.count; ++c) {
            best = std::min(best, segment_distance(p, pose.capsules[c]) - pose.capsules[c].radius -
                                      kHalfDiag * cell.g.voxel_size());
        }
        d.push_back(std::max(best, 0.0));
    }
    if (d.size() < k) {
        return kDistanceFarMm;
    }
    std::sort(d.begin(), d.end());
    return static_cast<std::uint16_t>(std::min(65535.0, std::floor(d[k - 1U] * 1000.0)));
}

}  // namespace

// verifies: SR-SSM-001
TEST_CASE("S_p and the reduced-speed distance follow ISO/TS 15066 with demo-like numbers") {
    const SeparationParams p = demo_params();
    REQUIRE(check_separation_params(p).ok());
    // S_p(0) = 1.6 (0.2 + 0.3) + 1.0 * 0.2 + 0.2 + 0.208 + 0.1 + 0.02 = 1.528 m.
    CHECK(protective_separation_distance(p, 0U) == doctest::Approx(1.528).epsilon(1e-12));
    // S_p(1) = 1.6 (0.2 + 0.1) + 0.25 * 0.2 + 0.02 + 0.208 + 0.1 + 0.02 = 0.878 m.
    CHECK(protective_separation_distance(p, 1U) == doctest::Approx(0.878).epsilon(1e-12));
    // Reduced below S_p(0) + (1.6 + 1.0) 0.5 = 2.828 m.
    CHECK(reduced_speed_distance(p) == doctest::Approx(2.828).epsilon(1e-12));
}

// verifies: SR-SSM-002
TEST_CASE("check_separation_params refuses what cannot be commissioned") {
    CHECK(check_separation_params(SeparationParams{}).ok());
    const auto refused = [](void (*change)(SeparationParams&)) {
        SeparationParams p = demo_params();
        change(p);
        return check_separation_params(p).error() == ErrorCode::kInvalidArgument;
    };
    CHECK(refused([](SeparationParams& p) { p.class_count = 0U; }));
    CHECK(refused([](SeparationParams& p) { p.class_count = 5U; }));
    CHECK(refused([](SeparationParams& p) { p.reduced_class = 2U; }));
    CHECK(refused([](SeparationParams& p) { p.min_foreground_voxels = 0U; }));
    CHECK(refused([](SeparationParams& p) { p.min_hidden_voxels = 0U; }));
    CHECK(refused([](SeparationParams& p) { p.min_foreground_voxels = kMaxSeparationVoxelCount + 1U; }));
    CHECK(refused([](SeparationParams& p) { p.min_hidden_voxels = kMaxSeparationVoxelCount + 1U; }));
    CHECK(refused([](SeparationParams& p) { p.human_speed_mps = -1.6; }));
    CHECK(refused([](SeparationParams& p) { p.reaction_time_s = std::numeric_limits<double>::quiet_NaN(); }));
    CHECK(refused([](SeparationParams& p) { p.slowdown_time_s = std::numeric_limits<double>::infinity(); }));
    CHECK(refused([](SeparationParams& p) { p.intrusion_distance_m = -0.001; }));
    CHECK(refused([](SeparationParams& p) { p.sensing_uncertainty_m = -0.001; }));
    CHECK(refused([](SeparationParams& p) { p.robot_uncertainty_m = -0.001; }));
    CHECK(refused([](SeparationParams& p) { p.classes[1].robot_speed_mps = -1.0; }));
    CHECK(refused([](SeparationParams& p) { p.classes[0].stopping_time_s = std::nan(""); }));
    CHECK(refused([](SeparationParams& p) { p.classes[1].stopping_distance_m = -0.1; }));
    SeparationParams p = demo_params();
    p.classes[3].robot_speed_mps = -1.0;  // beyond class_count: not read
    p.min_foreground_voxels = kMaxSeparationVoxelCount;
    CHECK(check_separation_params(p).ok());
}

// verifies: SR-SSM-002
TEST_CASE("check_separation_params refuses an S_p or reduced-speed distance that the millimetre field cannot hold") {
    // At 65.535 m a distance is capped to kDistanceFarMm, the value of "no voxel": a voxel inside S_p but that
    // far away read as far as S_p and asked for full speed (found on 2026-11-26 with a human speed of 1000 m/s).
    SeparationParams p = demo_params();
    p.human_speed_mps = 1000.0;
    CHECK(check_separation_params(p).error() == ErrorCode::kInvalidArgument);
    p = demo_params();
    p.slowdown_time_s = 0.0;  // the reduced-speed distance is S_p(0) here, the largest S_p
    p.intrusion_distance_m += 65.534 - 1e-9 - protective_separation_distance(p, 0U);
    REQUIRE(protective_separation_distance(p, 0U) <= 65.534);
    CHECK(check_separation_params(p).ok());
    p.intrusion_distance_m += 0.002;  // S_p(0) beyond 65.534 m
    CHECK(check_separation_params(p).error() == ErrorCode::kInvalidArgument);
    p = demo_params();
    p.slowdown_time_s = 30.0;  // only the reduced-speed distance beyond: (1.6 + 1.0) * 30 = 78 m
    CHECK(reduced_speed_distance(p) > 65.534);
    CHECK(check_separation_params(p).error() == ErrorCode::kInvalidArgument);
    p.human_speed_mps = std::numeric_limits<double>::max();  // finite values whose distance overflows to infinity
    p.slowdown_time_s = 0.5;
    CHECK(check_separation_params(p).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-SSM-003
TEST_CASE("a foreground voxel at a known distance: centre to capsule surface less half a diagonal, in mm") {
    Cell cell(small_grid());
    const SeparationParams p = demo_params();
    SeparationResult r = run(cell, sphere_pose(), p);
    CHECK(r.distance_mm == kDistanceFarMm);
    CHECK(r.foreground_mm == kDistanceFarMm);
    CHECK(r.hidden_mm == kDistanceFarMm);
    CHECK(r.request == SpeedRequest::kFull);
    CHECK(r.candidates == 0U);
    // 10 voxels along x: 0.5 - 0.1 - 0.0433 = 0.35670 m.
    cell.foreground(15, 5, 5);
    r = run(cell, sphere_pose(), p);
    CHECK(r.foreground_mm == 356U);
    CHECK(r.distance_mm == 356U);
    CHECK(r.hidden_mm == kDistanceFarMm);
    CHECK(r.candidates == 1U);
    // A diagonal neighbour: sqrt(3) * 0.05 - 0.1 - 0.0433 < 0: clamped to 0.
    cell.foreground(6, 6, 6);
    r = run(cell, sphere_pose(), p);
    CHECK(r.foreground_mm == 0U);
    // A capsule instead of the sphere: from (0.275, 0.275, 0.275) to (1.275, 0.275, 0.275). The voxel at
    // (31, 0, 9), centre (1.575, 0.025, 0.475), lies 0.3 in x beyond b, 0.25 in y and 0.2 in z:
    // |(0.3, 0.25, 0.2)| = 0.43875 - 0.1 - 0.04330 = 0.29545 m.
    Cell other(small_grid());
    RobotPose capsule = sphere_pose();
    capsule.capsules[0].b[0] = 1.275;
    other.foreground(31, 0, 9);
    CHECK(run(other, capsule, p).foreground_mm == 295U);
}

// verifies: SR-SSM-004
TEST_CASE("min_foreground_voxels and min_hidden_voxels: the distance within which that many lie") {
    Cell cell(small_grid());
    SeparationParams p = demo_params();
    cell.foreground(15, 5, 5);  // 0.5 m from the centre
    cell.foreground(25, 5, 5);  // 1.0 m
    cell.foreground(35, 5, 5);  // 1.5 m
    const std::uint16_t expected[] = {356U, 856U, 1356U, kDistanceFarMm};
    for (std::uint32_t k = 1; k <= 4U; ++k) {
        p.min_foreground_voxels = k;
        INFO("k = " << k);
        CHECK(run(cell, sphere_pose(), p).foreground_mm == expected[k - 1U]);
    }
    cell.active = 1U;
    cell.unseen(13, 5, 5, 1U);  // 0.4 m
    cell.unseen(23, 5, 5, 1U);  // 0.9 m
    p.min_foreground_voxels = 3U;
    p.min_hidden_voxels = 2U;
    SeparationResult r = run(cell, sphere_pose(), p);
    CHECK(r.hidden_mm == 756U);
    CHECK(r.foreground_mm == 1356U);
    CHECK(r.distance_mm == 756U);
    p.min_hidden_voxels = 1U;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == 256U);
    p.min_hidden_voxels = 3U;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == kDistanceFarMm);
}

// verifies: SR-SSM-005
TEST_CASE("unseen voxels count only inside the active case's zones, and only where the prior makes them accessible") {
    Cell cell(small_grid());
    const SeparationParams p = demo_params();
    cell.unseen(15, 5, 5, 0x4U);                                     // zone 2 only
    CHECK(run(cell, sphere_pose(), p).hidden_mm == kDistanceFarMm);  // no active zones
    cell.active = 0x3U;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == kDistanceFarMm);  // zones 0 and 1 active
    cell.active = 0x5U;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == 356U);
    // The prior: never foreground, or below accessible_min_prior (-754), is not unseen space a person can be in.
    cell.prior[cell.at(15, 5, 5)] = kNeverForeground;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == kDistanceFarMm);
    cell.prior[cell.at(15, 5, 5)] = -755;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == kDistanceFarMm);
    cell.prior[cell.at(15, 5, 5)] = -754;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == 356U);
    // Observed voxels are not unseen.
    cell.observed[cell.at(15, 5, 5)] = 1U;
    CHECK(run(cell, sphere_pose(), p).hidden_mm == kDistanceFarMm);
    // Foreground counts anywhere, zone or not; it is frame + prior that must reach the threshold.
    cell.frame[cell.at(15, 5, 5)] = 300;
    CHECK(run(cell, sphere_pose(), p).foreground_mm == kDistanceFarMm);  // 300 - 754 < 255
    cell.prior[cell.at(15, 5, 5)] = -45;
    CHECK(run(cell, sphere_pose(), p).foreground_mm == 356U);  // 300 - 45 = 255
}

// verifies: SR-SSM-006
TEST_CASE("the robot's own voxels are neither foreground nor unseen for the separation check") {
    Cell cell(small_grid());
    const SeparationParams p = demo_params();
    cell.active = 1U;
    cell.foreground(6, 5, 5);
    cell.unseen(5, 6, 5, 1U);
    SeparationResult r = run(cell, sphere_pose(), p);
    CHECK(r.foreground_mm == 0U);
    CHECK(r.hidden_mm == 0U);
    CHECK(r.request == SpeedRequest::kProtectiveStop);
    RobotMaskStats stats;
    REQUIRE(
        mark_robot_voxels(cell.g, sphere_pose(), 0.05, Span<std::uint8_t>(cell.mask.data(), cell.mask.size()), stats)
            .ok());
    REQUIRE(cell.mask[cell.at(6, 5, 5)] == 1U);
    r = run(cell, sphere_pose(), p);
    CHECK(r.foreground_mm == kDistanceFarMm);
    CHECK(r.hidden_mm == kDistanceFarMm);
    CHECK(r.request == SpeedRequest::kFull);
}

// verifies: SR-SSM-007
TEST_CASE("the speed request: stop below S_p of the current class, reduced below the slow-down distance") {
    // One long grid along x, 1 cm voxels, a sphere of radius 0.1 at x = 0.005 + half diagonal offsets removed:
    // a foreground voxel at x index i lies (i * 0.01) - 0.1 - 0.00866 m away.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(0.0, 0.0, 0.0), 0.01, {400, 1, 1}).value();
    RobotPose pose;
    pose.count = 1U;
    pose.capsules[0].a[0] = pose.capsules[0].b[0] = 0.005;
    pose.capsules[0].a[1] = pose.capsules[0].b[1] = 0.005;
    pose.capsules[0].a[2] = pose.capsules[0].b[2] = 0.005;
    pose.capsules[0].radius = 0.1;
    const SeparationParams p = demo_params();  // S_p(0) 1528 mm, S_p(1) 878 mm, reduced below 2828 mm
    const auto at = [&](std::int32_t i, std::uint8_t speed_class) {
        Cell cell(g);
        cell.foreground(i, 0, 0);
        return run(cell, pose, p, speed_class);
    };
    // Voxel i: d_mm = floor(10 i - 108.66).
    SeparationResult r = at(163, 0U);  // 1521 mm < 1528: stop at full speed
    CHECK(r.distance_mm == 1521U);
    CHECK(r.required_mm == 1528U);
    CHECK(r.request == SpeedRequest::kProtectiveStop);
    r = at(164, 0U);  // 1531 mm: reduced (below 2828)
    CHECK(r.request == SpeedRequest::kReduced);
    r = at(163, 1U);  // in the reduced class, S_p(1) = 878: reduced, not stop
    CHECK(r.required_mm == 878U);
    CHECK(r.request == SpeedRequest::kReduced);
    r = at(98, 1U);  // 871 mm < 878: stop
    CHECK(r.distance_mm == 871U);
    CHECK(r.request == SpeedRequest::kProtectiveStop);
    r = at(99, 1U);  // 881 mm
    CHECK(r.request == SpeedRequest::kReduced);
    r = at(293, 0U);  // 2821 mm < 2828: reduced
    CHECK(r.request == SpeedRequest::kReduced);
    r = at(294, 0U);  // 2831 mm: full
    CHECK(r.distance_mm == 2831U);
    CHECK(r.request == SpeedRequest::kFull);
}

// verifies: SR-SSM-008
TEST_CASE("compute_separation refuses short spans, an unknown speed class and bad parameters with a stop") {
    Cell cell(small_grid());
    const SeparationParams p = demo_params();
    SeparationResult out;
    SeparationInputs in = cell.inputs();
    in.prior = Span<const std::int16_t>(cell.prior.data(), cell.prior.size() - 1U);
    CHECK(compute_separation(cell.g, in, sphere_pose(), p, 0U, out).error() == ErrorCode::kStorageTooSmall);
    CHECK(out.request == SpeedRequest::kProtectiveStop);
    in = cell.inputs();
    in.zone_membership = {};
    CHECK(compute_separation(cell.g, in, sphere_pose(), p, 0U, out).error() == ErrorCode::kStorageTooSmall);
    CHECK(compute_separation(cell.g, cell.inputs(), sphere_pose(), p, 2U, out).error() == ErrorCode::kInvalidArgument);
    CHECK(out.request == SpeedRequest::kProtectiveStop);
    CHECK(out.distance_mm == 0U);
    SeparationParams bad = p;
    bad.human_speed_mps = -1.0;
    CHECK(compute_separation(cell.g, cell.inputs(), sphere_pose(), bad, 0U, out).error() ==
          ErrorCode::kInvalidArgument);
    RobotPose nan_pose = sphere_pose();
    nan_pose.capsules[0].a[2] = std::numeric_limits<double>::quiet_NaN();
    CHECK(compute_separation(cell.g, cell.inputs(), nan_pose, p, 0U, out).error() == ErrorCode::kInvalidArgument);
    CHECK(out.request == SpeedRequest::kProtectiveStop);
    REQUIRE(compute_separation(cell.g, cell.inputs(), sphere_pose(), p, 0U, out).ok());
    CHECK(out.request == SpeedRequest::kFull);
}

// verifies: SR-SSM-008
TEST_CASE("compute_separation refuses each short input span and each unusable pose with a stop") {
    Cell cell(small_grid());
    const SeparationParams p = demo_params();
    SeparationResult out;
    const auto refused = [&](const SeparationInputs& in, const RobotPose& pose, ErrorCode expected) {
        out.request = SpeedRequest::kFull;
        const Status st = compute_separation(cell.g, in, pose, p, 0U, out);
        return !st.ok() && st.error() == expected && out.request == SpeedRequest::kProtectiveStop &&
               out.distance_mm == 0U;
    };
    SeparationInputs in = cell.inputs();
    in.frame_log_odds = Span<const std::int16_t>(cell.frame.data(), cell.frame.size() - 1U);
    CHECK(refused(in, sphere_pose(), ErrorCode::kStorageTooSmall));
    in = cell.inputs();
    in.observed = Span<const std::uint8_t>(cell.observed.data(), cell.observed.size() - 1U);
    CHECK(refused(in, sphere_pose(), ErrorCode::kStorageTooSmall));
    in = cell.inputs();
    in.robot_mask = Span<const std::uint8_t>(cell.mask.data(), cell.mask.size() - 1U);
    CHECK(refused(in, sphere_pose(), ErrorCode::kStorageTooSmall));
    RobotPose pose = sphere_pose();
    pose.count = 0U;
    CHECK(refused(cell.inputs(), pose, ErrorCode::kInvalidArgument));
    pose.count = kMaxRobotCapsules + 1U;
    CHECK(refused(cell.inputs(), pose, ErrorCode::kInvalidArgument));
    pose = sphere_pose();
    pose.capsules[0].b[1] = std::numeric_limits<double>::infinity();
    CHECK(refused(cell.inputs(), pose, ErrorCode::kInvalidArgument));
    pose = sphere_pose();
    pose.capsules[0].radius = -0.01;
    CHECK(refused(cell.inputs(), pose, ErrorCode::kInvalidArgument));
    pose.capsules[0].radius = std::numeric_limits<double>::quiet_NaN();
    CHECK(refused(cell.inputs(), pose, ErrorCode::kInvalidArgument));
    CHECK(compute_separation(cell.g, cell.inputs(), sphere_pose(), p, 0U, out).ok());
}

// verifies: SR-SSM-009
TEST_CASE("the bounded search gives the brute-force distances for the test arm in random poses and scenes") {
    const RobotModel arm = make_test_arm(0.05, -0.1, 0.0);
    const GridGeometry g = paper_grid_geometry();
    std::mt19937 rng(15066);
    std::uniform_real_distribution<double> q(-3.0, 3.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const std::uint32_t ks[] = {1U, 3U, 17U, 64U};
    for (int trial = 0; trial < 24; ++trial) {
        Cell cell(g);
        const RobotPose pose = test_arm_pose(arm, test_arm_joints(q(rng), q(rng), q(rng), q(rng), q(rng), q(rng)));
        RobotMaskStats stats;
        REQUIRE(mark_robot_voxels(g, pose, 0.08, Span<std::uint8_t>(cell.mask.data(), cell.mask.size()), stats).ok());
        // From a few scattered voxels to nearly everything foreground or unseen.
        const double fg_share = trial % 4 == 3 ? 0.95 : 0.002 * (trial + 1);
        const double unseen_share = trial % 3 == 2 ? 0.9 : 0.01;
        for (std::size_t i = 0; i < g.voxel_count(); ++i) {
            cell.frame[i] = u(rng) < fg_share ? 2000 : 0;
            cell.observed[i] = u(rng) < unseen_share ? 0U : 1U;
            cell.zones[i] = u(rng) < 0.5 ? 1U : 2U;
        }
        cell.active = trial % 2 == 0 ? 1U : 3U;
        SeparationParams p = demo_params();
        p.min_foreground_voxels = ks[trial % 4];
        p.min_hidden_voxels = ks[(trial + 1) % 4];
        SeparationResult r;
        {
            const cellguard::test::AllocationScope scope;
            REQUIRE(compute_separation(g, cell.inputs(), pose, p, 0U, r).ok());
            CHECK(scope.allocations() == 0U);
        }
        INFO("trial " << trial);
        CHECK(r.foreground_mm == reference_mm(cell, pose, false, p.min_foreground_voxels));
        CHECK(r.hidden_mm == reference_mm(cell, pose, true, p.min_hidden_voxels));
        CHECK(r.distance_mm == std::min(r.foreground_mm, r.hidden_mm));
        CHECK(r.candidates <= g.voxel_count());
    }
}

// verifies: SR-SSM-001
TEST_CASE("S_p of a speed class beyond the commissioned ones is a contract violation") {
    SeparationParams p = demo_params();
    REQUIRE(check_separation_params(p).ok());
    const auto last = static_cast<std::uint8_t>(p.class_count - 1U);
    CHECK_FALSE(test::violates_contract([&] { (void)protective_separation_distance(p, last); }));
    CHECK(test::violates_contract([&] { (void)protective_separation_distance(p, p.class_count); }));
    p.class_count = static_cast<std::uint8_t>(kSpeedClasses + 1U);  // unchecked parameters
    CHECK(test::violates_contract([&] { (void)protective_separation_distance(p, kSpeedClasses); }));
}

// verifies: SR-SSM-002, SR-SSM-007
TEST_CASE("an S_p beyond the millimetre range is refused by compute_separation, and its result requests a stop") {
    Cell cell(small_grid());
    SeparationParams p = demo_params();
    p.human_speed_mps = 200.0;  // S_p(0) = 200 x 0.5 m + ... > 65.535 m: capped, it would equal "no voxel"
    cell.foreground(15, 5, 5);
    SeparationResult out;
    out.request = SpeedRequest::kFull;  // what the error must overwrite
    out.required_mm = 7U;
    CHECK(compute_separation(cell.g, cell.inputs(), sphere_pose(), p, 0U, out).error() == ErrorCode::kInvalidArgument);
    CHECK(out.request == SpeedRequest::kProtectiveStop);
    CHECK(out.required_mm == 0U);
}

// verifies: SR-SSM-009
TEST_CASE("a grid of more rows than the row flags cover gives the brute-force distances") {
    // 2 x 100 x 100 voxels: 10000 rows of 2 voxels, more than the 8192 rows whose contents the search flags.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(0.0, 0.0, 0.0), 0.05, {2, 100, 100}).value();
    Cell cell(g);
    RobotPose pose = sphere_pose();
    for (int k = 1; k < 3; ++k)
        pose.capsules[0].a[k] = pose.capsules[0].b[k] = 2.525;  // voxel (., 50, 50)
    cell.foreground(1, 50, 60);
    cell.foreground(0, 90, 10);
    cell.active = 1U;
    cell.unseen(0, 44, 50, 1U);
    SeparationParams p = demo_params();
    for (const std::uint32_t k : {1U, 2U}) {
        p.min_foreground_voxels = k;
        const SeparationResult r = run(cell, pose, p);
        CAPTURE(k);
        CHECK(r.foreground_mm == reference_mm(cell, pose, false, k));
        CHECK(r.hidden_mm == reference_mm(cell, pose, true, 1U));
        CHECK(r.foreground_mm < kDistanceFarMm);
    }
}

// verifies: SR-SSM-009
TEST_CASE("a capsule beyond either x end of the grid: rows near only it are searched nowhere, distances exact") {
    for (const double beyond : {-5.0, 7.0}) {
        Cell cell(small_grid());
        RobotPose pose;
        pose.count = 2U;
        for (int k = 0; k < 3; ++k) {  // a small sphere at voxel (10, 9, 9), one outside the grid on row (0, 0)
            pose.capsules[0].a[k] = pose.capsules[0].b[k] = k == 0 ? 0.525 : 0.475;
            pose.capsules[1].a[k] = pose.capsules[1].b[k] = k == 0 ? beyond : 0.025;
        }
        pose.capsules[0].radius = 0.02;
        pose.capsules[1].radius = 0.02;
        cell.foreground(12, 9, 9);  // near the first sphere: found before the rows near the second one
        cell.foreground(20, 0, 0);  // on the second sphere's row, but far from both
        SeparationParams p = demo_params();
        CAPTURE(beyond);
        for (const std::uint32_t k : {1U, 2U}) {
            p.min_foreground_voxels = k;
            CAPTURE(k);
            CHECK(run(cell, pose, p).foreground_mm == reference_mm(cell, pose, false, k));
        }
        p.min_foreground_voxels = 1U;
        CHECK(run(cell, pose, p).foreground_mm == 36U);  // 0.1 - 0.02 - 0.0433 m
    }
}

// verifies: SR-SSM-003
TEST_CASE("a voxel centre on a capsule's axis, where rounding makes the squared distance negative, is at distance 0") {
    // The segment from voxel (0, 0, 0)'s centre to voxel (0, 0, 6)'s passes through voxel (0, 0, 1)'s centre; in
    // binary64 its squared distance to the axis comes out as -4.3e-19, not 0.
    Cell cell(small_grid());
    RobotPose pose;
    pose.count = 1U;
    for (int k = 0; k < 3; ++k)
        pose.capsules[0].a[k] = pose.capsules[0].b[k] = 0.025;
    pose.capsules[0].b[2] = 0.325;
    pose.capsules[0].radius = 0.01;
    cell.foreground(0, 0, 1);
    const SeparationResult r = run(cell, pose, demo_params());
    CHECK(r.foreground_mm == 0U);
    CHECK(r.candidates == 1U);
    CHECK(r.request == SpeedRequest::kProtectiveStop);
}

// verifies: SR-SSM-004
TEST_CASE(
    "once a kind has its k voxels at distance 0 its further voxels are not measured, the other kind's still are") {
    Cell cell(small_grid());
    const SeparationParams p = demo_params();  // k = 1 for both kinds
    cell.active = 1U;
    cell.foreground(6, 5, 5);  // touches the sphere: the foreground distance is 0 at once
    cell.foreground(5, 5, 8);  // a row visited later: foreground only, not a candidate any more
    cell.unseen(5, 5, 2, 1U);  // the unseen voxel still sets the hidden distance: 0.15 - 0.1 - 0.0433 m
    const SeparationResult r = run(cell, sphere_pose(), p);
    CHECK(r.foreground_mm == 0U);
    CHECK(r.hidden_mm == reference_mm(cell, sphere_pose(), true, 1U));
    CHECK(r.hidden_mm == 6U);
    CHECK(r.candidates == 2U);
    CHECK(r.request == SpeedRequest::kProtectiveStop);
}

// verifies: SR-SSM-003
TEST_CASE("a foreground voxel 65.535 m or more from the robot reads kDistanceFarMm, one nearer its distance in mm") {
    Cell cell(small_grid());
    cell.foreground(0, 0, 0);  // centre (0.025, 0.025, 0.025)
    RobotPose pose;
    pose.count = 1U;
    pose.capsules[0].radius = 0.1;
    const SeparationParams p = demo_params();
    for (const double x : {100.0, -100.0, 60.0}) {
        CAPTURE(x);
        for (int k = 0; k < 3; ++k)
            pose.capsules[0].a[k] = pose.capsules[0].b[k] = k == 0 ? x : 0.025;
        const SeparationResult r = run(cell, pose, p);
        CHECK(r.candidates == 1U);
        CHECK(r.foreground_mm == reference_mm(cell, pose, false, 1U));
        if (std::abs(x) >= 100.0) {
            CHECK(r.foreground_mm == kDistanceFarMm);  // saturated, not wrapped to a near distance
        } else {
            CHECK(r.foreground_mm < kDistanceFarMm);
        }
        CHECK(r.request == SpeedRequest::kFull);
    }
}
