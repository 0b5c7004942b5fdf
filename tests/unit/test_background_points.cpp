// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: recorded (point-set) sensors have a commissioned view of the
// empty cell too (issue 21 part 3, hazards H-PRI-3, H-SEN-3): per direction
// bin the farthest and nearest commissioning range (direction_grid.hpp),
// stored in the background view image as a kind-1 record, compared point by
// point with the same rule and the same latch as a depth image's pixels.
// The point sets are the simulated paper cell's depth images turned into
// points in each sensor's frame, as a recorded .pcd of the cell would hold.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/firmware/scenario.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/host/io/background_files.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/prior/background_image.hpp"
#include "cellguard/prior_tool/prior_tool.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "paper_cell.hpp"
#include "test_tags.hpp"

using namespace cellguard;

namespace {

class StepClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t += 1U; }
    std::uint64_t t = 1000000U;
};

// The direction grid of a simulated sensor's point-set view, as the monitor
// and the prior tool derive it from a recorded sensor's configuration.
DirectionGrid grid_of(const sim::SensorSpec& s) {
    return recorded_view_grid(s.hfov_deg, s.vfov_deg, s.width, s.height);
}

// The paper cell with its prior and each sensor's direction-grid view of
// the empty cell, made from its render's points (8 identical frames, as
// --write-background makes it from the recorded frames).
struct Cell {
    GridGeometry g = paper_grid_geometry();
    std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const test::PaperCellCommissioning& commissioned = test::paper_cell_commissioning();  // built once, read-only
    std::vector<std::int16_t> frame_lo = commissioned.frame_log_odds;
    std::vector<std::int16_t> prior = commissioned.prior;
    std::vector<std::int16_t> scratch = commissioned.scratch;
    std::vector<std::uint8_t> frame_ob = commissioned.frame_observed;
    std::vector<std::uint32_t> mask;
    EvidenceGrid frame_grid;
    CompiledZones zones;
    SensorModelTable model;
    std::vector<std::vector<float>> views;
    std::vector<BackgroundReference> refs;

    Cell() : mask(g.voxel_count()), refs(sensors.size()) {
        const sim::SimulatedFrame& empty = commissioned.empty;
        frame_grid =
            EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
        const auto zs = firmware::scenario_zone_configs();
        zones = CompiledZones::compile(g, {zs.data(), zs.size()}, {mask.data(), mask.size()}).value();
        for (std::size_t s = 0; s < sensors.size(); ++s) {
            PointViewBuilder b(grid_of(sensors[s]));
            for (int k = 0; k < 8; ++k)
                REQUIRE(b.add(empty.readings[s]));
            views.push_back(b.values());
        }
        for (std::size_t s = 0; s < sensors.size(); ++s) {
            const std::size_t bins = views[s].size() / 2U;
            refs[s].grid = grid_of(sensors[s]);
            refs[s].depth = Span<const float>(views[s].data(), bins);
            refs[s].nearest = Span<const float>(views[s].data() + bins, bins);
        }
    }

    SafetyController controller(MonotonicClock& clock) {
        return SafetyController(firmware::scenario_controller_config(sensors.size()), frame_grid,
                                {scratch.data(), scratch.size()}, {prior.data(), prior.size()}, zones, model, clock,
                                nullptr);
    }
};

// A point-set reading of sensor @p spec (commissioned pose) holding @p points.
SensorReading point_reading(const sim::SensorSpec& spec, const std::vector<Eigen::Vector3f>& points) {
    SensorReading r;
    r.pose = spec.pose();
    r.kind = SensorDataKind::kPointSet;
    r.points = Span<const Eigen::Vector3f>(points.data(), points.size());
    r.max_range = spec.max_range;
    return r;
}

// One cycle's point-set inputs: sensor s renders @p scene with @p specs[s],
// its points read in the commissioned pose of cell.sensors[s].
struct Inputs {
    std::vector<std::vector<Eigen::Vector3f>> points;
    std::vector<SensorInput> in;
    Inputs(const Cell& cell, const std::vector<sim::SensorSpec>& specs, const sim::Scene& scene, std::uint64_t now) {
        const sim::SimulatedFrame f = sim::render_frame(specs, scene);
        for (const SensorReading& r : f.readings)
            points.push_back(depth_image_points(r));
        add(cell, points, now);
    }
    // The empty cell from the commissioned poses: the points of the shared
    // render of it (render_frame of the same sensors and scene gives these images, bit for bit).
    Inputs(const Cell& cell, std::uint64_t now) { add(cell, empty_points(), now); }
    void add(const Cell& cell, const std::vector<std::vector<Eigen::Vector3f>>& sensor_points, std::uint64_t now) {
        for (std::size_t s = 0; s < sensor_points.size(); ++s) {
            SensorInput i;
            i.reading = point_reading(cell.sensors[s], sensor_points[s]);
            i.captured_us = now;
            i.present = true;
            i.background = &cell.refs[s];
            in.push_back(i);
        }
    }
    // Each sensor's points of the empty cell, made once per process from the shared render (read-only).
    static const std::vector<std::vector<Eigen::Vector3f>>& empty_points() {
        static const std::vector<std::vector<Eigen::Vector3f>> points = [] {
            std::vector<std::vector<Eigen::Vector3f>> p;
            for (const SensorReading& r : test::paper_cell_commissioning().empty.readings)
                p.push_back(depth_image_points(r));
            return p;
        }();
        return points;
    }
    Span<const SensorInput> span() const { return {in.data(), in.size()}; }
};

struct ChangeRun {
    int detected_cycle = 0;  // first cycle after the change with kPriorCheckFailed (0: never)
    std::uint32_t max_longer = 0U;
    std::uint32_t changed_sensors = 0U;
    bool stop_after = false;
    bool stays_latched = true;
};

// The cycles a changed view is shown: the stated detection bound (BackgroundReference::changed_cycles'
// default) and one more, so a fault found later than the bound fails the check, not the run's length.
constexpr int kBound = 3;
constexpr int kChangedCycles = kBound + 1;
// The cycles of the empty cell after the change: the latch must hold through them.
constexpr int kCyclesAfter = 2;

// Two cycles of the empty cell, @p cycles of @p specs seeing @p scene, then the empty cell again.
ChangeRun run_change(const std::vector<sim::SensorSpec>& specs, const sim::Scene& scene, int cycles) {
    Cell cell;
    StepClock clock;
    SafetyController c = cell.controller(clock);
    ChangeRun out;
    for (int k = 0; k < 2; ++k) {
        const Inputs empty(cell, clock.t);
        REQUIRE(c.run_cycle(empty.span(), false).detected_faults == 0U);
        for (std::size_t s = 0; s < cell.sensors.size(); ++s)
            REQUIRE(c.background_change().last[s].longer == 0U);
    }
    Inputs changed(cell, specs, scene, clock.t);
    for (int k = 1; k <= cycles; ++k) {
        for (SensorInput& i : changed.in)
            i.captured_us = clock.t;
        const CycleReport& r = c.run_cycle(changed.span(), false);
        for (std::size_t s = 0; s < specs.size(); ++s)
            out.max_longer = std::max(out.max_longer, c.background_change().last[s].longer);
        if (out.detected_cycle == 0 && (r.detected_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U) {
            out.detected_cycle = k;
            out.stop_after = r.safety.stop_requested;
        }
    }
    out.changed_sensors = c.background_change().latched;
    for (int k = 0; k < kCyclesAfter; ++k) {
        const Inputs empty(cell, clock.t);
        const CycleReport& r = c.run_cycle(empty.span(), false);
        out.stays_latched = out.stays_latched && r.safety.stop_requested &&
                            (r.safety.latched_faults & fault_bit(Fault::kPriorCheckFailed)) != 0U;
    }
    return out;
}

void report(const char* what, const ChangeRun& r) {
    std::printf(
        "point-set background change: %s: detected in cycle %d, up to %u deeper points per sensor, "
        "sensors 0x%x\n",
        what, r.detected_cycle, r.max_longer, r.changed_sensors);
}

std::vector<sim::SensorSpec> turned(std::vector<sim::SensorSpec> specs, std::size_t s, double degrees, bool pitch) {
    const Eigen::Vector3d view = specs[s].target - specs[s].position;
    const Eigen::Vector3d axis = pitch ? view.cross(Eigen::Vector3d::UnitZ()).normalized() : Eigen::Vector3d::UnitZ();
    specs[s].target = specs[s].position + Eigen::AngleAxisd(degrees * M_PI / 180.0, axis) * view;
    return specs;
}

// A one-bin-per-degree grid of 10 x 10 bins around the axis, with bin (5, 5)
// (straight ahead, slightly right and up) at 2.0 .. 2.1 m, the rest no return.
struct SmallView {
    DirectionGrid grid{-5.0F * 0.017453292F, -5.0F * 0.017453292F, 0.017453292F, 10U, 10U};
    std::vector<float> far = std::vector<float>(100U, 0.0F);
    std::vector<float> near = std::vector<float>(100U, 0.0F);
    BackgroundReference ref;
    SmallView() {
        far[55] = 2.1F;
        near[55] = 2.0F;
        ref.grid = grid;
        ref.depth = Span<const float>(far.data(), far.size());
        ref.nearest = Span<const float>(near.data(), near.size());
    }
};

// A point at @p range along azimuth @p az_deg and elevation @p el_deg (sensor frame).
Eigen::Vector3f along(float az_deg, float el_deg, float range) {
    const float az = az_deg * 0.017453292F;
    const float el = el_deg * 0.017453292F;
    return {range * std::cos(el) * std::sin(az), -range * std::sin(el), range * std::cos(el) * std::cos(az)};
}

}  // namespace

// verifies: SR-BKG-007
TEST_CASE("point-set view: a point deeper than its bin counts, nearer or in a bin without a return never does") {
    SmallView v;
    std::vector<Eigen::Vector3f> pts = {
        along(0.5F, 0.5F, 2.05F),     // within the bin's range: matches
        along(0.5F, 0.5F, 1.96F),     // nearer than nearest, within the tolerance: matches
        along(0.5F, 0.5F, 1.0F),      // a person in front: referenced, neither matching nor deeper
        along(0.5F, 0.5F, 2.2F),      // 0.1 m beyond the farthest: deeper
        along(0.5F, 0.5F, 2.14F),     // within farthest + tolerance: matches
        along(-3.5F, 0.5F, 9.0F),     // a bin without a background return: never counts
        along(20.0F, 0.0F, 9.0F),     // outside the grid's field of view: counted apart
        {0.0F, 0.0F, 0.0F},           // at the origin: left out
        {std::nanf(""), 0.0F, 1.0F},  // not finite: left out
    };
    const Result<BackgroundMatch> m = match_points({pts.data(), pts.size()}, v.ref);
    REQUIRE(m.ok());
    CHECK(m.value().referenced == 5U);
    CHECK(m.value().matching == 3U);
    CHECK(m.value().longer == 1U);
    CHECK(m.value().outside == 1U);
    // The reading overload takes a point set to match_points.
    SensorReading r;
    r.kind = SensorDataKind::kPointSet;
    r.points = Span<const Eigen::Vector3f>(pts.data(), pts.size());
    const Result<BackgroundMatch> again = match_background(r, v.ref);
    REQUIRE(again.ok());
    CHECK(again.value().longer == 1U);

    // Refusals: a bad grid, view spans of the wrong size, a bad tolerance, a depth image against a point view.
    BackgroundReference bad = v.ref;
    bad.grid.bin_rad = 0.0F;
    CHECK(match_points({pts.data(), pts.size()}, bad).error() == ErrorCode::kInvalidArgument);
    bad = v.ref;
    bad.grid.azimuth_min_rad = std::nanf("");
    CHECK(match_points({pts.data(), pts.size()}, bad).error() == ErrorCode::kNonFiniteValue);
    bad = v.ref;
    bad.grid.azimuth_bins = 400U;  // beyond pi
    CHECK(match_points({pts.data(), pts.size()}, bad).error() == ErrorCode::kInvalidArgument);
    bad = v.ref;
    bad.nearest = Span<const float>(v.near.data(), 99U);
    CHECK(match_points({pts.data(), pts.size()}, bad).error() == ErrorCode::kMalformedInput);
    bad = v.ref;
    bad.tolerance_m = 0.0F;
    CHECK(match_points({pts.data(), pts.size()}, bad).error() == ErrorCode::kInvalidArgument);
    SensorReading image;
    image.kind = SensorDataKind::kDepthImage;
    image.depth = Span<const float>(v.far.data(), v.far.size());
    CHECK(match_background(image, v.ref).error() == ErrorCode::kInvalidArgument);
    // A point set against a depth image's view (no grid) is refused as before.
    BackgroundReference pixels;
    pixels.depth = Span<const float>(v.far.data(), v.far.size());
    CHECK_FALSE(match_background(r, pixels).ok());
    // Too many bins.
    DirectionGrid huge{-3.1F, -1.5F, 1e-5F, 60000U, 60000U};
    CHECK(check_direction_grid(huge).error() == ErrorCode::kCapacityExceeded);
}

// verifies: SR-BKG-007
TEST_CASE("point-set view: commissioning frames widen each bin to their nearest and farthest range") {
    SmallView v;
    std::vector<float> far(100U, 0.0F);
    std::vector<float> near(100U, 0.0F);
    const std::vector<Eigen::Vector3f> a = {
        along(0.5F, 0.5F, 2.05F), along(0.2F, 0.8F, 2.0F), along(30.0F, 0.0F, 1.0F), {0.0F, 0.0F, 0.0F}};
    const std::vector<Eigen::Vector3f> b = {along(0.6F, 0.4F, 2.1F)};
    const Result<DirectionViewAdded> ra = add_to_direction_view({a.data(), a.size()}, v.grid, {far.data(), 100U},
                                                                {near.data(), 100U});
    REQUIRE(ra.ok());
    CHECK(ra.value().binned == 2U);
    CHECK(ra.value().outside == 1U);
    CHECK(ra.value().invalid == 1U);
    REQUIRE(add_to_direction_view({b.data(), b.size()}, v.grid, {far.data(), 100U}, {near.data(), 100U}).ok());
    CHECK(far[55] == doctest::Approx(2.1F));
    CHECK(near[55] == doctest::Approx(2.0F));
    CHECK(std::count(far.begin(), far.end(), 0.0F) == 99);
    CHECK(add_to_direction_view({b.data(), b.size()}, v.grid, {far.data(), 99U}, {near.data(), 100U}).error() ==
          ErrorCode::kMalformedInput);
}

// verifies: SR-BKG-008
TEST_CASE(
    "point-set background change: the empty cell gives no deeper point, moved and removed boxes latch in 3 "
    "cycles" *
    CELLGUARD_LONG_REPLAY) {
    // The empty cell: run_change checks 0 deeper points in the two empty cycles; here a whole run of it.
    const ChangeRun none = run_change(sim::paper_sensors(), sim::reference_scene(), 6);
    report("empty cell", none);
    CHECK(none.detected_cycle == 0);
    CHECK(none.max_longer == 0U);
    for (const double dx : {0.1, -0.1}) {
        sim::Scene moved = sim::reference_scene();
        moved.boxes[0].center.x() += dx;
        const ChangeRun r = run_change(sim::paper_sensors(), moved, kChangedCycles);
        report(dx > 0.0 ? "box A moved +10 cm in x" : "box A moved -10 cm in x", r);
        CHECK(r.detected_cycle == kBound);
        CHECK(r.stop_after);
        CHECK(r.stays_latched);
    }
    sim::Scene moved = sim::reference_scene();
    moved.boxes[1].center.y() += 0.1;
    const ChangeRun rb = run_change(sim::paper_sensors(), moved, kChangedCycles);
    report("box B moved +10 cm in y", rb);
    CHECK(rb.detected_cycle == kBound);
    for (std::size_t b = 0; b < 2U; ++b) {
        sim::Scene removed = sim::reference_scene();
        removed.boxes.erase(removed.boxes.begin() + static_cast<std::ptrdiff_t>(b));
        const ChangeRun r = run_change(sim::paper_sensors(), removed, kChangedCycles);
        report(b == 0U ? "box A removed" : "box B removed", r);
        CHECK(r.detected_cycle == kBound);
        CHECK(r.stays_latched);
    }
}

// verifies: SR-BKG-008
TEST_CASE("point-set background change: a sensor turned by 1 degree latches the prior fault within 3 cycles" *
          CELLGUARD_LONG_REPLAY) {
    for (std::size_t s = 0; s < 4U; ++s) {
        for (const double deg : {1.0, -1.0}) {
            for (const bool pitch : {true, false}) {
                const ChangeRun r = run_change(turned(sim::paper_sensors(), s, deg, pitch), sim::reference_scene(),
                                               kChangedCycles);
                char what[64];
                std::snprintf(what, sizeof what, "sensor %zu %s %+.0f degree", s, pitch ? "pitched" : "yawed", deg);
                report(what, r);
                CAPTURE(what);
                CHECK(r.detected_cycle == kBound);
                CHECK(r.changed_sensors == (1U << s));
                CHECK(r.stays_latched);
            }
        }
    }
}

// verifies: SR-BKG-008
TEST_CASE("point-set background change: the demo's walking person never trips it" * CELLGUARD_LONG_REPLAY) {
    Cell cell;
    StepClock clock;
    SafetyController c = cell.controller(clock);
    std::vector<cell::SimulatedFrameSource> sources;
    sources.reserve(cell.sensors.size());
    for (const sim::SensorSpec& spec : cell.sensors)
        sources.emplace_back(spec);
    std::vector<SensorInput> in(cell.sensors.size());
    std::vector<std::vector<Eigen::Vector3f>> points(cell.sensors.size());
    std::uint32_t max_longer = 0U;
    double min_fraction = 1.0;
    bool person_stop = false;
    for (int k = 0; k < 120; ++k) {
        for (std::size_t s = 0; s < in.size(); ++s) {
            cell::FrameStatus status;
            SensorReading image;
            REQUIRE(sources[s].load_frame(static_cast<std::uint64_t>(k), image, status));
            points[s] = depth_image_points(image);
            in[s].reading = point_reading(cell.sensors[s], points[s]);
            in[s].captured_us = clock.t;
            in[s].present = true;
            in[s].background = &cell.refs[s];
        }
        const CycleReport& r = c.run_cycle({in.data(), in.size()}, false);
        CHECK((r.detected_faults & fault_bit(Fault::kPriorCheckFailed)) == 0U);
        CHECK((r.detected_faults & fault_bit(Fault::kFrameInconsistent)) == 0U);
        person_stop = person_stop || r.safety.stop_requested;
        for (std::size_t s = 0; s < in.size(); ++s) {
            const BackgroundMatch m = c.background_change().last[s];
            max_longer = std::max(max_longer, m.longer);
            min_fraction = std::min(min_fraction, static_cast<double>(m.matching) / m.referenced);
        }
    }
    std::printf(
        "point-set background change: demo person, 120 cycles: at most %u deeper points per sensor "
        "(limit %u), at least %.3f of the referenced points matched (limit 0.5)\n",
        max_longer, BackgroundReference{}.max_longer_pixels, min_fraction);
    CHECK(person_stop);
    CHECK(c.background_change().latched == 0U);
    CHECK(max_longer <= BackgroundReference{}.max_longer_pixels);
}

namespace {

// An image of one direction-grid view (sensor "recorded") for @p prior_crc.
std::vector<std::uint8_t> grid_image(const SmallView& v, std::uint32_t prior_crc, BackgroundSensorIdentity& id) {
    id = point_view_identity("recorded", Eigen::Isometry3d::Identity(), v.grid);
    std::vector<float> values(v.far);
    values.insert(values.end(), v.near.begin(), v.near.end());
    BackgroundViewRecord rec{id, Span<const float>(values.data(), values.size())};
    std::vector<std::uint8_t> bytes(background_image_size({&rec, 1U}));
    REQUIRE(write_background_image({&rec, 1U}, prior_crc, 8U, {bytes.data(), bytes.size()}).ok());
    return bytes;
}

void put_u32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
    for (std::size_t i = 0; i < 4U; ++i)
        b[at + i] = static_cast<std::uint8_t>(v >> (8U * i));
}

// Recomputes the first record's header CRC (and its payload CRC first).
void fix_record(std::vector<std::uint8_t>& b) {
    const std::size_t rec = kBackgroundImageHeaderSize;
    std::uint32_t len = 0U;
    std::memcpy(&len, &b[rec + 104U], 4U);
    put_u32(b, rec + 108U, crc32(Span<const std::uint8_t>(&b[rec + kBackgroundRecordHeaderSize], len)));
    put_u32(b, rec + 116U, crc32(Span<const std::uint8_t>(&b[rec], 116U)));
}

}  // namespace

// verifies: SR-BKG-009
TEST_CASE("point-set view image: a direction-grid record round-trips, bad ones are refused") {
    SmallView v;
    BackgroundSensorIdentity id;
    const std::vector<std::uint8_t> good = grid_image(v, 0xB03ED028U, id);
    CHECK(good.size() == kBackgroundImageHeaderSize + kBackgroundRecordHeaderSize + 8U * 100U);
    CHECK(background_view_values(id) == 200U);
    const Span<const std::uint8_t> image(good.data(), good.size());
    std::vector<float> out(200U, -1.0F);
    const Result<std::size_t, BackgroundImageError> n = load_background_view(image, 1U, 0xB03ED028U, 0U, id,
                                                                             {out.data(), out.size()});
    REQUIRE(n.ok());
    CHECK(n.value() == 200U);
    CHECK(out[55] == 2.1F);
    CHECK(out[155] == 2.0F);
    const DirectionGrid back = direction_grid_of(id);
    CHECK(back.bin_rad == v.grid.bin_rad);
    CHECK(back.azimuth_bins == 10U);

    // Another kind than the configured sensor's (a depth image of the same size): kWrongSensor.
    BackgroundSensorIdentity pixels = id;
    pixels.kind = kBackgroundViewDepthImage;
    CHECK(load_background_view(image, 1U, 0xB03ED028U, 0U, pixels, {out.data(), out.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    // Another grid (bin size) than configured: kWrongSensor.
    DirectionGrid other = v.grid;
    other.bin_rad *= 0.5F;
    CHECK(load_background_view(image, 1U, 0xB03ED028U, 0U,
                               point_view_identity("recorded", Eigen::Isometry3d::Identity(), other),
                               {out.data(), out.size()})
              .error() == BackgroundImageError::kWrongSensor);
    // Another prior: kPriorCrcMismatch. Storage for only the farthest half: kStorageTooSmall.
    CHECK(check_background_image(image, 1U, 0x12345678U).error() == BackgroundImageError::kPriorCrcMismatch);
    CHECK(load_background_view(image, 1U, 0xB03ED028U, 0U, id, {out.data(), 100U}).error() ==
          BackgroundImageError::kStorageTooSmall);
    // Truncated inside the nearest half; one byte of a range changed (payload CRC).
    CHECK(check_background_image(image.subspan(0U, good.size() - 4U), 1U, 0xB03ED028U).error() ==
          BackgroundImageError::kRecordTruncated);
    std::vector<std::uint8_t> b = good;
    b[good.size() - 300U] ^= 0x01U;
    CHECK(check_background_image({b.data(), b.size()}, 1U, 0xB03ED028U).error() ==
          BackgroundImageError::kPayloadCrcMismatch);
    // An unknown kind, a grid beyond the sphere, a payload length of the depth-image kind (CRCs fixed up):
    // kBadRecord.
    const std::size_t rec = kBackgroundImageHeaderSize;
    b = good;
    put_u32(b, rec + 12U, 2U);
    fix_record(b);
    CHECK(check_background_image({b.data(), b.size()}, 1U, 0xB03ED028U).error() == BackgroundImageError::kBadRecord);
    b = good;
    put_u32(b, rec + 4U, 400U);  // 400 azimuth bins of 1 degree
    fix_record(b);
    CHECK(check_background_image({b.data(), b.size()}, 1U, 0xB03ED028U).error() == BackgroundImageError::kBadRecord);
    b = good;
    put_u32(b, rec + 104U, 400U);
    fix_record(b);
    CHECK(check_background_image({b.data(), b.size()}, 1U, 0xB03ED028U).error() == BackgroundImageError::kBadRecord);
    // A bin whose nearest exceeds its farthest, and one with only a nearest: kDepthOutOfRange.
    for (const std::size_t bin : {55U, 56U}) {
        b = good;
        const float bad = 3.0F;
        std::memcpy(&b[rec + kBackgroundRecordHeaderSize + 4U * (100U + bin)], &bad, 4U);
        fix_record(b);
        CHECK(check_background_image({b.data(), b.size()}, 1U, 0xB03ED028U).error() ==
              BackgroundImageError::kDepthOutOfRange);
    }
    // The writer refuses such values and a bad grid.
    std::vector<float> values(v.far);
    values.insert(values.end(), v.near.begin(), v.near.end());
    values[155] = 2.5F;
    BackgroundViewRecord r{id, Span<const float>(values.data(), values.size())};
    std::vector<std::uint8_t> bytes(good.size());
    CHECK(write_background_image({&r, 1U}, 1U, 8U, {bytes.data(), bytes.size()}).error() ==
          ErrorCode::kInvalidArgument);
    values[155] = 2.0F;
    r.identity.intrinsics[3] = 1.0;
    CHECK(write_background_image({&r, 1U}, 1U, 8U, {bytes.data(), bytes.size()}).error() ==
          ErrorCode::kInvalidArgument);
}

namespace {

std::string read_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream text;
    text << f.rdbuf();
    return text.str();
}

// apps/monitor/test/pcd-cell.toml with only its recorded sensor, its two good frames four times each (8
// frames: enough for the probabilistic prior), and @p prior_table as its [prior] table body.
std::string recorded_only_config(const std::string& prior_table, bool keep_lidar_a = false) {
    const std::string fixtures = CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd/";
    std::string text = read_text(CELLGUARD_SOURCE_DIR "/apps/monitor/test/pcd-cell.toml");
    const std::size_t first = text.find("[[sensors]]");
    const std::size_t recorded = text.find("[[sensors]]\nname = \"recorded\"");
    REQUIRE(first != std::string::npos);
    REQUIRE(recorded != std::string::npos);
    const std::size_t from = keep_lidar_a ? text.find("[[sensors]]", first + 1U) : first;
    text.erase(from, recorded - from);
    const std::size_t files = text.find("pcd_files = [");
    const std::size_t files_end = text.find("]\n", files);
    std::string list = "pcd_files = [";
    for (int i = 0; i < 4; ++i)
        list += std::string(i == 0 ? "" : ", ") + "\"" + fixtures + "recorded-ascii.pcd\", \"" + fixtures +
                "recorded-binary.pcd\"";
    text.replace(files, files_end + 1U - files, list + "]");
    const std::size_t prior = text.find("[prior]\n");
    const std::size_t prior_end = text.find("\n[", prior + 1U);
    text.replace(prior, prior_end - prior, "[prior]\n" + prior_table);
    return text;
}

}  // namespace

// verifies: SR-BKG-009
TEST_CASE("point-set view image: the prior tool writes recorded sensors' views, the monitor loads and uses them") {
    char templ[] = "/tmp/cellguard_test_points_XXXXXX";
    REQUIRE(::mkdtemp(templ) != nullptr);
    const std::string dir = templ;
    const std::string with_file = recorded_only_config(
        "source = \"file\"\nfile = \"" + dir + "/prior.cgprior\"\nbackground_file = \"" + dir + "/background.cgbv\"\n");
    {
        std::ofstream f(dir + "/cell.toml");
        f << with_file;
    }
    std::ostringstream out;
    std::ostringstream err;
    const int status = prior_tool::run_prior_tool({"--config", dir + "/cell.toml", "--config-frames", "--out", dir,
                                                   "--write-background", dir + "/background.cgbv"},
                                                  out, err, false);
    INFO(out.str() << err.str());
    REQUIRE(status == prior_tool::kExitOk);
    CHECK(out.str().find("1 recorded sensors' direction-grid views of the empty cell") != std::string::npos);
    CHECK(out.str().find("(0 points outside the grids)") != std::string::npos);

    const cell::ConfigLoad load = cell::parse_monitor_config(with_file, "cell.toml", dir);
    INFO(load.error);
    REQUIRE(load.ok);
    CHECK(load.config.background_match == 0.5F);  // the default: on, with a recorded sensor
    {
        monitor::MonitorCell c;
        REQUIRE_FALSE(c.configure(load.config).failed());
        REQUIRE_FALSE(c.build_prior(load.config, nullptr).failed());
        const monitor::SetupError e = c.build_tables(load.config, nullptr);
        INFO(e.message);
        REQUIRE_FALSE(e.failed());
        const BackgroundReference& ref = c.backgrounds.at(0);
        const cell::SensorSettings& s = load.config.sensors[0];
        const DirectionGrid grid = recorded_view_grid(s.hfov_deg, s.vfov_deg, s.width, s.height);
        CHECK(ref.grid.bin_count() == grid.bin_count());
        CHECK(ref.depth.size() == grid.bin_count());
        CHECK(ref.nearest.size() == grid.bin_count());
        // The recorded frame shows its view: nothing deeper, every point matching; the same points 10 % farther
        // (a sensor pulled back, or the wrong unit) are deeper than the view nearly everywhere.
        cell::PcdFrameSource src("recorded", s.pcd_files, cell::sensor_pose(s), s.width, s.height,
                                 static_cast<float>(s.max_range));
        SensorReading r;
        REQUIRE(src.load(0U, r).ok);
        const Result<BackgroundMatch> m = match_background(r, ref);
        REQUIRE(m.ok());
        CHECK(m.value().longer == 0U);
        CHECK(m.value().matching == m.value().referenced);
        CHECK(m.value().referenced == 191U);
        std::vector<Eigen::Vector3f> farther(r.points.begin(), r.points.end());
        for (Eigen::Vector3f& p : farther)
            p *= 1.1F;
        r.points = Span<const Eigen::Vector3f>(farther.data(), farther.size());
        const Result<BackgroundMatch> f = match_background(r, ref);
        REQUIRE(f.ok());
        std::printf(
            "point-set view of the recorded fixture: %u bins; the frame 10 %% farther: %u of %u points "
            "deeper\n",
            static_cast<unsigned>(grid.bin_count()), f.value().longer, f.value().referenced);
        CHECK(f.value().longer > ref.max_longer_pixels);
    }
    // A byte of the views changed: the monitor refuses to start.
    std::string bytes = read_text(dir + "/background.cgbv");
    REQUIRE(bytes.size() > 10U);
    bytes[bytes.size() - 10U] = static_cast<char>(bytes[bytes.size() - 10U] ^ 0x10);
    {
        std::ofstream f(dir + "/changed.cgbv", std::ios::binary);
        f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    cell::MonitorConfig changed = load.config;
    changed.prior.background_file = dir + "/changed.cgbv";
    {
        monitor::MonitorCell c;
        REQUIRE_FALSE(c.configure(changed).failed());
        REQUIRE_FALSE(c.build_prior(changed, nullptr).failed());
        const monitor::SetupError e = c.build_tables(changed, nullptr);
        CHECK(e.failed());
        CHECK(e.message.find("background views:") != std::string::npos);
    }
    // A prior file without the views, the checks on: refused, saying what to give.
    const cell::ConfigLoad no_views = cell::parse_monitor_config(
        recorded_only_config("source = \"file\"\nfile = \"" + dir + "/prior.cgprior\"\n"), "cell.toml", dir);
    CHECK_FALSE(no_views.ok);
    CHECK(no_views.error.find("give prior.background_file") != std::string::npos);
    // A simulated sensor beside the recorded one has no recorded frames, so no view from them: refused.
    {
        std::ofstream f(dir + "/mixed.toml");
        f << recorded_only_config("source = \"simulated-background\"\nbackground_frames = 8\n", true);
    }
    std::ostringstream out2;
    std::ostringstream err2;
    CHECK(prior_tool::run_prior_tool({"--config", dir + "/mixed.toml", "--config-frames", "--out", dir + "/mixed",
                                      "--write-background", dir + "/mixed.cgbv"},
                                     out2, err2, false) == prior_tool::kExitInputError);
    INFO(err2.str());
    CHECK(err2.str().find("sensor 'lidar-a' has no recorded frames") != std::string::npos);
    std::filesystem::remove_all(dir);
}

// verifies: SR-BKG-009
TEST_CASE("point-set view image: the fuzzer's direction-grid seeds are accepted images") {
    for (const char* name : {"valid_direction_grid", "valid_grid_and_depth"}) {
        CAPTURE(name);
        const std::string seed = read_text(
            std::string(CELLGUARD_SOURCE_DIR "/tests/fuzz/corpus/fuzz_background_image/") + name);
        REQUIRE(seed.size() > 1U);
        std::vector<std::uint8_t> img(seed.begin() + 1, seed.end());  // the mode byte first
        const Result<BackgroundImageInfo, BackgroundImageError> r = check_background_image({img.data(), img.size()},
                                                                                           img[8], 0x12345678U);
        CHECK(r.ok());
    }
}
