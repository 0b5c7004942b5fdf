#include "cellguard/background_check.hpp"

#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cellguard {

namespace {

/// 1 when @p d is a reading: positive and finite (NaN compares false).
std::uint32_t is_reading(float d) noexcept {
    return static_cast<std::uint32_t>(d > 0.0F) & static_cast<std::uint32_t>(d < std::numeric_limits<float>::infinity());
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
#if defined(__SSE2__)
    // Four pixels at a time (x86-64); the same comparisons as the loop below,
    // which takes the rest and is the whole of it on other targets.
    const __m128 zero = _mm_setzero_ps();
    const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
    const __m128 tolerance = _mm_set1_ps(reference.tolerance_m);
    const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    __m128i referenced4 = _mm_setzero_si128();  // per lane: the count (subtracting a true compare, -1, adds one)
    __m128i matching4 = _mm_setzero_si128();
    for (; i + 4U <= live.size(); i += 4U) {
        const __m128 r = _mm_loadu_ps(reference.depth.data() + i);
        const __m128 d = _mm_loadu_ps(live.data() + i);
        const __m128 r_ok = _mm_and_ps(_mm_cmpgt_ps(r, zero), _mm_cmplt_ps(r, inf));
        const __m128 d_ok = _mm_and_ps(_mm_cmpgt_ps(d, zero), _mm_cmplt_ps(d, inf));
        const __m128 near = _mm_cmple_ps(_mm_and_ps(_mm_sub_ps(d, r), magnitude), tolerance);
        referenced4 = _mm_sub_epi32(referenced4, _mm_castps_si128(r_ok));
        matching4 = _mm_sub_epi32(matching4, _mm_castps_si128(_mm_and_ps(r_ok, _mm_and_ps(d_ok, near))));
    }
    alignas(16) std::uint32_t lanes[8] = {};
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes), referenced4);      // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): SIMD store of the lane counts
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes + 4), matching4);    // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): SIMD store of the lane counts
    m.referenced = lanes[0] + lanes[1] + lanes[2] + lanes[3];
    m.matching = lanes[4] + lanes[5] + lanes[6] + lanes[7];
#endif
    for (; i < live.size(); ++i) {
        const float r = reference.depth[i];
        const float d = live[i];
        // Branch-free, so that the compiler can compare several pixels at once.
        const std::uint32_t referenced = is_reading(r);
        const std::uint32_t within = is_reading(d) & static_cast<std::uint32_t>(std::fabs(d - r) <= reference.tolerance_m);
        m.referenced += referenced;
        m.matching += referenced & within;
    }
    return m;
}

bool background_seen(const BackgroundMatch& match, float min_fraction) noexcept {
    if (match.referenced == 0U || !(min_fraction > 0.0F) || !(min_fraction <= 1.0F)) {
        return false;
    }
    const auto needed = static_cast<std::uint64_t>(std::ceil(static_cast<double>(min_fraction) *
                                                             static_cast<double>(match.referenced)));
    return static_cast<std::uint64_t>(match.matching) >= needed;
}

}  // namespace cellguard
