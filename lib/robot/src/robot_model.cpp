// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/robot/robot_model.hpp"

#include <cmath>

#include "cellguard/base/contract.hpp"

namespace cellguard {

namespace {

RobotModelError fail(ErrorCode code, std::size_t index, const char* reason) noexcept {
    RobotModelError e;
    e.code = code;
    e.index = index;
    e.reason = reason;
    return e;
}

bool all_finite(const double* v, std::size_t n) noexcept {
    for (std::size_t i = 0U; i < n; ++i) {
        if (!std::isfinite(v[i])) {
            return false;
        }
    }
    return true;
}

/// |v| <= limit, compared squared (no sqrt); v finite.
bool within(const double v[3], double limit) noexcept {
    return v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= limit * limit;
}

/// | |v| - 1 | <= kUnitLengthTolerance, for n components (finite).
bool unit_length(const double* v, std::size_t n) noexcept {
    double sq = 0.0;
    for (std::size_t i = 0U; i < n; ++i) {
        sq += v[i] * v[i];
    }
    return std::fabs(std::sqrt(sq) - 1.0) <= kUnitLengthTolerance;
}

bool known_joint(JointType type) noexcept {
    switch (type) {
        case JointType::kFixed:
        case JointType::kRevolute:
        case JointType::kPrismatic: return true;
    }
    return false;
}

RobotModelError check_counts_and_base(const RobotModel& m) noexcept {
    if (m.link_count == 0U || m.capsule_count == 0U) {
        return fail(ErrorCode::kInvalidArgument, 0U, "a robot needs at least one link and one capsule");
    }
    if (m.link_count > kMaxRobotLinks) {
        return fail(ErrorCode::kCapacityExceeded, 0U, "more links than kMaxRobotLinks");
    }
    if (m.capsule_count > kMaxRobotCapsules) {
        return fail(ErrorCode::kCapacityExceeded, 0U, "more capsules than kMaxRobotCapsules");
    }
    if (m.joint_count > kMaxRobotJoints) {
        return fail(ErrorCode::kCapacityExceeded, 0U, "more movable joints than kMaxRobotJoints");
    }
    bool terminated = false;
    for (const char c : m.name) {
        terminated = terminated || c == '\0';
    }
    if (!terminated) {
        return fail(ErrorCode::kInvalidArgument, 0U, "robot name is not zero-terminated");
    }
    if (!all_finite(m.base_xyz, 3U) || !all_finite(m.base_wxyz, 4U)) {
        return fail(ErrorCode::kNonFiniteValue, 0U, "base pose is not finite");
    }
    if (!unit_length(m.base_wxyz, 4U)) {
        return fail(ErrorCode::kInvalidArgument, 0U, "base rotation is not a unit quaternion");
    }
    if (!within(m.base_xyz, kMaxRobotReach)) {
        return fail(ErrorCode::kInvalidArgument, 0U, "base position farther than kMaxRobotReach");
    }
    return RobotModelError{};
}

RobotModelError check_root(const RobotLink& root) noexcept {
    if (root.parent != 0U || root.joint != JointType::kFixed || root.command_index != kNoCommandIndex) {
        return fail(ErrorCode::kInvalidArgument, 0U, "the root link must be fixed, without parent or command index");
    }
    if (root.origin_xyz[0] != 0.0 || root.origin_xyz[1] != 0.0 || root.origin_xyz[2] != 0.0 ||
        root.origin_wxyz[0] != 1.0 || root.origin_wxyz[1] != 0.0 || root.origin_wxyz[2] != 0.0 ||
        root.origin_wxyz[3] != 0.0) {
        return fail(ErrorCode::kInvalidArgument, 0U, "the root link's origin must be the identity (base_* place it)");
    }
    return RobotModelError{};
}

RobotModelError check_link(const RobotModel& m, std::size_t i) noexcept {
    const RobotLink& l = m.links[i];
    const double numbers[] = {l.lower, l.upper, l.max_velocity, l.mimic_multiplier, l.mimic_offset};
    if (!all_finite(l.origin_xyz, 3U) || !all_finite(l.origin_wxyz, 4U) || !all_finite(l.axis, 3U) ||
        !all_finite(numbers, 5U)) {
        return fail(ErrorCode::kNonFiniteValue, i, "link has a value that is not finite");
    }
    if (!l.mimic && (l.mimic_multiplier != 1.0 || l.mimic_offset != 0.0)) {
        return fail(ErrorCode::kInvalidArgument, i, "a joint that is not a mimic has a mimic multiplier or offset");
    }
    if (i == 0U) {
        return l.mimic ? fail(ErrorCode::kInvalidArgument, 0U, "the root link cannot be a mimic") : check_root(l);
    }
    if (l.parent >= i) {
        return fail(ErrorCode::kInvalidArgument, i, "link's parent does not come before it (broken chain)");
    }
    if (!known_joint(l.joint)) {
        return fail(ErrorCode::kInvalidArgument, i, "link's joint type is unknown");
    }
    if (!unit_length(l.origin_wxyz, 4U)) {
        return fail(ErrorCode::kInvalidArgument, i, "joint origin rotation is not a unit quaternion");
    }
    if (!within(l.origin_xyz, kMaxRobotReach)) {
        return fail(ErrorCode::kInvalidArgument, i, "joint origin farther than kMaxRobotReach");
    }
    if (l.joint == JointType::kFixed) {
        if (l.command_index != kNoCommandIndex || l.mimic) {
            return fail(ErrorCode::kInvalidArgument, i, "fixed joint with a command index or a mimic");
        }
        return RobotModelError{};
    }
    if (!unit_length(l.axis, 3U)) {
        return fail(ErrorCode::kInvalidArgument, i, "joint axis is not a unit vector");
    }
    if (l.command_index >= m.joint_count) {
        return fail(ErrorCode::kInvalidArgument, i, "movable joint's command index is not below joint_count");
    }
    if (!(l.lower <= l.upper)) {
        return fail(ErrorCode::kInvalidArgument, i, "joint's lower limit is above its upper limit");
    }
    const double range = l.joint == JointType::kRevolute ? kMaxRevoluteLimit : kMaxRobotReach;
    if (l.lower < -range || l.upper > range) {
        return fail(ErrorCode::kInvalidArgument, i, "joint limit beyond kMaxRevoluteLimit or kMaxRobotReach");
    }
    if (!(l.max_velocity > 0.0)) {
        return fail(ErrorCode::kInvalidArgument, i, "joint's max_velocity is not positive");
    }
    return RobotModelError{};
}

/// Mimic link @p i (command indices already checked): a non-zero multiplier,
/// and its master's whole range mapped inside its own limits (a wrong
/// multiplier or offset shows there).
RobotModelError check_mimic(const RobotModel& m, std::size_t i) noexcept {
    const RobotLink& l = m.links[i];
    const RobotLink* master = commanded_link(m, l.command_index);
    // check_link put the index below joint_count, and every index there has its commanded joint.
    CG_ENFORCE(master != nullptr, "check_mimic runs after the command indices are checked");
    if (l.mimic_multiplier == 0.0) {
        return fail(ErrorCode::kInvalidArgument, i, "mimic multiplier is 0 (a fixed joint?)");
    }
    const double at_lower = l.mimic_multiplier * master->lower + l.mimic_offset;
    const double at_upper = l.mimic_multiplier * master->upper + l.mimic_offset;
    const double lo = at_lower < at_upper ? at_lower : at_upper;
    const double hi = at_lower < at_upper ? at_upper : at_lower;
    const double largest = std::fmax(1.0, std::fmax(std::fabs(l.lower), std::fabs(l.upper)));
    const double slack = kMimicRangeTolerance * largest;
    if (lo < l.lower - slack || hi > l.upper + slack) {
        return fail(ErrorCode::kInvalidArgument, i, "mimic's master range maps outside its limits (wrong ratio?)");
    }
    return RobotModelError{};
}

RobotModelError check_capsule(const RobotModel& m, std::size_t i) noexcept {
    const RobotCapsule& c = m.capsules[i];
    if (!all_finite(c.a, 3U) || !all_finite(c.b, 3U) || !std::isfinite(c.radius)) {
        return fail(ErrorCode::kNonFiniteValue, i, "capsule has a value that is not finite");
    }
    if (c.link >= m.link_count) {
        return fail(ErrorCode::kInvalidArgument, i, "capsule's link does not exist");
    }
    if (!(c.radius > 0.0) || c.radius > kMaxCapsuleRadius) {
        return fail(ErrorCode::kInvalidArgument, i, "capsule radius outside (0, kMaxCapsuleRadius]");
    }
    if (!within(c.a, kMaxRobotReach) || !within(c.b, kMaxRobotReach)) {
        return fail(ErrorCode::kInvalidArgument, i, "capsule end farther than kMaxRobotReach");
    }
    return RobotModelError{};
}

}  // namespace

RobotModelError check_robot_model(const RobotModel& model) noexcept {
    RobotModelError e = check_counts_and_base(model);
    if (!is_no_error(e)) {
        return e;
    }
    std::uint32_t indices_seen = 0U;
    for (std::size_t i = 0U; i < model.link_count; ++i) {
        e = check_link(model, i);
        if (!is_no_error(e)) {
            return e;
        }
        if (model.links[i].joint != JointType::kFixed && !model.links[i].mimic) {
            const std::uint32_t bit = 1U << model.links[i].command_index;  // < joint_count <= 7
            if ((indices_seen & bit) != 0U) {
                return fail(ErrorCode::kInvalidArgument, i, "two movable joints share a command index");
            }
            indices_seen |= bit;
        }
    }
    if (indices_seen != (1U << model.joint_count) - 1U) {
        return fail(ErrorCode::kInvalidArgument, 0U, "movable joints do not use command indices 0..joint_count-1");
    }
    for (std::size_t i = 1U; i < model.link_count; ++i) {
        e = model.links[i].mimic ? check_mimic(model, i) : RobotModelError{};
        if (!is_no_error(e)) {
            return e;
        }
    }
    for (std::size_t i = 0U; i < model.capsule_count; ++i) {
        e = check_capsule(model, i);
        if (!is_no_error(e)) {
            return e;
        }
    }
    return RobotModelError{};
}

const RobotLink* commanded_link(const RobotModel& model, std::size_t k) noexcept {
    for (std::size_t i = 1U; i < model.link_count && i < kMaxRobotLinks; ++i) {
        const RobotLink& l = model.links[i];
        if (l.joint != JointType::kFixed && !l.mimic && l.command_index == k) {
            return &l;
        }
    }
    return nullptr;
}

bool has_mimic_joint(const RobotModel& model) noexcept {
    for (std::size_t i = 0U; i < model.link_count && i < kMaxRobotLinks; ++i) {
        if (model.links[i].mimic) {
            return true;
        }
    }
    return false;
}

}  // namespace cellguard
