// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file trajectory.hpp
/// The simulated robot's motion and the simulated PLC's commands over time:
/// a joint trajectory (keyframes of time and joint positions in SI units,
/// linear in between), the schedule of the monitoring case and the speed
/// class, and the PLC's command message made from both. Loaded from scene
/// files (scene_file.hpp: [robot], [[robot.keyframe]], [[command]]); the
/// robot itself is a RobotModel of lib/robot from wherever it comes (a URDF
/// commissioned by the host tools, or a model written in code), so the
/// trajectory is checked against it after loading (check_trajectory).
///
/// Per cycle nothing here allocates: sample_trajectory, command_at,
/// simulated_command and TrajectoryClock work on storage made at start-up.
#ifndef CELLGUARD_HOST_SIM_TRAJECTORY_HPP
#define CELLGUARD_HOST_SIM_TRAJECTORY_HPP

#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard::sim {

/// Where an item was written: file, line and column (for error messages).
struct SourcePlace {
    std::string file;  ///< the scene file's name as given to the loader
    int line = 0;      ///< 1-based line, 0 when unknown (an item made in code)
    int column = 0;    ///< 1-based column
};

/// One keyframe: the robot's joint positions at a time.
struct Keyframe {
    double t = 0.0;       ///< seconds from the start of the run, >= 0
    JointPositions q{};   ///< rad (revolute) or m (prismatic), by command index
    SourcePlace place{};  ///< where it was written
};

/// Keyframes at strictly increasing times, all with the same joint count.
/// Before the first keyframe the robot holds the first pose, after the last
/// it holds the last; in between each joint moves linearly in time.
struct JointTrajectory {
    std::vector<Keyframe> keyframes;  ///< at least one when loaded from a file
};

/// Checks @p trajectory on its own (no robot needed): at least one keyframe;
/// every time finite and >= 0, each later than the one before; every joint
/// value finite; every keyframe with the same joint count, 1..kMaxRobotJoints.
/// Returns "" when valid, else "file:line:column: robot.keyframe[i]...: what".
std::string check_trajectory_values(const JointTrajectory& trajectory);

/// Checks @p trajectory against @p model: check_trajectory_values, then the
/// joint count equals the model's, every value lies within its joint's
/// [lower, upper], and no joint moves faster between two keyframes than its
/// max_velocity. Returns "" when valid, else an error naming the keyframe
/// and the joint ("file:line:column: robot.keyframe[2].joints[1]: ...").
std::string check_trajectory(const JointTrajectory& trajectory, const RobotModel& model);

/// The joint positions at time @p t (linear between keyframes, held before
/// the first and after the last). @p trajectory must be non-empty (else all
/// zero with count 0). Allocates nothing.
JointPositions sample_trajectory(const JointTrajectory& trajectory, double t) noexcept;

/// The time of the last keyframe (0 for an empty trajectory).
double trajectory_duration(const JointTrajectory& trajectory) noexcept;

/// From time t on (until the next step) the simulated PLC commands this case and speed class.
struct CommandStep {
    double t = 0.0;                     ///< seconds from the start of the run
    std::uint8_t monitoring_case = 0U;  ///< 0..kMaxMonitoringCases-1
    std::uint8_t speed_class = 0U;      ///< 0..kSpeedClasses-1
    SourcePlace place{};                ///< where it was written
};

/// The simulated PLC's schedule: steps at strictly increasing times, the
/// first at t = 0. Empty: case 0 and speed class 0 throughout.
struct CommandSchedule {
    std::vector<CommandStep> steps;  ///< in time order
};

/// What the schedule commands at one time.
struct ScheduledCommand {
    std::uint8_t monitoring_case = 0U;  ///< the case to apply
    std::uint8_t speed_class = 0U;      ///< the robot's speed class
};

/// Checks @p schedule: the first step at t = 0, times finite and strictly
/// increasing, cases < kMaxMonitoringCases, classes < kSpeedClasses; with
/// @p case_count > 0 also every case < case_count (the cell's commissioned
/// cases). Returns "" when valid, else "file:line:column: command[i].key: what".
std::string check_schedule(const CommandSchedule& schedule, std::uint8_t case_count = 0U);

/// The step in force at time @p t (the last step with step.t <= t; the first
/// before it). Allocates nothing.
ScheduledCommand command_at(const CommandSchedule& schedule, double t) noexcept;

/// The raw wire value of joint position @p q of a joint of type @p type
/// (robot_command.hpp's units), rounded to nearest and saturated to
/// -32767..32767 (never kJointRawInvalid).
std::int16_t joint_raw(JointType type, double q) noexcept;

/// The simulated PLC's command at one time: @p command's case and class,
/// joints @p q as raw values (each joint's type from @p model, by command
/// index), unused entries 0, and robot_id = the low 16 bits of @p image_crc.
RobotCommand simulated_command(const RobotModel& model, std::uint32_t image_crc, const JointPositions& q,
                               const ScheduledCommand& command) noexcept;

/// The robot's progress along its trajectory when it obeys the speed
/// request: trajectory time advances at full rate under kFull, at
/// reduced_rate under kReduced, and not at all under kProtectiveStop (an
/// ideal robot that stops at once: the stopping distance S_s is the
/// separation parameters' business, not the simulator's).
class TrajectoryClock {
public:
    /// A clock at trajectory time 0; @p reduced_rate in [0, 1] (clamped).
    explicit TrajectoryClock(double reduced_rate = 0.25) noexcept;
    /// Advances by @p dt seconds of run time (>= 0; negative counts 0) under
    /// @p request; returns the new trajectory time.
    double advance(double dt, SpeedRequest request) noexcept;
    /// The trajectory time.
    [[nodiscard]] double time() const noexcept { return time_; }

private:
    double reduced_rate_;
    double time_ = 0.0;
};

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_TRAJECTORY_HPP
