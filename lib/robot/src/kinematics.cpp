// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/robot/kinematics.hpp"

#include <Eigen/Core>
#include <cmath>

#include "cellguard/robot/robot_image.hpp"

namespace cellguard {

namespace {

// Every product below is written out as scalar double operations in a fixed
// order (no Eigen product expressions, whose vectorised kernels may use
// fused multiply-adds on some targets), and sine and cosine come from the
// polynomial below, not from the C library (whose last bit differs between
// glibc's x86-64 and aarch64 variants and newlib): so every target computes
// the same bits. Eigen's fixed-size types hold the values.

/// sin and cos of @p q: Cody-Waite reduction by pi/2 (pi/2 split in a 33-bit
/// head and a tail, exact products for |q| < 2^20 quadrants), then fdlibm's
/// kernel polynomials on [-pi/4, pi/4]; error within a few units in the last
/// place for |q| up to about 10^6 rad. Only +, -, *, floor: deterministic.
void sin_cos(double q, double& s, double& c) noexcept {
    constexpr double kInvPio2 = 6.36619772367581382433e-01;
    constexpr double kPio2Head = 1.57079632673412561417e+00;
    constexpr double kPio2Tail = 6.07710050650619224932e-11;
    const double n = std::floor(q * kInvPio2 + 0.5);
    const double r = (q - n * kPio2Head) - n * kPio2Tail;
    const double z = r * r;
    const double sr = r + r * z *
                              (-1.66666666666666324348e-01 +
                               z * (8.33333333332248946124e-03 +
                                    z * (-1.98412698298579493134e-04 +
                                         z * (2.75573137070700676789e-06 +
                                              z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
    const double cr = 1.0 - 0.5 * z +
                      z * z *
                          (4.16666666666666019037e-02 +
                           z * (-1.38888888888741095749e-03 +
                                z * (2.48015872894767294178e-05 +
                                     z * (-2.75573143513906633035e-07 +
                                          z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
    // Quadrant n mod 4, in 0..3: every step is exact for an integer-valued n
    // (division by 4 and floor are exact), and no library call is needed.
    const double quadrant = n - 4.0 * std::floor(n * 0.25);
    if (quadrant == 0.0) {
        s = sr;
        c = cr;
    } else if (quadrant == 1.0) {
        s = cr;
        c = -sr;
    } else if (quadrant == 2.0) {
        s = -sr;
        c = -cr;
    } else {
        s = -cr;
        c = sr;
    }
}

/// The rotation of quaternion (w, x, y, z), divided by its squared norm
/// (exact for any non-zero quaternion; a unit one within tolerance stays a rotation).
Eigen::Matrix3d rotation_of(const double q[4]) noexcept {
    const double w = q[0];
    const double x = q[1];
    const double y = q[2];
    const double z = q[3];
    const double s = 2.0 / (w * w + x * x + y * y + z * z);
    Eigen::Matrix3d r;
    r(0, 0) = 1.0 - s * (y * y + z * z);
    r(0, 1) = s * (x * y - w * z);
    r(0, 2) = s * (x * z + w * y);
    r(1, 0) = s * (x * y + w * z);
    r(1, 1) = 1.0 - s * (x * x + z * z);
    r(1, 2) = s * (y * z - w * x);
    r(2, 0) = s * (x * z - w * y);
    r(2, 1) = s * (y * z + w * x);
    r(2, 2) = 1.0 - s * (x * x + y * y);
    return r;
}

/// Rotation by @p angle about the unit @p axis (Rodrigues).
Eigen::Matrix3d axis_rotation(const double axis[3], double angle) noexcept {
    double s = 0.0;
    double c = 1.0;
    sin_cos(angle, s, c);
    const double t = 1.0 - c;
    const double x = axis[0];
    const double y = axis[1];
    const double z = axis[2];
    Eigen::Matrix3d r;
    r(0, 0) = c + t * x * x;
    r(0, 1) = t * x * y - s * z;
    r(0, 2) = t * x * z + s * y;
    r(1, 0) = t * x * y + s * z;
    r(1, 1) = c + t * y * y;
    r(1, 2) = t * y * z - s * x;
    r(2, 0) = t * x * z - s * y;
    r(2, 1) = t * y * z + s * x;
    r(2, 2) = c + t * z * z;
    return r;
}

Eigen::Matrix3d mul(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) noexcept {
    Eigen::Matrix3d r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r(i, j) = a(i, 0) * b(0, j) + a(i, 1) * b(1, j) + a(i, 2) * b(2, j);
        }
    }
    return r;
}

Eigen::Vector3d mul(const Eigen::Matrix3d& a, const Eigen::Vector3d& v) noexcept {
    Eigen::Vector3d r;
    for (int i = 0; i < 3; ++i) {
        r(i) = a(i, 0) * v(0) + a(i, 1) * v(1) + a(i, 2) * v(2);
    }
    return r;
}

Eigen::Vector3d vec(const double v[3]) noexcept { return {v[0], v[1], v[2]}; }

/// Position of movable link @p l's joint: its command's, or for a mimic
/// multiplier x its master's + offset (two operations, no fused multiply-add).
double joint_value(const RobotLink& l, const JointPositions& q) noexcept {
    CG_ENFORCE(l.command_index < q.count, "joint's command index beyond the positions");
    const double master = q.q[l.command_index];
    if (!l.mimic) {
        return master;
    }
    const double scaled = l.mimic_multiplier * master;
    return scaled + l.mimic_offset;
}

}  // namespace

const char* to_string(JointCheck check) noexcept {
    switch (check) {
        case JointCheck::kOk: return "joints accepted";
        case JointCheck::kJointCountMismatch: return "command joint count differs from the robot's";
        case JointCheck::kInvalidRaw: return "command joint value invalid (reserved value, or unused joint not 0)";
        case JointCheck::kOutsideLimits: return "command joint position outside its limits";
        case JointCheck::kRobotIdMismatch: return "command robot id differs from the robot image's";
    }
    return "unknown joint check";
}

Result<JointPositions, JointCheck> joint_positions(const RobotModel& model, std::uint32_t image_crc,
                                                   const RobotCommand& command) noexcept {
    if (command.robot_id != robot_id(image_crc)) {
        return JointCheck::kRobotIdMismatch;
    }
    if (command.joint_count != model.joint_count) {
        return JointCheck::kJointCountMismatch;
    }
    for (std::size_t k = 0U; k < kMaxCommandJoints; ++k) {
        const std::int16_t raw = command.joint_raw[k];
        if (k < command.joint_count ? raw == kJointRawInvalid : raw != 0) {
            return JointCheck::kInvalidRaw;
        }
    }
    JointPositions out;
    out.count = model.joint_count;
    for (std::size_t k = 0U; k < model.joint_count; ++k) {
        const RobotLink* link = commanded_link(model, k);
        CG_ENFORCE(link != nullptr, "joint_positions needs a checked model");
        const double unit = link->joint == JointType::kPrismatic ? kPrismaticJointUnitM : kRevoluteJointUnitRad;
        const double q = static_cast<double>(command.joint_raw[k]) * unit;
        const double tolerance = 0.5 * unit;
        if (q < link->lower - tolerance || q > link->upper + tolerance) {
            return JointCheck::kOutsideLimits;
        }
        out.q[k] = q;
    }
    return out;
}

void place_robot(const RobotModel& model, const JointPositions& q, RobotPose& out) noexcept {
    CG_ENFORCE(q.count == model.joint_count && model.link_count >= 1U && model.link_count <= kMaxRobotLinks &&
                   model.capsule_count <= kMaxRobotCapsules,
               "place_robot needs a checked model and its joint count");
    Eigen::Matrix3d rot[kMaxRobotLinks];
    Eigen::Vector3d pos[kMaxRobotLinks];
    rot[0] = rotation_of(model.base_wxyz);
    pos[0] = vec(model.base_xyz);
    for (std::size_t i = 1U; i < model.link_count; ++i) {
        const RobotLink& l = model.links[i];
        CG_ENFORCE(l.parent < i, "place_robot needs parents before children");
        const Eigen::Matrix3d& parent_rot = rot[l.parent];
        const Eigen::Matrix3d origin_rot = rotation_of(l.origin_wxyz);
        Eigen::Vector3d offset = vec(l.origin_xyz);
        Eigen::Matrix3d joint_rot = origin_rot;
        if (l.joint == JointType::kRevolute) {
            joint_rot = mul(origin_rot, axis_rotation(l.axis, joint_value(l, q)));
        } else if (l.joint == JointType::kPrismatic) {
            const double d = joint_value(l, q);
            const Eigen::Vector3d along(l.axis[0] * d, l.axis[1] * d, l.axis[2] * d);
            const Eigen::Vector3d moved = mul(origin_rot, along);
            offset = Eigen::Vector3d(offset(0) + moved(0), offset(1) + moved(1), offset(2) + moved(2));
        }
        rot[i] = mul(parent_rot, joint_rot);
        const Eigen::Vector3d world_offset = mul(parent_rot, offset);
        pos[i] = Eigen::Vector3d(pos[l.parent](0) + world_offset(0), pos[l.parent](1) + world_offset(1),
                                 pos[l.parent](2) + world_offset(2));
    }
    out = RobotPose{};
    out.count = model.capsule_count;
    for (std::size_t c = 0U; c < model.capsule_count; ++c) {
        const RobotCapsule& cap = model.capsules[c];
        CG_ENFORCE(cap.link < model.link_count, "capsule on a link that does not exist");
        const Eigen::Vector3d a = mul(rot[cap.link], vec(cap.a));
        const Eigen::Vector3d b = mul(rot[cap.link], vec(cap.b));
        PlacedCapsule& p = out.capsules[c];
        for (int k = 0; k < 3; ++k) {
            p.a[k] = pos[cap.link](k) + a(k);
            p.b[k] = pos[cap.link](k) + b(k);
        }
        p.radius = cap.radius;
        p.link = cap.link;
    }
}

}  // namespace cellguard
