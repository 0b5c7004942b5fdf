// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the sensor model holds at a real camera's density. On the
// three real Kinect frames (tests/data/kinect-frames, 640 x 480): every voxel
// that holds readings is occupied in that frame; the grid does not depend on
// the order of the readings; the ray table gives the grid of on-the-fly
// fusion voxel for voxel; and both accessibility methods call a frame replayed against a
// prior commissioned from itself CLEAR, and the same frame with a
// person-sized block of readings INTRUDED.
//
// The set-up of issue 24's independent reference: one camera at the origin
// looking along +x (target (3, 0, 0), fields of view 57 x 43 degrees,
// max_range 5 m), a 64 x 64 x 48 grid of 5 cm voxels from (0.4, -1.6, -0.6).
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/host/io/pcd.hpp"
#include "cellguard/host/owned_footprint.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/safety/zone_evaluation.hpp"
#include "cellguard/safety/zones.hpp"
#include "test_tags.hpp"

using namespace cellguard;

namespace {

const char* const kFrames[] = {
    CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142255.814212.pcd",
    CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142256.068683.pcd",
    CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142256.332395.pcd",
};

/// The camera of issue 24's reference.
sim::SensorSpec camera() {
    return sim::SensorSpec{"kinect", {0.0, 0.0, 0.0}, {3.0, 0.0, 0.0}, 640, 480, 57.0, 43.0, 5.0F};
}

GridGeometry grid_geometry() {
    return GridGeometry::make(Eigen::Vector3d(0.4, -1.6, -0.6), 0.05, GridDims{64, 64, 48}).value();
}

/// A frame's organised cloud (camera frame, NaN kept), 640 x 480.
std::vector<Eigen::Vector3f> read_frame(const char* path) {
    std::vector<PcdPoint> raw(640U * 480U);
    PcdCloudInfo info;
    PcdReadOptions keep;
    keep.keep_nonfinite = true;
    const IoStatus st = read_pcd(path, {raw.data(), raw.size()}, info, keep);
    REQUIRE_MESSAGE(st.ok(), st.message());
    REQUIRE(info.written == raw.size());
    std::vector<Eigen::Vector3f> points(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) {
        points[i] = Eigen::Vector3f(raw[i].x, raw[i].y, raw[i].z);
    }
    return points;
}

SensorReading point_reading(const std::vector<Eigen::Vector3f>& points) {
    const sim::SensorSpec c = camera();
    SensorReading r;
    r.kind = SensorDataKind::kPointSet;
    r.pose = c.pose();
    r.points = Span<const Eigen::Vector3f>(points.data(), points.size());
    r.max_range = c.max_range;
    return r;
}

/// A frame's depth image: each point's z (NaN stays NaN).
std::vector<float> depth_of(const std::vector<Eigen::Vector3f>& points) {
    std::vector<float> depth(points.size());
    std::transform(points.begin(), points.end(), depth.begin(), [](const Eigen::Vector3f& p) { return p.z(); });
    return depth;
}

/// The camera's depth-image reading of @p depth (640 x 480, issue 24's intrinsics).
SensorReading depth_reading(const std::vector<float>& depth) {
    const sim::SensorSpec c = camera();
    SensorReading r;
    r.kind = SensorDataKind::kDepthImage;
    r.pose = c.pose();
    r.intrinsics = c.intrinsics();
    r.depth = Span<const float>(depth.data(), depth.size());
    r.max_range = c.max_range;
    return r;
}

/// A grid with its storage and fusion scratch.
struct Grid {
    std::vector<std::int16_t> lo, scratch;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid;
    explicit Grid(const GridGeometry& g) : lo(g.voxel_count()), scratch(g.voxel_count()), ob(g.voxel_count()) {
        grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        grid.clear();
    }
    Span<std::int16_t> fusion_scratch() { return {scratch.data(), scratch.size()}; }
};

/// The voxels that hold at least one valid reading (computed here, not by fusion).
std::set<std::size_t> voxels_holding_readings(const GridGeometry& g, const SensorReading& r) {
    std::set<std::size_t> out;
    for (const Eigen::Vector3f& p : r.points) {
        const float range = p.norm();
        if (!p.allFinite() || p.z() <= 0.0F || range < r.min_range || range > r.max_range) {
            continue;
        }
        const VoxelCoord v = g.world_to_voxel_unchecked(r.pose * p.cast<double>());
        if (g.contains(v)) {
            out.insert(g.index_of(v));
        }
    }
    return out;
}

/// The frame with a person-sized block of readings 1.5 m in front of the
/// camera: every valid reading of pixels u 240..399, v 80..399 (about 0.45 m x
/// 0.9 m at 1.5 m) moved along its ray to depth 1.5 m; NaN pixels stay NaN.
std::vector<Eigen::Vector3f> with_person(std::vector<Eigen::Vector3f> points) {
    for (int v = 80; v < 400; ++v) {
        for (int u = 240; u < 400; ++u) {
            Eigen::Vector3f& p = points[static_cast<std::size_t>(v) * 640U + static_cast<std::size_t>(u)];
            if (p.allFinite() && p.z() > 0.0F) {
                p *= 1.5F / p.z();
            }
        }
    }
    return points;
}

/// The zone of issue 24's trial: one protective box over the whole view.
struct WholeViewZone {
    std::vector<std::uint32_t> mask;
    CompiledZones zones;
    explicit WholeViewZone(const GridGeometry& g) : mask(g.voxel_count()) {
        ZoneConfig z;
        z.box_min = Eigen::Vector3d(0.45, -1.5, -0.5);
        z.box_max = Eigen::Vector3d(3.5, 1.5, 1.5);
        z.max_unseen_voxels = 1000000U;
        zones = CompiledZones::compile(g, {&z, 1U}, {mask.data(), mask.size()}).value();
    }
};

/// The prior commissioned from the sensors' @p frame alone, given as many
/// times as min_background_frames asks for @p method. The frame is fused
/// once (fuse_background_frame) and its fused grid accumulated again for
/// each further copy: fuse_background_frame is clear, fuse_frame and
/// accumulate_background, so G_B is the same, bit for bit.
std::vector<std::int16_t> prior_from(const GridGeometry& g, Span<const SensorReading> frame, PriorMethod method) {
    AccessibilityParams params;
    params.method = method;
    const SensorModelTable model;
    const std::uint32_t frames = min_background_frames(params, model);
    REQUIRE(frames >= 1U);
    Grid background(g);
    Grid scratch_frame(g);
    REQUIRE(
        fuse_background_frame(background.grid, scratch_frame.grid, frame, model, scratch_frame.fusion_scratch()).ok());
    for (std::uint32_t k = 1; k < frames; ++k) {
        REQUIRE(accumulate_background(background.grid, scratch_frame.grid).ok());
    }
    const AccessibilityScratchSize size = accessibility_scratch_size(g.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    std::vector<std::int16_t> prior(g.voxel_count());
    REQUIRE(
        compute_accessibility_prior(background.grid, params,
                                    AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
                                    {prior.data(), prior.size()}, {})
            .ok());
    return prior;
}

/// The zone's report for @p frame fused alone against @p prior.
ZoneReport replay(const GridGeometry& g, const SensorReading& frame, const std::vector<std::int16_t>& prior,
                  const WholeViewZone& zone) {
    Grid fused(g);
    REQUIRE(fuse_frame(fused.grid, {&frame, 1U}, SensorModelTable{}, fused.fusion_scratch()).ok());
    ZoneEvaluation eval;
    REQUIRE(evaluate_zones(fused.grid, {prior.data(), prior.size()}, zone.zones, ZoneEvaluationParams{}, eval).ok());
    return eval.zones[0];
}

}  // namespace

// verifies: SR-FUSE-002
TEST_CASE("real frames: every voxel that holds readings is occupied, though hundreds of rays of the frame cross it") {
    const GridGeometry g = grid_geometry();
    for (const char* path : kFrames) {
        CAPTURE(std::string(path));
        const std::vector<Eigen::Vector3f> points = read_frame(path);
        const SensorReading r = point_reading(points);
        Grid fused(g);
        REQUIRE(fuse_sensor(fused.grid, r, SensorModelTable{}, fused.fusion_scratch()).ok());
        const std::set<std::size_t> holding = voxels_holding_readings(g, r);
        std::size_t not_occupied = 0;
        for (const std::size_t v : holding) {
            not_occupied += fused.lo[v] <= 0 ? 1U : 0U;
        }
        MESSAGE(std::string(path).substr(std::string(path).rfind('/') + 1)
                << ": " << holding.size() << " voxels hold readings, " << not_occupied << " of them not occupied");
        CHECK(holding.size() > 800U);  // the per-ray model lost 221 to 259 of about 900 (issue 24)
        CHECK(not_occupied == 0U);
    }
}

// verifies: SR-FUSE-002
TEST_CASE("real frames: shuffled readings give the identical grid") {
    const GridGeometry g = grid_geometry();
    for (const char* path : kFrames) {
        CAPTURE(std::string(path));
        std::vector<Eigen::Vector3f> points = read_frame(path);
        Grid in_order(g);
        REQUIRE(fuse_sensor(in_order.grid, point_reading(points), SensorModelTable{}, in_order.fusion_scratch()).ok());
        std::mt19937 rng(20261125U);
        std::shuffle(points.begin(), points.end(), rng);
        Grid shuffled(g);
        REQUIRE(fuse_sensor(shuffled.grid, point_reading(points), SensorModelTable{}, shuffled.fusion_scratch()).ok());
        CHECK(in_order.lo == shuffled.lo);
        CHECK(in_order.ob == shuffled.ob);
    }
}

// verifies: SR-FUSE-006
TEST_CASE("real frames: the ray table gives the grid of on-the-fly fusion, voxel for voxel") {
    const GridGeometry g = grid_geometry();
    for (const char* path : kFrames) {
        CAPTURE(std::string(path));
        const std::vector<float> depth = depth_of(read_frame(path));
        const SensorReading r = depth_reading(depth);
        host::OwnedRayTable table;
        REQUIRE(table.build(g, r).ok());
        Grid direct(g);
        Grid tabled(g);
        REQUIRE(fuse_sensor(direct.grid, r, SensorModelTable{}, direct.fusion_scratch()).ok());
        REQUIRE(table.table().fuse(tabled.grid, r.depth, SensorModelTable{}).ok());
        std::size_t differ = 0;
        std::size_t occupied_differ = 0;
        for (std::size_t v = 0; v < g.voxel_count(); ++v) {
            differ += (direct.lo[v] != tabled.lo[v] || direct.ob[v] != tabled.ob[v]) ? 1U : 0U;
            occupied_differ += ((direct.lo[v] > 0) != (tabled.lo[v] > 0)) ? 1U : 0U;
        }
        MESSAGE(std::string(path).substr(std::string(path).rfind('/') + 1)
                << ": " << differ << " voxels differ, " << occupied_differ << " in occupied or not");
        // Voxel for voxel (the per-ray model: 169, 169 and 189 voxels; before
        // readings on a face were placed by fuse_sensor's rule: 2, 4 and 3).
        CHECK(differ == 0U);
    }
}

// verifies: SR-FUSE-002, SR-EVAL-003
TEST_CASE(
    "real frames: replayed against a prior commissioned from itself a frame is CLEAR, and with a person INTRUDED, "
    "with both methods") {
    const GridGeometry g = grid_geometry();
    const WholeViewZone zone(g);
    for (const char* path : kFrames) {
        const std::vector<Eigen::Vector3f> points = read_frame(path);
        const std::vector<Eigen::Vector3f> person = with_person(points);
        for (const PriorMethod method : {PriorMethod::kThresholded, PriorMethod::kProbabilistic}) {
            CAPTURE(std::string(path));
            CAPTURE(static_cast<int>(method));
            const SensorReading background = point_reading(points);
            const std::vector<std::int16_t> prior = prior_from(g, {&background, 1U}, method);
            const ZoneReport empty = replay(g, point_reading(points), prior, zone);
            const ZoneReport intruded = replay(g, point_reading(person), prior, zone);
            MESSAGE(std::string(path).substr(std::string(path).rfind('/') + 1)
                    << " method " << static_cast<int>(method) << ": background " << empty.foreground
                    << " foreground voxels, with the person " << intruded.foreground);
            CHECK(empty.state == ZoneState::kClear);
            CHECK(empty.foreground == 0U);
            CHECK(intruded.state == ZoneState::kIntruded);
            CHECK(intruded.foreground > 50U);
        }
    }
}

// verifies: SR-FUSE-002, SR-EVAL-003
TEST_CASE("simulated cell at 640 x 480: the background is CLEAR and the scripted person detected, with both methods" *
          CELLGUARD_LONG_REPLAY) {
    // The paper's cell with its four sensors at a real camera's resolution
    // (four times the stereo cameras' pixels, eleven times the lidars').
    std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    for (sim::SensorSpec& s : sensors) {
        s.width = 640;
        s.height = 480;
    }
    const GridGeometry g = paper_grid_geometry();
    const cell::MonitorConfig demo = cell::demo_config();
    std::vector<ZoneConfig> configs;
    for (const cell::ZoneSettings& z : demo.zones) {
        configs.push_back(z.zone);
    }
    std::vector<std::uint32_t> mask(g.voxel_count());
    const CompiledZones zones =
        CompiledZones::compile(g, {configs.data(), configs.size()}, {mask.data(), mask.size()}).value();
    const sim::SimulatedFrame empty = sim::render_frame(sensors, sim::reference_scene());
    sim::Scene with_person = sim::reference_scene();
    with_person.boxes.push_back(cell::person_box(cell::demo_person(18)));  // in the protective zone
    const sim::SimulatedFrame person = sim::render_frame(sensors, with_person);
    const SensorModelTable model;
    for (const PriorMethod method : {PriorMethod::kThresholded, PriorMethod::kProbabilistic}) {
        CAPTURE(static_cast<int>(method));
        const std::vector<std::int16_t> prior = prior_from(g, {empty.readings.data(), empty.readings.size()}, method);
        const auto evaluate = [&](const sim::SimulatedFrame& f) {
            Grid fused(g);
            REQUIRE(fuse_frame(fused.grid, {f.readings.data(), f.readings.size()}, model, fused.fusion_scratch()).ok());
            ZoneEvaluation eval;
            REQUIRE(evaluate_zones(fused.grid, {prior.data(), prior.size()}, zones, ZoneEvaluationParams{}, eval).ok());
            return eval;
        };
        const ZoneEvaluation bg = evaluate(empty);
        const ZoneEvaluation in = evaluate(person);
        MESSAGE("method " << static_cast<int>(method) << ": background foreground voxels " << bg.zones[0].foreground
                          << " / " << bg.zones[1].foreground << ", with the person " << in.zones[0].foreground << " / "
                          << in.zones[1].foreground);
        CHECK(bg.zones[0].state == ZoneState::kClear);
        CHECK(bg.zones[1].state == ZoneState::kClear);
        CHECK(in.zones[0].state == ZoneState::kIntruded);  // the protective zone
        CHECK(in.zones[1].state == ZoneState::kIntruded);  // the warning zone around it
    }
}

// verifies: SR-FUSE-009, SR-FUSE-010
TEST_CASE(
    "real frames: footprint fusion keeps every hit, calls nothing free the exact path does not, and "
    "leaves at most 17 % of its free voxels unknown") {
    const GridGeometry g = grid_geometry();
    const SensorModelTable model;
    for (const char* path : kFrames) {
        CAPTURE(std::string(path));
        const std::vector<float> depth = depth_of(read_frame(path));
        const SensorReading r = depth_reading(depth);
        Grid direct(g);
        REQUIRE(fuse_sensor(direct.grid, r, model, direct.fusion_scratch()).ok());
        host::OwnedFootprintWorkspaces owned(g, 1U, 640, 480);
        const FootprintWorkspace ws = owned.spans()[0];
        REQUIRE(footprint_opinions(g, r, model, ws, nullptr).ok());
        std::size_t exact_free = 0;
        std::size_t unknown = 0;
        std::size_t weaker = 0;
        std::size_t wrong = 0;  // a hit lost or added, free where the exact path has none, or stronger
        for (std::size_t v = 0; v < g.voxel_count(); ++v) {
            const std::int16_t e = direct.scratch[v];
            const std::int16_t f = ws.opinions[v];
            const bool e_hit = e == model.reading_evidence();
            const bool f_hit = f == model.reading_evidence();
            wrong += (e_hit != f_hit || (e == kNoOpinion && f != kNoOpinion) || (!e_hit && f != kNoOpinion && f < e))
                         ? 1U
                         : 0U;
            if (e != kNoOpinion && !e_hit) {
                ++exact_free;
                unknown += f == kNoOpinion ? 1U : 0U;
                weaker += (f != kNoOpinion && f > e) ? 1U : 0U;
            }
        }
        const double lost = static_cast<double>(unknown) / static_cast<double>(exact_free);
        MESSAGE("exact free " << exact_free << ", unknown here " << unknown << " (" << 100.0 * lost << " %), weaker "
                              << weaker << ", wrong " << wrong);
        CHECK(exact_free > 2000U);
        CHECK(wrong == 0U);
        // 2026-12-06: 16.3 to 16.6 % on the three frames, the same voxels as the box subdivision
        // with its exact per-ray step gave before it (whose budget never reached these footprints
        // of more than 64 pixels): the voxels that only rays outside the inner square cross.
        CHECK(lost <= 0.17);
    }
}
