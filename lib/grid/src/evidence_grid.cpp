// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/evidence_grid.hpp"

namespace cellguard {

Result<EvidenceGrid> EvidenceGrid::make(const GridGeometry& geometry, Span<std::int16_t> log_odds,
                                        Span<std::uint8_t> observed) noexcept {
    const std::size_t n = geometry.voxel_count();
    if (n == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (log_odds.size() < n || observed.size() < n || log_odds.data() == nullptr || observed.data() == nullptr) {
        return ErrorCode::kStorageTooSmall;
    }
    EvidenceGrid grid;
    grid.geometry_ = geometry;
    grid.log_odds_ = log_odds.subspan(0U, n);
    grid.observed_ = observed.subspan(0U, n);
    return grid;
}

void EvidenceGrid::clear() noexcept {
    for (std::int16_t& v : log_odds_) {
        v = kLogOddsUnknown;
    }
    for (std::uint8_t& o : observed_) {
        o = 0U;
    }
}

std::size_t EvidenceGrid::observed_count() const noexcept {
    std::size_t count = 0U;
    for (const std::uint8_t o : observed_) {
        count += (o != 0U) ? 1U : 0U;
    }
    return count;
}

Status accumulate_background(EvidenceGrid& background, const EvidenceGrid& frame, BackgroundClamp clamp) noexcept {
    if (!(background.geometry() == frame.geometry())) {
        return ErrorCode::kGeometryMismatch;
    }
    if (clamp.min > clamp.max || clamp.min == kNeverForeground) {
        return ErrorCode::kInvalidArgument;
    }
    const Span<std::int16_t> bg = background.log_odds();
    const Span<std::uint8_t> bg_obs = background.observed();
    const Span<std::int16_t> fr = frame.log_odds();
    const Span<std::uint8_t> fr_obs = frame.observed();
    for (std::size_t i = 0U; i < bg.size(); ++i) {
        if (fr_obs[i] != 0U) {
            const std::int32_t sum = static_cast<std::int32_t>(bg[i]) + static_cast<std::int32_t>(fr[i]);
            bg[i] = static_cast<std::int16_t>(sum < clamp.min ? clamp.min : sum > clamp.max ? clamp.max : sum);
            bg_obs[i] = 1U;
        }
    }
    return Status{};
}

}  // namespace cellguard
