// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_cell.hpp
/// The simulated robot cell cycle by cycle: a scene file's static boxes and
/// walking people, and a robot (a RobotModel from wherever it comes) that
/// follows the file's joint trajectory, put together into one prepared
/// scene per cycle that the simulated sensors render (render_depth_into)
/// and the simulated PLC reports (simulated_command). Storage is allocated
/// when the simulation is made; update() and the renders allocate nothing.
///
/// A run's two clocks: run time t (people walk) and trajectory time (the
/// robot program's progress: where the robot is along its trajectory, and
/// the PLC's schedule of cases and speed classes, which a PLC switches with
/// the robot's program steps, not with the wall clock). They are equal for
/// a robot that never slows down; a TrajectoryClock (trajectory.hpp)
/// advances the trajectory time by the controller's speed requests for a
/// robot that obeys them.
#ifndef CELLGUARD_HOST_SIM_ROBOT_CELL_HPP
#define CELLGUARD_HOST_SIM_ROBOT_CELL_HPP

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/host/sim/scene_file.hpp"
#include "cellguard/host/sim/trajectory.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/robot/kinematics.hpp"

namespace cellguard::sim {

/// A scene file's scene at any time, with a robot pose, without allocating.
class LiveScene {
public:
    /// The boxes and people of @p file (copied); storage for all of them;
    /// the scene at time 0 without a robot.
    explicit LiveScene(const SceneFile& file);
    /// Not copyable: a copy's vectors need not keep the storage reserved here.
    LiveScene(const LiveScene&) = delete;
    /// Not copyable.
    LiveScene& operator=(const LiveScene&) = delete;
    /// Moves the storage (moved vectors keep it).
    LiveScene(LiveScene&&) noexcept = default;
    /// Moves the storage.
    LiveScene& operator=(LiveScene&&) noexcept = default;
    ~LiveScene() = default;
    /// The scene at run time @p t: the file's boxes, every person at @p t,
    /// and @p robot's capsules (count 0: no robot). The same scene as
    /// scene_at(file, t) with the robot added, bit for bit. Allocates nothing.
    const PreparedScene& update(double t, const RobotPose& robot) noexcept;
    /// The scene of the last update (the file's boxes before the first).
    [[nodiscard]] const PreparedScene& prepared() const noexcept { return prepared_; }

private:
    Scene scene_;                     ///< the file's boxes, then room for the people's
    std::size_t static_boxes_ = 0U;   ///< the file's boxes
    std::vector<PersonSpec> people_;  ///< the walking people
    PreparedScene prepared_;          ///< the scene of the last update
};

/// The robot cell: a LiveScene plus the robot following its trajectory and
/// the simulated PLC's schedule.
class RobotCellSimulation {
public:
    /// The cell of @p file with robot @p model. The model is placed where the
    /// file's [robot] table puts it (place_robot_base); make() refuses a
    /// model that fails check_robot_model or a trajectory or schedule that
    /// does not fit it (check_trajectory, check_schedule with @p case_count).
    /// Returns "" and fills @p out, or the error.
    static std::string make(const SceneFile& file, const RobotModel& model, std::uint8_t case_count,
                            RobotCellSimulation& out);

    /// An empty simulation (no robot, no scene) for make() to fill; update()
    /// on it places no robot.
    RobotCellSimulation() : scene_(SceneFile{}) {}

    /// Moves the cell to run time @p t (people) with the robot at trajectory
    /// time @p trajectory_t (joints, capsules, and the schedule's case and
    /// speed class), and makes the scene. Allocates nothing.
    void update(double t, double trajectory_t) noexcept;
    /// update(t, t): a robot that never slows down.
    void update(double t) noexcept { update(t, t); }

    /// The robot model as placed in the cell.
    [[nodiscard]] const RobotModel& model() const noexcept { return model_; }
    /// The robot's joints at the last update.
    [[nodiscard]] const JointPositions& joints() const noexcept { return joints_; }
    /// The robot's capsules at the last update (world frame).
    [[nodiscard]] const RobotPose& pose() const noexcept { return pose_; }
    /// The monitoring case and speed class scheduled at the last update.
    [[nodiscard]] const ScheduledCommand& scheduled() const noexcept { return scheduled_; }
    /// The simulated PLC's command at the last update, for a robot image with CRC @p image_crc.
    [[nodiscard]] RobotCommand command(std::uint32_t image_crc) const noexcept {
        return simulated_command(model_, image_crc, joints_, scheduled_);
    }
    /// The scene of the last update, to render (render_depth_into, render_frame_into).
    [[nodiscard]] const PreparedScene& scene() const noexcept { return scene_.prepared(); }
    /// The trajectory.
    [[nodiscard]] const JointTrajectory& trajectory() const noexcept { return trajectory_; }
    /// The schedule.
    [[nodiscard]] const CommandSchedule& schedule() const noexcept { return schedule_; }

private:
    LiveScene scene_;
    RobotModel model_{};
    JointTrajectory trajectory_;
    CommandSchedule schedule_;
    JointPositions joints_{};
    RobotPose pose_{};
    ScheduledCommand scheduled_{};
};

/// The smallest distance between box @p box and the surface of capsule
/// @p capsule (0 when they touch or overlap), metres: exact distances from
/// points along the capsule's segment, @p step metres apart (both ends
/// included), to the box, less the radius; so at most step / 2 too large.
/// For tests and the scenario's expected distances, not for the cycle.
double box_capsule_distance(const Box& box, const PlacedCapsule& capsule, double step = 0.01);

/// The smallest box_capsule_distance between any foreground box of
/// @p scene and any capsule of its robot; +infinity when either is missing.
double person_robot_distance(const Scene& scene, double step = 0.01);

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_ROBOT_CELL_HPP
