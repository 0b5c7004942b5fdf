// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "render.hpp"

#include <cmath>

#include "cellguard/grid/ray_traversal.hpp"

namespace cellguard::eval {

namespace {
// Palette: 0 white; per class (background, foreground, floor) three face
// shades (top, x side, y side) and an edge colour.
constexpr std::uint8_t kWhite = 0U;
constexpr std::uint8_t kFirstShade = 1U;  // 1 + 4 * (class - 1) + shade (0..2), edge at shade 3

std::vector<std::array<std::uint8_t, 3>> palette() {
    return {
        {255, 255, 255},                                                     // background of the image
        {200, 200, 200}, {165, 165, 165}, {135, 135, 135}, {80, 80, 80},     // background voxels
        {235, 45, 35},   {195, 30, 25},   {155, 20, 20},   {95, 10, 10},     // foreground voxels
        {232, 232, 224}, {215, 215, 206}, {200, 200, 192}, {185, 185, 176},  // floor
    };
}
}  // namespace

IndexedImage render_voxels(const GridGeometry& g, const std::vector<VoxelClass>& classes, const sim::SensorSpec& camera,
                           int width, int height) {
    sim::SensorSpec cam = camera;
    cam.width = width;
    cam.height = height;
    const PinholeIntrinsics k = cam.intrinsics();
    const Eigen::Isometry3d pose = cam.pose();
    const Eigen::Vector3d origin = pose.translation();
    IndexedImage img;
    img.width = width;
    img.height = height;
    img.palette = palette();
    img.pixels.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), kWhite);
    const double s = g.voxel_size();
    for (int v = 0; v < height; ++v) {
        for (int u = 0; u < width; ++u) {
            const Eigen::Vector3d dir =
                (pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0)).normalized();
            const Eigen::Vector3d end = origin + 20.0 * dir;
            bool done = false;
            std::uint8_t colour = kWhite;
            traverse_segment(g, origin, end, [&](const TraversedVoxel& tv) {
                if (done) {
                    return;
                }
                const VoxelClass c = classes[tv.index];
                if (c == VoxelClass::kEmpty) {
                    return;
                }
                done = true;
                // The entry point in voxel units, relative to the voxel's corner.
                const Eigen::Vector3d p = (origin + tv.t_enter * dir - g.origin()) / s -
                                          Eigen::Vector3d(tv.coord.x, tv.coord.y, tv.coord.z);
                // The entered face: the coordinate nearest to 0 or 1.
                int axis = 0;
                double best = 2.0;
                double frac[3];
                for (int a = 0; a < 3; ++a) {
                    frac[a] = std::fmin(std::fabs(p[a]), std::fabs(1.0 - p[a]));
                    if (frac[a] < best) {
                        best = frac[a];
                        axis = a;
                    }
                }
                const int shade = axis == 2 ? 0 : (axis == 0 ? 1 : 2);
                bool edge = false;
                for (int a = 0; a < 3; ++a) {
                    edge = edge || (a != axis && frac[a] < 0.06);
                }
                const int cls = static_cast<int>(c) - 1;
                colour = static_cast<std::uint8_t>(kFirstShade + 4 * cls + (edge ? 3 : shade));
            });
            img.pixels[static_cast<std::size_t>(v) * static_cast<std::size_t>(width) + static_cast<std::size_t>(u)] =
                colour;
        }
    }
    return img;
}

}  // namespace cellguard::eval
