// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: footprint fusion gives the one-core grid bit for bit with 1, 2 and 4 worker threads (issue 18, item 3).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/base/task_runner.hpp"
#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/port/worker_pool.hpp"
#include "paper_cell.hpp"

using namespace cellguard;

namespace {

/// One workspace per sensor over owned storage, sized for its image and the grid.
struct Workspaces {
    std::vector<std::vector<float>> mins, maxs;
    std::vector<std::vector<std::uint8_t>> invalid;
    std::vector<std::vector<std::int16_t>> opinions;
    std::vector<FootprintWorkspace> spans;
    Workspaces(const std::vector<SensorReading>& readings, std::size_t voxels) {
        const std::size_t n = readings.size();
        mins.resize(n);
        maxs.resize(n);
        invalid.resize(n);
        opinions.resize(n);
        for (std::size_t i = 0U; i < n; ++i) {
            const std::size_t cells = depth_pyramid_cells(readings[i].intrinsics.width, readings[i].intrinsics.height);
            mins[i].resize(cells);
            maxs[i].resize(cells);
            invalid[i].resize(cells);
            opinions[i].resize(voxels);
            spans.push_back(FootprintWorkspace{{mins[i].data(), cells},
                                               {maxs[i].data(), cells},
                                               {invalid[i].data(), cells},
                                               {opinions[i].data(), voxels}});
        }
    }
};

/// A grid over owned storage.
struct OwnedGrid {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid;
    explicit OwnedGrid(const GridGeometry& g)
        : lo(g.voxel_count()),
          ob(g.voxel_count()),
          grid(EvidenceGrid::make(g, Span<std::int16_t>(lo.data(), lo.size()), Span<std::uint8_t>(ob.data(), ob.size()))
                   .value()) {
        grid.clear();
    }
};

/// The paper's four sensors on the reference scene, then with a person-sized
/// box near the centre: two frames, so evidence accumulates.
struct TwoFrames {
    sim::SimulatedFrame empty = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    sim::SimulatedFrame person = test::paper_person_frame();
};

/// The four sensors' frame, one of them as uint16 millimetres (kDepthImageU16).
struct U16Frame {
    std::vector<std::uint16_t> raw;
    std::vector<SensorReading> readings;
    explicit U16Frame(const sim::SimulatedFrame& frame) : readings(frame.readings) {
        const std::vector<float>& depth = frame.depth[1];
        raw.resize(depth.size());
        for (std::size_t i = 0U; i < depth.size(); ++i) {
            const float mm = std::isfinite(depth[i]) ? std::round(depth[i] * 1000.0F) : 0.0F;
            raw[i] = mm > 0.0F && mm < 65535.0F ? static_cast<std::uint16_t>(mm) : std::uint16_t{0U};
        }
        readings[1].kind = SensorDataKind::kDepthImageU16;
        readings[1].depth = {};
        readings[1].depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size());
        readings[1].depth_scale = 0.001F;
        readings[1].depth_offset = 0.0F;
    }
};

/// Fuses @p frames one after another into a cleared grid with @p runner;
/// returns the grid and the summed footprint counts.
struct Fused {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    FootprintStats stats;
    std::uint64_t rays = 0U;
};
Fused fuse_with(TaskRunner& runner, const std::vector<const std::vector<SensorReading>*>& frames,
                const FootprintParams& params = FootprintParams{}) {
    const GridGeometry g = paper_grid_geometry();
    OwnedGrid owned(g);
    const SensorModelTable model;
    Fused out;
    for (const std::vector<SensorReading>* readings : frames) {
        Workspaces work(*readings, g.voxel_count());
        const Result<FusionStats> st = fuse_frame_footprint(
            owned.grid, Span<const SensorReading>(readings->data(), readings->size()), model,
            Span<const FootprintWorkspace>(work.spans.data(), work.spans.size()), runner, &out.stats, params);
        REQUIRE(st.ok());
        out.rays += st.value().rays_fused;
    }
    out.lo = owned.lo;
    out.ob = owned.ob;
    return out;
}

void check_same(const Fused& reference, const Fused& other) {
    REQUIRE(reference.lo.size() == other.lo.size());
    CHECK(std::memcmp(reference.lo.data(), other.lo.data(), reference.lo.size() * sizeof(std::int16_t)) == 0);
    CHECK(std::memcmp(reference.ob.data(), other.ob.data(), reference.ob.size()) == 0);
    CHECK(reference.rays == other.rays);
    CHECK(reference.stats.pixels == other.stats.pixels);
    CHECK(reference.stats.voxels_visited == other.stats.voxels_visited);
    CHECK(reference.stats.voxels_filled == other.stats.voxels_filled);
    CHECK(reference.stats.voxels_safe_side == other.stats.voxels_safe_side);
    CHECK(reference.stats.voxels_exact == other.stats.voxels_exact);
    CHECK(reference.stats.pixel_tests == other.stats.pixel_tests);
}

}  // namespace

// verifies: SR-FUSE-012, SR-GEN-008
TEST_CASE("footprint fusion: 1, 2 and 4 worker threads give the one-core grid bit for bit") {
    const TwoFrames frames;
    const U16Frame person_u16(frames.person);
    const std::vector<const std::vector<SensorReading>*> sequence = {&frames.empty.readings, &person_u16.readings,
                                                                     &frames.person.readings};
    SequentialRunner sequential;
    const Fused reference = fuse_with(sequential, sequence);
    // The comparison can fail: the frames leave a grid with evidence of both signs and unseen voxels.
    std::size_t free_voxels = 0U;
    std::size_t hit_voxels = 0U;
    std::size_t unseen = 0U;
    for (std::size_t i = 0U; i < reference.lo.size(); ++i) {
        free_voxels += reference.lo[i] < 0 ? 1U : 0U;
        hit_voxels += reference.lo[i] > 0 ? 1U : 0U;
        unseen += reference.ob[i] == 0U ? 1U : 0U;
    }
    CHECK(free_voxels > 1000U);
    CHECK(hit_voxels > 100U);
    CHECK(unseen > 0U);
    for (const std::size_t workers : {1U, 2U, 4U}) {
        linux_port::WorkerPool pool(workers);
        INFO("workers ", workers);
        check_same(reference, fuse_with(pool, sequence));
        check_same(reference, fuse_with(pool, sequence));  // the same pool again
    }
}

// verifies: SR-FUSE-015, SR-FUSE-012
TEST_CASE("footprint fusion: the AVX2 kernel pools to the scalar kernel's grid bit for bit, at the clamps too") {
    // Fifteen frames into one grid (not cleared between them): evidence of both signs
    // that reaches both clamps, and a grid whose size is not a multiple of 16 voxels
    // (the AVX2 pooling takes 16 at a time, the rest one at a time).
    const TwoFrames frames;
    const U16Frame person_u16(frames.person);
    std::vector<const std::vector<SensorReading>*> sequence;
    for (int k = 0; k < 5; ++k) {
        sequence.insert(sequence.end(), {&frames.empty.readings, &person_u16.readings, &frames.person.readings});
    }
    REQUIRE(paper_grid_geometry().voxel_count() % 16U != 0U);
    FootprintParams scalar;
    scalar.kernel = FusionKernel::kScalar;
    FootprintParams avx2;
    avx2.kernel = FusionKernel::kAvx2;
    SequentialRunner sequential;
    const Fused reference = fuse_with(sequential, sequence, scalar);
    const SensorModelTable model;
    std::size_t at_max = 0U;
    std::size_t at_min = 0U;
    for (const std::int16_t v : reference.lo) {
        at_max += v == model.pooled_max() ? 1U : 0U;
        at_min += v == model.pooled_min() ? 1U : 0U;
    }
    CHECK(at_max > 0U);
    CHECK(at_min > 0U);
    INFO("kernel run: ", static_cast<int>(resolve_fusion_kernel(FusionKernel::kAvx2)));
    check_same(reference, fuse_with(sequential, sequence, avx2));
    linux_port::WorkerPool pool(2U);
    check_same(reference, fuse_with(pool, sequence, avx2));
}

// verifies: SR-GEN-002, SR-FUSE-011
TEST_CASE("footprint fusion: a frame fused on four worker threads allocates nothing") {
    const TwoFrames frames;
    const GridGeometry g = paper_grid_geometry();
    OwnedGrid owned(g);
    Workspaces work(frames.person.readings, g.voxel_count());
    const SensorModelTable model;
    linux_port::WorkerPool pool(4U);
    const Span<const SensorReading> readings(frames.person.readings.data(), frames.person.readings.size());
    const Span<const FootprintWorkspace> spans(work.spans.data(), work.spans.size());
    REQUIRE(fuse_frame_footprint(owned.grid, readings, model, spans, pool).ok());  // warm
    const test::AllocationScope scope;
    const Result<FusionStats> st = fuse_frame_footprint(owned.grid, readings, model, spans, pool);
    const std::size_t allocations = scope.allocations();
    REQUIRE(st.ok());
    CHECK(allocations == 0U);
}

// verifies: SR-GEN-008
// verifies: SR-FUSE-012
TEST_CASE("footprint fusion: fewer workspaces than sensors give the same grid on one and four workers") {
    const TwoFrames frames;
    const GridGeometry g = paper_grid_geometry();
    const SensorModelTable model;
    const Span<const SensorReading> readings(frames.person.readings.data(), frames.person.readings.size());
    // One workspace big enough for the largest image: the sensors run one after another through it.
    Workspaces all(frames.person.readings, g.voxel_count());
    std::size_t largest = 0U;
    for (std::size_t i = 1U; i < all.spans.size(); ++i) {
        largest = all.spans[i].pyramid_min.size() > all.spans[largest].pyramid_min.size() ? i : largest;
    }
    const Span<const FootprintWorkspace> one(&all.spans[largest], 1U);
    const Span<const FootprintWorkspace> four(all.spans.data(), all.spans.size());
    SequentialRunner sequential;
    linux_port::WorkerPool pool(4U);
    OwnedGrid a(g);
    OwnedGrid b(g);
    OwnedGrid c(g);
    REQUIRE(fuse_frame_footprint(a.grid, readings, model, four, sequential).ok());
    REQUIRE(fuse_frame_footprint(b.grid, readings, model, one, pool).ok());
    REQUIRE(fuse_frame_footprint(c.grid, readings, model, four, pool).ok());
    CHECK(a.lo == b.lo);
    CHECK(a.ob == b.ob);
    CHECK(a.lo == c.lo);
    CHECK(a.ob == c.ob);
}
