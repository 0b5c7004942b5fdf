// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The benchmarks' one way of turning a depth image into world points (for
// the per-ray references and OctoMap): every pixel with a positive depth
// within the sensor's max_range, in the cell frame.
#ifndef CELLGUARD_BENCH_WORLD_READINGS_HPP
#define CELLGUARD_BENCH_WORLD_READINGS_HPP

#include <Eigen/Core>
#include <cstddef>

#include "cellguard/grid/sensor_frame.hpp"

namespace cellguard::bench {

/// Calls @p f(world point) for each valid reading of float depth image @p r, in pixel order.
template <typename F>
void for_each_world_reading(const SensorReading& r, F&& f) {
    const PinholeIntrinsics& k = r.intrinsics;
    for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u < k.width; ++u) {
            const float d =
                r.depth[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) + static_cast<std::size_t>(u)];
            const Eigen::Vector3d p((u - k.cx) / k.fx * d, (v - k.cy) / k.fy * d, d);
            if (!(d > 0.0F) || p.norm() > r.max_range) {
                continue;
            }
            f(Eigen::Vector3d(r.pose * p));
        }
    }
}

}  // namespace cellguard::bench

#endif  // CELLGUARD_BENCH_WORLD_READINGS_HPP
