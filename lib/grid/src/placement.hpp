// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file placement.hpp
/// Private to the grid module: where a depth pixel's reading lies, the one
/// rule of every fusion path (fusion.cpp, ray_table.cpp,
/// footprint_fusion.cpp). Inline, so the pixel loops run it without a call;
/// the grid module is compiled with -ffp-contract=off (lib/CMakeLists.txt),
/// so each expression rounds the same in every caller and on every target
/// (no fused multiply-add), and a reading on a voxel face lands in the same
/// voxel on every path.
#ifndef CELLGUARD_GRID_PLACEMENT_HPP
#define CELLGUARD_GRID_PLACEMENT_HPP

#include <Eigen/Geometry>
#include <cstdint>

#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_frame.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cellguard::detail {

/// The point of depth pixel (@p u, @p v) at depth @p d in the sensor frame:
/// x = (u - cx) * inv_fx * d and y = (v - cy) * inv_fy * d in double,
/// rounded to float, z = d.
inline Eigen::Vector3f pixel_point(const PinholeIntrinsics& k, double inv_fx, double inv_fy, std::int32_t u,
                                   std::int32_t v, float d) noexcept {
    const double rx = (static_cast<double>(u) - k.cx) * inv_fx;
    const double ry = (static_cast<double>(v) - k.cy) * inv_fy;
    return {static_cast<float>(rx * static_cast<double>(d)), static_cast<float>(ry * static_cast<double>(d)), d};
}

/// A sensor-frame point @p p in the cell frame, pose * p in double, each
/// coordinate summed left to right: ((r0 px + r1 py) + r2 pz) + t (the
/// order Eigen's fixed-size product takes, written out so that it is fixed).
inline Eigen::Vector3d cell_point(const Eigen::Isometry3d& pose, const Eigen::Vector3f& p) noexcept {
    const Eigen::Matrix4d& m = pose.matrix();
    const auto x = static_cast<double>(p.x());
    const auto y = static_cast<double>(p.y());
    const auto z = static_cast<double>(p.z());
    return {((m(0, 0) * x + m(0, 1) * y) + m(0, 2) * z) + m(0, 3),
            ((m(1, 0) * x + m(1, 1) * y) + m(1, 2) * z) + m(1, 3),
            ((m(2, 0) * x + m(2, 1) * y) + m(2, 2) * z) + m(2, 3)};
}

/// GridGeometry::world_to_voxel_unchecked(@p q), bit for bit: with SSE2,
/// x and y divided and floored in one register (the same IEEE quotients);
/// elsewhere that function itself. Each scaled coordinate within +-2^31.
inline VoxelCoord voxel_of(const GridGeometry& g, const Eigen::Vector3d& q) noexcept {
#if defined(__SSE2__)
    const Eigen::Vector3d& o = g.origin();
    const __m128d s = _mm_div_pd(_mm_sub_pd(_mm_set_pd(q.y(), q.x()), _mm_set_pd(o.y(), o.x())),
                                 _mm_set1_pd(g.voxel_size()));
    const __m128i t = _mm_cvttpd_epi32(s);  // truncation, as static_cast<std::int32_t>
    // One less where truncation rounded up (t > s: a negative non-integer); the mask is -1 there.
    const __m128i up = _mm_castpd_si128(_mm_cmpgt_pd(_mm_cvtepi32_pd(t), s));
    const __m128i f = _mm_add_epi32(t, _mm_shuffle_epi32(up, _MM_SHUFFLE(3, 3, 2, 0)));
    return VoxelCoord{_mm_cvtsi128_si32(f), _mm_cvtsi128_si32(_mm_shuffle_epi32(f, _MM_SHUFFLE(1, 1, 1, 1))),
                      GridGeometry::floor_index((q.z() - o.z()) / g.voxel_size())};
#else
    return g.world_to_voxel_unchecked(q);
#endif
}

}  // namespace cellguard::detail

#endif  // CELLGUARD_GRID_PLACEMENT_HPP
