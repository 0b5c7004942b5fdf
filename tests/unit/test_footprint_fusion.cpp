// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Footprint fusion (footprint_fusion.hpp) against the exact per-ray path
// (fuse_sensor): the same hits, free values only where a ray passes and never
// stronger than the exact ones, and the stated differences counted.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/owned_footprint.hpp"
#include "cellguard/host/sim/workcell.hpp"

using namespace cellguard;

namespace {

/// One footprint workspace for an image of @p w x @p h over @p g (host-owned storage).
struct OwnedWorkspace {
    host::OwnedFootprintWorkspaces owned;
    FootprintWorkspace ws;
    OwnedWorkspace(const GridGeometry& g, std::int32_t w, std::int32_t h) : owned(g, 1U, w, h), ws(owned.spans()[0]) {}
    /// The sensor's opinions, as footprint_opinions wrote them.
    [[nodiscard]] Span<const std::int16_t> opinions() const { return ws.opinions; }
};

struct OwnedGrid {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid;
    explicit OwnedGrid(const GridGeometry& g) : lo(g.voxel_count()), ob(g.voxel_count()) {
        grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        grid.clear();
    }
};

/// One sensor's exact opinions: fuse_sensor's scratch after the call.
std::vector<std::int16_t> exact_opinions(const GridGeometry& g, const SensorReading& r, const SensorModelTable& m) {
    OwnedGrid grid(g);
    std::vector<std::int16_t> scratch(g.voxel_count());
    REQUIRE(fuse_sensor(grid.grid, r, m, {scratch.data(), scratch.size()}).ok());
    return scratch;
}

/// How footprint opinions compare with exact ones, voxel by voxel.
struct Comparison {
    std::size_t hits_lost = 0;        ///< exact hit, footprint not
    std::size_t hits_added = 0;       ///< footprint hit, exact not
    std::size_t free_unobserved = 0;  ///< footprint free where exact has no opinion
    std::size_t free_stronger = 0;    ///< footprint free stronger than exact free
    std::size_t free_weaker = 0;      ///< footprint free weaker than exact (allowed)
    std::size_t lost_free = 0;        ///< exact free, footprint none (allowed: safe side)
    std::size_t same = 0;
};

Comparison compare(const std::vector<std::int16_t>& exact, Span<const std::int16_t> fp, const SensorModelTable& m) {
    Comparison c;
    const std::int16_t hit = m.reading_evidence();
    for (std::size_t i = 0; i < exact.size(); ++i) {
        const std::int16_t e = exact[i];
        const std::int16_t f = fp[i];
        if (e == f) {
            ++c.same;
        } else if (e == hit) {
            ++c.hits_lost;
        } else if (f == hit) {
            ++c.hits_added;
        } else if (f == kNoOpinion) {
            ++c.lost_free;
        } else if (e == kNoOpinion) {
            ++c.free_unobserved;
        } else if (f < e) {
            ++c.free_stronger;
        } else {
            ++c.free_weaker;
        }
    }
    return c;
}

/// The hit pass's kernels, the reference first (those this CPU lacks resolve to the next).
constexpr std::array<FusionKernel, 2> kFusionKernels{FusionKernel::kScalar, FusionKernel::kAvx2};

GridGeometry lowered_paper_grid() {
    // The paper's grid lowered by half a voxel, so the simulated floor does not lie on a face.
    return GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, -0.025), 0.05, GridDims{34, 30, 30}).value();
}

}  // namespace

// verifies: SR-FUSE-009, SR-FUSE-010
TEST_CASE("footprint fusion: the paper's simulated sensors give the exact hits and safe-side free values") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    // The paper's own grid puts the floor on voxel faces (the hit pass's exact fallback); the lowered one does not.
    // Without the exact step (the default) and with it for footprints of up to 64 pixels.
    for (const std::uint32_t limit : {0U, 64U}) {
        CAPTURE(limit);
        FootprintParams params;
        params.exact_footprint_max = limit;
        for (const GridGeometry& g : {lowered_paper_grid(), paper_grid_geometry()}) {
            const SensorModelTable model;
            for (const SensorReading& r : frame.readings) {
                OwnedWorkspace w(g, r.intrinsics.width, r.intrinsics.height);
                FootprintStats fs;
                const Result<FusionStats> s = footprint_opinions(g, r, model, w.ws, &fs, params);
                REQUIRE(s.ok());
                const std::vector<std::int16_t> exact = exact_opinions(g, r, model);
                const Comparison c = compare(exact, w.opinions(), model);
                MESSAGE("same " << c.same << ", lost free " << c.lost_free << ", weaker " << c.free_weaker
                                << ", stronger " << c.free_stronger << ", free where unobserved " << c.free_unobserved
                                << ", hits lost " << c.hits_lost << "/added " << c.hits_added << "; in view "
                                << fs.voxels_visited << ", filled " << fs.voxels_filled << ", safe side "
                                << fs.voxels_safe_side);
                CHECK(c.hits_lost == 0U);
                CHECK(c.hits_added == 0U);
                // Float rounding where a ray grazes an edge: bounded, not zero.
                CHECK(c.free_stronger <= g.voxel_count() / 1000U);
                CHECK(c.free_unobserved <= g.voxel_count() / 1000U);
                CHECK((limit == 0U || fs.voxels_exact > 0U));
            }
        }
    }
}

// verifies: SR-FUSE-009, SR-FUSE-010
TEST_CASE("footprint fusion: random depths keep every hit and call nothing free that no ray passes") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = lowered_paper_grid();
    const SensorModelTable model;
    std::mt19937 rng(7U);
    std::uniform_real_distribution<float> depth(0.3F, 4.0F);
    for (const SensorReading& base : frame.readings) {
        std::vector<float> d(base.depth.size());
        for (float& x : d) {
            x = depth(rng);
        }
        SensorReading r = base;
        r.depth = {d.data(), d.size()};
        for (const std::uint32_t limit : {0U, 64U}) {
            CAPTURE(limit);
            FootprintParams params;
            params.exact_footprint_max = limit;
            OwnedWorkspace w(g, r.intrinsics.width, r.intrinsics.height);
            FootprintStats fs;
            REQUIRE(footprint_opinions(g, r, model, w.ws, &fs, params).ok());
            const std::vector<std::int16_t> exact = exact_opinions(g, r, model);
            const Comparison c = compare(exact, w.opinions(), model);
            MESSAGE("random: same " << c.same << ", lost free " << c.lost_free << ", weaker " << c.free_weaker
                                    << ", stronger " << c.free_stronger << ", unobserved->free " << c.free_unobserved
                                    << ", safe side " << fs.voxels_safe_side << ", in view " << fs.voxels_visited);
            CHECK(c.hits_lost == 0U);
            CHECK(c.hits_added == 0U);
            CHECK(c.free_stronger <= g.voxel_count() / 1000U);
            CHECK(c.free_unobserved <= g.voxel_count() / 1000U);
            CHECK(fs.work_units() <= footprint_work_bound(g, r, params));
            CHECK((limit != 0U || fs.work_units() == footprint_work_bound(g, r, params)));
        }
    }
}

// verifies: SR-FUSE-011, SR-FUSE-012
TEST_CASE("footprint fusion: a frame allocates nothing and pools like fuse_frame on the same opinions") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = lowered_paper_grid();
    const SensorModelTable model;
    const SensorReading& r0 = frame.readings.front();
    // Room for every sensor's image in each workspace.
    const host::OwnedFootprintWorkspaces owned(g, frame.readings.size(), r0.intrinsics.width * 2,
                                               r0.intrinsics.height * 2);
    const Span<const FootprintWorkspace> ws = owned.spans();
    OwnedGrid parallel(g);
    OwnedGrid sequential(g);
    SequentialRunner runner;
    const Span<const SensorReading> sensors(frame.readings.data(), frame.readings.size());
    const std::uint64_t before = test::allocation_count();
    const auto a = fuse_frame_footprint(parallel.grid, sensors, model, ws, runner);
    const auto b = fuse_frame_footprint(sequential.grid, sensors, model, ws.subspan(0U, 1U), runner);
    CHECK(test::allocation_count() == before);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a.value().rays_fused == b.value().rays_fused);
    CHECK(parallel.lo == sequential.lo);
    CHECK(parallel.ob == sequential.ob);
}

// verifies: SR-FUSE-011
TEST_CASE("footprint fusion: bad input is refused and leaves the grid untouched") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = lowered_paper_grid();
    const SensorModelTable model;
    const SensorReading& r = frame.readings.front();
    OwnedWorkspace w(g, r.intrinsics.width, r.intrinsics.height);
    OwnedGrid grid(g);
    SequentialRunner runner;
    SUBCASE("a point set") {
        SensorReading p;
        p.kind = SensorDataKind::kPointSet;
        const Result<FusionStats> s = fuse_frame_footprint(grid.grid, {&p, 1U}, model, {&w.ws, 1U}, runner);
        CHECK(s.error() == ErrorCode::kInvalidArgument);
    }
    SUBCASE("a short pyramid") {
        FootprintWorkspace shorter = w.ws;
        shorter.pyramid_max = shorter.pyramid_max.subspan(0U, 10U);
        CHECK(fuse_frame_footprint(grid.grid, {&r, 1U}, model, {&shorter, 1U}, runner).error() ==
              ErrorCode::kStorageTooSmall);
    }
    SUBCASE("no workspace") {
        CHECK(fuse_frame_footprint(grid.grid, {&r, 1U}, model, {}, runner).error() == ErrorCode::kStorageTooSmall);
    }
    CHECK(grid.grid.observed_count() == 0U);
}

// verifies: SR-FUSE-011
TEST_CASE("footprint fusion: each short span, a bad reading and too many sensors are refused before any evidence") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = lowered_paper_grid();
    const SensorModelTable model;
    const SensorReading& r = frame.readings.front();
    OwnedWorkspace w(g, r.intrinsics.width, r.intrinsics.height);
    OwnedGrid grid(g);
    SequentialRunner runner;
    SensorReading bad = r;
    bad.intrinsics.width = 0;  // fails validate_sensor_reading
    SensorReading points;
    points.kind = SensorDataKind::kPointSet;
    // One sensor's opinions.
    CHECK(footprint_opinions(g, bad, model, w.ws, nullptr).error() != ErrorCode::kOk);
    CHECK(footprint_opinions(g, points, model, w.ws, nullptr).error() == ErrorCode::kInvalidArgument);
    FootprintWorkspace shorter = w.ws;
    shorter.opinions = shorter.opinions.subspan(0U, g.voxel_count() - 1U);
    CHECK(footprint_opinions(g, r, model, shorter, nullptr).error() == ErrorCode::kStorageTooSmall);
    shorter = w.ws;
    shorter.pyramid_invalid = shorter.pyramid_invalid.subspan(0U, 10U);
    CHECK(footprint_opinions(g, r, model, shorter, nullptr).error() == ErrorCode::kStorageTooSmall);
    // The frame.
    CHECK(fuse_frame_footprint(grid.grid, {&bad, 1U}, model, {&w.ws, 1U}, runner).error() != ErrorCode::kOk);
    shorter = w.ws;
    shorter.opinions = shorter.opinions.subspan(0U, g.voxel_count() - 1U);
    CHECK(fuse_frame_footprint(grid.grid, {&r, 1U}, model, {&shorter, 1U}, runner).error() ==
          ErrorCode::kStorageTooSmall);
    shorter = w.ws;
    shorter.pyramid_min = shorter.pyramid_min.subspan(0U, 10U);
    CHECK(fuse_frame_footprint(grid.grid, {&r, 1U}, model, {&shorter, 1U}, runner).error() ==
          ErrorCode::kStorageTooSmall);
    shorter = w.ws;
    shorter.pyramid_invalid = shorter.pyramid_invalid.subspan(0U, 10U);
    CHECK(fuse_frame_footprint(grid.grid, {&r, 1U}, model, {&shorter, 1U}, runner).error() ==
          ErrorCode::kStorageTooSmall);
    std::vector<SensorReading> many(kMaxSensors + 1U, r);
    CHECK(fuse_frame_footprint(grid.grid, {many.data(), many.size()}, model, {&w.ws, 1U}, runner).error() ==
          ErrorCode::kCapacityExceeded);
    CHECK(grid.grid.observed_count() == 0U);
}

// verifies: SR-FUSE-011
TEST_CASE(
    "footprint fusion: without the exact step its work is the bound from the geometry alone, whatever the "
    "cameras see, with it at most the bound") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = lowered_paper_grid();
    const SensorModelTable model;
    std::mt19937 rng(11U);
    FootprintParams fixed;
    fixed.exact_footprint_max = 0U;
    FootprintParams exact;
    exact.exact_footprint_max = 64U;
    for (const SensorReading& base : frame.readings) {
        const std::uint64_t bound = footprint_work_bound(g, base, fixed);
        CHECK(footprint_work_bound(g, base, exact) > bound);  // the exact step's most ray tests
        CHECK(footprint_work_bound(g, base) == bound);        // the default: no exact step
        const auto pixels = static_cast<std::uint64_t>(base.intrinsics.width) *
                            static_cast<std::uint64_t>(base.intrinsics.height);
        CHECK(bound > 2U * pixels);                     // some voxels in view
        CHECK(bound <= 2U * pixels + g.voxel_count());  // never more than the grid
        // The paper's readings, random depths, no reading at all, every reading at 1 mm: the same work.
        std::vector<float> d(base.depth.size());
        for (int pattern = 0; pattern < 4; ++pattern) {
            std::uniform_real_distribution<float> any(0.3F, 4.0F);
            for (std::size_t i = 0; i < d.size(); ++i) {
                d[i] = pattern == 0   ? base.depth[i]
                       : pattern == 1 ? any(rng)
                       : pattern == 2 ? std::numeric_limits<float>::quiet_NaN()
                                      : 0.001F;
            }
            SensorReading r = base;
            r.depth = {d.data(), d.size()};
            OwnedWorkspace w(g, r.intrinsics.width, r.intrinsics.height);
            FootprintStats fs;
            REQUIRE(footprint_opinions(g, r, model, w.ws, &fs, fixed).ok());
            CAPTURE(pattern);
            CHECK(fs.pixels == pixels);
            CHECK(fs.pixel_tests == 0U);
            CHECK(fs.work_units() == bound);
            FootprintStats with_exact;
            REQUIRE(footprint_opinions(g, r, model, w.ws, &with_exact, exact).ok());
            CHECK(with_exact.work_units() <= footprint_work_bound(g, r, exact));
        }
    }
    // A camera that looks away from the grid has no voxel in view; a point set and an empty grid no work.
    SensorReading away = frame.readings[0];
    away.pose = Eigen::Isometry3d::Identity();  // above the grid, looking up (+z)
    away.pose.translation() = Eigen::Vector3d(0.0, 0.0, 5.0);
    CHECK(footprint_work_bound(g, away) ==
          2U * static_cast<std::uint64_t>(away.intrinsics.width) * static_cast<std::uint64_t>(away.intrinsics.height));
    SensorReading points = frame.readings[0];
    points.kind = SensorDataKind::kPointSet;
    CHECK(footprint_work_bound(g, points) == 0U);
    CHECK(footprint_work_bound(GridGeometry{}, frame.readings[0]) == 0U);
}

// verifies: SR-FUSE-009
TEST_CASE("footprint fusion: the statistics are optional, the opinions the same without them") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const GridGeometry g = lowered_paper_grid();
    const SensorModelTable model;
    const SensorReading& r = frame.readings[0];
    OwnedWorkspace with(g, r.intrinsics.width, r.intrinsics.height);
    OwnedWorkspace without(g, r.intrinsics.width, r.intrinsics.height);
    FootprintStats fs;
    const Result<FusionStats> a = footprint_opinions(g, r, model, with.ws, &fs);
    const Result<FusionStats> b = footprint_opinions(g, r, model, without.ws, nullptr);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(fs.voxels_visited > 0U);
    CHECK(a.value().rays_fused == b.value().rays_fused);
    CHECK(std::equal(with.opinions().begin(), with.opinions().end(), without.opinions().begin()));
}

namespace {

/// A 16 x 16 camera of wide pixels (0.18 rad: each is wider than a 5 cm voxel
/// beyond 0.3 m) looking up the z axis of a grid 8 x 8 x 32 voxels tall,
/// principal point on pixel (8, 8), whose ray is parallel to the x and y faces.
struct CoarseCamera {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d::Zero(), 0.05, GridDims{8, 8, 32}).value();
    std::vector<float> depth = std::vector<float>(256U);
    SensorReading r;
    CoarseCamera() {
        r.kind = SensorDataKind::kDepthImage;
        r.intrinsics = PinholeIntrinsics{8.0, 8.0, 8.0, 8.0, 16, 16};
        r.pose.translation() = Eigen::Vector3d(0.21, 0.19, -0.4);
        r.min_range = 0.3F;
        r.max_range = 3.0F;
        for (std::size_t i = 0; i < depth.size(); ++i) {
            depth[i] = 0.9F + 0.05F * static_cast<float>(i % 7U);
        }
        r.depth = {depth.data(), depth.size()};
    }
};

}  // namespace

// verifies: SR-FUSE-009, SR-FUSE-010, SR-FUSE-003
TEST_CASE("footprint fusion: wide pixels over a tall grid give the exact hits and skip readings as fuse_sensor does") {
    // The camera inside a voxel column, on its face, and just before the face: the
    // principal ray (parallel to the x and y faces) then lies inside, on or beside a
    // voxel's slab; on an x face, a y face, or both (the line where two faces meet).
    struct Place {
        double x;
        double y;
        bool grazing;  ///< rays through voxel edges off the face may round to a free opinion (SR-FUSE-010)
    };
    const std::array<Place, 5> places{{{0.21, 0.19, false},
                                       {0.2, 0.19, false},
                                       {0.2 - 1e-9, 0.19, false},
                                       {0.2, 0.2, false},
                                       // 0.15 / 0.05 rounds below 3: from there rays pass exactly
                                       // through the edges of three voxels away from the face
                                       {0.21, 0.15, true}}};
    for (const Place& place : places) {
        const double x = place.x;
        const double y = place.y;
        CAPTURE(x);
        CAPTURE(y);
        CoarseCamera cam;
        cam.r.pose.translation().x() = x;
        cam.r.pose.translation().y() = y;
        const auto face_column = [&cam](double p, std::int32_t c) {  // c is a column beside a face p lies on
            const double f = p / cam.g.voxel_size();
            const double nearest = std::round(f);
            return std::abs(f - nearest) < 1e-9 &&
                   (c == static_cast<std::int32_t>(nearest) || c == static_cast<std::int32_t>(nearest) - 1);
        };
        const float ahead = 1.0F;                              // pixel (8, 8): range = depth
        const float right = std::sqrt(1.0F + 1.0F / 64.0F);    // pixel (9, 8): range = depth x right
        cam.depth[0] = 150.0F;                                 // beyond kMaxSensorRange
        cam.depth[1] = 0.1F;                                   // nearer than min_range
        cam.depth[2] = 5.0F;                                   // beyond max_range
        cam.depth[3] = -1.0F;                                  // behind
        cam.depth[136] = cam.r.min_range * ahead;              // exactly at min_range: valid
        cam.depth[137] = cam.r.max_range / right * 1.000002F;  // just beyond max_range (within the exact band)
        cam.depth[138] = cam.r.max_range / std::sqrt(1.0F + 4.0F / 64.0F) * 0.999998F;  // just within max_range
        const SensorModelTable model;
        OwnedWorkspace w(cam.g, 16, 16);
        FootprintStats fs;
        FootprintParams params;
        params.exact_footprint_max = 64U;  // the exact step's face-column rule (below)
        const Result<FusionStats> s = footprint_opinions(cam.g, cam.r, model, w.ws, &fs, params);
        REQUIRE(s.ok());
        OwnedGrid direct(cam.g);
        std::vector<std::int16_t> scratch(cam.g.voxel_count());
        const Result<FusionStats> e = fuse_sensor(direct.grid, cam.r, model, {scratch.data(), scratch.size()});
        REQUIRE(e.ok());
        CHECK(s.value().skipped_out_of_range == 4U);
        CHECK(s.value().skipped_behind == 1U);
        CHECK(s.value().skipped_out_of_range == e.value().skipped_out_of_range);
        CHECK(s.value().rays_fused == e.value().rays_fused);
        CHECK(s.value().readings_in_grid == e.value().readings_in_grid);
        const Comparison c = compare(scratch, w.opinions(), model);
        MESSAGE("coarse: same " << c.same << ", lost free " << c.lost_free << ", weaker " << c.free_weaker
                                << ", stronger " << c.free_stronger << ", unobserved->free " << c.free_unobserved
                                << "; in view " << fs.voxels_visited << ", safe side " << fs.voxels_safe_side
                                << ", filled " << fs.voxels_filled);
        CHECK(c.hits_lost == 0U);
        CHECK(c.hits_added == 0U);
        CHECK(c.free_stronger == 0U);
        // With the camera on the face x = 0.2 the rays of pixel column 8 lie in that
        // face: fuse_sensor's half-open rule puts them in voxel column x = 4, and so
        // does the footprint's exact test, which takes a ray parallel to a face in the
        // camera's voxel column (the box test alone, rounded: 0.05 * 3 - 0.2 + 0.05 > 0,
        // let them graze column x = 3 too, giving 54 voxels a free opinion on 2026-11-26).
        std::size_t beside_face = 0U;
        for (std::size_t i = 0; i < scratch.size(); ++i) {
            if (scratch[i] == kNoOpinion && w.opinions()[i] != kNoOpinion) {
                const VoxelCoord q = cam.g.coord_of(i);
                beside_face += (face_column(x, q.x) || face_column(y, q.y)) ? 1U : 0U;
            }
        }
        CHECK(beside_face == 0U);
        CHECK((place.grazing || c.free_unobserved == 0U));
        CHECK(c.free_unobserved <= 3U);
        CHECK(fs.voxels_exact > 0U);
    }
}

// verifies: SR-FUSE-009, SR-FUSE-003
TEST_CASE("footprint fusion: a camera a billion voxels from the grid places its readings the exact way, outside it") {
    for (const double x : {6.0e7, -6.0e7}) {  // 1.2e9 voxels along x, either side
        CAPTURE(x);
        CoarseCamera cam;
        cam.r.pose.translation() = Eigen::Vector3d(x, 0.19, -0.4);
        const SensorModelTable model;
        OwnedWorkspace w(cam.g, 16, 16);
        const Result<FusionStats> s = footprint_opinions(cam.g, cam.r, model, w.ws, nullptr);
        REQUIRE(s.ok());
        OwnedGrid direct(cam.g);
        std::vector<std::int16_t> scratch(cam.g.voxel_count());
        const Result<FusionStats> e = fuse_sensor(direct.grid, cam.r, model, {scratch.data(), scratch.size()});
        REQUIRE(e.ok());
        CHECK(s.value().rays_fused == 256U);
        CHECK(e.value().rays_fused == 256U);
        CHECK(s.value().readings_in_grid == 0U);
        CHECK(e.value().readings_in_grid == 0U);
        CHECK(std::count(w.opinions().begin(), w.opinions().end(), kNoOpinion) ==
              static_cast<std::ptrdiff_t>(cam.g.voxel_count()));
    }
}

// verifies: SR-FUSE-009, SR-FUSE-003
TEST_CASE(
    "footprint fusion: readings on voxel faces, at and away from the grid's first face, land in fuse_sensor's voxels") {
    // A tilted camera over planes z = 0, 0.15 and 0.35 (voxel faces of a 5 cm grid at
    // origin z 0, or at negative voxel coordinates for the grid at origin z 0.2), each
    // reading's depth the ray's intersection rounded to float, and one float either side.
    // Sparse images (one pixel in 7 valid), so that each reading's voxel shows in the hits.
    const std::int32_t w = 64;
    const std::int32_t h = 48;
    SensorReading r;
    r.kind = SensorDataKind::kDepthImage;
    r.intrinsics = PinholeIntrinsics{50.0, 50.0, 31.5, 23.5, w, h};
    r.pose.linear() = (Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) *
                       Eigen::AngleAxisd(3.14159265358979 + 0.3, Eigen::Vector3d::UnitX()))
                          .toRotationMatrix();
    r.pose.translation() = Eigen::Vector3d(0.3, 0.25, 1.6);
    r.min_range = 0.1F;
    r.max_range = 5.0F;
    std::vector<float> plane_depth(static_cast<std::size_t>(w * h));
    std::size_t on_face = 0U;
    for (std::int32_t v = 0; v < h; ++v) {
        for (std::int32_t u = 0; u < w; ++u) {
            const auto i = static_cast<std::size_t>(v * w + u);
            const Eigen::Vector3d dir = r.pose.linear() * Eigen::Vector3d((u - 31.5) / 50.0, (v - 23.5) / 50.0, 1.0);
            const double plane = std::array<double, 3>{0.0, 0.15, 0.35}[i % 3U];
            auto d = static_cast<float>((plane - 1.6) / dir.z());
            d = (i % 5U == 1U) ? std::nextafter(d, 0.0F) : (i % 5U == 2U) ? std::nextafter(d, 9.0F) : d;
            plane_depth[i] = d;
            const Eigen::Vector3d q = reading_in_cell(r.pose,
                                                      depth_pixel_point(r.intrinsics, 1.0 / 50.0, 1.0 / 50.0, u, v, d));
            on_face += std::fabs(q.z() / 0.05 - std::round(q.z() / 0.05)) < 1e-5 ? 1U : 0U;
        }
    }
    CHECK(on_face > 1000U);  // most readings within 1e-5 voxels of a face (float depths)
    const SensorModelTable model;
    for (const double oz : {0.0, 0.2}) {
        const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-0.6, -0.7, oz), 0.05, GridDims{30, 30, 12}).value();
        OwnedWorkspace ws(g, w, h);
        for (std::size_t j = 0; j < 7U * kFusionKernels.size(); ++j) {
            // Each pixel kernel in turn (the vector ones place four readings at a time).
            FootprintParams params;
            params.kernel = kFusionKernels[j / 7U];
            CAPTURE(oz);
            CAPTURE(j);
            std::vector<float> depth(plane_depth.size(), 0.0F);
            for (std::size_t i = j % 7U; i < depth.size(); i += 7U) {
                depth[i] = plane_depth[i];
            }
            r.depth = {depth.data(), depth.size()};
            const Result<FusionStats> s = footprint_opinions(g, r, model, ws.ws, nullptr, params);
            REQUIRE(s.ok());
            const std::vector<std::int16_t> exact = exact_opinions(g, r, model);
            const Comparison c = compare(exact, ws.opinions(), model);
            CHECK(c.hits_lost == 0U);
            CHECK(c.hits_added == 0U);
            CHECK(c.free_stronger == 0U);
            CHECK(s.value().readings_in_grid > 0U);
        }
    }
}

namespace {

/// What one footprint pass leaves behind: the opinions, the whole pyramid (level 0 is
/// the hit pass's), the counts.
struct PassResult {
    std::vector<std::int16_t> opinions;
    std::vector<float> pyramid_min;
    std::vector<float> pyramid_max;
    std::vector<std::uint8_t> pyramid_invalid;
    FusionStats fusion;
    FootprintStats footprint;
};

PassResult run_pass(const GridGeometry& g, const SensorReading& r, FusionKernel kernel) {
    const SensorModelTable model;
    OwnedWorkspace ws(g, r.intrinsics.width, r.intrinsics.height);
    FootprintParams params;
    params.kernel = kernel;
    params.exact_footprint_max = 64U;  // step 3 reads level 0's depths pixel by pixel
    PassResult out;
    const Result<FusionStats> s = footprint_opinions(g, r, model, ws.ws, &out.footprint, params);
    REQUIRE(s.ok());
    out.fusion = s.value();
    out.opinions.assign(ws.ws.opinions.begin(), ws.ws.opinions.end());
    out.pyramid_min.assign(ws.ws.pyramid_min.begin(), ws.ws.pyramid_min.end());
    out.pyramid_max.assign(ws.ws.pyramid_max.begin(), ws.ws.pyramid_max.end());
    out.pyramid_invalid.assign(ws.ws.pyramid_invalid.begin(), ws.ws.pyramid_invalid.end());
    return out;
}

/// Bit patterns equal (NaN and -0 included).
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void check_same_pass(const PassResult& ref, const PassResult& got) {
    CHECK(got.opinions == ref.opinions);
    CHECK(same_bits(got.pyramid_min, ref.pyramid_min));
    CHECK(same_bits(got.pyramid_max, ref.pyramid_max));
    CHECK(got.pyramid_invalid == ref.pyramid_invalid);
    CHECK(got.fusion.rays_fused == ref.fusion.rays_fused);
    CHECK(got.fusion.readings_in_grid == ref.fusion.readings_in_grid);
    CHECK(got.fusion.skipped_nan == ref.fusion.skipped_nan);
    CHECK(got.fusion.skipped_infinite == ref.fusion.skipped_infinite);
    CHECK(got.fusion.skipped_zero == ref.fusion.skipped_zero);
    CHECK(got.fusion.skipped_behind == ref.fusion.skipped_behind);
    CHECK(got.fusion.skipped_out_of_range == ref.fusion.skipped_out_of_range);
    CHECK(got.footprint.voxels_filled == ref.footprint.voxels_filled);
    CHECK(got.footprint.voxels_exact == ref.footprint.voxels_exact);
    CHECK(got.footprint.pixel_tests == ref.footprint.pixel_tests);
}

/// A depth the hit pass must get right: every class of reading, values at the range
/// limits and at kMaxSensorRange (one float either side), and ordinary depths.
float hostile_depth(std::mt19937& rng, float min_range, float max_range, float plane_depth) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const float near_min = min_range / 1.2F;  // the depth whose range is about min_range at the image's edge
    switch (rng() % 16U) {
        case 0: return std::numeric_limits<float>::quiet_NaN();
        case 1: return (rng() % 2U) != 0U ? kInf : -kInf;
        case 2: return (rng() % 2U) != 0U ? 0.0F : -0.0F;
        case 3: return -0.5F;
        case 4: return std::nextafter(min_range, (rng() % 2U) != 0U ? 0.0F : kInf);
        case 5: return std::nextafter(max_range, (rng() % 2U) != 0U ? 0.0F : kInf);
        case 6: return near_min * (1.0F + static_cast<float>(rng() % 200U) * 1e-4F);
        case 7: return std::nextafter(kMaxSensorRange, (rng() % 2U) != 0U ? 0.0F : kInf);
        case 8: return max_range * 1.5F;
        case 9: return 1e-30F;
        case 10: return plane_depth;  // on a voxel face (to float rounding)
        default: return min_range + static_cast<float>(rng() % 100000U) * 1e-5F * (max_range - min_range);
    }
}

}  // namespace

// verifies: SR-FUSE-015, SR-FUSE-009, SR-FUSE-013
TEST_CASE("footprint fusion: every pixel kernel gives the scalar kernel's opinions, pyramid and counts bit for bit") {
    // Frames of hostile readings (every class, the range limits and kMaxSensorRange one float
    // either side, depths on voxel faces), odd and even widths (the vector kernels take four
    // pixels at a time, the rest of a row one at a time), float and uint16 images, a grid the
    // camera sees only in part (hits outside it on every side).
    REQUIRE(resolve_fusion_kernel(FusionKernel::kScalar) == FusionKernel::kScalar);
#if defined(__x86_64__) && defined(__GNUC__)
    // On a CPU with AVX2 (every CI machine so far) the AVX2 kernel is compared here.
    CHECK((resolve_fusion_kernel(FusionKernel::kAvx2) == FusionKernel::kAvx2) == (__builtin_cpu_supports("avx2") != 0));
#endif
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-0.5, -0.4, 0.0), 0.05, GridDims{20, 18, 16}).value();
    std::mt19937 rng(15U);
    std::size_t compared = 0U;
    for (const std::int32_t w : {64, 37, 3}) {
        const std::int32_t h = w == 3 ? 5 : 23;
        SensorReading r;
        r.kind = SensorDataKind::kDepthImage;
        r.intrinsics = PinholeIntrinsics{40.0, 41.0, 0.5 * (w - 1), 11.0, w, h};
        r.pose.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(3.14159265358979 + 0.25, Eigen::Vector3d::UnitX()))
                              .toRotationMatrix();
        r.pose.translation() = Eigen::Vector3d(0.1, 0.05, 1.2);
        r.min_range = 0.3F;
        r.max_range = 2.0F;
        std::vector<float> depth(static_cast<std::size_t>(w * h));
        std::vector<std::uint16_t> raw(depth.size());
        for (int frame = 0; frame < 6; ++frame) {
            for (std::int32_t v = 0; v < h; ++v) {
                for (std::int32_t u = 0; u < w; ++u) {
                    const auto i = static_cast<std::size_t>(v * w + u);
                    const Eigen::Vector3d dir = r.pose.linear() *
                                                Eigen::Vector3d((u - r.intrinsics.cx) / 40.0, (v - 11.0) / 41.0, 1.0);
                    const auto plane = static_cast<float>((0.05 * (rng() % 8U) - 1.2) / dir.z());
                    // Frame 0: every reading valid and ordinary, so whole groups take the vector form.
                    depth[i] = frame == 0 ? 0.5F + 0.001F * static_cast<float>(i % 1000U)
                                          : hostile_depth(rng, r.min_range, r.max_range, plane);
                    raw[i] = static_cast<std::uint16_t>(frame == 0 ? 500U + i % 1000U : rng() % 2500U);
                }
            }
            if (w == 37 && frame % 3 == 0) {
                // The principal point is pixel (18, 11): its range is its depth. Raw 300 (frame 0) and
                // 2000 (frame 3) at 1 mm, offset 0, put it at min_range and max_range exactly: the long way.
                raw[static_cast<std::size_t>(11 * w + 18)] = frame == 0 ? 300U : 2000U;
            }
            for (const bool u16 : {false, true}) {
                CAPTURE(w);
                CAPTURE(frame);
                CAPTURE(u16);
                SensorReading s = r;
                if (u16) {
                    s.kind = SensorDataKind::kDepthImageU16;
                    s.depth_u16 = {raw.data(), raw.size()};
                    s.depth_scale = 0.001F;
                    s.depth_offset = std::array<float, 3>{0.0F, -0.0105F,
                                                          0.45F}[static_cast<std::size_t>(frame % 3)];  // raw 0 is none
                } else {
                    s.depth = {depth.data(), depth.size()};
                }
                const PassResult ref = run_pass(g, s, FusionKernel::kScalar);
                CHECK(ref.fusion.rays_fused > 0U);
                CAPTURE(static_cast<int>(resolve_fusion_kernel(FusionKernel::kAvx2)));
                check_same_pass(ref, run_pass(g, s, FusionKernel::kAvx2));
                ++compared;
            }
        }
    }
    CHECK(compared == 36U);
}
