// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file reading_class.hpp
/// Private to the grid module: how every fusion path (fusion.cpp,
/// footprint_fusion.cpp) decides whether a reading is fused or skipped, and
/// counts the skipped ones. One implementation, so the paths skip the same
/// readings.
#ifndef CELLGUARD_GRID_READING_CLASS_HPP
#define CELLGUARD_GRID_READING_CLASS_HPP

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "cellguard/grid/fusion.hpp"

namespace cellguard::detail {

/// Why a reading is fused or skipped.
enum class ReadingClass : std::uint8_t { kValid, kNan, kInfinite, kZero, kBehind, kOutOfRange };

/// A sensor-frame point: NaN, infinite, at the origin, behind the sensor, out of range, or valid.
inline ReadingClass classify_point(const Eigen::Vector3f& p, float min_range, float max_range) noexcept {
    if (std::isnan(p.x()) || std::isnan(p.y()) || std::isnan(p.z())) {
        return ReadingClass::kNan;
    }
    if (std::isinf(p.x()) || std::isinf(p.y()) || std::isinf(p.z())) {
        return ReadingClass::kInfinite;
    }
    if (p.x() == 0.0F && p.y() == 0.0F && p.z() == 0.0F) {
        return ReadingClass::kZero;
    }
    if (p.z() < 0.0F) {
        return ReadingClass::kBehind;
    }
    const float range = p.norm();
    if (range < min_range || range > max_range) {
        return ReadingClass::kOutOfRange;
    }
    return ReadingClass::kValid;
}

/// A raw depth-image value, before it becomes a point (0 * inf would hide an infinity as NaN).
inline ReadingClass classify_depth(float d) noexcept {
    return std::isnan(d)   ? ReadingClass::kNan
           : std::isinf(d) ? ReadingClass::kInfinite
           : d == 0.0F     ? ReadingClass::kZero
           : d < 0.0F      ? ReadingClass::kBehind
                           : ReadingClass::kValid;
}

/// Counts a skipped reading in @p s (kValid counts nothing).
inline void count_skipped(FusionStats& s, ReadingClass c) noexcept {
    switch (c) {
        case ReadingClass::kValid: break;
        case ReadingClass::kNan: ++s.skipped_nan; break;
        case ReadingClass::kInfinite: ++s.skipped_infinite; break;
        case ReadingClass::kZero: ++s.skipped_zero; break;
        case ReadingClass::kBehind: ++s.skipped_behind; break;
        case ReadingClass::kOutOfRange: ++s.skipped_out_of_range; break;
    }
}

}  // namespace cellguard::detail

#endif  // CELLGUARD_GRID_READING_CLASS_HPP
