// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file evidence_grid.hpp
/// Evidence grids over caller-provided storage: integer log-odds per voxel
/// plus a per-voxel observed flag (unknown is not empty).
///
/// The frame grid of one cycle and the background grid G_B are both an
/// `EvidenceGrid`; they differ in how they are filled (fusion.hpp adds the
/// evidence of one frame; `accumulate_background` sums many frames with
/// clamping). lib/ never allocates: storage comes from the caller, e.g. a
/// `StaticEvidenceGridStorage` on a controller or any buffer on a host.
#ifndef CELLGUARD_EVIDENCE_GRID_HPP
#define CELLGUARD_EVIDENCE_GRID_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/log_odds.hpp"

namespace cellguard {

/// A dense evidence grid: geometry plus views of int16 log-odds and uint8
/// observed flags (0 = no ray touched the voxel, 1 = observed), one each per
/// voxel, indexed by GridGeometry::index_of.
class EvidenceGrid {
public:
    /// An empty grid with no storage (placeholder only).
    EvidenceGrid() noexcept = default;

    /// Binds @p geometry to caller storage. Errors: kStorageTooSmall when
    /// either span holds fewer than geometry.voxel_count() elements (larger
    /// spans are fine; only the first voxel_count() elements are used),
    /// kInvalidArgument for an empty geometry. Does not clear the storage.
    static Result<EvidenceGrid> make(const GridGeometry& geometry, Span<std::int16_t> log_odds,
                                     Span<std::uint8_t> observed) noexcept;

    /// The grid's geometry.
    [[nodiscard]] const GridGeometry& geometry() const noexcept { return geometry_; }
    /// Log-odds of every voxel (exactly voxel_count() elements).
    [[nodiscard]] Span<std::int16_t> log_odds() const noexcept { return log_odds_; }
    /// Observed flag of every voxel (exactly voxel_count() elements).
    [[nodiscard]] Span<std::uint8_t> observed() const noexcept { return observed_; }
    /// Number of voxels.
    [[nodiscard]] std::size_t voxel_count() const noexcept { return log_odds_.size(); }

    /// Sets every voxel to probability 0.5 (log-odds 0) and unobserved.
    void clear() noexcept;
    /// Number of voxels whose observed flag is set.
    [[nodiscard]] std::size_t observed_count() const noexcept;

private:
    GridGeometry geometry_{};
    Span<std::int16_t> log_odds_{};
    Span<std::uint8_t> observed_{};
};

/// Statically sized storage for one evidence grid of NX x NY x NZ voxels, for
/// controllers that place their grids in .bss. Use with EvidenceGrid::make.
template <std::int32_t NX, std::int32_t NY, std::int32_t NZ>
struct StaticEvidenceGridStorage {
    static_assert(NX >= 1 && NY >= 1 && NZ >= 1, "grid dimensions must be positive");
    static_assert(NX <= kMaxDimension && NY <= kMaxDimension && NZ <= kMaxDimension,
                  "grid dimension above kMaxDimension");
    /// Number of voxels.
    // NOLINTNEXTLINE(bugprone-dynamic-static-initializers): constexpr, initialised at compile time (false positive in clang-tidy 14)
    static constexpr std::size_t kVoxels = static_cast<std::size_t>(NX) * static_cast<std::size_t>(NY) *
                                           static_cast<std::size_t>(NZ);
    static_assert(kVoxels <= kMaxVoxels, "grid above kMaxVoxels");
    std::int16_t log_odds[kVoxels];  ///< log-odds storage
    std::uint8_t observed[kVoxels];  ///< observed-flag storage
};

/// Clamping bounds of the background grid G_B, in log-odds units. The
/// defaults are log-odds of 0.001 and 0.999 (about -+6.9 nats): well below
/// t_E = 0.1 so that seen-free space reads as free (READING-NOTES, pitfalls).
struct BackgroundClamp {
    std::int16_t min = -1768;  ///< lower clamp, log_odds_from_probability(0.001)
    std::int16_t max = 1768;   ///< upper clamp, log_odds_from_probability(0.999)
};

/// Adds one fused frame to the background grid: for every voxel the frame
/// observed, background += frame, clamped to @p clamp; the observed flags are
/// OR-ed. Unobserved frame voxels leave the background untouched.
/// Errors: kGeometryMismatch when the grids differ in geometry,
/// kInvalidArgument when clamp.min > clamp.max or either bound is the sentinel.
[[nodiscard]] Status accumulate_background(EvidenceGrid& background, const EvidenceGrid& frame,
                                           BackgroundClamp clamp = BackgroundClamp{}) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_EVIDENCE_GRID_HPP
