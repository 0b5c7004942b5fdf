// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/background_check.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace cellguard {

namespace {

/// 1 when @p d is a reading: positive and finite (NaN compares false).
std::uint32_t is_reading(float d) noexcept {
    return static_cast<std::uint32_t>(d > 0.0F) &
           static_cast<std::uint32_t>(d < std::numeric_limits<float>::infinity());
}

}  // namespace

Result<BackgroundMatch> match_background(Span<const float> live, const BackgroundReference& reference) noexcept {
    if (live.size() != reference.depth.size()) {
        return ErrorCode::kMalformedInput;
    }
    if (!(std::isfinite(reference.tolerance_m) && reference.tolerance_m > 0.0F)) {
        return ErrorCode::kInvalidArgument;
    }
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
    for (; i + 4U <= live.size(); i += 4U) {
        Floats r;
        Floats d;
        std::memcpy(&r, reference.depth.data() + i, sizeof r);
        std::memcpy(&d, live.data() + i, sizeof d);
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
    }
    for (int lane = 0; lane < 4; ++lane) {
        m.referenced += static_cast<std::uint32_t>(referenced4[lane]);
        m.matching += static_cast<std::uint32_t>(matching4[lane]);
    }
    for (; i < live.size(); ++i) {
        const float r = reference.depth[i];
        const float d = live[i];
        // The last 0 to 3 pixels: the same comparisons, one at a time.
        const std::uint32_t referenced = is_reading(r);
        const std::uint32_t within = is_reading(d) &
                                     static_cast<std::uint32_t>(std::fabs(d - r) <= reference.tolerance_m);
        m.referenced += referenced;
        m.matching += referenced & within;
    }
    return m;
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
