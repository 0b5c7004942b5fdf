// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file accessibility.hpp
/// Accessibility analysis (the paper's sections II-IV): from a background
/// grid G_B to the prior, the int16 log-odds of P(fore) = P(acc) / 2 per
/// voxel, by one of the four methods of PriorMethod. Runs offline (at
/// commissioning) but, like all of lib/, needs no heap: scratch storage comes
/// from the caller, sized by accessibility_scratch_size().
///
/// Readings fixed here (see also shared/paper/READING-NOTES.md):
/// - Unobserved voxels (observed flag 0) count as P(occ) = 0.5 whatever
///   their stored log-odds (eq. 1 and the probabilistic baseline) and as
///   f = 0 in eq. 13.
/// - Beyond the grid: a closed face has occupied space behind it (not empty,
///   f = 1); an open face has free space behind it (empty, f = 0), except
///   where that space also lies beyond a closed face (the floor continues
///   under an open side).
/// - Configurations: the object R_c is the L1 ball of radius r around a
///   centre c (eq. 10). A configuration exists when R_c holds no cell beyond
///   a closed face (its centre is at least r from every closed face) and its
///   centre lies in the grid or at most r beyond open faces (centres farther
///   out cover no grid voxel). R_c may stick out of an open face.
/// - Sources (the seeds, A_0 lifted to configurations): every configuration
///   whose centre lies on an open face (the paper's A_0) or beyond one. The
///   latter is the object standing partly outside; it is reached from the
///   free space outside by moving straight in, which newly covers exactly
///   R_c's grid cells, so a source starts at cost G_ER(c) (eq. 14). With
///   these sources an empty voxel of an open face is accessible whenever it
///   lies at least r from every closed face, whatever lies behind it inside
///   the grid. A closed face is never a source.
///
/// Thresholded method (eqs. 1-7): E = {P(occ) < t_B}; E_R = configurations
/// whose cells are all empty (r erosions by the 6-neighbour cross, with the
/// boundary rule above); A_R = the 6-connected components of E_R that hold a
/// source; A = cells covered by some configuration of A_R (r dilations);
/// P(fore) = 0.5 in A, 0 elsewhere.
///
/// Probabilistic method (eqs. 8-21):
/// - f = 0 where P(occ) < t_E or the voxel is unobserved, else P(occ); the
///   cell cost is L = -ln(1 - f) = ln(1 + e^l) for log-odds l in nats,
///   computed exactly from the int16 (not as 1 - P in double, which rounds to
///   0 above ~37 nats). Every int16 value gives L <= 128 nats, so f = 1 occurs
///   only beyond closed faces, where it is a wall: configurations that would
///   cover such a cell do not exist (above). Hence P(acc) = 0 exactly, and the
///   prior is kNeverForeground, only where no existing configuration covers
///   the voxel or where there is no source at all (no open face, or no
///   configuration fits); everywhere else P(acc) > 0 and tiny values clamp to
///   kLogOddsMin.
/// - G_ER(c) = sum of L over R_c (eq. 14). A move from c_i to a 6-neighbour
///   c_j costs the sum of L over the cells of R_cj not in R_ci (eq. 17 as
///   READING-NOTES reads it). G_AR = least total cost from any source, by
///   Dijkstra's algorithm (eq. 18): configurations of cost 0 are settled by a
///   plain breadth-first flood first, the rest with a monotone bucket queue
///   (bucket_queue.hpp). Both are exact on the integer costs.
/// - The paper's approximation about turns is kept: each move conditions only
///   on the previous configuration, so cells that leave and re-enter R during
///   a turn are paid twice (in 3-D about r^2 cells per turn, not the r of the
///   paper's 2-D count); path costs therefore depend slightly on direction.
/// - P(acc)(c) = exp(-min of G_AR over the configurations whose R covers c)
///   (eq. 21, r passes of a cross minimum filter); P(fore) = P(acc) / 2.
///
/// Fixed-point costs and their error bound: cell costs are rounded to the
/// nearest 1/kAccessibilityCostUnitsPerNat nat (1/16384); every sum after that
/// is exact integer arithmetic. A nonzero cell cost is at least
/// L_min = -ln(1 - t_E), so each term's rounding is at most eps = 1 / (2 *
/// 16384 * L_min) of its value (eps = 2.9e-4 at t_E = 0.1; see
/// accessibility_cost_error_bound()), and for every voxel
///     |G_AR(fixed) - G_AR(exact)| <= eps * G_AR(exact),
/// before saturation. Costs at or above kAccessibilityCostSaturation (128
/// nats) are not resolved further: such voxels get G_AR = 128 nats, which
/// gives kLogOddsMin as every G_AR >= 127.4 nats would. The prior is then
/// rounded to the nearest log-odds unit (1/256 nat); since
/// |d ln(P/(2-P)) / dG| <= 2, its error is at most 2 * eps * G_AR nats + 1/2
/// unit. P(acc) as float underflows to 0 for G_AR above ~103 nats: use the
/// prior's sentinel, not P(acc) == 0, to tell "never" from "negligible".
///
/// Baselines (section IV): kThresholdedBaseline puts E in place of A in
/// eq. 7; kProbabilisticBaseline puts 1 - P(occ; G_B) in place of P(acc) in
/// eq. 6 (unobserved voxels: 0.5, so P(fore) = 0.25). Neither needs scratch.
///
/// Memory: the work arrays span the padded box of the grid (r more voxels
/// beyond each open face, then r + 1 more on every side). Per padded voxel the
/// thresholded method needs 2 bytes and 1 word (uint32), the probabilistic
/// method 7 words (cell costs then distances, G_ER, three move costs, two
/// queue links).
#ifndef CELLGUARD_ACCESSIBILITY_HPP
#define CELLGUARD_ACCESSIBILITY_HPP

#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_model.hpp"
#include "cellguard/prior/accessibility_params.hpp"
#include "cellguard/prior/bucket_queue.hpp"

namespace cellguard {

/// Largest radius r, in voxels, that the analysis accepts.
constexpr std::int32_t kMaxAccessibilityAnalysisRadius = kMaxAccessibilityRadius;
/// Fixed-point scale of the probabilistic method's costs: units per nat.
constexpr std::uint32_t kAccessibilityCostUnitsPerNat = 1U << 14U;
/// Cost (units) at which G_AR saturates: 2^21 - 1, just under 128 nats.
constexpr std::uint32_t kAccessibilityCostSaturation = MonotoneBucketQueue::kKeyLimit - 1U;

/// Caller-provided work storage; contents on entry do not matter and are
/// overwritten. Spans may be larger than needed.
struct AccessibilityScratch {
    Span<std::uint32_t> words{};  ///< at least accessibility_scratch_size().words elements
    Span<std::uint8_t> bytes{};   ///< at least accessibility_scratch_size().bytes elements
};

/// Element counts that an AccessibilityScratch must hold.
struct AccessibilityScratchSize {
    std::size_t words = 0U;  ///< uint32 elements
    std::size_t bytes = 0U;  ///< uint8 elements
};

namespace accessibility_detail {
/// Voxels of the padded work box along one axis (0 for n < 1).
constexpr std::uint64_t padded_extent(std::int32_t n, std::int32_t r, std::uint8_t open_faces,
                                      std::uint32_t axis) noexcept {
    const auto ur = static_cast<std::uint64_t>(r);
    const auto faces = static_cast<std::uint32_t>(open_faces);
    const std::uint64_t low = ((faces >> (2U * axis)) & 1U) != 0U ? ur : 0U;
    const std::uint64_t high = ((faces >> (2U * axis + 1U)) & 1U) != 0U ? ur : 0U;
    return n < 1 ? 0U : static_cast<std::uint64_t>(n) + low + high + 2U * (ur + 1U);
}
/// @p a * @p b, saturating at UINT64_MAX instead of wrapping.
constexpr std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) noexcept {
    return a != 0U && b > std::numeric_limits<std::uint64_t>::max() / a ? std::numeric_limits<std::uint64_t>::max()
                                                                        : a * b;
}
/// @p a + @p b, saturating at UINT64_MAX instead of wrapping.
constexpr std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) noexcept {
    return b > std::numeric_limits<std::uint64_t>::max() - a ? std::numeric_limits<std::uint64_t>::max() : a + b;
}
/// Voxels of the padded work box, for r clamped to [0, kMaxAccessibilityAnalysisRadius];
/// saturates at UINT64_MAX (dims beyond kMaxDimension, as a raw GridDims may hold).
constexpr std::uint64_t padded_count(GridDims dims, std::int32_t r, std::uint8_t open_faces) noexcept {
    const std::int32_t rc = r < 0 ? 0 : (r > kMaxAccessibilityAnalysisRadius ? kMaxAccessibilityAnalysisRadius : r);
    return saturating_mul(
        saturating_mul(padded_extent(dims.nx, rc, open_faces, 0U), padded_extent(dims.ny, rc, open_faces, 1U)),
        padded_extent(dims.nz, rc, open_faces, 2U));
}
/// @p v as size_t, saturating at SIZE_MAX.
constexpr std::size_t saturate_size(std::uint64_t v) noexcept {
    return v > std::numeric_limits<std::size_t>::max() ? std::numeric_limits<std::size_t>::max()
                                                       : static_cast<std::size_t>(v);
}
}  // namespace accessibility_detail

/// Scratch needed to compute a prior for a grid of @p dims with @p params
/// (radius clamped to [0, 8] here; invalid params are refused by
/// compute_accessibility_prior). The baselines, and unknown methods, need
/// none. Saturates at SIZE_MAX instead of wrapping.
constexpr AccessibilityScratchSize accessibility_scratch_size(GridDims dims,
                                                              const AccessibilityParams& params) noexcept {
    const std::uint64_t n = accessibility_detail::padded_count(dims, params.radius_voxels, params.open_faces);
    AccessibilityScratchSize size{};
    if (params.method == PriorMethod::kThresholded) {
        size.words = accessibility_detail::saturate_size(n);
        size.bytes = accessibility_detail::saturate_size(accessibility_detail::saturating_mul(2U, n));
    } else if (params.method == PriorMethod::kProbabilistic) {
        size.words = accessibility_detail::saturate_size(accessibility_detail::saturating_add(
            accessibility_detail::saturating_mul(7U, n), 2U * MonotoneBucketQueue::kListHeads));
    }
    return size;
}

/// Scratch that suffices for every valid parameter set on @p dims (r = 8,
/// all faces open, either method).
constexpr AccessibilityScratchSize accessibility_scratch_size_any(GridDims dims) noexcept {
    AccessibilityParams worst{};
    worst.radius_voxels = kMaxAccessibilityAnalysisRadius;
    worst.open_faces = kAllFaces;
    worst.method = PriorMethod::kThresholded;
    const AccessibilityScratchSize thresholded = accessibility_scratch_size(dims, worst);
    worst.method = PriorMethod::kProbabilistic;
    const AccessibilityScratchSize probabilistic = accessibility_scratch_size(dims, worst);
    AccessibilityScratchSize size{};
    size.words = thresholded.words > probabilistic.words ? thresholded.words : probabilistic.words;
    size.bytes = thresholded.bytes > probabilistic.bytes ? thresholded.bytes : probabilistic.bytes;
    return size;
}

/// Checks @p params: method one of PriorMethod's four values, t_b and t_e in
/// the open interval (0, 1) (NaN refused), radius in
/// [0, kMaxAccessibilityAnalysisRadius], open_faces within kAllFaces.
/// Errors: kInvalidArgument.
[[nodiscard]] Status validate_accessibility_params(const AccessibilityParams& params) noexcept;

/// Computes the prior of @p background with @p params into @p prior_out
/// (int16 log-odds of P(fore) per voxel, linear index order; values <= 0,
/// kNeverForeground where P(fore) = 0) and, when @p p_acc_out is not empty,
/// P(acc) per voxel as float, for inspection (the baselines write what they
/// put in its place: 1 in E / 0 outside it, or 1 - P(occ)). Only the first
/// voxel_count() elements of each output are written. Errors:
/// kInvalidArgument (params, see validate_accessibility_params, or a grid
/// without voxels), kStorageTooSmall (prior_out, a non-empty p_acc_out, or
/// scratch smaller than accessibility_scratch_size()), kCapacityExceeded (a
/// padded work box of more than MonotoneBucketQueue::kMaxItems voxels; not
/// reachable within kMaxVoxels). On error nothing is written to the outputs.
/// Deterministic; allocates nothing; uses no global state.
[[nodiscard]] Status compute_accessibility_prior(const EvidenceGrid& background, const AccessibilityParams& params,
                                                 AccessibilityScratch scratch, Span<std::int16_t> prior_out,
                                                 Span<float> p_acc_out) noexcept;

/// Log-odds of P(fore) = @p p_acc / 2 (eq. 6), ln(p / (2 - p)) in units
/// rounded to nearest: p_acc <= 0 (and NaN) gives kNeverForeground, tiny
/// positive values clamp to kLogOddsMin, p_acc >= 1 gives 0.
[[nodiscard]] std::int16_t fore_log_odds_from_accessibility(double p_acc) noexcept;

/// The relative bound eps on the fixed-point error of G_AR for @p t_e
/// (see above): 1 / (2 * kAccessibilityCostUnitsPerNat * -ln(1 - t_e)).
[[nodiscard]] double accessibility_cost_error_bound(double t_e) noexcept;

/// Fewest background frames G_B needs for @p params.method with @p model:
/// the smallest N >= 1 such that a voxel one sensor sees free (the constant
/// free evidence) in each of N frames, summed and clamped as
/// accumulate_background sums it, counts as empty: below t_E for the
/// probabilistic method and its baseline, below t_B for the thresholded ones.
/// Fewer frames leave seen-free space costly, and the probabilistic prior
/// then marks most of the cell inaccessible (nothing there could be
/// detected). 0 when no number of frames reaches it (clamp.min at or above
/// the threshold), and for @p params that validate_accessibility_params
/// refuses (a threshold outside (0, 1) has no such N). The commissioning
/// tool and the monitor refuse fewer.
[[nodiscard]] std::uint32_t min_background_frames(const AccessibilityParams& params, const SensorModelTable& model,
                                                  BackgroundClamp clamp = BackgroundClamp{}) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ACCESSIBILITY_HPP
