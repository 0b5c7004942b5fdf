// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Storage of a compact ray table in plain vectors the test can reach: to
// shorten one span at a time, or to flip a bit of the table's constant RAM.
// (host::OwnedRayTable hides its vectors; programs have no reason to touch them.)
#ifndef CELLGUARD_TESTS_RAY_TABLE_VECTORS_HPP
#define CELLGUARD_TESTS_RAY_TABLE_VECTORS_HPP

#include <cstdint>
#include <vector>

#include "cellguard/grid/ray_table.hpp"

namespace cellguard::test {

/// Vectors sized for a compact table of @p sensor in @p grid (count_ray_steps
/// must succeed: the caller REQUIREs it).
struct RayTableVectors {
    std::size_t entries = 0U;
    std::size_t pixels = 0U;
    std::vector<std::uint16_t> voxels, steps;
    std::vector<std::uint32_t> begin, full_hits, crossed, walked, hits;
    std::vector<std::int16_t> opinions;
    std::vector<float> enter, exit, norm;

    RayTableVectors(const GridGeometry& grid, const SensorReading& sensor)
        : entries(count_ray_steps(grid, sensor).value()),
          pixels(sensor.depth.size()),
          voxels(entries),
          steps(entries),
          begin(pixels + 1U),
          full_hits(grid.voxel_count()),
          crossed(grid.voxel_count()),
          walked(pixels),
          hits(grid.voxel_count()),
          opinions(grid.voxel_count()),
          enter(pixels),
          exit(pixels),
          norm(pixels) {}

    /// Spans over all of the vectors.
    [[nodiscard]] RayTableStorage storage() {
        return RayTableStorage{{voxels.data(), voxels.size()},
                               {steps.data(), steps.size()},
                               {},
                               {},
                               {begin.data(), begin.size()},
                               {enter.data(), enter.size()},
                               {exit.data(), exit.size()},
                               {norm.data(), norm.size()},
                               {full_hits.data(), full_hits.size()},
                               {crossed.data(), crossed.size()},
                               {walked.data(), walked.size()},
                               {hits.data(), hits.size()},
                               {opinions.data(), opinions.size()}};
    }
};

}  // namespace cellguard::test

#endif  // CELLGUARD_TESTS_RAY_TABLE_VECTORS_HPP
