// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: zone configuration checks and compilation into voxel sets.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cellguard/safety/zones.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {
GridGeometry grid10() {  // 10 x 10 x 10 voxels of 0.1 m from the origin
    return GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{10, 10, 10}).value();
}
ZoneConfig box(double x0, double y0, double z0, double x1, double y1, double z1) {
    ZoneConfig z;
    z.shape = ZoneShape::kBox;
    z.box_min = Eigen::Vector3d(x0, y0, z0);
    z.box_max = Eigen::Vector3d(x1, y1, z1);
    return z;
}
ZoneConfig prism(std::initializer_list<PolygonVertex> pts, double z0, double z1) {
    ZoneConfig z;
    z.shape = ZoneShape::kPrism;
    for (const auto& p : pts)
        z.polygon[z.polygon_size++] = p;
    z.z_min = z0;
    z.z_max = z1;
    return z;
}
}  // namespace

// verifies: SR-ZONE-001
TEST_CASE("zones: a box holds exactly the voxels whose centres it contains") {
    std::vector<std::uint32_t> mask(1000);
    const ZoneConfig zs[] = {box(0.0, 0.0, 0.0, 0.3, 0.2, 0.1)};
    const CompiledZones c = CompiledZones::compile(grid10(), zs, {mask.data(), mask.size()}).value();
    CHECK(c.size() == 1U);
    CHECK(c.voxel_count(0) == 3U * 2U * 1U);
    CHECK(mask[0] == 1U);
    CHECK(mask[3] == 0U);  // x = 3: centre 0.35 outside
    CHECK(c.total_memberships() == 6U);
}

// verifies: SR-ZONE-001
TEST_CASE("zones: a prism over a convex polygon is compiled in either winding, one bit per zone") {
    std::vector<std::uint32_t> mask(1000);
    const ZoneConfig zs[] = {
        prism({{0.0, 0.0}, {0.99, 0.0}, {0.0, 0.99}}, 0.0, 0.5),  // counter-clockwise triangle
        prism({{0.0, 0.0}, {0.0, 0.99}, {0.99, 0.0}}, 0.0, 0.5),  // the same, clockwise
        box(0.5, 0.5, 0.5, 1.0, 1.0, 1.0),
    };
    const CompiledZones c = CompiledZones::compile(grid10(), zs, {mask.data(), mask.size()}).value();
    CHECK(c.voxel_count(0) == c.voxel_count(1));
    // centres (x+0.5)/10 + (y+0.5)/10 <= 0.99: x + y <= 8 gives 45 columns (no centre on the edge), 5 layers.
    CHECK(c.voxel_count(0) == 45U * 5U);
    CHECK(c.voxel_count(2) == 125U);
    const std::size_t corner = grid10().index_of(VoxelCoord{0, 0, 0});
    CHECK(mask[corner] == 0b011U);
    const std::size_t top = grid10().index_of(VoxelCoord{9, 9, 9});
    CHECK(mask[top] == 0b100U);
}

// verifies: SR-ZONE-002
TEST_CASE("zones: invalid zones are rejected with the zone's index and a reason") {
    std::vector<std::uint32_t> mask(1000);
    const auto rejected = [&](const ZoneConfig& bad, ErrorCode code) {
        const ZoneConfig zs[] = {box(0, 0, 0, 0.5, 0.5, 0.5), bad};
        const auto r = CompiledZones::compile(grid10(), zs, {mask.data(), mask.size()});
        CHECK(r.error().code == code);
        CHECK(r.error().zone == 1U);
        CHECK(r.error().reason[0] != '\0');
        return !r.ok();
    };
    CHECK(rejected(box(0, 0, 0, 0.5, 0.5, 1.5), ErrorCode::kOutOfGrid));
    CHECK(rejected(box(0.5, 0, 0, 0.5, 0.5, 0.5), ErrorCode::kInvalidArgument));  // empty
    CHECK(rejected(box(0.6, 0, 0, 0.5, 0.5, 0.5), ErrorCode::kInvalidArgument));  // inverted
    CHECK(rejected(box(0, 0, std::numeric_limits<double>::quiet_NaN(), 0.5, 0.5, 0.5), ErrorCode::kNonFiniteValue));
    CHECK(rejected(box(0.01, 0.01, 0.01, 0.02, 0.02, 0.02), ErrorCode::kInvalidArgument));    // holds no voxel centre
    CHECK(rejected(prism({{0, 0}, {1, 0}}, 0, 0.5), ErrorCode::kInvalidArgument));            // too few vertices
    CHECK(rejected(prism({{0, 0}, {0.5, 0}, {1, 0}}, 0, 0.5), ErrorCode::kInvalidArgument));  // collinear
    CHECK(rejected(prism({{0, 0}, {1, 0}, {0.2, 0.2}, {0, 1}}, 0, 0.5), ErrorCode::kInvalidArgument));  // not convex
    CHECK(rejected(prism({{0, 0}, {1, 0}, {0, 1}}, 0.5, 0.5), ErrorCode::kInvalidArgument));            // no height
    CHECK(rejected(prism({{0, 0}, {1.5, 0}, {0, 1}}, 0, 0.5), ErrorCode::kOutOfGrid));
    // A pentagram turns the same way at every vertex but is not convex.
    CHECK(rejected(prism({{0.5, 1.0}, {0.2, 0.0}, {1.0, 0.65}, {0.0, 0.65}, {0.8, 0.0}}, 0, 0.5),
                   ErrorCode::kInvalidArgument));
    // A sliver: by rounding every turn is counter-clockwise (each cross product 2.8e-17), but the shoelace
    // sum of its area is exactly 0 and its exterior angles add up to one turn; the area check refuses it.
    CHECK(rejected(prism({{0.2, 0.2}, {0.8, 0.8}, {0.4, std::nextafter(0.4, 1.0)}}, 0, 0.5),
                   ErrorCode::kInvalidArgument));
    ZoneConfig zero_threshold = box(0, 0, 0, 0.5, 0.5, 0.5);
    zero_threshold.min_foreground_voxels = 0U;
    CHECK(rejected(zero_threshold, ErrorCode::kInvalidArgument));
}

// verifies: SR-ZONE-002
TEST_CASE(
    "zones: every coordinate of a zone is checked on its own: non-finite, outside each face, unknown kind or shape") {
    std::vector<std::uint32_t> mask(1000);
    const auto refused = [&](const ZoneConfig& bad, ErrorCode code) {
        const ZoneConfig zs[] = {bad};
        const auto r = CompiledZones::compile(grid10(), zs, {mask.data(), mask.size()});
        CHECK(r.error().zone == 0U);
        CHECK(r.error().reason[0] != '\0');
        return r.error().code == code;
    };
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    // Boxes: either corner non-finite; each face outside the grid [0, 1]^3.
    CHECK(refused(box(0, 0, 0, kInf, 0.5, 0.5), ErrorCode::kNonFiniteValue));
    CHECK(refused(box(-kInf, 0, 0, 0.5, 0.5, 0.5), ErrorCode::kNonFiniteValue));
    CHECK(refused(box(-0.1, 0, 0, 0.5, 0.5, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(box(0, -0.1, 0, 0.5, 0.5, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(box(0, 0, -0.1, 0.5, 0.5, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(box(0, 0, 0, 1.1, 0.5, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(box(0, 0, 0, 0.5, 1.1, 0.5), ErrorCode::kOutOfGrid));
    // Prisms: the height range non-finite at either end, or outside the grid at either end.
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, 1}}, kNaN, 0.5), ErrorCode::kNonFiniteValue));
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, 1}}, 0, kInf), ErrorCode::kNonFiniteValue));
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, 1}}, -0.1, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, 1}}, 0.5, 1.1), ErrorCode::kOutOfGrid));
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, 1}}, 0.5, 0.4), ErrorCode::kInvalidArgument));  // inverted
    // A vertex non-finite in x or in y, or outside the grid on each side.
    CHECK(refused(prism({{0, 0}, {kNaN, 0}, {0, 1}}, 0, 0.5), ErrorCode::kNonFiniteValue));
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, -kInf}}, 0, 0.5), ErrorCode::kNonFiniteValue));
    CHECK(refused(prism({{-0.1, 0}, {1, 0}, {0, 1}}, 0, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(prism({{0, -0.1}, {1, 0}, {0, 1}}, 0, 0.5), ErrorCode::kOutOfGrid));
    CHECK(refused(prism({{0, 0}, {1, 0}, {0, 1.1}}, 0, 0.5), ErrorCode::kOutOfGrid));
    // More than 16 vertices; a kind or shape value from a corrupted configuration.
    ZoneConfig many_vertices = prism({{0, 0}, {1, 0}, {0, 1}}, 0, 0.5);
    many_vertices.polygon_size = kMaxPolygonVertices + 1U;
    CHECK(refused(many_vertices, ErrorCode::kInvalidArgument));
    ZoneConfig bad_kind = box(0, 0, 0, 0.5, 0.5, 0.5);
    bad_kind.kind = static_cast<ZoneKind>(9);
    CHECK(refused(bad_kind, ErrorCode::kInvalidArgument));
    ZoneConfig bad_shape = box(0, 0, 0, 0.5, 0.5, 0.5);
    bad_shape.shape = static_cast<ZoneShape>(9);
    CHECK(refused(bad_shape, ErrorCode::kInvalidArgument));
}

// verifies: SR-ZONE-002
TEST_CASE("zones: more than 32 zones or too little storage is refused") {
    std::vector<std::uint32_t> mask(1000);
    std::vector<ZoneConfig> many(kMaxZones + 1U, box(0, 0, 0, 0.5, 0.5, 0.5));
    CHECK(CompiledZones::compile(grid10(), {many.data(), many.size()}, {mask.data(), mask.size()}).error().code ==
          ErrorCode::kCapacityExceeded);
    CHECK(CompiledZones::compile(grid10(), {many.data(), kMaxZones}, {mask.data(), mask.size()}).ok());
    CHECK(CompiledZones::compile(grid10(), {many.data(), 1U}, {mask.data(), 999U}).error().code ==
          ErrorCode::kStorageTooSmall);
}

// verifies: SR-CTRL-010
TEST_CASE("zones: the settings CRC changes with a zone's kind, thresholds or count, not with its geometry alone") {
    std::vector<std::uint32_t> mask(1000);
    ZoneConfig a = box(0, 0, 0, 0.5, 0.5, 0.5);
    const ZoneConfig one[] = {a};
    const std::uint32_t base = CompiledZones::compile(grid10(), one, {mask.data(), mask.size()}).value().settings_crc();
    CHECK(CompiledZones::compile(grid10(), one, {mask.data(), mask.size()}).value().settings_crc() == base);
    const auto crc_with = [&](const ZoneConfig& z) {
        const ZoneConfig zs[] = {z};
        return CompiledZones::compile(grid10(), zs, {mask.data(), mask.size()}).value().settings_crc();
    };
    ZoneConfig warning = a;
    warning.kind = ZoneKind::kWarning;
    CHECK(crc_with(warning) != base);
    ZoneConfig fg = a;
    fg.min_foreground_voxels = 2U;
    CHECK(crc_with(fg) != base);
    ZoneConfig unseen = a;
    unseen.max_unseen_voxels = 1U;
    CHECK(crc_with(unseen) != base);
    CHECK(crc_with(box(0, 0, 0, 0.5, 0.5, 0.4)) != base);  // another voxel count
    // The same voxels from a slightly different box: the same settings (the mask is checked on its own).
    CHECK(crc_with(box(0, 0, 0, 0.5, 0.5, 0.49)) == base);
    const ZoneConfig two[] = {a, a};
    CHECK(CompiledZones::compile(grid10(), two, {mask.data(), mask.size()}).value().settings_crc() != base);
}

// verifies: SR-ZONE-001
TEST_CASE("zones: zone_contains is false outside a prism's height and for a prism of fewer than 3 vertices") {
    const ZoneConfig p = prism({{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}}, 0.2, 0.8);
    CHECK(zone_contains(p, Eigen::Vector3d(0.5, 0.5, 0.5)));
    CHECK(zone_contains(p, Eigen::Vector3d(0.5, 0.5, 0.2)));  // the bounds are inclusive
    CHECK(zone_contains(p, Eigen::Vector3d(0.5, 0.5, 0.8)));
    CHECK_FALSE(zone_contains(p, Eigen::Vector3d(0.5, 0.5, 0.1)));
    CHECK_FALSE(zone_contains(p, Eigen::Vector3d(0.5, 0.5, 0.9)));
    CHECK_FALSE(zone_contains(p, Eigen::Vector3d(1.5, 0.5, 0.5)));
    const ZoneConfig segment = prism({{0.0, 0.0}, {1.0, 1.0}}, 0.0, 1.0);  // not validated: a caller's raw config
    CHECK_FALSE(zone_contains(segment, Eigen::Vector3d(0.5, 0.5, 0.5)));
    const ZoneConfig b = box(0.0, 0.0, 0.0, 1.0, 1.0, 1.0);
    CHECK(zone_contains(b, Eigen::Vector3d(1.0, 0.0, 0.5)));
    CHECK_FALSE(zone_contains(b, Eigen::Vector3d(1.0, -0.01, 0.5)));
}

// verifies: SR-ZONE-001, SR-GEN-003
TEST_CASE("zones: the configuration or voxel count of a zone beyond the compiled ones is a contract violation") {
    std::vector<std::uint32_t> mask(1000);
    const ZoneConfig zs[] = {box(0.0, 0.0, 0.0, 0.3, 0.2, 0.1)};
    const CompiledZones c = CompiledZones::compile(grid10(), zs, {mask.data(), mask.size()}).value();
    CHECK_FALSE(test::violates_contract([&] { (void)c.config(0U); }));
    CHECK_FALSE(test::violates_contract([&] { (void)c.voxel_count(0U); }));
    CHECK(test::violates_contract([&] { (void)c.config(1U); }));
    CHECK(test::violates_contract([&] { (void)c.voxel_count(1U); }));
}

// verifies: SR-ZONE-001
TEST_CASE("zones: a grid without voxels is refused, whatever the storage") {
    std::vector<std::uint32_t> mask(1000);
    const ZoneConfig z = box(0, 0, 0, 0.5, 0.5, 0.5);
    const GridGeometry empty;  // not made: no voxels
    REQUIRE(empty.voxel_count() == 0U);
    const auto r = CompiledZones::compile(empty, {&z, 1U}, {mask.data(), mask.size()});
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kStorageTooSmall);
    CHECK(CompiledZones::compile(grid10(), {&z, 1U}, {mask.data(), mask.size()}).ok());
}
