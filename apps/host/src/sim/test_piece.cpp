// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/test_piece.hpp"

#include <cmath>
#include <limits>

#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Entry distance of the ray into the solid cylinder: the interval where it is
/// within r of the axis, cut with the slab between the end planes; 0 inside.
double enter_cylinder(const TestPiece& p, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) noexcept {
    const double r = 0.5 * p.diameter;
    const double half = 0.5 * p.length;
    const Eigen::Vector3d& u = p.axis;
    const Eigen::Vector3d oc = origin - p.centre;
    // The slab |(o + t d - c) . u| <= half.
    const double s0 = oc.dot(u);
    const double ds = dir.dot(u);
    double t_in = -kInf;
    double t_out = kInf;
    if (std::fabs(ds) < 1e-15) {
        if (std::fabs(s0) > half) {
            return kInf;
        }
    } else {
        const double ta = (-half - s0) / ds;
        const double tb = (half - s0) / ds;
        t_in = std::fmin(ta, tb);
        t_out = std::fmax(ta, tb);
    }
    // The infinite cylinder |(o + t d - c) x u| <= r.
    const Eigen::Vector3d d_perp = dir - ds * u;
    const Eigen::Vector3d o_perp = oc - s0 * u;
    const double qa = d_perp.squaredNorm();
    const double qc = o_perp.squaredNorm() - r * r;
    if (qa < 1e-18) {
        if (qc > 0.0) {
            return kInf;  // parallel to the axis, outside the radius
        }
    } else {
        const double qb = d_perp.dot(o_perp);
        const double h = qb * qb - qa * qc;
        if (h < 0.0) {
            return kInf;
        }
        const double root = std::sqrt(h);
        t_in = std::fmax(t_in, (-qb - root) / qa);
        t_out = std::fmin(t_out, (-qb + root) / qa);
    }
    if (t_in > t_out || t_out < 0.0) {
        return kInf;
    }
    return std::fmax(0.0, t_in);
}

}  // namespace

const char* to_string(PieceShape shape) noexcept { return shape == PieceShape::kSphere ? "sphere" : "cylinder"; }

double TestPiece::bounding_radius() const noexcept {
    const double r = 0.5 * diameter;
    return shape == PieceShape::kSphere ? r : std::sqrt(r * r + 0.25 * length * length);
}

double TestPiece::lowest_z() const noexcept {
    const double r = 0.5 * diameter;
    if (shape == PieceShape::kSphere) {
        return centre.z() - r;
    }
    // The lowest point of an end disc: the end's centre lowered by r times the
    // disc's extent along z, sqrt(1 - u_z^2).
    const double uz = axis.z();
    const double disc = r * std::sqrt(std::fmax(0.0, 1.0 - uz * uz));
    return centre.z() - 0.5 * length * std::fabs(uz) - disc;
}

double intersect_piece(const TestPiece& piece, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) noexcept {
    if (piece.shape == PieceShape::kSphere) {
        return intersect_sphere(piece.centre, 0.5 * piece.diameter, origin, dir);
    }
    return enter_cylinder(piece, origin, dir);
}

bool piece_contains(const TestPiece& piece, const Eigen::Vector3d& p) noexcept {
    const Eigen::Vector3d q = p - piece.centre;
    const double r = 0.5 * piece.diameter;
    if (piece.shape == PieceShape::kSphere) {
        return q.squaredNorm() <= r * r;
    }
    const double s = q.dot(piece.axis);
    return std::fabs(s) <= 0.5 * piece.length && (q - s * piece.axis).squaredNorm() <= r * r;
}

}  // namespace cellguard::sim
