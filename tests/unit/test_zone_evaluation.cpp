// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: background subtraction and zone states (CLEAR, INTRUDED, UNSEEN);
// the robot's voxels are neither foreground nor unseen; only the active
// monitoring case's zones are evaluated.
#include <doctest/doctest.h>

#include <vector>

#include "cellguard/safety/zone_evaluation.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {
struct Fixture {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{10, 10, 10}).value();
    std::vector<std::int16_t> lo = std::vector<std::int16_t>(1000, 0);
    std::vector<std::uint8_t> ob = std::vector<std::uint8_t>(1000, 1);     // all observed
    std::vector<std::int16_t> prior = std::vector<std::int16_t>(1000, 0);  // P(fore) = 0.5 everywhere
    std::vector<std::uint32_t> mask = std::vector<std::uint32_t>(1000);
    EvidenceGrid frame;
    CompiledZones zones;
    Fixture() {
        frame = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        ZoneConfig protective;
        protective.box_min = Eigen::Vector3d(0.0, 0.0, 0.0);
        protective.box_max = Eigen::Vector3d(0.5, 0.5, 0.5);
        protective.max_unseen_voxels = 3U;
        ZoneConfig warning = protective;
        warning.kind = ZoneKind::kWarning;
        warning.box_max = Eigen::Vector3d(1.0, 1.0, 1.0);
        const ZoneConfig zs[] = {protective, warning};
        zones = CompiledZones::compile(g, zs, {mask.data(), mask.size()}).value();
    }
    std::size_t at(int x, int y, int z) const { return g.index_of(VoxelCoord{x, y, z}); }
    ZoneEvaluation run() {
        ZoneEvaluation e;
        REQUIRE(evaluate_zones(frame, {prior.data(), prior.size()}, zones, ZoneEvaluationParams{}, e).ok());
        return e;
    }
};
}  // namespace

// verifies: SR-ZONE-006
TEST_CASE("zone evaluation: the default thresholds are t_f = 0.73 and P(fore) >= 0.05") {
    const ZoneEvaluationParams p;
    CHECK(p.foreground_threshold == threshold_log_odds(0.73));
    CHECK(p.accessible_min_prior == log_odds_from_probability(0.05));
}

// verifies: SR-ZONE-005
TEST_CASE("zone evaluation: an empty, fully observed cell leaves every zone CLEAR") {
    Fixture f;
    const ZoneEvaluation e = f.run();
    CHECK(e.count == 2U);
    CHECK(e.zones[0].state == ZoneState::kClear);
    CHECK(e.zones[1].state == ZoneState::kClear);
    CHECK(e.not_clear_mask == 0U);
}

// verifies: SR-ZONE-003
TEST_CASE("zone evaluation: one foreground voxel intrudes every zone that holds it") {
    Fixture f;
    f.lo[f.at(2, 2, 2)] = 400;  // above t_f after adding the prior 0
    const ZoneEvaluation e = f.run();
    CHECK(e.zones[0].state == ZoneState::kIntruded);
    CHECK(e.zones[0].foreground == 1U);
    CHECK(e.zones[1].state == ZoneState::kIntruded);
    CHECK(e.intruded_mask == 0b11U);
}

// verifies: SR-ZONE-003, SR-GRID-002
TEST_CASE("zone evaluation: the prior removes background: a never-foreground voxel cannot intrude") {
    Fixture f;
    f.lo[f.at(2, 2, 2)] = kLogOddsMax;
    f.prior[f.at(2, 2, 2)] = kNeverForeground;
    f.lo[f.at(3, 3, 3)] = 400;
    f.prior[f.at(3, 3, 3)] = -300;  // P(fore) low: 400 - 300 stays below t_f
    const ZoneEvaluation e = f.run();
    CHECK(e.zones[0].state == ZoneState::kClear);
    std::vector<std::int16_t> sub(1000);
    ZoneEvaluation e2;
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), 1000U}, f.zones, ZoneEvaluationParams{}, e2, {sub.data(), 1000U})
                .ok());
    CHECK(sub[f.at(2, 2, 2)] == kNeverForeground);
    CHECK(sub[f.at(3, 3, 3)] == 100);
}

// verifies: SR-ZONE-004
TEST_CASE("zone evaluation: unobserved accessible space beyond the zone's allowance makes it UNSEEN") {
    Fixture f;
    for (int i = 0; i < 3; ++i)
        f.ob[f.at(i, 0, 0)] = 0U;
    CHECK(f.run().zones[0].state == ZoneState::kClear);  // 3 unseen: within the allowance
    f.ob[f.at(3, 0, 0)] = 0U;
    ZoneEvaluation e = f.run();
    CHECK(e.zones[0].state == ZoneState::kUnseen);
    CHECK(e.zones[0].unseen == 4U);
    CHECK(e.zones[1].state == ZoneState::kUnseen);  // the warning zone allows none
    // Unobserved but inaccessible (inside background objects) does not count.
    for (int i = 0; i < 4; ++i)
        f.prior[f.at(i, 0, 0)] = kNeverForeground;
    e = f.run();
    CHECK(e.zones[0].state == ZoneState::kClear);
    CHECK(e.zones[1].state == ZoneState::kClear);
}

// verifies: SR-ZONE-005
TEST_CASE("zone evaluation: INTRUDED outranks UNSEEN") {
    Fixture f;
    for (int i = 0; i < 8; ++i)
        f.ob[f.at(i % 5, 1, 1)] = 0U;
    f.lo[f.at(4, 4, 4)] = 1000;
    CHECK(f.run().zones[0].state == ZoneState::kIntruded);
}

// verifies: SR-ZONE-005
TEST_CASE("zone evaluation: zones of another grid or a short prior are refused") {
    Fixture f;
    ZoneEvaluation e;
    CHECK(evaluate_zones(f.frame, {f.prior.data(), 999U}, f.zones, ZoneEvaluationParams{}, e).error() ==
          ErrorCode::kStorageTooSmall);
    Fixture other;
    other.g = GridGeometry::make(Eigen::Vector3d::Ones(), 0.1, GridDims{10, 10, 10}).value();
    other.frame = EvidenceGrid::make(other.g, {other.lo.data(), 1000U}, {other.ob.data(), 1000U}).value();
    CHECK(evaluate_zones(other.frame, {f.prior.data(), 1000U}, f.zones, ZoneEvaluationParams{}, e).error() ==
          ErrorCode::kGeometryMismatch);
    // The same origin with another voxel size, and the same origin and voxel size with other dimensions.
    Fixture coarse;
    coarse.g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.2, GridDims{10, 10, 10}).value();
    coarse.frame = EvidenceGrid::make(coarse.g, {coarse.lo.data(), 1000U}, {coarse.ob.data(), 1000U}).value();
    CHECK(evaluate_zones(coarse.frame, {f.prior.data(), 1000U}, f.zones, ZoneEvaluationParams{}, e).error() ==
          ErrorCode::kGeometryMismatch);
    Fixture flat;
    flat.g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{10, 10, 9}).value();
    flat.frame = EvidenceGrid::make(flat.g, {flat.lo.data(), 900U}, {flat.ob.data(), 900U}).value();
    CHECK(evaluate_zones(flat.frame, {f.prior.data(), 1000U}, f.zones, ZoneEvaluationParams{}, e).error() ==
          ErrorCode::kGeometryMismatch);
    // An output array for the subtracted grid that is given but too short.
    std::vector<std::int16_t> subtracted(999U);
    CHECK(evaluate_zones(f.frame, {f.prior.data(), 1000U}, f.zones, ZoneEvaluationParams{}, e,
                         {subtracted.data(), subtracted.size()})
              .error() == ErrorCode::kStorageTooSmall);
    subtracted.resize(1000U);
    CHECK(evaluate_zones(f.frame, {f.prior.data(), 1000U}, f.zones, ZoneEvaluationParams{}, e,
                         {subtracted.data(), subtracted.size()})
              .ok());
}

// verifies: SR-ZONE-003, SR-ZONE-004
TEST_CASE("zone evaluation: counts per run of equal zone masks equal counting voxel by voxel") {
    // Eight overlapping zones (boxes of different sizes) and a pseudo-random
    // frame: runs of equal masks are long in some rows and one voxel long
    // where box edges alternate.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{10, 10, 10}).value();
    std::vector<ZoneConfig> zs(8);
    for (std::size_t z = 0; z < zs.size(); ++z) {
        const double a = 0.1 * static_cast<double>(z % 3U);
        const double b = 0.3 + 0.1 * static_cast<double>(z);
        zs[z].box_min = Eigen::Vector3d(a, 0.1 * static_cast<double>(z % 2U), 0.0);
        zs[z].box_max = Eigen::Vector3d(b, 1.0, b);
        zs[z].min_foreground_voxels = 1000U;  // counts only, states do not matter here
        zs[z].max_unseen_voxels = 1000U;
    }
    std::vector<std::uint32_t> mask(g.voxel_count());
    const CompiledZones zones = CompiledZones::compile(g, {zs.data(), zs.size()}, {mask.data(), mask.size()}).value();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    std::vector<std::int16_t> prior(g.voxel_count());
    std::uint32_t x = 12345U;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        x = x * 1664525U + 1013904223U;  // LCG
        lo[i] = (x >> 28U) < 5U ? 600 : -600;
        ob[i] = ((x >> 20U) & 3U) == 0U ? 0U : 1U;
        prior[i] = ((x >> 16U) & 7U) == 0U ? kNeverForeground : 0;
    }
    const EvidenceGrid frame = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
    const ZoneEvaluationParams params;
    ZoneEvaluation e;
    REQUIRE(evaluate_zones(frame, {prior.data(), prior.size()}, zones, params, e).ok());
    for (std::size_t z = 0; z < zs.size(); ++z) {
        CAPTURE(z);
        std::uint32_t fg = 0;
        std::uint32_t unseen = 0;
        for (std::size_t i = 0; i < g.voxel_count(); ++i) {
            if ((mask[i] & (1U << z)) == 0U) {
                continue;
            }
            fg += add_saturating(lo[i], prior[i]) >= params.foreground_threshold ? 1U : 0U;
            unseen += (ob[i] == 0U && prior[i] != kNeverForeground && prior[i] >= params.accessible_min_prior) ? 1U
                                                                                                               : 0U;
        }
        CHECK(fg > 0U);
        CHECK(unseen > 0U);
        CHECK(e.zones[z].foreground == fg);
        CHECK(e.zones[z].unseen == unseen);
    }
}

// verifies: SR-ROB-201
TEST_CASE("zone evaluation: the robot's voxels are neither foreground nor unseen, and are counted per zone as robot") {
    Fixture f;
    std::vector<std::uint8_t> robot(1000U, 0U);
    // The robot occupies a column through the protective zone: seen as
    // occupied at (2, 2, z), unobserved behind itself at (3, 2, z).
    for (int z = 0; z < 5; ++z) {
        f.lo[f.at(2, 2, z)] = 1000;
        f.ob[f.at(3, 2, z)] = 0U;
        robot[f.at(2, 2, z)] = 1U;
        robot[f.at(3, 2, z)] = 1U;
    }
    // Without the mask the robot intrudes and hides space.
    const ZoneEvaluation without = f.run();
    CHECK(without.zones[0].state == ZoneState::kIntruded);
    CHECK(without.zones[0].foreground == 5U);
    CHECK(without.zones[0].unseen == 5U);
    CHECK(without.zones[0].robot == 0U);
    // With it: every zone CLEAR, its voxels counted as the robot's only.
    ZoneEvaluationScope scope;
    scope.robot_mask = Span<const std::uint8_t>(robot.data(), robot.size());
    ZoneEvaluation e;
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, e).ok());
    CHECK(e.zones[0].state == ZoneState::kClear);
    CHECK(e.zones[0].foreground == 0U);
    CHECK(e.zones[0].unseen == 0U);
    CHECK(e.zones[0].robot == 10U);
    CHECK(e.zones[1].state == ZoneState::kClear);
    CHECK(e.zones[1].robot == 10U);
    CHECK(e.not_clear_mask == 0U);
    // A person next to the robot is still foreground.
    f.lo[f.at(1, 2, 2)] = 1000;
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, e).ok());
    CHECK(e.zones[0].state == ZoneState::kIntruded);
    CHECK(e.zones[0].foreground == 1U);
    // Any nonzero byte is the robot's; an empty mask is no robot.
    robot[f.at(1, 2, 2)] = 0xFFU;
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, e).ok());
    CHECK(e.zones[0].state == ZoneState::kClear);
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{},
                           ZoneEvaluationScope{}, e)
                .ok());
    CHECK(e.zones[0].foreground == 6U);
}

// verifies: SR-ROB-201
TEST_CASE("zone evaluation: a robot mask shorter than the grid is refused") {
    Fixture f;
    std::vector<std::uint8_t> robot(999U, 0U);
    ZoneEvaluationScope scope;
    scope.robot_mask = Span<const std::uint8_t>(robot.data(), robot.size());
    ZoneEvaluation e;
    CHECK(
        evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, e).error() ==
        ErrorCode::kStorageTooSmall);
}

// verifies: SR-CASE-005
TEST_CASE("zone evaluation: zones outside the active case are not evaluated: CLEAR, no counts, in no mask") {
    Fixture f;
    f.lo[f.at(2, 2, 2)] = 1000;  // in both zones
    f.ob[f.at(8, 8, 8)] = 0U;    // in the warning zone only
    ZoneEvaluationScope scope;
    scope.active_zones = 0b10U;  // the warning zone only
    ZoneEvaluation e;
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, e).ok());
    CHECK(e.active_mask == 0b10U);
    CHECK(e.zones[0].state == ZoneState::kClear);
    CHECK(e.zones[0].foreground == 0U);
    CHECK(e.zones[1].state == ZoneState::kIntruded);
    CHECK(e.zones[1].foreground == 1U);
    CHECK(e.zones[1].unseen == 1U);
    CHECK(e.intruded_mask == 0b10U);
    CHECK(e.not_clear_mask == 0b10U);
    // Bits beyond the zone count are ignored; the default scope is every zone.
    scope.active_zones = 0xFFFFFFFCU | 0b01U;
    REQUIRE(evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, e).ok());
    CHECK(e.active_mask == 0b01U);
    CHECK(e.intruded_mask == 0b01U);
    CHECK(f.run().active_mask == 0b11U);
    CHECK(f.run().intruded_mask == 0b11U);
}

// verifies: SR-GEN-004
TEST_CASE("zone evaluation: every zone state has its own name, and a value outside the enumeration is named INVALID") {
    test::check_enum_names<ZoneState>(4U, "INVALID");
}

// verifies: SR-ZONE-003, SR-CASE-005
TEST_CASE("zone evaluation: with 32 zones the last zone's bit is evaluated and reported like any other") {
    Fixture f;
    std::vector<ZoneConfig> zs(kMaxZones);
    for (std::size_t z = 0U; z < kMaxZones; ++z) {  // zones 0..30 at x 0..0.3, zone 31 at x 0.5..0.8
        zs[z].box_min = Eigen::Vector3d(z == kMaxZones - 1U ? 0.5 : 0.0, 0.0, 0.0);
        zs[z].box_max = zs[z].box_min + Eigen::Vector3d(0.3, 0.3, 0.3);
    }
    f.zones = CompiledZones::compile(f.g, {zs.data(), zs.size()}, {f.mask.data(), f.mask.size()}).value();
    f.lo[f.at(6, 1, 1)] = 400;  // foreground in zone 31 only
    const ZoneEvaluation e = f.run();
    CHECK(e.count == kMaxZones);
    CHECK(e.zones[kMaxZones - 1U].state == ZoneState::kIntruded);
    CHECK(e.zones[0].state == ZoneState::kClear);
    CHECK(e.intruded_mask == 0x80000000U);
    ZoneEvaluation only_zone_0;
    ZoneEvaluationScope scope;
    scope.active_zones = 1U;
    REQUIRE(
        evaluate_zones(f.frame, {f.prior.data(), f.prior.size()}, f.zones, ZoneEvaluationParams{}, scope, only_zone_0)
            .ok());
    CHECK(only_zone_0.intruded_mask == 0U);
    CHECK(only_zone_0.zones[kMaxZones - 1U].state == ZoneState::kClear);
}
