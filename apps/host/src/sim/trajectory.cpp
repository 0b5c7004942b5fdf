// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The simulated robot's joint trajectory and the simulated PLC's schedule.
#include "cellguard/host/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace cellguard::sim {

namespace {

// "file:line:column: key: what" (the scene loader's format), or "key: what"
// for an item made in code.
std::string error_at(const SourcePlace& place, const std::string& key, const std::string& what) {
    std::ostringstream m;
    if (place.line > 0) {
        m << place.file << ':' << place.line << ':' << place.column << ": ";
    }
    m << key << ": " << what;
    return m.str();
}

std::string keyframe_key(std::size_t i) { return "robot.keyframe[" + std::to_string(i) + "]"; }

std::string joint_key(std::size_t i, std::size_t j) { return keyframe_key(i) + ".joints[" + std::to_string(j) + "]"; }

const char* unit_of(const RobotLink& link) { return link.joint == JointType::kPrismatic ? "m" : "rad"; }

// Joint j of keyframe i against its link's limits, and its speed from keyframe i - 1.
std::string check_joint(const JointTrajectory& tr, std::size_t i, std::size_t j, const RobotLink& link) {
    const Keyframe& f = tr.keyframes[i];
    const double q = f.q.q[j];
    if (q < link.lower || q > link.upper) {
        std::ostringstream m;
        m << q << ' ' << unit_of(link) << " lies outside the joint's limits [" << link.lower << ", " << link.upper
          << "] " << unit_of(link);
        return error_at(f.place, joint_key(i, j), m.str());
    }
    if (i > 0U) {
        const Keyframe& e = tr.keyframes[i - 1U];
        const double speed = std::fabs(q - e.q.q[j]) / (f.t - e.t);
        if (speed > link.max_velocity) {
            std::ostringstream m;
            m << "moving from keyframe " << (i - 1U) << " takes " << speed << ' ' << unit_of(link)
              << "/s, faster than the joint's max_velocity " << link.max_velocity << ' ' << unit_of(link) << "/s";
            return error_at(f.place, joint_key(i, j), m.str());
        }
    }
    return {};
}

std::string check_keyframe_values(const JointTrajectory& tr, std::size_t i) {
    const Keyframe& f = tr.keyframes[i];
    const std::string key = keyframe_key(i);
    if (!std::isfinite(f.t) || f.t < 0.0) {
        return error_at(f.place, key + ".t", "expected a finite time >= 0 s");
    }
    if (i > 0U && !(f.t > tr.keyframes[i - 1U].t)) {
        std::ostringstream m;
        m << "times must increase: " << f.t << " s is not later than keyframe " << (i - 1U) << "'s "
          << tr.keyframes[i - 1U].t << " s";
        return error_at(f.place, key + ".t", m.str());
    }
    if (f.q.count == 0U || f.q.count > kMaxRobotJoints) {
        return error_at(f.place, key + ".joints", "expected 1 to 7 joint positions");
    }
    if (i > 0U && f.q.count != tr.keyframes[0].q.count) {
        return error_at(
            f.place, key + ".joints",
            std::to_string(f.q.count) + " joint positions, keyframe 0 has " + std::to_string(tr.keyframes[0].q.count));
    }
    for (std::size_t j = 0U; j < f.q.count; ++j) {
        if (!std::isfinite(f.q.q[j])) {
            return error_at(f.place, joint_key(i, j), "expected a finite joint position (NaN or infinite given)");
        }
    }
    return {};
}

}  // namespace

std::string check_trajectory_values(const JointTrajectory& trajectory) {
    if (trajectory.keyframes.empty()) {
        return "robot.keyframe: the trajectory needs at least one keyframe";
    }
    for (std::size_t i = 0U; i < trajectory.keyframes.size(); ++i) {
        std::string e = check_keyframe_values(trajectory, i);
        if (!e.empty()) {
            return e;
        }
    }
    return {};
}

std::string check_trajectory(const JointTrajectory& trajectory, const RobotModel& model) {
    std::string e = check_trajectory_values(trajectory);
    if (!e.empty()) {
        return e;
    }
    for (std::size_t i = 0U; i < trajectory.keyframes.size(); ++i) {
        const Keyframe& f = trajectory.keyframes[i];
        if (f.q.count != model.joint_count) {
            return error_at(f.place, keyframe_key(i) + ".joints",
                            std::to_string(f.q.count) + " joint positions, but the robot '" +
                                std::string(model.name, strnlen(model.name, kRobotNameBytes)) + "' has " +
                                std::to_string(model.joint_count) + " movable joints");
        }
        for (std::size_t j = 0U; j < f.q.count; ++j) {
            const RobotLink* link = commanded_link(model, j);
            if (link == nullptr) {
                return error_at(f.place, joint_key(i, j), "the robot has no joint with this command index");
            }
            e = check_joint(trajectory, i, j, *link);
            if (!e.empty()) {
                return e;
            }
        }
    }
    return {};
}

JointPositions sample_trajectory(const JointTrajectory& trajectory, double t) noexcept {
    const std::vector<Keyframe>& k = trajectory.keyframes;
    if (k.empty()) {
        return {};
    }
    if (!(t > k.front().t)) {  // also NaN: the first pose
        return k.front().q;
    }
    if (t >= k.back().t) {
        return k.back().q;
    }
    // The segment [k[i - 1].t, k[i].t) holding t (binary search: keyframes are sorted).
    const auto after = std::upper_bound(k.begin(), k.end(), t, [](double v, const Keyframe& f) { return v < f.t; });
    const Keyframe& b = *after;
    const Keyframe& a = *(after - 1);
    const double f = (t - a.t) / (b.t - a.t);
    JointPositions q = a.q;
    for (std::size_t j = 0U; j < q.count && j < kMaxRobotJoints; ++j) {
        q.q[j] = a.q.q[j] + f * (b.q.q[j] - a.q.q[j]);
    }
    return q;
}

double trajectory_duration(const JointTrajectory& trajectory) noexcept {
    return trajectory.keyframes.empty() ? 0.0 : trajectory.keyframes.back().t;
}

std::string check_schedule(const CommandSchedule& schedule, std::uint8_t case_count) {
    for (std::size_t i = 0U; i < schedule.steps.size(); ++i) {
        const CommandStep& s = schedule.steps[i];
        const std::string key = "command[" + std::to_string(i) + "]";
        if (i == 0U && s.t != 0.0) {
            return error_at(s.place, key + ".t", "the first command must be at t = 0 s");
        }
        if (!std::isfinite(s.t) || (i > 0U && !(s.t > schedule.steps[i - 1U].t))) {
            return error_at(s.place, key + ".t", "times must be finite and increase from one command to the next");
        }
        const unsigned limit = case_count > 0U ? case_count : kMaxMonitoringCases;
        if (s.monitoring_case >= limit) {
            return error_at(s.place, key + ".case",
                            "case " + std::to_string(s.monitoring_case) + " is not one of the cell's " +
                                std::to_string(limit) + " cases (0.." + std::to_string(limit - 1U) + ")");
        }
        if (s.speed_class >= kSpeedClasses) {
            return error_at(s.place, key + ".speed_class", "expected a speed class 0..3");
        }
    }
    return {};
}

ScheduledCommand command_at(const CommandSchedule& schedule, double t) noexcept {
    ScheduledCommand c;
    for (const CommandStep& s : schedule.steps) {
        if (&s != &schedule.steps.front() && !(s.t <= t)) {
            break;
        }
        c.monitoring_case = s.monitoring_case;
        c.speed_class = s.speed_class;
    }
    return c;
}

std::int16_t joint_raw(JointType type, double q) noexcept {
    const double unit = type == JointType::kPrismatic ? kPrismaticJointUnitM : kRevoluteJointUnitRad;
    const double r = std::nearbyint(q / unit);
    if (!(r > -32767.0)) {  // also NaN
        return -32767;
    }
    return r >= 32767.0 ? std::int16_t{32767} : static_cast<std::int16_t>(r);
}

RobotCommand simulated_command(const RobotModel& model, std::uint32_t image_crc, const JointPositions& q,
                               const ScheduledCommand& command) noexcept {
    RobotCommand c;
    c.monitoring_case = command.monitoring_case;
    c.speed_class = command.speed_class;
    c.joint_count = static_cast<std::uint8_t>(std::min<std::size_t>(q.count, kMaxCommandJoints));
    c.robot_id = static_cast<std::uint16_t>(image_crc & 0xFFFFU);
    for (std::size_t j = 0U; j < c.joint_count; ++j) {
        const RobotLink* link = commanded_link(model, j);
        c.joint_raw[j] = joint_raw(link != nullptr ? link->joint : JointType::kRevolute, q.q[j]);
    }
    return c;
}

TrajectoryClock::TrajectoryClock(double reduced_rate) noexcept
    : reduced_rate_(std::isfinite(reduced_rate) ? std::clamp(reduced_rate, 0.0, 1.0) : 0.0) {}

double TrajectoryClock::advance(double dt, SpeedRequest request) noexcept {
    const double step = std::isfinite(dt) && dt > 0.0 ? dt : 0.0;
    switch (request) {
        case SpeedRequest::kFull: time_ += step; break;
        case SpeedRequest::kReduced: time_ += reduced_rate_ * step; break;
        case SpeedRequest::kProtectiveStop: break;
    }
    return time_;
}

}  // namespace cellguard::sim
