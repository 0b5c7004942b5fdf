// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The demo's scripted person path.
#include "cellguard/host/cell/scenario.hpp"

#include <cstddef>

namespace cellguard::cell {
namespace {

struct Waypoint {
    int cycle;
    double x;
    double y;
    const char* phase;
};

// Cycle numbers at which the person is at (x, y); linear in between. The
// phase names the stretch that starts at the waypoint.
constexpr Waypoint kPath[] = {
    {0, 1.30, 0.60, "outside"},          {8, 1.30, 0.60, "walking in"}, {14, 0.70, 0.60, "walking in"},
    {15, 0.45, 0.60, "protective zone"}, {22, 0.20, 0.45, "leaving"},   {28, -0.45, 0.62, "walking to box A"},
    {34, -0.74, 0.20, "behind box A"},   {42, -0.74, 0.20, "leaving"},  {50, -1.40, 0.20, "outside"},
};
constexpr std::size_t kWaypoints = sizeof(kPath) / sizeof(kPath[0]);

}  // namespace

PersonPosition demo_person(int cycle) {
    if (cycle <= kPath[0].cycle) {
        return {kPath[0].x, kPath[0].y};
    }
    for (std::size_t i = 1U; i < kWaypoints; ++i) {
        if (cycle <= kPath[i].cycle) {
            const Waypoint& a = kPath[i - 1U];
            const Waypoint& b = kPath[i];
            const double f = static_cast<double>(cycle - a.cycle) / static_cast<double>(b.cycle - a.cycle);
            return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)};
        }
    }
    return {kPath[kWaypoints - 1U].x, kPath[kWaypoints - 1U].y};
}

const char* demo_phase(int cycle) {
    const char* phase = kPath[0].phase;
    for (const Waypoint& w : kPath) {
        if (cycle >= w.cycle) {
            phase = w.phase;
        }
    }
    return phase;
}

sim::Box person_box(const PersonPosition& p) {
    return sim::Box{{p.x, p.y, kPersonHeight / 2.0}, {kPersonWidth, kPersonWidth, kPersonHeight}, 0.0, false};
}

bool person_overlaps(const ZoneConfig& zone, const PersonPosition& p) {
    constexpr int kSteps = 30;  // 1 cm across the 0.3 m footprint
    for (int i = 0; i <= kSteps; ++i) {
        for (int j = 0; j <= kSteps; ++j) {
            for (int k = 0; k <= 170; k += 5) {
                const Eigen::Vector3d q(p.x - kPersonWidth / 2.0 + kPersonWidth * i / kSteps,
                                        p.y - kPersonWidth / 2.0 + kPersonWidth * j / kSteps, 0.01 * k);
                if (zone_contains(zone, q)) {
                    return true;
                }
            }
        }
    }
    return false;
}

}  // namespace cellguard::cell
