// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "hit_pass.hpp"

#include <array>
#include <cmath>
#include <cstring>

#include "placement.hpp"
#include "reading_class.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

// The AVX2 kernel: x86-64 only, built for AVX2 in its own functions (target
// attribute) and run only where the CPU has it (resolve_fusion_kernel).
#if defined(__x86_64__)
#define CELLGUARD_HIT_AVX2 1
#else
#define CELLGUARD_HIT_AVX2 0
#endif

namespace cellguard {

FusionKernel resolve_fusion_kernel(FusionKernel requested) noexcept {
#if CELLGUARD_HIT_AVX2
    // libgcc's CPU model, read once at start-up (CPUID and the OS's saved register state): no call.
    const auto avx2 = static_cast<bool>(__builtin_cpu_supports("avx2"));
#else
    const bool avx2 = false;
#endif
    return requested != FusionKernel::kScalar && avx2 ? FusionKernel::kAvx2 : FusionKernel::kScalar;
}

namespace detail {
namespace {

/// Step 1's placement of a reading in its voxel: fuse_sensor's own rule
/// (placement.hpp, inlined: the same point, the same voxel, bit for bit).
/// The class of the reading is decided by a test on its range in double
/// where that cannot differ from classify_point's in float: a reading whose
/// range lies within 1e-5 of a range limit, or that is not a positive finite
/// depth the short test may take, is classified the long way.
class HitPlacer {
public:
    HitPlacer(const GridGeometry& g, const SensorReading& r) noexcept
        : g_(g), r_(r), inv_fx_(1.0 / r.intrinsics.fx), inv_fy_(1.0 / r.intrinsics.fy), inv_s_(1.0 / g.voxel_size()) {
        const auto lo = static_cast<double>(r.min_range);
        const auto hi = static_cast<double>(r.max_range);
        min2_lo_ = lo * lo * (1.0 - 1e-5);
        min2_hi_ = lo * lo * (1.0 + 1e-5);
        max2_lo_ = hi * hi * (1.0 - 1e-5);
        max2_hi_ = hi * hi * (1.0 + 1e-5);
        // A reading within the range limit lies within +-1e9 voxels when |b| + |row of m|_1 x max
        // range does (m, b: the pose in voxels): then GridGeometry::floor_index's conversion to
        // int32 is defined. Else (a camera absurdly far from the grid) every reading goes the long
        // way, as fuse_sensor places it.
        const double s = g.voxel_size();
        const Eigen::Matrix3d m = r.pose.linear() / s;
        const Eigen::Vector3d b = (r.pose.translation() - g.origin()) / s;
        for (Eigen::Index a = 0; a < 3; ++a) {
            const double reach = std::fabs(b[a]) +
                                 (std::fabs(m(a, 0)) + std::fabs(m(a, 1)) + std::fabs(m(a, 2))) * hi * (1.0 + 1e-5);
            far_ = far_ || !(reach < 1e9);
        }
    }

    /// Starts image row @p v: the rays of its pixels (place() takes them in any order).
    void begin_row(std::int32_t v) noexcept {
        const double yn = (static_cast<double>(v) - r_.intrinsics.cy) * inv_fy_;
        row_yn_ = yn;
        row_range_ = yn * yn + 1.0;
    }

    /// The grid and the short test's constants, for the vector kernels (hit_group).
    [[nodiscard]] const GridGeometry& grid() const noexcept { return g_; }
    [[nodiscard]] bool far() const noexcept { return far_; }
    [[nodiscard]] double inv_fx() const noexcept { return inv_fx_; }
    [[nodiscard]] double inv_voxel_size() const noexcept { return inv_s_; }
    [[nodiscard]] double row_yn() const noexcept { return row_yn_; }
    [[nodiscard]] double row_range() const noexcept { return row_range_; }
    [[nodiscard]] double min2_hi() const noexcept { return min2_hi_; }
    [[nodiscard]] double max2_lo() const noexcept { return max2_lo_; }

    /// The class of the reading of pixel (u, v) of the row begun last at raw
    /// depth @p d, and its voxel when valid.
    [[gnu::always_inline]] ReadingClass place(std::int32_t u, std::int32_t v, float d,
                                              VoxelCoord& voxel) const noexcept {
        // One decision each (bitwise and of 0 or 1): a positive finite depth the short test may take.
        const unsigned usable = static_cast<unsigned>(d > 0.0F) & static_cast<unsigned>(d <= kMaxSensorRange) &
                                static_cast<unsigned>(!far_);
        if (usable == 0U) {
            return place_exactly(u, v, d, voxel);
        }
        const double xn = (static_cast<double>(u) - r_.intrinsics.cx) * inv_fx_;
        const auto dd = static_cast<double>(d);
        const double range2 = dd * dd * (xn * xn + row_range_);
        const unsigned inside = static_cast<unsigned>(range2 > min2_hi_) & static_cast<unsigned>(range2 < max2_lo_);
        if (inside == 0U) {  // not clearly inside the range limits
            const unsigned out = static_cast<unsigned>(range2 <= min2_lo_) | static_cast<unsigned>(range2 >= max2_hi_);
            if (out != 0U) {
                return ReadingClass::kOutOfRange;
            }
            return place_exactly(u, v, d, voxel);  // near a range limit
        }
        voxel = voxel_of(g_, cell_point(r_.pose, pixel_point(r_.intrinsics, inv_fx_, inv_fy_, u, v, d)));
        return ReadingClass::kValid;
    }

private:
    /// Out of line: the rare path, kept out of the pixel loop's code.
    [[gnu::noinline]] ReadingClass place_exactly(std::int32_t u, std::int32_t v, float d,
                                                 VoxelCoord& voxel) const noexcept {
        ReadingClass c = classify_depth(d);
        if (c != ReadingClass::kValid) {
            return c;
        }
        const Eigen::Vector3f p = pixel_point(r_.intrinsics, inv_fx_, inv_fy_, u, v, d);
        c = classify_point(p, r_.min_range, r_.max_range);
        if (c == ReadingClass::kValid) {
            voxel = g_.world_to_voxel_unchecked(cell_point(r_.pose, p));
        }
        return c;
    }

    const GridGeometry& g_;
    const SensorReading& r_;
    double inv_fx_ = 0.0;
    double inv_fy_ = 0.0;
    double inv_s_ = 0.0;      ///< 1 / voxel size (the vector kernels' products, voxel_floor4)
    double row_yn_ = 0.0;     ///< (v - cy) / fy of the current row (pixel_point's ry)
    double row_range_ = 0.0;  ///< yn^2 + 1 of the current row
    bool far_ = false;        ///< readings may lie beyond +-1e9 voxels: all go the long way
    double min2_lo_ = 0.0;
    double min2_hi_ = 0.0;
    double max2_lo_ = 0.0;
    double max2_hi_ = 0.0;
};

/// Where step 1 puts what it finds: the counts, level 0 of the pyramid and the hits.
class HitSink {
public:
    HitSink(const GridGeometry& g, std::int16_t hit, DepthPyramid& pyramid, Span<std::int16_t> opinions) noexcept
        : pyramid_(pyramid),
          out_(opinions.data()),
          nx_(static_cast<std::uint32_t>(g.dims().nx)),
          ny_(static_cast<std::uint32_t>(g.dims().ny)),
          nz_(static_cast<std::uint32_t>(g.dims().nz)),
          hit_(hit) {}

    /// A valid reading @p d of pixel (u, v) in voxel @p vc.
    [[gnu::always_inline]] void valid(std::int32_t u, std::int32_t v, float d, const VoxelCoord& vc) noexcept {
        pyramid_.set_pixel(u, v, d, true);
        ++stats_.rays_fused;
        // In the grid: each coordinate in [0, n) (a negative one is a large unsigned value).
        const auto x = static_cast<std::uint32_t>(vc.x);
        const auto y = static_cast<std::uint32_t>(vc.y);
        const auto z = static_cast<std::uint32_t>(vc.z);
        if (x < nx_ && y < ny_ && z < nz_) {
            out_[x + static_cast<std::size_t>(nx_) * (y + static_cast<std::size_t>(ny_) * z)] = hit_;
            ++stats_.readings_in_grid;
        }
    }
    /// Valid readings of pixels (u .. u + 3, v) at depths @p d (their hits apart: hit()).
    [[gnu::always_inline]] void valid4(std::int32_t u, std::int32_t v, const std::array<float, 4>& d) noexcept {
        pyramid_.set_valid4(u, v, d);
        stats_.rays_fused += 4U;
    }
    /// The hit of a lane at voxel @p index when @p in_grid.
    [[gnu::always_inline]] void hit(bool in_grid, std::uint32_t index) noexcept {
        if (in_grid) {
            out_[index] = hit_;
            ++stats_.readings_in_grid;
        }
    }
    /// Pixel (u, v) skipped for reason @p c: no reading in the pyramid.
    void skipped(std::int32_t u, std::int32_t v, ReadingClass c) noexcept {
        count_skipped(stats_, c);
        pyramid_.set_pixel(u, v, 0.0F, false);
    }
    [[nodiscard]] const FusionStats& stats() const noexcept { return stats_; }

private:
    FusionStats stats_{};
    DepthPyramid& pyramid_;
    std::int16_t* out_;
    std::uint32_t nx_;
    std::uint32_t ny_;
    std::uint32_t nz_;
    std::int16_t hit_;
};

/// One pixel the scalar way: the reference, and every pixel a vector kernel hands back.
[[gnu::always_inline]] inline void hit_pixel(const HitPlacer& placer, HitSink& sink, std::int32_t u, std::int32_t v,
                                             float d) noexcept {
    VoxelCoord vc;
    const ReadingClass c = placer.place(u, v, d, vc);
    if (c != ReadingClass::kValid) {
        sink.skipped(u, v, c);
        return;
    }
    sink.valid(u, v, d, vc);
}

/// Step 1 over every pixel, one at a time, reading depths through @p depth_at (i: the pixel's index).
template <typename DepthAt>
FusionStats hit_rows(const GridGeometry& g, const SensorReading& r, std::int16_t hit, DepthPyramid& pyramid,
                     Span<std::int16_t> opinions, DepthAt&& depth_at) noexcept {
    HitSink sink(g, hit, pyramid, opinions);
    HitPlacer placer(g, r);
    std::size_t i = 0U;
    for (std::int32_t v = 0; v < r.intrinsics.height; ++v) {
        placer.begin_row(v);
        for (std::int32_t u = 0; u < r.intrinsics.width; ++u, ++i) {
            hit_pixel(placer, sink, u, v, depth_at(i));
        }
    }
    return sink.stats();
}

/// A float image's depth of pixel @p i.
struct FloatDepth {
    const float* depth;
    [[gnu::always_inline]] float operator()(std::size_t i) const noexcept { return depth[i]; }
};
/// A uint16 image's depth of pixel @p i (depth_value).
struct U16Depth {
    const SensorReading* reading;
    [[gnu::always_inline]] float operator()(std::size_t i) const noexcept { return depth_value(*reading, i); }
};

#if CELLGUARD_HIT_AVX2
/// The AVX2 kernel's constants of one sensor, each in four lanes.
struct Avx2Sensor {
    __m256d lane_offset;  ///< 0, 1, 2, 3: the group's columns from its first
    __m256d cx;           ///< principal point, x
    __m256d inv_fx;       ///< 1 / fx
    __m256d min2_hi;      ///< HitPlacer's short range test
    __m256d max2_lo;
    __m256d pose[12];  ///< the pose's 3 x 4 matrix, row by row
    __m256d origin[3];
    __m256d size;      ///< voxel size
    __m256d inv_size;  ///< 1 / voxel size, rounded
    __m256d near_lo;   ///< 1e-6 and 1 - 1e-6: a product this near an integer is divided
    __m256d near_hi;
    __m128i n_x;  ///< the grid's sides
    __m128i n_y;
    __m128i n_z;
};

/// Every AVX2 helper: built for AVX2 and always inlined into hit_pass_avx2 (a call would pass AVX
/// registers through memory, and an AVX2 function may only be inlined into another).
#define CELLGUARD_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline

CELLGUARD_AVX2_INLINE Avx2Sensor avx2_sensor(const HitPlacer& placer, const SensorReading& r) noexcept {
    Avx2Sensor k{};
    k.lane_offset = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
    k.cx = _mm256_set1_pd(r.intrinsics.cx);
    k.inv_fx = _mm256_set1_pd(placer.inv_fx());
    k.min2_hi = _mm256_set1_pd(placer.min2_hi());
    k.max2_lo = _mm256_set1_pd(placer.max2_lo());
    const Eigen::Matrix4d& m = r.pose.matrix();
    for (Eigen::Index row = 0; row < 3; ++row) {
        for (Eigen::Index col = 0; col < 4; ++col) {
            k.pose[static_cast<std::size_t>(row * 4 + col)] = _mm256_set1_pd(m(row, col));
        }
        k.origin[static_cast<std::size_t>(row)] = _mm256_set1_pd(placer.grid().origin()[row]);
    }
    k.size = _mm256_set1_pd(placer.grid().voxel_size());
    k.inv_size = _mm256_set1_pd(placer.inv_voxel_size());
    k.near_lo = _mm256_set1_pd(1e-6);
    k.near_hi = _mm256_set1_pd(1.0 - 1e-6);
    k.n_x = _mm_set1_epi32(placer.grid().dims().nx);
    k.n_y = _mm_set1_epi32(placer.grid().dims().ny);
    k.n_z = _mm_set1_epi32(placer.grid().dims().nz);
    return k;
}

/// ((m0 x + m1 y) + m2 z) + m3 for pose row @p row: cell_point's sum in its order.
CELLGUARD_AVX2_INLINE __m256d avx2_cell(const Avx2Sensor& k, std::size_t row, __m256d x, __m256d y,
                                        __m256d z) noexcept {
    const std::size_t b = 4U * row;
    const __m256d xy = _mm256_add_pd(_mm256_mul_pd(k.pose[b], x), _mm256_mul_pd(k.pose[b + 1U], y));
    return _mm256_add_pd(_mm256_add_pd(xy, _mm256_mul_pd(k.pose[b + 2U], z)), k.pose[b + 3U]);
}

/// floor((q - origin) / size) of four coordinates within +-1e9 voxels, as
/// voxel_of takes it: the same integers. The product t = (q - origin) x
/// inv_size lies within 3.1 x 2^-53 |t| < 3.5e-7 of the exact quotient, the
/// rounded quotient within 2^-53 |t|: where t lies more than 1e-6 from every
/// integer, both floor to floor(t). Only when a lane lies nearer (a reading
/// on or at a voxel face) are the four divided.
CELLGUARD_AVX2_INLINE __m128i avx2_voxel(const Avx2Sensor& k, __m256d q, __m256d origin) noexcept {
    const __m256d x = _mm256_sub_pd(q, origin);
    const __m256d t = _mm256_mul_pd(x, k.inv_size);
    const __m256d frac = _mm256_sub_pd(t, _mm256_floor_pd(t));  // [0, 1)
    const __m256d near = _mm256_or_pd(_mm256_cmp_pd(frac, k.near_lo, _CMP_LT_OQ),
                                      _mm256_cmp_pd(frac, k.near_hi, _CMP_GT_OQ));
    const __m256d f = _mm256_movemask_pd(near) == 0 ? _mm256_floor_pd(t) : _mm256_floor_pd(_mm256_div_pd(x, k.size));
    return _mm256_cvttpd_epi32(f);  // integers within +-1e9: exact
}

/// One pixel the scalar way, read as depth_value reads it: every pixel the
/// AVX2 kernel hands back (a group with a reading the short test cannot
/// take, the rest of a row). Out of line: one copy for both kinds of image.
[[gnu::noinline]] void hit_pixel_at(const HitPlacer& placer, HitSink& sink, const SensorReading& r, std::int32_t u,
                                    std::int32_t v, std::size_t i) noexcept {
    hit_pixel(placer, sink, u, v, depth_value(r, i));
}

/// Four depths from pixel @p i on, and in @p present a bit per present one
/// (a uint16 image's raw 0 is not: depth_value reads it as NaN). A uint16
/// image's depths with depth_value's arithmetic: raw x scale + offset in
/// double, one rounding to float.
CELLGUARD_AVX2_INLINE __m128 avx2_depth4(const SensorReading& r, __m256d scale, __m256d offset, std::size_t i,
                                         unsigned& present) noexcept {
    if (r.kind != SensorDataKind::kDepthImageU16) {
        present = 0xFU;
        return _mm_loadu_ps(r.depth.data() + i);
    }
    std::uint64_t bits = 0U;
    std::memcpy(&bits, r.depth_u16.data() + i, sizeof bits);
    const __m128i r4 = _mm_cvtepu16_epi32(_mm_cvtsi64_si128(static_cast<long long>(bits)));
    present = 0xFU &
              ~static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(r4, _mm_setzero_si128()))));
    return _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(_mm256_cvtepi32_pd(r4), scale), offset));
}

/// Pixels (u .. u + 3, v) from pixel @p i on at depths @p d: when the short
/// test takes all four (present, positive, clearly inside the range limits)
/// they are placed with placement.hpp's operations in its order, four at a
/// time; else each by hit_pixel_at.
CELLGUARD_AVX2_INLINE void avx2_group(const Avx2Sensor& k, const HitPlacer& placer, HitSink& sink,
                                      const SensorReading& r, std::int32_t u, std::int32_t v, std::size_t i, __m128 d,
                                      unsigned present) noexcept {
    const __m256d xn = _mm256_mul_pd(
        _mm256_sub_pd(_mm256_add_pd(_mm256_set1_pd(static_cast<double>(u)), k.lane_offset), k.cx), k.inv_fx);
    const __m256d dd = _mm256_cvtps_pd(d);
    const __m256d range2 = _mm256_mul_pd(_mm256_mul_pd(dd, dd),
                                         _mm256_add_pd(_mm256_mul_pd(xn, xn), _mm256_set1_pd(placer.row_range())));
    const auto inside = static_cast<unsigned>(_mm256_movemask_pd(
        _mm256_and_pd(_mm256_cmp_pd(range2, k.min2_hi, _CMP_GT_OQ), _mm256_cmp_pd(range2, k.max2_lo, _CMP_LT_OQ))));
    // HitPlacer::place's short test; its d <= kMaxSensorRange is implied by the range test
    // (max_range <= kMaxSensorRange; an infinite or NaN depth fails it).
    const unsigned fast = present & static_cast<unsigned>(_mm_movemask_ps(_mm_cmpgt_ps(d, _mm_setzero_ps()))) & inside;
    if (fast != 0xFU) {
        for (std::int32_t j = 0; j < 4; ++j) {
            hit_pixel_at(placer, sink, r, u + j, v, i + static_cast<std::size_t>(j));
        }
        return;
    }
    // pixel_point: x and y in double, rounded to float; cell_point; voxel_of.
    const __m256d px = _mm256_cvtps_pd(_mm256_cvtpd_ps(_mm256_mul_pd(xn, dd)));
    const __m256d py = _mm256_cvtps_pd(_mm256_cvtpd_ps(_mm256_mul_pd(_mm256_set1_pd(placer.row_yn()), dd)));
    const __m128i vx = avx2_voxel(k, avx2_cell(k, 0U, px, py, dd), k.origin[0]);
    const __m128i vy = avx2_voxel(k, avx2_cell(k, 1U, px, py, dd), k.origin[1]);
    const __m128i vz = avx2_voxel(k, avx2_cell(k, 2U, px, py, dd), k.origin[2]);
    // In the grid: 0 <= c < n on each axis; then the index fits (kMaxVoxels < 2^31).
    const __m128i minus1 = _mm_set1_epi32(-1);
    const __m128i in_x = _mm_and_si128(_mm_cmpgt_epi32(vx, minus1), _mm_cmpgt_epi32(k.n_x, vx));
    const __m128i in_y = _mm_and_si128(_mm_cmpgt_epi32(vy, minus1), _mm_cmpgt_epi32(k.n_y, vy));
    const __m128i in_z = _mm_and_si128(_mm_cmpgt_epi32(vz, minus1), _mm_cmpgt_epi32(k.n_z, vz));
    const auto in_grid = static_cast<unsigned>(
        _mm_movemask_ps(_mm_castsi128_ps(_mm_and_si128(_mm_and_si128(in_x, in_y), in_z))));
    const __m128i index = _mm_add_epi32(vx, _mm_mullo_epi32(k.n_x, _mm_add_epi32(vy, _mm_mullo_epi32(k.n_y, vz))));
    // Each lane by a constant index (a register extract, not a store and reload).
    sink.hit((in_grid & 1U) != 0U, static_cast<std::uint32_t>(_mm_extract_epi32(index, 0)));
    sink.hit((in_grid & 2U) != 0U, static_cast<std::uint32_t>(_mm_extract_epi32(index, 1)));
    sink.hit((in_grid & 4U) != 0U, static_cast<std::uint32_t>(_mm_extract_epi32(index, 2)));
    sink.hit((in_grid & 8U) != 0U, static_cast<std::uint32_t>(_mm_extract_epi32(index, 3)));
    std::array<float, 4> four{};
    _mm_storeu_ps(four.data(), d);
    sink.valid4(u, v, four);
}

/// FusionKernel::kAvx2 for either kind of image (one copy of the kernel):
/// four pixels at a time (avx2_group), the rest of each row one at a time; a
/// camera whose readings may lie beyond +-1e9 voxels (HitPlacer::far) goes
/// the scalar way throughout. Called only where the CPU has AVX2.
__attribute__((target("avx2"))) FusionStats hit_pass_avx2(const GridGeometry& g, const SensorReading& r,
                                                          std::int16_t hit, DepthPyramid& pyramid,
                                                          Span<std::int16_t> opinions) noexcept {
    HitPlacer placer(g, r);
    HitSink sink(g, hit, pyramid, opinions);
    const std::int32_t w = r.intrinsics.width;
    const std::int32_t groups = placer.far() ? 0 : w / 4;  // far: every pixel the scalar way
    const Avx2Sensor k = avx2_sensor(placer, r);
    const __m256d scale = _mm256_set1_pd(static_cast<double>(r.depth_scale));
    const __m256d offset = _mm256_set1_pd(static_cast<double>(r.depth_offset));
    std::size_t i = 0U;
    for (std::int32_t v = 0; v < r.intrinsics.height; ++v) {
        placer.begin_row(v);
        std::int32_t u = 0;
        for (; u < 4 * groups; u += 4, i += 4U) {
            unsigned present = 0U;
            const __m128 d = avx2_depth4(r, scale, offset, i, present);
            avx2_group(k, placer, sink, r, u, v, i, d, present);
        }
        for (; u < w; ++u, ++i) {
            hit_pixel_at(placer, sink, r, u, v, i);
        }
    }
    return sink.stats();
}
#endif

}  // namespace

FusionStats hit_pass(const GridGeometry& g, const SensorReading& r, std::int16_t hit, DepthPyramid& pyramid,
                     Span<std::int16_t> opinions, FusionKernel kernel) noexcept {
    switch (resolve_fusion_kernel(kernel)) {
#if CELLGUARD_HIT_AVX2
        case FusionKernel::kAvx2: return hit_pass_avx2(g, r, hit, pyramid, opinions);
#endif
        default: break;
    }
    if (r.kind == SensorDataKind::kDepthImageU16) {
        return hit_rows(g, r, hit, pyramid, opinions, U16Depth{&r});
    }
    return hit_rows(g, r, hit, pyramid, opinions, FloatDepth{r.depth.data()});
}

}  // namespace detail
}  // namespace cellguard
