// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The configuration picture: top view and one sensor's view of the grid,
// the background and the zones (picture.hpp).
#include "cellguard/monitor/picture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <utility>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/grid/ray_traversal.hpp"

namespace cellguard::monitor {
namespace {

// 5 x 7 font (ASCII 32..126), five columns per character, bit 0 the top row
// (bit 7 for descenders). The glyphs are Adafruit's glcdfont, byte for byte
// (Adafruit GFX Library, BSD-2-Clause; see NOTICE and .reuse/dep5).
constexpr std::uint8_t kFont[95][5] = {
    {0x00, 0x00, 0x00, 0x00, 0x00}, {0x00, 0x00, 0x5F, 0x00, 0x00}, {0x00, 0x07, 0x00, 0x07, 0x00},
    {0x14, 0x7F, 0x14, 0x7F, 0x14}, {0x24, 0x2A, 0x7F, 0x2A, 0x12}, {0x23, 0x13, 0x08, 0x64, 0x62},
    {0x36, 0x49, 0x56, 0x20, 0x50}, {0x00, 0x08, 0x07, 0x03, 0x00}, {0x00, 0x1C, 0x22, 0x41, 0x00},
    {0x00, 0x41, 0x22, 0x1C, 0x00}, {0x2A, 0x1C, 0x7F, 0x1C, 0x2A}, {0x08, 0x08, 0x3E, 0x08, 0x08},
    {0x00, 0x80, 0x70, 0x30, 0x00}, {0x08, 0x08, 0x08, 0x08, 0x08}, {0x00, 0x00, 0x60, 0x60, 0x00},
    {0x20, 0x10, 0x08, 0x04, 0x02}, {0x3E, 0x51, 0x49, 0x45, 0x3E}, {0x00, 0x42, 0x7F, 0x40, 0x00},
    {0x72, 0x49, 0x49, 0x49, 0x46}, {0x21, 0x41, 0x49, 0x4D, 0x33}, {0x18, 0x14, 0x12, 0x7F, 0x10},
    {0x27, 0x45, 0x45, 0x45, 0x39}, {0x3C, 0x4A, 0x49, 0x49, 0x31}, {0x41, 0x21, 0x11, 0x09, 0x07},
    {0x36, 0x49, 0x49, 0x49, 0x36}, {0x46, 0x49, 0x49, 0x29, 0x1E}, {0x00, 0x00, 0x14, 0x00, 0x00},
    {0x00, 0x40, 0x34, 0x00, 0x00}, {0x00, 0x08, 0x14, 0x22, 0x41}, {0x14, 0x14, 0x14, 0x14, 0x14},
    {0x00, 0x41, 0x22, 0x14, 0x08}, {0x02, 0x01, 0x59, 0x09, 0x06}, {0x3E, 0x41, 0x5D, 0x59, 0x4E},
    {0x7C, 0x12, 0x11, 0x12, 0x7C}, {0x7F, 0x49, 0x49, 0x49, 0x36}, {0x3E, 0x41, 0x41, 0x41, 0x22},
    {0x7F, 0x41, 0x41, 0x41, 0x3E}, {0x7F, 0x49, 0x49, 0x49, 0x41}, {0x7F, 0x09, 0x09, 0x09, 0x01},
    {0x3E, 0x41, 0x41, 0x51, 0x73}, {0x7F, 0x08, 0x08, 0x08, 0x7F}, {0x00, 0x41, 0x7F, 0x41, 0x00},
    {0x20, 0x40, 0x41, 0x3F, 0x01}, {0x7F, 0x08, 0x14, 0x22, 0x41}, {0x7F, 0x40, 0x40, 0x40, 0x40},
    {0x7F, 0x02, 0x1C, 0x02, 0x7F}, {0x7F, 0x04, 0x08, 0x10, 0x7F}, {0x3E, 0x41, 0x41, 0x41, 0x3E},
    {0x7F, 0x09, 0x09, 0x09, 0x06}, {0x3E, 0x41, 0x51, 0x21, 0x5E}, {0x7F, 0x09, 0x19, 0x29, 0x46},
    {0x26, 0x49, 0x49, 0x49, 0x32}, {0x03, 0x01, 0x7F, 0x01, 0x03}, {0x3F, 0x40, 0x40, 0x40, 0x3F},
    {0x1F, 0x20, 0x40, 0x20, 0x1F}, {0x3F, 0x40, 0x38, 0x40, 0x3F}, {0x63, 0x14, 0x08, 0x14, 0x63},
    {0x03, 0x04, 0x78, 0x04, 0x03}, {0x61, 0x59, 0x49, 0x4D, 0x43}, {0x00, 0x7F, 0x41, 0x41, 0x41},
    {0x02, 0x04, 0x08, 0x10, 0x20}, {0x00, 0x41, 0x41, 0x41, 0x7F}, {0x04, 0x02, 0x01, 0x02, 0x04},
    {0x40, 0x40, 0x40, 0x40, 0x40}, {0x00, 0x03, 0x07, 0x08, 0x00}, {0x20, 0x54, 0x54, 0x78, 0x40},
    {0x7F, 0x28, 0x44, 0x44, 0x38}, {0x38, 0x44, 0x44, 0x44, 0x28}, {0x38, 0x44, 0x44, 0x28, 0x7F},
    {0x38, 0x54, 0x54, 0x54, 0x18}, {0x00, 0x08, 0x7E, 0x09, 0x02}, {0x18, 0xA4, 0xA4, 0x9C, 0x78},
    {0x7F, 0x08, 0x04, 0x04, 0x78}, {0x00, 0x44, 0x7D, 0x40, 0x00}, {0x20, 0x40, 0x40, 0x3D, 0x00},
    {0x7F, 0x10, 0x28, 0x44, 0x00}, {0x00, 0x41, 0x7F, 0x40, 0x00}, {0x7C, 0x04, 0x78, 0x04, 0x78},
    {0x7C, 0x08, 0x04, 0x04, 0x78}, {0x38, 0x44, 0x44, 0x44, 0x38}, {0xFC, 0x18, 0x24, 0x24, 0x18},
    {0x18, 0x24, 0x24, 0x18, 0xFC}, {0x7C, 0x08, 0x04, 0x04, 0x08}, {0x48, 0x54, 0x54, 0x54, 0x24},
    {0x04, 0x04, 0x3F, 0x44, 0x24}, {0x3C, 0x40, 0x40, 0x20, 0x7C}, {0x1C, 0x20, 0x40, 0x20, 0x1C},
    {0x3C, 0x40, 0x30, 0x40, 0x3C}, {0x44, 0x28, 0x10, 0x28, 0x44}, {0x4C, 0x90, 0x90, 0x90, 0x7C},
    {0x44, 0x64, 0x54, 0x4C, 0x44}, {0x00, 0x08, 0x36, 0x41, 0x00}, {0x00, 0x00, 0x77, 0x00, 0x00},
    {0x00, 0x41, 0x36, 0x08, 0x00}, {0x02, 0x01, 0x02, 0x04, 0x02},
};

constexpr PictureColour kBlack{0, 0, 0};
constexpr PictureColour kText{20, 20, 20};
constexpr PictureColour kFree{255, 255, 255};
constexpr PictureColour kOutside{70, 75, 90};
constexpr PictureColour kPanel{250, 250, 250};
constexpr PictureColour kGridLine{215, 215, 225};
constexpr int kTextScale = 2;
constexpr int kLineHeight = 8 * kTextScale + 4;
constexpr int kMargin = 16;

void put(RgbImage& img, int x, int y, PictureColour c) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) {
        return;
    }
    const std::size_t o = img.offset(x, y);
    img.rgb[o] = c.r;
    img.rgb[o + 1U] = c.g;
    img.rgb[o + 2U] = c.b;
}

PictureColour get(const RgbImage& img, int x, int y) {
    const std::size_t o = img.offset(x, y);
    return PictureColour{img.rgb[o], img.rgb[o + 1U], img.rgb[o + 2U]};
}

std::uint8_t mix(double a, double b, double t) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(a + (b - a) * t, 0.0, 255.0)));
}

PictureColour blend(PictureColour under, PictureColour over, double alpha) {
    return PictureColour{mix(under.r, over.r, alpha), mix(under.g, over.g, alpha), mix(under.b, over.b, alpha)};
}

PictureColour grey(double v) {
    const auto g = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
    return PictureColour{g, g, g};
}

void fill_rect(RgbImage& img, int x, int y, int w, int h, PictureColour c) {
    for (int j = y; j < y + h; ++j) {
        for (int i = x; i < x + w; ++i) {
            put(img, i, j, c);
        }
    }
}

void frame_rect(RgbImage& img, int x, int y, int w, int h, int t, PictureColour c) {
    fill_rect(img, x - t, y - t, w + 2 * t, t, c);
    fill_rect(img, x - t, y + h, w + 2 * t, t, c);
    fill_rect(img, x - t, y, t, h, c);
    fill_rect(img, x + w, y, t, h, c);
}

PictureColour zone_colour(const ZoneConfig& z) {
    return z.kind == ZoneKind::kProtective ? kProtectiveColour : kWarningColour;
}

/// Darker variant of a zone colour for its borders and edges.
PictureColour edge_colour(const ZoneConfig& z) {
    return z.kind == ZoneKind::kProtective ? PictureColour{150, 0, 0} : PictureColour{170, 120, 0};
}

bool is_background(const PictureInput& in, std::size_t i) {
    const std::int16_t p = in.prior[i];
    return p == kNeverForeground || p < in.accessible_min_prior;
}

/// Draws text with a white box behind it (labels over the drawing).
void label(RgbImage& img, int x, int y, const std::string& text, PictureColour colour, int scale) {
    const int w = static_cast<int>(text.size()) * 6 * scale + scale;
    fill_rect(img, x - scale, y - scale, w + scale, 8 * scale + scale, kFree);
    draw_text(img, x, y, text, colour, scale);
}

/// "(a, b)" with two decimals.
std::string pair_text(double a, double b) {
    char buf[64];
    static_cast<void>(std::snprintf(buf, sizeof buf, "(%.2f, %.2f)", a, b));
    return buf;
}

// ---- robot ----------------------------------------------------------------

/// The distance from floor point @p p to capsule @p c's segment projected onto the floor.
double floor_segment_distance(const Eigen::Vector2d& p, const PlacedCapsule& c) {
    const Eigen::Vector2d a(c.a[0], c.a[1]);
    const Eigen::Vector2d ab = Eigen::Vector2d(c.b[0], c.b[1]) - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - a - t * ab).norm();
}

/// The smallest distance from any point above or below floor point @p p to
/// the surface of a capsule of @p pose (negative inside one): the floor
/// distance to each projected segment less its radius.
double floor_robot_distance(const Eigen::Vector2d& p, const RobotPose& pose) {
    double d = std::numeric_limits<double>::infinity();
    for (std::uint8_t i = 0U; i < pose.count; ++i) {
        d = std::min(d, floor_segment_distance(p, pose.capsules[i]) - pose.capsules[i].radius);
    }
    return d;
}

/// The centre of the robot's capsule ends.
Eigen::Vector3d robot_centre(const RobotPose& pose) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::uint8_t i = 0U; i < pose.count; ++i) {
        const PlacedCapsule& c = pose.capsules[i];
        sum += Eigen::Vector3d(c.a[0], c.a[1], c.a[2]) + Eigen::Vector3d(c.b[0], c.b[1], c.b[2]);
    }
    return pose.count > 0U ? Eigen::Vector3d(sum / (2.0 * pose.count)) : sum;
}

/// Dashes of about @p dash pixels along a closed outline around (@p cx, @p cy).
bool dash_on(double x, double y, double cx, double cy, double dash) {
    const double arc = std::atan2(y - cy, x - cx) * std::hypot(x - cx, y - cy);
    return static_cast<long>(std::floor(arc / dash)) % 2 == 0;
}

/// The first hit (t > 0) of the ray @p o + t @p d (unit @p d) on the sphere
/// of radius @p r around @p c; its normal into @p n.
bool ray_sphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& c, double r, double& t,
                Eigen::Vector3d& n) {
    const Eigen::Vector3d oc = o - c;
    const double b = d.dot(oc);
    const double h = b * b - (oc.squaredNorm() - r * r);
    if (h < 0.0 || -b - std::sqrt(h) <= 0.0) {
        return false;
    }
    t = -b - std::sqrt(h);
    n = (oc + t * d) / r;
    return true;
}

/// The first hit (t > 0) of the ray @p o + t @p d (unit @p d) on the side of
/// capsule @p c grown by @p grow (the infinite cylinder's entry, when it lies
/// between the ends; the end spheres cover the rest).
bool ray_cylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const PlacedCapsule& c, double grow, double& t,
                  Eigen::Vector3d& n) {
    const Eigen::Vector3d a(c.a[0], c.a[1], c.a[2]);
    const Eigen::Vector3d ba = Eigen::Vector3d(c.b[0], c.b[1], c.b[2]) - a;
    const Eigen::Vector3d oa = o - a;
    const double r = c.radius + grow;
    const double baba = ba.squaredNorm();
    const double bard = ba.dot(d);
    const double baoa = ba.dot(oa);
    const double qa = baba - bard * bard;
    if (baba < 1e-12 || qa < 1e-12 * baba) {
        return false;  // a sphere, or a ray along the axis: the end spheres are hit first
    }
    const double qb = baba * d.dot(oa) - baoa * bard;
    const double qc = baba * oa.squaredNorm() - baoa * baoa - r * r * baba;
    const double h = qb * qb - qa * qc;
    if (h < 0.0) {
        return false;
    }
    const double tc = (-qb - std::sqrt(h)) / qa;
    const double y = baoa + tc * bard;
    if (tc <= 0.0 || y <= 0.0 || y >= baba) {
        return false;
    }
    t = tc;
    n = (oa + tc * d - ba * (y / baba)) / r;
    return true;
}

/// The robot's first surface along a ray: distance (infinite: none) and normal.
struct RobotHit {
    double t = std::numeric_limits<double>::infinity();  ///< metres along the ray
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   ///< outward, at the hit
};

/// The first hit of the ray @p o + t @p d (unit @p d) on the capsules of
/// @p pose, each grown by @p grow: the smallest of the sides' and the end spheres' hits.
RobotHit ray_robot(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const RobotPose& pose, double grow) {
    RobotHit hit;
    for (std::uint8_t i = 0U; i < pose.count; ++i) {
        const PlacedCapsule& c = pose.capsules[i];
        double t = 0.0;
        Eigen::Vector3d n;
        if (ray_cylinder(o, d, c, grow, t, n) && t < hit.t) {
            hit = RobotHit{t, n};
        }
        if (ray_sphere(o, d, Eigen::Vector3d(c.a[0], c.a[1], c.a[2]), c.radius + grow, t, n) && t < hit.t) {
            hit = RobotHit{t, n};
        }
        if (ray_sphere(o, d, Eigen::Vector3d(c.b[0], c.b[1], c.b[2]), c.radius + grow, t, n) && t < hit.t) {
            hit = RobotHit{t, n};
        }
    }
    return hit;
}

// ---- top view -------------------------------------------------------------

/// Each voxel column's zone membership bits (the OR over its height), 0 outside the grid.
class ColumnBits {
public:
    ColumnBits(int nx, int ny)
        : nx_(nx), ny_(ny), bits_(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0U) {}
    void set(int ix, int iy, std::uint32_t bits) { bits_[index(ix, iy)] = bits; }
    [[nodiscard]] std::uint32_t at(int ix, int iy) const {
        if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) {
            return 0U;
        }
        return bits_[index(ix, iy)];
    }
    [[nodiscard]] bool in_zone(int ix, int iy, std::size_t z) const { return (at(ix, iy) >> z & 1U) != 0U; }

private:
    [[nodiscard]] std::size_t index(int ix, int iy) const {
        return static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(ix);
    }
    int nx_;
    int ny_;
    std::vector<std::uint32_t> bits_;
};

/// The top view's voxel columns: background grey by height, zones tinted; returns each column's zone bits.
ColumnBits draw_top_columns(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const GridDims d = in.grid.dims();
    const int s = L.voxel_px;
    const Span<const std::uint32_t> mask = in.zones->membership();
    ColumnBits columns(d.nx, d.ny);
    for (int iy = 0; iy < d.ny; ++iy) {
        for (int ix = 0; ix < d.nx; ++ix) {
            int top = -1;
            std::uint32_t bits = 0U;
            bool unseen = false;  // an accessible zone voxel no sensor observes in the empty cell
            for (int iz = 0; iz < d.nz; ++iz) {
                const std::size_t i = in.grid.index_of(VoxelCoord{ix, iy, iz});
                const bool background = is_background(in, i);
                if (background) {
                    top = iz;
                }
                bits |= mask[i];
                unseen = unseen || (mask[i] != 0U && !background && i < in.observed.size() && in.observed[i] == 0U);
            }
            columns.set(ix, iy, bits);
            // Background: grey by the height of its highest voxel (darker = higher).
            PictureColour c = kFree;
            if (top >= 0) {
                c = grey(205.0 - 130.0 * static_cast<double>(top) / std::max(1, d.nz - 1));
            }
            // Zones: warning first, protective over it.
            for (int pass = 0; pass < 2; ++pass) {
                for (std::size_t z = 0U; z < in.zones->size(); ++z) {
                    const ZoneConfig& zc = in.zones->config(z);
                    const bool protective = zc.kind == ZoneKind::kProtective;
                    if ((bits >> z & 1U) != 0U && protective == (pass == 1)) {
                        c = blend(c, zone_colour(zc), 0.55);
                    }
                }
            }
            const int px = L.top_x + ix * s;
            const int py = L.top_y + (d.ny - 1 - iy) * s;
            fill_rect(img, px, py, s, s, c);
            for (int v = 0; unseen && v < s; ++v) {
                for (int u = 0; u < s; ++u) {
                    if ((px + u + py + v) % 4 == 0) {  // diagonal hatching, continuous across columns
                        put(img, px + u, py + v, kUnseenColour);
                    }
                }
            }
        }
    }
    return columns;
}

/// Light lines every 0.5 m (every voxel when voxels are larger).
void draw_top_grid_lines(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const GridDims d = in.grid.dims();
    const int s = L.voxel_px;
    const double vs = in.grid.voxel_size();
    const int every = std::max(1, static_cast<int>(std::lround(0.5 / vs)));
    for (int ix = 0; ix <= d.nx; ix += every) {
        for (int y = 0; y < d.ny * s; ++y) {
            const int x = L.top_x + ix * s;
            put(img, x, L.top_y + y, blend(get(img, std::min(x, img.width - 1), L.top_y + y), kGridLine, 0.6));
        }
    }
    for (int iy = 0; iy <= d.ny; iy += every) {
        for (int x = 0; x < d.nx * s; ++x) {
            const int y = L.top_y + (d.ny - iy) * s;
            put(img, L.top_x + x, y, blend(get(img, L.top_x + x, std::min(y, img.height - 1)), kGridLine, 0.6));
        }
    }
}

/// Zone borders: where a voxel column's membership differs from its neighbour's.
void draw_zone_borders(RgbImage& img, const PictureInput& in, const PictureLayout& L, const ColumnBits& columns) {
    const GridDims d = in.grid.dims();
    const int s = L.voxel_px;
    for (std::size_t z = 0U; z < in.zones->size(); ++z) {
        const PictureColour ec = edge_colour(in.zones->config(z));
        for (int iy = 0; iy < d.ny; ++iy) {
            for (int ix = 0; ix < d.nx; ++ix) {
                if (!columns.in_zone(ix, iy, z)) {
                    continue;
                }
                const int px = L.top_x + ix * s;
                const int py = L.top_y + (d.ny - 1 - iy) * s;
                if (!columns.in_zone(ix - 1, iy, z)) {
                    fill_rect(img, px, py, 2, s, ec);
                }
                if (!columns.in_zone(ix + 1, iy, z)) {
                    fill_rect(img, px + s - 2, py, 2, s, ec);
                }
                if (!columns.in_zone(ix, iy + 1, z)) {
                    fill_rect(img, px, py, s, 2, ec);
                }
                if (!columns.in_zone(ix, iy - 1, z)) {
                    fill_rect(img, px, py + s - 2, s, 2, ec);
                }
            }
        }
    }
}

/// Zone numbers at the centre of their footprints.
void draw_zone_numbers(RgbImage& img, const PictureInput& in, const PictureLayout& L, const ColumnBits& columns) {
    const GridDims d = in.grid.dims();
    for (std::size_t z = 0U; z < in.zones->size(); ++z) {
        double sx = 0.0;
        double sy = 0.0;
        int n = 0;
        for (int iy = 0; iy < d.ny; ++iy) {
            for (int ix = 0; ix < d.nx; ++ix) {
                if (columns.in_zone(ix, iy, z)) {
                    sx += ix;
                    sy += iy;
                    ++n;
                }
            }
        }
        if (n > 0) {
            int px = 0;
            int py = 0;
            top_view_pixel(L, in.grid, static_cast<int>(std::lround(sx / n)), static_cast<int>(std::lround(sy / n)), px,
                           py);
            const std::string t = std::to_string(z + 1U);
            label(img, px - static_cast<int>(t.size()) * 6, py - 8, t, edge_colour(in.zones->config(z)), 2);
        }
    }
}

/// Metres per pixel in the top view.
double top_metres_per_pixel(const PictureInput& in, const PictureLayout& L) {
    return in.grid.voxel_size() / L.voxel_px;
}

/// The top-view pixel position (fractional, pixel centres at integers) of floor point @p p.
Eigen::Vector2d top_view_position(const PictureInput& in, const PictureLayout& L, const Eigen::Vector2d& p) {
    const double m = top_metres_per_pixel(in, L);
    const Eigen::Vector3d o = in.grid.origin();
    return {L.top_x + (p.x() - o.x()) / m - 0.5, L.top_y + in.grid.dims().ny * L.voxel_px - (p.y() - o.y()) / m - 0.5};
}

/// Calls @p f(px, py, floor point) for every pixel of the top view.
template <typename F>
void for_top_pixels(const PictureInput& in, const PictureLayout& L, F&& f) {
    const GridDims d = in.grid.dims();
    for (int py = L.top_y; py < L.top_y + d.ny * L.voxel_px; ++py) {
        for (int px = L.top_x; px < L.top_x + d.nx * L.voxel_px; ++px) {
            f(px, py, top_view_point(L, in.grid, px, py));
        }
    }
}

/// The separation rings (solid, two pixels wide) and the mask margin's
/// dashed outline: the pixels whose floor distance to the robot lies within
/// a pixel of the ring's distance.
void draw_top_rings(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const PictureRobot& robot = *in.robot;
    const double m = top_metres_per_pixel(in, L);
    const Eigen::Vector2d c = top_view_position(in, L, robot_centre(robot.pose).head<2>());
    for_top_pixels(in, L, [&](int px, int py, const Eigen::Vector2d& p) {
        const double d = floor_robot_distance(p, robot.pose);
        for (const PictureRing& ring : robot.rings) {
            if (std::abs(d - ring.distance_m) <= m) {
                put(img, px, py, ring.colour);
            }
        }
        if (std::abs(d - robot.margin_m) <= m && dash_on(px, py, c.x(), c.y(), 6.0)) {
            put(img, px, py, kRobotMarginColour);
        }
    });
}

/// The capsules from above, lower ones first: filled, lighter where higher, with a dark edge.
void draw_top_capsules(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const RobotPose& pose = in.robot->pose;
    std::vector<std::uint8_t> order(pose.count);
    std::iota(order.begin(), order.end(), std::uint8_t{0});
    const auto top = [&](std::uint8_t i) { return std::max(pose.capsules[i].a[2], pose.capsules[i].b[2]); };
    std::stable_sort(order.begin(), order.end(), [&](std::uint8_t i, std::uint8_t j) { return top(i) < top(j); });
    const double m = top_metres_per_pixel(in, L);
    const double z_lo = in.grid.origin().z();
    const double z_span = std::max(in.grid.max_corner().z() - z_lo, 1e-3);
    const PictureColour edge = blend(kRobotColour, kBlack, 0.55);
    for (const std::uint8_t i : order) {
        const PlacedCapsule& c = pose.capsules[i];
        const double h = std::clamp((top(i) - z_lo) / z_span, 0.0, 1.0);
        const PictureColour fill = blend(kRobotColour, kFree, 0.5 * h);
        for_top_pixels(in, L, [&](int px, int py, const Eigen::Vector2d& p) {
            const double d = floor_segment_distance(p, c) - c.radius;
            if (d <= 0.0) {
                put(img, px, py, d > -1.5 * m ? edge : fill);
            }
        });
    }
}

/// The outline's point at floor distance @p distance from the robot along
/// the direction @p angle (radians) from its centre, as a top-view pixel
/// position; false when it leaves the top view first.
bool ring_point(const PictureInput& in, const PictureLayout& L, double distance, double angle, Eigen::Vector2d& out) {
    const Eigen::Vector2d c = robot_centre(in.robot->pose).head<2>();
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    const double step = 0.5 * top_metres_per_pixel(in, L);
    const GridDims d = in.grid.dims();
    const int steps = static_cast<int>(100.0 / step);
    for (int i = 0; i < steps; ++i) {
        const Eigen::Vector2d p = c + (static_cast<double>(i) * step) * dir;
        const Eigen::Vector2d px = top_view_position(in, L, p);
        if (px.x() < L.top_x || px.y() < L.top_y || px.x() >= L.top_x + d.nx * L.voxel_px ||
            px.y() >= L.top_y + d.ny * L.voxel_px) {
            return false;
        }
        if (floor_robot_distance(p, in.robot->pose) >= distance) {
            out = px;
            return true;
        }
    }
    return false;
}

/// A label box in the picture.
struct LabelBox {
    int x, y, w, h;  ///< left, top, width, height
    [[nodiscard]] bool overlaps(const LabelBox& o) const {
        return x < o.x + o.w + 4 && o.x < x + w + 4 && y < o.y + o.h + 4 && o.y < y + h + 4;
    }
};

/// Each ring's tag and distance next to it, where it is inside the top view
/// and clear of the other labels (trying directions around the robot).
void draw_ring_labels(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const GridDims d = in.grid.dims();
    const LabelBox view{L.top_x, L.top_y, d.nx * L.voxel_px, d.ny * L.voxel_px};
    std::vector<LabelBox> placed;
    for (const PictureRing& ring : in.robot->rings) {
        char buf[96];
        static_cast<void>(std::snprintf(buf, sizeof buf, "%s %.2f m", ring.tag.c_str(), ring.distance_m));
        const int w = static_cast<int>(std::string(buf).size()) * 6 * kTextScale;
        const int h = 8 * kTextScale;
        for (int k = 0; k < 36; ++k) {
            const int fan = (k + 1) / 2;  // 0, 1, 1, 2, 2, ...: alternately either side of 45 degrees
            const double angle = (45.0 + 10.0 * fan * (k % 2 == 0 ? 1.0 : -1.0)) * M_PI / 180.0;
            Eigen::Vector2d p;
            if (!ring_point(in, L, ring.distance_m, angle, p)) {
                continue;
            }
            // Beside the point, on the side away from the robot first, then the other sides.
            const int x = static_cast<int>(p.x());
            const int y = static_cast<int>(p.y());
            const bool right = std::cos(angle) >= 0.0;
            const LabelBox boxes[4] = {{right ? x + 6 : x - 6 - w, y - h / 2, w, h},
                                       {right ? x - 6 - w : x + 6, y - h / 2, w, h},
                                       {x - w / 2, y - 6 - h, w, h},
                                       {x - w / 2, y + 6, w, h}};
            const auto fits = [&](const LabelBox& box) {
                return box.x >= view.x && box.y >= view.y && box.x + box.w < view.x + view.w &&
                       box.y + box.h < view.y + view.h &&
                       std::none_of(placed.begin(), placed.end(), [&](const LabelBox& b) { return b.overlaps(box); });
            };
            const LabelBox* box = std::find_if(std::begin(boxes), std::end(boxes), fits);
            if (box != std::end(boxes)) {
                // A darker text: the ring's own colour stays the ring's pixels.
                label(img, box->x, box->y, buf, blend(ring.colour, kBlack, 0.3), kTextScale);
                placed.push_back(*box);
                break;
            }
        }
    }
}

void draw_top_view(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const GridDims d = in.grid.dims();
    const int s = L.voxel_px;
    const ColumnBits columns = draw_top_columns(img, in, L);
    draw_top_grid_lines(img, in, L);
    draw_zone_borders(img, in, L, columns);
    if (in.robot != nullptr) {
        draw_top_rings(img, in, L);
        draw_top_capsules(img, in, L);
    }
    draw_zone_numbers(img, in, L, columns);
    if (in.robot != nullptr) {
        draw_ring_labels(img, in, L);
    }
    frame_rect(img, L.top_x, L.top_y, d.nx * s, d.ny * s, 2, kBlack);
    // Corner coordinates and axes.
    const Eigen::Vector3d lo = in.grid.origin();
    const Eigen::Vector3d hi = in.grid.max_corner();
    draw_text(img, L.top_x, L.top_y + d.ny * s + 6, pair_text(lo.x(), lo.y()), kText, 1);
    const std::string tr = pair_text(hi.x(), hi.y());
    draw_text(img, L.top_x + d.nx * s - static_cast<int>(tr.size()) * 6, L.top_y - 12, tr, kText, 1);
    draw_text(img, L.top_x + d.nx * s / 2 - 20, L.top_y + d.ny * s + 6, "x ->", kText, 1);
}

// ---- sensor view ----------------------------------------------------------

/// Projects world point @p p into the picture; false when behind the sensor.
bool project(const PictureSensor& s, const PictureLayout& L, const Eigen::Vector3d& p, double& x, double& y) {
    const Eigen::Vector3d c = s.pose.inverse() * p;
    if (c.z() <= 1e-6) {
        return false;
    }
    const PinholeIntrinsics& k = s.intrinsics;
    const double u = k.fx * c.x() / c.z() + k.cx;
    const double v = k.fy * c.y() / c.z() + k.cy;
    x = L.view_x + (u + 0.5) * L.view_scale;
    y = L.view_y + (v + 0.5) * L.view_scale;
    return true;
}

/// Draws the 3-D segment a-b in the sensor view, clipped to the view.
void draw_segment(RgbImage& img, const PictureSensor& s, const PictureLayout& L, const Eigen::Vector3d& a,
                  const Eigen::Vector3d& b, PictureColour c, int thickness) {
    const double len_px = 4.0 * (a - b).norm() / 0.005 + 16.0;  // dense enough for any view scale used here
    const int n = static_cast<int>(std::min(len_px, 20000.0));
    for (int i = 0; i <= n; ++i) {
        const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(i) / n);
        double x = 0.0;
        double y = 0.0;
        if (!project(s, L, p, x, y)) {
            continue;
        }
        for (int dy = 0; dy < thickness; ++dy) {
            for (int dx = 0; dx < thickness; ++dx) {
                const int px = static_cast<int>(std::floor(x)) + dx;
                const int py = static_cast<int>(std::floor(y)) + dy;
                if (px >= L.view_x && py >= L.view_y && px < L.view_x + L.view_w && py < L.view_y + L.view_h) {
                    put(img, px, py, c);
                }
            }
        }
    }
}

void draw_box_edges(RgbImage& img, const PictureSensor& s, const PictureLayout& L, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi, PictureColour c, int thickness) {
    for (int axis = 0; axis < 3; ++axis) {
        const int a1 = (axis + 1) % 3;
        const int a2 = (axis + 2) % 3;
        for (unsigned k = 0U; k < 4U; ++k) {
            Eigen::Vector3d p = lo;
            p[a1] = (k & 1U) != 0U ? hi[a1] : lo[a1];
            p[a2] = (k & 2U) != 0U ? hi[a2] : lo[a2];
            Eigen::Vector3d q = p;
            q[axis] = hi[axis];
            draw_segment(img, s, L, p, q, c, thickness);
        }
    }
}

void draw_zone_edges(RgbImage& img, const PictureSensor& s, const PictureLayout& L, const ZoneConfig& z) {
    const PictureColour c = edge_colour(z);
    if (z.shape == ZoneShape::kBox) {
        draw_box_edges(img, s, L, z.box_min, z.box_max, c, 1);
        return;
    }
    for (std::size_t i = 0U; i < z.polygon_size; ++i) {
        const PolygonVertex& v = z.polygon[i];
        const PolygonVertex& w = z.polygon[(i + 1U) % z.polygon_size];
        draw_segment(img, s, L, {v.x, v.y, z.z_min}, {w.x, w.y, z.z_min}, c, 1);
        draw_segment(img, s, L, {v.x, v.y, z.z_max}, {w.x, w.y, z.z_max}, c, 1);
        draw_segment(img, s, L, {v.x, v.y, z.z_min}, {v.x, v.y, z.z_max}, c, 1);
    }
}

/// The robot's colour where a ray of direction @p dir meets its surface with normal @p n: darker where oblique.
PictureColour robot_shade(const Eigen::Vector3d& dir, const Eigen::Vector3d& n) {
    const double facing = std::abs(n.dot(dir));
    return blend(blend(kBlack, kRobotColour, 0.45 + 0.55 * facing), kFree, 0.3 * std::pow(facing, 6.0));
}

/// One sensor-view ray from @p s in direction @p dir (unit): the zone tints
/// front to back, then the robot, the first background voxel, free space
/// or the outside of the grid.
PictureColour sensor_ray_colour(const PictureInput& in, const PictureSensor& s, const Eigen::Vector3d& dir) {
    const Span<const std::uint32_t> mask = in.zones->membership();
    const Eigen::Vector3d origin = s.pose.translation();
    const RobotHit robot = in.robot != nullptr ? ray_robot(origin, dir, in.robot->pose, 0.0) : RobotHit{};
    double r = 0.0;
    double g = 0.0;
    double b = 0.0;
    double transmit = 1.0;
    bool entered = false;
    bool hit = false;
    double hit_t = 0.0;
    (void)traverse_segment(in.grid, origin, origin + dir * s.max_range, [&](const TraversedVoxel& t) {
        if (hit || t.t_enter >= robot.t) {
            return;
        }
        entered = true;
        if (is_background(in, t.index)) {
            hit = true;
            hit_t = t.t_enter;
            return;
        }
        const std::uint32_t bits = mask[t.index];
        for (std::size_t z = 0U; z < in.zones->size() && transmit > 0.0; ++z) {
            if ((bits >> z & 1U) != 0U) {
                const PictureColour c = zone_colour(in.zones->config(z));
                const double a = 0.09;
                r += transmit * a * c.r;
                g += transmit * a * c.g;
                b += transmit * a * c.b;
                transmit *= 1.0 - a;
            }
        }
    });
    PictureColour end = kOutside;
    if (robot.t <= s.max_range && (!hit || robot.t < hit_t)) {
        end = robot_shade(dir, robot.normal);
    } else if (hit) {
        end = grey(215.0 - 110.0 * std::clamp((hit_t - 1.5) / 3.5, 0.0, 1.0));
    } else if (entered) {
        end = kFree;
    }
    return PictureColour{mix(0.0, r + transmit * end.r, 1.0), mix(0.0, g + transmit * end.g, 1.0),
                         mix(0.0, b + transmit * end.b, 1.0)};
}

/// The direction of the sensor-view picture pixel (@p px, @p py) (relative to the view's corner).
Eigen::Vector3d view_direction(const PictureSensor& s, const PictureLayout& L, int px, int py) {
    const PinholeIntrinsics& k = s.intrinsics;
    const double u = (px + 0.5) / L.view_scale - 0.5;
    const double v = (py + 0.5) / L.view_scale - 0.5;
    return (s.pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0)).normalized();
}

/// The mask margin's dashed outline in the sensor view: the edge of the
/// silhouette of the capsules grown by the margin.
void draw_view_margin(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const PictureSensor& s = in.sensors[in.view_sensor];
    const auto w = static_cast<std::size_t>(L.view_w);
    std::vector<std::uint8_t> inside(w * static_cast<std::size_t>(L.view_h), 0U);
    for (int py = 0; py < L.view_h; ++py) {
        for (int px = 0; px < L.view_w; ++px) {
            const RobotHit h = ray_robot(s.pose.translation(), view_direction(s, L, px, py), in.robot->pose,
                                         in.robot->margin_m);
            inside[static_cast<std::size_t>(py) * w + static_cast<std::size_t>(px)] = h.t <= s.max_range ? 1U : 0U;
        }
    }
    const auto at = [&](int px, int py) {
        return inside[static_cast<std::size_t>(py) * w + static_cast<std::size_t>(px)] != 0U;
    };
    // Both sides of the silhouette's edge (two pixels); a neighbour outside the view is no edge.
    const auto differs = [&](int px, int py, int nx, int ny) {
        return nx >= 0 && ny >= 0 && nx < L.view_w && ny < L.view_h && at(nx, ny) != at(px, py);
    };
    double cx = 0.0;
    double cy = 0.0;
    if (!project(s, L, robot_centre(in.robot->pose), cx, cy)) {
        cx = L.view_x + L.view_w / 2.0;
        cy = L.view_y + L.view_h / 2.0;
    }
    for (int py = 0; py < L.view_h; ++py) {
        for (int px = 0; px < L.view_w; ++px) {
            const bool edge = differs(px, py, px - 1, py) || differs(px, py, px + 1, py) ||
                              differs(px, py, px, py - 1) || differs(px, py, px, py + 1);
            if (edge && dash_on(L.view_x + px, L.view_y + py, cx, cy, 6.0)) {
                put(img, L.view_x + px, L.view_y + py, kRobotMarginColour);
            }
        }
    }
}

void draw_sensor_view(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const PictureSensor& s = in.sensors[in.view_sensor];
    for (int py = 0; py < L.view_h; ++py) {
        for (int px = 0; px < L.view_w; ++px) {
            put(img, L.view_x + px, L.view_y + py, sensor_ray_colour(in, s, view_direction(s, L, px, py)));
        }
    }
    for (std::size_t z = 0U; z < in.zones->size(); ++z) {
        draw_zone_edges(img, s, L, in.zones->config(z));
    }
    if (in.robot != nullptr) {
        draw_view_margin(img, in, L);
    }
    draw_box_edges(img, s, L, in.grid.origin(), in.grid.max_corner(), kBlack, 2);
    frame_rect(img, L.view_x, L.view_y, L.view_w, L.view_h, 2, kBlack);
}

std::string zone_line(const PictureInput& in, std::size_t z) {
    const ZoneConfig& c = in.zones->config(z);
    char buf[256];
    const std::string name = z < in.zone_names.size() ? in.zone_names[z] : std::string("zone");
    if (c.shape == ZoneShape::kBox) {
        static_cast<void>(std::snprintf(
            buf, sizeof buf, "%2zu %-14s %-10s box    x %.2f..%.2f  y %.2f..%.2f  z %.2f..%.2f m  %u voxels", z + 1U,
            name.c_str(), c.kind == ZoneKind::kProtective ? "protective" : "warning", c.box_min.x(), c.box_max.x(),
            c.box_min.y(), c.box_max.y(), c.box_min.z(), c.box_max.z(), in.zones->voxel_count(z)));
    } else {
        static_cast<void>(std::snprintf(buf, sizeof buf,
                                        "%2zu %-14s %-10s prism  %zu vertices  z %.2f..%.2f m  %u voxels", z + 1U,
                                        name.c_str(), c.kind == ZoneKind::kProtective ? "protective" : "warning",
                                        c.polygon_size, c.z_min, c.z_max, in.zones->voxel_count(z)));
    }
    std::string line = buf;
    if (!in.cases.empty()) {
        std::string numbers;
        for (const PictureCase& k : in.cases) {
            if ((k.zone_mask >> z & 1U) != 0U) {
                numbers += (numbers.empty() ? "" : ",") + std::to_string(k.number);
            }
        }
        line += numbers.empty() ? "  in no case" : "  cases " + numbers;
    }
    return line;
}

/// One legend line per monitoring case: its number, name and zones.
std::vector<std::string> case_lines(const PictureInput& in) {
    std::vector<std::string> lines;
    for (const PictureCase& k : in.cases) {
        char buf[96];
        static_cast<void>(std::snprintf(buf, sizeof buf, "case %2d %-14s zones ", k.number, k.name.c_str()));
        std::string line = buf;
        bool first = true;
        for (std::size_t z = 0U; z < in.zones->size(); ++z) {
            if ((k.zone_mask >> z & 1U) != 0U) {
                line += (first ? "" : ", ") + std::to_string(z + 1U) + " " +
                        (z < in.zone_names.size() ? in.zone_names[z] : std::string("zone"));
                first = false;
            }
        }
        lines.push_back(line);
    }
    return lines;
}

}  // namespace

int draw_text(RgbImage& image, int x, int y, const std::string& text, PictureColour colour, int scale) {
    for (const char ch : text) {
        const int code = static_cast<unsigned char>(ch);
        const int glyph = code >= 32 && code <= 126 ? code - 32 : '?' - 32;
        for (int col = 0; col < 5; ++col) {
            const std::uint8_t bits = kFont[glyph][col];
            for (int row = 0; row < 8; ++row) {
                if (((static_cast<unsigned>(bits) >> static_cast<unsigned>(row)) & 1U) != 0U) {
                    fill_rect(image, x + col * scale, y + row * scale, scale, scale, colour);
                }
            }
        }
        x += 6 * scale;
    }
    return x;
}

void top_view_pixel(const PictureLayout& layout, const GridGeometry& grid, int ix, int iy, int& px, int& py) {
    px = layout.top_x + ix * layout.voxel_px + layout.voxel_px / 2;
    py = layout.top_y + (grid.dims().ny - 1 - iy) * layout.voxel_px + layout.voxel_px / 2;
}

Eigen::Vector2d top_view_point(const PictureLayout& layout, const GridGeometry& grid, int px, int py) {
    const double m = grid.voxel_size() / layout.voxel_px;
    return {grid.origin().x() + (px - layout.top_x + 0.5) * m,
            grid.origin().y() + (layout.top_y + grid.dims().ny * layout.voxel_px - py - 0.5) * m};
}

namespace {

/// The header's lines: the title, the grid, (the robot's pose,) the headings of the views.
int header_lines(const PictureInput& in) { return in.robot != nullptr ? 5 : 4; }

int header_height(const PictureInput& in) { return kMargin + header_lines(in) * kLineHeight + 12; }

/// Where the top view and the sensor view go: the top view about 520 pixels on its longer side, the sensor view as
/// tall as the top view, both below the header.
PictureLayout plan_layout(const PictureInput& in) {
    const GridDims d = in.grid.dims();
    PictureLayout L;
    L.voxel_px = std::clamp(520 / std::max(d.nx, d.ny), 2, 24);
    const int top_w = d.nx * L.voxel_px;
    const int top_h = d.ny * L.voxel_px;
    if (in.view_sensor < in.sensors.size()) {
        const PinholeIntrinsics& k = in.sensors[in.view_sensor].intrinsics;
        L.view_scale = static_cast<double>(std::max(top_h, 300)) / std::max(1, k.height);
        L.view_w = static_cast<int>(std::lround(k.width * L.view_scale));
        L.view_h = static_cast<int>(std::lround(k.height * L.view_scale));
    }
    L.top_x = kMargin + 8;
    L.top_y = header_height(in);
    L.view_x = L.top_x + top_w + 48;
    L.view_y = header_height(in);
    return L;
}

/// The title, the grid line, and the two views with their headings.
void draw_views(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const GridDims d = in.grid.dims();
    draw_text(img, kMargin, kMargin, in.title, kText, kTextScale);
    char buf[200];
    static_cast<void>(std::snprintf(
        buf, sizeof buf, "grid %d x %d x %d voxels of %.3f m from (%.2f, %.2f, %.2f); %zu zones", d.nx, d.ny, d.nz,
        in.grid.voxel_size(), in.grid.origin().x(), in.grid.origin().y(), in.grid.origin().z(), in.zones->size()));
    draw_text(img, kMargin, kMargin + kLineHeight, buf, kText, kTextScale);
    if (in.robot != nullptr) {
        const std::string pose = "robot '" + in.robot->name + "' at " + in.robot->pose_source;
        draw_text(img, kMargin, kMargin + 2 * kLineHeight, pose, kRobotMarginColour, kTextScale);
    }
    const int heading_y = kMargin + (header_lines(in) - 2) * kLineHeight + 10;
    draw_text(img, L.top_x, heading_y, "top view (x right, y up)", kText, kTextScale);
    draw_text(img, L.top_x, heading_y + kLineHeight, "grey: background (prior: not accessible), darker = higher", kText,
              1);
    draw_top_view(img, in, L);
    if (in.view_sensor < in.sensors.size()) {
        const PictureSensor& s = in.sensors[in.view_sensor];
        static_cast<void>(
            std::snprintf(buf, sizeof buf, "view of sensor %zu '%s'", in.view_sensor + 1U, s.name.c_str()));
        draw_text(img, L.view_x, heading_y, buf, kText, kTextScale);
        static_cast<void>(
            std::snprintf(buf, sizeof buf, "%d x %d pixels from (%.2f, %.2f, %.2f) m; zones tinted, grid edges black%s",
                          s.intrinsics.width, s.intrinsics.height, s.pose.translation().x(), s.pose.translation().y(),
                          s.pose.translation().z(), in.robot != nullptr ? "; robot blue, its mask margin dashed" : ""));
        draw_text(img, L.view_x, heading_y + kLineHeight, buf, kText, 1);
        draw_sensor_view(img, in, L);
    }
}

/// A colour swatch with @p text after it at (@p x, @p y); returns the x for the next one.
int swatch(RgbImage& img, int x, int y, PictureColour c, const std::string& text) {
    fill_rect(img, x, y, 8 * kTextScale, 8 * kTextScale - 2, c);
    frame_rect(img, x, y, 8 * kTextScale, 8 * kTextScale - 2, 1, kBlack);
    return draw_text(img, x + 8 * kTextScale + 8, y, text, kText, kTextScale) + 24;
}

/// A line sample (solid, or dashed) with @p text after it; returns the x for the next one.
int line_swatch(RgbImage& img, int x, int y, PictureColour c, bool dashed, const std::string& text) {
    for (int i = 0; i < 24; ++i) {
        if (!dashed || i % 8 < 5) {
            fill_rect(img, x + i, y + 3 * kTextScale, 1, 2, c);
        }
    }
    return draw_text(img, x + 32, y, text, kText, kTextScale) + 24;
}

/// The width of @p text at the legend's scale.
int text_width(const std::string& text) { return static_cast<int>(text.size()) * 6 * kTextScale; }

/// The colour swatches and the zone table from @p y down; returns the y below them.
int draw_legend(RgbImage& img, const PictureInput& in, const std::vector<std::string>& zone_lines, int y) {
    int x = swatch(img, kMargin, y, blend(kFree, kProtectiveColour, 0.55), "protective zone");
    x = swatch(img, x, y, blend(kFree, kWarningColour, 0.55), "warning zone");
    static_cast<void>(swatch(img, x, y, grey(160.0), "background (darker = higher / farther)"));
    y += kLineHeight;
    x = swatch(img, kMargin, y, kFree, "free grid space");
    x = swatch(img, x, y, kOutside, "outside the grid");
    if (!in.observed.empty()) {
        static_cast<void>(swatch(img, x, y, kUnseenColour, "hatched: zone part no sensor sees (unseen)"));
    }
    y += kLineHeight + 8;
    draw_text(img, kMargin, y, " # name           kind       shape", kText, kTextScale);
    y += kLineHeight;
    for (std::size_t z = 0U; z < zone_lines.size(); ++z) {
        const ZoneConfig& c = in.zones->config(z);
        fill_rect(img, kMargin, y, 8, 8 * kTextScale - 2, zone_colour(c));
        draw_text(img, kMargin + 12, y, zone_lines[z], kText, kTextScale);
        y += kLineHeight;
    }
    return y;
}

/// The monitoring cases (the PLC selects one; only its zones are monitored); returns the y below them.
int draw_case_legend(RgbImage& img, const std::vector<std::string>& lines, int y) {
    if (lines.empty()) {
        return y;
    }
    y += 8;
    draw_text(img, kMargin, y, "monitoring cases (the PLC selects one; only its zones are monitored):", kText,
              kTextScale);
    y += kLineHeight;
    for (const std::string& line : lines) {
        draw_text(img, kMargin + 12, y, line, kText, kTextScale);
        y += kLineHeight;
    }
    return y;
}

/// The robot's pose, its margin and the separation distances; returns the y below them.
int draw_robot_legend(RgbImage& img, const PictureInput& in, int width, int y) {
    const PictureRobot& r = *in.robot;
    y += 8;
    std::string joints = "joints (PLC order, rad or m):";
    for (std::uint8_t k = 0U; k < r.joints.count; ++k) {
        char buf[32];
        static_cast<void>(std::snprintf(buf, sizeof buf, " %.3f", r.joints.q[k]));
        joints += buf;
    }
    draw_text(img, kMargin, y, "the robot's pose: " + joints, kText, 1);
    y += 14;
    char buf[160];
    static_cast<void>(std::snprintf(buf, sizeof buf, "mask margin %.2f m (its voxels are the robot's)", r.margin_m));
    const int x = swatch(img, kMargin, y, kRobotColour, "robot capsules (lighter = higher)");
    static_cast<void>(line_swatch(img, x, y, kRobotMarginColour, true, buf));
    y += kLineHeight;
    int rx = kMargin;
    for (const PictureRing& ring : r.rings) {
        static_cast<void>(std::snprintf(buf, sizeof buf, "%s: %.2f m", ring.name.c_str(), ring.distance_m));
        if (rx > kMargin && rx + 32 + text_width(buf) > width - kMargin) {
            rx = kMargin;
            y += kLineHeight;
        }
        rx = line_swatch(img, rx, y, ring.colour, false, buf);
    }
    y += kLineHeight;
    draw_text(img, kMargin, y,
              "rings (top view): the floor outline of every point, at any height, within that distance of the "
              "capsules' surfaces; the separation check measures from the surfaces",
              kText, 1);
    return y + 14;
}

}  // namespace

RgbImage render_config_picture(const PictureInput& in, PictureLayout* layout_out) {
    const PictureLayout L = plan_layout(in);
    const int body_h = std::max(in.grid.dims().ny * L.voxel_px, L.view_h) + 30;
    std::vector<std::string> zone_lines;
    for (std::size_t z = 0U; z < in.zones->size(); ++z) {
        zone_lines.push_back(zone_line(in, z));
    }
    const std::vector<std::string> cases = case_lines(in);
    int widest = 0;
    for (const std::vector<std::string>* lines : {&std::as_const(zone_lines), &cases}) {
        for (const std::string& line : *lines) {
            widest = std::max(widest, text_width(line) + 40);
        }
    }
    const int width = std::max({L.view_x + L.view_w + kMargin, widest + 2 * kMargin, 900});
    // Room for every legend line, the rings one a line at most; cut to what was drawn.
    const std::size_t lines = 5U + zone_lines.size() + cases.size() +
                              (in.robot != nullptr ? 5U + in.robot->rings.size() : 0U);
    const int height = header_height(in) + body_h + static_cast<int>(lines) * kLineHeight + 2 * kMargin;
    RgbImage img = RgbImage::filled(width, height, kPanel.r, kPanel.g, kPanel.b);
    draw_views(img, in, L);
    int y = draw_legend(img, in, zone_lines, header_height(in) + body_h);
    y = draw_case_legend(img, cases, y);
    if (in.robot != nullptr) {
        y = draw_robot_legend(img, in, width, y);
    }
    img.height = std::min(height, y + kMargin);
    img.rgb.resize(img.offset(0, img.height));
    if (layout_out != nullptr) {
        *layout_out = L;
    }
    return img;
}

PictureRobot picture_robot(const cell::MonitorConfig& cfg, const RobotModel& model,
                           const sim::JointTrajectory& trajectory) {
    PictureRobot r;
    r.name = model.name;
    if (!trajectory.keyframes.empty() && trajectory.keyframes.front().q.count == model.joint_count) {
        r.joints = trajectory.keyframes.front().q;
        char buf[96];
        static_cast<void>(std::snprintf(buf, sizeof buf, "the demo trajectory's first keyframe (t = %.2f s)",
                                        trajectory.keyframes.front().t));
        r.pose_source = buf;
    } else {
        r.joints.count = model.joint_count;
        r.pose_source = "all joints 0 (no demo trajectory)";
    }
    place_robot(model, r.joints, r.pose);
    r.margin_m = cfg.robot.margin_m;
    const SeparationParams& sp = cfg.robot.separation;
    constexpr PictureColour kClassColours[kSpeedClasses] = {{200, 0, 200}, {0, 150, 170}, {150, 90, 20}, {70, 70, 70}};
    for (std::uint8_t k = 0U; k < sp.class_count && k < kSpeedClasses; ++k) {
        const char* what = k == 0U ? " (full)" : (k == sp.reduced_class ? " (reduced)" : "");
        r.rings.push_back(PictureRing{protective_separation_distance(sp, k),
                                      "S_p speed class " + std::to_string(k) + what, "S_p" + std::to_string(k),
                                      kClassColours[k]});
    }
    r.rings.push_back(PictureRing{reduced_speed_distance(sp), "reduced speed below", "reduce", {20, 150, 20}});
    return r;
}

bool config_picture_input(const std::string& title, const cell::MonitorConfig& cfg, const GridGeometry& grid,
                          const CompiledZones& zones, const std::vector<sim::SensorSpec>& specs,
                          Span<const std::int16_t> prior, const std::string& view_sensor, const PictureRobot* robot,
                          PictureInput& in, std::string& error) {
    in = PictureInput{};
    in.robot = robot;
    for (const cell::CaseSettings& k : cfg.cases) {
        in.cases.push_back(PictureCase{k.number, k.name, k.zone_mask});
    }
    in.title = title;
    in.grid = grid;
    in.zones = &zones;
    for (const cell::ZoneSettings& z : cfg.zones) {
        in.zone_names.push_back(z.name);
    }
    in.prior = prior;
    in.accessible_min_prior = cfg.accessible_min_prior;
    for (const sim::SensorSpec& s : specs) {
        in.sensors.push_back(PictureSensor{s.name, s.pose(), s.intrinsics(), static_cast<double>(s.max_range)});
    }
    in.view_sensor = 0U;
    if (!view_sensor.empty()) {
        in.view_sensor = specs.size();
        for (std::size_t i = 0U; i < specs.size(); ++i) {
            if (specs[i].name == view_sensor || std::to_string(i + 1U) == view_sensor) {
                in.view_sensor = i;
            }
        }
        if (in.view_sensor == specs.size()) {
            error = "no sensor named or numbered '" + view_sensor + "'";
            return false;
        }
    }
    return true;
}

bool write_config_picture(const std::string& path, const std::string& title, const cell::MonitorConfig& cfg,
                          const GridGeometry& grid, const CompiledZones& zones,
                          const std::vector<sim::SensorSpec>& specs, Span<const std::int16_t> prior,
                          const std::string& view_sensor, const PictureRobot* robot, std::string& error) {
    PictureInput in;
    return config_picture_input(title, cfg, grid, zones, specs, prior, view_sensor, robot, in, error) &&
           write_png(path, render_config_picture(in), error);
}

}  // namespace cellguard::monitor
