// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: ray traversal (exact Amanatides & Woo, 3D Bresenham) against brute-force references.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cellguard/grid/ray_traversal.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

using V3 = Eigen::Vector3d;
using LD = long double;

constexpr double kGrazing = 1e-9;  // metres: below this, a voxel may be visited or not

std::vector<TraversedVoxel> collect(Rasterization m, const GridGeometry& g, const V3& a, const V3& b) {
    std::vector<TraversedVoxel> out;
    const std::size_t n = traverse(m, g, a, b, [&](const TraversedVoxel& v) { out.push_back(v); });
    if (n != out.size()) {
        out.clear();  // makes every later check fail loudly
        out.push_back(TraversedVoxel{~std::size_t{0}, VoxelCoord{-99, -99, -99}, -1.0, -1.0});
    }
    return out;
}

std::tuple<int, int, int> key(const VoxelCoord& c) { return {c.x, c.y, c.z}; }

std::string str(const V3& p) {
    std::ostringstream os;
    os.precision(17);
    os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    return os.str();
}
std::string str(const VoxelCoord& c) {
    return "(" + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) + ")";
}

// ---------------------------------------------------------------------------------------------
// Brute-force reference for the exact traversal. A point's cell is GridGeometry's definition,
// (p - origin) / voxel_size floored; from those voxel-unit endpoints on, everything is long double.

struct RefSegment {
    LD u0[3];
    LD u1[3];
    LD du[3];
    LD length;        // metres
    double length_d;  // metres, as the library computes it
    bool start_inside;
    bool end_inside;
    VoxelCoord start_voxel;
    VoxelCoord end_voxel;
};

RefSegment ref_segment(const GridGeometry& g, const V3& a, const V3& b) {
    RefSegment s{};
    const V3 ua = (a - g.origin()) / g.voxel_size();
    const V3 ub = (b - g.origin()) / g.voxel_size();
    LD sq = 0.0L;
    for (int i = 0; i < 3; ++i) {
        s.u0[i] = ua[i];
        s.u1[i] = ub[i];
        s.du[i] = s.u1[i] - s.u0[i];
        const LD d = static_cast<LD>(b[i]) - static_cast<LD>(a[i]);
        sq += d * d;
    }
    s.length = std::sqrt(sq);
    s.length_d = (b - a).norm();
    const Result<VoxelCoord> sv = g.world_to_voxel(a);
    const Result<VoxelCoord> ev = g.world_to_voxel(b);
    s.start_inside = sv.ok();
    s.end_inside = ev.ok();
    s.start_voxel = sv.value_or(VoxelCoord{});
    s.end_voxel = ev.value_or(VoxelCoord{});
    return s;
}

// Slab method: the fractions [f0, f1] of the segment inside voxel v's box grown by `grow` voxel
// units; false when empty. An axis along which the segment does not move must hold it in the
// half-open cell [v - grow, v + 1 + grow).
bool ref_slab(const RefSegment& s, const VoxelCoord& v, LD grow, LD& f0, LD& f1) {
    f0 = 0.0L;
    f1 = 1.0L;
    const int c[3] = {v.x, v.y, v.z};
    for (int i = 0; i < 3; ++i) {
        const LD lo = static_cast<LD>(c[i]) - grow;
        const LD hi = static_cast<LD>(c[i]) + 1.0L + grow;
        if (s.du[i] == 0.0L) {
            if (!(lo <= s.u0[i] && s.u0[i] < hi)) {
                return false;
            }
        } else {
            const LD ta = (lo - s.u0[i]) / s.du[i];
            const LD tb = (hi - s.u0[i]) / s.du[i];
            f0 = std::max(f0, std::min(ta, tb));
            f1 = std::min(f1, std::max(ta, tb));
        }
    }
    return f0 <= f1;
}

struct RefVoxel {
    VoxelCoord c;
    LD t0;   // metres
    LD t1;   // metres
    LD len;  // metres
};

// Every voxel whose intersection with the segment is longer than kGrazing, plus the start and
// end voxels, in order from start to end.
std::vector<RefVoxel> ref_strict(const GridGeometry& g, const RefSegment& s, std::vector<RefVoxel>* grazing) {
    std::vector<RefVoxel> strict;
    const GridDims d = g.dims();
    for (int z = 0; z < d.nz; ++z) {
        for (int y = 0; y < d.ny; ++y) {
            for (int x = 0; x < d.nx; ++x) {
                const VoxelCoord v{x, y, z};
                LD f0 = 0.0L;
                LD f1 = 0.0L;
                if (!ref_slab(s, v, 0.0L, f0, f1)) {
                    continue;
                }
                const RefVoxel r{v, f0 * s.length, f1 * s.length, (f1 - f0) * s.length};
                if (r.len > kGrazing) {
                    strict.push_back(r);
                } else if (r.len > 0.0L && grazing != nullptr) {
                    grazing->push_back(r);
                }
            }
        }
    }
    std::sort(strict.begin(), strict.end(), [](const RefVoxel& a, const RefVoxel& b) { return a.t0 < b.t0; });
    const auto place = [&](const VoxelCoord& c, bool front) {
        const auto it = std::find_if(strict.begin(), strict.end(), [&](const RefVoxel& r) { return r.c == c; });
        RefVoxel r{c, front ? 0.0L : s.length, front ? 0.0L : s.length, 0.0L};
        if (it != strict.end()) {
            r = *it;
            strict.erase(it);
        }
        strict.insert(front ? strict.begin() : strict.end(), r);
    };
    if (s.end_inside) {
        place(s.end_voxel, false);
    }
    if (s.start_inside && !(s.end_inside && s.end_voxel == s.start_voxel && strict.size() == 1U)) {
        place(s.start_voxel, true);
    }
    return strict;
}

struct CompareStats {
    long segments = 0;
    long visited = 0;
    long nonempty = 0;
    long with_lattice_ties = 0;
    long tolerated_segments = 0;  // segments with at least one grazing mismatch
    long tolerated_voxels = 0;    // grazing voxels visited but not required, or skipped
    long failures = 0;
    std::vector<std::string> first_failures;
};

void fail(CompareStats& st, const std::string& what, const V3& a, const V3& b) {
    ++st.failures;
    if (st.first_failures.size() < 8U) {
        st.first_failures.push_back(what + " for " + str(a) + " -> " + str(b));
    }
}

// Compares the visit sequence t of segment a -> b with the reference.
void compare_sequence(const GridGeometry& g, const V3& a, const V3& b, const std::vector<TraversedVoxel>& t,
                      CompareStats& st) {
    ++st.segments;
    const RefSegment s = ref_segment(g, a, b);
    std::vector<RefVoxel> grazing;
    const std::vector<RefVoxel> ref = ref_strict(g, s, &grazing);
    st.visited += static_cast<long>(t.size());
    st.nonempty += t.empty() ? 0 : 1;

    // Structure of the visit sequence.
    std::set<std::tuple<int, int, int>> seen;
    for (std::size_t i = 0; i < t.size(); ++i) {
        const TraversedVoxel& v = t[i];
        if (!g.contains(v.coord) || v.index != g.index_of(v.coord)) {
            fail(st, "voxel outside or wrong index", a, b);
            return;
        }
        if (!seen.insert(key(v.coord)).second)
            fail(st, "voxel visited twice", a, b);
        if (!(0.0 <= v.t_enter && v.t_enter <= v.t_exit && v.t_exit <= s.length_d))
            fail(st, "t out of order", a, b);
        if (i > 0) {
            const VoxelCoord& p = t[i - 1].coord;
            const int dx = std::abs(v.coord.x - p.x);
            const int dy = std::abs(v.coord.y - p.y);
            const int dz = std::abs(v.coord.z - p.z);
            if (dx > 1 || dy > 1 || dz > 1 || dx + dy + dz == 0)
                fail(st, "consecutive voxels not adjacent", a, b);
            if (t[i - 1].t_exit != v.t_enter)
                fail(st, "t_exit of one voxel is not t_enter of the next", a, b);
        }
    }
    if (max_voxels_per_segment(g) < t.size())
        fail(st, "more visits than the bound", a, b);

    // Endpoint voxels: exactly GridGeometry's voxel of start and end.
    if (s.start_inside && (t.empty() || t.front().coord != s.start_voxel || t.front().t_enter != 0.0)) {
        fail(st, "first voxel is not the start voxel", a, b);
    }
    if (s.end_inside && (t.empty() || t.back().coord != s.end_voxel || t.back().t_exit != s.length_d)) {
        fail(st, "last voxel is not the end voxel", a, b);
    }
    // Clip agrees with the traversal's range.
    const ClippedSegment clip = clip_segment_to_grid(g, a, b);
    if (clip.hits != !t.empty())
        fail(st, "clip_segment_to_grid disagrees on hitting", a, b);
    if (!t.empty() && (clip.t_enter != t.front().t_enter || clip.t_exit != t.back().t_exit)) {
        fail(st, "clip range is not the traversal's range", a, b);
    }

    // Same set, same order, same t (within kGrazing), up to grazing voxels.
    std::vector<const TraversedVoxel*> required_in_t;
    long tolerated = 0;
    for (const TraversedVoxel& v : t) {
        const auto it = std::find_if(ref.begin(), ref.end(), [&](const RefVoxel& r) { return r.c == v.coord; });
        if (it != ref.end()) {
            required_in_t.push_back(&v);
            continue;
        }
        LD f0 = 0.0L;
        LD f1 = 0.0L;
        const bool touches = ref_slab(s, v.coord, static_cast<LD>(kGrazing) / g.voxel_size(), f0, f1);
        LD len0 = 0.0L;
        LD g0 = 0.0L;
        LD g1 = 0.0L;
        if (ref_slab(s, v.coord, 0.0L, g0, g1))
            len0 = (g1 - g0) * s.length;
        if (touches && len0 <= kGrazing) {
            // Passing through for a positive length below 1e-9 m is right; for none, tolerated.
            tolerated += len0 > 0.0L ? 0 : 1;
        } else {
            fail(st, "visits " + str(v.coord) + " which the segment does not pass through", a, b);
        }
    }
    if (required_in_t.size() != ref.size()) {
        fail(st,
             "misses a voxel passed through for more than 1e-9 m (" + std::to_string(ref.size()) + " expected, " +
                 std::to_string(required_in_t.size()) + " found)",
             a, b);
    } else {
        for (std::size_t i = 0; i < ref.size(); ++i) {
            const TraversedVoxel& v = *required_in_t[i];
            if (v.coord != ref[i].c) {
                fail(st, "order differs at " + std::to_string(i), a, b);
                break;
            }
            if (std::fabs(static_cast<LD>(v.t_enter) - ref[i].t0) > kGrazing ||
                std::fabs(static_cast<LD>(v.t_exit) - ref[i].t1) > kGrazing) {
                fail(st, "t_enter/t_exit differ from the reference at " + str(v.coord), a, b);
            }
        }
    }
    for (const RefVoxel& r : grazing) {
        if (seen.count(key(r.c)) == 0U)
            ++tolerated;
    }
    if (tolerated > 0) {
        ++st.tolerated_segments;
        st.tolerated_voxels += tolerated;
    }
}

// Compares traverse_segment with the reference on one segment.
void compare_exact(const GridGeometry& g, const V3& a, const V3& b, CompareStats& st) {
    compare_sequence(g, a, b, collect(Rasterization::kExact, g, a, b), st);
}

// ---------------------------------------------------------------------------------------------
// Random segments of every kind that matters.

class SegmentMaker {
public:
    SegmentMaker(const GridGeometry& g, std::uint32_t seed) : g_(g), rng_(seed) {}

    double uni(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
    int dim(int axis) const { return axis == 0 ? g_.dims().nx : (axis == 1 ? g_.dims().ny : g_.dims().nz); }

    // origin + k * voxel_size, nudged by a few ulps so that GridGeometry maps it to exactly k
    // (a point exactly on a face plane by the library's own arithmetic) when such a double exists.
    double lattice(int axis, int k) const {
        const double o = g_.origin()[axis];
        const double s = g_.voxel_size();
        double x = o + s * k;
        double best = x;
        double down = x;
        double up = x;
        for (int i = 0; i < 8; ++i) {
            if ((up - o) / s == static_cast<double>(k))
                return up;
            if ((down - o) / s == static_cast<double>(k))
                return down;
            up = std::nextafter(up, std::numeric_limits<double>::infinity());
            down = std::nextafter(down, -std::numeric_limits<double>::infinity());
        }
        return best;
    }
    double random_coord(int axis, double margin) {
        return uni(g_.origin()[axis] - margin, g_.max_corner()[axis] + margin);
    }
    V3 random_point(double margin) {
        return V3(random_coord(0, margin), random_coord(1, margin), random_coord(2, margin));
    }
    V3 lattice_point() {
        return V3(lattice(0, integer(-2, dim(0) + 2)), lattice(1, integer(-2, dim(1) + 2)),
                  lattice(2, integer(-2, dim(2) + 2)));
    }
    V3 mixed_point() {
        V3 p;
        for (int a = 0; a < 3; ++a)
            p[a] = integer(0, 1) == 0 ? lattice(a, integer(-1, dim(a) + 1)) : random_coord(a, 0.2);
        return p;
    }
    V3 random_direction() {
        V3 d(uni(-1.0, 1.0), uni(-1.0, 1.0), uni(-1.0, 1.0));
        return d.norm() > 1e-3 ? V3(d.normalized()) : V3(1.0, 0.0, 0.0);
    }

    // Kind i % 11 of segment.
    std::pair<V3, V3> make(int i) {
        const double s = g_.voxel_size();
        switch (i % 11) {
            case 0:  // anywhere around the grid: inside, entering, leaving, crossing, missing
                return {random_point(3 * s), random_point(3 * s)};
            case 1:  // inside
                return {random_point(0.0), random_point(0.0)};
            case 2:  // lattice to lattice: faces, edges, corners
                return {lattice_point(), lattice_point()};
            case 3: {  // lattice start, whole-voxel diagonal steps: exact edge and corner crossings
                int k[3];
                int d[3];
                const int m = integer(1, 6);
                for (int a = 0; a < 3; ++a) {
                    k[a] = integer(-1, dim(a));
                    d[a] = integer(-1, 1) * integer(1, 2);
                }
                return {V3(lattice(0, k[0]), lattice(1, k[1]), lattice(2, k[2])),
                        V3(lattice(0, k[0] + m * d[0]), lattice(1, k[1] + m * d[1]), lattice(2, k[2] + m * d[2]))};
            }
            case 4: {  // parallel to an axis, often on a face plane or an edge
                const V3 a = mixed_point();
                V3 b = a;
                const int axis = integer(0, 2);
                b[axis] = integer(0, 1) == 0 ? random_coord(axis, 2 * s) : lattice(axis, integer(-1, dim(axis) + 1));
                return {a, b};
            }
            case 5: {  // lying in a face plane (one shared lattice coordinate) or on an edge line (two)
                V3 a = random_point(2 * s);
                V3 b = random_point(2 * s);
                const int axis = integer(0, 2);
                a[axis] = b[axis] = lattice(axis, integer(0, dim(axis)));
                if (integer(0, 2) == 0) {
                    const int other = (axis + 1 + integer(0, 1)) % 3;
                    a[other] = b[other] = lattice(other, integer(0, dim(other)));
                }
                return {a, b};
            }
            case 6: {  // zero length
                const V3 a = integer(0, 1) == 0 ? random_point(s) : mixed_point();
                return {a, a};
            }
            case 7: {  // very short, often starting on a face, edge or corner
                const V3 a = integer(0, 1) == 0 ? mixed_point() : lattice_point();
                return {a, a + random_direction() * std::pow(10.0, uni(-13.0, -6.0))};
            }
            case 8: {  // missing the grid, or long and from far away
                const int axis = integer(0, 2);
                V3 a = random_point(3 * s);
                V3 b = random_point(3 * s);
                if (integer(0, 1) == 0) {
                    const double beyond = integer(0, 1) == 0 ? g_.origin()[axis] - uni(1e-9, 3 * s)
                                                             : g_.max_corner()[axis] + uni(0.0, 3 * s);
                    a[axis] = beyond;
                    b[axis] = beyond + (beyond < g_.origin()[axis] ? -uni(0.0, s) : uni(0.0, s));
                } else {
                    const V3 c = random_point(0.0);
                    const V3 dir = random_direction();
                    a = c - dir * uni(1.0, 50.0);
                    b = c + dir * uni(1.0, 50.0);
                }
                return {a, b};
            }
            case 9: {  // an endpoint on the grid's minimum or maximum face
                V3 a = random_point(0.0);
                const int axis = integer(0, 2);
                a[axis] = integer(0, 1) == 0 ? lattice(axis, 0) : lattice(axis, dim(axis));
                const V3 b = random_point(2 * s);
                return integer(0, 1) == 0 ? std::make_pair(a, b) : std::make_pair(b, a);
            }
            default: {  // near-lattice: a few 1e-13 m off faces, edges and corners (grazing)
                V3 a = lattice_point();
                V3 b = lattice_point();
                for (int ax = 0; ax < 3; ++ax) {
                    a[ax] += uni(-1e-13, 1e-13);
                    b[ax] += uni(-1e-13, 1e-13);
                }
                return {a, b};
            }
        }
    }

private:
    const GridGeometry& g_;
    std::mt19937 rng_;
};

GridGeometry grid_of(const V3& origin, double voxel_size, GridDims dims) {
    return GridGeometry::make(origin, voxel_size, dims).value();
}
GridGeometry grid_a() {  // voxel size 0.1 (not a binary fraction), origin off any lattice
    return grid_of(V3(-0.37, 0.21, -0.13), 0.1, GridDims{7, 5, 6});
}
GridGeometry grid_b() {  // binary fractions: lattice coordinates are exact
    return GridGeometry::make(V3(-0.5, 0.25, -0.375), 0.125, GridDims{7, 5, 6}).value();
}

void report(const char* name, const CompareStats& st) {
    std::ostringstream os;
    os << name << ": " << st.segments << " segments, " << st.nonempty << " reach the grid, " << st.visited
       << " voxels visited; grazing mismatches tolerated in " << st.tolerated_segments << " segments ("
       << st.tolerated_voxels << " voxels); failures " << st.failures;
    for (const std::string& f : st.first_failures)
        os << "\n  " << f;
    MESSAGE(os.str());
}

}  // namespace

// verifies: SR-TRAV-001
TEST_CASE("traversal: exact traversal equals a brute-force reference on 24000 random segments (voxel 0.1 m)") {
    const GridGeometry g = grid_a();
    SegmentMaker maker(g, 20240611U);
    CompareStats st;
    for (int i = 0; i < 24000; ++i) {
        const auto seg = maker.make(i);
        compare_exact(g, seg.first, seg.second, st);
    }
    report("grid 7x5x6 at 0.1 m", st);
    CHECK(st.failures == 0);
    CHECK(st.nonempty > st.segments / 2);
    // Grazing mismatches come only from segments through (or within rounding of) a voxel
    // edge or corner whose coordinates 0.1 m voxels cannot represent exactly: a small fraction.
    CHECK(st.tolerated_segments * 60 < st.segments);  // 1.3% with this seed
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: exact traversal equals a brute-force reference on 6000 random segments (exact lattice)") {
    const GridGeometry g = grid_b();
    SegmentMaker maker(g, 7U);
    CompareStats st;
    long lattice_segments = 0;
    long lattice_tolerated = 0;
    for (int i = 0; i < 6000; ++i) {
        const auto seg = maker.make(i);
        const long before = st.tolerated_segments;
        compare_exact(g, seg.first, seg.second, st);
        if (i % 11 == 2 || i % 11 == 3) {  // lattice to lattice, through faces, edges and corners
            ++lattice_segments;
            lattice_tolerated += st.tolerated_segments - before;
        }
    }
    report("grid 7x5x6 at 0.125 m", st);
    MESSAGE("lattice-to-lattice segments: " << lattice_segments << ", with a grazing mismatch: " << lattice_tolerated);
    CHECK(st.failures == 0);
    // With binary-fraction geometry, lattice coordinates are exact in voxel units, crossings at
    // edges and corners are computed exactly equal, and nothing needs tolerating.
    CHECK(lattice_segments > 1000);
    CHECK(lattice_tolerated == 0);
    // Elsewhere only crossings that nearly coincide (within ~1e-16 of the segment) can differ.
    CHECK(st.tolerated_segments * 500 < st.segments);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: the reference comparison detects a wrong traversal") {
    // Guards the reference itself: doctored visit sequences must be rejected.
    const GridGeometry g = grid_a();
    const V3 a = g.voxel_center(VoxelCoord{0, 0, 0}) + V3(0.01, 0.02, 0.0);
    const V3 b = g.voxel_center(VoxelCoord{6, 4, 5});
    const std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, a, b);
    REQUIRE(t.size() >= 13U);
    const auto failures = [&](const std::vector<TraversedVoxel>& seq) {
        CompareStats st;
        compare_sequence(g, a, b, seq, st);
        return st.failures;
    };
    CHECK(failures(t) == 0);
    std::vector<TraversedVoxel> dropped = t;  // a voxel crossed for a long way is missing
    dropped.erase(dropped.begin() + 5);
    CHECK(failures(dropped) > 0);
    std::vector<TraversedVoxel> swapped = t;  // order
    std::swap(swapped[4].coord, swapped[5].coord);
    std::swap(swapped[4].index, swapped[5].index);
    CHECK(failures(swapped) > 0);
    std::vector<TraversedVoxel> extra = t;  // a voxel the segment does not touch
    const VoxelCoord far{6, 0, 0};
    extra.insert(extra.begin() + 3, TraversedVoxel{g.index_of(far), far, extra[3].t_enter, extra[3].t_enter});
    CHECK(failures(extra) > 0);
    std::vector<TraversedVoxel> first_moved = t;  // the first voxel is not the start voxel
    first_moved.front().coord = VoxelCoord{1, 0, 0};
    first_moved.front().index = g.index_of(first_moved.front().coord);
    CHECK(failures(first_moved) > 0);
    std::vector<TraversedVoxel> last_moved = t;  // the last voxel is not the end voxel
    last_moved.back().coord = VoxelCoord{5, 4, 5};
    last_moved.back().index = g.index_of(last_moved.back().coord);
    CHECK(failures(last_moved) > 0);
    std::vector<TraversedVoxel> shifted = t;  // distances off by 1e-6 m
    shifted[6].t_exit += 1e-6;
    shifted[7].t_enter += 1e-6;
    CHECK(failures(shifted) > 0);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a segment along an axis visits every voxel it touches, with exact distances") {
    const GridGeometry g = GridGeometry::make(V3(-1.0, -1.0, 0.0), 0.25, GridDims{8, 4, 4}).value();
    const V3 a = g.voxel_center(VoxelCoord{0, 2, 3});
    const V3 b = g.voxel_center(VoxelCoord{7, 2, 3});
    const std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, a, b);
    REQUIRE(t.size() == 8U);
    for (int i = 0; i < 8; ++i) {
        CHECK(t[static_cast<std::size_t>(i)].coord == VoxelCoord{i, 2, 3});
        CHECK(t[static_cast<std::size_t>(i)].index == g.index_of(VoxelCoord{i, 2, 3}));
        CHECK(t[static_cast<std::size_t>(i)].t_enter == doctest::Approx(std::max(0.0, 0.25 * i - 0.125)));
        CHECK(t[static_cast<std::size_t>(i)].t_exit == doctest::Approx(std::min(1.75, 0.25 * i + 0.125)));
    }
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a segment lying in a face plane visits only the voxels above the face") {
    const GridGeometry g = GridGeometry::make(V3(0.0, 0.0, 0.0), 0.5, GridDims{4, 4, 4}).value();
    // y = 1.0 is the face between rows 1 and 2.
    std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, V3(0.1, 1.0, 0.3), V3(1.9, 1.0, 0.3));
    REQUIRE(t.size() == 4U);
    for (const TraversedVoxel& v : t)
        CHECK(v.coord.y == 2);
    // On an edge line (y = 1.0 and z = 0.5): the voxels above both faces.
    t = collect(Rasterization::kExact, g, V3(0.1, 1.0, 0.5), V3(1.9, 1.0, 0.5));
    REQUIRE(t.size() == 4U);
    for (const TraversedVoxel& v : t)
        CHECK((v.coord.y == 2 && v.coord.z == 1));
    // On the grid's minimum face: inside; on its maximum face: outside (half-open cells).
    CHECK(collect(Rasterization::kExact, g, V3(0.1, 0.0, 0.3), V3(1.9, 0.0, 0.3)).size() == 4U);
    CHECK(collect(Rasterization::kExact, g, V3(0.1, 2.0, 0.3), V3(1.9, 2.0, 0.3)).empty());
    CHECK_FALSE(clip_segment_to_grid(g, V3(0.1, 2.0, 0.3), V3(1.9, 2.0, 0.3)).hits);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a segment through lattice corners steps diagonally and skips voxels it only touches") {
    const GridGeometry g = GridGeometry::make(V3(0.0, 0.0, 0.0), 0.5, GridDims{4, 4, 4}).value();
    const std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, V3(0.25, 0.25, 0.25), V3(1.25, 1.25, 1.25));
    REQUIRE(t.size() == 3U);
    CHECK(t[0].coord == VoxelCoord{0, 0, 0});
    CHECK(t[1].coord == VoxelCoord{1, 1, 1});
    CHECK(t[2].coord == VoxelCoord{2, 2, 2});
    // Through an edge (x = y = 0.5 at z = 0.25): steps x and y together.
    const std::vector<TraversedVoxel> e = collect(Rasterization::kExact, g, V3(0.25, 0.25, 0.25), V3(0.75, 0.75, 0.25));
    REQUIRE(e.size() == 2U);
    CHECK(e[1].coord == VoxelCoord{1, 1, 0});
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: an end exactly on a face belongs to the voxel above it") {
    const GridGeometry g = GridGeometry::make(V3(0.0, 0.0, 0.0), 0.5, GridDims{4, 4, 4}).value();
    // Moving up onto the face x = 1.0: the voxel above is the last, with zero length.
    std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, V3(0.1, 0.1, 0.1), V3(1.0, 0.1, 0.1));
    REQUIRE(t.size() == 3U);
    CHECK(t[2].coord == VoxelCoord{2, 0, 0});
    CHECK(t[2].t_enter == doctest::Approx(0.9));
    CHECK(t[2].t_exit == doctest::Approx(0.9));
    // Moving down onto the same face: it is the lower face of the last voxel; nothing is added.
    t = collect(Rasterization::kExact, g, V3(1.9, 0.1, 0.1), V3(1.0, 0.1, 0.1));
    REQUIRE(t.size() == 2U);
    CHECK(t[1].coord == VoxelCoord{2, 0, 0});
    // Starting on a face and moving down: the start voxel (above) first, with zero length.
    t = collect(Rasterization::kExact, g, V3(1.0, 0.1, 0.1), V3(0.1, 0.1, 0.1));
    REQUIRE(t.size() == 3U);
    CHECK(t[0].coord == VoxelCoord{2, 0, 0});
    CHECK(t[0].t_exit == 0.0);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a segment from outside is clipped at the grid box and one ending outside stops there") {
    const GridGeometry g = GridGeometry::make(V3(0.0, 0.0, 0.0), 1.0, GridDims{4, 4, 4}).value();
    const V3 a(-2.0, 0.5, 0.5);
    const V3 b(6.0, 0.5, 0.5);
    const ClippedSegment c = clip_segment_to_grid(g, a, b);
    CHECK(c.hits);
    CHECK(c.t_enter == doctest::Approx(2.0));
    CHECK(c.t_exit == doctest::Approx(6.0));
    CHECK(c.length == doctest::Approx(8.0));
    const std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, a, b);
    REQUIRE(t.size() == 4U);
    CHECK(t.front().coord == VoxelCoord{0, 0, 0});
    CHECK(t.front().t_enter == doctest::Approx(2.0));
    CHECK(t.back().coord == VoxelCoord{3, 0, 0});
    CHECK(t.back().t_exit == doctest::Approx(6.0));
    // Ending exactly on the minimum face from outside: only the end voxel, at t = length.
    const std::vector<TraversedVoxel> touch = collect(Rasterization::kExact, g, V3(-1.0, 0.5, 0.5), V3(0.0, 0.5, 0.5));
    REQUIRE(touch.size() == 1U);
    CHECK(touch[0].coord == VoxelCoord{0, 0, 0});
    CHECK(touch[0].t_enter == doctest::Approx(1.0));
    const ClippedSegment tc = clip_segment_to_grid(g, V3(-1.0, 0.5, 0.5), V3(0.0, 0.5, 0.5));
    CHECK(tc.hits);
    CHECK(tc.t_enter == doctest::Approx(1.0));
    CHECK(tc.t_exit == doctest::Approx(1.0));
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a segment entering or leaving the grid exactly through a voxel edge skips the voxel it touches") {
    // Both segments cross the box exactly on a voxel edge, where rounding the entry or exit
    // point puts it on the wrong side of the edge; the set-up corrects that with exact fractions.
    const GridGeometry g = GridGeometry::make(V3(0.0, 0.0, 0.0), 1.0, GridDims{8, 8, 8}).value();
    // Enters at (2, 3.449, 8): on the edge x = 2 of the top face, moving up in x.
    std::vector<TraversedVoxel> t = collect(Rasterization::kExact, g, V3(-1.0, 1.0, 10.0), V3(17.375, 16.0, -2.25));
    REQUIRE(t.size() == 12U);
    CHECK(t.front().coord == VoxelCoord{2, 3, 7});
    CHECK(t.front().t_exit > t.front().t_enter);
    // Leaves at z = 8 on an edge of the top face.
    t = collect(Rasterization::kExact, g, V3(-7.0, 11.375, -9.0), V3(12.4375, 2.0, 16.0));
    REQUIRE(t.size() == 16U);
    CHECK(t.back().coord == VoxelCoord{6, 5, 7});
    CHECK(t.back().t_exit > t.back().t_enter);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: non-finite, far-away and missing segments visit nothing") {
    const GridGeometry g = grid_a();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const V3 in = g.voxel_center(VoxelCoord{3, 2, 2});
    for (const Rasterization m : {Rasterization::kExact, Rasterization::kBresenham3d}) {
        CHECK(collect(m, g, V3(nan, 0.0, 0.0), in).empty());
        CHECK(collect(m, g, in, V3(0.0, inf, 0.0)).empty());
        CHECK(collect(m, g, V3(-inf, 0.0, 0.0), V3(inf, 0.0, 0.0)).empty());
        CHECK(collect(m, g, in, V3(0.0, 0.0, 1e300)).empty());                 // beyond kMaxSegmentVoxelCoordinate
        CHECK(collect(m, g, V3(5.0, 5.0, 5.0), V3(6.0, 5.0, 5.0)).empty());    // misses
        CHECK(collect(m, g, V3(-5.0, 0.0, 0.0), V3(5.0, 0.0, 10.0)).empty());  // passes beside
        CHECK(count_traversed_voxels(m, g, V3(nan, nan, nan), in) == 0U);
    }
    CHECK_FALSE(clip_segment_to_grid(g, V3(nan, 0.0, 0.0), in).hits);
    CHECK(clip_segment_to_grid(g, V3(nan, 0.0, 0.0), in).length == 0.0);
    CHECK_FALSE(clip_segment_to_grid(g, V3(5.0, 5.0, 5.0), V3(6.0, 5.0, 5.0)).hits);
    CHECK(collect(Rasterization::kExact, GridGeometry{}, V3(0.0, 0.0, 0.0), V3(1.0, 1.0, 1.0)).empty());
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: wild finite input never leaves the grid nor exceeds the bound") {
    // Coordinates of random sign and magnitude from 1e-300 to 1e300, some near the grid.
    const GridGeometry g = grid_a();
    std::mt19937 rng(31U);
    std::uniform_real_distribution<double> mant(-1.0, 1.0);
    std::uniform_int_distribution<int> expo(-300, 300);
    std::uniform_int_distribution<int> kind(0, 3);
    const auto coord = [&](int axis) {
        switch (kind(rng)) {
            case 0: return mant(rng) * std::pow(10.0, expo(rng));
            case 1: return g.origin()[axis] + mant(rng) * std::pow(10.0, expo(rng) / 20);
            case 2: return g.origin()[axis] + std::ldexp(mant(rng), expo(rng) / 10);
            default: return g.origin()[axis] + 0.35 + mant(rng) * 0.5;
        }
    };
    long bad = 0;
    long nonempty = 0;
    for (int i = 0; i < 20000; ++i) {
        const V3 a(coord(0), coord(1), coord(2));
        const V3 b(coord(0), coord(1), coord(2));
        for (const Rasterization m : {Rasterization::kExact, Rasterization::kBresenham3d}) {
            std::size_t n = 0U;
            double last_enter = 0.0;
            const std::size_t count = traverse(m, g, a, b, [&](const TraversedVoxel& v) {
                const bool ok = g.contains(v.coord) && v.index == g.index_of(v.coord) && std::isfinite(v.t_enter) &&
                                std::isfinite(v.t_exit) && v.t_enter <= v.t_exit && v.t_enter >= last_enter;
                bad += ok ? 0 : 1;
                last_enter = v.t_enter;
                ++n;
            });
            bad += (count == n && n <= max_voxels_per_segment(g)) ? 0 : 1;
            nonempty += n > 0U ? 1 : 0;
        }
    }
    CHECK(bad == 0);
    CHECK(nonempty > 1000);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a zero-length segment visits the voxel holding it") {
    const GridGeometry g = grid_a();
    const V3 p = g.voxel_center(VoxelCoord{4, 1, 5});
    for (const Rasterization m : {Rasterization::kExact, Rasterization::kBresenham3d}) {
        const std::vector<TraversedVoxel> t = collect(m, g, p, p);
        REQUIRE(t.size() == 1U);
        CHECK(t[0].coord == VoxelCoord{4, 1, 5});
        CHECK(t[0].t_enter == 0.0);
        CHECK(t[0].t_exit == 0.0);
        CHECK(collect(m, g, V3(9.0, 9.0, 9.0), V3(9.0, 9.0, 9.0)).empty());
    }
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: the largest grids are walked within the nx + ny + nz - 2 bound") {
    const GridGeometry g = GridGeometry::make(V3(-20.48, -20.48, 0.0), 0.01, GridDims{4096, 4096, 8}).value();
    const V3 a(-20.475, -20.475, 0.005);
    const V3 b(20.475, 20.4, 0.075);
    std::size_t n = 0U;
    VoxelCoord last{};
    double t_prev = 0.0;
    bool monotone = true;
    const std::size_t count = traverse_segment(g, a, b, [&](const TraversedVoxel& v) {
        monotone = monotone && v.t_enter >= t_prev;
        t_prev = v.t_enter;
        last = v.coord;
        ++n;
    });
    CHECK(count == n);
    CHECK(n <= max_voxels_per_segment(g));
    CHECK(max_voxels_per_segment(g) == 4096U + 4096U + 8U - 2U);
    CHECK(n >= 4096U + 4088U);
    CHECK(monotone);
    CHECK(last == g.world_to_voxel(b).value());
    CHECK(count_traversed_voxels(Rasterization::kBresenham3d, g, a, b) == 4096U);
}

// verifies: SR-TRAV-001, SR-TRAV-002
TEST_CASE("traversal: dispatch runs the chosen method and rejects an unknown one") {
    const GridGeometry g = grid_a();
    const V3 a = g.voxel_center(VoxelCoord{0, 0, 0});
    const V3 b = g.voxel_center(VoxelCoord{6, 3, 2});
    std::size_t exact = 0U;
    std::size_t bres = 0U;
    CHECK(traverse(Rasterization::kExact, g, a, b, [&](const TraversedVoxel&) { ++exact; }) == exact);
    CHECK(traverse(Rasterization::kBresenham3d, g, a, b, [&](const TraversedVoxel&) { ++bres; }) == bres);
    CHECK(exact == traverse_segment(g, a, b, [](const TraversedVoxel&) {}));
    CHECK(bres == 7U);
    CHECK(exact > bres);
    CHECK(count_traversed_voxels(Rasterization::kExact, g, a, b) == exact);
    CHECK(test::violates_contract([&] { (void)count_traversed_voxels(static_cast<Rasterization>(7), g, a, b); }));
}

// ---------------------------------------------------------------------------------------------
// Bresenham.

namespace {

// The plain 3D Bresenham line from voxel(a) to voxel(b): at step i the minor axes are
// i * |d| / D rounded to nearest (halves towards the end), computed in long double.
std::vector<VoxelCoord> plain_bresenham(const GridGeometry& g, const V3& a, const V3& b) {
    const VoxelCoord v0 = g.world_to_voxel_unchecked(a);
    const VoxelCoord v1 = g.world_to_voxel_unchecked(b);
    const long long d[3] = {static_cast<long long>(v1.x) - v0.x, static_cast<long long>(v1.y) - v0.y,
                            static_cast<long long>(v1.z) - v0.z};
    const long long big = std::max({std::llabs(d[0]), std::llabs(d[1]), std::llabs(d[2])});
    std::vector<VoxelCoord> out;
    for (long long i = 0; i <= big; ++i) {
        long long c[3] = {v0.x, v0.y, v0.z};
        for (int k = 0; k < 3; ++k) {
            if (big == 0)
                continue;
            const LD f = static_cast<LD>(i) * static_cast<LD>(std::llabs(d[k])) / static_cast<LD>(big);
            const long long q = static_cast<long long>(std::floor(f + 0.5L));
            c[k] += d[k] < 0 ? -q : q;
        }
        const VoxelCoord v{static_cast<int>(c[0]), static_cast<int>(c[1]), static_cast<int>(c[2])};
        if (g.contains(v))
            out.push_back(v);
    }
    return out;
}

}  // namespace

// verifies: SR-TRAV-002
TEST_CASE("traversal: Bresenham equals the plain integer line on 24000 random segments, clipped to the grid") {
    const GridGeometry g = grid_a();
    SegmentMaker maker(g, 99U);
    long failures = 0;
    long inside_segments = 0;
    long visited = 0;
    std::vector<std::string> first;
    const auto fail_b = [&](const std::string& what, const V3& a, const V3& b) {
        ++failures;
        if (first.size() < 8U)
            first.push_back(what + " for " + str(a) + " -> " + str(b));
    };
    for (int i = 0; i < 24000; ++i) {
        const auto seg = maker.make(i);
        const V3& a = seg.first;
        const V3& b = seg.second;
        const std::vector<TraversedVoxel> t = collect(Rasterization::kBresenham3d, g, a, b);
        const std::vector<VoxelCoord> ref = plain_bresenham(g, a, b);
        visited += static_cast<long>(t.size());
        if (t.size() != ref.size()) {
            fail_b("count " + std::to_string(t.size()) + " != " + std::to_string(ref.size()), a, b);
            continue;
        }
        const double length = (b - a).norm();
        const V3 dir = length > 0.0 ? V3((b - a) / length) : V3::Zero();
        const double half = length > 0.0 ? 0.5 * g.voxel_size() / dir.cwiseAbs().maxCoeff() : 0.0;
        for (std::size_t k = 0; k < t.size(); ++k) {
            const TraversedVoxel& v = t[k];
            if (v.coord != ref[k] || v.index != g.index_of(v.coord))
                fail_b("voxel " + std::to_string(k) + " differs", a, b);
            const double centre = (g.voxel_center(v.coord) - a).dot(dir);
            const double te = std::min(std::max(centre - half, 0.0), length);
            const double tx = std::min(std::max(centre + half, 0.0), length);
            if (std::fabs(v.t_enter - te) > kGrazing || std::fabs(v.t_exit - tx) > kGrazing)
                fail_b("t differs", a, b);
            if (k > 0) {
                const VoxelCoord& p = t[k - 1].coord;
                const int dx = std::abs(v.coord.x - p.x);
                const int dy = std::abs(v.coord.y - p.y);
                const int dz = std::abs(v.coord.z - p.z);
                if (dx > 1 || dy > 1 || dz > 1 || dx + dy + dz == 0)
                    fail_b("not 26-connected", a, b);
                if (v.t_enter < t[k - 1].t_enter)
                    fail_b("t_enter decreases", a, b);
            }
        }
        const Result<VoxelCoord> sv = g.world_to_voxel(a);
        const Result<VoxelCoord> ev = g.world_to_voxel(b);
        if (sv.ok() && ev.ok()) {
            ++inside_segments;
            const VoxelCoord s0 = sv.value();
            const VoxelCoord s1 = ev.value();
            const std::size_t expected = static_cast<std::size_t>(
                std::max({std::abs(s1.x - s0.x), std::abs(s1.y - s0.y), std::abs(s1.z - s0.z)}) + 1);
            if (t.size() != expected)
                fail_b("not max(|dx|,|dy|,|dz|)+1 voxels", a, b);
            if (t.empty() || t.front().coord != s0 || t.back().coord != s1)
                fail_b("endpoints not included", a, b);
        }
    }
    std::ostringstream os;
    os << "Bresenham: 24000 segments, " << inside_segments << " fully inside, " << visited
       << " voxels visited; failures " << failures;
    for (const std::string& f : first)
        os << "\n  " << f;
    MESSAGE(os.str());
    CHECK(failures == 0);
    CHECK(inside_segments > 3000);
}

// verifies: SR-TRAV-002
TEST_CASE("traversal: Bresenham misses voxels the exact traversal passes through (why it is only an option)") {
    const GridGeometry g = grid_a();
    // A diagonal in the xy-plane, from the centre of (0,0,2) to the centre of (6,3,2).
    const V3 a = g.voxel_center(VoxelCoord{0, 0, 2});
    const V3 b = g.voxel_center(VoxelCoord{6, 3, 2});
    const std::vector<TraversedVoxel> exact = collect(Rasterization::kExact, g, a, b);
    const std::vector<TraversedVoxel> bres = collect(Rasterization::kBresenham3d, g, a, b);
    CHECK(bres.size() == 7U);
    CHECK(exact.size() == 10U);
    std::set<std::tuple<int, int, int>> in_bres;
    for (const TraversedVoxel& v : bres)
        in_bres.insert(key(v.coord));
    double longest_missed = 0.0;
    for (const TraversedVoxel& v : exact) {
        if (in_bres.count(key(v.coord)) == 0U)
            longest_missed = std::max(longest_missed, v.t_exit - v.t_enter);
    }
    // The ray crosses a missed voxel for over a fifth of a voxel: real free space left unobserved.
    CHECK(longest_missed > 0.2 * g.voxel_size());

    // Over random segments inside the grid, the exact traversal never visits fewer voxels, and
    // Bresenham misses a voxel crossed for more than a tenth of a voxel in most of them.
    SegmentMaker maker(g, 5U);
    int segments = 0;
    int fewer = 0;
    int missing = 0;
    for (int i = 0; i < 2000; ++i) {
        const V3 p = maker.random_point(0.0);
        const V3 q = maker.random_point(0.0);
        const std::vector<TraversedVoxel> e = collect(Rasterization::kExact, g, p, q);
        const std::vector<TraversedVoxel> r = collect(Rasterization::kBresenham3d, g, p, q);
        ++segments;
        fewer += e.size() < r.size() ? 1 : 0;
        std::set<std::tuple<int, int, int>> rs;
        for (const TraversedVoxel& v : r)
            rs.insert(key(v.coord));
        bool misses = false;
        for (const TraversedVoxel& v : e) {
            misses = misses || (rs.count(key(v.coord)) == 0U && v.t_exit - v.t_enter > 0.1 * g.voxel_size());
        }
        missing += misses ? 1 : 0;
    }
    CHECK(fewer == 0);
    CHECK(missing * 2 > segments);
}

// verifies: SR-TRAV-001
TEST_CASE(
    "traversal: the crossing bound below a distance is 0 before the segment, never beyond it, else a safe floor") {
    const GridGeometry g = grid_a();
    const V3 a = g.voxel_center(VoxelCoord{0, 1, 1});
    const V3 b = g.voxel_center(VoxelCoord{5, 2, 3});
    const detail::ExactTraversalPlan p = detail::plan_exact_traversal(g, a, b);
    REQUIRE(p.visits);
    REQUIRE(p.t_out > p.t_in);
    // Before the segment's start in the grid, and at or below 0: no crossing is known to be below.
    CHECK(detail::tau_bound_below(p, p.t_in - 1e-3) == 0U);
    CHECK(detail::tau_bound_below(p, 0.0) == 0U);
    CHECK(detail::tau_bound_below(p, -1.0) == 0U);
    CHECK(detail::tau_bound_below(p, std::numeric_limits<double>::quiet_NaN()) == 0U);
    // At or beyond where the last voxel is left: every crossing.
    CHECK(detail::tau_bound_below(p, p.t_out) == detail::kTauNever);
    CHECK(detail::tau_bound_below(p, p.t_out + 1.0) == detail::kTauNever);
    // In between: a bound whose crossings all end at or before the distance.
    const double mid = 0.5 * (p.t_in + p.t_out);
    const std::uint64_t tau = detail::tau_bound_below(p, mid);
    REQUIRE(tau > 0U);
    REQUIRE(tau < detail::kTauNever);
    CHECK(detail::exit_metres(p, tau - 1U) <= mid);
    CHECK(detail::exit_metres(p, 2U * tau) > mid);
    // A plan whose metres per tau are so small that the bound would pass 2^62: every crossing.
    detail::ExactTraversalPlan fine = p;
    fine.metres_per_tau = 1e-30;
    CHECK(detail::tau_bound_below(fine, mid) == detail::kTauNever);
}

// verifies: SR-TRAV-001
TEST_CASE("traversal: a segment whose length in metres overflows binary64 visits nothing") {
    // Voxels of 1e150 m: the far ends lie 1e8 voxels from the grid, within kMaxSegmentVoxelCoordinate, but the
    // square of their distance (2e158 m) is beyond binary64, so its length is not finite. The same grid walks a
    // segment of 3e150 m.
    const GridGeometry g = grid_of(V3(-2e150, -2e150, -2e150), 1e150, GridDims{4, 4, 4});
    const V3 far_lo(-1e158, 0.5e150, 0.5e150);
    const V3 far_hi(1e158, 0.5e150, 0.5e150);
    for (const Rasterization m : {Rasterization::kExact, Rasterization::kBresenham3d}) {
        CAPTURE(static_cast<int>(m));
        CHECK(collect(m, g, V3(-1.5e150, 0.5e150, 0.5e150), V3(1.5e150, 0.5e150, 0.5e150)).size() == 4U);
        CHECK(collect(m, g, far_lo, far_hi).empty());
        CHECK(count_traversed_voxels(m, g, far_lo, far_hi) == 0U);
    }
    CHECK(clip_segment_to_grid(g, V3(-1.5e150, 0.5e150, 0.5e150), V3(1.5e150, 0.5e150, 0.5e150)).hits);
    CHECK_FALSE(clip_segment_to_grid(g, far_lo, far_hi).hits);
}
