// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// What bench_cycle and bench_scale both build around a controller: the
// worst-case zones and a clock of this thread's CPU time.
#ifndef CELLGUARD_BENCH_CELLS_HPP
#define CELLGUARD_BENCH_CELLS_HPP

#include <cstdint>
#include <vector>

#include <time.h>

#include "cellguard/grid/grid.hpp"
#include "cellguard/safety/clock.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::bench {

/// kMaxZones zones that each cover the whole grid: boxes of the whole grid
/// and prisms over its footprint (an octagon with vertices on the grid's
/// edges would miss the corners, so the prisms use the rectangle), half
/// protective, half warning, each stopping on one foreground voxel and
/// allowing no unseen one: every voxel is in every zone (the most zone work
/// a cycle can do).
inline std::vector<ZoneConfig> worst_case_zones(const GridGeometry& g) {
    const Eigen::Vector3d lo = g.origin();
    const Eigen::Vector3d hi = g.max_corner();
    std::vector<ZoneConfig> zones(kMaxZones);
    for (std::size_t z = 0U; z < kMaxZones; ++z) {
        ZoneConfig& c = zones[z];
        c.kind = z < kMaxZones / 2U ? ZoneKind::kProtective : ZoneKind::kWarning;
        c.min_foreground_voxels = 1U;
        c.max_unseen_voxels = 0U;
        if (z % 2U == 0U) {
            c.shape = ZoneShape::kBox;
            c.box_min = lo;
            c.box_max = hi;
        } else {
            c.shape = ZoneShape::kPrism;
            c.polygon[0] = PolygonVertex{lo.x(), lo.y()};
            c.polygon[1] = PolygonVertex{hi.x(), lo.y()};
            c.polygon[2] = PolygonVertex{hi.x(), hi.y()};
            c.polygon[3] = PolygonVertex{lo.x(), hi.y()};
            c.polygon_size = 4U;
            c.z_min = lo.z();
            c.z_max = hi.z();
        }
    }
    return zones;
}

/// The controller's clock in a benchmark: this thread's CPU time in
/// microseconds (monotonic, like the port's clock), so the controller's own
/// stage timing measures work, not the time the scheduler of a shared
/// machine gave to other processes. Whole cycles are also timed on the wall clock.
class ThreadCpuClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override {
        timespec t{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return static_cast<std::uint64_t>(t.tv_sec) * 1000000U + static_cast<std::uint64_t>(t.tv_nsec) / 1000U;
    }
};

}  // namespace cellguard::bench

#endif  // CELLGUARD_BENCH_CELLS_HPP
