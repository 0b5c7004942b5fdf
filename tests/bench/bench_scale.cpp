// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Scale benchmark (issue 18, deliverable 5): footprint fusion
// (footprint_fusion.hpp) with real depth cameras in the whole cell, against
// the exact per-ray path (fuse_frame) and OctoMap on the same readings, in
// the same run. A program that prints figures, not a test with a time limit:
// time never decides the exit status.
//
// Cases (fresh grid per cycle, one thread):
// - real-5cm:   four 640 x 480 depth cameras (58 x 45 deg, max range 10 m)
//               at (+-1.9, +-1.9, 2.4) m, the upper corners of the
//               4 x 4 x 2.5 m cell (x, y in [-2, 2], floor z = 0), aimed at
//               the centre of the floor, into 80 x 80 x 50 voxels at 5 cm
//               (the whole cell, origin (-2, -2, 0));
// - real-2.5cm: the same readings into 160 x 160 x 100 at 2.5 cm;
// - paper:      the paper's sensors (sim::paper_sensors) in its 4 x 4 x 2 m
//               cell into the paper's grid (paper_grid_geometry, 34 x 30 x 30).
// Reading patterns (computed analytically per pixel, ray against boxes):
// - max-range: the empty cell, each reading 1 mm before where its ray leaves
//              the cell (its far wall or the floor): the longest reading in
//              the cell, so every ray crosses the whole cell;
// - random:    the range along each ray drawn uniformly in [0.1 m, the
//              max-range reading] (fixed seed, std::mt19937's bits);
// - person:    a 0.5 x 0.3 x 1.8 m box standing on the floor 1 m
//              (horizontally) in front of sensor 0, its wide face to the
//              sensor, in the empty cell (max-range elsewhere): the worst
//              occlusion, most of sensor 0's image ends near the sensor;
// - faces:     the empty cell, each reading where its ray leaves the cell:
//              on the floor or a wall, which lie on voxel faces (as a
//              noise-free render of a floor at a face does): the hit pass's
//              worst case, every reading placed by the exact arithmetic.
// Paths:
// - footprint: fuse_frame_footprint, one workspace
//              per sensor (as a threaded runner needs), SequentialRunner;
// - per-ray:   fuse_frame (exact), the reference; fewer cycles in the real
//              cells (about a second a frame);
// - OctoMap:   real cells: insertPointCloud of every reading (all lie in the
//              cell) at the grid's resolution; paper: the same rays clipped
//              to the paper's grid with insertPointCloud's semantics (as
//              bench_fusion); fresh tree per frame.
//
// Times: wall clock (steady_clock) around each cycle and this thread's CPU
// time (CLOCK_THREAD_CPUTIME_ID: excludes time the shared machine's
// scheduler gave to other processes). The goals are judged on the thread's
// CPU time; the wall clock is printed beside it.
//
// Usage: bench_scale [--cycles N] [--quick] [--threads N] [--exact-max N] [--case NAME]
//   --exact-max N footprint fusion's exact_footprint_max (default 0: no exact
//               step, the same work in every frame)
//   --threads N footprint fusion on the Linux port's WorkerPool with N workers
//               (default 1: SequentialRunner, the reference); the goals are
//               then judged on the wall clock
//   --cycles N  footprint cycles per case and pattern (default 300), and the
//               per-ray cycles in the paper's cell
//   --quick     for CI: 30 cycles, 1 per-ray frame in the real cells, 1 OctoMap frame
//   --pattern P one reading pattern only (max-range, random, person, faces), for profiling
//   --footprint-only  footprint fusion alone (no per-ray or OctoMap frames), for profiling
//   --kernel K  the hit pass's and pooling's kernel: fastest (default), scalar, avx2
//               (FootprintParams::kernel; the same grid with each)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <time.h>

#include "bench_cells.hpp"
#include "cellguard/base/task_runner.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/owned_footprint.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "cellguard/safety/monitoring_cases.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/zones.hpp"
#include "test_robot.hpp"
#include "world_readings.hpp"

#ifdef CELLGUARD_HAVE_WORKER_POOL
#include "cellguard/port/worker_pool.hpp"
#endif

#ifdef CELLGUARD_HAVE_OCTOMAP
#include <octomap/octomap.h>
#endif

using namespace cellguard;
using SteadyClock = std::chrono::steady_clock;

namespace {

constexpr int kWarmupCycles = 3;
constexpr double kMiB = 1048576.0;

/// The 1-, 5- and 15-minute load averages as /proc/loadavg gives them.
std::string load_line() {
    char buf[128] = {};
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fgets(buf, sizeof buf, f) == nullptr) {
            buf[0] = '\0';
        }
        std::fclose(f);
    }
    std::string s(buf);
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) {
        s.pop_back();
    }
    return s.empty() ? std::string("unavailable") : s;
}

/// This thread's CPU time, milliseconds.
double thread_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
    return v[std::min(i == 0U ? 0U : i - 1U, v.size() - 1U)];
}

[[noreturn]] void fail(const char* what, ErrorCode e) {
    std::fprintf(stderr, "bench_scale: %s: %s\n", what, to_string(e));
    std::exit(2);
}

/// One cell: its grid, its sensors and the cell's box (the walls and floor).
struct Case {
    const char* name;
    GridGeometry grid;
    std::vector<sim::SensorSpec> sensors;
    Eigen::Vector3d cell_lo;
    Eigen::Vector3d cell_hi;
    bool real;  ///< a real cell (whole-cell grid): OctoMap on whole rays, few per-ray frames
};

std::vector<sim::SensorSpec> real_sensors() {
    const Eigen::Vector3d target(0.0, 0.0, 0.0);
    const double c = 1.9;
    const double h = 2.4;
    std::vector<sim::SensorSpec> s(4);
    s[0] = sim::SensorSpec{"cam-a", {-c, -c, h}, target, 640, 480, 58.0, 45.0, 10.0F};
    s[1] = sim::SensorSpec{"cam-b", {c, c, h}, target, 640, 480, 58.0, 45.0, 10.0F};
    s[2] = sim::SensorSpec{"cam-c", {c, -c, h}, target, 640, 480, 58.0, 45.0, 10.0F};
    s[3] = sim::SensorSpec{"cam-d", {-c, c, h}, target, 640, 480, 58.0, 45.0, 10.0F};
    return s;
}

GridGeometry geometry(const Eigen::Vector3d& origin, double size, GridDims dims) {
    const Result<GridGeometry> g = GridGeometry::make(origin, size, dims);
    if (!g.ok()) {
        fail("grid geometry", g.error());
    }
    return g.value();
}

std::vector<Case> make_cases() {
    const Eigen::Vector3d lo(-2.0, -2.0, 0.0);
    std::vector<Case> cases;
    cases.push_back(
        Case{"paper", paper_grid_geometry(), sim::paper_sensors(), lo, Eigen::Vector3d(2.0, 2.0, 2.0), false});
    cases.push_back(Case{"real-5cm", geometry(lo, 0.05, GridDims{80, 80, 50}), real_sensors(), lo,
                         Eigen::Vector3d(2.0, 2.0, 2.5), true});
    cases.push_back(Case{"real-2.5cm", geometry(lo, 0.025, GridDims{160, 160, 100}), real_sensors(), lo,
                         Eigen::Vector3d(2.0, 2.0, 2.5), true});
    return cases;
}

enum class Pattern { kMaxRange, kRandom, kPerson, kFaces };
constexpr Pattern kPatterns[] = {Pattern::kMaxRange, Pattern::kRandom, Pattern::kPerson, Pattern::kFaces};

const char* pattern_name(Pattern p) {
    switch (p) {
        case Pattern::kMaxRange: return "max-range";
        case Pattern::kRandom: return "random";
        case Pattern::kPerson: return "person";
        case Pattern::kFaces: return "faces";
    }
    return "?";
}

/// Distance along origin + t * dir (origin inside) to where the ray leaves the box [lo, hi].
double exit_distance(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi) {
    double t = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (d[a] > 0.0) {
            t = std::min(t, (hi[a] - o[a]) / d[a]);
        } else if (d[a] < 0.0) {
            t = std::min(t, (lo[a] - o[a]) / d[a]);
        }
    }
    return t;
}

/// The person: a 0.5 x 0.3 x 1.8 m box on the floor, 1 m horizontally in
/// front of @p sensor towards the cell's centre, its 0.5 m face to the sensor.
sim::Box person_near(const sim::SensorSpec& sensor) {
    const Eigen::Vector2d p = sensor.position.head<2>();
    const Eigen::Vector2d towards_sensor = p.normalized();
    const Eigen::Vector2d c = p - 1.0 * towards_sensor;
    sim::Box b;
    b.center = Eigen::Vector3d(c.x(), c.y(), 0.9);
    b.size = Eigen::Vector3d(0.5, 0.3, 1.8);
    b.yaw = std::atan2(towards_sensor.y(), towards_sensor.x()) + 0.5 * 3.14159265358979323846;
    b.background = false;
    return b;
}

/// One frame of readings: the images and the readings that point into them.
struct Frame {
    std::vector<std::vector<float>> depth;
    std::vector<SensorReading> readings;
    std::uint64_t pixels = 0U;
};

Frame make_frame(const Case& c, Pattern pattern) {
    sim::Scene scene;
    scene.floor = false;  // the cell's box (floor and walls) is handled by exit_distance
    if (pattern == Pattern::kPerson) {
        scene.boxes.push_back(person_near(c.sensors[0]));
    }
    const sim::PreparedScene prepared(scene);
    std::mt19937 rng(18U);
    Frame f;
    f.depth.resize(c.sensors.size());
    for (std::size_t s = 0; s < c.sensors.size(); ++s) {
        const sim::SensorSpec& spec = c.sensors[s];
        const PinholeIntrinsics k = spec.intrinsics();
        const Eigen::Isometry3d pose = spec.pose();
        std::vector<float>& img = f.depth[s];
        img.assign(static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height), 0.0F);
        for (std::int32_t v = 0; v < k.height; ++v) {
            for (std::int32_t u = 0; u < k.width; ++u) {
                const Eigen::Vector3d ray_cam((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
                const Eigen::Vector3d dir = (pose.linear() * ray_cam).normalized();
                const double exit = exit_distance(spec.position, dir, c.cell_lo, c.cell_hi);
                double t = pattern == Pattern::kFaces ? exit : exit - 0.001;
                if (pattern == Pattern::kRandom) {
                    const double x = static_cast<double>(rng() >> 8U) / 16777216.0;  // [0, 1), 24 bits
                    t = 0.1 + x * (t - 0.1);
                } else if (pattern == Pattern::kPerson) {
                    t = std::min(t, prepared.cast(spec.position, dir).distance);
                }
                img[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) + static_cast<std::size_t>(u)] =
                    static_cast<float>(t / ray_cam.norm());
            }
        }
        f.pixels += img.size();
    }
    for (std::size_t s = 0; s < c.sensors.size(); ++s) {
        f.readings.push_back(sim::depth_reading(c.sensors[s], {f.depth[s].data(), f.depth[s].size()}));
    }
    return f;
}

/// A grid with its own storage.
struct OwnedGrid {
    std::vector<std::int16_t> lo;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid;
    explicit OwnedGrid(const GridGeometry& g) : lo(g.voxel_count()), ob(g.voxel_count()) {
        const Result<EvidenceGrid> r = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()});
        if (!r.ok()) {
            fail("evidence grid", r.error());
        }
        grid = r.value();
    }
};

/// Times of one path on one case and pattern.
struct Timing {
    int cycles = 0;
    std::vector<double> wall_ms, cpu_ms;
    [[nodiscard]] double median() const { return percentile(wall_ms, 0.5); }
    [[nodiscard]] double p99() const { return percentile(wall_ms, 0.99); }
    [[nodiscard]] double max_wall() const { return *std::max_element(wall_ms.begin(), wall_ms.end()); }
    [[nodiscard]] double max_cpu() const { return *std::max_element(cpu_ms.begin(), cpu_ms.end()); }
    [[nodiscard]] double median_cpu() const { return percentile(cpu_ms, 0.5); }
};

/// Runs @p body once per cycle, timing it (after @p warmup untimed calls).
template <typename Body>
Timing time_cycles(int cycles, int warmup, Body body) {
    for (int i = 0; i < warmup; ++i) {
        body();
    }
    Timing t;
    t.cycles = cycles;
    for (int i = 0; i < cycles; ++i) {
        const double c0 = thread_cpu_ms();
        const auto w0 = SteadyClock::now();
        body();
        const auto w1 = SteadyClock::now();
        const double c1 = thread_cpu_ms();
        t.wall_ms.push_back(std::chrono::duration<double, std::milli>(w1 - w0).count());
        t.cpu_ms.push_back(c1 - c0);
    }
    return t;
}

/// Footprint fusion's figures on one case and pattern.
struct FootprintRun {
    Timing t;
    FootprintStats most;                      ///< the largest counts of any cycle (field by field)
    std::uint64_t bound = 0U;                 ///< footprint_work_bound summed over the sensors
    std::uint64_t measured = 0U;              ///< the most work units of a cycle (FootprintStats::work_units)
    std::uint64_t least = ~std::uint64_t{0};  ///< the fewest work units of a cycle
    std::size_t memory_bytes = 0U;            ///< pyramids, opinions and footprint table of every workspace
};

FootprintRun run_footprint(const Case& c, const Frame& f, int cycles, TaskRunner& runner,
                           const FootprintParams& params) {
    OwnedGrid g(c.grid);
    const host::OwnedFootprintWorkspaces w(c.grid, f.readings);
    const SensorModelTable model;
    FootprintRun run;
    run.memory_bytes = w.bytes();
    for (const SensorReading& r : f.readings) {
        run.bound += footprint_work_bound(c.grid, r, params);
    }
    const Span<const SensorReading> sensors(f.readings.data(), f.readings.size());
    const Span<const FootprintWorkspace> spaces = w.spans();
    run.t = time_cycles(cycles, kWarmupCycles, [&] {
        g.grid.clear();
        FootprintStats st;
        const Result<FusionStats> r = fuse_frame_footprint(g.grid, sensors, model, spaces, runner, &st, params);
        if (!r.ok()) {
            fail("fuse_frame_footprint", r.error());
        }
        run.most.pixels = std::max(run.most.pixels, st.pixels);
        run.most.voxels_visited = std::max(run.most.voxels_visited, st.voxels_visited);
        run.most.voxels_filled = std::max(run.most.voxels_filled, st.voxels_filled);
        run.most.voxels_safe_side = std::max(run.most.voxels_safe_side, st.voxels_safe_side);
        run.most.voxels_exact = std::max(run.most.voxels_exact, st.voxels_exact);
        run.most.pixel_tests = std::max(run.most.pixel_tests, st.pixel_tests);
        run.measured = std::max(run.measured, st.work_units());
        run.least = std::min(run.least, st.work_units());
    });
    return run;
}

/// The whole cycle's figures: SafetyController::run_cycle as the monitor runs it.
struct CycleRun {
    Timing t;                   ///< around run_cycle: wall clock and this thread's CPU time
    Timing fusion;              ///< its fusion stage (the controller's timing, this thread's CPU time)
    std::uint32_t faults = 0U;  ///< faults other than an overrun seen in any cycle (0 expected)
};

/// The robot side of the whole cycle: the 6-axis test arm (UR10 sizes) standing
/// at the grid's centre, one monitoring case over every zone, separation
/// parameters as the controller's tests use them.
struct CycleRobot {
    static constexpr std::uint32_t kImageCrc = 0xC0FFEE42U;
    RobotModel arm;
    std::vector<std::uint8_t> mask;
    MonitoringCases cases;
    CycleRobot(const GridGeometry& g, const CompiledZones& zones)
        : arm(test::make_test_arm(g.origin().x() + 0.5 * g.dims().nx * g.voxel_size(),
                                  g.origin().y() + 0.5 * g.dims().ny * g.voxel_size(), g.origin().z())),
          mask(g.voxel_count()) {
        const std::uint32_t every_zone[] = {0xFFFFFFFFU >> (32U - static_cast<std::uint32_t>(zones.size()))};
        cases = MonitoringCases::make(zones, every_zone).value();
    }
    void attach(ControllerConfig& cc) {
        cc.robot.model = &arm;
        cc.robot.image_crc = kImageCrc;
        cc.robot.mask_margin_m = 0.05;
        cc.robot.mask = Span<std::uint8_t>(mask.data(), mask.size());
        SeparationParams& p = cc.robot.separation;
        p.reaction_time_s = 0.1;
        p.classes[0] = SpeedClassLimits{1.0, 0.2, 0.05};
        p.class_count = 1U;
        p.slowdown_time_s = 0.0;
        p.sensing_uncertainty_m = 0.05;
        p.robot_uncertainty_m = 0.01;
        p.min_hidden_voxels = 8U;
        cc.cases = &cases;
        cc.max_command_age_us = 1000000000U;
    }
    /// A good command: case 0, the arm's six joints, received at @p now_us.
    static CommandInput command(std::uint64_t now_us, std::uint8_t counter) {
        CommandInput in;
        in.valid = true;
        in.received_us = now_us;
        in.counter = counter;
        in.command.monitoring_case = 0U;
        in.command.joint_count = 6U;
        in.command.robot_id = robot_id(kImageCrc);
        return in;
    }
};

/// Whole cycles on one case and pattern: footprint fusion (as @p params,
/// on @p runner), background subtraction against a prior that makes every
/// voxel foreground, kMaxZones zones that each cover the grid, the robot mask
/// and the separation of the test arm, the frozen-sensor and
/// changed-background checks (the frames as their own views, so they pass)
/// and the run-time memory checks: the most work of every stage.
CycleRun run_whole_cycle(const Case& c, const Frame& f, int cycles, TaskRunner& runner, const FootprintParams& params) {
    const GridGeometry& g = c.grid;
    const std::vector<ZoneConfig> zone_configs = bench::worst_case_zones(g);
    std::vector<std::uint32_t> membership(g.voxel_count());
    const Result<CompiledZones, ZoneError> compiled = CompiledZones::compile(
        g, {zone_configs.data(), zone_configs.size()}, {membership.data(), membership.size()});
    if (!compiled.ok()) {
        std::fprintf(stderr, "bench_scale: zone %zu: %s\n", compiled.error().zone, compiled.error().reason);
        std::exit(2);
    }
    const CompiledZones zones = compiled.value();
    const std::vector<std::int16_t> prior(g.voxel_count(), kLogOddsMax);
    const SensorModelTable model;
    OwnedGrid frame(g);
    const host::OwnedFootprintWorkspaces w(g, f.readings);
    CycleRobot robot(g, zones);
    ControllerConfig cc;
    cc.sensor_count = f.readings.size();
    cc.cycle_budget_us = 1000000U;  // overruns are not what is measured here
    cc.max_frame_age_us = 1000000000U;
    cc.max_repeated_frames = std::numeric_limits<std::uint32_t>::max();  // on, never reached
    cc.footprint.method = FusionMethod::kFootprint;
    cc.footprint.params = params;
    cc.footprint.workspaces = w.spans();
    cc.footprint.runner = &runner;
    robot.attach(cc);
    bench::ThreadCpuClock clock;
    SafetyController controller(cc, frame.grid, Span<std::int16_t>(), {prior.data(), prior.size()}, zones, model, clock,
                                nullptr);
    std::vector<BackgroundReference> backgrounds(f.readings.size());
    std::vector<SensorInput> inputs(f.readings.size());
    for (std::size_t s = 0U; s < inputs.size(); ++s) {
        backgrounds[s].depth = f.readings[s].depth;
        inputs[s].reading = f.readings[s];
        inputs[s].present = true;
        inputs[s].background = &backgrounds[s];
    }
    CycleRun run;
    std::uint8_t counter = 0U;
    run.t = time_cycles(cycles, kWarmupCycles, [&] {
        const std::uint64_t now = clock.now_us();
        for (SensorInput& in : inputs) {
            in.captured_us = now;
        }
        const CycleReport& r = controller.run_cycle({inputs.data(), inputs.size()}, false,
                                                    CycleRobot::command(now, counter++));
        run.faults |= r.detected_faults & ~fault_bit(Fault::kCycleOverrun);
        run.fusion.cpu_ms.push_back(
            static_cast<double>(controller.monitor().last().stage_us[static_cast<std::size_t>(CycleStage::kFuse)]) /
            1000.0);
    });
    // The warm-up cycles' fusion times out: the same cycles as run.t.
    run.fusion.cpu_ms.erase(run.fusion.cpu_ms.begin(), run.fusion.cpu_ms.begin() + kWarmupCycles);
    run.fusion.wall_ms = run.fusion.cpu_ms;
    run.fusion.cycles = cycles;
    return run;
}

/// The exact per-ray path's figures.
struct ExactRun {
    Timing t;
    std::uint64_t voxel_updates = 0U;
};

ExactRun run_exact(const Case& c, const Frame& f, int cycles) {
    OwnedGrid g(c.grid);
    std::vector<std::int16_t> scratch(c.grid.voxel_count());
    const SensorModelTable model;
    ExactRun run;
    run.t = time_cycles(cycles, cycles > 10 ? kWarmupCycles : 0, [&] {
        g.grid.clear();
        const Result<FusionStats> r = fuse_frame(g.grid, {f.readings.data(), f.readings.size()}, model,
                                                 {scratch.data(), scratch.size()});
        if (!r.ok()) {
            fail("fuse_frame", r.error());
        }
        run.voxel_updates = r.value().voxel_updates;
    });
    return run;
}

#ifdef CELLGUARD_HAVE_OCTOMAP
/// Each sensor's readings as world points, as fusion places them.
std::vector<octomap::Pointcloud> world_clouds(const Frame& f) {
    std::vector<octomap::Pointcloud> clouds(f.readings.size());
    for (std::size_t s = 0; s < f.readings.size(); ++s) {
        bench::for_each_world_reading(f.readings[s], [&](const Eigen::Vector3d& w) {
            clouds[s].push_back(static_cast<float>(w.x()), static_cast<float>(w.y()), static_cast<float>(w.z()));
        });
    }
    return clouds;
}

octomap::point3d to_point(const Eigen::Vector3d& p) {
    return octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
}

/// OctoMap's insertPointCloud of every reading, one call per sensor, fresh tree per frame.
Timing run_octomap_whole(const Case& c, const Frame& f, int frames) {
    const std::vector<octomap::Pointcloud> clouds = world_clouds(f);
    return time_cycles(frames, 0, [&] {
        octomap::OcTree tree(c.grid.voxel_size());
        for (std::size_t s = 0; s < clouds.size(); ++s) {
            tree.insertPointCloud(clouds[s], to_point(f.readings[s].pose.translation()), -1.0, false, false);
        }
    });
}

/// The same rays clipped to the grid's box with insertPointCloud's semantics
/// (bench_fusion: free and occupied key sets per sensor, each key updated at
/// most once per scan; the reading is occupied only when inside the box).
Timing run_octomap_clipped(const Case& c, const Frame& f, int frames) {
    struct Seg {
        octomap::point3d a, b;
        bool occupied_end;
        std::size_t sensor;
    };
    const std::vector<octomap::Pointcloud> clouds = world_clouds(f);
    const Eigen::Vector3d lo = c.grid.origin();
    const Eigen::Vector3d hi = c.grid.max_corner();
    std::vector<Seg> segs;
    for (std::size_t s = 0; s < clouds.size(); ++s) {
        const Eigen::Vector3d o = f.readings[s].pose.translation();
        for (const octomap::point3d& p : clouds[s]) {
            const Eigen::Vector3d d = Eigen::Vector3d(p.x(), p.y(), p.z()) - o;
            double t0 = 0.0;
            double t1 = 1.0;
            bool hit = true;
            for (int a = 0; a < 3 && hit; ++a) {
                if (std::abs(d[a]) < 1e-15) {
                    hit = o[a] >= lo[a] && o[a] < hi[a];
                    continue;
                }
                double ta = (lo[a] - o[a]) / d[a];
                double tb = (hi[a] - o[a]) / d[a];
                if (ta > tb) {
                    std::swap(ta, tb);
                }
                t0 = std::max(t0, ta);
                t1 = std::min(t1, tb);
                hit = t0 < t1;
            }
            if (hit) {
                segs.push_back(Seg{to_point(o + t0 * d), to_point(o + t1 * d), t1 >= 1.0, s});
            }
        }
    }
    return time_cycles(frames, 0, [&] {
        octomap::OcTree tree(c.grid.voxel_size());
        for (std::size_t s = 0; s < clouds.size(); ++s) {
            octomap::KeySet free_cells;
            octomap::KeySet occupied_cells;
            octomap::KeyRay keyray;
            for (const Seg& seg : segs) {
                if (seg.sensor != s) {
                    continue;
                }
                if (tree.computeRayKeys(seg.a, seg.b, keyray)) {
                    free_cells.insert(keyray.begin(), keyray.end());
                }
                octomap::OcTreeKey k;
                if (seg.occupied_end && tree.coordToKeyChecked(seg.b, k)) {
                    occupied_cells.insert(k);
                }
            }
            for (const auto& k : occupied_cells) {
                free_cells.erase(k);
            }
            for (const auto& k : free_cells) {
                tree.updateNode(k, false);
            }
            for (const auto& k : occupied_cells) {
                tree.updateNode(k, true);
            }
        }
    });
}
#endif

/// Everything measured on one case and pattern.
struct Row {
    const Case* c = nullptr;
    Pattern pattern = Pattern::kMaxRange;
    FootprintRun fp;
    CycleRun cycle;  ///< the whole cycle (t.cycles 0: not run, --footprint-only)
    ExactRun exact;
    Timing octomap;  ///< cycles 0: not run
};

struct Options {
    int cycles = 300;
    int threads = 1;
    int exact_real_frames = 5;
    int octomap_frames = 3;
    bool quick = false;
    std::string only;             ///< --case NAME: only that case (paper, real-5cm, real-2.5cm); its goals alone
    std::string only_pattern;     ///< --pattern NAME: only that reading pattern (profiling)
    FootprintParams params{};     ///< --exact-max N: FootprintParams::exact_footprint_max
    bool footprint_only = false;  ///< --footprint-only: no per-ray or OctoMap reference (profiling)
};

[[noreturn]] void usage(const char* why) {
    std::fprintf(
        stderr,
        "bench_scale: %s\nusage: bench_scale [--cycles N] [--quick] [--threads N] [--exact-max N] [--kernel K] [--footprint-only] [--pattern P] "
        "[--case paper|real-5cm|real-2.5cm]\n",
        why);
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    bool cycles_given = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--cycles" && i + 1 < argc) {
            o.cycles = std::atoi(argv[++i]);
            cycles_given = true;
            if (o.cycles < 1) {
                usage("--cycles expects a positive number");
            }
        } else if (a == "--threads" && i + 1 < argc) {
            o.threads = std::atoi(argv[++i]);
#ifdef CELLGUARD_HAVE_WORKER_POOL
            if (o.threads < 1 || o.threads > static_cast<int>(linux_port::kMaxWorkers)) {
                usage("--threads expects 1 to 16");
            }
#else
            if (o.threads != 1) {
                usage("--threads: built without the Linux port's WorkerPool, only 1");
            }
#endif
        } else if (a == "--exact-max" && i + 1 < argc) {
            const int n = std::atoi(argv[++i]);
            if (n < 0 || n > 65536) {
                usage("--exact-max expects 0 to 65536");
            }
            o.params.exact_footprint_max = static_cast<std::uint32_t>(n);
        } else if (a == "--kernel" && i + 1 < argc) {
            const std::string k = argv[++i];
            if (k == "fastest") {
                o.params.kernel = FusionKernel::kFastest;
            } else if (k == "scalar") {
                o.params.kernel = FusionKernel::kScalar;
            } else if (k == "avx2") {
                o.params.kernel = FusionKernel::kAvx2;
            } else {
                usage("--kernel expects fastest, scalar or avx2");
            }
        } else if (a == "--footprint-only") {
            o.footprint_only = true;
        } else if (a == "--quick") {
            o.quick = true;
        } else if (a == "--case" && i + 1 < argc) {
            o.only = argv[++i];
        } else if (a == "--pattern" && i + 1 < argc) {
            o.only_pattern = argv[++i];
        } else {
            usage(("unknown argument " + a).c_str());
        }
    }
    if (o.quick) {
        o.cycles = cycles_given ? o.cycles : 30;
        o.exact_real_frames = 1;
        o.octomap_frames = 1;
    }
    return o;
}

void print_timing(const char* path, const Timing& t, const char* ratio_label, double ratio) {
    std::printf("    %-10s %6d %9.2f %9.2f %9.2f %9.2f %9.2f", path, t.cycles, t.median(), t.p99(), t.max_wall(),
                t.median_cpu(), t.max_cpu());
    if (ratio_label != nullptr) {
        std::printf("   %7.1fx %s", ratio, ratio_label);
    }
    std::printf("\n");
}

void print_row(const Row& r) {
    std::printf("  %s, %s\n", r.c->name, pattern_name(r.pattern));
    print_timing("footprint", r.fp.t, nullptr, 0.0);
    if (r.cycle.t.cycles > 0) {
        print_timing("cycle", r.cycle.t, "cycle / footprint alone (median)", r.cycle.t.median() / r.fp.t.median());
        std::printf("    %-10s %6d %9s %9s %9s %9.2f %9.2f   (the fusion stage of the cycles above)%s\n", "its fusion",
                    r.cycle.fusion.cycles, "-", "-", "-", r.cycle.fusion.median_cpu(), r.cycle.fusion.max_cpu(),
                    r.cycle.faults != 0U ? "; FAULTS seen" : "");
    }
    if (r.exact.t.cycles > 0) {
        print_timing("per-ray", r.exact.t, "per-ray / footprint (median)", r.exact.t.median() / r.fp.t.median());
    }
    if (r.octomap.cycles > 0) {
        print_timing("OctoMap", r.octomap, "OctoMap / footprint (median)", r.octomap.median() / r.fp.t.median());
    }
}

void print_work(const Row& r) {
    const FootprintStats& s = r.fp.most;
    std::printf("  %-11s %-10s %11llu %11llu %11llu %9llu %9llu %9llu %9llu %10llu %12.1f\n", r.c->name,
                pattern_name(r.pattern), static_cast<unsigned long long>(r.fp.bound),
                static_cast<unsigned long long>(r.fp.least), static_cast<unsigned long long>(r.fp.measured),
                static_cast<unsigned long long>(s.voxels_visited), static_cast<unsigned long long>(s.voxels_filled),
                static_cast<unsigned long long>(s.voxels_exact), static_cast<unsigned long long>(s.voxels_safe_side),
                static_cast<unsigned long long>(s.pixel_tests), static_cast<double>(r.exact.voxel_updates) / 1e6);
}

}  // namespace

int main(int argc, char** argv) {
    const Options opt = parse(argc, argv);
    const auto start = SteadyClock::now();
    std::printf("bench_scale: footprint fusion with real depth cameras (issue 18); load average at start: %s\n",
                load_line().c_str());
#ifdef NDEBUG
    const char* checks = "CG_ENFORCE on, CG_ASSERT compiled out (NDEBUG)";
#else
    const char* checks = "CG_ENFORCE and CG_ASSERT on";
#endif
    if (opt.threads == 1) {
        std::printf("  footprint on one thread (SequentialRunner); ");
    } else {
        std::printf("  footprint on %d threads (WorkerPool; CPU columns: the calling thread only); ", opt.threads);
    }
    std::printf(
        "per-ray and OctoMap on one thread;\n  fresh grid per cycle, %s; footprint: %d cycles after %d warm-up;\n",
        checks, opt.cycles, kWarmupCycles);
    const FusionKernel kernel = resolve_fusion_kernel(opt.params.kernel);
    std::printf("  hit pass's pixel kernel: %s\n",
                kernel == FusionKernel::kAvx2 ? "avx2 (4 pixels at a time)" : "scalar (the reference)");
    std::printf("  per-ray (fuse_frame, exact): %d frames in the real cells, %d in the paper's; OctoMap: %d frames\n",
                opt.exact_real_frames, opt.cycles, opt.octomap_frames);
    const std::vector<Case> cases = make_cases();
    SequentialRunner sequential;
#ifdef CELLGUARD_HAVE_WORKER_POOL
    std::unique_ptr<linux_port::WorkerPool> pool;
    if (opt.threads > 1) {
        pool = std::make_unique<linux_port::WorkerPool>(static_cast<std::size_t>(opt.threads));
    }
    TaskRunner& runner = pool ? static_cast<TaskRunner&>(*pool) : static_cast<TaskRunner&>(sequential);
#else
    TaskRunner& runner = sequential;
#endif
    std::vector<Row> rows;
    std::printf("\ncases\n");
    for (const Case& c : cases) {
        std::uint64_t pixels = 0U;
        for (const sim::SensorSpec& s : c.sensors) {
            pixels += static_cast<std::uint64_t>(s.width) * static_cast<std::uint64_t>(s.height);
        }
        std::printf("  %-11s grid %d x %d x %d at %.3f m (%zu voxels), %zu sensors, %llu pixels a frame\n", c.name,
                    c.grid.dims().nx, c.grid.dims().ny, c.grid.dims().nz, c.grid.voxel_size(), c.grid.voxel_count(),
                    c.sensors.size(), static_cast<unsigned long long>(pixels));
    }

    std::printf("\ncycle time, ms (median and p99 wall clock; max wall clock; median and max thread CPU time)\n");
    std::printf("    %-10s %6s %9s %9s %9s %9s %9s\n", "path", "cycles", "median", "p99", "max", "cpu med", "cpu max");
    for (const Case& c : cases) {
        if (!opt.only.empty() && opt.only != c.name) {
            continue;
        }
        for (Pattern p : kPatterns) {
            if (!opt.only_pattern.empty() && opt.only_pattern != pattern_name(p)) {
                continue;
            }
            const Frame f = make_frame(c, p);
            Row r;
            r.c = &c;
            r.pattern = p;
            r.fp = run_footprint(c, f, opt.cycles, runner, opt.params);
            if (!opt.footprint_only) {
                r.cycle = run_whole_cycle(c, f, opt.cycles, runner, opt.params);
                r.exact = run_exact(c, f, c.real ? opt.exact_real_frames : opt.cycles);
#ifdef CELLGUARD_HAVE_OCTOMAP
                r.octomap = c.real ? run_octomap_whole(c, f, opt.octomap_frames)
                                   : run_octomap_clipped(c, f, opt.octomap_frames);
#endif
            }
            std::fprintf(stderr, "bench_scale: %s %s done at %.0f s\n", c.name, pattern_name(p),
                         std::chrono::duration<double>(SteadyClock::now() - start).count());
            print_row(r);  // as it comes: a long run on a loaded machine shows its rows early
            rows.push_back(std::move(r));
            std::fflush(stdout);
        }
    }

#ifdef CELLGUARD_HAVE_OCTOMAP
    std::printf(
        "  OctoMap: real cells insertPointCloud of every reading at the grid's resolution; paper: the same rays\n"
        "  clipped to the paper's grid. OctoMap applies a voxel at most once per scan and stops at its clamping\n"
        "  limits; the evidence grid adds every ray (per-ray) or its footprint-bounded opinion (footprint).\n");
#else
    std::printf("  OctoMap not found at configure time: no OctoMap rows (install liboctomap-dev)\n");
#endif

    std::printf(
        "\nwork per cycle (footprint; units = 2 x pixels + voxels in view; the fewest and the most of any "
        "cycle; voxel counts: the most)\n");
    std::printf("  exact-max %u (voxels with a footprint of at most this many pixels evaluated ray by ray)\n",
                opt.params.exact_footprint_max);
    std::printf("  %-11s %-10s %11s %11s %11s %9s %9s %9s %9s %10s %12s\n", "case", "pattern", "bound", "fewest",
                "most", "in view", "filled", "exact", "safe side", "pix tests", "per-ray Mupd");
    bool bound_held = true;
    bool bound_tight = true;
    for (const Row& r : rows) {
        print_work(r);
        bound_held = bound_held && r.fp.measured <= r.fp.bound;
        bound_tight = bound_tight && static_cast<double>(r.fp.least) >= 0.95 * static_cast<double>(r.fp.bound);
    }
    std::printf("  measured <= bound in every cycle: %s\n", bound_held ? "yes" : "NO (bound violated)");
    std::printf("  measured >= 95 %% of the bound in every cycle: %s\n", bound_tight ? "yes" : "NO (bound not tight)");

    std::printf(
        "\nmemory, MiB (footprint: pyramids, opinions and footprint table of one workspace per sensor; the grid itself apart)\n");
    double largest_mib = 0.0;
    for (const Row& r : rows) {
        if (r.pattern != Pattern::kMaxRange) {
            continue;  // the same workspaces for every pattern
        }
        const Case& c = *r.c;
        const double mib = static_cast<double>(r.fp.memory_bytes) / kMiB;
        largest_mib = std::max(largest_mib, mib);
        std::printf("  %-11s footprint %7.2f   grid (int16 log-odds + uint8 observed) %7.2f   per-ray scratch %7.2f\n",
                    c.name, mib, static_cast<double>(c.grid.voxel_count() * 3U) / kMiB,
                    static_cast<double>(c.grid.voxel_count() * 2U) / kMiB);
    }

    // The goals, judged on the thread's CPU time (the wall clock beside it).
    double max5_cpu = 0.0, max5_wall = 0.0, max25_cpu = 0.0, max25_wall = 0.0, paper_cpu = 0.0, paper_wall = 0.0;
    double min_ratio = std::numeric_limits<double>::infinity();
    std::uint32_t cycle_faults = 0U;
    std::string min_ratio_at = "none";
    for (const Row& r : rows) {
        const std::string name = r.c->name;
        double* cpu = name == "real-5cm" ? &max5_cpu : name == "real-2.5cm" ? &max25_cpu : &paper_cpu;
        double* wall = name == "real-5cm" ? &max5_wall : name == "real-2.5cm" ? &max25_wall : &paper_wall;
        // The whole cycle where it ran, else fusion alone (--footprint-only).
        const Timing& judged = r.cycle.t.cycles > 0 ? r.cycle.t : r.fp.t;
        *cpu = std::max(*cpu, judged.max_cpu());
        *wall = std::max(*wall, judged.max_wall());
        cycle_faults |= r.cycle.faults;
        if (r.octomap.cycles > 0 && r.octomap.median() / r.fp.t.median() < min_ratio) {
            min_ratio = r.octomap.median() / r.fp.t.median();
            min_ratio_at = name + " " + pattern_name(r.pattern);
        }
    }
    const double seconds = std::chrono::duration<double>(SteadyClock::now() - start).count();
    std::printf("\nload average at end: %s; run %.0f s\n\n", load_line().c_str(), seconds);
    // One thread: judged on its CPU time; a pool: on the wall clock (the
    // calling thread's CPU time is not the cycle's).
    const bool one = opt.threads == 1;
    const std::string on = one ? std::string("on one core") : "on " + std::to_string(opt.threads) + " threads";
    const auto measured = [&](const char* name) { return opt.only.empty() || opt.only == name; };
    const auto verdict = [&](const char* name, bool met) {
        return !measured(name) ? "not measured (--case)" : met ? "met" : "NOT met";
    };
    const double j5 = one ? max5_cpu : max5_wall;
    const double j25 = one ? max25_cpu : max25_wall;
    const double jp = one ? paper_cpu : paper_wall;
    const char* what = opt.footprint_only ? "fusion alone (--footprint-only)" : "the whole cycle";
    std::printf("goals on %s; cycle faults other than overruns: %s\n", what, cycle_faults == 0U ? "none" : "SEEN");
    std::printf("goal: the 5 cm cell's worst cycle within 10 ms %s (max %.2f ms CPU, %.2f ms wall) %s\n", on.c_str(),
                max5_cpu, max5_wall, verdict("real-5cm", j5 <= 10.0));
    std::printf(
        "goal: the 2.5 cm cell's worst cycle within 33 ms %s, on two threads (max %.2f ms CPU, %.2f ms wall) %s\n",
        on.c_str(), max25_cpu, max25_wall, verdict("real-2.5cm", j25 <= 33.0 && opt.threads == 2));
    std::printf("goal: the 2.5 cm cell's tables and scratch within 64 MiB (largest of the cells run %.2f MiB) %s\n",
                largest_mib, verdict("real-2.5cm", largest_mib <= 64.0));
    if (std::isfinite(min_ratio)) {
        std::printf("goal: fusion alone at least 100x OctoMap on the same readings (smallest %.1fx, %s) %s\n",
                    min_ratio, min_ratio_at.c_str(), min_ratio >= 100.0 ? "met" : "NOT met");
    } else {
        std::printf("goal: fusion alone at least 100x OctoMap on the same readings (%s) NOT met\n",
                    opt.footprint_only ? "not measured: --footprint-only" : "OctoMap not built");
    }
    std::printf(
        "goal: the paper's cell within 2 ms worst case for every pattern %s (max %.2f ms CPU, %.2f ms wall) %s\n",
        on.c_str(), paper_cpu, paper_wall, verdict("paper", jp <= 2.0));
    return bound_held ? 0 : 1;
}
