// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/zone_evaluation.hpp"

namespace cellguard {

const char* to_string(ZoneState state) noexcept {
    switch (state) {
        case ZoneState::kClear: return "CLEAR";
        case ZoneState::kIntruded: return "INTRUDED";
        case ZoneState::kUnseen: return "UNSEEN";
        case ZoneState::kFault: return "FAULT";
    }
    return "INVALID";
}

Status evaluate_zones(const EvidenceGrid& frame, Span<const std::int16_t> prior, const CompiledZones& zones,
                      const ZoneEvaluationParams& params, ZoneEvaluation& out,
                      Span<std::int16_t> subtracted_out) noexcept {
    const std::size_t n = frame.voxel_count();
    if (!(zones.geometry() == frame.geometry()) || zones.membership().size() != n) {
        return ErrorCode::kGeometryMismatch;
    }
    if (prior.size() < n || (!subtracted_out.empty() && subtracted_out.size() < n)) {
        return ErrorCode::kStorageTooSmall;
    }
    std::uint32_t foreground[kMaxZones] = {};
    std::uint32_t unseen[kMaxZones] = {};
    const Span<const std::int16_t> lo(frame.log_odds().data(), n);
    const Span<const std::uint8_t> observed(frame.observed().data(), n);
    const Span<const std::uint32_t> mask = zones.membership();
    const bool write_subtracted = !subtracted_out.empty();
    // Voxels that count are summed per run of equal zone masks, and a run's
    // sums go to its zones once: the same counts as adding voxel by voxel,
    // with the per-zone work done per run (zones are boxes and prisms, so
    // successive voxels mostly share their mask).
    std::uint32_t run_mask = 0U;
    std::uint32_t run_foreground = 0U;
    std::uint32_t run_unseen = 0U;
    const auto flush_run = [&]() noexcept {
        std::uint32_t bits = run_mask;
        for (std::size_t z = 0U; bits != 0U; ++z, bits >>= 1U) {
            if ((bits & 1U) != 0U) {
                foreground[z] += run_foreground;
                unseen[z] += run_unseen;
            }
        }
        run_foreground = 0U;
        run_unseen = 0U;
    };
    for (std::size_t i = 0U; i < n; ++i) {
        const std::int16_t sum = add_saturating(lo[i], prior[i]);
        if (write_subtracted) {
            subtracted_out[i] = sum;
        }
        const std::uint32_t bits = mask[i];
        if (bits == 0U) {
            continue;
        }
        const bool is_foreground = sum >= params.foreground_threshold;
        const bool is_unseen = observed[i] == 0U && prior[i] != kNeverForeground &&
                               prior[i] >= params.accessible_min_prior;
        if (!is_foreground && !is_unseen) {
            continue;
        }
        if (bits != run_mask) {
            flush_run();
            run_mask = bits;
        }
        // A run is at most n <= kMaxVoxels (2^27) voxels long: no overflow.
        run_foreground += is_foreground ? 1U : 0U;
        run_unseen += is_unseen ? 1U : 0U;
    }
    flush_run();
    out = ZoneEvaluation{};
    out.count = zones.size();
    for (std::size_t z = 0U; z < zones.size(); ++z) {
        const ZoneConfig& c = zones.config(z);
        ZoneReport& r = out.zones[z];
        r.foreground = foreground[z];
        r.unseen = unseen[z];
        const std::uint32_t bit = 1U << z;
        if (r.foreground >= c.min_foreground_voxels) {
            r.state = ZoneState::kIntruded;
            out.intruded_mask |= bit;
        } else if (r.unseen > c.max_unseen_voxels) {
            r.state = ZoneState::kUnseen;
            out.unseen_mask |= bit;
        } else {
            r.state = ZoneState::kClear;
        }
        if (r.state != ZoneState::kClear) {
            out.not_clear_mask |= bit;
        }
    }
    return Status{};
}

}  // namespace cellguard
