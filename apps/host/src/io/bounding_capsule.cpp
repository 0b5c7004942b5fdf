// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// bounding_capsule() and segment_distance() of urdf_import.hpp: a capsule
// around a mesh's vertices.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "cellguard/base/contract.hpp"
#include "cellguard/host/io/urdf_import.hpp"

namespace cellguard::host {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The capsule along unit @p axis: its line through the centre of the
/// points' bounding rectangle across the axis, radius the largest distance
/// from that line, and the shortest segment that contains every point.
Capsule capsule_along(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& axis) {
    const Eigen::Vector3d u = axis.normalized();
    // Two unit vectors across u.
    const Eigen::Vector3d helper = std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d v = u.cross(helper).normalized();
    const Eigen::Vector3d w = u.cross(v);
    Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    for (const Eigen::Vector3d& p : points) {
        const Eigen::Vector2d q(p.dot(v), p.dot(w));
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
    }
    const Eigen::Vector2d centre = 0.5 * (lo + hi);
    double r2 = 0.0;
    for (const Eigen::Vector3d& p : points) {
        r2 = std::max(r2, (Eigen::Vector2d(p.dot(v), p.dot(w)) - centre).squaredNorm());
    }
    // A point at axial t and squared distance d2 from the line lies in the
    // capsule when the segment reaches t - s .. t + s, s = sqrt(r2 - d2).
    double t_low = std::numeric_limits<double>::infinity();  // segment must start at or below
    double t_high = -t_low;                                  // and end at or above
    for (const Eigen::Vector3d& p : points) {
        const double d2 = (Eigen::Vector2d(p.dot(v), p.dot(w)) - centre).squaredNorm();
        const double s = std::sqrt(std::max(0.0, r2 - d2));
        t_low = std::min(t_low, p.dot(u) + s);
        t_high = std::max(t_high, p.dot(u) - s);
    }
    if (t_low > t_high) {  // short and wide: one point of the axis reaches all (a sphere)
        t_low = t_high = 0.5 * (t_low + t_high);
    }
    const Eigen::Vector3d base = centre.x() * v + centre.y() * w;
    return Capsule{base + t_low * u, base + t_high * u, std::sqrt(r2)};
}

}  // namespace

double capsule_volume(const Capsule& c) noexcept {
    const double r = c.radius;
    return kPi * r * r * (c.b - c.a).norm() + 4.0 / 3.0 * kPi * r * r * r;
}

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + t * ab)).norm();
}

Capsule bounding_capsule(const std::vector<Eigen::Vector3d>& points) {
    CG_ENFORCE(!points.empty(), "a bounding capsule needs points");
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points) {
        mean += p;
    }
    mean /= static_cast<double>(points.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d& p : points) {
        cov += (p - mean) * (p - mean).transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Eigen::Vector3d axes[4] = {eig.eigenvectors().col(2), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                     Eigen::Vector3d::UnitZ()};
    Capsule best{};
    double best_volume = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& axis : axes) {
        if (!axis.allFinite() || axis.norm() < 0.5) {
            continue;
        }
        const Capsule c = capsule_along(points, axis);
        const double volume = capsule_volume(c);
        if (volume < best_volume) {
            best = c;
            best_volume = volume;
        }
    }
    // Containment as computed: the radius reaches the farthest point.
    for (const Eigen::Vector3d& p : points) {
        best.radius = std::max(best.radius, segment_distance(p, best.a, best.b));
    }
    return best;
}

}  // namespace cellguard::host
