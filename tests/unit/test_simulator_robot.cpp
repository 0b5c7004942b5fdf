// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: SR-SIM-001, SR-SIM-002, SR-SIM-003, SR-SIM-004, SR-SIM-005, SR-SIM-006, SR-SIM-007
// The simulated robot cell (apps/host/src/sim: workcell, trajectory,
// robot_cell, scene_file): the robot's capsules in depth images and in the
// ground truth, joint trajectories and the PLC's schedule from scene files
// with every refusal, the person's path, the robot-cell scene's speed
// request timeline, the arm alone after fusion, and no allocation per cycle.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "cellguard/host/sim/ground_truth.hpp"
#include "cellguard/host/sim/robot_cell.hpp"
#include "cellguard/host/sim/scene_file.hpp"
#include "cellguard/host/sim/trajectory.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "test_robot.hpp"
#include "test_tags.hpp"

using namespace cellguard;

namespace {

constexpr double kPi = 3.14159265358979323846;

PlacedCapsule capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) {
    PlacedCapsule c;
    for (int i = 0; i < 3; ++i) {
        c.a[i] = a[i];
        c.b[i] = b[i];
    }
    c.radius = r;
    return c;
}

Eigen::Vector3d end_a(const PlacedCapsule& c) { return {c.a[0], c.a[1], c.a[2]}; }
Eigen::Vector3d end_b(const PlacedCapsule& c) { return {c.b[0], c.b[1], c.b[2]}; }

/// Distance between segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection, 5.1.9).
double segment_distance(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1, const Eigen::Vector3d& p2,
                        const Eigen::Vector3d& q2) {
    const Eigen::Vector3d d1 = q1 - p1;
    const Eigen::Vector3d d2 = q2 - p2;
    const Eigen::Vector3d r = p1 - p2;
    const double a = d1.squaredNorm();
    const double e = d2.squaredNorm();
    const double f = d2.dot(r);
    double s = 0.0;
    double t = 0.0;
    if (a <= 1e-18 && e <= 1e-18) {
        return r.norm();
    }
    if (a <= 1e-18) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = d1.dot(r);
        if (e <= 1e-18) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = d1.dot(d2);
            const double denom = a * e - b * b;
            s = denom > 1e-18 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) {
                t = 0.0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1.0) {
                t = 1.0;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return ((p1 + s * d1) - (p2 + t * d2)).norm();
}

/// Distance from @p p to the surface of capsule @p c (negative inside).
double capsule_surface_distance(const PlacedCapsule& c, const Eigen::Vector3d& p) {
    return segment_distance(p, p, end_a(c), end_b(c)) - c.radius;
}

/// The robot-cell scene file.
sim::SceneFile robot_cell_file() {
    const sim::SceneLoad load = sim::load_scene_file(std::string(CELLGUARD_SOURCE_DIR) +
                                                     "/apps/evaluation/scenes/robot-cell.toml");
    REQUIRE_MESSAGE(load.ok, load.error);
    return load.scene;
}

/// The proposed grid of the robot cell: x -2..3, y -2..2, z 0..1.8 m in 10 cm voxels.
GridGeometry robot_cell_grid() { return GridGeometry::make({-2.0, -2.0, 0.0}, 0.1, GridDims{50, 40, 18}).value(); }

/// A scene file text with a [robot] of @p keyframes (TOML) and @p commands.
std::string robot_text(const std::string& keyframes, const std::string& commands = "") {
    return "name = \"t\"\n[robot]\nposition = [0.0, 0.0, 0.0]\n" + keyframes + commands;
}

/// The error of parsing @p text as "bad.toml" ("" when it loads).
std::string parse_error(const std::string& text) {
    const sim::SceneLoad load = sim::parse_scene(text, "bad.toml");
    return load.ok ? std::string() : load.error;
}

}  // namespace

// verifies: SR-SIM-001
TEST_CASE("simulator robot: capsules appear in a depth image exactly where their surface is") {
    // An ideal sensor in the paper's corner; odd image size: the centre pixel lies on the optical axis.
    const sim::SensorSpec sensor{"ideal", {-1.9, -1.9, 1.9}, {0.0, 0.0, 0.75}, 81, 61, 60.0, 45.0, 10.0F};
    sim::Scene scene;
    scene.robot.count = 3U;
    scene.robot.capsules[0] = capsule({0.0, 0.0, 0.75}, {0.0, 0.0, 0.75}, 0.1);  // a sphere on the optical axis
    scene.robot.capsules[1] = capsule({0.5, -0.3, 0.2}, {0.8, 0.2, 0.9}, 0.08);  // a slanted capsule
    scene.robot.capsules[2] = capsule({-0.6, 0.5, 0.1}, {-0.1, 0.6, 0.1}, 0.1);  // one lying on the floor
    std::vector<float> with;
    std::vector<float> without;
    sim::render_depth(sensor, scene, with);
    sim::render_depth(sensor, sim::Scene{}, without);

    // On the axis the sphere's near surface: depth = distance to its centre - radius.
    const double axis = (Eigen::Vector3d(0.0, 0.0, 0.75) - sensor.position).norm();
    CHECK(static_cast<double>(with[30U * 81U + 40U]) == doctest::Approx(axis - 0.1).epsilon(1e-6));

    const PinholeIntrinsics k = sensor.intrinsics();
    const Eigen::Isometry3d pose = sensor.pose();
    int on_robot = 0;
    for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u < k.width; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * 81U + static_cast<std::size_t>(u);
            const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
            const Eigen::Vector3d dir = pose.linear() * ray_cam;
            const Eigen::Vector3d end = pose.translation() + static_cast<double>(with[i]) * dir;
            double nearest = std::numeric_limits<double>::infinity();
            for (std::size_t c = 0U; c < 3U; ++c) {
                nearest = std::fmin(nearest, capsule_surface_distance(scene.robot.capsules[c], end));
            }
            if (with[i] != without[i]) {
                ++on_robot;
                CHECK(with[i] < without[i]);       // the robot stands in front of the floor
                CHECK(std::fabs(nearest) < 1e-5);  // the reading lies on a capsule's surface
            } else {                               // the ray reaches the floor past every capsule
                const Eigen::Vector3d o = pose.translation();
                for (std::size_t c = 0U; c < 3U; ++c) {
                    const PlacedCapsule& cap = scene.robot.capsules[c];
                    CHECK(segment_distance(o, end, end_a(cap), end_b(cap)) >= cap.radius - 1e-6);
                }
            }
        }
    }
    CHECK(on_robot > 60);
}

// verifies: SR-SIM-001
TEST_CASE("simulator robot: the ground truth labels the robot's voxels robot, never foreground") {
    const GridGeometry g = GridGeometry::make({-1.0, -1.0, 0.0}, 0.1, GridDims{20, 20, 15}).value();
    sim::Scene scene;
    scene.robot.count = 1U;
    scene.robot.capsules[0] = capsule({0.0, 0.0, 0.1}, {0.3, 0.2, 1.0}, 0.1);
    const sim::GroundTruth t = sim::ideal_ground_truth(g, sim::paper_sensors(), scene);
    CHECK(t.foreground == 0U);
    CHECK(t.unknown == 0U);
    CHECK(t.robot > 20U);
    // The capsule's axis is inside it, never seen: robot.
    const Result<VoxelCoord> mid = g.world_to_voxel({0.15, 0.1, 0.55});
    REQUIRE(mid.ok());
    CHECK(t.label[g.index_of(mid.value())] == sim::Truth::kRobot);
    // Every robot voxel touches the capsule or holds a reading on it.
    for (std::size_t i = 0U; i < g.voxel_count(); ++i) {
        if (t.label[i] == sim::Truth::kRobot) {
            const VoxelCoord c = g.coord_of(i);
            const Eigen::Vector3d centre = g.origin() +
                                           g.voxel_size() * Eigen::Vector3d(c.x + 0.5, c.y + 0.5, c.z + 0.5);
            CHECK(capsule_surface_distance(scene.robot.capsules[0], centre) <= 0.5 * std::sqrt(3.0) * 0.1 + 1e-9);
        }
    }
    // A person beside the robot stays foreground.
    scene.boxes.push_back(sim::Box{{-0.6, -0.6, 0.5}, {0.3, 0.3, 1.0}, 0.0, false});
    const sim::GroundTruth with_person = sim::ideal_ground_truth(g, sim::paper_sensors(), scene);
    CHECK(with_person.foreground > 10U);
    CHECK(with_person.robot > 20U);
}

// verifies: SR-SIM-001
TEST_CASE(
    "simulator robot: capsule rays from inside, along the axis and past the ends, prepared = plain, bit for bit") {
    const PlacedCapsule c = capsule({0.0, 0.0, 0.2}, {0.0, 0.0, 0.9}, 0.1);
    CHECK(sim::intersect_capsule(c, {0.0, 0.0, 2.0}, {0.0, 0.0, -1.0}) == doctest::Approx(1.0));  // top sphere
    CHECK(sim::intersect_capsule(c, {1.0, 0.0, 0.5}, {-1.0, 0.0, 0.0}) == doctest::Approx(0.9));  // the side
    CHECK(sim::intersect_capsule(c, {0.0, 0.0, 0.5}, {1.0, 0.0, 0.0}) == 0.0);                    // from inside
    CHECK(std::isinf(sim::intersect_capsule(c, {1.0, 0.0, 0.5}, {1.0, 0.0, 0.0})));               // behind
    CHECK(std::isinf(sim::intersect_capsule(c, {1.0, 0.0, 1.05}, {-1.0, 0.0, 0.0})));             // above the cap
    CHECK(sim::capsule_contains(c, {0.0, 0.05, 0.95}));
    CHECK_FALSE(sim::capsule_contains(c, {0.0, 0.09, 1.0}));

    sim::Scene scene = sim::reference_scene();
    scene.robot.count = 2U;
    scene.robot.capsules[0] = c;
    scene.robot.capsules[1] = capsule({0.4, 0.4, 0.5}, {0.4, 0.4, 0.5}, 0.2);
    const sim::PreparedScene prepared(scene);
    const sim::SensorSpec s = sim::paper_sensors()[2];
    const Eigen::Isometry3d pose = s.pose();
    const PinholeIntrinsics k = s.intrinsics();
    int hits = 0;
    for (int v = 0; v < k.height; v += 3) {
        for (int u = 0; u < k.width; u += 3) {
            const Eigen::Vector3d dir =
                (pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0)).normalized();
            const sim::RayHit a = prepared.cast(pose.translation(), dir);
            const sim::RayHit b = sim::cast_ray_hit(scene, pose.translation(), dir);
            CHECK(a.distance == b.distance);
            CHECK(a.box == b.box);
            CHECK(a.capsule == b.capsule);
            CHECK(sim::cast_ray(scene, pose.translation(), dir) == a.distance);
            hits += a.capsule >= 0 ? 1 : 0;
        }
    }
    CHECK(hits > 50);
    // assign and set_robot replace the robot without allocating.
    sim::PreparedScene live(scene.boxes.size());
    const test::AllocationScope scope;
    const bool assigned = live.assign(scene);
    const bool cleared = live.set_robot(RobotPose{});
    const std::size_t allocations = scope.allocations();
    CHECK(assigned);
    CHECK(cleared);
    CHECK(live.scene().robot.count == 0U);
    CHECK(allocations == 0U);
}

// verifies: SR-SIM-002
TEST_CASE("simulator robot: a joint trajectory interpolates linearly between keyframes and holds at both ends") {
    sim::JointTrajectory tr;
    sim::Keyframe k0;
    k0.t = 1.0;
    k0.q = test::test_arm_joints(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    sim::Keyframe k1;
    k1.t = 3.0;
    k1.q = test::test_arm_joints(1.0, -0.5, 0.2, 0.0, 0.0, 2.0);
    sim::Keyframe k2;
    k2.t = 4.0;
    k2.q = test::test_arm_joints(1.0, 0.5, 0.2, 0.0, 0.0, 2.0);
    tr.keyframes = {k0, k1, k2};
    CHECK(sim::check_trajectory_values(tr).empty());
    CHECK(sim::check_trajectory(tr, test::make_test_arm()).empty());
    CHECK(sim::trajectory_duration(tr) == 4.0);
    const JointPositions before = sim::sample_trajectory(tr, 0.0);
    CHECK(before.count == 6U);
    CHECK(before.q[0] == 0.0);
    CHECK(sim::sample_trajectory(tr, std::nan("")).q[0] == 0.0);
    const JointPositions mid = sim::sample_trajectory(tr, 2.0);
    CHECK(mid.q[0] == doctest::Approx(0.5));
    CHECK(mid.q[1] == doctest::Approx(-0.25));
    CHECK(mid.q[5] == doctest::Approx(1.0));
    const JointPositions at = sim::sample_trajectory(tr, 3.0);
    for (std::size_t j = 0U; j < 6U; ++j) {
        CHECK(at.q[j] == k1.q.q[j]);  // exactly the keyframe
    }
    CHECK(sim::sample_trajectory(tr, 3.5).q[1] == doctest::Approx(0.0));
    CHECK(sim::sample_trajectory(tr, 100.0).q[1] == 0.5);
    CHECK(sim::sample_trajectory(sim::JointTrajectory{}, 1.0).count == 0U);

    // The clock: full rate, the reduced rate, standing still.
    sim::TrajectoryClock clock(0.25);
    CHECK(clock.advance(1.0, SpeedRequest::kFull) == 1.0);
    CHECK(clock.advance(1.0, SpeedRequest::kReduced) == 1.25);
    CHECK(clock.advance(1.0, SpeedRequest::kProtectiveStop) == 1.25);
    CHECK(clock.advance(-1.0, SpeedRequest::kFull) == 1.25);
}

// verifies: SR-SIM-003
TEST_CASE("simulator robot: trajectories and schedules load from scene files") {
    const std::string text = robot_text(
        "yaw_deg = 90.0\nmodel = \"arm.urdf\"\n"
        "[[robot.keyframe]]\nt = 0.0\njoints = [0.0, 0.5, 1.0, 0.0, 0.0, 0.0]\n"
        "[[robot.keyframe]]\nt = 2.0\njoints = [1.0, 0.5, 1.0, 0.0, 0.0, 0.0]\n",
        "[[command]]\nt = 0.0\ncase = 1\n[[command]]\nt = 1.5\ncase = 3\nspeed_class = 2\n");
    const sim::SceneLoad load = sim::parse_scene(text, "robot.toml", "/cell");
    REQUIRE_MESSAGE(load.ok, load.error);
    const sim::SceneFile& f = load.scene;
    CHECK(f.robot.present);
    CHECK(f.robot.model == "/cell/arm.urdf");
    CHECK(f.robot.yaw == doctest::Approx(kPi / 2.0));
    REQUIRE(f.robot.trajectory.keyframes.size() == 2U);
    CHECK(f.robot.trajectory.keyframes[1].place.line == 9);
    CHECK(sim::sample_trajectory(f.robot.trajectory, 1.0).q[0] == doctest::Approx(0.5));
    REQUIRE(f.commands.steps.size() == 2U);
    CHECK(sim::command_at(f.commands, 1.4).monitoring_case == 1U);
    CHECK(sim::command_at(f.commands, 1.5).monitoring_case == 3U);
    CHECK(sim::command_at(f.commands, 1.5).speed_class == 2U);
    CHECK(sim::command_at(sim::CommandSchedule{}, 1.5).monitoring_case == 0U);

    RobotModel arm = test::make_test_arm();
    sim::place_robot_base(f.robot, arm);
    CHECK(arm.base_wxyz[0] == doctest::Approx(std::sqrt(0.5)));
    CHECK(arm.base_wxyz[3] == doctest::Approx(std::sqrt(0.5)));
    CHECK(check_robot_model(arm).code == ErrorCode::kOk);

    // The PLC's command: raw joints in the wire's units, the robot id, back through the controller's check.
    const JointPositions q = sim::sample_trajectory(f.robot.trajectory, 1.0);
    const RobotCommand cmd = sim::simulated_command(arm, 0xABCD1234U, q, sim::command_at(f.commands, 1.0));
    CHECK(cmd.robot_id == 0x1234U);
    CHECK(cmd.joint_count == 6U);
    CHECK(cmd.joint_raw[0] == 2500);  // 0.5 rad / 0.2 mrad
    const Result<JointPositions, JointCheck> back = joint_positions(arm, 0xABCD1234U, cmd);
    REQUIRE(back.ok());
    for (std::size_t j = 0U; j < 6U; ++j) {
        CHECK(std::fabs(back.value().q[j] - q.q[j]) <= 0.5 * kRevoluteJointUnitRad + 1e-12);
    }
    CHECK(sim::joint_raw(JointType::kRevolute, 100.0) == 32767);
    CHECK(sim::joint_raw(JointType::kRevolute, -100.0) == -32767);
    CHECK(sim::joint_raw(JointType::kPrismatic, 0.01) == 100);
}

// verifies: SR-SIM-004
TEST_CASE("simulator robot: every bad trajectory or schedule value is refused with the keyframe's place") {
    const std::string k0 = "[[robot.keyframe]]\nt = 0.0\njoints = [0.0, 0.5, 1.0, 0.0, 0.0, 0.0]\n";
    struct Case {
        std::string text;
        std::string expected;  ///< a part of the error
    };
    const Case cases[] = {
        {robot_text(k0 + "[[robot.keyframe]]\nt = 1.0\njoints = [0.0, nan, 1.0, 0.0, 0.0, 0.0]\n"),
         "bad.toml:9:16: robot.keyframe[1].joints[1]: expected a finite number"},
        {robot_text(k0 + "[[robot.keyframe]]\nt = inf\njoints = [0.0, 0.5, 1.0, 0.0, 0.0, 0.0]\n"),
         "bad.toml:8:5: robot.keyframe[1].t: expected a finite number"},
        {robot_text(k0 + "[[robot.keyframe]]\nt = 0.0\njoints = [0.0, 0.5, 1.0, 0.0, 0.0, 0.0]\n"),
         "bad.toml:7:1: robot.keyframe[1].t: times must increase: 0 s is not later than keyframe 0's 0 s"},
        {robot_text("[[robot.keyframe]]\nt = 2.0\njoints = [0.0]\n[[robot.keyframe]]\nt = 1.0\njoints = [0.0]\n"),
         "bad.toml:7:1: robot.keyframe[1].t: times must increase"},
        {robot_text("[[robot.keyframe]]\nt = -1.0\njoints = [0.0]\n"),
         "robot.keyframe[0].t: expected a finite time >= 0"},
        {robot_text(k0 + "[[robot.keyframe]]\nt = 1.0\njoints = [0.0, 0.5, 1.0]\n"),
         "bad.toml:7:1: robot.keyframe[1].joints: 3 joint positions, keyframe 0 has 6"},
        {robot_text("[[robot.keyframe]]\nt = 0.0\njoints = [0, 0, 0, 0, 0, 0, 0, 0]\n"),
         "robot.keyframe[0].joints: expected an array of 1 to 7 joint positions"},
        {robot_text("[[robot.keyframe]]\nt = 0.0\njoints = []\n"),
         "robot.keyframe[0].joints: expected an array of 1 to 7"},
        {robot_text("[[robot.keyframe]]\nt = 0.0\njoints = [\"a\"]\n"),
         "robot.keyframe[0].joints[0]: expected a number"},
        {robot_text("[[robot.keyframe]]\nt = 0.0\n"), "robot.keyframe[0].joints"},
        {robot_text("[[robot.keyframe]]\njoints = [0.0]\n"), "robot.keyframe[0].t"},
        {robot_text("[[robot.keyframe]]\nt = 0.0\njoints = [0.0]\nspeed = 1\n"), "robot.keyframe[0].speed"},
        {robot_text(""), "robot.keyframe"},
        {"[robot]\n[[robot.keyframe]]\nt = 0.0\njoints = [0.0]\n", "robot.position"},
        {robot_text(k0, "[[command]]\nt = 0.5\ncase = 0\n"), "command[0].t: the first command must be at t = 0 s"},
        {robot_text(k0, "[[command]]\nt = 0.0\ncase = 0\n[[command]]\nt = 0.0\ncase = 1\n"),
         "command[1].t: times must be finite and increase"},
        {robot_text(k0, "[[command]]\nt = 0.0\ncase = 16\n"),
         "bad.toml:9:8: command[0].case: expected an integer in 0..15, got 16"},
        {robot_text(k0, "[[command]]\nt = 0.0\ncase = 0\nspeed_class = 4\n"), "command[0].speed_class"},
        {robot_text(k0, "[[command]]\nt = 0.0\n"), "command[0].case"},
    };
    for (const Case& c : cases) {
        const std::string error = parse_error(c.text);
        INFO(c.text);
        CHECK_MESSAGE(error.find(c.expected) != std::string::npos, error);
    }

    // Against the robot: joint count, limits, speed; and the schedule against the cell's cases.
    const RobotModel arm = test::make_test_arm();
    const auto model_error = [&](const std::string& keyframes) {
        const sim::SceneLoad load = sim::parse_scene(robot_text(keyframes), "bad.toml");
        REQUIRE_MESSAGE(load.ok, load.error);
        return sim::check_trajectory(load.scene.robot.trajectory, arm);
    };
    CHECK(model_error(k0).empty());
    CHECK(model_error("[[robot.keyframe]]\nt = 0.0\njoints = [0.0, 0.5, 1.0, 0.0, 0.0]\n") ==
          "bad.toml:4:1: robot.keyframe[0].joints: 5 joint positions, but the robot 'cellguard_test_arm' has 6 "
          "movable joints");
    const std::string limit = model_error(k0 +
                                          "[[robot.keyframe]]\nt = 4.0\njoints = [0.0, 0.5, 3.2, 0.0, 0.0, 0.0]\n");
    CHECK_MESSAGE(
        limit.find("bad.toml:7:1: robot.keyframe[1].joints[2]: 3.2 rad lies outside the joint's limits") == 0U, limit);
    const std::string fast = model_error(k0 + "[[robot.keyframe]]\nt = 0.1\njoints = [1.0, 0.5, 1.0, 0.0, 0.0, 0.0]\n");
    CHECK_MESSAGE(fast.find("robot.keyframe[1].joints[0]: moving from keyframe 0 takes 10 rad/s, faster than the "
                            "joint's max_velocity 2.094") != std::string::npos,
                  fast);
    sim::CommandSchedule schedule;
    schedule.steps.push_back(sim::CommandStep{0.0, 2U, 0U, {"cell.toml", 3, 1}});
    CHECK(sim::check_schedule(schedule).empty());
    CHECK(sim::check_schedule(schedule, 3U).empty());
    CHECK(sim::check_schedule(schedule, 2U) ==
          "cell.toml:3:1: command[0].case: case 2 is not one of the cell's 2 cases (0..1)");
    // A trajectory made in code names the keyframe without a place.
    sim::JointTrajectory tr;
    tr.keyframes.resize(1U);
    tr.keyframes[0].q = test::test_arm_joints(0.0, 0.0, std::nan(""), 0.0, 0.0, 0.0);
    CHECK(sim::check_trajectory(tr, arm) ==
          "robot.keyframe[0].joints[2]: expected a finite joint position (NaN or infinite given)");
    CHECK(sim::check_trajectory(sim::JointTrajectory{}, arm) ==
          "robot.keyframe: the trajectory needs at least one keyframe");

    // The simulation refuses a scene without a robot, a broken model, a trajectory or a schedule that do not fit.
    sim::RobotCellSimulation cell;
    cell.update(1.0);  // never made: no robot
    CHECK(cell.pose().count == 0U);
    const sim::SceneFile file = robot_cell_file();
    CHECK(sim::RobotCellSimulation::make(sim::SceneFile{}, arm, 3U, cell) == "the scene '' has no [robot]");
    RobotModel broken = arm;
    broken.links[3].upper = -10.0;  // upper < lower
    CHECK(sim::RobotCellSimulation::make(file, broken, 3U, cell).find("robot model: ") == 0U);
    RobotModel stiff = arm;
    stiff.links[1].max_velocity = 1.0;  // the pan's 1.26 rad/s carry is too fast for it
    CHECK(sim::RobotCellSimulation::make(file, stiff, 3U, cell)
              .find("robot.keyframe[4].joints[0]: moving from "
                    "keyframe 3 takes 1.25664 rad/s") != std::string::npos);
    CHECK(sim::RobotCellSimulation::make(file, arm, 2U, cell)
              .find("command[1].case: case 2 is not one of the "
                    "cell's 2 cases") != std::string::npos);
    CHECK(sim::RobotCellSimulation::make(file, arm, 3U, cell).empty());
}

// verifies: SR-SIM-005
TEST_CASE("simulator robot: a person waits, walks at the set speed, stands at a waypoint and walks on") {
    sim::PersonSpec p;
    p.speed_mps = 1.2;
    p.start_s = 5.0;
    p.path = {{3.6, 0.0}, {1.2, 0.0}, {1.2, 0.4}, {3.6, 0.4}};
    p.dwell_s = {0.0, 3.0, 0.0, 0.0};
    CHECK(sim::person_position(p, 0.0).x() == 3.6);
    CHECK(sim::person_position(p, 5.0).x() == 3.6);
    CHECK(sim::person_position(p, 6.0).x() == doctest::Approx(2.4));  // 1.2 m in 1 s
    CHECK(sim::person_position(p, 7.0).x() == doctest::Approx(1.2));  // arrives
    CHECK(sim::person_position(p, 9.9).x() == doctest::Approx(1.2));  // stands 3 s
    CHECK(sim::person_position(p, 9.9).y() == doctest::Approx(0.0));
    CHECK(sim::person_position(p, 10.0 + 0.2 / 1.2).y() == doctest::Approx(0.2));
    CHECK(sim::person_position(p, 10.0 + 0.4 / 1.2 + 1.0).x() == doctest::Approx(2.4));
    CHECK(sim::person_position(p, 100.0).x() == doctest::Approx(3.6));  // stays at the end
    CHECK(sim::person_arc_length(p, 8.0) == doctest::Approx(2.4));      // no steps while standing

    // person_boxes_into gives person_boxes' boxes, bit for bit, without allocating.
    for (const double t : {0.0, 5.5, 6.3, 8.0, 10.1, 11.0, 40.0}) {
        const std::vector<sim::Box> boxes = sim::person_boxes(p, t);
        sim::PersonBoxes into;
        const test::AllocationScope scope;
        sim::person_boxes_into(p, t, into);
        const std::size_t allocations = scope.allocations();
        CHECK(allocations == 0U);
        REQUIRE(boxes.size() == into.size());
        for (std::size_t i = 0U; i < boxes.size(); ++i) {
            CHECK(boxes[i].center == into[i].center);
            CHECK(boxes[i].size == into[i].size);
            CHECK(boxes[i].yaw == into[i].yaw);
        }
    }

    // The scene file's form: [x, y, dwell] waypoints and start_s; a bad dwell is refused.
    const sim::SceneLoad load = sim::parse_scene(
        "[[person]]\nspeed_mps = 1.2\nstart_s = 5.0\npath = [[3.6, 0.0], [1.2, 0.0, 3.0], [1.2, 0.4]]\n", "p.toml");
    REQUIRE_MESSAGE(load.ok, load.error);
    REQUIRE(load.scene.people.size() == 1U);
    CHECK(load.scene.people[0].dwell_s == std::vector<double>{0.0, 3.0, 0.0});
    CHECK(load.scene.people[0].start_s == 5.0);
    CHECK(parse_error("[[person]]\npath = [[0.0, 0.0, -1.0]]\n").find("person[0].path: a waypoint's dwell time") !=
          std::string::npos);
    CHECK(parse_error("[[person]]\nspeed_mps = 0.0\npath = [[0.0, 0.0, 1.0]]\n").find("person[0].speed_mps") !=
          std::string::npos);
}

namespace {

/// The separation parameters proposed for the robot-cell demo (robot-cell.toml's comment).
struct DemoSeparation {
    double v_h = 1.6;
    double t_r = 0.3;
    double v_r[2] = {0.5, 0.25};
    double t_s[2] = {0.2, 0.1};
    double s_s[2] = {0.05, 0.0125};
    double t_slowdown = 0.2;
    double c = 0.85;
    double z_d = 0.05;
    double z_r = 0.02;
    [[nodiscard]] double s_p(int k) const { return v_h * (t_r + t_s[k]) + v_r[k] * t_r + s_s[k] + c + z_d + z_r; }
    [[nodiscard]] double reduced_below() const { return s_p(0) + (v_h + v_r[0]) * t_slowdown; }
    /// The request for distance @p d with the robot in class @p k.
    [[nodiscard]] SpeedRequest request(double d, int k) const {
        if (d < s_p(k)) {
            return SpeedRequest::kProtectiveStop;
        }
        return d < reduced_below() ? SpeedRequest::kReduced : SpeedRequest::kFull;
    }
};

/// The robot-cell simulation with the test arm (6 commissioned cases would do; the scene uses 3).
sim::RobotCellSimulation robot_cell(const sim::SceneFile& file) {
    sim::RobotCellSimulation cell;
    const std::string error = sim::RobotCellSimulation::make(file, test::make_test_arm(), 3U, cell);
    REQUIRE_MESSAGE(error.empty(), error);
    return cell;
}

}  // namespace

// verifies: SR-SIM-006
TEST_CASE("simulator robot: the robot-cell scene's arm serves both stations clear of them, and the case follows it") {
    const sim::SceneFile file = robot_cell_file();
    CHECK(file.name == "robot-cell");
    CHECK(file.sensors.size() == 4U);
    CHECK(file.robot.model.find("apps/evaluation/scenes/../../monitor/config/robot-arm.urdf") != std::string::npos);
    sim::RobotCellSimulation cell = robot_cell(file);
    const GridGeometry g = robot_cell_grid();
    std::vector<int> cases;
    double clearance = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 120; ++k) {
        const double t = 0.1 * k;
        cell.update(t);
        if (cases.empty() || cases.back() != cell.scheduled().monitoring_case) {
            cases.push_back(cell.scheduled().monitoring_case);
        }
        const RobotPose& pose = cell.pose();
        for (std::size_t c = 0U; c < pose.count; ++c) {
            const PlacedCapsule& cap = pose.capsules[c];
            for (std::size_t b = 0U; b < 2U; ++b) {  // the two stations
                clearance = std::fmin(clearance, sim::box_capsule_distance(file.scene.boxes[b], cap));
            }
            if (c > 0U) {  // all but the base column stay above the floor and inside the grid
                CHECK(std::fmin(cap.a[2], cap.b[2]) - cap.radius > 0.0);
            }
            for (const double* end : {cap.a, cap.b}) {
                CHECK(g.world_to_voxel({end[0], end[1], end[2]}).ok());
            }
        }
    }
    CHECK(cases == std::vector<int>{0, 2, 1, 2, 0});
    CHECK(clearance > 0.02);  // the tool stops above the tables
    MESSAGE("closest approach of the arm to a station table: " << clearance << " m");
}

// verifies: SR-SIM-005, SR-SIM-006
TEST_CASE("simulator robot: the person makes the expected request FULL, REDUCED, STOP, then back as it leaves") {
    const sim::SceneFile file = robot_cell_file();
    sim::RobotCellSimulation cell = robot_cell(file);
    const DemoSeparation sep;
    CHECK(sep.s_p(0) == doctest::Approx(1.92));
    CHECK(sep.s_p(1) == doctest::Approx(1.6475));
    CHECK(sep.reduced_below() == doctest::Approx(2.34));
    sim::TrajectoryClock clock(0.25);
    SpeedRequest last = SpeedRequest::kFull;
    std::vector<SpeedRequest> phases;
    std::vector<double> starts;
    const double grid_x_max = 3.0;
    for (int k = 0; k < 180; ++k) {
        const double t = 0.1 * k;
        cell.update(t, clock.time());
        // The PLC drops to the reduced class (1) while REDUCED or STOP is requested.
        const int speed_class = last == SpeedRequest::kFull ? cell.scheduled().speed_class : 1;
        const bool seen = sim::person_position(file.people[0], t).x() - 0.2 < grid_x_max;
        const double d = seen ? sim::person_robot_distance(cell.scene().scene()) : 1e9;
        last = sep.request(d, speed_class);
        if (phases.empty() || phases.back() != last) {
            phases.push_back(last);
            starts.push_back(t);
            MESSAGE("t = " << t << " s: " << std::string(to_string(last)) << " (distance " << d
                           << " m, trajectory time " << clock.time() << " s)");
        }
        clock.advance(0.1, last);
    }
    REQUIRE(phases.size() == 5U);
    CHECK(phases == std::vector<SpeedRequest>{SpeedRequest::kFull, SpeedRequest::kReduced,
                                              SpeedRequest::kProtectiveStop, SpeedRequest::kReduced,
                                              SpeedRequest::kFull});
    CHECK(starts[1] > 5.4);               // REDUCED only once the person is inside the grid
    CHECK(starts[2] - starts[1] >= 0.2);  // at least two cycles of REDUCED before the stop
    CHECK(clock.time() >= 12.0);          // the arm finishes its program after the person has left
}

// verifies: SR-SIM-007
TEST_CASE("simulator robot: a cycle of the robot cell (scene, four renders, the PLC's command) allocates nothing") {
    const sim::SceneFile file = robot_cell_file();
    sim::RobotCellSimulation cell = robot_cell(file);
    std::vector<std::vector<float>> images;
    std::vector<Span<float>> depth;
    images.reserve(file.sensors.size());
    depth.reserve(file.sensors.size());
    for (const sim::SensorSpec& s : file.sensors) {
        images.emplace_back(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height));
    }
    for (std::vector<float>& image : images) {
        depth.emplace_back(image.data(), image.size());
    }
    std::vector<SensorReading> readings(file.sensors.size());
    sim::TrajectoryClock clock(0.25);
    std::vector<std::size_t> allocations;
    allocations.reserve(12U);
    std::size_t capsules_placed = 0U;
    for (int k = 0; k < 12; ++k) {
        const double t = 5.0 + 0.25 * k;  // the person walks in, the arm works at B
        const test::AllocationScope scope;
        cell.update(t, clock.time());
        const bool rendered = sim::render_frame_into(file.sensors, cell.scene(), {depth.data(), depth.size()},
                                                     {readings.data(), readings.size()});
        const RobotCommand command = cell.command(0x1234U);
        clock.advance(0.25, SpeedRequest::kFull);
        allocations.push_back(scope.allocations());
        CHECK(rendered);
        CHECK(command.joint_count == 6U);
        capsules_placed += cell.pose().count;
    }
    CHECK(allocations == std::vector<std::size_t>(12U, 0U));
    CHECK(capsules_placed == 12U * 7U);
}

namespace {

/// What fusing the arm alone gave: foreground voxels and how far from the capsules.
struct ArmAlone {
    std::size_t foreground = 0U;     ///< foreground voxels over all frames
    std::size_t beyond = 0U;         ///< of those, centres more than one voxel + half a diagonal from the capsules
    std::size_t within_half_m = 0U;  ///< of those beyond, centres within 0.5 m of the capsules' surface
    double worst = -1.0;             ///< the largest distance of a foreground centre from the capsules' surface
};

/// The voxel centres of @p frame that are foreground against @p prior, measured against @p pose.
void score_arm_frame(const GridGeometry& g, const EvidenceGrid& frame, const std::vector<std::int16_t>& prior,
                     const RobotPose& pose, ArmAlone& out) {
    const Span<std::int16_t> lo = frame.log_odds();
    const Span<std::uint8_t> seen = frame.observed();
    for (std::size_t i = 0U; i < g.voxel_count(); ++i) {
        if (seen[i] == 0U || add_saturating(lo[i], prior[i]) < 255) {
            continue;
        }
        ++out.foreground;
        const VoxelCoord c = g.coord_of(i);
        const Eigen::Vector3d centre = g.origin() + g.voxel_size() * Eigen::Vector3d(c.x + 0.5, c.y + 0.5, c.z + 0.5);
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0U; j < pose.count; ++j) {
            d = std::fmin(d, capsule_surface_distance(pose.capsules[j], centre));
        }
        out.worst = std::fmax(out.worst, d);
        const bool beyond = d > g.voxel_size() * (1.0 + 0.5 * std::sqrt(3.0));
        out.beyond += beyond ? 1U : 0U;
        out.within_half_m += beyond && d <= 0.5 ? 1U : 0U;
    }
}

/// The monitor's pipeline on the robot cell without the person, every @p step seconds of its 12 s program:
/// G_B from 8 frames of the empty cell (no robot), the accessibility prior, then each frame fused and subtracted.
/// @p noisy: the scene's noise models (each frame its own seed), else ideal sensors. @p empty, if given, gets
/// the same for frames of the empty cell (the noise's own foreground), measured against the arm's pose.
ArmAlone fuse_arm_alone(double step, bool noisy, ArmAlone* empty = nullptr) {
    sim::SceneFile file = robot_cell_file();
    file.people.clear();
    sim::RobotCellSimulation cell = robot_cell(file);
    const GridGeometry g = robot_cell_grid();
    sim::OwnedGrid background(g);
    sim::OwnedGrid frame(g);
    const SensorModelTable model;
    background.grid.clear();
    const std::vector<sim::NoiseModel> ideal;
    const std::vector<sim::NoiseModel>& noise = noisy ? file.noise : ideal;
    const sim::Scene cell_background = sim::background_of(file.scene);
    sim::SimulatedFrame f = sim::render_noisy_frame(file.sensors, noise, cell_background, 1000U);
    for (std::uint64_t i = 0U; i < 8U; ++i) {
        if (!noisy && i > 0U) {
            // Ideal frames are all the same: frame.grid still holds this one fused (fuse_background_frame is
            // clear, fuse_frame and accumulate_background), so accumulating it again gives the same G_B.
            REQUIRE(accumulate_background(background.grid, frame.grid).ok());
            continue;
        }
        if (noisy && i > 0U) {
            f = sim::render_noisy_frame(file.sensors, noise, cell_background, 1000U + i);
        }
        REQUIRE(fuse_background_frame(background.grid, frame.grid, {f.readings.data(), f.readings.size()}, model,
                                      frame.fusion_scratch())
                    .ok());
    }
    std::vector<std::int16_t> prior;
    REQUIRE(sim::compute_prior(background.grid, AccessibilityParams{}, prior));
    ArmAlone out;
    for (int k = 0; k * step <= 12.0; ++k) {
        cell.update(k * step);
        const std::uint64_t seed = 2000U + static_cast<std::uint64_t>(k);
        for (int pass = 0; pass < (empty != nullptr ? 2 : 1); ++pass) {
            const sim::Scene& scene = pass == 0 ? cell.scene().scene() : cell_background;
            f = sim::render_noisy_frame(file.sensors, noise, scene, seed);
            frame.grid.clear();
            REQUIRE(fuse_frame(frame.grid, {f.readings.data(), f.readings.size()}, model, frame.fusion_scratch()).ok());
            score_arm_frame(g, frame.grid, prior, cell.pose(), pass == 0 ? out : *empty);
        }
    }
    return out;
}

}  // namespace

// verifies: SR-SIM-006
TEST_CASE("simulator robot: the arm alone, fused and subtracted, is foreground only next to its capsules" *
          CELLGUARD_LONG_REPLAY) {
    const double half_diagonal = 0.5 * std::sqrt(3.0) * 0.1;
    const ArmAlone ideal = fuse_arm_alone(0.5, false);
    MESSAGE("arm alone, ideal sensors: " << ideal.foreground << " foreground voxels in 25 frames, the farthest centre "
                                         << ideal.worst << " m from the capsules' surface");
    CHECK(ideal.foreground > 0U);  // without a mask the arm is foreground
    // A mask of the capsules grown by a margin m marks every voxel whose centre lies within m + half a
    // diagonal of their surface: with ideal sensors m = 0 already masks every foreground voxel of the arm.
    CHECK(ideal.worst <= half_diagonal);
    // With the scene's noise models (flying pixels, stereo noise) the arm's foreground spreads further; the
    // count of voxels beyond a one-voxel margin is for the margin's derivation (safety manual), not a pass mark.
    ArmAlone empty;
    const ArmAlone noisy = fuse_arm_alone(2.0, true, &empty);
    MESSAGE("arm alone, noisy sensors: " << noisy.foreground << " foreground voxels in 7 frames, the farthest "
                                         << noisy.worst << " m from the capsules' surface, " << noisy.beyond
                                         << " beyond a 0.1 m margin (" << noisy.within_half_m
                                         << " of them within 0.5 m)");
    MESSAGE("empty cell, noisy sensors (the noise's own foreground): " << empty.foreground << " foreground voxels, "
                                                                       << empty.beyond << " beyond the margin ("
                                                                       << empty.within_half_m << " within 0.5 m)");
    CHECK(noisy.foreground > empty.foreground);
}
