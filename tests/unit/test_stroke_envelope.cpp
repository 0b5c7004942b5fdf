// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies stroke_envelope.hpp: the envelope of a capsule over a gripper's stroke contains the capsule in every pose
// (random poses between the sampled ones included), is tight where the motion is a translation, and refuses chains
// it cannot bound.
// Requirements: SR-ROB-108
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "cellguard/host/io/stroke_envelope.hpp"

using namespace cellguard;
using cellguard::host::Capsule;
using cellguard::host::StrokeEnvelope;
using cellguard::host::StrokeRange;
using cellguard::host::StrokeStep;

namespace {

StrokeStep movable(JointType type, const Eigen::Vector3d& xyz, const Eigen::Vector3d& axis, std::size_t variable,
                   double multiplier = 1.0, double offset = 0.0) {
    StrokeStep s;
    s.origin = Eigen::Translation3d(xyz) * Eigen::Quaterniond::Identity();
    s.type = type;
    s.axis = axis.normalized();
    s.variable = variable;
    s.multiplier = multiplier;
    s.offset = offset;
    return s;
}

/// Largest excess of the capsule at @p v over the envelope (<= 0: contained).
double excess(const std::vector<StrokeStep>& chain, const std::vector<double>& v, const Capsule& c,
              const Capsule& envelope) {
    const Eigen::Isometry3d pose = host::stroke_pose(chain, v);
    const double da = host::segment_distance(pose * c.a, envelope.a, envelope.b);
    const double db = host::segment_distance(pose * c.b, envelope.a, envelope.b);
    return std::max(da, db) + c.radius - envelope.radius;
}

}  // namespace

// verifies: SR-ROB-108
TEST_CASE("stroke envelope: a finger sliding 40 mm is enclosed by the capsule along its slide, no thicker") {
    const std::vector<StrokeStep> chain = {movable(JointType::kPrismatic, {0.0, 0.0, 0.06}, {0.0, 1.0, 0.0}, 0U)};
    const std::vector<StrokeRange> ranges = {{0.0, 0.04}};
    const Capsule finger{Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 0.05), 0.01};
    StrokeEnvelope e;
    REQUIRE(host::envelope_capsule(chain, ranges, finger, e).ok());
    CHECK(e.poses == 1025U);
    // A translation: every sampled end lies on the envelope's plane; the margin is half a step (20 um).
    CHECK(e.between == doctest::Approx(0.5 * 0.04 / 1024.0));
    CHECK(e.capsule.radius <= 0.01 + 0.5 * std::hypot(0.04, 0.05) + 1e-4);
    for (int k = 0; k <= 100; ++k) {
        CHECK(excess(chain, {0.0004 * k}, finger, e.capsule) <= 1e-12);
    }
}

// verifies: SR-ROB-108
TEST_CASE("stroke envelope: a finger and its tip on two revolute joints, 20,000 random poses, each enclosed") {
    // Like a Jaco finger: a knuckle 0 .. 1.3 rad, a tip 0 .. 2 rad on a 44 mm phalanx, the tip capsule 40 mm long.
    const std::vector<StrokeStep> chain = {movable(JointType::kRevolute, {0.0, 0.03, 0.1}, {1.0, 0.0, 0.0}, 0U),
                                           movable(JointType::kRevolute, {0.0, 0.044, 0.0}, {1.0, 0.0, 0.0}, 1U)};
    const std::vector<StrokeRange> ranges = {{0.0, 1.3}, {0.0, 2.0}};
    const Capsule tip{Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.04, 0.0), 0.008};
    StrokeEnvelope e;
    REQUIRE(host::envelope_capsule(chain, ranges, tip, e).ok());
    CHECK(e.poses == 129U * 129U);
    CHECK(e.between > 0.0);
    CHECK(e.between < 1e-3);  // 129 samples per joint: under a millimetre of margin
    std::mt19937_64 rng(20261207U);
    std::uniform_real_distribution<double> u0(0.0, 1.3);
    std::uniform_real_distribution<double> u1(0.0, 2.0);
    double worst = -1.0;
    for (int k = 0; k < 20000; ++k) {
        worst = std::max(worst, excess(chain, {u0(rng), u1(rng)}, tip, e.capsule));
    }
    CHECK(worst <= 1e-12);
    // Not absurd: the tip reaches at most 0.03 + 0.044 + 0.04 + radius from the anchor's knuckle axis.
    CHECK(e.capsule.radius < 0.12);
}

// verifies: SR-ROB-108
TEST_CASE("stroke envelope: a mimic finger follows its master with the multiplier and offset, enclosed over it") {
    // Two fingers on one variable, the second mirrored (multiplier -1, offset 0.01).
    const std::vector<StrokeStep> chain = {
        movable(JointType::kPrismatic, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 0U, -1.0, 0.01)};
    const std::vector<StrokeRange> ranges = {{0.0, 0.04}};
    const Capsule finger{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.005};
    StrokeEnvelope e;
    REQUIRE(host::envelope_capsule(chain, ranges, finger, e).ok());
    // The centre runs from y = 0.01 to y = -0.03.
    const double lo = std::min(e.capsule.a.y(), e.capsule.b.y());
    const double hi = std::max(e.capsule.a.y(), e.capsule.b.y());
    CHECK(lo == doctest::Approx(-0.03));
    CHECK(hi == doctest::Approx(0.01));
    CHECK(host::stroke_pose(chain, {0.04}).translation().y() == doctest::Approx(-0.03));
}

// verifies: SR-ROB-108
TEST_CASE("stroke envelope: four variables on one capsule, an unknown variable or a reversed range are refused") {
    const Capsule c{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.01};
    std::vector<StrokeStep> four;
    for (std::size_t k = 0U; k < 4U; ++k) {
        four.push_back(movable(JointType::kRevolute, {0.0, 0.01, 0.0}, {1.0, 0.0, 0.0}, k));
    }
    StrokeEnvelope e;
    const std::vector<StrokeRange> r4(4U, StrokeRange{0.0, 1.0});
    const IoStatus too_many = host::envelope_capsule(four, r4, c, e);
    CHECK(too_many.error() == ErrorCode::kCapacityExceeded);
    const std::vector<StrokeStep> one = {movable(JointType::kRevolute, {0.0, 0.01, 0.0}, {1.0, 0.0, 0.0}, 3U)};
    CHECK(host::envelope_capsule(one, {StrokeRange{0.0, 1.0}}, c, e).error() == ErrorCode::kInvalidArgument);
    const std::vector<StrokeStep> first = {movable(JointType::kRevolute, {0.0, 0.01, 0.0}, {1.0, 0.0, 0.0}, 0U)};
    CHECK(host::envelope_capsule(first, {StrokeRange{1.0, 0.0}}, c, e).error() == ErrorCode::kInvalidArgument);
    CHECK(host::envelope_capsule(first, {StrokeRange{0.0, NAN}}, c, e).error() == ErrorCode::kInvalidArgument);
    CHECK(host::stroke_samples(1U) == 1025U);
    CHECK(host::stroke_samples(2U) == 129U);
    CHECK(host::stroke_samples(3U) == 33U);
}
