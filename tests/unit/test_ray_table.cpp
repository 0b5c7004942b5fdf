// Requirements: precomputed rays of static sensors give the same evidence as
// on-the-fly fusion, within the stated boundary cases, and allocate nothing.
#include <doctest/doctest.h>

#include <cstdlib>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/ray_table.hpp"
#include "cellguard/sim/workcell.hpp"

using namespace cellguard;

namespace {

struct OwnedTable {
    std::vector<RayStep> steps;
    std::vector<std::uint32_t> begin;
    std::vector<float> enter;
    std::vector<float> norm;
    RayTable table;
};

OwnedTable make_table(const GridGeometry& g, const SensorReading& r) {
    OwnedTable t;
    const std::size_t n = count_ray_steps(g, r).value();
    const std::size_t pixels = r.depth.size();
    t.steps.resize(n);
    t.begin.resize(pixels + 1U);
    t.enter.resize(pixels);
    t.norm.resize(pixels);
    t.table = RayTable::build(g, r, RayTableStorage{{t.steps.data(), n}, {t.begin.data(), t.begin.size()},
                                                    {t.enter.data(), t.enter.size()}, {t.norm.data(), t.norm.size()}})
                  .value();
    return t;
}

struct OwnedGrid {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid;
    explicit OwnedGrid(const GridGeometry& g) : lo(g.voxel_count()), ob(g.voxel_count()) {
        grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        grid.clear();
    }
};

}  // namespace

// verifies: SR-FUSE-006
TEST_CASE("ray table: fusing through precomputed rays matches on-the-fly fusion on the simulated workcell") {
    const sim::SimulatedFrame frame = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    // The paper's grid lowered by half a voxel: the simulated floor (exactly z = 0) would
    // otherwise lie on the grid's bottom face, where every floor reading is a boundary case.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, -0.025), 0.05, GridDims{34, 30, 30}).value();
    const SensorModelTable model;
    OwnedGrid direct(g);
    OwnedGrid tabled(g);
    FusionStats direct_stats;
    FusionStats table_stats;
    for (const SensorReading& r : frame.readings) {
        direct_stats.add(fuse_sensor(direct.grid, r, model).value());
        const OwnedTable t = make_table(g, r);
        table_stats.add(t.table.fuse(tabled.grid, r.depth, model).value());
    }
    CHECK(table_stats.rays_fused == direct_stats.rays_fused);
    CHECK(table_stats.skipped() == direct_stats.skipped());
    // Boundary cases (readings within rounding of a face, grazing rays) differ; bound them.
    const double updates_ratio = static_cast<double>(table_stats.voxel_updates) / static_cast<double>(direct_stats.voxel_updates);
    CHECK(updates_ratio == doctest::Approx(1.0).epsilon(0.001));
    CHECK(std::abs(static_cast<long>(table_stats.readings_in_grid) - static_cast<long>(direct_stats.readings_in_grid)) <=
          static_cast<long>(direct_stats.readings_in_grid / 1000U));
    std::size_t observed_differ = 0;
    std::size_t sign_differ = 0;
    for (std::size_t i = 0; i < g.voxel_count(); ++i) {
        observed_differ += (direct.ob[i] != tabled.ob[i]) ? 1U : 0U;
        sign_differ += ((direct.lo[i] > 0) != (tabled.lo[i] > 0)) ? 1U : 0U;
    }
    MESSAGE("voxels whose observed flag differs: " << observed_differ << ", whose occupied sign differs: " << sign_differ);
    CHECK(observed_differ <= g.voxel_count() / 1000U);
    CHECK(sign_differ <= g.voxel_count() / 200U);
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
    CHECK(t.table.fuse(grid.grid, r.depth.subspan(0, r.depth.size() - 1U), model).error() == ErrorCode::kMalformedInput);
    OwnedGrid other(whole_cell_grid_geometry());
    CHECK(t.table.fuse(other.grid, r.depth, model).error() == ErrorCode::kGeometryMismatch);
    CHECK(RayTable{}.fuse(grid.grid, r.depth, model).error() == ErrorCode::kInvalidArgument);

    std::vector<RayStep> few(10);
    std::vector<std::uint32_t> begin(r.depth.size() + 1U);
    std::vector<float> enter(r.depth.size()), norm(r.depth.size());
    CHECK(RayTable::build(g, r, RayTableStorage{{few.data(), few.size()}, {begin.data(), begin.size()},
                                                {enter.data(), enter.size()}, {norm.data(), norm.size()}})
              .error() == ErrorCode::kStorageTooSmall);
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
    const FusionStats sd = fuse_sensor(b.grid, r, model).value();
    CHECK(st.skipped_nan == 1U);
    CHECK(st.skipped_infinite == 1U);
    CHECK(st.skipped_zero == sd.skipped_zero);
    CHECK(st.skipped_behind == 1U);
    CHECK(st.skipped_out_of_range == 1U);
    CHECK(st.skipped() == sd.skipped());
}
