// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/prior/accessibility.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/prior/bucket_queue.hpp"
#include "cellguard/prior/morphology.hpp"

namespace cellguard {

namespace {

// Distance label of a work-box voxel that is not a configuration; also the
// "no configuration covers this voxel" value of the minimum filter.
constexpr std::uint32_t kNoConfiguration = 0xFFFFFFFFU;
// Distance label of a configuration that Dijkstra has not reached yet.
constexpr std::uint32_t kUnreached = 0xFFFFFFFEU;
// Values of the thresholded byte arrays.
constexpr std::uint8_t kOccupied = 0U;
constexpr std::uint8_t kEmpty = 1U;
constexpr std::uint8_t kAccessible = 2U;
// Largest number of (a, b) pairs with |a| + |b| <= r: 2 r^2 + 2 r + 1.
constexpr std::size_t kMaxDiamond = 2U * kMaxAccessibilityAnalysisRadius * kMaxAccessibilityAnalysisRadius +
                                    2U * kMaxAccessibilityAnalysisRadius + 1U;

// Where an array coordinate lies on one axis, relative to the grid.
enum class Zone : std::uint8_t { kInside, kOpenSide, kClosedSide };

// The padded work box. Array coordinates: the grid starts at g0; the work box
// W = [w0, w1) adds r beyond each open face; a margin of r + 1 surrounds W.
// Configurations (centres of R that exist) fill the box [c0, c1).
struct Layout {
    std::int32_t n[3] = {};
    std::int32_t r = 0;
    bool open_low[3] = {};
    bool open_high[3] = {};
    std::int32_t a[3] = {};
    std::int32_t g0[3] = {};
    std::int32_t w0[3] = {};
    std::int32_t w1[3] = {};
    std::int32_t c0[3] = {};
    std::int32_t c1[3] = {};
    std::size_t sy = 0U;
    std::size_t sz = 0U;
    std::size_t count = 0U;

    [[nodiscard]] std::size_t index(std::int32_t x, std::int32_t y, std::int32_t z) const noexcept {
        return static_cast<std::size_t>(x) + sy * static_cast<std::size_t>(y) + sz * static_cast<std::size_t>(z);
    }
    [[nodiscard]] Zone zone(std::size_t axis, std::int32_t c) const noexcept {
        if (c < g0[axis]) {
            return open_low[axis] ? Zone::kOpenSide : Zone::kClosedSide;
        }
        if (c >= g0[axis] + n[axis]) {
            return open_high[axis] ? Zone::kOpenSide : Zone::kClosedSide;
        }
        return Zone::kInside;
    }
    [[nodiscard]] bool configurations_exist() const noexcept { return c0[0] < c1[0] && c0[1] < c1[1] && c0[2] < c1[2]; }
    // True when coordinate c on this axis lies on an open face or beyond the
    // grid (array coords); a configuration is a source when this holds on
    // any axis.
    [[nodiscard]] bool source_coordinate(std::size_t axis, std::int32_t c) const noexcept {
        return c < g0[axis] || c >= g0[axis] + n[axis] || (open_low[axis] && c == g0[axis]) ||
               (open_high[axis] && c == g0[axis] + n[axis] - 1);
    }
    // Calls f(index) for every source: every configuration centred on an
    // open face or beyond one. Visits only the sources, row by row.
    template <typename F>
    void for_each_source(F&& f) const noexcept {
        if (!configurations_exist()) {
            return;
        }
        for (std::int32_t z = c0[2]; z < c1[2]; ++z) {
            const bool z_source = source_coordinate(2U, z);
            for (std::int32_t y = c0[1]; y < c1[1]; ++y) {
                const std::size_t row = index(0, y, z);
                if (z_source || source_coordinate(1U, y)) {
                    for (std::int32_t x = c0[0]; x < c1[0]; ++x) {
                        f(row + static_cast<std::size_t>(x));
                    }
                    continue;
                }
                // Only x on or beyond the two x faces can qualify.
                const std::int32_t low_end = std::min(c1[0], g0[0] + 1);
                const std::int32_t high_begin = std::max(low_end, std::max(c0[0], g0[0] + n[0] - 1));
                for (std::int32_t x = c0[0]; x < low_end; ++x) {
                    if (source_coordinate(0U, x)) {
                        f(row + static_cast<std::size_t>(x));
                    }
                }
                for (std::int32_t x = high_begin; x < c1[0]; ++x) {
                    if (source_coordinate(0U, x)) {
                        f(row + static_cast<std::size_t>(x));
                    }
                }
            }
        }
    }
    [[nodiscard]] PaddedRegion work_region() const noexcept {
        PaddedRegion region;
        region.array = GridDims{a[0], a[1], a[2]};
        region.first = VoxelCoord{w0[0], w0[1], w0[2]};
        region.size = GridDims{w1[0] - w0[0], w1[1] - w0[1], w1[2] - w0[2]};
        return region;
    }
};

Layout make_layout(GridDims dims, const AccessibilityParams& params) noexcept {
    Layout l;
    l.n[0] = dims.nx;
    l.n[1] = dims.ny;
    l.n[2] = dims.nz;
    l.r = params.radius_voxels;
    const std::int32_t margin = l.r + 1;
    for (std::size_t k = 0U; k < 3U; ++k) {
        const auto faces = static_cast<std::uint32_t>(params.open_faces);
        l.open_low[k] = ((faces >> (2U * k)) & 1U) != 0U;
        l.open_high[k] = ((faces >> (2U * k + 1U)) & 1U) != 0U;
        const std::int32_t pad_low = l.open_low[k] ? l.r : 0;
        const std::int32_t pad_high = l.open_high[k] ? l.r : 0;
        l.a[k] = l.n[k] + pad_low + pad_high + 2 * margin;
        l.w0[k] = margin;
        l.g0[k] = margin + pad_low;
        l.w1[k] = l.g0[k] + l.n[k] + pad_high;
        l.c0[k] = l.open_low[k] ? l.g0[k] - l.r : l.g0[k] + l.r;
        l.c1[k] = l.open_high[k] ? l.g0[k] + l.n[k] + l.r : l.g0[k] + l.n[k] - l.r;
    }
    l.sy = static_cast<std::size_t>(l.a[0]);
    l.sz = l.sy * static_cast<std::size_t>(l.a[1]);
    l.count = l.sz * static_cast<std::size_t>(l.a[2]);
    CG_ENFORCE(l.count == accessibility_detail::padded_count(dims, params.radius_voxels, params.open_faces),
               "accessibility: layout differs from the scratch size formula");
    return l;
}

// Writes value into every array voxel outside the work box W.
template <typename T>
void fill_outside_work_box(const Layout& l, Span<T> buffer, T value) noexcept {
    const auto a0 = static_cast<std::size_t>(l.a[0]);
    const auto w0 = static_cast<std::size_t>(l.w0[0]);
    const auto w1 = static_cast<std::size_t>(l.w1[0]);
    for (std::int32_t z = 0; z < l.a[2]; ++z) {
        for (std::int32_t y = 0; y < l.a[1]; ++y) {
            const std::size_t row = l.index(0, y, z);
            T* const p = buffer.subspan(row, a0).data();
            if (z < l.w0[2] || z >= l.w1[2] || y < l.w0[1] || y >= l.w1[1]) {
                std::fill(p, p + a0, value);
            } else {
                std::fill(p, p + w0, value);
                std::fill(p + w1, p + a0, value);
            }
        }
    }
}

// Whole log-odds units @p units (a rounded value <= 0 here) as int16 log-odds, clamped to
// [kLogOddsMin, kLogOddsMax]; at or below kLogOddsMin without the int32 cast, which could overflow.
std::int16_t log_odds_from_units(double units) noexcept {
    return units <= static_cast<double>(kLogOddsMin) ? kLogOddsMin : clamp_log_odds(static_cast<std::int32_t>(units));
}

// Smallest log-odds l such that P(occ) = probability_from_log_odds(l) >= t
// (32768 when there is none): P(occ) < t exactly when l < the result.
std::int32_t first_log_odds_at_or_above(double t) noexcept {
    const double guess = std::ceil((std::log(t) - std::log1p(-t)) * static_cast<double>(kLogOddsScale));
    std::int32_t l = guess >= static_cast<double>(kLogOddsMax)   ? kLogOddsMax
                     : guess <= static_cast<double>(kLogOddsMin) ? kLogOddsMin
                                                                 : static_cast<std::int32_t>(guess);
    while (l > kLogOddsMin && probability_from_log_odds(static_cast<std::int16_t>(l - 1)) >= t) {
        --l;
    }
    while (l <= kLogOddsMax && probability_from_log_odds(static_cast<std::int16_t>(l)) < t) {
        ++l;
    }
    return l;
}

// ln(P(fore) / (1 - P(fore))) for P(fore) = exp(-g) / 2, g >= 0 nats, in units.
std::int16_t fore_log_odds_from_cost(double g) noexcept {
    const double nats = -g - std::log(2.0 - std::exp(-g));
    return log_odds_from_units(std::nearbyint(nats * static_cast<double>(kLogOddsScale)));
}

// -ln(1 - P(occ)) = ln(1 + e^x) for log-odds x in nats, without rounding
// P(occ) to 1.
double softplus(double x) noexcept { return x > 0.0 ? x + std::log1p(std::exp(-x)) : std::log1p(std::exp(x)); }

// ---------------------------------------------------------------- baselines

void thresholded_baseline(const EvidenceGrid& g, std::int32_t empty_below, Span<std::int16_t> prior,
                          Span<float> p_acc) noexcept {
    const Span<std::int16_t> lo = g.log_odds();  // read only
    const Span<std::uint8_t> ob = g.observed();  // read only
    for (std::size_t i = 0U; i < g.voxel_count(); ++i) {
        const std::int32_t l = ob[i] != 0U ? lo[i] : 0;
        const bool empty = l < empty_below;
        prior[i] = empty ? kLogOddsUnknown : kNeverForeground;
        if (!p_acc.empty()) {
            p_acc[i] = empty ? 1.0F : 0.0F;
        }
    }
}

void probabilistic_baseline(const EvidenceGrid& g, Span<std::int16_t> prior, Span<float> p_acc) noexcept {
    const Span<std::int16_t> lo = g.log_odds();  // read only
    const Span<std::uint8_t> ob = g.observed();  // read only
    std::int32_t memo_l = 0;                     // log-odds 0 (P(occ) = 0.5): P(acc) = 0.5, prior ln(1/3)
    std::int16_t memo_prior = fore_log_odds_from_accessibility(0.5);
    float memo_p = 0.5F;
    for (std::size_t i = 0U; i < g.voxel_count(); ++i) {
        const std::int32_t l = ob[i] != 0U ? lo[i] : 0;
        if (l != memo_l) {
            memo_l = l;
            if (l == kNeverForeground) {  // P(occ) = 0 exactly
                memo_prior = kLogOddsUnknown;
                memo_p = 1.0F;
            } else {
                // P(acc) = 1 - P(occ) = 1 / (1 + e^x); ln(P / (2 - P)) = -ln(1 + 2 e^x).
                const double x = static_cast<double>(l) / static_cast<double>(kLogOddsScale);
                const double units = std::nearbyint(-std::log1p(2.0 * std::exp(x)) *
                                                    static_cast<double>(kLogOddsScale));
                memo_prior = log_odds_from_units(units);
                memo_p = static_cast<float>(1.0 / (1.0 + std::exp(x)));
            }
        }
        prior[i] = memo_prior;
        if (!p_acc.empty()) {
            p_acc[i] = memo_p;
        }
    }
}

// ---------------------------------------------------------------- thresholded

// E (eq. 1) into @p cur: kEmpty or kOccupied per array voxel; on the grid
// from the log-odds, beyond it empty unless beyond a closed face.
void empty_cells(const EvidenceGrid& g, const Layout& l, std::int32_t empty_below, Span<std::uint8_t> cur) noexcept {
    const Span<std::int16_t> lo = g.log_odds();  // read only
    const Span<std::uint8_t> ob = g.observed();  // read only
    const auto a0 = static_cast<std::size_t>(l.a[0]);
    for (std::int32_t z = 0; z < l.a[2]; ++z) {
        const Zone zz = l.zone(2U, z);
        for (std::int32_t y = 0; y < l.a[1]; ++y) {
            const Zone zy = l.zone(1U, y);
            std::uint8_t* const row = cur.subspan(l.index(0, y, z), a0).data();
            if (zz == Zone::kClosedSide || zy == Zone::kClosedSide) {
                std::fill(row, row + a0, kOccupied);
                continue;
            }
            const auto g_begin = static_cast<std::size_t>(l.g0[0]);
            const auto g_end = g_begin + static_cast<std::size_t>(l.n[0]);
            std::fill(row, row + g_begin, l.open_low[0] ? kEmpty : kOccupied);
            std::fill(row + g_end, row + a0, l.open_high[0] ? kEmpty : kOccupied);
            if (zy != Zone::kInside || zz != Zone::kInside) {
                std::fill(row + g_begin, row + g_end, kEmpty);  // beyond an open face only
                continue;
            }
            const std::size_t gi = g.geometry().index_of(VoxelCoord{0, y - l.g0[1], z - l.g0[2]});
            for (std::size_t x = 0U; x < g_end - g_begin; ++x) {
                const std::int32_t lv = ob[gi + x] != 0U ? lo[gi + x] : 0;
                row[g_begin + x] = lv < empty_below ? kEmpty : kOccupied;
            }
        }
    }
}

// A_R (eq. 3) in @p cur: flood fill of the empty voxels (E_R) from the
// sources, 6-neighbour; reached voxels become kAccessible. @p queue holds
// the FIFO.
void flood_from_sources(const Layout& l, Span<std::uint8_t> cur, Span<std::uint32_t> queue) noexcept {
    fill_outside_work_box(l, cur, kOccupied);
    std::size_t head = 0U;
    std::size_t tail = 0U;
    l.for_each_source([&](std::size_t i) {
        if (cur[i] == kEmpty) {
            cur[i] = kAccessible;
            queue[tail++] = static_cast<std::uint32_t>(i);
        }
    });
    std::uint8_t* const state = cur.data();
    std::uint32_t* const fifo = queue.data();
    auto visit = [&](std::size_t j) noexcept {
        if (state[j] == kEmpty) {
            state[j] = kAccessible;
            fifo[tail++] = static_cast<std::uint32_t>(j);
        }
    };
    while (head < tail) {
        const std::size_t i = fifo[head++];  // in W, so all six neighbours are in the array
        visit(i + 1U);
        visit(i - 1U);
        visit(i + l.sy);
        visit(i - l.sy);
        visit(i + l.sz);
        visit(i - l.sz);
    }
}

// P(fore) = 0.5 in A, 0 elsewhere (eq. 7), per grid voxel, from @p accessible (1 in A).
void write_thresholded_prior(const Layout& l, Span<const std::uint8_t> accessible, Span<std::int16_t> prior,
                             Span<float> p_acc) noexcept {
    std::size_t gi = 0U;
    for (std::int32_t z = 0; z < l.n[2]; ++z) {
        for (std::int32_t y = 0; y < l.n[1]; ++y) {
            const std::size_t row = l.index(l.g0[0], y + l.g0[1], z + l.g0[2]);
            for (std::int32_t x = 0; x < l.n[0]; ++x, ++gi) {
                const bool in_a = accessible[row + static_cast<std::size_t>(x)] != 0U;
                prior[gi] = in_a ? kLogOddsUnknown : kNeverForeground;
                if (!p_acc.empty()) {
                    p_acc[gi] = in_a ? 1.0F : 0.0F;
                }
            }
        }
    }
}

// The thresholded method (section II): E, E_R, A_R, A, and the prior.
void thresholded(const EvidenceGrid& g, const Layout& l, std::int32_t empty_below, AccessibilityScratch scratch,
                 Span<std::int16_t> prior, Span<float> p_acc) noexcept {
    Span<std::uint8_t> cur = scratch.bytes.subspan(0U, l.count);
    Span<std::uint8_t> other = scratch.bytes.subspan(l.count, l.count);

    empty_cells(g, l, empty_below, cur);
    std::copy(cur.begin(), cur.end(), other.begin());  // same boundary layer in both

    // E_R = E eroded by R (eq. 2): r erosions by the cross.
    const PaddedRegion work = l.work_region();
    for (std::int32_t k = 0; k < l.r; ++k) {
        erode_cross(work, Span<const std::uint8_t>(cur.data(), cur.size()), other);
        std::swap(cur, other);
    }

    flood_from_sources(l, cur, scratch.words.subspan(0U, l.count));

    // A = A_R dilated by R (eq. 4): r dilations by the cross.
    for (std::int32_t z = l.w0[2]; z < l.w1[2]; ++z) {
        for (std::int32_t y = l.w0[1]; y < l.w1[1]; ++y) {
            for (std::int32_t x = l.w0[0]; x < l.w1[0]; ++x) {
                const std::size_t i = l.index(x, y, z);
                cur[i] = cur[i] == kAccessible ? 1U : 0U;
            }
        }
    }
    fill_outside_work_box(l, other, std::uint8_t{0U});
    for (std::int32_t k = 0; k < l.r; ++k) {
        dilate_cross(work, Span<const std::uint8_t>(cur.data(), cur.size()), other);
        std::swap(cur, other);
    }

    write_thresholded_prior(l, Span<const std::uint8_t>(cur.data(), cur.size()), prior, p_acc);
}

// ---------------------------------------------------------------- probabilistic

// Offsets (linear, array strides) of the cells that a move along +axis newly
// covers, relative to the destination: d[axis] = r - |d_b| - |d_c| for every
// (d_b, d_c) with |d_b| + |d_c| <= r. Returns the number of offsets.
std::size_t move_cap_offsets(const Layout& l, std::size_t axis, std::ptrdiff_t (&out)[kMaxDiamond]) noexcept {
    const std::ptrdiff_t stride[3] = {1, static_cast<std::ptrdiff_t>(l.sy), static_cast<std::ptrdiff_t>(l.sz)};
    const std::size_t b = (axis + 1U) % 3U;
    const std::size_t c = (axis + 2U) % 3U;
    std::size_t count = 0U;
    for (std::int32_t db = -l.r; db <= l.r; ++db) {
        const std::int32_t rest = l.r - std::abs(db);
        for (std::int32_t dc = -rest; dc <= rest; ++dc) {
            const std::int32_t da = rest - std::abs(dc);
            out[count++] = da * stride[axis] + db * stride[b] + dc * stride[c];
        }
    }
    return count;
}

// Values per block of the inner loops: a fixed trip count lets the compiler
// vectorise them even at -O2 (GCC's "very cheap" cost model).
constexpr std::size_t kBlock = 8U;

// out[x] = sum over k of base[plus[k] + x] - base[minus[k] + x] (minus may be
// null: no subtraction), for x in [0, width); modulo 2^32. Blocks of kBlock;
// a row that is not a multiple of kBlock ends with a block that overlaps the
// previous one (out does not alias base, so recomputing is harmless).
void sum_shifted_rows(const std::uint32_t* base, const std::ptrdiff_t* plus, const std::ptrdiff_t* minus,
                      std::size_t count, std::uint32_t* out, std::size_t width) noexcept {
    auto block = [&](std::size_t x) noexcept {
        std::uint32_t acc[kBlock] = {};
        for (std::size_t k = 0U; k < count; ++k) {
            const std::uint32_t* const p = base + plus[k] + static_cast<std::ptrdiff_t>(x);
            for (std::size_t j = 0U; j < kBlock; ++j) {
                acc[j] += p[j];
            }
            if (minus != nullptr) {
                const std::uint32_t* const q = base + minus[k] + static_cast<std::ptrdiff_t>(x);
                for (std::size_t j = 0U; j < kBlock; ++j) {
                    acc[j] -= q[j];
                }
            }
        }
        for (std::size_t j = 0U; j < kBlock; ++j) {
            out[x + j] = acc[j];
        }
    };
    if (width >= kBlock) {
        for (std::size_t x = 0U; x + kBlock <= width; x += kBlock) {
            block(x);
        }
        if (width % kBlock != 0U) {
            block(width - kBlock);
        }
        return;
    }
    for (std::size_t x = 0U; x < width; ++x) {
        std::uint32_t acc = 0U;
        for (std::size_t k = 0U; k < count; ++k) {
            acc += base[plus[k] + static_cast<std::ptrdiff_t>(x)];
            if (minus != nullptr) {
                acc -= base[minus[k] + static_cast<std::ptrdiff_t>(x)];
            }
        }
        out[x] = acc;
    }
}

// The probabilistic method's working arrays, all carved from the scratch words.
struct ProbabilisticBuffers {
    Span<std::uint32_t> dist;    // cell costs, then their prefix sums, then the labels G_AR
    Span<std::uint32_t> ger;     // G_ER per configuration
    Span<std::uint32_t> cap[3];  // move costs along +x, +y, +z; cap[0] is reused by the minimum filter
    Span<std::uint32_t> next;    // the bucket queue's links (phase 1 of Dijkstra: its FIFO)
    Span<std::uint32_t> prev;    // the bucket queue's back links
};

ProbabilisticBuffers probabilistic_buffers(const Layout& l, const AccessibilityScratch& scratch) noexcept {
    const std::size_t n = l.count;
    const std::size_t links = MonotoneBucketQueue::link_count(n);
    ProbabilisticBuffers b;
    b.dist = scratch.words.subspan(0U, n);
    b.ger = scratch.words.subspan(n, n);
    b.cap[0] = scratch.words.subspan(2U * n, n);
    b.cap[1] = scratch.words.subspan(3U * n, n);
    b.cap[2] = scratch.words.subspan(4U * n, n);
    b.next = scratch.words.subspan(5U * n, links);
    b.prev = scratch.words.subspan(5U * n + links, links);
    return b;
}

// Cell costs L = -ln(1 - f) (eq. 13-14) in fixed point into @p dist; zero
// outside the grid and where f = 0 (unobserved, or below the free threshold).
void cell_costs(const EvidenceGrid& g, const Layout& l, std::int32_t free_below, Span<std::uint32_t> dist) noexcept {
    const Span<std::int16_t> lo = g.log_odds();  // read only
    const Span<std::uint8_t> ob = g.observed();  // read only
    std::fill(dist.begin(), dist.end(), 0U);
    std::int32_t memo_l = kLogOddsMax + 1;
    std::uint32_t memo_cost = 0U;
    std::size_t gi = 0U;
    for (std::int32_t z = 0; z < l.n[2]; ++z) {
        for (std::int32_t y = 0; y < l.n[1]; ++y) {
            const std::size_t row = l.index(l.g0[0], y + l.g0[1], z + l.g0[2]);
            for (std::int32_t x = 0; x < l.n[0]; ++x, ++gi) {
                const std::int32_t lv = lo[gi];
                if (ob[gi] == 0U || lv < free_below) {
                    continue;  // f = 0
                }
                if (lv != memo_l) {
                    memo_l = lv;
                    const double nats = softplus(static_cast<double>(lv) / static_cast<double>(kLogOddsScale));
                    const double units = std::nearbyint(nats * static_cast<double>(kAccessibilityCostUnitsPerNat));
                    memo_cost = units >= static_cast<double>(kAccessibilityCostSaturation)
                                    ? kAccessibilityCostSaturation
                                    : static_cast<std::uint32_t>(units);
                }
                dist[row + static_cast<std::size_t>(x)] = memo_cost;
            }
        }
    }
}

// Move costs along +x, +y, +z (eq. 17) into @p cap: for each configuration
// c, the sum of the cell costs @p dist over the cells that a move into c
// newly covers.
void move_costs(const Layout& l, Span<const std::uint32_t> dist, const Span<std::uint32_t> (&cap)[3]) noexcept {
    const auto width = static_cast<std::size_t>(l.w1[0] - l.w0[0]);
    std::ptrdiff_t offsets[3][kMaxDiamond] = {};
    std::size_t offset_count = 0U;
    for (std::size_t axis = 0U; axis < 3U; ++axis) {
        offset_count = move_cap_offsets(l, axis, offsets[axis]);
    }
    for (std::int32_t z = l.w0[2]; z < l.w1[2]; ++z) {
        for (std::int32_t y = l.w0[1]; y < l.w1[1]; ++y) {
            const std::size_t row = l.index(l.w0[0], y, z);
            for (std::size_t axis = 0U; axis < 3U; ++axis) {
                sum_shifted_rows(dist.data() + row, offsets[axis], nullptr, offset_count,
                                 cap[axis].subspan(row, width).data(), width);
            }
        }
    }
}

// G_ER (eq. 14) into @p ger: the sum of the cell costs over R_c, from
// inclusive prefix sums along x that replace the costs in @p dist (modulo
// 2^32: every segment sum is far below 2^32, so differences are exact).
void eroded_costs(const Layout& l, Span<std::uint32_t> dist, Span<std::uint32_t> ger) noexcept {
    const auto a0 = static_cast<std::size_t>(l.a[0]);
    for (std::size_t row = 0U; row < l.count; row += a0) {
        std::uint32_t sum = 0U;
        for (std::size_t x = 0U; x < a0; ++x) {
            sum += dist[row + x];
            dist[row + x] = sum;
        }
    }
    const auto width = static_cast<std::size_t>(l.w1[0] - l.w0[0]);
    const auto sy = static_cast<std::ptrdiff_t>(l.sy);
    const auto sz = static_cast<std::ptrdiff_t>(l.sz);
    std::ptrdiff_t high[kMaxDiamond] = {};
    std::ptrdiff_t low[kMaxDiamond] = {};
    std::size_t count = 0U;
    for (std::int32_t dz = -l.r; dz <= l.r; ++dz) {
        const std::int32_t rest = l.r - std::abs(dz);
        for (std::int32_t dy = -rest; dy <= rest; ++dy) {
            const std::int32_t w = rest - std::abs(dy);  // the row segment [x - w, x + w]
            high[count] = dz * sz + dy * sy + w;
            low[count] = dz * sz + dy * sy - w - 1;
            ++count;
        }
    }
    for (std::int32_t z = l.w0[2]; z < l.w1[2]; ++z) {
        for (std::int32_t y = l.w0[1]; y < l.w1[1]; ++y) {
            const std::size_t row = l.index(l.w0[0], y, z);
            sum_shifted_rows(dist.data() + row, high, low, count, ger.subspan(row, width).data(), width);
        }
    }
}

// Calls f(i) for every configuration i (the box [c0, c1)), row by row.
template <typename F>
void for_each_configuration(const Layout& l, F&& f) noexcept {
    if (!l.configurations_exist()) {
        return;
    }
    for (std::int32_t z = l.c0[2]; z < l.c1[2]; ++z) {
        for (std::int32_t y = l.c0[1]; y < l.c1[1]; ++y) {
            for (std::int32_t x = l.c0[0]; x < l.c1[0]; ++x) {
                f(l.index(x, y, z));
            }
        }
    }
}

// Dijkstra's labels (eq. 18) and what it reads: labels d, G_ER gr, the move
// costs cp along +x, +y, +z, the array strides.
struct PathLabels {
    std::uint32_t* d;
    const std::uint32_t* gr;
    const std::uint32_t* cp[3];
    std::size_t stride[3];

    // Relaxes the move u -> v of cost `move` from a settled u (cost du);
    // returns true when v's label was lowered. A settled v has d[v] <= du.
    [[nodiscard]] bool relax(std::uint32_t du, std::size_t v, std::uint32_t move) const noexcept {
        const std::uint32_t nd = du + move;
        if (nd < d[v] && nd < kAccessibilityCostSaturation) {
            d[v] = nd;
            return true;
        }
        return false;
    }
    // Cost of the move from u back to w = u - e along @p axis: cap_-(w) =
    // cap_+(u) - G_ER(u) + G_ER(w) (both count R_u and R_w); exact modulo 2^32.
    [[nodiscard]] std::uint32_t backward_move(std::size_t axis, std::size_t u, std::size_t w) const noexcept {
        return cp[axis][u] - gr[u] + gr[w];
    }
};

// Labels every array voxel kNoConfiguration, every configuration kUnreached.
void reset_labels(const Layout& l, Span<std::uint32_t> dist) noexcept {
    std::fill(dist.begin(), dist.end(), kNoConfiguration);
    if (l.configurations_exist()) {
        for (std::int32_t z = l.c0[2]; z < l.c1[2]; ++z) {
            for (std::int32_t y = l.c0[1]; y < l.c1[1]; ++y) {
                const Span<std::uint32_t> row = dist.subspan(l.index(l.c0[0], y, z),
                                                             static_cast<std::size_t>(l.c1[0] - l.c0[0]));
                std::fill(row.begin(), row.end(), kUnreached);
            }
        }
    }
}

// Dijkstra, phase 1: the sources start at G_ER; every configuration of cost
// 0 is settled by a plain breadth-first flood (most of a workcell is free
// space), with @p fifo as its queue. Returns true when there is a source
// (then every configuration is reachable: they fill a box).
bool settle_zero_cost(const Layout& l, const PathLabels& p, Span<std::uint32_t> fifo) noexcept {
    std::uint32_t* const d = p.d;
    const std::uint32_t* const gr = p.gr;
    std::size_t head = 0U;
    std::size_t tail = 0U;
    bool any_source = false;
    l.for_each_source([&](std::size_t i) {
        any_source = true;
        if (gr[i] == 0U) {
            d[i] = 0U;
            fifo[tail++] = static_cast<std::uint32_t>(i);
        } else if (gr[i] < std::min(d[i], kAccessibilityCostSaturation)) {
            d[i] = gr[i];
        }
    });
    while (head < tail) {
        const std::size_t u = fifo[head++];  // d[u] == 0
        for (std::size_t axis = 0U; axis < 3U; ++axis) {
            const std::size_t v = u + p.stride[axis];
            if (d[v] != 0U && d[v] != kNoConfiguration && p.relax(0U, v, p.cp[axis][v]) && d[v] == 0U) {
                fifo[tail++] = static_cast<std::uint32_t>(v);
            }
            const std::size_t w = u - p.stride[axis];
            if (d[w] != 0U && d[w] != kNoConfiguration && p.relax(0U, w, p.backward_move(axis, u, w)) && d[w] == 0U) {
                fifo[tail++] = static_cast<std::uint32_t>(w);
            }
        }
    }
    return any_source;
}

// After a relaxation lowered v's label from @p old: enters v into the queue
// or moves it to its lower bucket.
void requeue(MonotoneBucketQueue& queue, std::size_t v, std::uint32_t old) noexcept {
    if (old == kUnreached) {
        queue.push(static_cast<std::uint32_t>(v));
    } else {
        queue.decrease(static_cast<std::uint32_t>(v));
    }
}

// Dijkstra, phase 2: the bucket queue from every labelled configuration not
// settled by phase 1 (links in @p next and @p prev).
void settle_by_bucket_queue(const Layout& l, const PathLabels& p, Span<const std::uint32_t> dist,
                            Span<std::uint32_t> next, Span<std::uint32_t> prev) noexcept {
    std::uint32_t* const d = p.d;
    MonotoneBucketQueue queue = MonotoneBucketQueue::make(dist, next, prev).value();
    for_each_configuration(l, [&](std::size_t i) {
        if (d[i] != 0U && d[i] < kAccessibilityCostSaturation) {
            queue.push(static_cast<std::uint32_t>(i));
        }
    });
    while (!queue.empty()) {
        const std::uint32_t u = queue.pop();
        const std::uint32_t du = d[u];
        for (std::size_t axis = 0U; axis < 3U; ++axis) {
            const std::size_t v = u + p.stride[axis];
            const std::uint32_t dv = d[v];
            if (dv > du && dv != kNoConfiguration && p.relax(du, v, p.cp[axis][v])) {
                requeue(queue, v, dv);
            }
            const std::size_t w = u - p.stride[axis];
            const std::uint32_t dw = d[w];
            if (dw > du && dw != kNoConfiguration && p.relax(du, w, p.backward_move(axis, u, w))) {
                requeue(queue, w, dw);
            }
        }
    }
}

// G_AR by least-cost paths (eqs. 15-18) into b.dist: Dijkstra from the
// sources, in two phases. A configuration not reached below saturation is
// reachable at >= 128 nats if there is a source.
void least_cost_paths(const Layout& l, const ProbabilisticBuffers& b) noexcept {
    reset_labels(l, b.dist);
    const PathLabels p{
        b.dist.data(), b.ger.data(), {b.cap[0].data(), b.cap[1].data(), b.cap[2].data()}, {1U, l.sy, l.sz}};
    const bool any_source = settle_zero_cost(l, p, b.next.subspan(0U, l.count));  // phase 2 links there after
    settle_by_bucket_queue(l, p, Span<const std::uint32_t>(b.dist.data(), b.dist.size()), b.next, b.prev);
    for_each_configuration(l, [&](std::size_t i) {
        std::uint32_t& v = p.d[i];
        if (v == kUnreached) {
            v = any_source ? kAccessibilityCostSaturation : kNoConfiguration;
        }
    });
}

// P(acc) = exp(-G), P(fore) = P(acc) / 2 (eq. 6) per grid voxel, from the
// filtered costs @p cost.
void write_probabilistic_prior(const Layout& l, Span<const std::uint32_t> cost, Span<std::int16_t> prior,
                               Span<float> p_acc) noexcept {
    std::uint32_t memo_g = 0U;
    std::int16_t memo_prior = kLogOddsUnknown;
    float memo_p = 1.0F;
    std::size_t gi = 0U;
    for (std::int32_t z = 0; z < l.n[2]; ++z) {
        for (std::int32_t y = 0; y < l.n[1]; ++y) {
            const std::size_t row = l.index(l.g0[0], y + l.g0[1], z + l.g0[2]);
            for (std::int32_t x = 0; x < l.n[0]; ++x, ++gi) {
                const std::uint32_t gv = cost[row + static_cast<std::size_t>(x)];
                if (gv != memo_g) {
                    memo_g = gv;
                    if (gv == kNoConfiguration) {
                        memo_prior = kNeverForeground;
                        memo_p = 0.0F;
                    } else {
                        const double nats = static_cast<double>(gv) /
                                            static_cast<double>(kAccessibilityCostUnitsPerNat);
                        memo_prior = fore_log_odds_from_cost(nats);
                        memo_p = static_cast<float>(std::exp(-nats));
                    }
                }
                prior[gi] = memo_prior;
                if (!p_acc.empty()) {
                    p_acc[gi] = memo_p;
                }
            }
        }
    }
}

// The probabilistic method (section III): cell costs, move costs, G_ER,
// least-cost paths to G_AR, the minimum over R_c, and the prior.
void probabilistic(const EvidenceGrid& g, const Layout& l, std::int32_t free_below, const AccessibilityScratch& scratch,
                   Span<std::int16_t> prior, Span<float> p_acc) noexcept {
    const ProbabilisticBuffers b = probabilistic_buffers(l, scratch);
    cell_costs(g, l, free_below, b.dist);
    move_costs(l, Span<const std::uint32_t>(b.dist.data(), b.dist.size()), b.cap);
    eroded_costs(l, b.dist, b.ger);
    least_cost_paths(l, b);

    // min over R_c of G_AR (eq. 21): r passes of the cross minimum filter.
    Span<std::uint32_t> cur = b.dist;
    Span<std::uint32_t> other = b.cap[0];
    fill_outside_work_box(l, other, kNoConfiguration);
    const PaddedRegion work = l.work_region();
    for (std::int32_t k = 0; k < l.r; ++k) {
        min_cross(work, Span<const std::uint32_t>(cur.data(), cur.size()), other);
        std::swap(cur, other);
    }
    write_probabilistic_prior(l, Span<const std::uint32_t>(cur.data(), cur.size()), prior, p_acc);
}

}  // namespace

Status validate_accessibility_params(const AccessibilityParams& params) noexcept {
    const bool known_method = params.method == PriorMethod::kThresholded ||
                              params.method == PriorMethod::kProbabilistic ||
                              params.method == PriorMethod::kThresholdedBaseline ||
                              params.method == PriorMethod::kProbabilisticBaseline;
    const bool thresholds_ok = params.t_b > 0.0 && params.t_b < 1.0 && params.t_e > 0.0 && params.t_e < 1.0;
    const bool radius_ok = params.radius_voxels >= 0 && params.radius_voxels <= kMaxAccessibilityAnalysisRadius;
    const bool faces_ok = (params.open_faces & static_cast<std::uint8_t>(~kAllFaces)) == 0U;
    if (!known_method || !thresholds_ok || !radius_ok || !faces_ok) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

Status compute_accessibility_prior(const EvidenceGrid& background, const AccessibilityParams& params,
                                   AccessibilityScratch scratch, Span<std::int16_t> prior_out,
                                   Span<float> p_acc_out) noexcept {
    const Status valid = validate_accessibility_params(params);
    if (!valid.ok()) {
        return valid;
    }
    const std::size_t voxels = background.voxel_count();
    if (voxels == 0U || voxels != background.geometry().voxel_count()) {
        return ErrorCode::kInvalidArgument;
    }
    const GridDims dims = background.geometry().dims();
    const AccessibilityScratchSize need = accessibility_scratch_size(dims, params);
    if (prior_out.size() < voxels || (!p_acc_out.empty() && p_acc_out.size() < voxels) ||
        scratch.words.size() < need.words || scratch.bytes.size() < need.bytes) {
        return ErrorCode::kStorageTooSmall;
    }
    if (accessibility_detail::padded_count(dims, params.radius_voxels, params.open_faces) >
        MonotoneBucketQueue::kMaxItems) {
        return ErrorCode::kCapacityExceeded;
    }
    const Span<std::int16_t> prior = prior_out.subspan(0U, voxels);
    const Span<float> p_acc = p_acc_out.empty() ? Span<float>() : p_acc_out.subspan(0U, voxels);
    switch (params.method) {
        case PriorMethod::kThresholded:
            thresholded(background, make_layout(dims, params), first_log_odds_at_or_above(params.t_b), scratch, prior,
                        p_acc);
            break;
        case PriorMethod::kProbabilistic:
            probabilistic(background, make_layout(dims, params), first_log_odds_at_or_above(params.t_e), scratch, prior,
                          p_acc);
            break;
        case PriorMethod::kThresholdedBaseline:
            thresholded_baseline(background, first_log_odds_at_or_above(params.t_b), prior, p_acc);
            break;
        case PriorMethod::kProbabilisticBaseline: probabilistic_baseline(background, prior, p_acc); break;
    }
    return Status{};
}

std::int16_t fore_log_odds_from_accessibility(double p_acc) noexcept {
    if (!(p_acc > 0.0)) {
        return kNeverForeground;
    }
    if (p_acc >= 1.0) {
        return kLogOddsUnknown;
    }
    return log_odds_from_units(
        std::nearbyint((std::log(p_acc) - std::log(2.0 - p_acc)) * static_cast<double>(kLogOddsScale)));
}

double accessibility_cost_error_bound(double t_e) noexcept {
    return 1.0 / (2.0 * static_cast<double>(kAccessibilityCostUnitsPerNat) * -std::log1p(-t_e));
}

std::uint32_t min_background_frames(const AccessibilityParams& params, const SensorModelTable& model,
                                    BackgroundClamp clamp) noexcept {
    if (!validate_accessibility_params(params).ok()) {
        return 0U;  // a threshold outside (0, 1) or NaN: no frame count is defined (and no NaN is cast)
    }
    const bool probabilistic = params.method == PriorMethod::kProbabilistic ||
                               params.method == PriorMethod::kProbabilisticBaseline;
    const std::int32_t empty_below = first_log_odds_at_or_above(probabilistic ? params.t_e : params.t_b);
    const std::int32_t per_frame = model.constant_free_evidence();  // < 0 (SensorModelTable::make)
    if (clamp.min >= empty_below || per_frame >= 0) {
        return 0U;
    }
    // The smallest N with N * per_frame < empty_below; the clamp only stops the sum at clamp.min < empty_below.
    const std::int32_t gap = empty_below - 1;  // N * per_frame <= gap
    if (gap >= per_frame) {
        return 1U;
    }
    return static_cast<std::uint32_t>((-gap + (-per_frame) - 1) / (-per_frame));
}

}  // namespace cellguard
