// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/ground_truth.hpp"

#include <algorithm>

namespace cellguard::sim {

namespace {
constexpr std::uint8_t kSeenEmpty = 1U;
constexpr std::uint8_t kHitBackground = 2U;
constexpr std::uint8_t kHitForeground = 4U;
constexpr std::uint8_t kHitRobot = 8U;

// The point @p i (0..26) of the 3 x 3 x 3 lattice of voxel @p c: corners, edge and face centres, centre.
Eigen::Vector3d lattice_point(const GridGeometry& g, const VoxelCoord& c, int i) {
    const Eigen::Vector3d lo = g.origin() + g.voxel_size() * Eigen::Vector3d(c.x, c.y, c.z);
    const double half = 0.5 * g.voxel_size();
    const int ix = i % 3;
    const int iy = (i / 3) % 3;
    const int iz = i / 9;
    return lo + half * Eigen::Vector3d(ix, iy, iz);
}

bool overlaps_robot(const GridGeometry& g, const Scene& scene, const VoxelCoord& c) {
    const std::size_t n = std::min<std::size_t>(scene.robot.count, kMaxRobotCapsules);
    for (std::size_t k = 0; k < n; ++k) {
        for (int i = 0; i < 27; ++i) {
            if (capsule_contains(scene.robot.capsules[k], lattice_point(g, c, i))) {
                return true;
            }
        }
    }
    return false;
}

bool overlaps_foreground(const GridGeometry& g, const Scene& scene, const VoxelCoord& c) {
    const Eigen::Vector3d lo = g.origin() + g.voxel_size() * Eigen::Vector3d(c.x, c.y, c.z);
    const double half = 0.5 * g.voxel_size();
    for (const Box& b : scene.boxes) {
        if (b.background) {
            continue;
        }
        for (int i = 0; i < 27; ++i) {  // the 3 x 3 x 3 lattice of corners, edge and face centres, centre
            const int ix = i % 3;
            const int iy = (i / 3) % 3;
            const int iz = i / 9;
            const Eigen::Vector3d p = lo + half * Eigen::Vector3d(ix, iy, iz);
            if (box_contains(b, p)) {
                return true;
            }
        }
    }
    return false;
}
}  // namespace

GroundTruth ideal_ground_truth(const GridGeometry& g, const std::vector<SensorSpec>& sensors, const Scene& scene,
                               Rasterization rasterization) {
    std::vector<std::uint8_t> seen(g.voxel_count(), 0U);
    const PreparedScene prepared(scene);
    for (const SensorSpec& sensor : sensors) {
        const PinholeIntrinsics k = sensor.intrinsics();
        const Eigen::Isometry3d pose = sensor.pose();
        const Eigen::Vector3d origin = pose.translation();
        for (std::int32_t v = 0; v < k.height; ++v) {
            for (std::int32_t u = 0; u < k.width; ++u) {
                // The same ray as render_depth's.
                const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
                const Eigen::Vector3d dir = (pose.linear() * ray_cam).normalized();
                const RayHit hit = prepared.cast(origin, dir);
                if (!std::isfinite(hit.distance) || hit.distance > static_cast<double>(sensor.max_range)) {
                    continue;
                }
                const Eigen::Vector3d end = origin + hit.distance * dir;
                const bool foreground = hit.box >= 0 && !scene.boxes[static_cast<std::size_t>(hit.box)].background;
                const std::uint8_t hit_flag = foreground ? kHitForeground
                                                         : (hit.capsule >= 0 ? kHitRobot : kHitBackground);
                const Result<VoxelCoord> end_voxel = g.world_to_voxel(end);
                const bool end_inside = end_voxel.ok();
                const std::size_t end_index = end_inside ? g.index_of(end_voxel.value()) : 0U;
                traverse(rasterization, g, origin, end, [&](const TraversedVoxel& tv) {
                    if (!(end_inside && tv.index == end_index)) {
                        seen[tv.index] = static_cast<std::uint8_t>(seen[tv.index] | kSeenEmpty);
                    }
                });
                if (end_inside) {
                    seen[end_index] = static_cast<std::uint8_t>(seen[end_index] | hit_flag);
                }
            }
        }
    }
    GroundTruth t;
    t.label.assign(g.voxel_count(), Truth::kNotForeground);
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        if ((seen[i] & kHitForeground) != 0U) {
            t.label[i] = Truth::kForeground;
            ++t.foreground;
        } else if (seen[i] == 0U && overlaps_foreground(g, scene, g.coord_of(i))) {
            t.label[i] = Truth::kUnknown;
            ++t.unknown;
        } else if ((seen[i] & kHitRobot) != 0U || (seen[i] == 0U && overlaps_robot(g, scene, g.coord_of(i)))) {
            // A reading on the robot, or the robot's unseen inside.
            t.label[i] = Truth::kRobot;
            ++t.robot;
        } else {
            ++t.not_foreground;
        }
    }
    return t;
}

std::vector<std::uint8_t> background_interior_mask(const GridGeometry& g, const Scene& scene, double margin) {
    std::vector<std::uint8_t> mask(g.voxel_count(), 0U);
    const double extent = g.voxel_size() + 2.0 * margin;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        const VoxelCoord c = g.coord_of(i);
        const Eigen::Vector3d lo = g.origin() + g.voxel_size() * Eigen::Vector3d(c.x, c.y, c.z) -
                                   Eigen::Vector3d::Constant(margin);
        for (const Box& b : scene.boxes) {
            if (!b.background) {
                continue;
            }
            bool inside = true;
            for (unsigned k = 0U; k < 8U && inside; ++k) {  // the eight corners
                const Eigen::Vector3d p = lo + extent * Eigen::Vector3d(k & 1U, (k >> 1U) & 1U, (k >> 2U) & 1U);
                inside = box_contains(b, p);
            }
            if (inside) {
                mask[i] = 1U;
                break;
            }
        }
    }
    return mask;
}

}  // namespace cellguard::sim
