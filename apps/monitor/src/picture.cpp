// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The configuration picture: top view and one sensor's view of the grid,
// the background and the zones (picture.hpp).
#include "cellguard/monitor/picture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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
            for (int iz = 0; iz < d.nz; ++iz) {
                const std::size_t i = in.grid.index_of(VoxelCoord{ix, iy, iz});
                if (is_background(in, i)) {
                    top = iz;
                }
                bits |= mask[i];
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

void draw_top_view(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const GridDims d = in.grid.dims();
    const int s = L.voxel_px;
    const ColumnBits columns = draw_top_columns(img, in, L);
    draw_top_grid_lines(img, in, L);
    draw_zone_borders(img, in, L, columns);
    draw_zone_numbers(img, in, L, columns);
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

void draw_sensor_view(RgbImage& img, const PictureInput& in, const PictureLayout& L) {
    const PictureSensor& s = in.sensors[in.view_sensor];
    const PinholeIntrinsics& k = s.intrinsics;
    const Span<const std::uint32_t> mask = in.zones->membership();
    const Eigen::Vector3d origin = s.pose.translation();
    for (int py = 0; py < L.view_h; ++py) {
        for (int px = 0; px < L.view_w; ++px) {
            const double u = (px + 0.5) / L.view_scale - 0.5;
            const double v = (py + 0.5) / L.view_scale - 0.5;
            const Eigen::Vector3d dir =
                (s.pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0)).normalized();
            // Front to back: zone tints, then the first background voxel.
            double r = 0.0;
            double g = 0.0;
            double b = 0.0;
            double transmit = 1.0;
            bool entered = false;
            bool hit = false;
            double hit_t = 0.0;
            (void)traverse_segment(in.grid, origin, origin + dir * s.max_range, [&](const TraversedVoxel& t) {
                if (hit) {
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
            if (hit) {
                end = grey(215.0 - 110.0 * std::clamp((hit_t - 1.5) / 3.5, 0.0, 1.0));
            } else if (entered) {
                end = kFree;
            }
            put(img, L.view_x + px, L.view_y + py,
                PictureColour{mix(0.0, r + transmit * end.r, 1.0), mix(0.0, g + transmit * end.g, 1.0),
                              mix(0.0, b + transmit * end.b, 1.0)});
        }
    }
    for (std::size_t z = 0U; z < in.zones->size(); ++z) {
        draw_zone_edges(img, s, L, in.zones->config(z));
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
    return buf;
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

namespace {

constexpr int kHeaderHeight = kMargin + 4 * kLineHeight + 12;

/// Where the top view and the sensor view go: the top view about 420 pixels on its longer side, the sensor view as
/// tall as the top view, both below the header.
PictureLayout plan_layout(const PictureInput& in) {
    const GridDims d = in.grid.dims();
    PictureLayout L;
    L.voxel_px = std::clamp(420 / std::max(d.nx, d.ny), 2, 24);
    const int top_w = d.nx * L.voxel_px;
    const int top_h = d.ny * L.voxel_px;
    if (in.view_sensor < in.sensors.size()) {
        const PinholeIntrinsics& k = in.sensors[in.view_sensor].intrinsics;
        L.view_scale = static_cast<double>(std::max(top_h, 300)) / std::max(1, k.height);
        L.view_w = static_cast<int>(std::lround(k.width * L.view_scale));
        L.view_h = static_cast<int>(std::lround(k.height * L.view_scale));
    }
    L.top_x = kMargin + 8;
    L.top_y = kHeaderHeight;
    L.view_x = L.top_x + top_w + 48;
    L.view_y = kHeaderHeight;
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
    const int heading_y = kMargin + 2 * kLineHeight + 10;
    draw_text(img, L.top_x, heading_y, "top view (x right, y up)", kText, kTextScale);
    draw_text(img, L.top_x, heading_y + kLineHeight, "grey: background (prior: not accessible), darker = higher", kText,
              1);
    draw_top_view(img, in, L);
    if (in.view_sensor < in.sensors.size()) {
        const PictureSensor& s = in.sensors[in.view_sensor];
        static_cast<void>(
            std::snprintf(buf, sizeof buf, "view of sensor %zu '%s'", in.view_sensor + 1U, s.name.c_str()));
        draw_text(img, L.view_x, heading_y, buf, kText, kTextScale);
        static_cast<void>(std::snprintf(buf, sizeof buf,
                                        "%d x %d pixels from (%.2f, %.2f, %.2f) m; zones tinted, grid edges black",
                                        s.intrinsics.width, s.intrinsics.height, s.pose.translation().x(),
                                        s.pose.translation().y(), s.pose.translation().z()));
        draw_text(img, L.view_x, heading_y + kLineHeight, buf, kText, 1);
        draw_sensor_view(img, in, L);
    }
}

/// The colour swatches and the zone table from @p y down.
void draw_legend(RgbImage& img, const PictureInput& in, const std::vector<std::string>& zone_lines, int y) {
    int x = kMargin;
    auto swatch = [&](PictureColour c, const char* text) {
        fill_rect(img, x, y, 8 * kTextScale, 8 * kTextScale - 2, c);
        frame_rect(img, x, y, 8 * kTextScale, 8 * kTextScale - 2, 1, kBlack);
        x = draw_text(img, x + 8 * kTextScale + 8, y, text, kText, kTextScale) + 24;
    };
    swatch(blend(kFree, kProtectiveColour, 0.55), "protective zone");
    swatch(blend(kFree, kWarningColour, 0.55), "warning zone");
    swatch(grey(160.0), "background (darker = higher / farther)");
    y += kLineHeight;
    x = kMargin;
    swatch(kFree, "free grid space");
    swatch(kOutside, "outside the grid");
    y += kLineHeight + 8;
    draw_text(img, kMargin, y, " # name           kind       shape", kText, kTextScale);
    y += kLineHeight;
    for (std::size_t z = 0U; z < zone_lines.size(); ++z) {
        const ZoneConfig& c = in.zones->config(z);
        fill_rect(img, kMargin, y, 8, 8 * kTextScale - 2, zone_colour(c));
        draw_text(img, kMargin + 12, y, zone_lines[z], kText, kTextScale);
        y += kLineHeight;
    }
}

}  // namespace

RgbImage render_config_picture(const PictureInput& in, PictureLayout* layout_out) {
    const PictureLayout L = plan_layout(in);
    const int top_h = in.grid.dims().ny * L.voxel_px;
    const std::size_t legend_lines = 4U + in.zones->size();
    const int body_h = std::max(top_h, L.view_h) + 30;
    std::vector<std::string> zone_lines;
    zone_lines.reserve(in.zones->size());
    int widest = 0;
    for (std::size_t z = 0U; z < in.zones->size(); ++z) {
        zone_lines.push_back(zone_line(in, z));
        widest = std::max(widest, static_cast<int>(zone_lines.back().size()) * 6 * kTextScale + 40);
    }
    const int width = std::max({L.view_x + L.view_w + kMargin, widest + 2 * kMargin, 900});
    const int height = kHeaderHeight + body_h + static_cast<int>(legend_lines) * kLineHeight + 2 * kMargin;
    RgbImage img = RgbImage::filled(width, height, kPanel.r, kPanel.g, kPanel.b);
    draw_views(img, in, L);
    draw_legend(img, in, zone_lines, kHeaderHeight + body_h);
    if (layout_out != nullptr) {
        *layout_out = L;
    }
    return img;
}

bool write_config_picture(const std::string& path, const std::string& title, const cell::MonitorConfig& cfg,
                          const GridGeometry& grid, const CompiledZones& zones,
                          const std::vector<sim::SensorSpec>& specs, Span<const std::int16_t> prior,
                          const std::string& view_sensor, std::string& error) {
    PictureInput in;
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
    return write_png(path, render_config_picture(in), error);
}

}  // namespace cellguard::monitor
