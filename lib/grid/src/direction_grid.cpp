// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/direction_grid.hpp"

#include <cmath>

#include "cellguard/base/saturating.hpp"

namespace cellguard {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kEdgeSlack = 1e-5;  ///< radians: the float edges' rounding

/// True when [min, min + bins x bin] lies inside [-limit, limit] (with slack).
bool span_inside(float min, float bin, std::uint32_t bins, double limit) noexcept {
    const auto lo = static_cast<double>(min);
    const double hi = lo + static_cast<double>(bins) * static_cast<double>(bin);
    return lo >= -limit - kEdgeSlack && hi <= limit + kEdgeSlack;
}

}  // namespace

Status check_direction_grid(const DirectionGrid& grid) noexcept {
    if (!std::isfinite(grid.azimuth_min_rad) || !std::isfinite(grid.elevation_min_rad) ||
        !std::isfinite(grid.bin_rad)) {
        return ErrorCode::kNonFiniteValue;
    }
    if (!(grid.bin_rad > 0.0F) || grid.azimuth_bins == 0U || grid.elevation_bins == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (grid.bin_count() > kMaxDirectionBins) {
        return ErrorCode::kCapacityExceeded;
    }
    if (!span_inside(grid.azimuth_min_rad, grid.bin_rad, grid.azimuth_bins, kPi) ||
        !span_inside(grid.elevation_min_rad, grid.bin_rad, grid.elevation_bins, kPi / 2.0)) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

std::size_t direction_bin(const DirectionGrid& grid, const Eigen::Vector3f& p, float& range) noexcept {
    range = 0.0F;
    if (!p.allFinite()) {
        return kNoDirectionBin;
    }
    const float horizontal = std::sqrt(p.x() * p.x() + p.z() * p.z());
    const float r = std::sqrt(horizontal * horizontal + p.y() * p.y());
    if (!(r > 0.0F) || !std::isfinite(r)) {
        return kNoDirectionBin;
    }
    range = r;
    // Bin coordinates as floats first: a comparison, not a cast, decides
    // whether the point is inside (no out-of-range float-to-int conversion).
    const float a = (std::atan2(p.x(), p.z()) - grid.azimuth_min_rad) / grid.bin_rad;
    const float e = (std::atan2(-p.y(), horizontal) - grid.elevation_min_rad) / grid.bin_rad;
    if (!(a >= 0.0F) || !(e >= 0.0F) || !(a < static_cast<float>(grid.azimuth_bins)) ||
        !(e < static_cast<float>(grid.elevation_bins))) {
        return kNoDirectionBin;
    }
    // a < azimuth_bins as a float can still round to azimuth_bins: clamp.
    const auto column = static_cast<std::uint32_t>(a);
    const auto row = static_cast<std::uint32_t>(e);
    const std::uint32_t c = column < grid.azimuth_bins ? column : grid.azimuth_bins - 1U;
    const std::uint32_t w = row < grid.elevation_bins ? row : grid.elevation_bins - 1U;
    return static_cast<std::size_t>(w) * grid.azimuth_bins + c;
}

Result<DirectionViewAdded> add_to_direction_view(Span<const Eigen::Vector3f> points, const DirectionGrid& grid,
                                                 Span<float> farthest, Span<float> nearest) noexcept {
    const Status ok = check_direction_grid(grid);
    if (!ok.ok()) {
        return ok.error();
    }
    if (farthest.size() != grid.bin_count() || nearest.size() != grid.bin_count()) {
        return ErrorCode::kMalformedInput;
    }
    DirectionViewAdded added;
    for (const Eigen::Vector3f& p : points) {
        float r = 0.0F;
        const std::size_t bin = direction_bin(grid, p, r);
        if (bin == kNoDirectionBin) {
            std::uint32_t& count = r > 0.0F ? added.outside : added.invalid;
            count = saturating_increment(count);
            continue;
        }
        const bool empty = !(farthest[bin] > 0.0F);
        farthest[bin] = empty || r > farthest[bin] ? r : farthest[bin];
        nearest[bin] = empty || r < nearest[bin] ? r : nearest[bin];
        added.binned = saturating_increment(added.binned);
    }
    return added;
}

}  // namespace cellguard
