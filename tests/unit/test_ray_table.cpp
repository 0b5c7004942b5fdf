// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: precomputed rays of static sensors give the same evidence as
// on-the-fly fusion, within the stated boundary cases, and allocate nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_table.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "contract_capture.hpp"
#include "ray_table_vectors.hpp"

using namespace cellguard;

namespace {

/// A built table (REQUIREd to build).
struct OwnedTable {
    host::OwnedRayTable owned;
    const RayTable& table;
    OwnedTable(const GridGeometry& g, const SensorReading& r) : table(owned.table()) {
        REQUIRE(owned.build(g, r).ok());
    }
};

OwnedTable make_table(const GridGeometry& g, const SensorReading& r) { return OwnedTable(g, r); }

struct OwnedGrid {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    std::vector<std::int16_t> scratch;
    EvidenceGrid grid;
    Span<std::int16_t> fusion_scratch() { return {scratch.data(), scratch.size()}; }
    explicit OwnedGrid(const GridGeometry& g) : lo(g.voxel_count()), ob(g.voxel_count()), scratch(g.voxel_count()) {
        grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        grid.clear();
    }
};

/// The sensor model applied ray by ray to the table's entries, with each
/// reading placed by fuse_sensor's rule (depth_pixel_point, reading_in_cell,
/// the half-open rule): the entry of that voxel gets the hit and every entry
/// before it the profile's free opinion (constant, then the ramp); a reading
/// outside the grid leaves every entry it passes free. Each voxel keeps the
/// largest opinion (fusion.hpp), kNoOpinion where no ray reached it.
struct ExactOpinions {
    std::vector<std::int16_t> opinion;
};

ExactOpinions walk_per_ray(const host::OwnedRayTable& t, const SensorReading& r, const SensorModelTable& model,
                           const GridGeometry& g) {
    const std::size_t voxel_count = g.voxel_count();
    ExactOpinions out{std::vector<std::int16_t>(voxel_count, kNoOpinion)};
    const auto add = [&](std::uint32_t v, std::int16_t e) { out.opinion[v] = std::max(out.opinion[v], e); };
    const PinholeIntrinsics& k = r.intrinsics;
    for (std::size_t i = 0; i < r.depth.size(); ++i) {
        const float d = r.depth[i];
        if (!std::isfinite(d) || d <= 0.0F) {
            continue;
        }
        const float range = d * t.table().pixel_norm(i);
        if (range < r.min_range || range > r.max_range || range < t.table().pixel_enter(i)) {
            continue;
        }
        const auto u = static_cast<std::int32_t>(i % static_cast<std::size_t>(k.width));
        const auto v = static_cast<std::int32_t>(i / static_cast<std::size_t>(k.width));
        const VoxelCoord c = g.world_to_voxel_unchecked(
            reading_in_cell(r.pose, depth_pixel_point(k, 1.0 / k.fx, 1.0 / k.fy, u, v, d)));
        const std::size_t hit_voxel = g.contains(c) ? g.index_of(c) : voxel_count;
        const std::uint32_t end = t.table().pixel_begin(i + 1U);
        for (std::uint32_t e = t.table().pixel_begin(i); e < end; ++e) {
            const float exit = t.table().entry_exit(i, e);
            if (t.table().entry_voxel(e) == hit_voxel) {
                add(t.table().entry_voxel(e), model.reading_evidence());
                break;
            }
            if (hit_voxel != voxel_count && exit > range + 0.01F) {
                break;  // past the reading by more than any rounding: the hit was not on this ray's entries
            }
            add(t.table().entry_voxel(e), model.free_evidence(static_cast<double>(range - exit)));
            if (hit_voxel == voxel_count && exit > range) {
                break;  // a reading outside the grid: the ray ends at the box
            }
        }
    }
    return out;
}

/// Voxels where the fused grid (one sensor into a cleared grid) is not the
/// exact opinions pooled.
std::size_t differs_from_exact(const OwnedGrid& fused, const ExactOpinions& exact, const SensorModelTable& model) {
    std::size_t differ = 0;
    for (std::size_t v = 0; v < exact.opinion.size(); ++v) {
        const bool reached = exact.opinion[v] != kNoOpinion;
        const std::int16_t want = reached ? model.pool(0, exact.opinion[v]) : std::int16_t{0};
        differ += (fused.lo[v] != want || (fused.ob[v] != 0U) != reached) ? 1U : 0U;
    }
    return differ;
}

/// Depth values that put each pixel's reading at @p range_of(pixel) metres.
template <typename RangeOf>
std::vector<float> depths_at(const host::OwnedRayTable& t, std::size_t pixels, RangeOf range_of) {
    std::vector<float> depth(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
        depth[i] = range_of(i) / t.table().pixel_norm(i);
    }
    return depth;
}

}  // namespace

// verifies: SR-FUSE-006
TEST_CASE("ray table: fusing through precomputed rays matches on-the-fly fusion on the simulated workcell") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    // The paper's grid lowered by half a voxel: the simulated floor (exactly z = 0) would
    // otherwise lie on the grid's bottom face, where every floor reading is a boundary case.
    const GridGeometry g =
        GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, -0.025), 0.05, GridDims{34, 30, 30}).value();
    const SensorModelTable model;
    OwnedGrid direct(g);
    OwnedGrid tabled(g);
    FusionStats direct_stats;
    FusionStats table_stats;
    for (const SensorReading& r : frame.readings) {
        direct_stats.add(fuse_sensor(direct.grid, r, model, direct.fusion_scratch()).value());
        const OwnedTable t = make_table(g, r);
        table_stats.add(t.table.fuse(tabled.grid, r.depth, model).value());
    }
    CHECK(table_stats.rays_fused == direct_stats.rays_fused);
    CHECK(table_stats.skipped() == direct_stats.skipped());
    // Boundary cases (readings within rounding of a face, grazing rays) differ; bound them.
    const double updates_ratio = static_cast<double>(table_stats.voxel_updates) /
                                 static_cast<double>(direct_stats.voxel_updates);
    CHECK(updates_ratio == doctest::Approx(1.0).epsilon(0.001));
    CHECK(
        std::abs(static_cast<long>(table_stats.readings_in_grid) - static_cast<long>(direct_stats.readings_in_grid)) <=
        static_cast<long>(direct_stats.readings_in_grid / 1000U));
    std::size_t observed_differ = 0;
    std::size_t sign_differ = 0;
    std::size_t value_differ = 0;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        observed_differ += (direct.ob[i] != tabled.ob[i]) ? 1U : 0U;
        sign_differ += ((direct.lo[i] > 0) != (tabled.lo[i] > 0)) ? 1U : 0U;
        value_differ += (direct.lo[i] != tabled.lo[i]) ? 1U : 0U;
    }
    MESSAGE("voxels whose observed flag differs: " << observed_differ << ", occupied sign: " << sign_differ
                                                   << ", evidence: " << value_differ);
    // Readings on voxel faces (the simulated boxes and floor lie on them)
    // are placed by fuse_sensor's rule: the same voxels are observed and
    // occupied. A compact table's exit distances are rounded to 0.12 mm, which
    // moves a few voxels' free opinions by a step of the ramp (measured 27).
    CHECK(observed_differ == 0U);
    CHECK(sign_differ == 0U);
    CHECK(value_differ <= g.voxel_count() / 1000U);
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: each crossed voxel gets the sensor model's one opinion of the per-ray walk") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    // The paper's grid (compact entries) and the same cell in 2.5 cm voxels
    // (244,800 voxels: wide entries).
    const GridGeometry paper = paper_grid_geometry();
    const GridGeometry fine =
        GridGeometry::make(paper.origin(), paper.voxel_size() / 2.0, GridDims{68, 60, 60}).value();
    REQUIRE(ray_table_is_compact(paper, frame.readings[0]));
    REQUIRE(!ray_table_is_compact(fine, frame.readings[0]));
    const SensorModelTable model;
    for (const GridGeometry& g : {paper, fine}) {
        CAPTURE(g.voxel_count());
        for (const SensorReading& sensor : frame.readings) {
            host::OwnedRayTable t;
            REQUIRE(t.build(g, sensor).ok());
            const std::size_t px = sensor.depth.size();
            // The simulated frame; every reading at max range (the whole table
            // walked: pass 2 takes off nothing); every reading 1 mm before where
            // its ray leaves the grid (ramps and peaks in the last voxels);
            // readings spread over each ray (the constant part's end is searched
            // for, runs break at every pixel).
            std::vector<std::vector<float>> cases;
            cases.emplace_back(sensor.depth.begin(), sensor.depth.end());
            cases.push_back(depths_at(t, px, [&](std::size_t) { return sensor.max_range * 0.9999F; }));
            cases.push_back(depths_at(t, px, [&](std::size_t i) {
                const std::uint32_t b = t.table().pixel_begin(i);
                const std::uint32_t e = t.table().pixel_begin(i + 1U);
                return e > b ? t.table().entry_exit(i, e - 1U) - 0.001F : sensor.max_range * 0.5F;
            }));
            cases.push_back(depths_at(t, px, [&](std::size_t i) {
                return sensor.min_range + (sensor.max_range - sensor.min_range) * static_cast<float>(i % 97U) / 97.0F;
            }));
            // A quarter along each ray in the grid (less than half of the table
            // walked: pass 2 counts the walked entries), and every other pixel
            // invalid, the rest at max range (about half walked).
            cases.push_back(depths_at(t, px, [&](std::size_t i) {
                const std::uint32_t b = t.table().pixel_begin(i);
                const std::uint32_t e = t.table().pixel_begin(i + 1U);
                return e > b ? t.table().entry_exit(i, b + (e - b) / 4U) : sensor.max_range * 0.5F;
            }));
            cases.push_back(depths_at(t, px, [&](std::size_t i) {
                return i % 2U == 0U ? std::numeric_limits<float>::quiet_NaN() : sensor.max_range * 0.9999F;
            }));
            for (std::size_t c = 0; c < cases.size(); ++c) {
                CAPTURE(c);
                SensorReading r = sensor;
                r.depth = Span<const float>(cases[c].data(), cases[c].size());
                OwnedGrid fused(g);
                const FusionStats st = t.table().fuse(fused.grid, r.depth, model).value();
                const ExactOpinions exact = walk_per_ray(t, r, model, g);
                CHECK(st.voxel_updates > 0U);
                MESSAGE("case " << c << ": " << st.voxel_updates << " of " << t.table().step_count()
                                << " entries walked");
                CHECK(differs_from_exact(fused, exact, model) == 0U);
            }
        }
    }
}

// verifies: SR-FUSE-006
TEST_CASE(
    "ray table: readings exactly on an entry's exit, or a ramp before it, give the exact opinions for rays of every length") {
    // The search for the end of the constant part compares keys with a
    // limit. A search that ends one entry late gives a ramp voxel only the
    // constant, and readings on a boundary are where that shows (tried: it
    // fails here); one that ends early costs time only, since the ramp gives
    // the constant beyond its length. Rays of the paper's grid are 1 to over
    // 32 entries long (x86-64 compares up to 32 keys at once and searches
    // longer rays), and the table's last pixels end near the end of the key array.
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorModelTable model;
    const auto ramp = static_cast<float>(model.ramp_length());
    std::size_t longest = 0U;
    std::size_t shortest = std::numeric_limits<std::size_t>::max();
    for (const SensorReading& sensor : frame.readings) {
        host::OwnedRayTable t;
        REQUIRE(t.build(g, sensor).ok());
        REQUIRE(ray_table_is_compact(g, sensor));
        const std::size_t px = sensor.depth.size();
        for (std::size_t i = 0; i < px; ++i) {
            const std::size_t n = t.table().pixel_begin(i + 1U) - t.table().pixel_begin(i);
            if (n > 0U) {
                longest = std::max(longest, n);
                shortest = std::min(shortest, n);
            }
        }
        // The k-th entry's exit, k drawn per pixel: exactly on it, one float
        // above it, and one ramp beyond it (the constant part ends exactly there).
        const auto entry_exit_of = [&](std::size_t i) {
            const std::uint32_t b = t.table().pixel_begin(i);
            const std::uint32_t e = t.table().pixel_begin(i + 1U);
            return e > b ? t.table().entry_exit(i, b + static_cast<std::uint32_t>((i * 7U) % (e - b)))
                         : sensor.max_range * 0.5F;
        };
        std::vector<std::vector<float>> cases;
        cases.push_back(depths_at(t, px, entry_exit_of));
        cases.push_back(depths_at(t, px, [&](std::size_t i) {
            return std::nextafter(entry_exit_of(i), std::numeric_limits<float>::infinity());
        }));
        cases.push_back(depths_at(t, px, [&](std::size_t i) { return entry_exit_of(i) + ramp; }));
        for (std::size_t c = 0; c < cases.size(); ++c) {
            CAPTURE(c);
            SensorReading r = sensor;
            r.depth = Span<const float>(cases[c].data(), cases[c].size());
            OwnedGrid fused(g);
            REQUIRE(t.table().fuse(fused.grid, r.depth, model).ok());
            CHECK(differs_from_exact(fused, walk_per_ray(t, r, model, g), model) == 0U);
        }
    }
    MESSAGE("rays of " << shortest << " to " << longest << " entries");
    CHECK(shortest < 32U);
    CHECK(longest > 32U);
}

// verifies: SR-GEN-002
TEST_CASE("ray table: a frame through the table allocates no memory") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorModelTable model;
    const OwnedTable t = make_table(g, frame.readings[0]);
    OwnedGrid grid(g);
    const test::AllocationScope scope;
    const Result<FusionStats> s = t.table.fuse(grid.grid, frame.readings[0].depth, model);
    CHECK(scope.allocations() == 0U);
    REQUIRE(s.ok());
    CHECK(s.value().rays_fused > 0U);
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: wrong image size, wrong grid and too-small storage are refused") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorModelTable model;
    const SensorReading& r = frame.readings[0];
    const OwnedTable t = make_table(g, r);
    OwnedGrid grid(g);
    CHECK(t.table.fuse(grid.grid, r.depth.subspan(0, r.depth.size() - 1U), model).error() ==
          ErrorCode::kMalformedInput);
    OwnedGrid other(whole_cell_grid_geometry());
    CHECK(t.table.fuse(other.grid, r.depth, model).error() == ErrorCode::kGeometryMismatch);
    CHECK(RayTable{}.fuse(grid.grid, r.depth, model).error() == ErrorCode::kInvalidArgument);

    // Each span one entry short in turn (the others large enough) is refused.
    REQUIRE(ray_table_is_compact(g, r));
    test::RayTableVectors v(g, r);
    const std::size_t n = v.entries;
    const std::size_t px = v.pixels;
    const RayTableStorage full = v.storage();
    REQUIRE(RayTable::build(g, r, full).ok());
    for (int shortened = 0; shortened < 13; ++shortened) {
        CAPTURE(shortened);
        RayTableStorage s = full;
        switch (shortened) {
            case 0: s.compact_voxels = s.compact_voxels.subspan(0, n - 1U); break;
            case 1: s.compact_voxels = {}; break;  // a compact grid needs compact entries
            case 11: s.compact_exit_steps = s.compact_exit_steps.subspan(0, n - 1U); break;
            case 12: s.compact_exit_steps = {}; break;
            case 2: s.pixel_begin = s.pixel_begin.subspan(0, px); break;
            case 3: s.pixel_enter = s.pixel_enter.subspan(0, px - 1U); break;
            case 4: s.pixel_exit = s.pixel_exit.subspan(0, px - 1U); break;
            case 5: s.pixel_norm = s.pixel_norm.subspan(0, px - 1U); break;
            case 6: s.hit_count = s.hit_count.subspan(0, v.hits.size() - 1U); break;
            case 7: s.full_hits = s.full_hits.subspan(0, v.full_hits.size() - 1U); break;
            case 8: s.pixel_walked = s.pixel_walked.subspan(0, px - 1U); break;
            case 9: s.crossed_voxels = s.crossed_voxels.subspan(0, v.crossed.size() - 1U); break;
            default: s.sensor_opinion = s.sensor_opinion.subspan(0, v.opinions.size() - 1U); break;
        }
        CHECK(RayTable::build(g, r, s).error() == ErrorCode::kStorageTooSmall);
    }
    SensorReading points = r;
    points.kind = SensorDataKind::kPointSet;
    CHECK(count_ray_steps(g, points).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-FUSE-006, SR-FUSE-003
TEST_CASE("ray table: invalid depth values are skipped and counted like on-the-fly fusion") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorModelTable model;
    SensorReading r = frame.readings[0];
    std::vector<float> depth(r.depth.begin(), r.depth.end());
    depth[0] = std::numeric_limits<float>::quiet_NaN();
    depth[1] = std::numeric_limits<float>::infinity();
    depth[2] = 0.0F;
    depth[3] = -1.0F;
    depth[4] = 50.0F;  // beyond max_range
    r.depth = Span<const float>(depth.data(), depth.size());
    const OwnedTable t = make_table(g, r);
    OwnedGrid a(g);
    OwnedGrid b(g);
    const FusionStats st = t.table.fuse(a.grid, r.depth, model).value();
    const FusionStats sd = fuse_sensor(b.grid, r, model, b.fusion_scratch()).value();
    CHECK(st.skipped_nan == 1U);
    CHECK(st.skipped_infinite == 1U);
    CHECK(st.skipped_zero == sd.skipped_zero);
    CHECK(st.skipped_behind == 1U);
    CHECK(st.skipped_out_of_range == 1U);
    CHECK(st.skipped() == sd.skipped());
}

// verifies: SR-FUSE-007
TEST_CASE("ray table: a bit flipped in any part of its constant RAM is found within one check pass") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorReading& r = frame.readings[1];
    test::RayTableVectors v(g, r);
    const std::size_t n = v.entries;
    const std::size_t px = v.pixels;
    const RayTableStorage storage = v.storage();
    const RayTable table = RayTable::build(g, r, storage).value();
    std::size_t crossed_count = 0U;
    for (const std::uint32_t h : v.full_hits) {
        crossed_count += h != 0U ? 1U : 0U;
    }
    // What a pass reads: the limits and the reading placement (57 words), both entry arrays, the four
    // per-pixel arrays, full_hits and the crossed voxels.
    const RayTableSignatureRegions regions = table.signature_regions();
    const Span<const SignatureRegion> list(regions.data(), regions.size());
    CHECK(table.checked_bytes() ==
          57U * 4U + 4U * n + 4U * (px + 1U) + 12U * px + 4U * g.voxel_count() + 4U * crossed_count);
    CHECK(regions[0].size() == 57U * 4U);
    CHECK(regions[1].data() ==
          reinterpret_cast<const std::uint8_t*>(v.voxels.data()));  // NOLINT: the byte view of the entries
    // build()'s CRC is the CRC of the regions read in order.
    CHECK(SignatureCheck(list).reference() == table.storage_crc());
    CHECK(table.limits_intact());
    constexpr std::size_t kSlice = 65536U;
    SignatureCheck check(list, table.storage_crc());
    CHECK(check.total_bytes() == table.checked_bytes());
    const std::size_t calls_per_pass = check.steps_per_pass(kSlice);
    CHECK(calls_per_pass == (table.checked_bytes() + kSlice - 1U) / kSlice);

    // Runs check steps until a pass ends; returns its verdict and how many calls it took.
    const auto run_pass = [&](SignatureCheck& c) {
        std::size_t calls = 0U;
        bool failed = false;
        do {
            failed = c.step(kSlice);
            ++calls;
        } while (!failed && c.position() != 0U && calls <= 2U * calls_per_pass);
        return std::make_pair(!failed, calls);
    };
    for (int pass = 0; pass < 2; ++pass) {
        const auto [intact, calls] = run_pass(check);
        CHECK(intact);
        CHECK(calls == calls_per_pass);
    }
    // Working memory is not checked: fuse() writes it.
    v.walked[7] ^= 1U;
    v.hits[7] ^= 1U;
    v.opinions[7] ^= 1;
    CHECK(run_pass(check).first);

    std::uint8_t* const parts[] = {reinterpret_cast<std::uint8_t*>(v.voxels.data()),  // NOLINT: bit flips for the test
                                   reinterpret_cast<std::uint8_t*>(v.steps.data()),   // NOLINT
                                   reinterpret_cast<std::uint8_t*>(v.begin.data()),   // NOLINT
                                   reinterpret_cast<std::uint8_t*>(v.enter.data()),   // NOLINT
                                   reinterpret_cast<std::uint8_t*>(v.exit.data()),    // NOLINT
                                   reinterpret_cast<std::uint8_t*>(v.norm.data()),    // NOLINT
                                   reinterpret_cast<std::uint8_t*>(v.full_hits.data()),  // NOLINT
                                   reinterpret_cast<std::uint8_t*>(v.crossed.data())};   // NOLINT
    for (std::size_t p = 0U; p < std::size(parts); ++p) {
        CAPTURE(p);
        // Mid-pass: the flip lands in a part the pass has not read yet or has.
        SignatureCheck mid(list, table.storage_crc());
        (void)mid.step(kSlice);
        parts[p][3] ^= 0x10U;
        // The pass under way may end intact (it read the byte before the
        // flip); the next must not.
        std::size_t calls = 1U;
        while (!mid.step(kSlice) && calls <= 2U * calls_per_pass + 1U) {
            ++calls;
        }
        CHECK(mid.failed());
        CHECK(calls <= 2U * calls_per_pass);
        parts[p][3] ^= 0x10U;
        // Latched; a new check over the repaired table passes a whole pass.
        CHECK(mid.step(kSlice));
        SignatureCheck fresh(list, table.storage_crc());
        CHECK(run_pass(fresh).first);
    }

    // The limits' words are a region of the table object itself: a flip
    // there is found by the signature, and limits_intact() sees that they
    // no longer match the limits fuse() uses.
    RayTable copy = table;
    const RayTableSignatureRegions copy_regions = copy.signature_regions();
    CHECK(copy_regions[0].data() != regions[0].data());  // a copy's regions view the copy's words
    for (std::size_t k = 1U; k < copy_regions.size(); ++k)
        CHECK(copy_regions[k].data() == regions[k].data());
    SignatureCheck of_copy(Span<const SignatureRegion>(copy_regions.data(), copy_regions.size()), copy.storage_crc());
    std::uint8_t* const words = const_cast<std::uint8_t*>(copy_regions[0].data());  // NOLINT: bit flip for the test
    words[5] ^= 0x02U;
    CHECK_FALSE(copy.limits_intact());
    CHECK_FALSE(run_pass(of_copy).first);
    words[5] ^= 0x02U;
    CHECK(copy.limits_intact());
    // Likewise the reading placement's words (from word 19: fx, fy, cx, cy,
    // 1/fx, 1/fy, width, height, the pose), which fuse() reads near a face.
    for (const std::size_t byte : {19U * 4U + 3U, 31U * 4U, 33U * 4U + 7U, 56U * 4U + 2U}) {
        CAPTURE(byte);
        words[byte] ^= 0x10U;
        CHECK_FALSE(copy.limits_intact());
        words[byte] ^= 0x10U;
        CHECK(copy.limits_intact());
    }

    // An empty table has no regions and nothing to fail.
    const RayTable empty;
    CHECK(empty.checked_bytes() == 0U);
    CHECK(empty.limits_intact());
    const RayTableSignatureRegions none = empty.signature_regions();
    SignatureCheck empty_check(Span<const SignatureRegion>(none.data(), none.size()), empty.storage_crc());
    CHECK_FALSE(empty_check.step(kSlice));
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: the compact exit step is the smallest power of two that reaches the grid's far corner") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorReading& r = frame.readings[0];
    double farthest = 0.0;
    for (const double x : {g.origin().x(), g.max_corner().x()}) {
        for (const double y : {g.origin().y(), g.max_corner().y()}) {
            for (const double z : {g.origin().z(), g.max_corner().z()}) {
                farthest = std::max(farthest, (Eigen::Vector3d(x, y, z) - r.pose.translation()).norm());
            }
        }
    }
    const double reach = std::min(farthest, static_cast<double>(r.max_range));
    const auto step = static_cast<double>(compact_exit_step(g, r));
    int exponent = 0;
    CHECK(std::frexp(step, &exponent) == 0.5);  // a power of two
    CHECK(65535.0 * step >= reach);
    CHECK(65535.0 * step / 2.0 < reach * 1.0001);  // and the smallest such
    CHECK(ray_table_is_compact(g, r));

    // 90 m away with a 100 m range the step (2^-9 m) is coarser than
    // 1/256 of a 5 cm voxel: the table is wide.
    SensorReading distant = r;
    distant.max_range = kMaxSensorRange;
    distant.pose.translation() += Eigen::Vector3d(0.0, 0.0, 90.0);
    CHECK(static_cast<double>(compact_exit_step(g, distant)) == std::ldexp(1.0, -9));
    CHECK_FALSE(ray_table_is_compact(g, distant));
    // A range shorter than the far corner: the step reaches max_range instead.
    SensorReading short_range = r;
    short_range.max_range = 0.5F;
    REQUIRE(farthest > 0.5);
    const auto short_step = static_cast<double>(compact_exit_step(g, short_range));
    CHECK(std::frexp(short_step, &exponent) == 0.5);
    CHECK(65535.0 * short_step >= 0.5);
    CHECK(65535.0 * short_step / 2.0 < 0.5 * 1.0001);
    CHECK(short_step < step);
    // An invalid sensor has no step.
    SensorReading invalid = r;
    invalid.max_range = -1.0F;
    CHECK(compact_exit_step(g, invalid) == 0.0F);
    CHECK_FALSE(ray_table_is_compact(g, invalid));
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: an entry beyond the table or not of the pixel asked for is a contract violation") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const OwnedTable t = make_table(g, frame.readings[0]);
    const RayTable& table = t.table;
    REQUIRE(table.step_count() > 0U);
    std::size_t pixel = 1U;  // a pixel after the first with at least one entry
    while (pixel + 1U < table.pixel_count() &&
           (table.pixel_begin(pixel) == 0U || table.pixel_begin(pixel + 1U) == table.pixel_begin(pixel))) {
        ++pixel;
    }
    REQUIRE(pixel + 1U < table.pixel_count());
    const std::uint32_t first = table.pixel_begin(pixel);
    const std::uint32_t end = table.pixel_begin(pixel + 1U);
    CHECK_FALSE(test::violates_contract([&] { (void)table.entry_voxel(table.step_count() - 1U); }));
    CHECK(test::violates_contract([&] { (void)table.entry_voxel(table.step_count()); }));
    CHECK_FALSE(test::violates_contract([&] { (void)table.entry_exit(pixel, first); }));
    CHECK_FALSE(test::violates_contract([&] { (void)table.entry_exit(pixel, end - 1U); }));
    CHECK(test::violates_contract([&] { (void)table.entry_exit(pixel, first - 1U); }));
    CHECK(test::violates_contract([&] { (void)table.entry_exit(pixel, end); }));
    CHECK(test::violates_contract([&] { (void)table.entry_exit(table.pixel_count(), 0U); }));
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: readings nearer than the ramp to a sensor inside the grid give the exact opinions") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry paper = paper_grid_geometry();
    const GridGeometry fine =
        GridGeometry::make(paper.origin(), paper.voxel_size() / 2.0, GridDims{68, 60, 60}).value();
    const SensorModelTable model;
    const auto ramp = static_cast<float>(model.ramp_length());
    SensorReading sensor = frame.readings[0];
    sensor.pose.translation() = Eigen::Vector3d(0.01, 0.02, 0.73);  // inside the grid, off every face
    sensor.min_range = 0.01F;
    REQUIRE(paper.contains(paper.world_to_voxel_unchecked(sensor.pose.translation())));
    REQUIRE(ray_table_is_compact(paper, sensor));
    REQUIRE_FALSE(ray_table_is_compact(fine, sensor));
    for (const GridGeometry& g : {paper, fine}) {
        CAPTURE(g.voxel_count());
        host::OwnedRayTable t;
        REQUIRE(t.build(g, sensor).ok());
        const std::size_t px = sensor.depth.size();
        // Every reading half a ramp from the sensor (the constant part is
        // empty), and readings spread over the first two ramps.
        std::vector<std::vector<float>> cases;
        cases.push_back(depths_at(t, px, [&](std::size_t) { return 0.5F * ramp; }));
        cases.push_back(
            depths_at(t, px, [&](std::size_t i) { return 0.02F + 2.0F * ramp * static_cast<float>(i % 89U) / 89.0F; }));
        for (std::size_t c = 0; c < cases.size(); ++c) {
            CAPTURE(c);
            SensorReading r = sensor;
            r.depth = Span<const float>(cases[c].data(), cases[c].size());
            OwnedGrid fused(g);
            const FusionStats st = t.table().fuse(fused.grid, r.depth, model).value();
            CHECK(st.rays_fused == px);
            CHECK(st.readings_in_grid == px);
            CHECK(differs_from_exact(fused, walk_per_ray(t, r, model, g), model) == 0U);
        }
    }
}

// verifies: SR-FUSE-006, SR-FUSE-004
TEST_CASE("ray table: a sensor that fails validation or is a point set is refused by build") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = paper_grid_geometry();
    const SensorReading& r = frame.readings[0];
    test::RayTableVectors v(g, r);
    SensorReading invalid = r;
    invalid.max_range = -1.0F;
    CHECK(RayTable::build(g, invalid, v.storage()).error() == ErrorCode::kInvalidArgument);
    CHECK(count_ray_steps(g, invalid).error() == ErrorCode::kInvalidArgument);
    SensorReading points = r;
    points.kind = SensorDataKind::kPointSet;
    CHECK(RayTable::build(g, points, v.storage()).error() == ErrorCode::kInvalidArgument);
    CHECK(RayTable::build(g, r, v.storage()).ok());
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: a wide table holds as many entries as its shorter entry span, and fuses like the per-ray walk") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry paper = paper_grid_geometry();
    const GridGeometry g = GridGeometry::make(paper.origin(), paper.voxel_size() / 2.0, GridDims{68, 60, 60}).value();
    const SensorReading& r = frame.readings[0];
    REQUIRE_FALSE(ray_table_is_compact(g, r));
    const std::size_t n = count_ray_steps(g, r).value();
    const std::size_t px = r.depth.size();
    const std::size_t nv = g.voxel_count();
    std::vector<std::uint32_t> voxels(n + 5U);
    std::vector<float> exits(n + 1U);
    std::vector<std::uint32_t> begin(px + 1U), full_hits(nv), crossed(nv), walked(px), hits(nv);
    std::vector<std::int16_t> opinions(nv);
    std::vector<float> enter(px), exit(px), norm(px);
    const auto storage = [&](std::size_t voxel_count, std::size_t exit_count) {
        return RayTableStorage{{},
                               {},
                               {voxels.data(), voxel_count},
                               {exits.data(), exit_count},
                               {begin.data(), begin.size()},
                               {enter.data(), enter.size()},
                               {exit.data(), exit.size()},
                               {norm.data(), norm.size()},
                               {full_hits.data(), full_hits.size()},
                               {crossed.data(), crossed.size()},
                               {walked.data(), walked.size()},
                               {hits.data(), hits.size()},
                               {opinions.data(), opinions.size()}};
    };
    // One span short of the entries, the other longer: too small either way.
    CHECK(RayTable::build(g, r, storage(n + 5U, n - 1U)).error() == ErrorCode::kStorageTooSmall);
    CHECK(RayTable::build(g, r, storage(n - 1U, n + 1U)).error() == ErrorCode::kStorageTooSmall);
    // Spans of different lengths, both long enough: built, and fused as the per-ray walk.
    const Result<RayTable> built = RayTable::build(g, r, storage(n + 5U, n + 1U));
    REQUIRE(built.ok());
    const RayTable& table = built.value();
    CHECK(table.step_count() == n);
    const SensorModelTable model;
    OwnedGrid direct(g);
    OwnedGrid tabled(g);
    const FusionStats a = fuse_sensor(direct.grid, r, model, direct.fusion_scratch()).value();
    const FusionStats b = table.fuse(tabled.grid, r.depth, model).value();
    CHECK(a.rays_fused == b.rays_fused);
    CHECK(tabled.grid.observed_count() == direct.grid.observed_count());
}

// verifies: SR-FUSE-006
TEST_CASE("ray table: a reading beyond the last exit step of a compact table still gives the exact opinions") {
    // A 0.4 m cube seen along its diagonal from 0.9998 m off its far corner: the
    // compact step is 2^-16 m (65535 steps reach 0.99998 m), and readings at
    // 0.99999 m lie beyond the last step but within a ramp of where the
    // central rays leave the grid.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.05, GridDims{8, 8, 8}).value();
    const double offset = 0.9998 / std::sqrt(3.0) - 0.4;
    const Eigen::Vector3d axis = Eigen::Vector3d::Ones().normalized();
    const Eigen::Vector3d right = Eigen::Vector3d(1.0, -1.0, 0.0).normalized();
    SensorReading sensor;
    sensor.kind = SensorDataKind::kDepthImage;
    sensor.pose.linear().col(0) = right;
    sensor.pose.linear().col(1) = axis.cross(right);
    sensor.pose.linear().col(2) = axis;
    sensor.pose.translation() = Eigen::Vector3d::Constant(-offset);
    sensor.intrinsics = PinholeIntrinsics{20.0, 20.0, 4.0, 4.0, 9, 9};
    sensor.min_range = 0.1F;
    sensor.max_range = 5.0F;
    std::vector<float> placeholder(81U, 1.0F);
    sensor.depth = {placeholder.data(), placeholder.size()};
    REQUIRE(validate_sensor_reading(sensor).ok());
    REQUIRE(ray_table_is_compact(g, sensor));
    REQUIRE(compact_exit_step(g, sensor) == std::ldexp(1.0F, -16));
    host::OwnedRayTable t;
    REQUIRE(t.build(g, sensor).ok());
    const SensorModelTable model;
    const std::vector<float> depth = depths_at(t, 81U, [](std::size_t) { return 0.99999F; });
    SensorReading r = sensor;
    r.depth = {depth.data(), depth.size()};
    OwnedGrid fused(g);
    const FusionStats st = t.table().fuse(fused.grid, r.depth, model).value();
    CHECK(st.rays_fused == 81U);
    CHECK(st.readings_in_grid == 0U);
    CHECK(fused.grid.observed_count() > 0U);
    CHECK(differs_from_exact(fused, walk_per_ray(t, r, model, g), model) == 0U);
}
