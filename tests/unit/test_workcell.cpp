// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the simulator's sensors with explicit pinhole intrinsics
// (SensorSpec::set_intrinsics, issue 19): intrinsics equal to a field of
// view's give the same images, rays, background views, readings, grids (ray
// and footprint fusion), ray tables, priors and work bound, bit for bit, from
// the simulator up to the monitor's start-up; a principal point off the
// image centre moves the image by exactly that many pixels.
#include <doctest/doctest.h>

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/owned_footprint.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/monitor_cell.hpp"

using namespace cellguard;

namespace {

/// @p s with explicit intrinsics equal to those of its fields of view.
sim::SensorSpec explicit_copy(const sim::SensorSpec& s) {
    const PinholeIntrinsics k = s.intrinsics();
    sim::SensorSpec e = s;
    e.hfov_deg = 0.0;  // set_intrinsics derives them again
    e.vfov_deg = 0.0;
    e.set_intrinsics(k.fx, k.fy, k.cx, k.cy);
    return e;
}

/// True when @p a and @p b hold the same floats, bit for bit.
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

/// The paper's grid (the demo's: 34 x 30 x 30 of 5 cm).
GridGeometry paper_grid() { return GridGeometry::make({-0.85, -0.75, 0.0}, 0.05, GridDims{34, 30, 30}).value(); }

/// The log-odds of @p frame's readings fused into a cleared paper grid, ray
/// by ray or (@p footprint) by footprint fusion.
std::vector<std::int16_t> fused(const sim::SimulatedFrame& frame, bool footprint) {
    const GridGeometry g = paper_grid();
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
    grid.clear();
    std::vector<std::int16_t> scratch(g.voxel_count());
    const host::OwnedFootprintWorkspaces spaces(g, frame.readings);
    const Result<FusionStats> r = host::fuse_frame_by(grid, {frame.readings.data(), frame.readings.size()},
                                                      SensorModelTable{}, {scratch.data(), scratch.size()},
                                                      Rasterization::kExact, footprint ? &spaces : nullptr);
    REQUIRE(r.ok());
    return lo;
}

/// The scene with the demo's person in the protective zone.
sim::Scene person_scene() {
    sim::Scene scene = sim::reference_scene();
    scene.boxes.push_back(cell::person_box(cell::demo_person(15)));
    return scene;
}

/// %.17g: a double written so that it reads back to the same bits.
std::string exact(double v) {
    char text[40];
    static_cast<void>(std::snprintf(text, sizeof text, "%.17g", v));
    return text;
}

}  // namespace

// verifies: SR-CFG-014, SR-SIM-001
TEST_CASE("workcell: explicit intrinsics equal to the fields of view's give the same images, rays and grids") {
    const std::vector<sim::SensorSpec> fov = sim::paper_sensors();
    std::vector<sim::SensorSpec> given;
    for (const sim::SensorSpec& s : fov) {
        given.push_back(explicit_copy(s));
    }
    const sim::Scene scene = person_scene();
    const sim::PreparedScene prepared(scene);
    for (std::size_t i = 0U; i < fov.size(); ++i) {
        CAPTURE(fov[i].name);
        const PinholeIntrinsics a = fov[i].intrinsics();
        const PinholeIntrinsics b = given[i].intrinsics();
        CHECK(given[i].has_intrinsics);
        CHECK(std::memcmp(&a.fx, &b.fx, sizeof a.fx) == 0);
        CHECK(std::memcmp(&a.cy, &b.cy, sizeof a.cy) == 0);
        CHECK(given[i].hfov_deg == doctest::Approx(fov[i].hfov_deg).epsilon(1e-12));
        CHECK(given[i].vfov_deg == doctest::Approx(fov[i].vfov_deg).epsilon(1e-12));
        std::vector<float> da;
        std::vector<float> db;
        sim::render_depth(fov[i], prepared, da);
        sim::render_depth(given[i], prepared, db);
        CHECK(same_bits(da, db));
        // The rays computed once, and the background view plus the person.
        const sim::SensorRays rays(given[i]);
        std::vector<float> dr(db.size());
        REQUIRE(sim::render_depth_into(rays, prepared, {dr.data(), dr.size()}));
        CHECK(same_bits(da, dr));
        const sim::BackgroundView view(given[i], sim::reference_scene());
        sim::Scene moving;
        moving.boxes.push_back(scene.boxes.back());
        std::vector<float> dv(db.size());
        REQUIRE(view.render_into(sim::PreparedScene(moving), {dv.data(), dv.size()}));
        CHECK(same_bits(da, dv));
    }
    const sim::SimulatedFrame fa = sim::render_frame(fov, scene);
    const sim::SimulatedFrame fb = sim::render_frame(given, scene);
    CHECK(fused(fa, false) == fused(fb, false));
    CHECK(fused(fa, true) == fused(fb, true));
    CHECK(fused(fa, false) != fused(sim::render_frame(fov, sim::reference_scene()), false));  // the person shows
}

// verifies: SR-CFG-014, SR-SIM-001
TEST_CASE("workcell: a principal point off the image centre moves the image by as many pixels") {
    const sim::SensorSpec centred = sim::paper_sensors()[2];  // 320 x 240
    const PinholeIntrinsics k = centred.intrinsics();
    constexpr int kDu = 12;
    constexpr int kDv = -7;
    sim::SensorSpec shifted = centred;
    shifted.set_intrinsics(k.fx, k.fy, k.cx + kDu, k.cy + kDv);
    CHECK(shifted.intrinsics().cx == k.cx + kDu);
    CHECK(sim::depth_reading(shifted, {}).intrinsics.cy == k.cy + kDv);
    const sim::PreparedScene scene(person_scene());
    std::vector<float> a;
    std::vector<float> b;
    sim::render_depth(centred, scene, a);
    sim::render_depth(shifted, scene, b);
    const auto at = [&k](const std::vector<float>& d, int u, int v) {
        return d[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) + static_cast<std::size_t>(u)];
    };
    // Pixel (u + du, v + dv) of the shifted camera looks along pixel (u, v)'s ray of the centred one.
    std::size_t compared = 0U;
    std::size_t mismatched = 0U;
    std::size_t differ_in_place = 0U;
    for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u < k.width; ++u) {
            differ_in_place += at(a, u, v) != at(b, u, v) ? 1U : 0U;
            if (u + kDu < 0 || u + kDu >= k.width || v + kDv < 0 || v + kDv >= k.height) {
                continue;
            }
            const float x = at(a, u, v);
            const float y = at(b, u + kDu, v + kDv);
            mismatched += std::memcmp(&x, &y, sizeof x) != 0 ? 1U : 0U;
            ++compared;
        }
    }
    CHECK(compared == static_cast<std::size_t>((k.width - kDu) * (k.height + kDv)));
    CHECK(mismatched == 0U);
    CHECK(differ_in_place > 1000U);  // the shift is not a no-op
}

// verifies: SR-CFG-014, SR-SIM-001
TEST_CASE("workcell: the monitor started with intrinsics equal to a field of view builds the same cell") {
    // Every sensor of the demo given by its fields of view's fx, fy, cx, cy, written back exactly.
    std::string text = cell::demo_config_text();
    for (const sim::SensorSpec& s : sim::paper_sensors()) {
        char fov[64];
        static_cast<void>(std::snprintf(fov, sizeof fov, "fov = [%.1f, %.1f]", s.hfov_deg, s.vfov_deg));
        const PinholeIntrinsics k = s.intrinsics();
        const std::size_t at = text.find(fov);
        REQUIRE_MESSAGE(at != std::string::npos, fov);
        text.replace(at, std::strlen(fov),
                     "intrinsics = { fx = " + exact(k.fx) + ", fy = " + exact(k.fy) + ", cx = " + exact(k.cx) +
                         ", cy = " + exact(k.cy) + " }");
    }
    const cell::ConfigLoad load = cell::parse_monitor_config(text, "cell.toml");
    REQUIRE_MESSAGE(load.ok, load.error);
    const cell::MonitorConfig demo = cell::demo_config();
    monitor::MonitorCell a;
    monitor::MonitorCell b;
    for (monitor::MonitorCell* c : {&a, &b}) {
        const cell::MonitorConfig& cfg = c == &a ? demo : load.config;
        REQUIRE_FALSE(c->configure(cfg).failed());
        REQUIRE_FALSE(c->build_prior(cfg, nullptr).failed());
        REQUIRE_FALSE(c->build_tables(cfg, nullptr).failed());
    }
    REQUIRE(b.specs.size() == 4U);
    CHECK(b.specs[0].has_intrinsics);
    CHECK_FALSE(a.specs[0].has_intrinsics);
    CHECK(a.prior == b.prior);
    for (std::size_t s = 0U; s < 4U; ++s) {
        CAPTURE(s);
        CHECK(same_bits(a.layout.depth[s], b.layout.depth[s]));
        CHECK(a.tables[s].table().step_count() == b.tables[s].table().step_count());
        CHECK(a.tables[s].table().storage_crc() == b.tables[s].table().storage_crc());
    }
    CHECK(a.work.rays == b.work.rays);
    CHECK(a.work.voxel_steps == b.work.voxel_steps);
    CHECK(a.work.grid_voxels == b.work.grid_voxels);
}
