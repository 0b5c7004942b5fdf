// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: accessibility analysis (paper eqs. 1-21 and the section IV
// baselines): known answers, agreement with plain references on random grids,
// monotonicity, the open / closed face rules, parameter and storage errors.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/prior/accessibility.hpp"

using namespace cellguard;

namespace {

constexpr std::int16_t kFree = -1768;  // P(occ) = 0.001: seen empty many times
constexpr std::int16_t kOcc = 1768;    // P(occ) = 0.999: a surface seen many times

template <typename T>
Span<T> span_of(std::vector<T>& v) {
    return Span<T>(v.data(), v.size());
}

struct Background {
    Background(int nx, int ny, int nz, std::int16_t l = kFree, bool observed = true)
        : geometry(GridGeometry::make(Eigen::Vector3d::Zero(), 0.05, GridDims{nx, ny, nz}).value()),
          lo(geometry.voxel_count(), l),
          ob(geometry.voxel_count(), observed ? 1U : 0U) {}
    [[nodiscard]] std::size_t index(int x, int y, int z) const { return geometry.index_of(VoxelCoord{x, y, z}); }
    void set(int x, int y, int z, std::int16_t l, bool observed = true) {
        lo[index(x, y, z)] = l;
        ob[index(x, y, z)] = observed ? 1U : 0U;
    }
    EvidenceGrid grid() { return EvidenceGrid::make(geometry, span_of(lo), span_of(ob)).value(); }
    [[nodiscard]] GridDims dims() const { return geometry.dims(); }
    [[nodiscard]] int n(int axis) const { return axis == 0 ? dims().nx : (axis == 1 ? dims().ny : dims().nz); }
    GridGeometry geometry;
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
};

AccessibilityParams params_of(PriorMethod method, int r, std::uint8_t open_faces) {
    AccessibilityParams p;
    p.method = method;
    p.radius_voxels = r;
    p.open_faces = open_faces;
    return p;
}

struct Prior {
    std::vector<std::int16_t> prior;
    std::vector<float> p_acc;
};

Prior compute(Background& bg, const AccessibilityParams& p) {
    const AccessibilityScratchSize need = accessibility_scratch_size(bg.dims(), p);
    std::vector<std::uint32_t> words(need.words, 0xDEADBEEFU);
    std::vector<std::uint8_t> bytes(need.bytes, 0xA5U);
    Prior out{std::vector<std::int16_t>(bg.lo.size(), 1234), std::vector<float>(bg.lo.size(), -1.0F)};
    const Status s = compute_accessibility_prior(bg.grid(), p, AccessibilityScratch{span_of(words), span_of(bytes)},
                                                 span_of(out.prior), span_of(out.p_acc));
    REQUIRE(s.ok());
    for (std::size_t i = 0; i < out.prior.size(); ++i) {
        REQUIRE(out.prior[i] <= 0);  // written, and P(fore) <= 0.5
        REQUIRE(out.p_acc[i] >= 0.0F);
        REQUIRE(out.p_acc[i] <= 1.0F);
    }
    return out;
}

// ------------------------------------------------------------------ plain references

// The rules of accessibility.hpp written the obvious way: configurations
// centred in [-r, n - 1 + r] per axis, cells beyond a closed face occupied,
// beyond an open face free; sources on or beyond open faces.
struct Reference {
    Reference(const Background& bg, const AccessibilityParams& p) : bg_(bg), p_(p), r_(p.radius_voxels) {
        for (int a = 0; a < 3; ++a) {
            n_[a] = bg.n(a);
            e_[a] = n_[a] + 2 * r_;
        }
    }
    [[nodiscard]] bool open(int axis, int high) const { return (p_.open_faces & (1U << (2 * axis + high))) != 0U; }
    [[nodiscard]] bool inside(const int q[3]) const {
        return q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < n_[0] && q[1] < n_[1] && q[2] < n_[2];
    }
    [[nodiscard]] bool beyond_closed(const int q[3]) const {
        for (int a = 0; a < 3; ++a) {
            if ((q[a] < 0 && !open(a, 0)) || (q[a] >= n_[a] && !open(a, 1)))
                return true;
        }
        return false;
    }
    [[nodiscard]] bool source(const int c[3]) const {
        for (int a = 0; a < 3; ++a) {
            if (c[a] < 0 || c[a] >= n_[a] || (c[a] == 0 && open(a, 0)) || (c[a] == n_[a] - 1 && open(a, 1)))
                return true;
        }
        return false;
    }
    // P(occ; G_B), unobserved = 0.5.
    [[nodiscard]] double p_occ(const int q[3]) const {
        const std::size_t i = bg_.index(q[0], q[1], q[2]);
        return bg_.ob[i] != 0U ? probability_from_log_odds(bg_.lo[i]) : 0.5;
    }
    [[nodiscard]] int configs() const { return e_[0] * e_[1] * e_[2]; }
    [[nodiscard]] int config_index(const int c[3]) const {
        return (c[0] + r_) + e_[0] * ((c[1] + r_) + e_[1] * (c[2] + r_));
    }
    void config_of(int index, int c[3]) const {
        c[0] = index % e_[0] - r_;
        c[1] = (index / e_[0]) % e_[1] - r_;
        c[2] = index / (e_[0] * e_[1]) - r_;
    }
    [[nodiscard]] bool in_config_range(const int c[3]) const {
        for (int a = 0; a < 3; ++a) {
            if (c[a] < -r_ || c[a] >= n_[a] + r_)
                return false;
        }
        return true;
    }
    // Calls f(q) for every cell q of R_c (L1 ball of radius r around c).
    template <typename F>
    void for_ball(const int c[3], F&& f) const {
        for (int dz = -r_; dz <= r_; ++dz) {
            for (int dy = -r_; dy <= r_; ++dy) {
                for (int dx = -r_; dx <= r_; ++dx) {
                    if (std::abs(dx) + std::abs(dy) + std::abs(dz) > r_)
                        continue;
                    const int q[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                    f(q);
                }
            }
        }
    }
    // Thresholded: true for every voxel in A (eqs. 1-4).
    [[nodiscard]] std::vector<bool> thresholded_a() const {
        auto empty = [&](const int q[3]) { return inside(q) ? p_occ(q) < p_.t_b : !beyond_closed(q); };
        std::vector<int> state(static_cast<std::size_t>(configs()), 0);  // 0 not in E_R, 1 in E_R, 2 accessible
        std::queue<int> todo;
        for (int i = 0; i < configs(); ++i) {
            int c[3];
            config_of(i, c);
            bool all_empty = true;
            for_ball(c, [&](const int q[3]) { all_empty = all_empty && empty(q); });
            state[static_cast<std::size_t>(i)] = all_empty ? 1 : 0;
        }
        for (int i = 0; i < configs(); ++i) {
            int c[3];
            config_of(i, c);
            if (state[static_cast<std::size_t>(i)] == 1 && source(c)) {
                state[static_cast<std::size_t>(i)] = 2;
                todo.push(i);
            }
        }
        while (!todo.empty()) {
            int c[3];
            config_of(todo.front(), c);
            todo.pop();
            for (int a = 0; a < 3; ++a) {
                for (int s = -1; s <= 1; s += 2) {
                    int d[3] = {c[0], c[1], c[2]};
                    d[a] += s;
                    if (!in_config_range(d))
                        continue;
                    int& st = state[static_cast<std::size_t>(config_index(d))];
                    if (st == 1) {
                        st = 2;
                        todo.push(config_index(d));
                    }
                }
            }
        }
        std::vector<bool> a(bg_.lo.size(), false);
        for (int z = 0; z < n_[2]; ++z) {
            for (int y = 0; y < n_[1]; ++y) {
                for (int x = 0; x < n_[0]; ++x) {
                    const int v[3] = {x, y, z};
                    bool covered = false;
                    for_ball(v, [&](const int c[3]) {
                        covered = covered ||
                                  (in_config_range(c) && state[static_cast<std::size_t>(config_index(c))] == 2);
                    });
                    a[bg_.index(x, y, z)] = covered;
                }
            }
        }
        return a;
    }
    // Probabilistic: min over covering configurations of G_AR per voxel, in
    // nats (infinity where none), by a binary-heap Dijkstra in double.
    [[nodiscard]] std::vector<double> probabilistic_g() const {
        const double inf = std::numeric_limits<double>::infinity();
        auto cost = [&](const int q[3]) {  // L = -ln(1 - f), eq. 13
            if (!inside(q))
                return 0.0;
            const std::size_t i = bg_.index(q[0], q[1], q[2]);
            if (bg_.ob[i] == 0U)
                return 0.0;
            const double p = probability_from_log_odds(bg_.lo[i]);
            return p < p_.t_e ? 0.0 : -std::log1p(-p);
        };
        std::vector<double> dist(static_cast<std::size_t>(configs()), inf);
        std::vector<bool> valid(static_cast<std::size_t>(configs()), false);
        using Entry = std::pair<double, int>;
        std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
        for (int i = 0; i < configs(); ++i) {
            int c[3];
            config_of(i, c);
            bool ok = true;
            double g = 0.0;
            for_ball(c, [&](const int q[3]) {
                ok = ok && !beyond_closed(q);
                g += cost(q);
            });
            valid[static_cast<std::size_t>(i)] = ok;
            if (ok && source(c)) {
                dist[static_cast<std::size_t>(i)] = g;
                heap.push({g, i});
            }
        }
        while (!heap.empty()) {
            const auto [du, u] = heap.top();
            heap.pop();
            if (du > dist[static_cast<std::size_t>(u)])
                continue;
            int c[3];
            config_of(u, c);
            for (int a = 0; a < 3; ++a) {
                for (int s = -1; s <= 1; s += 2) {
                    int d[3] = {c[0], c[1], c[2]};
                    d[a] += s;
                    if (!in_config_range(d) || !valid[static_cast<std::size_t>(config_index(d))])
                        continue;
                    double move = 0.0;  // cells of R_d not in R_c (eq. 17)
                    for_ball(d, [&](const int q[3]) {
                        if (std::abs(q[0] - c[0]) + std::abs(q[1] - c[1]) + std::abs(q[2] - c[2]) > r_)
                            move += cost(q);
                    });
                    const int v = config_index(d);
                    if (du + move < dist[static_cast<std::size_t>(v)]) {
                        dist[static_cast<std::size_t>(v)] = du + move;
                        heap.push({du + move, v});
                    }
                }
            }
        }
        std::vector<double> g(bg_.lo.size(), inf);
        for (int z = 0; z < n_[2]; ++z) {
            for (int y = 0; y < n_[1]; ++y) {
                for (int x = 0; x < n_[0]; ++x) {
                    const int v[3] = {x, y, z};
                    double best = inf;
                    for_ball(v, [&](const int c[3]) {
                        if (in_config_range(c) && valid[static_cast<std::size_t>(config_index(c))]) {
                            best = std::min(best, dist[static_cast<std::size_t>(config_index(c))]);
                        }
                    });
                    g[bg_.index(x, y, z)] = best;
                }
            }
        }
        return g;
    }

    const Background& bg_;
    AccessibilityParams p_;
    int r_;
    int n_[3] = {};
    int e_[3] = {};
};

// A random background: seen-free voxels, unobserved voxels (with junk
// log-odds: only the flag counts), voxels near the thresholds, occupied ones.
Background random_background(std::mt19937& rng, int max_dim) {
    auto dim = [&] { return 1 + static_cast<int>(rng() % static_cast<unsigned>(max_dim)); };
    Background bg(dim(), dim(), dim());
    auto in = [&](int lo, int hi) {
        return static_cast<std::int16_t>(lo + static_cast<int>(rng() % static_cast<unsigned>(hi - lo + 1)));
    };
    for (std::size_t i = 0; i < bg.lo.size(); ++i) {
        const unsigned u = rng() % 100U;
        bg.ob[i] = 1U;
        if (u < 45U) {
            bg.lo[i] = in(-1768, -700);
        } else if (u < 60U) {
            bg.lo[i] = in(-2000, 2000);
            bg.ob[i] = 0U;
        } else if (u < 70U) {
            bg.lo[i] = in(-700, 100);
        } else {
            bg.lo[i] = in(100, 2500);
        }
    }
    return bg;
}

}  // namespace

// ------------------------------------------------------------------ known answers

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: the hollow interior of a closed box is inaccessible, both methods") {
    Background bg(14, 14, 10);
    for (int y = 0; y < 14; ++y)
        for (int x = 0; x < 14; ++x)
            bg.set(x, y, 0, kOcc);  // the floor
    for (int z = 1; z <= 6; ++z)
        for (int y = 4; y <= 9; ++y)
            for (int x = 4; x <= 9; ++x) {
                const bool interior = x > 4 && x < 9 && y > 4 && y < 9 && z > 1 && z < 6;
                bg.set(x, y, z, interior ? std::int16_t{0} : kOcc, !interior);
            }
    const Prior t = compute(bg, params_of(PriorMethod::kThresholded, 2, kPaperOpenFaces));
    const AccessibilityParams pp = params_of(PriorMethod::kProbabilistic, 2, kPaperOpenFaces);
    const Prior p = compute(bg, pp);
    const std::vector<double> g = Reference(bg, pp).probabilistic_g();
    const double eps = accessibility_cost_error_bound(pp.t_e);
    int interior = 0;
    double least = 1e9;
    for (int z = 2; z <= 5; ++z)
        for (int y = 5; y <= 8; ++y)
            for (int x = 5; x <= 8; ++x) {
                const std::size_t i = bg.index(x, y, z);
                CHECK(t.prior[i] == kNeverForeground);
                // Reachable at a finite cost: the object overlaps the wall.
                CHECK(p.prior[i] != kNeverForeground);
                CHECK(p.p_acc[i] < 1e-14F);  // at least five wall cells of 6.9 nats
                CHECK(std::abs(p.prior[i] - fore_log_odds_from_accessibility(std::exp(-g[i]))) <=
                      2.0 * eps * g[i] * kLogOddsScale + 1.0);
                least = std::min(least, g[i]);
                ++interior;
            }
    CHECK(interior == 64);
    CHECK(least > 34.0);  // next to a wall, a ball outside reaches in through five wall cells
    for (const auto& v : {VoxelCoord{1, 1, 5}, VoxelCoord{12, 7, 3}, VoxelCoord{7, 12, 8}, VoxelCoord{7, 1, 8}}) {
        const std::size_t i = bg.index(v.x, v.y, v.z);
        CHECK(t.prior[i] == 0);
        CHECK(p.prior[i] == 0);
        CHECK(p.p_acc[i] == 1.0F);
    }
    // Between the box top (z = 6) and the closed ceiling only three layers
    // are free: narrower than the object.
    CHECK(t.prior[bg.index(7, 7, 8)] == kNeverForeground);
    // The floor is background in both methods (closed face, occupied voxels).
    CHECK(t.prior[bg.index(7, 1, 0)] == kNeverForeground);
    CHECK(p.p_acc[bg.index(7, 1, 0)] < 1.1e-3F);
}

// verifies: SR-PRIOR-004
TEST_CASE("accessibility: behind walls at the saturation bound the prior is kLogOddsMin, not the sentinel") {
    Background bg(12, 12, 12);
    for (int z = 3; z <= 8; ++z)
        for (int y = 3; y <= 8; ++y)
            for (int x = 3; x <= 8; ++x) {
                const bool interior = x > 3 && x < 8 && y > 3 && y < 8 && z > 3 && z < 8;
                bg.set(x, y, z, interior ? kFree : kLogOddsMax);
            }
    const Prior p = compute(bg, params_of(PriorMethod::kProbabilistic, 1, kAllFaces));
    const std::size_t i = bg.index(5, 5, 5);
    CHECK(p.prior[i] == kLogOddsMin);
    CHECK(p.p_acc[i] == 0.0F);
    CHECK(p.prior[bg.index(1, 1, 1)] == 0);
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: a slot narrower than the object seals the space behind it, a wider one does not") {
    for (const int half : {1, 2}) {  // slot 3 x 3 (sealed for r = 2) and 5 x 5 (open)
        Background bg(14, 11, 11);
        for (int z = 0; z < 11; ++z)
            for (int y = 0; y < 11; ++y)
                if (std::abs(y - 5) > half || std::abs(z - 5) > half)
                    bg.set(5, y, z, kOcc);
        const Prior t = compute(bg, params_of(PriorMethod::kThresholded, 2, kFaceMinX));
        const Prior p = compute(bg, params_of(PriorMethod::kProbabilistic, 2, kFaceMinX));
        const std::size_t behind = bg.index(9, 5, 5);
        const std::size_t front = bg.index(2, 5, 5);
        CHECK(t.prior[front] == 0);
        CHECK(p.p_acc[front] == 1.0F);
        if (half == 1) {
            CHECK(t.prior[behind] == kNeverForeground);
            CHECK(p.p_acc[behind] < 1e-9F);  // at least 4 wall cells of 6.9 nats in the slot
            CHECK(p.prior[behind] != kNeverForeground);
        } else {
            CHECK(t.prior[behind] == 0);
            CHECK(p.p_acc[behind] == 1.0F);
            CHECK(p.prior[behind] == 0);
        }
    }
}

// verifies: SR-PRIOR-001, SR-PRIOR-002
TEST_CASE("accessibility: the 2-D example in the spirit of Fig. 2 (r = 1) gives the expected accessible set") {
    // '#' occupied, '.' free. A hollow box with a one-voxel gap (narrower
    // than the object), a ring with a one-voxel hole, and a U-shaped notch.
    const std::vector<std::string> map = {
        "..............",  //
        ".######.......",  //
        ".#....#...###.",  //
        ".#....#...#.#.",  //
        ".#....#...###.",  //
        ".#....#.......",  //
        ".##.###...###.",  //
        "..........#.#.",  //
        "..........#.#.",  //
        "..............",
    };
    // Expected accessibility of the middle slice: 'x' marks free voxels the
    // object cannot reach: the box interior (sealed gap), the ring's hole,
    // the one-voxel passage between ring and U (at (11, 5)), the notch bottom.
    const std::vector<std::string> expected = {
        "..............",  //
        ".######.......",  //
        ".#xxxx#...###.",  //
        ".#xxxx#...#x#.",  //
        ".#xxxx#...###.",  //
        ".#xxxx#....x..",  //
        ".##.###...###.",  //
        "..........#x#.",  //
        "..........#.#.",  //
        "..............",
    };
    // Extruded over three slices; floor and ceiling closed, so the object
    // (an L1 ball of radius 1) only fits in the middle slice: a 2-D problem.
    Background bg(14, 10, 3);
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 10; ++y)
            for (int x = 0; x < 14; ++x)
                bg.set(x, y, z, map[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)] == '#' ? kOcc : kFree);
    const Prior t = compute(bg, params_of(PriorMethod::kThresholded, 1, kPaperOpenFaces));
    const Prior p = compute(bg, params_of(PriorMethod::kProbabilistic, 1, kPaperOpenFaces));
    int inaccessible_free = 0;
    for (int y = 0; y < 10; ++y) {
        for (int x = 0; x < 14; ++x) {
            const char e = expected[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)];
            const std::size_t i = bg.index(x, y, 1);
            CAPTURE(x);
            CAPTURE(y);
            CHECK(t.prior[i] == (e == '.' ? 0 : kNeverForeground));
            if (e == '.') {
                // On a 0/1 map the probabilistic method agrees exactly.
                CHECK(p.p_acc[i] == 1.0F);
                CHECK(p.prior[i] == 0);
            } else {
                CHECK(p.p_acc[i] > 0.0F);
                CHECK(p.p_acc[i] < 1.1e-3F);  // at least one occupied cell, 6.9 nats
                CHECK(p.prior[i] != kNeverForeground);
            }
            inaccessible_free += e == 'x' ? 1 : 0;
        }
    }
    CHECK(inaccessible_free == 19);
}

// verifies: SR-PRIOR-004
TEST_CASE("accessibility: the baselines use E, and 1 - P(occ) with unobserved voxels at 0.5") {
    Background bg(3, 1, 1);
    bg.set(0, 0, 0, kFree);
    bg.set(1, 0, 0, 3000, false);  // unobserved: its stored log-odds do not count
    bg.set(2, 0, 0, kOcc);
    const Prior t = compute(bg, params_of(PriorMethod::kThresholdedBaseline, 2, 0U));
    CHECK(t.prior[0] == 0);
    CHECK(t.prior[1] == 0);  // P = 0.5 < t_B = 0.51: an interior stays in E
    CHECK(t.prior[2] == kNeverForeground);
    CHECK(t.p_acc[1] == 1.0F);
    const Prior p = compute(bg, params_of(PriorMethod::kProbabilisticBaseline, 2, 0U));
    CHECK(p.prior[1] == fore_log_odds_from_accessibility(0.5));  // P(fore) = 0.25
    CHECK(p.prior[1] == -281);
    CHECK(p.p_acc[1] == 0.5F);
    CHECK(p.prior[0] == fore_log_odds_from_accessibility(1.0 - probability_from_log_odds(kFree)));
    CHECK(p.prior[2] == fore_log_odds_from_accessibility(1.0 - probability_from_log_odds(kOcc)));
    CHECK(p.p_acc[2] == doctest::Approx(0.001).epsilon(0.01));
    // A background voxel at P(occ) = 0 exactly, and one at the top bound.
    bg.set(0, 0, 0, kNeverForeground);
    bg.set(2, 0, 0, kLogOddsMax);
    const Prior q = compute(bg, params_of(PriorMethod::kProbabilisticBaseline, 2, 0U));
    CHECK(q.prior[0] == 0);
    CHECK(q.p_acc[0] == 1.0F);
    CHECK(q.prior[2] == kLogOddsMin);  // tiny but not zero
}

// verifies: SR-PRIOR-004
TEST_CASE("accessibility: the log-odds of P(acc) / 2 keep the sentinel for exactly zero only") {
    CHECK(fore_log_odds_from_accessibility(0.0) == kNeverForeground);
    CHECK(fore_log_odds_from_accessibility(std::nan("")) == kNeverForeground);
    CHECK(fore_log_odds_from_accessibility(1e-300) == kLogOddsMin);
    CHECK(fore_log_odds_from_accessibility(1.0) == 0);
    CHECK(fore_log_odds_from_accessibility(0.5) == -281);  // 256 ln(1/3)
    CHECK(fore_log_odds_from_accessibility(0.2) == static_cast<std::int16_t>(std::lround(256.0 * std::log(0.2 / 1.8))));
}

// ------------------------------------------------------------------ face rules

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: a closed face is not a source, an open face is") {
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic}) {
        Background bg(9, 9, 9);
        for (int z = 0; z < 9; ++z)
            for (int y = 0; y < 9; ++y)
                bg.set(4, y, z, kOcc);  // a wall across the grid
        const std::size_t far_side = bg.index(6, 4, 4);
        const Prior one = compute(bg, params_of(m, 1, kFaceMinX));
        const Prior two = compute(bg, params_of(m, 1, kFaceMinX | kFaceMaxX));
        const Prior none = compute(bg, params_of(m, 1, 0U));
        CHECK(one.prior[bg.index(2, 4, 4)] == 0);
        if (m == PriorMethod::kThresholded) {
            CHECK(one.prior[far_side] == kNeverForeground);
        } else {
            CHECK(one.p_acc[far_side] < 1e-14F);  // five wall cells of 6.9 nats
        }
        CHECK(two.prior[far_side] == 0);
        CHECK(two.p_acc[far_side] == 1.0F);
        for (const std::int16_t v : none.prior)
            CHECK(v == kNeverForeground);
    }
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: beyond a closed face is occupied, beyond an open face is free") {
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic}) {
        // Free grid, only x = 0 open, r = 2: the ball cannot reach the corner
        // between two closed faces, but reaches the floor away from them.
        Background free_grid(9, 9, 9);
        const Prior f = compute(free_grid, params_of(m, 2, kFaceMinX));
        CHECK(f.prior[free_grid.index(0, 0, 0)] == kNeverForeground);
        CHECK(f.prior[free_grid.index(4, 0, 0)] == kNeverForeground);
        CHECK(f.prior[free_grid.index(0, 4, 0)] == 0);
        CHECK(f.prior[free_grid.index(8, 4, 4)] == 0);
        CHECK(f.prior[free_grid.index(8, 1, 4)] == kNeverForeground);  // nearest centre (6, 2, 4) is 3 away
        CHECK(f.prior[free_grid.index(7, 3, 4)] == 0);
        CHECK(f.prior[free_grid.index(8, 0, 0)] == kNeverForeground);
        // Solid grid with one empty voxel on the open face: the object
        // stands outside and touches it, so it is accessible.
        Background solid(9, 9, 9, kOcc);
        solid.set(0, 4, 4, kFree);
        const Prior s = compute(solid, params_of(m, 2, kFaceMinX));
        CHECK(s.prior[solid.index(0, 4, 4)] == 0);
        CHECK(s.p_acc[solid.index(0, 4, 4)] == 1.0F);
        if (m == PriorMethod::kThresholded)
            CHECK(s.prior[solid.index(1, 4, 4)] == kNeverForeground);
    }
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: an empty voxel on an open face, r away from closed faces, is always accessible") {
    std::mt19937 rng(21U);
    int checked = 0;
    for (int trial = 0; trial < 120; ++trial) {
        Background bg = random_background(rng, 7);
        const auto method = trial % 2 == 0 ? PriorMethod::kThresholded : PriorMethod::kProbabilistic;
        AccessibilityParams p = params_of(method, static_cast<int>(rng() % 4U), static_cast<std::uint8_t>(rng() % 64U));
        const Prior out = compute(bg, p);
        const Reference ref(bg, p);
        for (int z = 0; z < bg.n(2); ++z)
            for (int y = 0; y < bg.n(1); ++y)
                for (int x = 0; x < bg.n(0); ++x) {
                    const int v[3] = {x, y, z};
                    const double p_occ = ref.p_occ(v);
                    const bool observed = bg.ob[bg.index(x, y, z)] != 0U;
                    const bool empty = method == PriorMethod::kThresholded ? p_occ < p.t_b
                                                                           : (!observed || p_occ < p.t_e);
                    if (!empty)
                        continue;
                    for (int a = 0; a < 3; ++a) {
                        for (int high = 0; high <= 1; ++high) {
                            if (!ref.open(a, high) || v[a] != (high != 0 ? bg.n(a) - 1 : 0))
                                continue;
                            bool room = true;  // the ball outside the face stays clear of closed faces
                            for (int b = 0; b < 3; ++b) {
                                if (b == a)
                                    continue;
                                room = room && (ref.open(b, 0) || v[b] >= p.radius_voxels) &&
                                       (ref.open(b, 1) || v[b] <= bg.n(b) - 1 - p.radius_voxels);
                            }
                            if (!room)
                                continue;
                            CHECK(out.prior[bg.index(x, y, z)] == 0);
                            CHECK(out.p_acc[bg.index(x, y, z)] == 1.0F);
                            ++checked;
                        }
                    }
                }
    }
    CHECK(checked > 500);
}

// ------------------------------------------------------------------ references

// verifies: SR-PRIOR-001
TEST_CASE("accessibility: the thresholded method equals a brute-force erosion, flood fill and dilation") {
    std::mt19937 rng(1U);
    int accessible = 0;
    int inaccessible = 0;
    for (int trial = 0; trial < 300; ++trial) {
        Background bg = random_background(rng, 7);
        AccessibilityParams p = params_of(PriorMethod::kThresholded, static_cast<int>(rng() % 4U),
                                          static_cast<std::uint8_t>(rng() % 64U));
        const double tb[3] = {0.51, 0.45, 0.7};
        p.t_b = tb[rng() % 3U];
        const Prior out = compute(bg, p);
        const std::vector<bool> a = Reference(bg, p).thresholded_a();
        for (std::size_t i = 0; i < a.size(); ++i) {
            CAPTURE(trial);
            CAPTURE(i);
            CHECK(out.prior[i] == (a[i] ? 0 : kNeverForeground));
            CHECK(out.p_acc[i] == (a[i] ? 1.0F : 0.0F));
            (a[i] ? accessible : inaccessible) += 1;
        }
    }
    CHECK(accessible > 1000);
    CHECK(inaccessible > 1000);
}

// verifies: SR-PRIOR-002
TEST_CASE("accessibility: the probabilistic method agrees with a double-precision Dijkstra within the stated bound") {
    std::mt19937 rng(5U);
    int graded = 0;  // voxels with 0 < G_AR < 100 nats
    for (int trial = 0; trial < 150; ++trial) {
        Background bg = random_background(rng, 6);
        AccessibilityParams p = params_of(PriorMethod::kProbabilistic, static_cast<int>(rng() % 4U),
                                          static_cast<std::uint8_t>(rng() % 64U));
        p.t_e = trial % 3 == 0 ? 0.3 : 0.1;
        const Prior out = compute(bg, p);
        const std::vector<double> g = Reference(bg, p).probabilistic_g();
        const double eps = accessibility_cost_error_bound(p.t_e);
        for (std::size_t i = 0; i < g.size(); ++i) {
            CAPTURE(trial);
            CAPTURE(i);
            CAPTURE(g[i]);
            if (std::isinf(g[i])) {
                CHECK(out.prior[i] == kNeverForeground);
                CHECK(out.p_acc[i] == 0.0F);
                continue;
            }
            CHECK(out.prior[i] != kNeverForeground);
            const int expected = fore_log_odds_from_accessibility(std::exp(-g[i]));
            CHECK(std::abs(out.prior[i] - expected) <= 2.0 * eps * g[i] * kLogOddsScale + 1.0);
            if (g[i] < 80.0) {
                REQUIRE(out.p_acc[i] > 0.0F);
                CHECK(std::abs(-std::log(static_cast<double>(out.p_acc[i])) - g[i]) <= eps * g[i] + 1e-5);
            }
            graded += g[i] > 0.0 && g[i] < 100.0 ? 1 : 0;
        }
    }
    CHECK(graded > 1000);
}

// verifies: SR-PRIOR-001, SR-PRIOR-002
TEST_CASE("accessibility: the largest radius (8 voxels) agrees with both references") {
    std::mt19937 rng(13U);
    for (int trial = 0; trial < 6; ++trial) {
        Background bg = random_background(rng, 5);
        for (std::size_t i = 0; i < bg.lo.size(); ++i) {
            if (rng() % 3U != 0U)
                bg.lo[i] = kFree;  // keep costs below saturation now and then
        }
        const auto faces = static_cast<std::uint8_t>(trial == 0 ? kAllFaces : rng() % 64U);
        const AccessibilityParams t = params_of(PriorMethod::kThresholded, kMaxAccessibilityAnalysisRadius, faces);
        const AccessibilityParams p = params_of(PriorMethod::kProbabilistic, kMaxAccessibilityAnalysisRadius, faces);
        const Prior out_t = compute(bg, t);
        const Prior out_p = compute(bg, p);
        const std::vector<bool> a = Reference(bg, t).thresholded_a();
        const std::vector<double> g = Reference(bg, p).probabilistic_g();
        const double eps = accessibility_cost_error_bound(p.t_e);
        for (std::size_t i = 0; i < a.size(); ++i) {
            CHECK(out_t.prior[i] == (a[i] ? 0 : kNeverForeground));
            if (std::isinf(g[i])) {
                CHECK(out_p.prior[i] == kNeverForeground);
            } else {
                CHECK(std::abs(out_p.prior[i] - fore_log_odds_from_accessibility(std::exp(-g[i]))) <=
                      2.0 * eps * g[i] * kLogOddsScale + 1.0);
            }
        }
    }
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: more occupied evidence never raises P(acc)") {
    std::mt19937 rng(9U);
    for (int trial = 0; trial < 120; ++trial) {
        Background bg = random_background(rng, 7);
        const auto method = trial % 2 == 0 ? PriorMethod::kThresholded : PriorMethod::kProbabilistic;
        const AccessibilityParams p = params_of(method, static_cast<int>(rng() % 4U),
                                                static_cast<std::uint8_t>(1U + rng() % 63U));
        const Prior before = compute(bg, p);
        const int changes = 1 + static_cast<int>(rng() % 5U);
        for (int k = 0; k < changes; ++k) {
            const std::size_t i = rng() % bg.lo.size();
            if (bg.ob[i] != 0U) {
                bg.lo[i] = static_cast<std::int16_t>(
                    std::min<int>(kLogOddsMax, bg.lo[i] + 1 + static_cast<int>(rng() % 3000U)));
            } else {
                bg.ob[i] = 1U;  // unobserved counted as 0.5 (thresholded) or f = 0: now at least that
                bg.lo[i] = static_cast<std::int16_t>(rng() % 3000U);
            }
        }
        const Prior after = compute(bg, p);
        for (std::size_t i = 0; i < bg.lo.size(); ++i) {
            CAPTURE(trial);
            CHECK(after.p_acc[i] <= before.p_acc[i]);
            CHECK(after.prior[i] <= before.prior[i]);
        }
    }
}

// ------------------------------------------------------------------ errors and storage

// verifies: SR-PRIOR-005
TEST_CASE("accessibility: bad parameters are refused with kInvalidArgument and nothing is written") {
    Background bg(4, 4, 4);
    const AccessibilityParams good{};
    REQUIRE(validate_accessibility_params(good).ok());
    std::vector<AccessibilityParams> bad(14, good);
    bad[0].method = static_cast<PriorMethod>(0);
    bad[1].method = static_cast<PriorMethod>(5);
    bad[2].t_b = 0.0;
    bad[3].t_b = 1.0;
    bad[4].t_b = std::nan("");
    bad[5].t_e = 0.0;
    bad[6].t_e = 1.0;
    bad[7].t_e = -0.1;
    bad[8].t_e = std::nan("");
    bad[9].radius_voxels = -1;
    bad[10].radius_voxels = kMaxAccessibilityAnalysisRadius + 1;
    bad[11].open_faces = 0x40U;
    bad[12].open_faces = 0x80U | kFaceMinX;
    bad[13].t_b = std::numeric_limits<double>::infinity();
    const AccessibilityScratchSize any = accessibility_scratch_size_any(bg.dims());
    std::vector<std::uint32_t> words(any.words);
    std::vector<std::uint8_t> bytes(any.bytes);
    std::vector<std::int16_t> prior(bg.lo.size(), 77);
    for (const AccessibilityParams& p : bad) {
        CHECK(validate_accessibility_params(p).error() == ErrorCode::kInvalidArgument);
        CHECK(compute_accessibility_prior(bg.grid(), p, AccessibilityScratch{span_of(words), span_of(bytes)},
                                          span_of(prior), Span<float>())
                  .error() == ErrorCode::kInvalidArgument);
    }
    for (const std::int16_t v : prior)
        CHECK(v == 77);
    CHECK(compute_accessibility_prior(EvidenceGrid{}, good, AccessibilityScratch{span_of(words), span_of(bytes)},
                                      span_of(prior), Span<float>())
              .error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-PRIOR-005
TEST_CASE("accessibility: too-small outputs or scratch give kStorageTooSmall, larger ones are fine") {
    Background bg(5, 4, 3);
    const std::size_t n = bg.lo.size();
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                PriorMethod::kThresholdedBaseline, PriorMethod::kProbabilisticBaseline}) {
        const AccessibilityParams p = params_of(m, 2, kPaperOpenFaces);
        const AccessibilityScratchSize need = accessibility_scratch_size(bg.dims(), p);
        std::vector<std::uint32_t> words(need.words + 5U);
        std::vector<std::uint8_t> bytes(need.bytes + 5U);
        std::vector<std::int16_t> prior(n + 3U, 77);
        std::vector<float> p_acc(n + 3U, -1.0F);
        const AccessibilityScratch scratch{span_of(words), span_of(bytes)};
        auto run = [&](AccessibilityScratch s, Span<std::int16_t> out, Span<float> acc) {
            return compute_accessibility_prior(bg.grid(), p, s, out, acc).error();
        };
        CHECK(run(scratch, Span<std::int16_t>(prior.data(), n - 1U), Span<float>()) == ErrorCode::kStorageTooSmall);
        CHECK(run(scratch, span_of(prior), Span<float>(p_acc.data(), n - 1U)) == ErrorCode::kStorageTooSmall);
        if (need.words > 0U) {
            CHECK(run(AccessibilityScratch{Span<std::uint32_t>(words.data(), need.words - 1U), span_of(bytes)},
                      span_of(prior), Span<float>()) == ErrorCode::kStorageTooSmall);
        }
        if (need.bytes > 0U) {
            CHECK(run(AccessibilityScratch{span_of(words), Span<std::uint8_t>(bytes.data(), need.bytes - 1U)},
                      span_of(prior), Span<float>()) == ErrorCode::kStorageTooSmall);
        }
        for (const std::int16_t v : prior)
            CHECK(v == 77);
        CHECK(run(scratch, span_of(prior), Span<float>()) == ErrorCode::kOk);
        CHECK(run(scratch, span_of(prior), span_of(p_acc)) == ErrorCode::kOk);
        CHECK(prior[n] == 77);  // only voxel_count() values written
        CHECK(p_acc[n] == -1.0F);
        const AccessibilityScratchSize any = accessibility_scratch_size_any(bg.dims());
        CHECK(any.words >= need.words);
        CHECK(any.bytes >= need.bytes);
    }
    constexpr AccessibilityScratchSize paper = accessibility_scratch_size(GridDims{34, 30, 30}, AccessibilityParams{});
    static_assert(paper.words == 7U * 44U * 40U * 36U + 2U * MonotoneBucketQueue::kListHeads,
                  "probabilistic scratch of the paper's grid: 7 words per padded voxel plus list heads");
    CHECK(
        accessibility_scratch_size(GridDims{34, 30, 30}, params_of(PriorMethod::kProbabilisticBaseline, 2, 0U)).words ==
        0U);
}

// verifies: SR-GEN-002
TEST_CASE("accessibility: computing a prior allocates nothing") {
    Background bg(10, 9, 8, kFree);
    bg.set(5, 5, 5, kOcc);
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                PriorMethod::kThresholdedBaseline, PriorMethod::kProbabilisticBaseline}) {
        const AccessibilityParams p = params_of(m, 2, kPaperOpenFaces);
        const AccessibilityScratchSize need = accessibility_scratch_size(bg.dims(), p);
        std::vector<std::uint32_t> words(need.words);
        std::vector<std::uint8_t> bytes(need.bytes);
        std::vector<std::int16_t> prior(bg.lo.size());
        std::vector<float> p_acc(bg.lo.size());
        const EvidenceGrid grid = bg.grid();
        const test::AllocationScope scope;
        const Status s = compute_accessibility_prior(grid, p, AccessibilityScratch{span_of(words), span_of(bytes)},
                                                     span_of(prior), span_of(p_acc));
        CHECK(scope.allocations() == 0U);
        CHECK(s.ok());
    }
}

// verifies: SR-PRIOR-002
TEST_CASE("accessibility: the padded work box clamps the radius and is empty for an empty grid") {
    using accessibility_detail::padded_count;
    using accessibility_detail::padded_extent;
    const GridDims dims{4, 5, 6};
    // No open faces: each axis grows by 2 (r + 1).
    CHECK(padded_count(dims, 1, 0U) == (4U + 4U) * (5U + 4U) * (6U + 4U));
    CHECK(padded_count(dims, -3, 0U) == padded_count(dims, 0, 0U));  // a negative radius counts as 0
    CHECK(padded_count(dims, kMaxAccessibilityAnalysisRadius + 5, 0x3FU) ==
          padded_count(dims, kMaxAccessibilityAnalysisRadius, 0x3FU));  // above the largest: clamped
    CHECK(padded_extent(4, 2, 0x01U, 0U) == 4U + 2U + 2U * 3U);         // the low x face open
    CHECK(padded_extent(4, 2, 0x02U, 0U) == 4U + 2U + 2U * 3U);         // the high x face open
    CHECK(padded_extent(0, 2, 0x3FU, 1U) == 0U);
    CHECK(padded_count(GridDims{4, 0, 6}, 2, 0U) == 0U);
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: a grid with an empty axis needs no scratch, for either method or any parameters") {
    std::vector<int> extents = {0, 7, 9};  // read at run time
    for (std::size_t empty_axis = 0U; empty_axis < 3U; ++empty_axis) {
        std::swap(extents[0], extents[empty_axis]);
        const GridDims dims{extents[0], extents[1], extents[2]};
        CAPTURE(empty_axis);
        const AccessibilityScratchSize any = accessibility_scratch_size_any(dims);
        CHECK(any.words == 2U * MonotoneBucketQueue::kListHeads);  // only the queue's list heads
        CHECK(any.bytes == 0U);
        const AccessibilityScratchSize t = accessibility_scratch_size(dims,
                                                                      params_of(PriorMethod::kThresholded, 2, 0U));
        CHECK(t.words == 0U);
        CHECK(t.bytes == 0U);
        std::swap(extents[0], extents[empty_axis]);
    }
    // A non-empty grid: the probabilistic method's words, the thresholded method's bytes.
    const GridDims dims{extents[1], extents[1], extents[2]};
    const AccessibilityScratchSize any = accessibility_scratch_size_any(dims);
    CHECK(any.words == accessibility_scratch_size(dims, params_of(PriorMethod::kProbabilistic, 8, kAllFaces)).words);
    CHECK(any.bytes == accessibility_scratch_size(dims, params_of(PriorMethod::kThresholded, 8, kAllFaces)).bytes);
    CHECK(any.bytes > 0U);
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: scratch sizes saturate instead of wrapping for dimensions no grid can have") {
    using accessibility_detail::padded_count;
    using accessibility_detail::saturating_add;
    using accessibility_detail::saturating_mul;
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
    std::vector<int> extents = {std::numeric_limits<int>::max(), 1 << 20, 1 << 21};  // read at run time
    // (2^31 + 18) * (2^20 + 18) * (2^21 + 18) is beyond 64 bits: the count saturates.
    const GridDims huge{extents[0], extents[0], extents[0]};
    CHECK(padded_count(huge, 8, kAllFaces) == kMax);
    // (2^21 + 2)^3 (no radius, no open face: each axis grows by 2) is just above 2^63: it fits, twice it does not.
    const GridDims big{extents[2], extents[2], extents[2]};
    const std::uint64_t n = padded_count(big, 0, 0U);
    const std::uint64_t side = (std::uint64_t{1} << 21U) + 2U;
    CHECK(n == side * side * side);
    CHECK(n > (std::uint64_t{1} << 63U));
    const AccessibilityScratchSize t = accessibility_scratch_size(big, params_of(PriorMethod::kThresholded, 0, 0U));
    CHECK(t.words == n);
    CHECK(t.bytes == std::numeric_limits<std::size_t>::max());  // 2n saturates
    const AccessibilityScratchSize p = accessibility_scratch_size(big, params_of(PriorMethod::kProbabilistic, 0, 0U));
    CHECK(p.words == std::numeric_limits<std::size_t>::max());  // 7n saturates
    const AccessibilityScratchSize any = accessibility_scratch_size_any(huge);
    CHECK(any.words == std::numeric_limits<std::size_t>::max());
    CHECK(any.bytes == std::numeric_limits<std::size_t>::max());
    // The helpers at their edges.
    const std::uint64_t zero = extents.size() - 3U;  // 0, at run time
    CHECK(saturating_mul(zero, kMax) == 0U);
    CHECK(saturating_mul(kMax, 2U) == kMax);
    CHECK(saturating_add(kMax - 1U, 1U) == kMax);
    CHECK(saturating_add(kMax - 1U, 2U) == kMax);
    CHECK(saturating_add(kMax, zero) == kMax);
}

// verifies: SR-FUSE-008
TEST_CASE("accessibility: no number of background frames suffices when the clamp stops at or above the threshold") {
    const SensorModelTable model;
    AccessibilityParams p;
    p.method = PriorMethod::kProbabilistic;
    const std::int16_t empty_below = threshold_log_odds(p.t_e);
    CHECK(min_background_frames(p, model, BackgroundClamp{static_cast<std::int16_t>(empty_below + 10), 1768}) == 0U);
    CHECK(min_background_frames(p, model, BackgroundClamp{0, 1768}) == 0U);
    CHECK(min_background_frames(p, model, BackgroundClamp{}) == 3U);  // with the defaults (H-PRI-7)
    // A t_B so small that not even the lowest log-odds lies below it.
    p.method = PriorMethod::kThresholded;
    p.t_b = 1e-300;
    CHECK(min_background_frames(p, model, BackgroundClamp{kLogOddsMin, kLogOddsMax}) == 0U);
    // Thresholds that validate_accessibility_params refuses define no frame count: 0, the "never enough" answer
    // (a t_B of 1.5 or NaN made the first log-odds guess NaN, cast to an integer: undefined behaviour).
    for (const double t : {1.0, 1.5, 0.0, -0.5, std::numeric_limits<double>::quiet_NaN()}) {
        CAPTURE(t);
        p.method = PriorMethod::kThresholded;
        p.t_b = t;
        CHECK(min_background_frames(p, model) == 0U);
        p.t_b = AccessibilityParams{}.t_b;
        p.method = PriorMethod::kProbabilistic;
        p.t_e = t;
        CHECK(min_background_frames(p, model) == 0U);
        p.t_e = AccessibilityParams{}.t_e;
    }
    CHECK(min_background_frames(p, model) == 3U);
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: scratch sizes of a grid far beyond kMaxDimension saturate at SIZE_MAX instead of wrapping") {
    // 2^21 voxels an axis: the padded box has about 2^63 voxels, and 7 of its words wrapped a uint64 before
    // (any.bytes came out as 897,216,034,190,096); 2^22 wrapped the box itself.
    for (const std::int32_t n :
         {std::int32_t{1} << 21, std::int32_t{1} << 22, std::numeric_limits<std::int32_t>::max()}) {
        CAPTURE(n);
        const GridDims dims{n, n, n};
        const std::uint64_t box = accessibility_detail::padded_count(dims, kMaxAccessibilityAnalysisRadius, kAllFaces);
        const auto side = static_cast<std::uint64_t>(n) + 2U * 8U + 2U * 9U;
        const bool box_fits = side * side <= std::numeric_limits<std::uint64_t>::max() / side;
        CHECK(box == (box_fits ? side * side * side : std::numeric_limits<std::uint64_t>::max()));
        const AccessibilityScratchSize any = accessibility_scratch_size_any(dims);
        CHECK(any.words == std::numeric_limits<std::size_t>::max());
        CHECK(any.bytes == std::numeric_limits<std::size_t>::max());
    }
    CHECK(accessibility_detail::saturating_mul(0U, std::numeric_limits<std::uint64_t>::max()) == 0U);
    CHECK(accessibility_detail::saturating_add(std::numeric_limits<std::uint64_t>::max() - 1U, 1U) ==
          std::numeric_limits<std::uint64_t>::max());
    CHECK(accessibility_detail::saturating_add(std::numeric_limits<std::uint64_t>::max(), 1U) ==
          std::numeric_limits<std::uint64_t>::max());
}

// verifies: SR-PRIOR-002, SR-PRIOR-004
TEST_CASE("accessibility: a cell full of surfaces at the top log-odds is reachable only at saturation everywhere") {
    Background bg(6, 5, 4, kLogOddsMax);
    const Prior p = compute(bg, params_of(PriorMethod::kProbabilistic, 1, kAllFaces));
    for (std::size_t i = 0; i < p.prior.size(); ++i) {
        REQUIRE(p.prior[i] == kLogOddsMin);  // tiny but not the never-foreground sentinel: there are sources
        REQUIRE(p.p_acc[i] == 0.0F);
    }
    // A free voxel on an open face costs nothing to reach; a voxel inside the solid stays saturated.
    bg.set(0, 2, 2, kFree);
    for (const std::uint8_t faces : {kAllFaces, static_cast<std::uint8_t>(kFaceMinX)}) {
        CAPTURE(static_cast<int>(faces));
        const Prior q = compute(bg, params_of(PriorMethod::kProbabilistic, 0, faces));
        CHECK(q.prior[bg.index(0, 2, 2)] == 0);
        CHECK(q.p_acc[bg.index(0, 2, 2)] == 1.0F);
        CHECK(q.prior[bg.index(3, 2, 2)] == kLogOddsMin);
    }
    // r = 1: the object fits only half outside the open face at that voxel; every move inward newly covers several
    // voxels at the top log-odds, more than the saturation cost in one step.
    for (const int x : {0, 6}) {
        Background solid(7, 7, 7, kLogOddsMax);
        solid.set(x, 3, 3, kFree);
        const auto face = static_cast<std::uint8_t>(x == 0 ? kFaceMinX : kFaceMaxX);
        const Prior r = compute(solid, params_of(PriorMethod::kProbabilistic, 1, face));
        CAPTURE(x);
        CHECK(r.prior[solid.index(x, 3, 3)] == 0);
        CHECK(r.p_acc[solid.index(x, 3, 3)] == 1.0F);
        CHECK(r.prior[solid.index(x == 0 ? 1 : 5, 3, 3)] == kLogOddsMin);
        CHECK(r.prior[solid.index(3, 3, 3)] == kLogOddsMin);
    }
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: the thresholded baseline's test P(occ) < t_B is exact at one ulp above a voxel's P(occ)") {
    Background bg(3, 1, 1);
    bg.set(0, 0, 0, kFree);
    bg.set(1, 0, 0, static_cast<std::int16_t>(kFree + 1));
    bg.set(2, 0, 0, kOcc);
    const double p_free = probability_from_log_odds(kFree);
    AccessibilityParams p = params_of(PriorMethod::kThresholdedBaseline, 0, 0U);
    // One ulp above P(kFree): kFree is below it (empty), kFree + 1 is not. (The logit of this t_B rounds down
    // to kFree, so the first guess must be corrected upwards.)
    p.t_b = std::nextafter(p_free, 1.0);
    const Prior above = compute(bg, p);
    CHECK(above.prior[0] == kLogOddsUnknown);
    CHECK(above.prior[1] == kNeverForeground);
    CHECK(above.prior[2] == kNeverForeground);
    // At P(kFree) itself kFree is not below it.
    p.t_b = p_free;
    const Prior at = compute(bg, p);
    CHECK(at.prior[0] == kNeverForeground);
    CHECK(at.p_acc[0] == 0.0F);
}

// verifies: SR-PRIOR-003
TEST_CASE("accessibility: a t_B whose logit rounds one above its log-odds is still exact: that voxel is not empty") {
    // t_B = P(occ) of a voxel L itself: L is not below it (not empty), L - 1 is. Around -8516 the logit of
    // P(occ)(L) rounds up to L + 1, so the first guess must be corrected downwards.
    for (std::int16_t l = -8520; l <= -8505; ++l) {
        CAPTURE(l);
        Background bg(2, 1, 1);
        bg.set(0, 0, 0, static_cast<std::int16_t>(l - 1));
        bg.set(1, 0, 0, l);
        AccessibilityParams p = params_of(PriorMethod::kThresholdedBaseline, 0, 0U);
        p.t_b = probability_from_log_odds(l);
        const Prior out = compute(bg, p);
        CHECK(out.prior[0] == kLogOddsUnknown);
        CHECK(out.prior[1] == kNeverForeground);
    }
}
