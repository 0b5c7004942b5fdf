// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Cycle benchmark (issue 5, "Timing"): the paper's cell through the same
// code path as cellguard-monitor (SafetyController::run_cycle with the
// sensors' precomputed ray tables, the zones, the safety logic and the CAN
// safety output encoder) on worst-case inputs, for many cycles.
//
// Worst case:
// - the paper's four sensors (204,288 pixels), every pixel a valid reading
//   at the sensor's maximum range, so every ray crosses the grid as far as
//   it can (its whole ray table) and no pixel is skipped;
// - kMaxZones (32) zones, each covering the whole grid (16 protective, 16
//   warning, boxes and prisms alternating), so every voxel belongs to every
//   zone: the zone stage visits the most (voxel, zone) pairs there can be;
// - a prior that makes every voxel foreground (the largest log-odds), so
//   every one of those pairs is counted (a real prior skips most of them).
// The CAN output encodes the three frames of each cycle (the safety frame
// carries the first 16 zones, kMaxZonesInFrame) into memory: no I/O.
//
// Printed: median, p99 and max cycle time (and per stage); the work bound
// of compute_work_bound (cycle.hpp) against the operations each cycle really
// performed (counted: the exit status is 1 if any cycle exceeded the
// bound); and the bound turned into time with per-operation costs measured
// in the same run. A program that prints figures, not a test with a time
// limit: time never decides the exit status.
//
// Then (issue 17) the robot's share: mark_robot_voxels + compute_separation
// on the same grid with the 6-axis test arm (tests/support/test_robot.hpp)
// in a new pose each call, for a typical scene (a person-sized cluster) and
// the worst ones (every voxel foreground, every voxel unseen in an active
// zone, both) and one that defeats the search's pruning; per call in
// microseconds of thread CPU time (median and the worst call), against this
// run's fusion and largest cycle.
//
// Usage: bench_cycle [--cycles N] [--no-timing] [--readings max-range|grid-exit|mid-ray|random]
//   --cycles N   measured cycles (default 10000), after 20 warm-up cycles
//   --readings   max-range (default, the worst case): every reading at
//                the sensor's maximum range; grid-exit: every reading 1 mm
//                before where its ray leaves the grid, so the same voxels are
//                walked but each ray's end must be searched for (a binary
//                search of its exit distances), its last voxels take the
//                sensor profile's ramp (a per-voxel table look-up) and its
//                last voxel the reading's peak; mid-ray: every reading in
//                the middle voxel of its ray's part in the grid, so half of
//                each table is walked (the most the ray table's hit
//                counting visits, ray_table.hpp) and the rest is not;
//                random: every reading in a voxel of its ray drawn at
//                random (a fixed seed), so where each search ends and how
//                long each ramp is cannot be predicted from the last pixel
//   --no-timing  no warm-up and no timing report (for callgrind:
//                tools/bench-cycle-callgrind.sh divides the instructions
//                counted inside run_cycle by N)
#include <algorithm>
#include <array>
#include <bitset>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <time.h>

#include "bench_cells.hpp"
#include "cellguard/base/crc32.hpp"
#include "cellguard/base/stack_paint.hpp"
#include "cellguard/can/safety_output.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/grid/ray_table.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/robot/robot_mask.hpp"
#include "cellguard/robot/separation.hpp"
#include "cellguard/safety/cycle.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/zones.hpp"
#include "test_robot.hpp"

using namespace cellguard;
using SteadyClock = std::chrono::steady_clock;

namespace {

constexpr int kWarmupCycles = 20;

/// The 1-minute load average (how busy the shared machine was).
double load_average() {
    double l = -1.0;
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &l) != 1) {
            l = -1.0;
        }
        std::fclose(f);
    }
    return l;
}

/// A CAN sender that keeps the last frame in memory (no I/O in the benchmark).
class MemorySender final : public CanSender {
public:
    bool send(const CanFrame& frame) noexcept override {
        last = frame;
        ++frames;
        return true;
    }
    CanFrame last{};
    std::uint64_t frames = 0U;
};

/// The CAN output bound after the controller (it needs the prior's CRC).
class Forward final : public CycleOutput {
public:
    bool publish(const CycleReport& r) noexcept override { return target != nullptr && target->publish(r); }
    CanSafetyOutput* target = nullptr;
};

/// One measured cycle.
struct CycleSample {
    double total_ms = 0.0;                               ///< around run_cycle, steady clock (wall time)
    double cpu_ms = 0.0;                                 ///< around run_cycle, this thread's CPU time
    std::array<std::uint64_t, kCycleStages> stage_us{};  ///< the controller's own stage timing
    std::uint64_t rays = 0U;                             ///< readings handled (fused + skipped)
    std::uint64_t voxel_steps = 0U;                      ///< voxel updates of fusion
    std::uint64_t zone_visits = 0U;                      ///< (voxel, zone) pairs the zone stage counted
};

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1U;
    return v[std::min(i, v.size() - 1U)];
}

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

/// This thread's CPU time, milliseconds (excludes time the scheduler gave
/// to other processes: the machines are shared).
double thread_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

/// The (voxel, zone) pairs evaluate_zones counted in the cycle just run:
/// a voxel's zone bits are walked when it is foreground or unseen
/// (zone_evaluation.cpp). Recounted from the frame grid, outside the timing.
std::uint64_t count_zone_visits(const EvidenceGrid& frame, const std::vector<std::int16_t>& prior,
                                const CompiledZones& zones, const ZoneEvaluationParams& params) {
    std::uint64_t visits = 0U;
    const Span<const std::uint32_t> mask = zones.membership();
    for (std::size_t i = 0U; i < frame.voxel_count(); ++i) {
        const std::int16_t sum = add_saturating(frame.log_odds()[i], prior[i]);
        const bool fg = sum >= params.foreground_threshold;
        const bool unseen = frame.observed()[i] == 0U && prior[i] != kNeverForeground &&
                            prior[i] >= params.accessible_min_prior;
        if (fg || unseen) {
            visits += std::bitset<32>(mask[i]).count();
        }
    }
    return visits;
}

/// One scene of the robot section: the frame's log-odds, observed flags and the prior.
struct RobotScene {
    const char* name;
    std::vector<std::int16_t> frame;
    std::vector<std::uint8_t> observed;
    std::vector<std::int16_t> prior;
};

/// Times of one scene over many calls, microseconds of this thread's CPU time.
struct RobotTimes {
    std::vector<double> mark_us, sep_us, both_us;
    std::uint64_t most_tested = 0U;
    std::uint32_t most_candidates = 0U;
    std::uint16_t last_distance = 0U;
};

/// Robot masking and separation on the paper's grid (issue 17's goal: at
/// most 1 ms added to the cycle's worst case): the 6-axis test arm
/// (tests/support/test_robot.hpp) standing at the grid's centre, in a new
/// pose every call (a fixed sequence of poses over the joints' range), its
/// mask grown by 0.1 m, then compute_separation against the scene. The
/// zones are the benchmark's 32 zones covering the grid, all active.
void bench_robot(const GridGeometry& g, const std::vector<std::uint32_t>& membership, double fuse_median_ms,
                 double cycle_max_ms, int calls) {
    const RobotModel arm = test::make_test_arm(0.0, 0.0, 0.0);
    const double margin = 0.1;
    const std::size_t n = g.voxel_count();
    SeparationParams params;
    params.reaction_time_s = 0.2;
    params.class_count = 2U;
    params.classes[0] = SpeedClassLimits{1.0, 0.3, 0.2};
    params.classes[1] = SpeedClassLimits{0.25, 0.1, 0.02};
    params.reduced_class = 1U;
    params.slowdown_time_s = 0.5;
    params.intrusion_distance_m = 0.208;
    params.sensing_uncertainty_m = 0.1;
    params.robot_uncertainty_m = 0.02;
    params.min_foreground_voxels = 8U;
    params.min_hidden_voxels = 64U;

    // A fixed sequence of poses (64-bit LCG: the same on every platform).
    std::uint64_t lcg = 0x2545F4914F6CDD1DULL;
    std::vector<JointPositions> poses(64);
    for (JointPositions& q : poses) {
        q.count = 6U;
        for (std::size_t j = 0U; j < 6U; ++j) {
            lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL;
            q.q[j] = (static_cast<double>(lcg >> 11U) / 9007199254740992.0 - 0.5) * 2.0 * 3.1;
        }
    }

    std::vector<RobotScene> scenes;
    scenes.push_back({"empty: nothing foreground, all observed", std::vector<std::int16_t>(n, -400),
                      std::vector<std::uint8_t>(n, 1U), std::vector<std::int16_t>(n, -100)});
    // Typical: everything observed and empty, a person-sized cluster (4 x 4 x 12 voxels) about 0.7 m from the base axis.
    scenes.push_back({"typical: 192 foreground voxels (a person), all observed", std::vector<std::int16_t>(n, -400),
                      std::vector<std::uint8_t>(n, 1U), std::vector<std::int16_t>(n, -100)});
    for (std::int32_t z = 4; z < 16; ++z) {
        for (std::int32_t y = 13; y < 17; ++y) {
            for (std::int32_t x = 29; x < 33; ++x) {
                scenes.back().frame[g.index_of({x, y, z})] = 2000;
            }
        }
    }
    scenes.push_back({"worst: every voxel foreground", std::vector<std::int16_t>(n, kLogOddsMax),
                      std::vector<std::uint8_t>(n, 1U), std::vector<std::int16_t>(n, -100)});
    scenes.push_back({"worst: every voxel unseen in the active zones", std::vector<std::int16_t>(n, 0),
                      std::vector<std::uint8_t>(n, 0U), std::vector<std::int16_t>(n, -100)});
    scenes.push_back({"worst: every voxel foreground and unseen", std::vector<std::int16_t>(n, kLogOddsMax),
                      std::vector<std::uint8_t>(n, 0U), std::vector<std::int16_t>(n, -100)});
    // Adversarial for the search's pruning: foreground everywhere 0.4 m and more from the base's axis, so the
    // k-th distance stays large and many rows near the robot must be read and many distances computed.
    scenes.push_back({"hard: foreground everywhere >= 0.4 m from the base axis", std::vector<std::int16_t>(n, -400),
                      std::vector<std::uint8_t>(n, 1U), std::vector<std::int16_t>(n, -100)});
    for (std::size_t i = 0U; i < n; ++i) {
        const Eigen::Vector3d c = g.voxel_center(g.coord_of(i));
        if (c.x() * c.x() + c.y() * c.y() >= 0.16) {
            scenes.back().frame[i] = 2000;
        }
    }

    std::vector<std::uint8_t> mask(n);
    const std::uint64_t mark_bound = robot_mask_work_bound(arm, margin, g.voxel_size());
    std::printf(
        "\nrobot masking + separation (issue 17) on the paper's grid, %d calls per scene, a new pose each call:\n",
        calls);
    std::printf(
        "  6-axis test arm (UR10 sizes, 7 capsules) at the grid's centre, margin %.2f m, k = %u foreground /"
        " %u hidden voxels,\n  %zu zones all active; times are this thread's CPU time per call, microseconds\n",
        margin, params.min_foreground_voxels, params.min_hidden_voxels, static_cast<std::size_t>(kMaxZones));
    std::printf("  %-58s %8s %8s %8s %8s %8s %9s %9s\n", "scene", "mark med", "sep med", "both med", "both p99",
                "both max", "max tests", "max cands");
    double worst_both = 0.0;
    for (const RobotScene& scene : scenes) {
        SeparationInputs in;
        in.frame_log_odds = {scene.frame.data(), n};
        in.observed = {scene.observed.data(), n};
        in.prior = {scene.prior.data(), n};
        in.robot_mask = {mask.data(), n};
        in.zone_membership = {membership.data(), n};
        in.active_zones = 0xFFFFFFFFU;
        RobotTimes t;
        for (int k = 0; k < kWarmupCycles + calls; ++k) {
            RobotPose pose;
            place_robot(arm, poses[static_cast<std::size_t>(k) % poses.size()], pose);
            RobotMaskStats stats;
            SeparationResult result;
            const double c0 = thread_cpu_ms();
            const Status m = mark_robot_voxels(g, pose, margin, {mask.data(), n}, stats);
            const double c1 = thread_cpu_ms();
            const Status sep = compute_separation(g, in, pose, params, 0U, result);
            const double c2 = thread_cpu_ms();
            if (!m.ok() || !sep.ok()) {
                std::fprintf(stderr, "bench_cycle: robot section refused its input\n");
                std::exit(2);
            }
            if (k < kWarmupCycles) {
                continue;
            }
            t.mark_us.push_back((c1 - c0) * 1000.0);
            t.sep_us.push_back((c2 - c1) * 1000.0);
            t.both_us.push_back((c2 - c0) * 1000.0);
            t.most_tested = std::max(t.most_tested, stats.tested);
            t.most_candidates = std::max(t.most_candidates, result.candidates);
        }
        const double both_max = *std::max_element(t.both_us.begin(), t.both_us.end());
        worst_both = std::max(worst_both, both_max);
        std::printf("  %-58s %8.1f %8.1f %8.1f %8.1f %8.1f %9llu %9u\n", scene.name, median(t.mark_us),
                    median(t.sep_us), median(t.both_us), percentile(t.both_us, 0.99), both_max,
                    static_cast<unsigned long long>(t.most_tested), t.most_candidates);
    }
    std::printf(
        "  mask work bound (robot_mask_work_bound): %llu voxel tests; separation bound: %zu voxels x %u capsules\n",
        static_cast<unsigned long long>(mark_bound), n, static_cast<unsigned>(arm.capsule_count));
    std::printf(
        "  worst call (both, max over scenes and calls): %.1f us = %.1f %% of this run's median fusion (%.3f ms)"
        "\n  and %.1f %% of its largest measured cycle (%.3f ms); the goal is at most 1000 us added\n",
        worst_both, 100.0 * worst_both / (fuse_median_ms * 1000.0), fuse_median_ms,
        100.0 * worst_both / (cycle_max_ms * 1000.0), cycle_max_ms);
}

[[noreturn]] void usage(const char* message) {
    std::fprintf(
        stderr,
        "bench_cycle: %s\nusage: bench_cycle [--cycles N] [--no-timing] [--readings max-range|grid-exit|mid-ray|random]\n",
        message);
    std::exit(2);
}

}  // namespace

/// CPU time per call of @p f, microseconds: the median over 31 batches of @p reps calls.
template <typename F>
double cost_us(int reps, F&& f) {
    std::vector<double> batches;
    for (int b = 0; b < 31; ++b) {
        const double t0 = thread_cpu_ms();
        for (int r = 0; r < reps; ++r) {
            f();
        }
        batches.push_back((thread_cpu_ms() - t0) * 1000.0 / reps);
    }
    return median(batches);
}

/// The memory diagnostics of hazards H-MEM-2..4: each one's cost per cycle
/// (this thread's CPU time) and the ray-table check's detection time for
/// slices of 256 KiB, 1 MiB and 2 MiB (the largest of @p table_bytes).
void bench_memory_checks(const SafetyController& controller, const ControllerConfig& cc,
                         const std::vector<std::size_t>& table_bytes) {
    std::printf("\nmemory diagnostics per cycle (H-MEM-2..4), this thread's CPU time, median of 31 batches:\n");
    Crc32TableCheck tables;
    const double crc_table_us = cost_us(2000, [&] { static_cast<void>(tables.step(cc.crc_table_check_values)); });
    std::printf("  CRC-32 tables: %u byte values (%u entries) per cycle: %.3f us; a pass in %u cycles\n",
                cc.crc_table_check_values, 8U * cc.crc_table_check_values, crc_table_us,
                Crc32TableCheck::steps_per_pass(cc.crc_table_check_values));
    volatile std::uint32_t sink = 0U;
    const double seal_us = cost_us(20000, [&] { sink = sink + controller.state_crc(); });
    const CompiledZones no_zones{};
    SafetyLogic logic(cc.logic, no_zones);
    const double logic_us = cost_us(20000, [&] { sink = sink + logic.state_crc(); });
    std::printf(
        "  seals: the controller's state and configuration %.3f us, the safety logic's %.3f us per CRC;\n"
        "  each is computed twice per cycle (compared, then sealed): %.3f us per cycle\n",
        seal_us, logic_us, 2.0 * (seal_us + logic_us));
    std::vector<std::uint32_t> stack(1024U * 128U);
    StackPaint paint(Span<std::uint32_t>(stack.data(), stack.size()), 1024U);
    paint.paint();
    const double guard_us = cost_us(2000, [&] { sink = sink + (paint.guard_intact() ? 1U : 0U); });
    const double scan_us = cost_us(20, [&] { sink = sink + static_cast<std::uint32_t>(paint.high_water_bytes()); });
    std::printf(
        "  stack guard band of 4 KiB: %.3f us per cycle (the high-water scan of 512 KiB, for summaries: %.1f us)\n",
        guard_us, scan_us);
    std::vector<std::uint8_t> bytes(2U * 1024U * 1024U);
    for (std::size_t i = 0U; i < bytes.size(); ++i) {
        bytes[i] = static_cast<std::uint8_t>(i * 131U);
    }
    const std::size_t largest = *std::max_element(table_bytes.begin(), table_bytes.end());
    std::printf("  ray-table check, one sensor's slice per cycle (%zu sensors in turn, largest table %zu bytes):\n",
                table_bytes.size(), largest);
    std::printf("    %-10s %12s %14s %22s %22s\n", "slice", "cost/cycle", "cycles/pass", "2 passes @ 100 ms",
                "2 passes @ 10 ms");
    for (const std::size_t slice : {std::size_t{262144U}, std::size_t{1048576U}, std::size_t{2097152U}}) {
        const double us = cost_us(3, [&] { sink = sink + crc32(Span<const std::uint8_t>(bytes.data(), slice)); });
        const std::size_t pass = table_bytes.size() * ((largest + slice - 1U) / slice);
        std::printf("    %4zu KiB%s %9.1f us %14zu %17zu cyc %4.1f s %13zu cyc %4.2f s\n", slice / 1024U,
                    slice == cc.table_check_slice_bytes ? "*" : " ", us, pass, 2U * pass,
                    static_cast<double>(2U * pass) * 0.1, 2U * pass, static_cast<double>(2U * pass) * 0.01);
    }
    std::printf("    (* the default, ControllerConfig::table_check_slice_bytes)\n");
}

int main(int argc, char** argv) {
    int cycles = 10000;
    bool timing = true;
    bool grid_exit = false;
    bool mid_ray = false;
    bool random_voxel = false;
    std::uint64_t lcg = 0x853c49e6748fea9bULL;  // the random pattern's generator state
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--cycles" && i + 1 < argc) {
            char* end = nullptr;
            const long n = std::strtol(argv[++i], &end, 10);
            if (end == nullptr || *end != '\0' || n < 1 || n > 10000000) {
                usage("--cycles expects an integer 1..10000000");
            }
            cycles = static_cast<int>(n);
        } else if (a == "--no-timing") {
            timing = false;
        } else if (a == "--readings" && i + 1 < argc) {
            const std::string v = argv[++i];
            if (v != "max-range" && v != "grid-exit" && v != "mid-ray" && v != "random") {
                usage("--readings expects max-range, grid-exit, mid-ray or random");
            }
            grid_exit = v == "grid-exit";
            mid_ray = v == "mid-ray";
            random_voxel = v == "random";
        } else {
            usage(("unknown argument '" + a + "'").c_str());
        }
    }

    // The paper's grid and sensors (apps/monitor/config/paper-cell.toml).
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, 0.0), 0.05, GridDims{34, 30, 30}).value();
    const std::vector<sim::SensorSpec> specs = sim::paper_sensors();
    const std::size_t n_sensors = specs.size();

    // Ray tables, built as cellguard-monitor builds them.
    std::vector<SensorReading> readings(n_sensors);
    std::vector<std::vector<float>> depth(n_sensors);
    std::vector<host::OwnedRayTable> tables(n_sensors);
    std::uint64_t table_voxel_steps = 0U;  // every pixel's whole ray in the grid
    for (std::size_t s = 0U; s < n_sensors; ++s) {
        const std::size_t px = static_cast<std::size_t>(specs[s].width) * static_cast<std::size_t>(specs[s].height);
        SensorReading& r = readings[s];
        r.pose = specs[s].pose();
        r.kind = SensorDataKind::kDepthImage;
        r.intrinsics = specs[s].intrinsics();
        r.max_range = specs[s].max_range;
        depth[s].assign(px, 1.0F);
        r.depth = Span<const float>(depth[s].data(), px);
        if (!tables[s].build(g, r).ok()) {
            std::fprintf(stderr, "bench_cycle: ray table of sensor %zu refused\n", s);
            return 2;
        }
        table_voxel_steps += tables[s].table().step_count();
        const RayTable& table = tables[s].table();
        // Every reading at the maximum range: depth along the axis = range / |dir|,
        // the largest float whose range (as the table computes it) is within max_range.
        // grid-exit: the reading 1 mm before where the ray leaves the grid;
        // mid-ray: the reading 1 mm before the exit of the ray's middle voxel;
        // random: 1 mm before the exit of a voxel drawn from the ray's voxels
        // (a 64-bit linear congruential generator: the same draws on every
        // platform, unlike std::uniform_int_distribution).
        for (std::size_t i = 0U; i < px; ++i) {
            float range = r.max_range;
            const std::uint32_t b = table.pixel_begin(i);
            const std::uint32_t e = table.pixel_begin(i + 1U);
            if (grid_exit && e > b) {
                range = std::min(r.max_range, table.entry_exit(i, e - 1U) - 0.001F);
            }
            if (mid_ray && e > b) {
                range = std::min(r.max_range, table.entry_exit(i, b + (e - b) / 2U) - 0.001F);
            }
            if (random_voxel && e > b) {
                lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL;
                const auto pick = static_cast<std::uint32_t>((lcg >> 33U) % (e - b));
                range = std::min(r.max_range, table.entry_exit(i, b + pick) - 0.001F);
            }
            const float norm = table.pixel_norm(i);
            float d = range / norm;
            while (d * norm > range) {
                d = std::nextafter(d, 0.0F);
            }
            depth[s][i] = d;
        }
    }

    // 32 zones covering the grid.
    const std::vector<ZoneConfig> zone_configs = bench::worst_case_zones(g);
    std::vector<std::uint32_t> membership(g.voxel_count());
    const Result<CompiledZones, ZoneError> compiled = CompiledZones::compile(
        g, {zone_configs.data(), zone_configs.size()}, {membership.data(), membership.size()});
    if (!compiled.ok()) {
        std::fprintf(stderr, "bench_cycle: zone %zu: %s\n", compiled.error().zone, compiled.error().reason);
        return 2;
    }
    const CompiledZones zones = compiled.value();

    // Grids and the worst-case prior (every voxel foreground).
    const SensorModelTable model;
    std::vector<std::int16_t> frame_lo(g.voxel_count());
    std::vector<std::uint8_t> frame_ob(g.voxel_count());
    EvidenceGrid frame_grid =
        EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
    const std::vector<std::int16_t> prior(g.voxel_count(), kLogOddsMax);

    ControllerConfig cc;
    cc.sensor_count = n_sensors;
    cc.cycle_budget_us = 5000U;  // the goal; overruns are counted, never fatal here
    cc.max_frame_age_us = 1000000U;
    // The frozen-sensor check on, so that its fingerprint of every frame is
    // in the measured cycle; its limit is never reached (these frames repeat).
    cc.max_repeated_frames = std::numeric_limits<std::uint32_t>::max();
    bench::ThreadCpuClock clock;
    Forward forward;
    // Every sensor has a ray table: fuse_sensor's scratch is never used.
    SafetyController controller(cc, frame_grid, Span<std::int16_t>(), {prior.data(), prior.size()}, zones, model, clock,
                                &forward);
    MemorySender sender;
    SafetyOutputConfig oc;
    oc.zone_count = static_cast<std::uint8_t>(kMaxZonesInFrame);
    oc.prior_crc = controller.prior_crc();
    // Session link off: the benchmark times the 0.1 frame set; the link frame is one more encode
    oc.session_link = false;
    CanSafetyOutput output(oc, sender);
    if (!output.status().ok()) {
        std::fprintf(stderr, "bench_cycle: CAN output refused: %s\n", to_string(output.status().error()));
        return 2;
    }
    forward.target = &output;

    const CycleWorkBound bound = compute_work_bound(g, {readings.data(), readings.size()}, zones);

    // The background check on, with the frames themselves as the
    // commissioned views (so it always passes): its comparison of every
    // pixel is in the measured cycle.
    std::vector<BackgroundReference> backgrounds(n_sensors);
    std::vector<SensorInput> inputs(n_sensors);
    for (std::size_t s = 0U; s < n_sensors; ++s) {
        backgrounds[s].depth = readings[s].depth;
        inputs[s].reading = readings[s];
        inputs[s].present = true;
        inputs[s].table = &tables[s].table();
        inputs[s].background = &backgrounds[s];
    }

    std::printf("bench_cycle: the paper's cell, worst-case inputs\n");
    std::printf("  grid %d x %d x %d = %zu voxels; %zu sensors, %llu pixels, every reading %s\n", g.dims().nx,
                g.dims().ny, g.dims().nz, g.voxel_count(), n_sensors, static_cast<unsigned long long>(bound.rays),
                grid_exit      ? "1 mm before where its ray leaves the grid"
                : mid_ray      ? "in the middle voxel of its ray in the grid"
                : random_voxel ? "in a randomly drawn voxel of its ray in the grid"
                               : "at the sensor's max range (10 m)");
    std::printf("  %zu zones (kMaxZones), each covering the grid; prior: every voxel foreground (%d)\n", zones.size(),
                static_cast<int>(kLogOddsMax));
    // The periodic ray-table check: one sensor's slice per cycle, the sensors in turn.
    std::size_t table_bytes = 0U;
    std::size_t slowest_pass = 0U;  // cycles until the largest table has been read once
    for (std::size_t s = 0U; s < n_sensors; ++s) {
        const std::size_t bytes = tables[s].table().checked_bytes();
        table_bytes += bytes;
        slowest_pass = std::max(slowest_pass,
                                n_sensors * ((bytes + cc.table_check_slice_bytes - 1U) / cc.table_check_slice_bytes));
    }
    std::printf(
        "  ray-table check: %zu bytes of table RAM, %zu per cycle (prior: %zu, zone mask: %zu per cycle);\n"
        "  the largest table is read once every %zu cycles\n",
        table_bytes, cc.table_check_slice_bytes, cc.prior_check_slice_bytes, cc.zone_check_slice_bytes, slowest_pass);
    std::printf(
        "  frozen-sensor check on: every frame is fingerprinted (its limit is set out of reach);\n"
        "  background check on: every pixel is compared with a view (the frame itself, so it passes)\n");
    std::printf(
        "  every cycle fuses the same frames and does the same work; cycles differ only in which slices\n"
        "  the integrity checks read, so the spread of the cycle times below does not come from the input\n");

    // Warm-up (not measured), then the measured cycles.
    const int warmup = timing ? kWarmupCycles : 0;
    std::vector<CycleSample> samples;
    samples.reserve(static_cast<std::size_t>(cycles));
    bool over_bound = false;
    std::uint64_t faults = 0U;
    CycleSample worst_ops;
    for (int k = 0; k < warmup + cycles; ++k) {
        const std::uint64_t captured = clock.now_us();
        for (SensorInput& in : inputs) {
            in.captured_us = captured;
        }
        const double c0 = thread_cpu_ms();
        const auto t0 = SteadyClock::now();
        const CycleReport& r = controller.run_cycle({inputs.data(), inputs.size()}, false);
        const auto t1 = SteadyClock::now();
        const double c1 = thread_cpu_ms();
        faults |= r.detected_faults;
        if (k < warmup) {
            continue;
        }
        CycleSample s;
        s.total_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
        s.cpu_ms = c1 - c0;
        for (std::size_t st = 0U; st < kCycleStages; ++st) {
            s.stage_us[st] = controller.monitor().last().stage_us[st];
        }
        s.rays = static_cast<std::uint64_t>(r.fusion.rays_fused) + r.fusion.skipped();
        s.voxel_steps = r.fusion.voxel_updates;
        s.zone_visits = timing || k == 0 ? count_zone_visits(frame_grid, prior, zones, cc.zones) : 0U;
        over_bound = over_bound || s.rays > bound.rays || s.voxel_steps > bound.voxel_steps ||
                     s.zone_visits > bound.zone_updates;
        worst_ops.rays = std::max(worst_ops.rays, s.rays);
        worst_ops.voxel_steps = std::max(worst_ops.voxel_steps, s.voxel_steps);
        worst_ops.zone_visits = std::max(worst_ops.zone_visits, s.zone_visits);
        samples.push_back(s);
    }
    const std::uint32_t unexpected = static_cast<std::uint32_t>(faults) & ~fault_bit(Fault::kCycleOverrun);

    std::printf("\nwork per cycle: computed bound (compute_work_bound) vs the most any measured cycle performed\n");
    std::printf("  %-34s %12s %12s\n", "operation", "bound", "measured");
    std::printf("  %-34s %12llu %12llu\n", "rays (readings)", static_cast<unsigned long long>(bound.rays),
                static_cast<unsigned long long>(worst_ops.rays));
    std::printf("  %-34s %12llu %12llu   (ray tables' exact maximum: %llu)\n", "voxel steps (fusion)",
                static_cast<unsigned long long>(bound.voxel_steps),
                static_cast<unsigned long long>(worst_ops.voxel_steps),
                static_cast<unsigned long long>(table_voxel_steps));
    std::printf("  %-34s %12llu %12llu   (clear + subtract + each table's hit counts: by construction)\n",
                "grid-pass voxels", static_cast<unsigned long long>(bound.grid_voxels),
                static_cast<unsigned long long>((2U + 3U * n_sensors) * g.voxel_count()));
    std::printf("  %-34s %12llu %12llu%s\n", "zone updates ((voxel, zone) pairs)",
                static_cast<unsigned long long>(bound.zone_updates),
                static_cast<unsigned long long>(worst_ops.zone_visits), timing ? "" : "   (first cycle only)");
    std::printf("  measured <= bound in every cycle: %s\n", over_bound ? "NO (bound violated)" : "yes");
    std::printf("  CAN frames encoded: %llu; faults detected other than overrun: 0x%X\n",
                static_cast<unsigned long long>(sender.frames), unexpected);

    if (!timing) {
        std::printf("\n%d cycles run (no timing: count instructions with tools/bench-cycle-callgrind.sh)\n", cycles);
        return over_bound ? 1 : 0;
    }

    std::vector<double> wall, cpu, fuse_ms, zone_ms, rest_ms, step_ns, zone_ns;
    for (const CycleSample& s : samples) {
        wall.push_back(s.total_ms);
        cpu.push_back(s.cpu_ms);
        const auto fuse_us = static_cast<double>(s.stage_us[0]);
        const auto zones_us = static_cast<double>(s.stage_us[1]);
        fuse_ms.push_back(fuse_us / 1000.0);
        zone_ms.push_back(zones_us / 1000.0);
        rest_ms.push_back(static_cast<double>(s.stage_us[2] + s.stage_us[3]) / 1000.0);
        // Per-operation costs of this cycle. Fusion's time is charged to its
        // voxel steps (the per-ray overhead and the grid clear included, so
        // the cost per step is an overestimate); the zone stage's time to its
        // grid pass plus its (voxel, zone) visits.
        step_ns.push_back(fuse_us * 1000.0 / static_cast<double>(std::max<std::uint64_t>(s.voxel_steps, 1U)));
        zone_ns.push_back(zones_us * 1000.0 /
                          static_cast<double>(g.voxel_count() + std::max<std::uint64_t>(s.zone_visits, 1U)));
    }
    const auto row = [](const char* name, const std::vector<double>& v) {
        std::printf("  %-34s %7.3f ms %7.3f ms %7.3f ms\n", name, median(v), percentile(v, 0.99),
                    *std::max_element(v.begin(), v.end()));
    };
    const double max_cpu = *std::max_element(cpu.begin(), cpu.end());
    const double max_wall = *std::max_element(wall.begin(), wall.end());
    std::printf("\ncycle time over %d cycles (after %d warm-up cycles), one thread; load average %.1f at the end\n",
                cycles, warmup, load_average());
    std::printf("  %-34s %10s %10s %10s\n", "", "median", "p99", "max");
    row("whole cycle, thread CPU time", cpu);
    row("  fuse (clear + ray tables)", fuse_ms);
    row("  subtract + zones", zone_ms);
    row("  logic + CAN output", rest_ms);
    row("whole cycle, wall clock", wall);
    std::printf(
        "  cycles over the 5 ms goal: %zu by CPU time, %zu by wall clock (wall time includes preemption\n"
        "  by other processes on this shared machine); rate at the largest CPU-time cycle: %.0f Hz\n",
        static_cast<std::size_t>(std::count_if(cpu.begin(), cpu.end(), [](double t) { return t > 5.0; })),
        static_cast<std::size_t>(std::count_if(wall.begin(), wall.end(), [](double t) { return t > 5.0; })),
        1000.0 / max_cpu);

    // The bound in time: operations of the bound x per-operation costs
    // measured above, plus the largest logic + output time seen.
    const auto bound_ms = [&](double ns_step, double ns_zone, double rest) {
        return (static_cast<double>(bound.voxel_steps) * ns_step +
                static_cast<double>(g.voxel_count() + bound.zone_updates) * ns_zone) /
                   1e6 +
               rest;
    };
    const double rest_max = *std::max_element(rest_ms.begin(), rest_ms.end());
    const double b_med = bound_ms(median(step_ns), median(zone_ns), rest_max);
    const double b_p99 = bound_ms(percentile(step_ns, 0.99), percentile(zone_ns, 0.99), rest_max);
    const double tight_ms = (static_cast<double>(table_voxel_steps) * median(step_ns) +
                             static_cast<double>(g.voxel_count() + bound.zone_updates) * median(zone_ns)) /
                                1e6 +
                            rest_max;
    std::printf("\ncomputed bound in time (the bound's operations x per-operation CPU cost measured in this run):\n");
    std::printf(
        "  cost per voxel step %.3f ns (median; p99 %.3f); per grid voxel or zone visit %.3f ns (median; p99 %.3f)\n",
        median(step_ns), percentile(step_ns, 0.99), median(zone_ns), percentile(zone_ns, 0.99));
    std::printf("  compute_work_bound: %.3f ms at median costs, %.3f ms at p99 costs\n", b_med, b_p99);
    std::printf("  (with the ray tables' exact step count instead: %.3f ms at median costs)\n", tight_ms);
    std::printf("  largest measured cycle: %.3f ms CPU time, %.3f ms wall clock\n", max_cpu, max_wall);
    std::printf(
        "  bound (median costs) above every measured cycle's CPU time: %s (%.2fx the largest); "
        "above every wall-clock time: %s\n",
        b_med >= max_cpu ? "yes" : "NO", b_med / max_cpu, b_med >= max_wall ? "yes" : "no");
    std::vector<std::size_t> table_sizes;
    for (const host::OwnedRayTable& t : tables) {
        table_sizes.push_back(t.table().checked_bytes());
    }
    bench_memory_checks(controller, cc, table_sizes);
    bench_robot(g, membership, median(fuse_ms), max_cpu, std::min(cycles, 2000));
    return over_bound ? 1 : 0;
}
