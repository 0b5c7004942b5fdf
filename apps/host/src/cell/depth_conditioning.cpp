// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/cell/depth_conditioning.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cellguard::cell {
namespace {

bool has_reading(float d) noexcept { return d > 0.0F && std::isfinite(d); }

/// True when the reading of pixel (u, v) of @p image (with a reading) differs
/// from a 4-neighbour's reading by more than the edge filter's jump.
bool at_edge(const float* image, std::int32_t w, std::int32_t h, std::int32_t u, std::int32_t v,
             const DepthConditioning& c) noexcept {
    const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u);
    const auto d = static_cast<double>(image[i]);
    const double jump = std::max(c.edge_jump_min_m, c.edge_jump_per_m * d);
    const std::int32_t du[4] = {-1, 1, 0, 0};
    const std::int32_t dv[4] = {0, 0, -1, 1};
    const std::int32_t reach = c.edge_radius > 1 ? c.edge_radius : 1;
    for (int k = 0; k < 4 * reach; ++k) {
        const std::int32_t step = 1 + k / 4;
        const std::int32_t nu = u + step * du[k % 4];
        const std::int32_t nv = v + step * dv[k % 4];
        if (nu < 0 || nv < 0 || nu >= w || nv >= h) {
            continue;
        }
        const float n =
            image[static_cast<std::size_t>(nv) * static_cast<std::size_t>(w) + static_cast<std::size_t>(nu)];
        if (has_reading(n) && std::fabs(static_cast<double>(n) - d) > jump) {
            return true;
        }
    }
    return false;
}

/// True when pixel @p i's reading lies nearer than the empty cell's depth (not on it).
bool in_front(const float* depth, const float* background, std::size_t i) noexcept {
    return has_reading(depth[i]) && (!has_reading(background[i]) || depth[i] < background[i]);
}

/// The speckle filter over @p depth (read from @p scratch, a copy).
std::uint64_t drop_speckles(Span<float> depth, Span<const float> background, Span<float> scratch, std::int32_t w,
                            std::int32_t h, int min_neighbours) noexcept {
    std::copy(depth.begin(), depth.end(), scratch.begin());
    const float* img = scratch.data();
    const float* bg = background.data();
    std::uint64_t dropped = 0U;
    for (std::int32_t v = 0; v < h; ++v) {
        for (std::int32_t u = 0; u < w; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(u);
            if (!in_front(img, bg, i)) {
                continue;
            }
            int near = 0;
            for (std::int32_t dv = -1; dv <= 1; ++dv) {
                for (std::int32_t du = -1; du <= 1; ++du) {
                    const std::int32_t nu = u + du;
                    const std::int32_t nv = v + dv;
                    if ((du == 0 && dv == 0) || nu < 0 || nv < 0 || nu >= w || nv >= h) {
                        continue;
                    }
                    near += in_front(img, bg,
                                     static_cast<std::size_t>(nv) * static_cast<std::size_t>(w) +
                                         static_cast<std::size_t>(nu))
                                ? 1
                                : 0;
                }
            }
            if (near < min_neighbours) {
                depth[i] = 0.0F;
                ++dropped;
            }
        }
    }
    return dropped;
}

}  // namespace

bool condition_depth(Span<float> depth, Span<const float> background, Span<float> scratch, std::int32_t width,
                     std::int32_t height, const DepthConditioning& c, ConditioningCounts* counts) noexcept {
    if (width <= 0 || height <= 0) {
        return false;
    }
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (depth.size() != n || scratch.size() < n || (!background.empty() && background.size() != n)) {
        return false;
    }
    ConditioningCounts local;
    if (c.edge_jump_per_m > 0.0 || c.edge_jump_min_m > 0.0) {
        std::copy(depth.begin(), depth.end(), scratch.begin());  // edges are found on the image as given
        for (std::int32_t v = 0; v < height; ++v) {
            for (std::int32_t u = 0; u < width; ++u) {
                const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                                      static_cast<std::size_t>(u);
                if (has_reading(scratch[i]) && at_edge(scratch.data(), width, height, u, v, c)) {
                    depth[i] = 0.0F;
                    ++local.dropped;
                }
            }
        }
    }
    if (c.background_tolerance_per_m > 0.0 && !background.empty()) {
        for (std::size_t i = 0U; i < n; ++i) {
            const float b = background[i];
            const double off = std::fabs(static_cast<double>(depth[i]) - static_cast<double>(b));
            if (has_reading(depth[i]) && has_reading(b) &&
                off <= static_cast<double>(b) * c.background_tolerance_per_m) {
                depth[i] = b;
                ++local.snapped;
            }
        }
    }
    if (c.speckle_min_neighbours > 0 && !background.empty()) {
        local.speckles = drop_speckles(depth, background, scratch, width, height, c.speckle_min_neighbours);
    }
    if (counts != nullptr) {
        counts->dropped += local.dropped;
        counts->snapped += local.snapped;
        counts->speckles += local.speckles;
    }
    return true;
}

}  // namespace cellguard::cell
