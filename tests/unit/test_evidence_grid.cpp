// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: evidence grid storage, observed flags, background accumulation.
#include <doctest/doctest.h>

#include "cellguard/grid/evidence_grid.hpp"

using namespace cellguard;

namespace {
GridGeometry small_geometry() { return GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{4, 3, 2}).value(); }
}  // namespace

// verifies: SR-GRID-003
TEST_CASE("evidence grid: storage smaller than the grid is refused") {
    std::int16_t lo[23];
    std::uint8_t ob[24];
    CHECK(EvidenceGrid::make(small_geometry(), Span<std::int16_t>(lo), Span<std::uint8_t>(ob)).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(EvidenceGrid::make(GridGeometry{}, Span<std::int16_t>(lo), Span<std::uint8_t>(ob)).error() ==
          ErrorCode::kInvalidArgument);
    // Each of the two arrays on its own: too small, or a null pointer with a size.
    std::int16_t lo24[24];
    std::uint8_t ob23[23];
    CHECK(EvidenceGrid::make(small_geometry(), Span<std::int16_t>(lo24), Span<std::uint8_t>(ob23)).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(EvidenceGrid::make(small_geometry(), Span<std::int16_t>(nullptr, 24U), Span<std::uint8_t>(ob)).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(EvidenceGrid::make(small_geometry(), Span<std::int16_t>(lo24), Span<std::uint8_t>(nullptr, 24U)).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(EvidenceGrid::make(small_geometry(), Span<std::int16_t>(lo24), Span<std::uint8_t>(ob)).ok());
}

// verifies: SR-GRID-003
TEST_CASE("evidence grid: a cleared grid is unknown and unobserved everywhere") {
    static StaticEvidenceGridStorage<4, 3, 2> storage;
    for (auto& v : storage.log_odds)
        v = 123;
    for (auto& o : storage.observed)
        o = 1;
    EvidenceGrid g = EvidenceGrid::make(small_geometry(), storage.log_odds, storage.observed).value();
    g.clear();
    CHECK(g.observed_count() == 0U);
    for (const auto v : g.log_odds())
        CHECK(v == 0);
}

// verifies: SR-GRID-003
TEST_CASE("evidence grid: background accumulation adds observed voxels only, with clamping") {
    static StaticEvidenceGridStorage<4, 3, 2> bg_s;
    static StaticEvidenceGridStorage<4, 3, 2> fr_s;
    EvidenceGrid bg = EvidenceGrid::make(small_geometry(), bg_s.log_odds, bg_s.observed).value();
    EvidenceGrid fr = EvidenceGrid::make(small_geometry(), fr_s.log_odds, fr_s.observed).value();
    bg.clear();
    fr.clear();
    fr.log_odds()[0] = -100;
    fr.observed()[0] = 1;
    fr.log_odds()[1] = 500;  // not observed: must be ignored
    fr.log_odds()[2] = 900;
    fr.observed()[2] = 1;
    const BackgroundClamp clamp{-250, 1000};
    for (int i = 0; i < 5; ++i) {
        REQUIRE(accumulate_background(bg, fr, clamp).ok());
    }
    CHECK(bg.log_odds()[0] == -250);
    CHECK(bg.log_odds()[1] == 0);
    CHECK(bg.observed()[1] == 0);
    CHECK(bg.log_odds()[2] == 1000);
    CHECK(bg.observed_count() == 2U);
    CHECK(accumulate_background(bg, fr, BackgroundClamp{10, -10}).error() == ErrorCode::kInvalidArgument);
    // A lower clamp at the never-foreground sentinel is refused even when it is not above the upper one.
    CHECK(accumulate_background(bg, fr, BackgroundClamp{kNeverForeground, kNeverForeground}).error() ==
          ErrorCode::kInvalidArgument);
    CHECK(accumulate_background(bg, fr, BackgroundClamp{kNeverForeground, 0}).error() == ErrorCode::kInvalidArgument);
    CHECK(bg.log_odds()[0] == -250);
}

// verifies: SR-GRID-003
TEST_CASE("evidence grid: accumulating grids of different geometry is refused") {
    static StaticEvidenceGridStorage<4, 3, 2> a_s;
    static StaticEvidenceGridStorage<4, 3, 2> b_s;
    EvidenceGrid a = EvidenceGrid::make(small_geometry(), a_s.log_odds, a_s.observed).value();
    const GridGeometry other = GridGeometry::make(Eigen::Vector3d(0.1, 0, 0), 0.1, GridDims{4, 3, 2}).value();
    const EvidenceGrid b = EvidenceGrid::make(other, b_s.log_odds, b_s.observed).value();
    CHECK(accumulate_background(a, b).error() == ErrorCode::kGeometryMismatch);
}
