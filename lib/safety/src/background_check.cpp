// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/background_check.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "cellguard/base/saturating.hpp"

namespace cellguard {

namespace {

/// 1 when @p d is a reading: positive and finite (NaN compares false).
std::uint32_t is_reading(float d) noexcept {
    return static_cast<std::uint32_t>(d > 0.0F) &
           static_cast<std::uint32_t>(d < std::numeric_limits<float>::infinity());
}

/// A kDepthImage view read in place: four floats at a time as stored.
struct FloatLive {
    const float* depth;
    float operator[](std::size_t i) const noexcept { return depth[i]; }
    template <typename Floats>
    void load4(std::size_t i, Floats& out) const noexcept {
        std::memcpy(&out, depth + i, sizeof out);
    }
};

/// A kDepthImageU16 reading read in place through depth_value (raw 0: NaN).
struct U16Live {
    const SensorReading* reading;
    float operator[](std::size_t i) const noexcept { return depth_value(*reading, i); }
    template <typename Floats>
    void load4(std::size_t i, Floats& out) const noexcept {
        out = Floats{depth_value(*reading, i), depth_value(*reading, i + 1U), depth_value(*reading, i + 2U),
                     depth_value(*reading, i + 3U)};
    }
};

/// match_background for either kind of @p live image of @p n pixels (the
/// checks are done by the caller).
template <typename Live>
BackgroundMatch match_pixels(const Live& live, std::size_t n, const BackgroundReference& reference) noexcept {
    BackgroundMatch m;
    std::size_t i = 0U;
    // Four pixels at a time in GCC/Clang vector types (SSE2 on x86-64, NEON
    // on aarch64, scalar code on targets without SIMD): the same comparisons
    // as the loop below, which takes the remaining pixels.
    using Floats = float __attribute__((vector_size(16)));
    using Lanes = std::int32_t __attribute__((vector_size(16)));
    const float inf = std::numeric_limits<float>::infinity();
    Lanes referenced4 = {0, 0, 0, 0};  // per lane: the count (subtracting a true compare, -1, adds one)
    Lanes matching4 = {0, 0, 0, 0};
    Lanes longer4 = {0, 0, 0, 0};
    for (; i + 4U <= n; i += 4U) {
        Floats r;
        Floats d;
        std::memcpy(&r, reference.depth.data() + i, sizeof r);
        live.load4(i, d);
        const Lanes r_ok = (r > 0.0F) & (r < inf);
        const Lanes d_ok = (d > 0.0F) & (d < inf);
        const Floats difference = d - r;
        Lanes magnitude_bits;
        std::memcpy(&magnitude_bits, &difference, sizeof magnitude_bits);
        magnitude_bits &= 0x7FFFFFFF;  // |d - r|: the sign bit cleared, as fabs does
        Floats magnitude;
        std::memcpy(&magnitude, &magnitude_bits, sizeof magnitude);
        const Lanes near = magnitude <= reference.tolerance_m;
        referenced4 -= r_ok;
        matching4 -= r_ok & d_ok & near;
        longer4 -= r_ok & d_ok & (difference > reference.tolerance_m);
    }
    for (int lane = 0; lane < 4; ++lane) {
        m.referenced += static_cast<std::uint32_t>(referenced4[lane]);
        m.matching += static_cast<std::uint32_t>(matching4[lane]);
        m.longer += static_cast<std::uint32_t>(longer4[lane]);
    }
    for (; i < n; ++i) {
        const float r = reference.depth[i];
        const float d = live[i];
        // The last 0 to 3 pixels: the same comparisons, one at a time.
        const std::uint32_t referenced = is_reading(r);
        const std::uint32_t within = is_reading(d) &
                                     static_cast<std::uint32_t>(std::fabs(d - r) <= reference.tolerance_m);
        m.referenced += referenced;
        m.matching += referenced & within;
        m.longer += referenced & is_reading(d) & static_cast<std::uint32_t>(d - r > reference.tolerance_m);
    }
    return m;
}

bool tolerance_ok(const BackgroundReference& reference) noexcept {
    return std::isfinite(reference.tolerance_m) && reference.tolerance_m > 0.0F;
}

}  // namespace

Result<BackgroundMatch> match_background(Span<const float> live, const BackgroundReference& reference) noexcept {
    if (live.size() != reference.depth.size()) {
        return ErrorCode::kMalformedInput;
    }
    if (!tolerance_ok(reference)) {
        return ErrorCode::kInvalidArgument;
    }
    return match_pixels(FloatLive{live.data()}, live.size(), reference);
}

Result<BackgroundMatch> match_points(Span<const Eigen::Vector3f> points,
                                     const BackgroundReference& reference) noexcept {
    const Status grid_ok = check_direction_grid(reference.grid);
    if (!grid_ok.ok()) {
        return grid_ok.error();
    }
    const std::size_t bins = reference.grid.bin_count();
    if (reference.depth.size() != bins || reference.nearest.size() != bins) {
        return ErrorCode::kMalformedInput;
    }
    if (!tolerance_ok(reference)) {
        return ErrorCode::kInvalidArgument;
    }
    BackgroundMatch m;
    const float tolerance = reference.tolerance_m;
    for (const Eigen::Vector3f& p : points) {
        float range = 0.0F;
        const std::size_t bin = direction_bin(reference.grid, p, range);
        if (bin == kNoDirectionBin) {
            m.outside = saturating_add(m.outside, static_cast<std::uint32_t>(range > 0.0F));
            continue;
        }
        const float far = reference.depth[bin];
        if (is_reading(far) == 0U) {
            continue;  // no background return in this direction: nothing to compare with
        }
        // At most kMaxReadingsPerSensor points are checked by the caller;
        // the counts saturate all the same.
        m.referenced = saturating_add(m.referenced, 1U);
        const bool longer = range - far > tolerance;
        const bool within = !longer && range >= reference.nearest[bin] - tolerance;
        m.matching = saturating_add(m.matching, static_cast<std::uint32_t>(within));
        m.longer = saturating_add(m.longer, static_cast<std::uint32_t>(longer));
    }
    return m;
}

Result<BackgroundMatch> match_background(const SensorReading& live, const BackgroundReference& reference) noexcept {
    if (live.kind == SensorDataKind::kPointSet) {
        return match_points(live.points, reference);
    }
    if (!is_depth_image(live.kind) || !reference.nearest.empty()) {
        return ErrorCode::kInvalidArgument;  // a depth image against a point-set view (or an unknown kind)
    }
    if (live.kind == SensorDataKind::kDepthImage) {
        return match_background(live.depth, reference);
    }
    if (live.depth_u16.size() != reference.depth.size()) {
        return ErrorCode::kMalformedInput;
    }
    if (!tolerance_ok(reference)) {
        return ErrorCode::kInvalidArgument;
    }
    return match_pixels(U16Live{&live}, live.depth_u16.size(), reference);
}

void BackgroundChangeTracker::track(std::size_t slot, const BackgroundMatch& match,
                                    const BackgroundReference& reference) noexcept {
    if (slot >= kMaxSensors) {
        return;
    }
    last[slot] = match;
    std::uint32_t& run = streak[slot];
    if (reference.changed_cycles == 0U || !background_changed(match, reference.max_longer_pixels)) {
        run = 0U;  // a frame that shows the commissioned background ends the run
        return;
    }
    run = saturating_increment(run);
    if (run >= reference.changed_cycles) {
        latched |= 1U << slot;  // only a restart (and recommissioning) clears it
    }
}

bool background_seen(const BackgroundMatch& match, float min_fraction) noexcept {
    if (match.referenced == 0U || !(min_fraction > 0.0F) || !(min_fraction <= 1.0F)) {
        return false;
    }
    const auto needed = static_cast<std::uint64_t>(
        std::ceil(static_cast<double>(min_fraction) * static_cast<double>(match.referenced)));
    return static_cast<std::uint64_t>(match.matching) >= needed;
}

}  // namespace cellguard
