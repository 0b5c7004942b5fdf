// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The simulator's test pieces (apps/host sim/test_piece.hpp): cylinders with
// flat ends and spheres at any pose, their ray intersection against closed
// forms and against the solid's own inside test.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

#include "cellguard/host/sim/noise.hpp"
#include "cellguard/host/sim/test_piece.hpp"

using namespace cellguard;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

sim::TestPiece rod(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double diameter, double length) {
    sim::TestPiece p;
    p.shape = sim::PieceShape::kCylinder;
    p.centre = centre;
    p.axis = axis.normalized();
    p.diameter = diameter;
    p.length = length;
    return p;
}

}  // namespace

// verifies: SR-EVAL-004
TEST_CASE("test pieces: a ray meets a rod's side, its flat end, or misses beyond the end, as the closed forms say") {
    const sim::TestPiece r = rod({0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}, 0.04, 0.3);  // vertical, 40 mm x 300 mm
    // Side on, through the axis: the distance less the radius.
    CHECK(sim::intersect_piece(r, {-2.0, 0.0, 1.0}, {1.0, 0.0, 0.0}) == doctest::Approx(1.98).epsilon(1e-12));
    // End on, along the axis from above: the distance to the top face.
    CHECK(sim::intersect_piece(r, {0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}) == doctest::Approx(1.85).epsilon(1e-12));
    // Down onto the top face off the axis (inside the radius): the face, not the side.
    CHECK(sim::intersect_piece(r, {0.015, 0.0, 3.0}, {0.0, 0.0, -1.0}) == doctest::Approx(1.85).epsilon(1e-12));
    // Just beyond the end or just outside the radius: a miss.
    CHECK(sim::intersect_piece(r, {-2.0, 0.0, 1.16}, {1.0, 0.0, 0.0}) == kInf);
    CHECK(sim::intersect_piece(r, {0.021, 0.0, 3.0}, {0.0, 0.0, -1.0}) == kInf);
    // Behind the origin: a miss; from inside: 0.
    CHECK(sim::intersect_piece(r, {2.0, 0.0, 1.0}, {1.0, 0.0, 0.0}) == kInf);
    CHECK(sim::intersect_piece(r, {0.0, 0.0, 1.1}, {1.0, 0.0, 0.0}) == 0.0);
    // A sphere: the distance to the centre less the radius.
    sim::TestPiece ball;
    ball.shape = sim::PieceShape::kSphere;
    ball.centre = {1.0, 1.0, 1.0};
    ball.diameter = 0.1;
    CHECK(sim::intersect_piece(ball, {1.0, 1.0, 3.0}, {0.0, 0.0, -1.0}) == doctest::Approx(1.95).epsilon(1e-12));
    CHECK(sim::intersect_piece(ball, {1.06, 1.0, 3.0}, {0.0, 0.0, -1.0}) == kInf);
    CHECK(std::string(sim::to_string(sim::PieceShape::kSphere)) == "sphere");
    CHECK(std::string(sim::to_string(sim::PieceShape::kCylinder)) == "cylinder");
}

// verifies: SR-EVAL-004
TEST_CASE("test pieces: at random poses every hit lies on the surface, and the bounds hold the piece") {
    sim::Rng rng(17U);
    for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d axis(rng.normal(), rng.normal(), rng.normal());
        sim::TestPiece p = rod({rng.uniform(), rng.uniform(), 1.0 + rng.uniform()}, axis, 0.02 + 0.2 * rng.uniform(),
                               0.3 + 0.2 * rng.uniform());
        if (i % 2 == 1) {
            p.shape = sim::PieceShape::kSphere;
        }
        const Eigen::Vector3d origin(-2.0, -2.0, 2.4);
        int hits = 0;
        for (int j = 0; j < 200; ++j) {
            // Rays aimed at random points near the piece.
            const Eigen::Vector3d aim = p.centre + p.bounding_radius() *
                                                       Eigen::Vector3d(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                                                       rng.uniform() - 0.5) *
                                                       2.0;
            const Eigen::Vector3d dir = (aim - origin).normalized();
            const double t = sim::intersect_piece(p, origin, dir);
            if (t == kInf) {
                // A miss: no point of the ray (in 1 mm steps) is inside.
                bool inside = false;
                for (int step = 0; step < 6000 && !inside; ++step) {
                    inside = sim::piece_contains(p, origin + 0.001 * step * dir);
                }
                CHECK_FALSE(inside);
                continue;
            }
            ++hits;
            CHECK(sim::piece_contains(p, origin + (t + 1e-6) * dir));
            CHECK_FALSE(sim::piece_contains(p, origin + (t - 1e-6) * dir));
            CHECK((origin + t * dir - p.centre).norm() <= p.bounding_radius() + 1e-9);
            CHECK((origin + t * dir).z() >= p.lowest_z() - 1e-9);
        }
        CHECK(hits > 0);
    }
}

// verifies: SR-EVAL-004
TEST_CASE("test pieces: the lowest point of a lying, a standing and a tilted rod") {
    CHECK(rod({0.0, 0.0, 0.02}, {1.0, 0.0, 0.0}, 0.04, 0.3).lowest_z() == doctest::Approx(0.0));
    CHECK(rod({0.0, 0.0, 0.5}, {0.0, 0.0, 1.0}, 0.04, 0.3).lowest_z() == doctest::Approx(0.35));
    // Tilted 45 degrees: the end's centre 0.15 / sqrt(2) lower, its rim 0.02 / sqrt(2) lower still.
    const double s = std::sqrt(0.5);
    CHECK(rod({0.0, 0.0, 1.0}, {1.0, 0.0, 1.0}, 0.04, 0.3).lowest_z() == doctest::Approx(1.0 - 0.15 * s - 0.02 * s));
    CHECK(rod({0.0, 0.0, 1.0}, {1.0, 0.0, 1.0}, 0.04, 0.3).bounding_radius() ==
          doctest::Approx(std::sqrt(0.02 * 0.02 + 0.15 * 0.15)));
}
