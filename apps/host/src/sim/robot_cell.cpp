// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The simulated robot cell cycle by cycle (robot_cell.hpp).
#include "cellguard/host/sim/robot_cell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cellguard::sim {

LiveScene::LiveScene(const SceneFile& file)
    : scene_(file.scene),
      static_boxes_(file.scene.boxes.size()),
      people_(file.people),
      prepared_(file.scene.boxes.size() + kPersonBoxCount * file.people.size()) {
    scene_.boxes.reserve(static_boxes_ + kPersonBoxCount * people_.size());
    (void)update(0.0, RobotPose{});
}

const PreparedScene& LiveScene::update(double t, const RobotPose& robot) noexcept {
    // Within the reserved capacity resize() and push_back() never reallocate.
    scene_.boxes.resize(static_boxes_);
    PersonBoxes boxes;
    for (const PersonSpec& p : people_) {
        person_boxes_into(p, t, boxes);
        for (const Box& b : boxes) {
            scene_.boxes.push_back(b);
        }
    }
    scene_.robot = robot;
    (void)prepared_.assign(scene_);
    return prepared_;
}

std::string RobotCellSimulation::make(const SceneFile& file, const RobotModel& model, std::uint8_t case_count,
                                      RobotCellSimulation& out) {
    if (!file.robot.present) {
        return "the scene '" + file.name + "' has no [robot]";
    }
    RobotModel placed = model;
    place_robot_base(file.robot, placed);
    const RobotModelError m = check_robot_model(placed);
    if (m.code != ErrorCode::kOk) {
        return std::string("robot model: ") + m.reason + " (item " + std::to_string(m.index) + ")";
    }
    std::string error = check_trajectory(file.robot.trajectory, placed);
    if (error.empty()) {
        error = check_schedule(file.commands, case_count);
    }
    if (!error.empty()) {
        return error;
    }
    out.scene_ = LiveScene(file);
    out.model_ = placed;
    out.trajectory_ = file.robot.trajectory;
    out.schedule_ = file.commands;
    out.update(0.0);
    return {};
}

void RobotCellSimulation::update(double t, double trajectory_t) noexcept {
    joints_ = sample_trajectory(trajectory_, trajectory_t);
    if (trajectory_.keyframes.empty()) {
        pose_ = RobotPose{};  // not made by make(): no robot
    } else {
        place_robot(model_, joints_, pose_);
    }
    scheduled_ = command_at(schedule_, trajectory_t);  // the PLC switches with the robot's program
    (void)scene_.update(t, pose_);
}

namespace {
// Exact distance from @p p to box @p b (0 inside).
double point_box_distance(const Box& b, const Eigen::Vector3d& p) {
    const Eigen::AngleAxisd inv_yaw(-b.yaw, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d local = inv_yaw * (p - b.center);
    const Eigen::Vector3d outside = (local.cwiseAbs() - 0.5 * b.size).cwiseMax(0.0);
    return outside.norm();
}
}  // namespace

double box_capsule_distance(const Box& box, const PlacedCapsule& capsule, double step) {
    const Eigen::Vector3d a(capsule.a[0], capsule.a[1], capsule.a[2]);
    const Eigen::Vector3d b(capsule.b[0], capsule.b[1], capsule.b[2]);
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / std::max(step, 1e-4))));
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i) {
        const Eigen::Vector3d p = a + (static_cast<double>(i) / n) * (b - a);
        best = std::fmin(best, point_box_distance(box, p));
    }
    return std::fmax(0.0, best - capsule.radius);
}

double person_robot_distance(const Scene& scene, double step) {
    double best = std::numeric_limits<double>::infinity();
    for (const Box& b : scene.boxes) {
        if (b.background) {
            continue;
        }
        for (std::size_t k = 0; k < std::min<std::size_t>(scene.robot.count, kMaxRobotCapsules); ++k) {
            best = std::fmin(best, box_capsule_distance(b, scene.robot.capsules[k], step));
        }
    }
    return best;
}

}  // namespace cellguard::sim
