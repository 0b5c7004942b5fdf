// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/robot/robot_mask.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace cellguard {

namespace {

/// sqrt(3) / 2: half a voxel's diagonal, per metre of voxel edge.
constexpr double kHalfDiagonal = 0.8660254037844386;
/// 1 / sqrt(3): the largest share of a segment's length on each axis when all three are equal.
constexpr double kInvSqrt3 = 0.5773502691896258;

bool pose_finite(const RobotPose& pose) noexcept {
    for (std::size_t c = 0U; c < pose.count; ++c) {
        const PlacedCapsule& p = pose.capsules[c];
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(p.a[k]) || !std::isfinite(p.b[k])) {
                return false;
            }
        }
        if (!std::isfinite(p.radius) || p.radius < 0.0) {
            return false;
        }
    }
    return true;
}

/// The voxel range [lo, hi] along one axis whose cells meet [min, max]
/// (metres), clipped to [0, n - 1]; false when it is empty.
bool axis_range(double min, double max, double origin, double size, std::int32_t n, std::int32_t& lo,
                std::int32_t& hi) noexcept {
    const double a = std::floor((min - origin) / size);
    const double b = std::floor((max - origin) / size);
    if (b < 0.0 || a > static_cast<double>(n - 1)) {
        return false;
    }
    lo = a < 0.0 ? 0 : static_cast<std::int32_t>(a);
    hi = b > static_cast<double>(n - 1) ? n - 1 : static_cast<std::int32_t>(b);
    return true;
}

/// Marks the voxels of @p grid whose centres lie within @p reach of the
/// segment of @p cap; returns the voxel tests made.
std::uint64_t mark_capsule(const GridGeometry& grid, const PlacedCapsule& cap, double reach, Span<std::uint8_t> mask,
                           std::uint32_t& marked) noexcept {
    const double s = grid.voxel_size();
    const GridDims dims = grid.dims();
    const Eigen::Vector3d& o = grid.origin();
    std::int32_t lo[3] = {0, 0, 0};
    std::int32_t hi[3] = {0, 0, 0};
    const std::int32_t n[3] = {dims.nx, dims.ny, dims.nz};
    for (int k = 0; k < 3; ++k) {
        const double min = std::fmin(cap.a[k], cap.b[k]) - reach;
        const double max = std::fmax(cap.a[k], cap.b[k]) + reach;
        if (!axis_range(min, max, o(k), s, n[k], lo[k], hi[k])) {
            return 0U;
        }
    }
    const double dx = cap.b[0] - cap.a[0];
    const double dy = cap.b[1] - cap.a[1];
    const double dz = cap.b[2] - cap.a[2];
    const double dd = dx * dx + dy * dy + dz * dz;
    const double reach2 = reach * reach;
    const auto nx = static_cast<std::size_t>(dims.nx);
    const auto ny = static_cast<std::size_t>(dims.ny);
    for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
        const double wz = o(2) + s * (static_cast<double>(z) + 0.5) - cap.a[2];
        for (std::int32_t y = lo[1]; y <= hi[1]; ++y) {
            const double wy = o(1) + s * (static_cast<double>(y) + 0.5) - cap.a[1];
            // Along the row only w's x part changes: dot(w, d) and |w|^2 split into a constant and an x term.
            const double dot_yz = wy * dy + wz * dz;
            const double w2_yz = wy * wy + wz * wz;
            std::uint8_t* row = mask.data() + nx * (static_cast<std::size_t>(y) + ny * static_cast<std::size_t>(z));
            for (std::int32_t x = lo[0]; x <= hi[0]; ++x) {
                const double wx = o(0) + s * (static_cast<double>(x) + 0.5) - cap.a[0];
                const double dot = wx * dx + dot_yz;
                const double w2 = wx * wx + w2_yz;
                // Squared distance to the segment: to a (t <= 0), to b (t >= 1), else to the line.
                double dist2 = w2;
                if (dot >= dd) {
                    dist2 = w2 - 2.0 * dot + dd;
                } else if (dot > 0.0) {
                    dist2 = w2 - dot * (dot / dd);
                }
                if (dist2 <= reach2 && row[x] == 0U) {
                    row[x] = 1U;
                    ++marked;
                }
            }
        }
    }
    return static_cast<std::uint64_t>(hi[0] - lo[0] + 1) * static_cast<std::uint64_t>(hi[1] - lo[1] + 1) *
           static_cast<std::uint64_t>(hi[2] - lo[2] + 1);
}

}  // namespace

Status mark_robot_voxels(const GridGeometry& grid, const RobotPose& pose, double margin_m, Span<std::uint8_t> mask,
                         RobotMaskStats& stats) noexcept {
    stats = RobotMaskStats{};
    const std::size_t n = grid.voxel_count();
    if (mask.size() < n) {
        return ErrorCode::kStorageTooSmall;
    }
    if (!std::isfinite(margin_m) || margin_m < 0.0 || pose.count > kMaxRobotCapsules || !pose_finite(pose)) {
        std::memset(mask.data(), 1, n);
        stats.marked = static_cast<std::uint32_t>(n);  // n <= kMaxVoxels < 2^32
        return ErrorCode::kInvalidArgument;
    }
    std::memset(mask.data(), 0, n);
    const double grow = margin_m + kHalfDiagonal * grid.voxel_size();
    for (std::size_t c = 0U; c < pose.count; ++c) {
        stats.tested += mark_capsule(grid, pose.capsules[c], pose.capsules[c].radius + grow, mask, stats.marked);
    }
    return Status{};
}

std::uint64_t robot_mask_work_bound(const RobotModel& model, double margin_m, double voxel_size_m) noexcept {
    if (!std::isfinite(margin_m) || margin_m < 0.0 || !std::isfinite(voxel_size_m) || !(voxel_size_m > 0.0) ||
        model.capsule_count > kMaxRobotCapsules) {
        return 0U;
    }
    double total = 0.0;
    for (std::size_t c = 0U; c < model.capsule_count; ++c) {
        const RobotCapsule& cap = model.capsules[c];
        double len2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            len2 += (cap.b[k] - cap.a[k]) * (cap.b[k] - cap.a[k]);
        }
        // Per axis: the box's extent in voxels (the segment's share in the worst orientation, all three axes
        // equal, plus twice the grown radius) and 2 for the cells the box's ends fall in; the rounding of the
        // placed ends (a few ulps) is covered by the relative slack.
        const double reach = cap.radius + margin_m + kHalfDiagonal * voxel_size_m;
        const double per_axis = ((std::sqrt(len2) * kInvSqrt3 + 2.0 * reach) / voxel_size_m) * (1.0 + 1e-9) + 2.0;
        total += per_axis * per_axis * per_axis;
    }
    return total >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(std::ceil(total));
}

}  // namespace cellguard
