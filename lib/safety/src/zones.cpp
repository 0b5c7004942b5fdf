// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/zones.hpp"

#include <array>
#include <cmath>

#include "cellguard/base/crc32.hpp"

namespace cellguard {

namespace {

double cross2(const PolygonVertex& a, const PolygonVertex& b, const PolygonVertex& c) noexcept {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// +1 counter-clockwise, -1 clockwise, 0 when not strictly convex or degenerate.
int polygon_orientation(const ZoneConfig& z) noexcept {
    int sign = 0;
    double area2 = 0.0;
    for (std::size_t i = 0U; i < z.polygon_size; ++i) {
        const PolygonVertex& a = z.polygon[i];
        const PolygonVertex& b = z.polygon[(i + 1U) % z.polygon_size];
        const PolygonVertex& c = z.polygon[(i + 2U) % z.polygon_size];
        const double turn = cross2(a, b, c);
        area2 += a.x * b.y - b.x * a.y;
        if (turn == 0.0) {
            return 0;  // collinear consecutive vertices or a repeated vertex
        }
        const int s = turn > 0.0 ? 1 : -1;
        if (sign == 0) {
            sign = s;
        } else if (s != sign) {
            return 0;
        }
    }
    // A sliver whose turns all round to one sign can still sum to no area (a star: polygon_simple_winding).
    return (area2 * sign > 0.0) ? sign : 0;
}

bool polygon_simple_winding(const ZoneConfig& z) noexcept {
    // The sum of exterior angles of a convex polygon is exactly one turn.
    double total = 0.0;
    for (std::size_t i = 0U; i < z.polygon_size; ++i) {
        const PolygonVertex& a = z.polygon[i];
        const PolygonVertex& b = z.polygon[(i + 1U) % z.polygon_size];
        const PolygonVertex& c = z.polygon[(i + 2U) % z.polygon_size];
        const double e1x = b.x - a.x;
        const double e1y = b.y - a.y;
        const double e2x = c.x - b.x;
        const double e2y = c.y - b.y;
        total += std::atan2(e1x * e2y - e1y * e2x, e1x * e2x + e1y * e2y);
    }
    return std::fabs(std::fabs(total) - 2.0 * 3.14159265358979323846) < 1e-6;
}

ZoneError validate(const GridGeometry& grid, const ZoneConfig& z, std::size_t index) noexcept {
    const Eigen::Vector3d& lo = grid.origin();
    const Eigen::Vector3d hi = grid.max_corner();
    if (z.min_foreground_voxels == 0U) {
        return ZoneError{ErrorCode::kInvalidArgument, index, "min_foreground_voxels must be at least 1"};
    }
    if (z.kind != ZoneKind::kProtective && z.kind != ZoneKind::kWarning) {
        return ZoneError{ErrorCode::kInvalidArgument, index, "unknown zone kind"};
    }
    if (z.shape == ZoneShape::kBox) {
        if (!z.box_min.allFinite() || !z.box_max.allFinite()) {
            return ZoneError{ErrorCode::kNonFiniteValue, index, "box corner is not finite"};
        }
        if ((z.box_max.array() <= z.box_min.array()).any()) {
            return ZoneError{ErrorCode::kInvalidArgument, index, "box is empty or inverted"};
        }
        if ((z.box_min.array() < lo.array()).any() || (z.box_max.array() > hi.array()).any()) {
            return ZoneError{ErrorCode::kOutOfGrid, index, "box reaches outside the grid"};
        }
        return ZoneError{};
    }
    if (z.shape != ZoneShape::kPrism) {
        return ZoneError{ErrorCode::kInvalidArgument, index, "unknown zone shape"};
    }
    if (z.polygon_size < 3U || z.polygon_size > kMaxPolygonVertices) {
        return ZoneError{ErrorCode::kInvalidArgument, index, "polygon needs 3 to 16 vertices"};
    }
    if (!std::isfinite(z.z_min) || !std::isfinite(z.z_max)) {
        return ZoneError{ErrorCode::kNonFiniteValue, index, "prism height is not finite"};
    }
    for (std::size_t i = 0U; i < z.polygon_size; ++i) {
        const PolygonVertex& v = z.polygon[i];
        if (!std::isfinite(v.x) || !std::isfinite(v.y)) {
            return ZoneError{ErrorCode::kNonFiniteValue, index, "polygon vertex is not finite"};
        }
        if (v.x < lo.x() || v.y < lo.y() || v.x > hi.x() || v.y > hi.y()) {
            return ZoneError{ErrorCode::kOutOfGrid, index, "polygon vertex outside the grid"};
        }
    }
    if (!(z.z_max > z.z_min)) {
        return ZoneError{ErrorCode::kInvalidArgument, index, "prism height range is empty or inverted"};
    }
    if (z.z_min < lo.z() || z.z_max > hi.z()) {
        return ZoneError{ErrorCode::kOutOfGrid, index, "prism height outside the grid"};
    }
    if (polygon_orientation(z) == 0 || !polygon_simple_winding(z)) {
        return ZoneError{ErrorCode::kInvalidArgument, index, "polygon is degenerate or not convex"};
    }
    return ZoneError{};
}

}  // namespace

bool zone_contains(const ZoneConfig& zone, const Eigen::Vector3d& p) noexcept {
    if (zone.shape == ZoneShape::kBox) {
        return (p.array() >= zone.box_min.array()).all() && (p.array() <= zone.box_max.array()).all();
    }
    if (p.z() < zone.z_min || p.z() > zone.z_max || zone.polygon_size < 3U) {
        return false;
    }
    const PolygonVertex q{p.x(), p.y()};
    bool has_pos = false;
    bool has_neg = false;
    for (std::size_t i = 0U; i < zone.polygon_size && i < kMaxPolygonVertices; ++i) {
        const double c = cross2(zone.polygon[i], zone.polygon[(i + 1U) % zone.polygon_size], q);
        has_pos = has_pos || c > 0.0;
        has_neg = has_neg || c < 0.0;
    }
    return !(has_pos && has_neg);
}

Result<CompiledZones, ZoneError> CompiledZones::compile(const GridGeometry& grid, Span<const ZoneConfig> zones,
                                                        Span<std::uint32_t> membership) noexcept {
    if (zones.size() > kMaxZones) {
        return ZoneError{ErrorCode::kCapacityExceeded, 0U, "more zones than kMaxZones (32)"};
    }
    if (grid.voxel_count() == 0U || membership.size() < grid.voxel_count()) {
        return ZoneError{ErrorCode::kStorageTooSmall, 0U, "membership storage smaller than the grid"};
    }
    for (std::size_t z = 0U; z < zones.size(); ++z) {
        const ZoneError err = validate(grid, zones[z], z);
        if (err.code != ErrorCode::kOk) {
            return err;
        }
    }
    CompiledZones c;
    c.geometry_ = grid;
    c.count_ = zones.size();
    for (std::size_t z = 0U; z < zones.size(); ++z) {
        c.zones_[z] = zones[z];
    }
    const Span<std::uint32_t> mask = membership.subspan(0U, grid.voxel_count());
    for (std::size_t i = 0U; i < mask.size(); ++i) {
        const Eigen::Vector3d centre = grid.voxel_center(grid.coord_of(i));
        std::uint32_t bits = 0U;
        for (std::size_t z = 0U; z < c.count_; ++z) {
            if (zone_contains(c.zones_[z], centre)) {
                bits |= (1U << z);
                ++c.voxels_[z];
            }
        }
        mask[i] = bits;
    }
    for (std::size_t z = 0U; z < c.count_; ++z) {
        if (c.voxels_[z] == 0U) {
            return ZoneError{ErrorCode::kInvalidArgument, z, "zone holds no voxel centre"};
        }
        c.total_ += c.voxels_[z];
    }
    c.membership_ = Span<const std::uint32_t>(mask.data(), mask.size());
    return c;
}

std::uint32_t CompiledZones::settings_crc() const noexcept {
    // The same way RayTable::check_header gathers its settings: words, then
    // the CRC of their bytes.
    std::array<std::uint32_t, 2U + 4U * kMaxZones> words{};
    words[0] = static_cast<std::uint32_t>(count_);
    words[1] = static_cast<std::uint32_t>(total_);
    std::size_t n = 2U;
    for (std::size_t z = 0U; z < count_ && z < kMaxZones; ++z) {
        words[n++] = static_cast<std::uint32_t>(zones_[z].kind);
        words[n++] = zones_[z].min_foreground_voxels;
        words[n++] = zones_[z].max_unseen_voxels;
        words[n++] = voxels_[z];
    }
    return crc32(as_bytes(Span<const std::uint32_t>(words.data(), n)));
}

}  // namespace cellguard
