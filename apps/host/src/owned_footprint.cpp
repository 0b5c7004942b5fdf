// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/owned_footprint.hpp"

#include <algorithm>

namespace cellguard::host {

OwnedFootprintWorkspaces::OwnedFootprintWorkspaces(const GridGeometry& grid, std::size_t sensors, std::int32_t width,
                                                   std::int32_t height) {
    const std::size_t n = std::max<std::size_t>(sensors, 1U);
    const std::size_t cells = depth_pyramid_cells(width, height);
    const std::size_t voxels = grid.voxel_count();
    min_.resize(n * cells);
    max_.resize(n * cells);
    invalid_.resize(n * cells);
    opinions_.resize(n * voxels);
    for (std::size_t i = 0; i < n; ++i) {
        spans_.push_back(FootprintWorkspace{{min_.data() + i * cells, cells},
                                            {max_.data() + i * cells, cells},
                                            {invalid_.data() + i * cells, cells},
                                            {opinions_.data() + i * voxels, voxels}});
    }
}

namespace {

std::int32_t largest(const std::vector<SensorReading>& readings, bool width) {
    std::int32_t m = 1;
    for (const SensorReading& r : readings) {
        m = std::max(m, width ? r.intrinsics.width : r.intrinsics.height);
    }
    return m;
}

}  // namespace

OwnedFootprintWorkspaces::OwnedFootprintWorkspaces(const GridGeometry& grid, const std::vector<SensorReading>& readings)
    : OwnedFootprintWorkspaces(grid, readings.size(), largest(readings, true), largest(readings, false)) {
    // Each count is a pass over the grid's voxels in view: taken once per sensor.
    std::vector<std::size_t> counts(readings.size());
    std::size_t total = 0U;
    for (std::size_t i = 0U; i < readings.size(); ++i) {
        counts[i] = footprint_table_entries(grid, readings[i]);
        total += counts[i];
    }
    entries_.resize(total);
    tables_.resize(readings.size());
    std::size_t at = 0U;
    for (std::size_t i = 0U; i < readings.size(); ++i) {
        const std::size_t n = counts[i];
        tables_[i] = FootprintTable(Span<FootprintEntry>(entries_.data() + at, n));
        spans_[i].table = &tables_[i];
        at += n;
    }
}

std::size_t OwnedFootprintWorkspaces::bytes() const noexcept {
    return min_.size() * sizeof(float) + max_.size() * sizeof(float) + invalid_.size() +
           opinions_.size() * sizeof(std::int16_t) + entries_.size() * sizeof(FootprintEntry);
}

Result<FusionStats> fuse_frame_by(EvidenceGrid& grid, Span<const SensorReading> readings, const SensorModelTable& model,
                                  Span<std::int16_t> scratch, Rasterization rasterization,
                                  const OwnedFootprintWorkspaces* footprint) {
    if (footprint == nullptr) {
        return fuse_frame(grid, readings, model, scratch, rasterization);
    }
    SequentialRunner runner;
    return fuse_frame_footprint(grid, readings, model, footprint->spans(), runner);
}

}  // namespace cellguard::host
