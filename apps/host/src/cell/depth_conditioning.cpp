// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/cell/depth_conditioning.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace cellguard::cell {
namespace {

bool has_reading(float d) noexcept { return d > 0.0F && std::isfinite(d); }

/// The nearest and farthest reading up to @p reach pixels from pixel (u, v)
/// of @p img along its row and column (NaN: no reading, passed over); none:
/// the pixel's own @p d.
struct Extremes {
    float near;  ///< the nearest
    float far;   ///< the farthest

    /// Takes @p x in: std::min(a, b) and std::max(a, b) keep a when b is NaN.
    void take(float x) noexcept {
        near = std::min(near, x);
        far = std::max(far, x);
    }
};
Extremes neighbour_extremes(const float* img, std::int32_t w, std::int32_t h, std::int32_t u, std::int32_t v,
                            std::int32_t reach, float d) noexcept {
    const auto row = static_cast<std::ptrdiff_t>(w);
    const float* p = img + static_cast<std::ptrdiff_t>(v) * row + u;
    const bool inside = u >= reach && v >= reach && u + reach < w && v + reach < h;  // no bound to check
    Extremes e{d, d};
    for (std::int32_t k = 1; k <= reach; ++k) {
        const std::ptrdiff_t down = k * row;
        e.take(inside || u >= k ? p[-k] : d);
        e.take(inside || u + k < w ? p[k] : d);
        e.take(inside || v >= k ? p[-down] : d);
        e.take(inside || v + k < h ? p[down] : d);
    }
    return e;
}

/// The edge filter: drops each reading of @p depth that differs from a
/// reading up to c.edge_radius pixels away along its row or column by more
/// than the jump, found on @p scratch (the image as given, NaN for no
/// reading). The largest difference is the nearest or the farthest
/// neighbour's, so two compares decide; the floats' difference is exact in
/// double, as a per-neighbour compare's is.
std::uint64_t drop_edges(Span<float> depth, Span<float> scratch, std::int32_t w, std::int32_t h,
                         const DepthConditioning& c) noexcept {
    const std::size_t n = depth.size();
    for (std::size_t i = 0U; i < n; ++i) {
        scratch[i] = has_reading(depth[i]) ? depth[i] : std::numeric_limits<float>::quiet_NaN();
    }
    const std::int32_t reach = c.edge_radius > 1 ? c.edge_radius : 1;
    std::uint64_t dropped = 0U;
    for (std::int32_t v = 0; v < h; ++v) {
        for (std::int32_t u = 0; u < w; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(u);
            const float d = scratch[i];
            if (std::isnan(d)) {
                continue;
            }
            const Extremes e = neighbour_extremes(scratch.data(), w, h, u, v, reach, d);
            const auto dd = static_cast<double>(d);
            const double jump = std::max(c.edge_jump_min_m, c.edge_jump_per_m * dd);
            if (static_cast<double>(e.far) - dd > jump || dd - static_cast<double>(e.near) > jump) {
                depth[i] = 0.0F;
                ++dropped;
            }
        }
    }
    return dropped;
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
        local.dropped = drop_edges(depth, scratch, width, height, c);
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
