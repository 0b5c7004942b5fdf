// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file zones.hpp
/// Protective and warning zones: their configuration in world coordinates,
/// and their compilation into voxel sets in bounded storage.
///
/// A zone is an axis-aligned box or a vertical prism over a convex polygon
/// (the way safety laser scanners define fields), between two heights. A
/// voxel belongs to a zone when its centre lies inside the zone (closed
/// boundary). Compilation writes one bit per zone into a per-voxel
/// membership mask (caller storage, one uint32 per voxel), so evaluating all
/// zones is one pass over the grid, with work bounded by the voxel count plus
/// the total membership count.
#ifndef CELLGUARD_ZONES_HPP
#define CELLGUARD_ZONES_HPP

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"

namespace cellguard {

/// Most zones of one configuration (one bit each in a uint32 mask).
constexpr std::size_t kMaxZones = 32U;
/// Most vertices of a prism zone's polygon.
constexpr std::size_t kMaxPolygonVertices = 16U;

/// Zone mask with a bit for each of @p zone_count zones (all 32 bits from kMaxZones on).
[[nodiscard]] constexpr std::uint32_t all_zone_bits(std::size_t zone_count) noexcept {
    return zone_count >= kMaxZones ? 0xFFFFFFFFU : ((1U << zone_count) - 1U);
}

/// What a zone protects against.
enum class ZoneKind : std::uint8_t {
    kProtective = 0,  ///< an object inside requests a protective stop
    kWarning = 1,     ///< an object inside raises a warning
};

/// The shape of a zone.
enum class ZoneShape : std::uint8_t {
    kBox = 0,    ///< axis-aligned box [box_min, box_max]
    kPrism = 1,  ///< convex polygon in x-y, extruded from z_min to z_max
};

/// A polygon vertex in the x-y plane, metres (plain and zero-initialised,
/// unlike Eigen's vectors, so a ZoneConfig never holds indeterminate values).
struct PolygonVertex {
    double x = 0.0;  ///< world x, metres
    double y = 0.0;  ///< world y, metres
};

/// One zone as an integrator draws it. Thresholds are per zone.
struct ZoneConfig {
    ZoneKind kind = ZoneKind::kProtective;              ///< protective or warning
    ZoneShape shape = ZoneShape::kBox;                  ///< box or prism
    Eigen::Vector3d box_min = Eigen::Vector3d::Zero();  ///< kBox: minimum corner, metres
    Eigen::Vector3d box_max = Eigen::Vector3d::Zero();  ///< kBox: maximum corner, metres
    PolygonVertex polygon[kMaxPolygonVertices] = {};    ///< kPrism: vertices in x-y, in order
    std::size_t polygon_size = 0U;                      ///< kPrism: number of vertices used (3..16)
    double z_min = 0.0;                                 ///< kPrism: bottom height, metres
    double z_max = 0.0;                                 ///< kPrism: top height, metres
    /// INTRUDED when at least this many voxels of the zone are foreground (>= 1).
    std::uint32_t min_foreground_voxels = 1U;
    /// UNSEEN when more than this many accessible voxels of the zone were not observed.
    std::uint32_t max_unseen_voxels = 0U;
};

/// Why a zone configuration was rejected, with the zone's position.
struct ZoneError {
    ErrorCode code =
        ErrorCode::kOk;       ///< kInvalidArgument, kOutOfGrid, kCapacityExceeded, kNonFiniteValue, kStorageTooSmall
    std::size_t zone = 0U;    ///< index of the offending zone (0 for errors of the whole set)
    const char* reason = "";  ///< static text: what is wrong
};

/// True when @p e means "no error" (its code is kOk): what Result<T, ZoneError> checks.
constexpr bool is_no_error(const ZoneError& e) noexcept { return e.code == ErrorCode::kOk; }

/// The compiled zones: configuration copy, per-zone voxel counts, and the
/// membership mask view (bit z of mask[i] set when voxel i is in zone z).
// NOLINTNEXTLINE(bugprone-reserved-identifier,cert-dcl37-c,cert-dcl51-cpp): __i0 is the index clang gives the implicit copy of the array member, not a name in the source
class CompiledZones {
public:
    /// No zones (placeholder).
    CompiledZones() noexcept = default;

    /// Validates @p zones against @p grid and compiles them into
    /// @p membership (one uint32 per voxel, overwritten). On error the
    /// result's ZoneError says which zone, the code and why.
    /// Rejected: more than kMaxZones zones; non-finite coordinates; an
    /// empty or inverted box or height range; a polygon with fewer than 3
    /// or more than kMaxPolygonVertices vertices, not convex, or of zero
    /// area; a zone reaching outside the grid; a zone that holds no voxel
    /// centre; min_foreground_voxels of 0; storage smaller than the grid.
    static Result<CompiledZones, ZoneError> compile(const GridGeometry& grid, Span<const ZoneConfig> zones,
                                                    Span<std::uint32_t> membership) noexcept;

    /// Number of zones.
    [[nodiscard]] std::size_t size() const noexcept { return count_; }
    /// Configuration of zone @p z (checked).
    [[nodiscard]] const ZoneConfig& config(std::size_t z) const noexcept {
        CG_ENFORCE(z < count_, "zone index out of range");
        return zones_[z];
    }
    /// Number of voxels of zone @p z (checked).
    [[nodiscard]] std::uint32_t voxel_count(std::size_t z) const noexcept {
        CG_ENFORCE(z < count_, "zone index out of range");
        return voxels_[z];
    }
    /// Sum over zones of their voxel counts: the work bound of evaluation beyond one grid pass.
    [[nodiscard]] std::size_t total_memberships() const noexcept { return total_; }
    /// The membership mask, one uint32 per voxel.
    [[nodiscard]] Span<const std::uint32_t> membership() const noexcept { return membership_; }
    /// The grid the zones were compiled for.
    [[nodiscard]] const GridGeometry& geometry() const noexcept { return geometry_; }
    /// CRC-32 of what zone evaluation and the safety logic read besides the
    /// membership mask: the zone count, total_memberships(), and per zone its
    /// kind, min_foreground_voxels, max_unseen_voxels and voxel count (each
    /// a uint32 in host byte order: the value is only compared within one
    /// run). The controller compares it every cycle with its value at
    /// start-up (SR-CTRL-010).
    [[nodiscard]] std::uint32_t settings_crc() const noexcept;

private:
    GridGeometry geometry_{};
    ZoneConfig zones_[kMaxZones] = {};
    std::uint32_t voxels_[kMaxZones] = {};
    std::size_t count_ = 0U;
    std::size_t total_ = 0U;
    Span<const std::uint32_t> membership_{};
};

/// True when world point @p p lies in @p zone (closed boundary). For a
/// prism the polygon may be clockwise or counter-clockwise.
[[nodiscard]] bool zone_contains(const ZoneConfig& zone, const Eigen::Vector3d& p) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ZONES_HPP
