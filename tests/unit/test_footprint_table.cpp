// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: footprint tables (footprint_fusion.hpp) give the opinions of
// footprint fusion without a table bit for bit, are made from the geometry
// alone, and are made again, or refused, when they do not fit (issue 34).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/base/task_runner.hpp"
#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "paper_cell.hpp"

using namespace cellguard;

namespace {

/// One sensor's workspace over owned storage, with or without a table.
struct Work {
    std::vector<float> mins, maxs;
    std::vector<std::uint8_t> invalid;
    std::vector<std::int16_t> opinions;
    std::vector<FootprintEntry> entries;
    FootprintTable table;
    FootprintWorkspace space;
    Work(const GridGeometry& g, const SensorReading& r, std::size_t table_entries) {
        const std::size_t cells = depth_pyramid_cells(r.intrinsics.width, r.intrinsics.height);
        mins.resize(cells);
        maxs.resize(cells);
        invalid.resize(cells);
        opinions.resize(g.voxel_count());
        entries.resize(table_entries);
        table = FootprintTable(Span<FootprintEntry>(entries.data(), entries.size()));
        space = FootprintWorkspace{
            {mins.data(), cells}, {maxs.data(), cells}, {invalid.data(), cells}, {opinions.data(), opinions.size()}};
    }
    FootprintWorkspace with_table() {
        FootprintWorkspace w = space;
        w.table = &table;
        return w;
    }
};

/// Both ways on one reading: the opinions and every count must be equal.
void check_same_opinions(const GridGeometry& g, const SensorReading& r, const FootprintParams& params = {}) {
    const SensorModelTable model;
    Work plain(g, r, 0U);
    Work tabled(g, r, footprint_table_entries(g, r));
    FootprintStats a;
    FootprintStats b;
    const Result<FusionStats> ra = footprint_opinions(g, r, model, plain.space, &a, params);
    const Result<FusionStats> rb = footprint_opinions(g, r, model, tabled.with_table(), &b, params);
    REQUIRE(ra.ok());
    REQUIRE(rb.ok());
    CHECK(std::memcmp(plain.opinions.data(), tabled.opinions.data(), plain.opinions.size() * sizeof(std::int16_t)) ==
          0);
    CHECK(a.voxels_visited == b.voxels_visited);
    CHECK(a.voxels_filled == b.voxels_filled);
    CHECK(a.voxels_safe_side == b.voxels_safe_side);
    CHECK(a.voxels_exact == b.voxels_exact);
    CHECK(a.pixel_tests == b.pixel_tests);
    CHECK(b.table_makes == 1U);
    CHECK(b.voxels_visited == tabled.table.entries().size());
    CHECK(a.work_units() <= footprint_work_bound(g, r, params));
    CHECK((params.exact_footprint_max != 0U || a.work_units() == footprint_work_bound(g, r, params)));
}

/// A constant depth image of @p r's size.
struct ConstantImage {
    std::vector<float> depth;
    SensorReading reading;
    ConstantImage(const SensorReading& r, float d)
        : depth(static_cast<std::size_t>(r.intrinsics.width) * static_cast<std::size_t>(r.intrinsics.height), d),
          reading(r) {
        reading.depth = Span<const float>(depth.data(), depth.size());
    }
};

}  // namespace

// verifies: SR-FUSE-014
TEST_CASE("footprint table: the opinions and counts of fusion without a table, bit for bit") {
    const GridGeometry g = paper_grid_geometry();
    SUBCASE("the paper's sensors, reference scene and a person") {
        const sim::SimulatedFrame empty = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
        const sim::SimulatedFrame person = test::paper_person_frame();
        for (std::size_t s = 0U; s < empty.readings.size(); ++s) {
            CAPTURE(s);
            check_same_opinions(g, empty.readings[s]);
            check_same_opinions(g, person.readings[s]);
            FootprintParams exact;
            exact.exact_footprint_max = 64U;
            check_same_opinions(g, person.readings[s], exact);
        }
    }
    SUBCASE("random depths, some pixels without a reading") {
        const sim::SimulatedFrame frame = test::paper_person_frame();
        std::mt19937 rng(34U);
        std::uniform_real_distribution<float> depth(0.2F, 4.0F);
        for (std::size_t s = 0U; s < frame.readings.size(); ++s) {
            CAPTURE(s);
            std::vector<float> d(frame.depth[s].size());
            for (float& v : d) {
                v = (rng() % 10U == 0U) ? std::nanf("") : depth(rng);
            }
            SensorReading r = frame.readings[s];
            r.depth = Span<const float>(d.data(), d.size());
            check_same_opinions(g, r);
            // The same depths as uint16 millimetres (NaN: raw 0, no reading).
            std::vector<std::uint16_t> raw(d.size());
            for (std::size_t i = 0U; i < d.size(); ++i) {
                raw[i] = std::isnan(d[i]) ? std::uint16_t{0U} : static_cast<std::uint16_t>(d[i] * 1000.0F);
            }
            SensorReading u16 = r;
            u16.kind = SensorDataKind::kDepthImageU16;
            u16.depth = {};
            u16.depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size());
            u16.depth_scale = 0.001F;
            check_same_opinions(g, u16);
        }
    }
}

// verifies: SR-FUSE-014
TEST_CASE("footprint table: a reading at a voxel's thresholds, and one float either side, decides as without a table") {
    // A constant image puts every pixel of every footprint at the same depth:
    // at an entry's front and fill thresholds, and at the floats just below,
    // the fast decisions must flip exactly where the double tests do.
    const GridGeometry g = paper_grid_geometry();
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const SensorReading& r = frame.readings[0];
    Work probe(g, r, footprint_table_entries(g, r));
    const SensorModelTable model;
    REQUIRE(probe.table.make(g, r, model).ok());
    const Span<const FootprintEntry> entries = probe.table.entries();
    REQUIRE(entries.size() > 100U);
    std::size_t fillable = 0U;
    for (std::size_t k = 0U; k < entries.size(); k += entries.size() / 12U) {
        const FootprintEntry& e = entries[k];
        const float inf = std::numeric_limits<float>::infinity();
        std::vector<float> depths{e.front, std::nextafter(e.front, -inf), std::nextafter(e.front, inf)};
        if (e.fill < inf) {
            ++fillable;
            depths.push_back(e.fill);
            depths.push_back(std::nextafter(e.fill, -inf));
        }
        for (const float d : depths) {
            CAPTURE(k);
            CAPTURE(d);
            const ConstantImage image(r, d);
            check_same_opinions(g, image.reading);
        }
    }
    CHECK(fillable > 0U);
}

// verifies: SR-FUSE-014
TEST_CASE("footprint table: made from the geometry once, again when the camera, the grid or the ramp changes") {
    const GridGeometry g = paper_grid_geometry();
    const sim::SimulatedFrame frame = test::paper_person_frame();
    const SensorReading& r = frame.readings[1];
    const std::size_t n = footprint_table_entries(g, r);
    REQUIRE(n > 0U);
    CHECK(n < g.voxel_count());
    Work work(g, r, n);
    const SensorModelTable model;
    FootprintStats stats;
    for (int i = 0; i < 3; ++i) {
        REQUIRE(footprint_opinions(g, r, model, work.with_table(), &stats).ok());
    }
    CHECK(stats.table_makes == 1U);
    CHECK(work.table.makes() == 1U);
    CHECK(work.table.entries().size() == n);
    CHECK(work.table.matches(g, r, model));

    SensorReading moved = r;  // a camera moved by 1 mm: the table no longer fits it
    moved.pose.translation().x() += 1e-3;
    CHECK_FALSE(work.table.matches(g, moved, model));
    SensorReading other_focus = r;
    other_focus.intrinsics.fx *= 1.01;
    CHECK_FALSE(work.table.matches(g, other_focus, model));
    SensorModelParams longer;
    longer.ramp_length = 0.2;
    const SensorModelTable other_ramp = SensorModelTable::make(longer).value();
    CHECK_FALSE(work.table.matches(g, r, other_ramp));
    const GridGeometry shifted =
        GridGeometry::make(g.origin() + Eigen::Vector3d(0.01, 0.0, 0.0), g.voxel_size(), g.dims()).value();
    CHECK_FALSE(work.table.matches(shifted, r, model));
    const GridGeometry finer = GridGeometry::make(g.origin(), 0.5 * g.voxel_size(), g.dims()).value();
    CHECK_FALSE(work.table.matches(finer, r, model));
    const GridGeometry taller =
        GridGeometry::make(g.origin(), g.voxel_size(), GridDims{g.dims().nx, g.dims().ny, g.dims().nz + 1}).value();
    CHECK_FALSE(work.table.matches(taller, r, model));
    for (int field = 0; field < 5; ++field) {  // each other number of the camera
        CAPTURE(field);
        SensorReading other = r;
        PinholeIntrinsics& k = other.intrinsics;
        (field == 0 ? k.fy : field == 1 ? k.cx : k.cy) += field < 3 ? 0.5 : 0.0;
        k.width += field == 3 ? 2 : 0;
        k.height += field == 4 ? 2 : 0;
        CHECK_FALSE(work.table.matches(g, other, model));
    }
    SensorReading turned = r;  // the same position, turned by 1 mrad
    turned.pose.linear() = turned.pose.linear() * Eigen::AngleAxisd(1e-3, Eigen::Vector3d::UnitY()).toRotationMatrix();
    CHECK_FALSE(work.table.matches(g, turned, model));
    SensorReading points = r;
    points.kind = SensorDataKind::kPointSet;
    CHECK_FALSE(work.table.matches(g, points, model));

    // Fusing the moved camera makes the table again (its size may differ: room was left).
    Work roomy(g, r, g.voxel_count());
    REQUIRE(footprint_opinions(g, r, model, roomy.with_table(), nullptr).ok());
    REQUIRE(footprint_opinions(g, moved, model, roomy.with_table(), nullptr).ok());
    CHECK(roomy.table.makes() == 2U);
    CHECK(roomy.table.matches(g, moved, model));
    CHECK(roomy.table.entries().size() == footprint_table_entries(g, moved));
}

// verifies: SR-FUSE-014, SR-FUSE-011
TEST_CASE("footprint table: too small, or for a point set or a bad camera, it is refused and nothing is fused") {
    const GridGeometry g = paper_grid_geometry();
    const sim::SimulatedFrame frame = test::paper_person_frame();
    const SensorModelTable model;
    const std::size_t n = footprint_table_entries(g, frame.readings[0]);
    std::vector<Work> works;
    works.reserve(frame.readings.size());
    std::vector<FootprintWorkspace> spaces;
    for (const SensorReading& r : frame.readings) {
        works.emplace_back(g, r, footprint_table_entries(g, r));
    }
    works[0].entries.resize(n - 1U);  // one entry short
    works[0].table = FootprintTable(Span<FootprintEntry>(works[0].entries.data(), works[0].entries.size()));
    for (Work& w : works) {
        spaces.push_back(w.with_table());
    }
    std::vector<std::int16_t> lo(g.voxel_count(), 7);
    std::vector<std::uint8_t> ob(g.voxel_count(), 0U);
    EvidenceGrid grid = EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()),
                                           Span<std::uint8_t>(ob.data(), ob.size()))
                            .value();
    SequentialRunner runner;
    const Result<FusionStats> r = fuse_frame_footprint(
        grid, Span<const SensorReading>(frame.readings.data(), frame.readings.size()), model,
        Span<const FootprintWorkspace>(spaces.data(), spaces.size()), runner);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error() == ErrorCode::kStorageTooSmall);
    CHECK(works[0].table.entries().empty());
    for (std::size_t i = 0U; i < lo.size(); ++i) {
        if (lo[i] != 7 || ob[i] != 0U) {
            FAIL("voxel " << i << " changed by a refused frame");
        }
    }

    FootprintTable& t = works[1].table;
    SensorReading points = frame.readings[1];
    points.kind = SensorDataKind::kPointSet;
    CHECK(t.make(g, points, model).error() == ErrorCode::kInvalidArgument);
    SensorReading tilted = frame.readings[1];
    tilted.pose.linear() *= 1.01;  // not a rotation
    CHECK(t.make(g, tilted, model).error() == ErrorCode::kInvalidArgument);
    for (int bad = 0; bad < 9; ++bad) {  // each number of the camera made unusable in turn
        CAPTURE(bad);
        SensorReading cam = frame.readings[1];
        PinholeIntrinsics& k = cam.intrinsics;
        const double nan = std::nan("");
        switch (bad) {
            case 0: k.fx = nan; break;
            case 1: k.fy = nan; break;
            case 2: k.cx = nan; break;
            case 3: k.cy = nan; break;
            case 4: k.fx = 0.0; break;
            case 5: k.fy = -1.0; break;
            case 6: k.width = 5000; break;  // wider than a pyramid may be
            case 7: k.height = 0; break;
            default: cam.pose.translation().x() = nan; break;
        }
        CHECK(t.make(g, cam, model).error() == ErrorCode::kInvalidArgument);
        CHECK(footprint_table_entries(g, cam) == 0U);
    }
    CHECK(t.make(GridGeometry{}, frame.readings[1], model).error() == ErrorCode::kInvalidArgument);
    CHECK(footprint_table_entries(g, points) == 0U);
    CHECK(footprint_table_entries(GridGeometry{}, frame.readings[1]) == 0U);
    CHECK_FALSE(t.matches(g, frame.readings[1], model));
    CHECK(t.entries().empty());
}

// verifies: SR-FUSE-014, SR-FUSE-012
TEST_CASE("footprint table: one workspace for all sensors uses none, and the grid is the same either way") {
    const GridGeometry g = paper_grid_geometry();
    const sim::SimulatedFrame frame = test::paper_person_frame();
    const SensorModelTable model;
    const Span<const SensorReading> readings(frame.readings.data(), frame.readings.size());
    std::vector<Work> works;
    works.reserve(frame.readings.size());
    std::vector<FootprintWorkspace> spaces;
    for (const SensorReading& r : frame.readings) {
        works.emplace_back(g, r, footprint_table_entries(g, r));
    }
    for (Work& w : works) {
        spaces.push_back(w.with_table());
    }
    struct Owned {
        std::vector<std::int16_t> lo;
        std::vector<std::uint8_t> ob;
        EvidenceGrid grid;
        explicit Owned(const GridGeometry& geo)
            : lo(geo.voxel_count()),
              ob(geo.voxel_count()),
              grid(EvidenceGrid::make(geo, Span<std::int16_t>(lo.data(), lo.size()),
                                      Span<std::uint8_t>(ob.data(), ob.size()))
                       .value()) {
            grid.clear();
        }
    };
    Owned per_sensor(g);
    Owned shared(g);
    SequentialRunner runner;
    FootprintStats a;
    FootprintStats b;
    REQUIRE(fuse_frame_footprint(per_sensor.grid, readings, model,
                                 Span<const FootprintWorkspace>(spaces.data(), spaces.size()), runner, &a)
                .ok());
    // The shared workspace's pyramid holds the largest image, and it has a table.
    std::size_t largest = 0U;
    for (std::size_t s = 1U; s < frame.readings.size(); ++s) {
        const PinholeIntrinsics& k = frame.readings[s].intrinsics;
        const PinholeIntrinsics& m = frame.readings[largest].intrinsics;
        largest = k.width * k.height > m.width * m.height ? s : largest;
    }
    Work one(g, frame.readings[largest], g.voxel_count());
    const FootprintWorkspace one_space = one.with_table();
    REQUIRE(
        fuse_frame_footprint(shared.grid, readings, model, Span<const FootprintWorkspace>(&one_space, 1U), runner, &b)
            .ok());
    CHECK(one.table.makes() == 0U);
    CHECK(a.table_makes == frame.readings.size());
    CHECK(b.table_makes == 0U);
    CHECK(per_sensor.lo == shared.lo);
    CHECK(per_sensor.ob == shared.ob);
    // A second frame with the tables made allocates nothing.
    const test::AllocationScope scope;
    const Result<FusionStats> again = fuse_frame_footprint(
        per_sensor.grid, readings, model, Span<const FootprintWorkspace>(spaces.data(), spaces.size()), runner, &a);
    const std::size_t allocations = scope.allocations();
    REQUIRE(again.ok());
    CHECK(allocations == 0U);
    CHECK(a.table_makes == frame.readings.size());
}
