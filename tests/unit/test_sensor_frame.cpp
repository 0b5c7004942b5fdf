// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: validate_sensor_reading refuses every defect of a sensor's
// description, each with its own error code, and accepts the valid one.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "cellguard/grid/sensor_frame.hpp"

using namespace cellguard;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A valid 4 x 3 depth image looking down from 2 m.
struct DepthFixture {
    std::vector<float> depth = std::vector<float>(12U, 1.0F);
    SensorReading reading;
    DepthFixture() {
        reading.kind = SensorDataKind::kDepthImage;
        reading.pose.translation() = Eigen::Vector3d(0.5, 0.5, 2.0);
        reading.pose.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
        reading.intrinsics = PinholeIntrinsics{2.0, 2.0, 1.5, 1.0, 4, 3};
        reading.depth = Span<const float>(depth.data(), depth.size());
        reading.min_range = 0.1F;
        reading.max_range = 5.0F;
    }
};

struct Defect {
    const char* what;
    std::function<void(SensorReading&)> apply;
    ErrorCode expected;
};

}  // namespace

// verifies: SR-FUSE-004
TEST_CASE("sensor frame: a valid depth image and a valid point set are accepted") {
    DepthFixture f;
    CHECK(validate_sensor_reading(f.reading).ok());
    const Eigen::Vector3f points[2] = {Eigen::Vector3f(0.0F, 0.0F, 1.0F), Eigen::Vector3f(0.1F, 0.0F, 1.0F)};
    SensorReading p;
    p.points = Span<const Eigen::Vector3f>(points);
    CHECK(validate_sensor_reading(p).ok());
    p.points = Span<const Eigen::Vector3f>();  // no points this frame is not a malformed description
    CHECK(validate_sensor_reading(p).ok());
}

// verifies: SR-FUSE-004
TEST_CASE("sensor frame: each defect of a depth image's description is refused with its own error") {
    const std::vector<Defect> defects = {
        {"pose translation NaN", [](SensorReading& r) { r.pose.translation().x() = kNaN; }, ErrorCode::kNonFiniteValue},
        {"pose rotation infinite", [](SensorReading& r) { r.pose.linear()(1, 2) = kInf; }, ErrorCode::kNonFiniteValue},
        {"min_range NaN", [](SensorReading& r) { r.min_range = std::nanf(""); }, ErrorCode::kNonFiniteValue},
        {"max_range infinite", [](SensorReading& r) { r.max_range = HUGE_VALF; }, ErrorCode::kNonFiniteValue},
        {"rotation scaled by 1.001", [](SensorReading& r) { r.pose.linear() *= 1.001; }, ErrorCode::kInvalidArgument},
        {"rotation sheared", [](SensorReading& r) { r.pose.linear()(0, 1) += 1e-3; }, ErrorCode::kInvalidArgument},
        {"a mirror (det -1)", [](SensorReading& r) { r.pose.linear() = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal(); },
         ErrorCode::kInvalidArgument},
        {"min_range negative", [](SensorReading& r) { r.min_range = -0.01F; }, ErrorCode::kInvalidArgument},
        {"min_range equal to max_range", [](SensorReading& r) { r.min_range = r.max_range; },
         ErrorCode::kInvalidArgument},
        {"max_range above the limit", [](SensorReading& r) { r.max_range = std::nextafter(kMaxSensorRange, 1000.0F); },
         ErrorCode::kInvalidArgument},
        {"unknown data kind", [](SensorReading& r) { r.kind = static_cast<SensorDataKind>(7); },
         ErrorCode::kInvalidArgument},
        {"fx NaN", [](SensorReading& r) { r.intrinsics.fx = kNaN; }, ErrorCode::kNonFiniteValue},
        {"fy infinite", [](SensorReading& r) { r.intrinsics.fy = kInf; }, ErrorCode::kNonFiniteValue},
        {"cx NaN", [](SensorReading& r) { r.intrinsics.cx = kNaN; }, ErrorCode::kNonFiniteValue},
        {"cy infinite", [](SensorReading& r) { r.intrinsics.cy = -kInf; }, ErrorCode::kNonFiniteValue},
        {"fx zero", [](SensorReading& r) { r.intrinsics.fx = 0.0; }, ErrorCode::kInvalidArgument},
        {"fy negative", [](SensorReading& r) { r.intrinsics.fy = -2.0; }, ErrorCode::kInvalidArgument},
        {"width zero", [](SensorReading& r) { r.intrinsics.width = 0; }, ErrorCode::kInvalidArgument},
        {"height negative", [](SensorReading& r) { r.intrinsics.height = -3; }, ErrorCode::kInvalidArgument},
        {"641 x 480 pixels",
         [](SensorReading& r) {
             r.intrinsics.width = 641;
             r.intrinsics.height = 480;
         },
         ErrorCode::kCapacityExceeded},
        {"one depth value short", [](SensorReading& r) { r.depth = r.depth.subspan(0U, r.depth.size() - 1U); },
         ErrorCode::kMalformedInput},
        {"no depth values", [](SensorReading& r) { r.depth = Span<const float>(); }, ErrorCode::kMalformedInput},
    };
    for (const Defect& d : defects) {
        CAPTURE(d.what);
        DepthFixture f;
        d.apply(f.reading);
        const Status s = validate_sensor_reading(f.reading);
        CHECK_FALSE(s.ok());
        CHECK(s.error() == d.expected);
    }
}

// verifies: SR-FUSE-004
TEST_CASE("sensor frame: 640 x 480 pixels are accepted and a point set over that capacity is refused") {
    DepthFixture f;
    std::vector<float> full(kMaxReadingsPerSensor, 1.0F);
    f.reading.intrinsics = PinholeIntrinsics{500.0, 500.0, 319.5, 239.5, 640, 480};
    f.reading.depth = Span<const float>(full.data(), full.size());
    CHECK(validate_sensor_reading(f.reading).ok());

    std::vector<Eigen::Vector3f> points(kMaxReadingsPerSensor + 1U, Eigen::Vector3f(0.0F, 0.0F, 1.0F));
    SensorReading p;
    p.points = Span<const Eigen::Vector3f>(points.data(), points.size());
    CHECK(validate_sensor_reading(p).error() == ErrorCode::kCapacityExceeded);
    p.points = p.points.subspan(0U, kMaxReadingsPerSensor);
    CHECK(validate_sensor_reading(p).ok());
    p.max_range = -1.0F;  // ranges are checked for point sets too
    CHECK(validate_sensor_reading(p).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-CTRL-008
TEST_CASE(
    "sensor frame: the fingerprint is equal for equal data and changes with any single bit, the order or the count") {
    DepthFixture a;
    DepthFixture b;  // the same values in other memory
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        a.depth[i] = 0.5F + 0.25F * static_cast<float>(i);
        b.depth[i] = a.depth[i];
    }
    const std::uint64_t fa = reading_fingerprint(a.reading);
    CHECK(reading_fingerprint(b.reading) == fa);
    // Every bit of every value, one at a time.
    for (std::size_t i = 0; i < b.depth.size(); ++i) {
        for (unsigned bit = 0; bit < 32U; ++bit) {
            std::uint32_t bits = 0U;
            std::memcpy(&bits, &a.depth[i], sizeof bits);
            bits ^= 1U << bit;
            std::memcpy(&b.depth[i], &bits, sizeof bits);
            CAPTURE(i);
            CAPTURE(bit);
            CHECK(reading_fingerprint(b.reading) != fa);
            b.depth[i] = a.depth[i];
        }
    }
    // Two values swapped, in the same lane (i, i + 4) and across lanes (i, i + 1).
    std::swap(b.depth[1], b.depth[5]);
    CHECK(reading_fingerprint(b.reading) != fa);
    std::swap(b.depth[1], b.depth[5]);
    std::swap(b.depth[6], b.depth[7]);
    CHECK(reading_fingerprint(b.reading) != fa);
    std::swap(b.depth[6], b.depth[7]);
    REQUIRE(reading_fingerprint(b.reading) == fa);
    // One value fewer (the count is part of it), and 0.0 against -0.0 (other bits).
    b.reading.depth = b.reading.depth.subspan(0U, b.depth.size() - 1U);
    CHECK(reading_fingerprint(b.reading) != fa);
    a.depth.assign(12U, 0.0F);
    b.depth.assign(12U, -0.0F);
    CHECK(reading_fingerprint(a.reading) != reading_fingerprint(b.reading));
}

// verifies: SR-CTRL-008
TEST_CASE("sensor frame: a point set's fingerprint follows its coordinates") {
    std::vector<Eigen::Vector3f> points = {{0.0F, 0.0F, 1.0F}, {0.1F, 0.2F, 1.5F}, {-0.3F, 0.0F, 2.0F}};
    SensorReading p;
    p.points = Span<const Eigen::Vector3f>(points.data(), points.size());
    const std::uint64_t f = reading_fingerprint(p);
    CHECK(reading_fingerprint(p) == f);
    points[2].y() = 1e-6F;
    CHECK(reading_fingerprint(p) != f);
    points[2].y() = 0.0F;
    CHECK(reading_fingerprint(p) == f);
    p.points = p.points.subspan(0U, 2U);
    CHECK(reading_fingerprint(p) != f);
}
