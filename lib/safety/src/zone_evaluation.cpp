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

namespace {

/// Per-zone counts of one pass.
struct ZoneCounts {
    std::uint32_t foreground[kMaxZones] = {};
    std::uint32_t unseen[kMaxZones] = {};
    std::uint32_t robot[kMaxZones] = {};
};

/// Voxels that count are summed per run of equal zone masks, and a run's
/// sums go to its zones once: the same counts as adding voxel by voxel, with
/// the per-zone work done per run (zones are boxes and prisms, so successive
/// voxels mostly share their mask).
class RunCounter {
public:
    explicit RunCounter(ZoneCounts& counts) noexcept : counts_(&counts) {}
    void add(std::uint32_t bits, bool foreground, bool unseen, bool robot) noexcept {
        if (bits != mask_) {
            flush();
            mask_ = bits;
        }
        // A run is at most n <= kMaxVoxels (2^27) voxels long: no overflow.
        foreground_ += foreground ? 1U : 0U;
        unseen_ += unseen ? 1U : 0U;
        robot_ += robot ? 1U : 0U;
    }
    void flush() noexcept {
        std::uint32_t bits = mask_;
        for (std::size_t z = 0U; bits != 0U; ++z, bits >>= 1U) {
            if ((bits & 1U) != 0U) {
                counts_->foreground[z] += foreground_;
                counts_->unseen[z] += unseen_;
                counts_->robot[z] += robot_;
            }
        }
        foreground_ = 0U;
        unseen_ = 0U;
        robot_ = 0U;
    }

private:
    ZoneCounts* counts_;
    std::uint32_t mask_ = 0U;
    std::uint32_t foreground_ = 0U;
    std::uint32_t unseen_ = 0U;
    std::uint32_t robot_ = 0U;
};

void count_voxels(const EvidenceGrid& frame, Span<const std::int16_t> prior, Span<const std::uint32_t> mask,
                  const ZoneEvaluationParams& params, const ZoneEvaluationScope& scope, std::uint32_t active,
                  ZoneCounts& counts, Span<std::int16_t> subtracted_out) noexcept {
    const std::size_t n = frame.voxel_count();
    const Span<const std::int16_t> lo(frame.log_odds().data(), n);
    const Span<const std::uint8_t> observed(frame.observed().data(), n);
    const bool write_subtracted = !subtracted_out.empty();
    const bool have_robot = !scope.robot_mask.empty();
    RunCounter run(counts);
    for (std::size_t i = 0U; i < n; ++i) {
        const std::int16_t sum = add_saturating(lo[i], prior[i]);
        if (write_subtracted) {
            subtracted_out[i] = sum;
        }
        const std::uint32_t bits = mask[i] & active;
        if (bits == 0U) {
            continue;
        }
        if (have_robot && scope.robot_mask[i] != 0U) {
            run.add(bits, false, false, true);  // the robot's: neither foreground nor unseen
            continue;
        }
        const bool is_foreground = sum >= params.foreground_threshold;
        const bool is_unseen = observed[i] == 0U && prior[i] != kNeverForeground &&
                               prior[i] >= params.accessible_min_prior;
        if (is_foreground || is_unseen) {
            run.add(bits, is_foreground, is_unseen, false);
        }
    }
    run.flush();
}

}  // namespace

Status evaluate_zones(const EvidenceGrid& frame, Span<const std::int16_t> prior, const CompiledZones& zones,
                      const ZoneEvaluationParams& params, ZoneEvaluation& out,
                      Span<std::int16_t> subtracted_out) noexcept {
    return evaluate_zones(frame, prior, zones, params, ZoneEvaluationScope{}, out, subtracted_out);
}

Status evaluate_zones(const EvidenceGrid& frame, Span<const std::int16_t> prior, const CompiledZones& zones,
                      const ZoneEvaluationParams& params, const ZoneEvaluationScope& scope, ZoneEvaluation& out,
                      Span<std::int16_t> subtracted_out) noexcept {
    const std::size_t n = frame.voxel_count();
    if (!(zones.geometry() == frame.geometry()) || zones.membership().size() != n) {
        return ErrorCode::kGeometryMismatch;
    }
    if (prior.size() < n || (!subtracted_out.empty() && subtracted_out.size() < n) ||
        (!scope.robot_mask.empty() && scope.robot_mask.size() < n)) {
        return ErrorCode::kStorageTooSmall;
    }
    const std::uint32_t active = scope.active_zones & all_zone_bits(zones.size());
    ZoneCounts counts;
    count_voxels(frame, prior, zones.membership(), params, scope, active, counts, subtracted_out);
    out = ZoneEvaluation{};
    out.count = zones.size();
    out.active_mask = active;
    for (std::size_t z = 0U; z < zones.size(); ++z) {
        const ZoneConfig& c = zones.config(z);
        ZoneReport& r = out.zones[z];
        r.foreground = counts.foreground[z];
        r.unseen = counts.unseen[z];
        r.robot = counts.robot[z];
        const std::uint32_t bit = 1U << z;
        // A zone outside the active case is not evaluated: CLEAR, no mask bit.
        const bool active_zone = (active & bit) != 0U;
        r.state = ZoneState::kClear;
        if (active_zone && r.foreground >= c.min_foreground_voxels) {
            r.state = ZoneState::kIntruded;
            out.intruded_mask |= bit;
        } else if (active_zone && r.unseen > c.max_unseen_voxels) {
            r.state = ZoneState::kUnseen;
            out.unseen_mask |= bit;
        }
        if (r.state != ZoneState::kClear) {
            out.not_clear_mask |= bit;
        }
    }
    return Status{};
}

}  // namespace cellguard
