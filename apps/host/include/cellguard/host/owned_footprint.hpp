// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file owned_footprint.hpp
/// Host-owned working memory of footprint fusion (footprint_fusion.hpp): one
/// workspace per sensor, allocated once at start (the cycle allocates
/// nothing), sized for the largest image of the configured sensors, and the
/// one call by which host programs fuse a frame either way.
#ifndef CELLGUARD_HOST_OWNED_FOOTPRINT_HPP
#define CELLGUARD_HOST_OWNED_FOOTPRINT_HPP

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cellguard/grid/footprint_fusion.hpp"

namespace cellguard::host {

/// Workspaces of footprint fusion for @p sensors sensors of at most
/// @p width x @p height pixels over @p grid.
class OwnedFootprintWorkspaces {
public:
    /// Allocates @p sensors workspaces (at least one).
    OwnedFootprintWorkspaces(const GridGeometry& grid, std::size_t sensors, std::int32_t width, std::int32_t height);
    /// Workspaces for every depth image of @p readings (their largest image),
    /// each with a footprint table for its sensor (made on its first frame).
    OwnedFootprintWorkspaces(const GridGeometry& grid, const std::vector<SensorReading>& readings);

    /// The workspaces, as fuse_frame_footprint and the controller take them.
    [[nodiscard]] Span<const FootprintWorkspace> spans() const noexcept { return {spans_.data(), spans_.size()}; }
    /// Bytes held (pyramids, opinions and tables), for the memory figures.
    [[nodiscard]] std::size_t bytes() const noexcept;

private:
    std::vector<float> min_;
    std::vector<float> max_;
    std::vector<std::uint8_t> invalid_;
    std::vector<std::int16_t> opinions_;
    std::vector<FootprintEntry> entries_;
    std::vector<FootprintTable> tables_;
    std::vector<FootprintWorkspace> spans_;
};

/// Fuses @p readings into @p grid (cleared first by the caller) by footprint
/// fusion when @p footprint is non-null, else ray by ray (fuse_frame with
/// @p rasterization through @p scratch): the one switch of host programs.
[[nodiscard]] Result<FusionStats> fuse_frame_by(EvidenceGrid& grid, Span<const SensorReading> readings,
                                                const SensorModelTable& model, Span<std::int16_t> scratch,
                                                Rasterization rasterization, const OwnedFootprintWorkspaces* footprint);

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_OWNED_FOOTPRINT_HPP
