// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file fusion_stats_check.hpp
/// Checks that two fusion calls counted alike (every field of FusionStats),
/// for the tests that compare two paths over the same readings.
#ifndef CELLGUARD_TESTS_FUSION_STATS_CHECK_HPP
#define CELLGUARD_TESTS_FUSION_STATS_CHECK_HPP

#include <doctest/doctest.h>

#include "cellguard/grid/fusion.hpp"

/// CHECKs each count of @p a against @p b.
inline void check_same_stats(const cellguard::FusionStats& a, const cellguard::FusionStats& b) {
    CHECK(a.rays_fused == b.rays_fused);
    CHECK(a.readings_in_grid == b.readings_in_grid);
    CHECK(a.skipped_nan == b.skipped_nan);
    CHECK(a.skipped_infinite == b.skipped_infinite);
    CHECK(a.skipped_zero == b.skipped_zero);
    CHECK(a.skipped_behind == b.skipped_behind);
    CHECK(a.skipped_out_of_range == b.skipped_out_of_range);
    CHECK(a.voxel_updates == b.voxel_updates);
}

#endif  // CELLGUARD_TESTS_FUSION_STATS_CHECK_HPP
