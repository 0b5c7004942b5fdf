// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: monitoring cases: the default case 0 monitors every zone, a
// commissioned case names at least one existing zone, at most sixteen cases,
// and the set's CRC changes with any case.
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "cellguard/safety/monitoring_cases.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {
struct Zones {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{4, 4, 4}).value();
    std::vector<std::uint32_t> mask = std::vector<std::uint32_t>(64);
    CompiledZones zones;
    explicit Zones(std::size_t count = 3U) {
        std::vector<ZoneConfig> zs(count);
        for (ZoneConfig& z : zs) {
            z.box_max = Eigen::Vector3d(0.2, 0.2, 0.2);
        }
        zones = CompiledZones::compile(g, {zs.data(), zs.size()}, {mask.data(), mask.size()}).value();
    }
};
}  // namespace

// verifies: SR-CASE-001
TEST_CASE("monitoring cases: without cases there is one case 0 that monitors every zone") {
    const Zones z;
    const MonitoringCases d = MonitoringCases::all_zones(z.zones);
    CHECK(d.count() == 1U);
    CHECK(d.contains(0U));
    CHECK_FALSE(d.contains(1U));
    CHECK(d.zones_of(0U) == 0b111U);
    CHECK(d.fits(z.zones));
    const Result<MonitoringCases, CaseError> from_empty = MonitoringCases::make(z.zones, {});
    REQUIRE(from_empty.ok());
    CHECK(from_empty.value().count() == 1U);
    CHECK(from_empty.value().zones_of(0U) == 0b111U);
    CHECK(from_empty.value().settings_crc() == d.settings_crc());
    // Edge counts: no zones at all (an empty mask) and all 32 zones.
    const Zones none(0U);
    CHECK(MonitoringCases::all_zones(none.zones).zones_of(0U) == 0U);
    const Zones full(kMaxZones);
    CHECK(MonitoringCases::all_zones(full.zones).zones_of(0U) == 0xFFFFFFFFU);
    CHECK(all_zone_bits(kMaxZones) == 0xFFFFFFFFU);
    CHECK(all_zone_bits(5U) == 0x1FU);
}

// verifies: SR-CASE-002
TEST_CASE("monitoring cases: each commissioned case keeps its zones under its number") {
    const Zones z;
    const std::uint32_t masks[] = {0b001U, 0b110U, 0b111U, 0b110U};  // two numbers may name the same zones
    const Result<MonitoringCases, CaseError> c = MonitoringCases::make(z.zones, masks);
    REQUIRE(c.ok());
    CHECK(c.value().count() == 4U);
    CHECK(c.value().zone_count() == 3U);
    for (std::size_t k = 0U; k < 4U; ++k) {
        CHECK(c.value().zones_of(k) == masks[k]);
    }
    CHECK(c.value().contains(3U));
    CHECK_FALSE(c.value().contains(4U));
    CHECK_FALSE(c.value().contains(255U));
    CHECK(c.value().fits(z.zones));
}

// verifies: SR-CASE-003
TEST_CASE("monitoring cases: a case naming no zone, or a zone beyond the configured ones, is refused with its number") {
    const Zones z;
    const std::uint32_t empty_case[] = {0b001U, 0U};
    const Result<MonitoringCases, CaseError> e = MonitoringCases::make(z.zones, empty_case);
    REQUIRE_FALSE(e.ok());
    CHECK(e.error().code == ErrorCode::kInvalidArgument);
    CHECK(e.error().case_number == 1U);
    CHECK(std::strstr(e.error().reason, "no zone") != nullptr);
    const std::uint32_t beyond[] = {0b001U, 0b011U, 0b1000U};  // zone 3 of a set of three
    const Result<MonitoringCases, CaseError> b = MonitoringCases::make(z.zones, beyond);
    REQUIRE_FALSE(b.ok());
    CHECK(b.error().code == ErrorCode::kInvalidArgument);
    CHECK(b.error().case_number == 2U);
    const std::uint32_t high_bit[] = {0x80000000U | 0b1U};
    CHECK_FALSE(MonitoringCases::make(z.zones, high_bit).ok());
}

// verifies: SR-CASE-003
TEST_CASE("monitoring cases: sixteen cases are accepted, seventeen are refused") {
    const Zones z;
    std::vector<std::uint32_t> masks(kMaxMonitoringCases, 0b1U);
    const Result<MonitoringCases, CaseError> sixteen = MonitoringCases::make(z.zones, {masks.data(), masks.size()});
    REQUIRE(sixteen.ok());
    CHECK(sixteen.value().count() == 16U);
    CHECK(sixteen.value().contains(15U));
    masks.push_back(0b1U);
    const Result<MonitoringCases, CaseError> seventeen = MonitoringCases::make(z.zones, {masks.data(), masks.size()});
    REQUIRE_FALSE(seventeen.ok());
    CHECK(seventeen.error().code == ErrorCode::kCapacityExceeded);
}

// verifies: SR-CASE-004
TEST_CASE("monitoring cases: the settings CRC changes with any case's zones, the case count and the zone count") {
    const Zones z;
    const std::uint32_t a[] = {0b001U, 0b110U};
    const std::uint32_t b[] = {0b001U, 0b100U};
    const std::uint32_t c[] = {0b001U, 0b110U, 0b110U};
    const std::uint32_t crc_a = MonitoringCases::make(z.zones, a).value().settings_crc();
    CHECK(crc_a == MonitoringCases::make(z.zones, a).value().settings_crc());
    CHECK(crc_a != MonitoringCases::make(z.zones, b).value().settings_crc());
    CHECK(crc_a != MonitoringCases::make(z.zones, c).value().settings_crc());
    const Zones four(4U);
    CHECK(crc_a != MonitoringCases::make(four.zones, a).value().settings_crc());
    // A set made for other zones does not fit these.
    CHECK_FALSE(MonitoringCases::make(four.zones, a).value().fits(z.zones));
    const std::uint32_t zone3[] = {0b1000U};
    CHECK_FALSE(MonitoringCases::make(four.zones, zone3).value().fits(z.zones));
    CHECK_FALSE(MonitoringCases{}.fits(z.zones));  // the placeholder has no case
}

// verifies: SR-CASE-002, SR-GEN-003
TEST_CASE("monitoring cases: the zones of a case number that does not exist are a contract violation") {
    const Zones z;
    const std::uint32_t masks[] = {0b001U, 0b110U};
    const MonitoringCases c = MonitoringCases::make(z.zones, masks).value();
    CHECK_FALSE(test::violates_contract([&] { (void)c.zones_of(1U); }));
    CHECK(test::violates_contract([&] { (void)c.zones_of(2U); }));
    CHECK(test::violates_contract([&] { (void)c.zones_of(kMaxMonitoringCases); }));
}

// verifies: SR-CASE-002
TEST_CASE("monitoring cases: with 32 zones every bit names a zone, and case 0 monitors all 32") {
    const Zones z(kMaxZones);
    const MonitoringCases d = MonitoringCases::all_zones(z.zones);
    CHECK(d.zones_of(0U) == 0xFFFFFFFFU);
    CHECK(d.fits(z.zones));
    const std::uint32_t masks[] = {0x80000000U, 0xFFFFFFFFU};
    const Result<MonitoringCases, CaseError> c = MonitoringCases::make(z.zones, masks);
    REQUIRE(c.ok());
    CHECK(c.value().zones_of(0U) == 0x80000000U);
    CHECK(c.value().zones_of(1U) == 0xFFFFFFFFU);
    CHECK(c.value().fits(z.zones));
}

// verifies: SR-CASE-004
TEST_CASE("monitoring cases: a stored case whose mask gained a zone beyond the configured ones no longer fits") {
    const Zones z;
    const std::uint32_t masks[] = {0b011U};
    MonitoringCases c = MonitoringCases::make(z.zones, masks).value();
    REQUIRE(c.fits(z.zones));
    // A bit flip in memory: case 0's mask (the object's first word) now names zone 7 too.
    std::uint32_t first = 0U;
    std::memcpy(&first, &c, sizeof(first));
    REQUIRE(first == 0b011U);
    first |= 0x80U;
    std::memcpy(static_cast<void*>(&c), &first, sizeof(first));  // trivially copyable: a plain byte write
    CHECK(c.zones_of(0U) == 0x83U);
    CHECK_FALSE(c.fits(z.zones));
}
