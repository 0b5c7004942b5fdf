// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Soak run of the monitor's cycle (issue 21): the monitor's own loop
// (MonitorLoop, as cellguard-monitor wires it: the cell's prior and ray
// tables, the simulated sensors, the CAN output encoding its frames into a
// counting sender instead of a socket, status lines into a buffered sink)
// for many cycles, with the demo's person walking through the cell again
// and again (the scene's cycle is the cycle modulo --scene-cycles, so the
// stop, the restart and the warnings come back in every round).
//
// Checked in every cycle, and counted:
// - missed deadlines: the controller's cycle took longer than the
//   configuration's budget (the overrun the controller itself detects and
//   latches as kCycleOverrun), split by the cycle thread's CPU time: over
//   the budget in CPU time is the cycle's own work and fails the soak;
//   within it, the thread waited for a core (the host's doing: printed, the
//   controller's overrun report checked, not a failure);
// - allocations: any heap allocation on the cycle's thread during the cycle
//   (tests/support/alloc_counter: operator new and glibc malloc);
// - the work bound: the rays (readings) and the ray method's voxel steps of
//   the cycle against the cell's compute_work_bound (monitor_cell.hpp);
// - faults: any fault other than an overrun fails (the demo's scene latches none);
// - decisions: every round of the scene must stop exactly as the first did
//   in every round without a latched fault, in it or in the round before (whose recovery and restart delay
//   reach into it) (the stop starts in the same cycle of the scene, and lasts as long within
//   one cycle: the restart delay runs on the cycle clock, which advances
//   with real time within a cycle, so its end may fall a cycle later).
// Printed: the counts, the cycle time's median, p99, p99.99 and maximum
// (histogram of 10 us bins), the process's peak resident memory in MiB
// and the load average. Exit status 1 when any check failed, 2 on a bad
// argument or a cell that cannot be built.
//
// Usage: soak_monitor [--cycles N] [--config FILE] [--scene-cycles L] [--progress K]
//   --cycles N         cycles to run (default 100000)
//   --config FILE      a monitor configuration (default: the built-in demo)
//   --scene-cycles L   the scene repeats every L cycles (default 60, the demo's run)
//   --progress K       a progress line every K cycles (default 0: none)
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/port/clock.hpp"
#include "monitor_test_doubles.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;

namespace {

/// Passes each load on with the scene's cycle: @p cycle modulo the scene's length.
class LoopingSource final : public FrameSource {
public:
    LoopingSource(FrameSource& inner, std::uint64_t scene_cycles) : inner_(&inner), scene_(scene_cycles) {}
    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override {
        return inner_->load_frame(cycle % scene_, reading, status);
    }
    void write_summary(std::FILE* out) const noexcept override { inner_->write_summary(out); }

private:
    FrameSource* inner_;
    std::uint64_t scene_;
};

/// Cycle times in 10 us bins up to 1 s; longer ones in the last bin (the maximum is kept exactly).
class CycleHistogram {
public:
    void add(std::uint64_t us) noexcept {
        ++bins_[std::min<std::uint64_t>(us / kBinUs, kBins - 1U)];
        ++count_;
        max_ = std::max(max_, us);
    }
    /// The upper edge of the bin holding quantile @p q (0..1), microseconds.
    [[nodiscard]] double quantile_us(double q) const noexcept {
        const auto target = static_cast<std::uint64_t>(q * static_cast<double>(count_));
        std::uint64_t seen = 0U;
        for (std::size_t b = 0U; b < kBins; ++b) {
            seen += bins_[b];
            if (seen > target) {
                return static_cast<double>((b + 1U) * kBinUs);
            }
        }
        return static_cast<double>(max_);
    }
    [[nodiscard]] std::uint64_t max_us() const noexcept { return max_; }

private:
    static constexpr std::uint64_t kBinUs = 10U;
    static constexpr std::size_t kBins = 100000U;
    std::array<std::uint64_t, kBins> bins_{};
    std::uint64_t count_ = 0U;
    std::uint64_t max_ = 0U;
};

struct Options {
    long cycles = 100000;
    std::string config;
    long scene_cycles = 60;
    long progress = 0;
};

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        char* end = nullptr;
        if (a == "--config" && has_value) {
            o.config = argv[++i];
            continue;
        }
        long* target = a == "--cycles"         ? &o.cycles
                       : a == "--scene-cycles" ? &o.scene_cycles
                       : a == "--progress"     ? &o.progress
                                               : nullptr;
        if (target == nullptr || !has_value) {
            return false;
        }
        *target = std::strtol(argv[++i], &end, 10);
        if (end == nullptr || *end != '\0' || *target < (target == &o.progress ? 0 : 1) || *target > 100000000L) {
            return false;
        }
    }
    return true;
}

/// The calling thread's CPU time, microseconds.
std::uint64_t thread_cpu_us() {
    timespec t{};
    static_cast<void>(clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t));
    return static_cast<std::uint64_t>(t.tv_sec) * 1000000U + static_cast<std::uint64_t>(t.tv_nsec) / 1000U;
}

double peak_rss_mib() {
    rusage u{};
    return getrusage(RUSAGE_SELF, &u) == 0 ? static_cast<double>(u.ru_maxrss) / 1024.0 : -1.0;
}

double load_average() {
    double l[1] = {-1.0};
    return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

/// The counts of a soak run.
struct SoakCounts {
    std::uint64_t missed_deadlines = 0U;       ///< cycles longer than the budget
    std::uint64_t missed_by_cpu = 0U;          ///< of those, cycles whose own CPU time exceeded the budget
    std::uint64_t worst_cpu_us = 0U;           ///< the most CPU time any cycle took (cycle, load and output)
    std::uint64_t missed_worst_cpu_us = 0U;    ///< the most CPU time among the cycles over the budget
    std::uint64_t cycles_that_allocated = 0U;  ///< cycles with a heap allocation on the cycle's thread
    std::uint64_t allocations = 0U;            ///< those allocations
    std::uint64_t over_work_bound = 0U;        ///< cycles whose rays or voxel steps exceeded the bound
    std::uint64_t faulted_cycles = 0U;         ///< cycles with a fault detected other than a cycle overrun
    std::uint64_t overrun_cycles = 0U;         ///< cycles that reported the overrun of the cycle before
    std::uint64_t rounds_that_differ = 0U;     ///< fault-free scene rounds whose stops differ from the reference's
    std::uint64_t rounds_with_a_fault = 0U;    ///< scene rounds with a fault latched (not compared)
    std::uint64_t rounds_after_a_fault = 0U;   ///< scene rounds right after one with a fault (not compared)
    std::uint64_t stop_cycles = 0U;            ///< cycles with the stop requested
    std::uint64_t most_rays = 0U, most_steps = 0U;
};

/// The first cycle with the stop in @p round, or the round's length.
std::size_t first_stop(const std::vector<std::uint8_t>& round) {
    return static_cast<std::size_t>(std::find(round.begin(), round.end(), 1U) - round.begin());
}

/// Whether @p a stops in the same scene cycle as @p b and for as many cycles, within one.
bool same_stops(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    const auto count = [](const std::vector<std::uint8_t>& r) { return std::count(r.begin(), r.end(), 1U); };
    const auto ca = count(a);
    const auto cb = count(b);
    return first_stop(a) == first_stop(b) && ca <= cb + 1 && cb <= ca + 1;
}

void print_round(const char* name, const std::vector<std::uint8_t>& round) {
    std::printf("    %-12s ", name);
    for (const std::uint8_t stop : round) {
        std::printf("%c", stop != 0U ? 'S' : '.');
    }
    std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse(argc, argv, o)) {
        std::fprintf(stderr, "usage: soak_monitor [--cycles N] [--config FILE] [--scene-cycles L] [--progress K]\n");
        return 2;
    }
    MonitorConfig cfg = demo_config();
    if (!o.config.empty()) {
        const ConfigLoad load = load_monitor_config(o.config);
        if (!load.ok) {
            std::fprintf(stderr, "soak_monitor: %s\n", load.error.c_str());
            return 2;
        }
        cfg = load.config;
    }
    cfg.demo_cycles = 0;  // the loop's own per-cycle records: the histogram here instead
    MonitorCell cell;
    if (cell.configure(cfg).failed() || cell.build_prior(cfg, nullptr).failed() ||
        cell.build_tables(cfg, nullptr).failed()) {
        std::fprintf(stderr, "soak_monitor: the cell could not be built\n");
        return 2;
    }
    std::vector<std::unique_ptr<FrameSource>> inner;
    std::vector<std::unique_ptr<LoopingSource>> looping;
    std::vector<FrameSource*> sources;
    for (std::size_t s = 0U; s < cfg.sensors.size(); ++s) {
        const sim::SensorSpec& spec = cell.specs[s];
        if (cfg.sensors[s].pcd_files.empty()) {
            inner.push_back(std::make_unique<SimulatedFrameSource>(spec));
        } else {
            inner.push_back(std::make_unique<PcdFrameSource>(spec.name, cfg.sensors[s].pcd_files,
                                                             sensor_pose(cfg.sensors[s]), spec.width, spec.height,
                                                             spec.max_range));
        }
        looping.push_back(std::make_unique<LoopingSource>(*inner.back(), static_cast<std::uint64_t>(o.scene_cycles)));
        sources.push_back(looping.back().get());
    }
    linux_port::LinuxMonotonicClock real_clock;
    // A measurement: the controller sees each cycle's real duration on simulated cycle starts, so a
    // cycle the host made late is an overrun it reports (cycle_clock.hpp).
    CycleClock clock(CycleClock::Mode::kSimulatedWithRealElapsed, real_clock);
    test::CountingSender sender;
    CanPort can;
    can.use_sender(sender);
    std::FILE* sink = std::fopen("/dev/null", "w");
    static char sink_buffer[1U << 16U];
    if (sink == nullptr || std::setvbuf(sink, sink_buffer, _IOFBF, sizeof sink_buffer) != 0) {
        std::fprintf(stderr, "soak_monitor: cannot open /dev/null\n");
        return 2;
    }
    MonitorLoop loop(cfg, cell, sources, can, clock, sink);
    if (!loop.status().ok()) {
        std::fprintf(stderr, "soak_monitor: the loop cannot run this configuration\n");
        return 2;
    }
    const bool ray_method = cfg.fusion.method == FusionMethod::kRay;
    const CycleWorkBound& bound = cell.work;
    auto histogram = std::make_unique<CycleHistogram>();
    SoakCounts n;
    const auto scene = static_cast<std::size_t>(o.scene_cycles);
    std::vector<std::uint8_t> first_round(scene, 0U), this_round(scene, 0U);
    bool round_faulted = false;     // a fault was latched in some cycle of this round
    bool previous_faulted = false;  // ... or in the round before: its recovery and restart delay reach into this one
    std::printf(
        "soak_monitor: %ld cycles of %s, %zu sensors, the scene repeating every %ld cycles, budget %.1f ms, "
        "fusion: %s\n",
        o.cycles, o.config.empty() ? "the built-in demo" : o.config.c_str(), cfg.sensors.size(), o.scene_cycles,
        static_cast<double>(cfg.budget_us) / 1000.0, ray_method ? "ray tables" : "footprint");
    std::fflush(stdout);
    for (long k = 0; k < o.cycles; ++k) {
        const test::ThreadAllocationScope scope;
        const std::uint64_t cpu0 = thread_cpu_us();
        const CycleReport& r = loop.run_cycle(static_cast<int>(k));
        const std::uint64_t cpu = thread_cpu_us() - cpu0;  // the frames' loading included: an upper bound
        const std::size_t allocated = scope.allocations();
        const std::uint64_t us = loop.controller().monitor().last().total_us;
        histogram->add(us);
        n.worst_cpu_us = std::max(n.worst_cpu_us, cpu);
        if (us > cfg.budget_us) {
            // Wall-clock time over the budget: the cycle's own work when its CPU time is too, else a
            // thread that waited for a core (the host's doing; the controller still latches the overrun).
            ++n.missed_deadlines;
            n.missed_by_cpu += cpu > cfg.budget_us ? 1U : 0U;
            n.missed_worst_cpu_us = std::max(n.missed_worst_cpu_us, cpu);
        }
        n.cycles_that_allocated += allocated != 0U ? 1U : 0U;
        n.allocations += allocated;
        const std::uint64_t rays = static_cast<std::uint64_t>(r.fusion.rays_fused) + r.fusion.skipped();
        n.most_rays = std::max(n.most_rays, rays);
        n.most_steps = std::max(n.most_steps, r.fusion.voxel_updates);
        n.over_work_bound += (rays > bound.rays || (ray_method && r.fusion.voxel_updates > bound.voxel_steps)) ? 1U
                                                                                                               : 0U;
        const std::uint32_t overrun = fault_bit(Fault::kCycleOverrun);
        n.faulted_cycles += (r.detected_faults & ~overrun) != 0U ? 1U : 0U;
        n.overrun_cycles += (r.detected_faults & overrun) != 0U ? 1U : 0U;
        round_faulted = round_faulted || r.safety.latched_faults != 0U;
        n.stop_cycles += r.safety.stop_requested ? 1U : 0U;
        const auto c = static_cast<std::size_t>(k) % scene;
        // The first round includes the start-up interlock; rounds are compared from the second on.
        (k < o.scene_cycles ? first_round : this_round)[c] = r.safety.stop_requested ? 1U : 0U;
        if (k >= 2 * o.scene_cycles && c + 1U == scene && round_faulted) {
            ++n.rounds_with_a_fault;  // a latched fault holds the stop: not the scene's decisions
        } else if (k >= 2 * o.scene_cycles && c + 1U == scene && previous_faulted) {
            // A fault latched late in the round before clears only after its recovery cycles, and the
            // restart delay then holds the stop into this round (seen: a round opening with 5 stop cycles).
            ++n.rounds_after_a_fault;
        } else if (k >= 2 * o.scene_cycles && c + 1U == scene) {
            if (!same_stops(this_round, first_round) && n.rounds_that_differ++ == 0U) {
                std::printf("  the round ending in cycle %ld stopped otherwise than the second round (S: stop):\n", k);
                print_round("this round", this_round);
                print_round("second round", first_round);
            }
        } else if (k >= o.scene_cycles && c + 1U == scene) {
            first_round = this_round;  // the second round is the reference (the first starts interlocked)
        }
        if (c + 1U == scene) {
            previous_faulted = round_faulted;
            round_faulted = false;
        }
        if (o.progress > 0 && (k + 1) % o.progress == 0) {
            std::printf(
                "  %ld cycles: max %.2f ms, missed %llu (by CPU time %llu), allocating %llu, over bound %llu, "
                "faulted %llu\n",
                k + 1, static_cast<double>(histogram->max_us()) / 1000.0,
                static_cast<unsigned long long>(n.missed_deadlines), static_cast<unsigned long long>(n.missed_by_cpu),
                static_cast<unsigned long long>(n.cycles_that_allocated),
                static_cast<unsigned long long>(n.over_work_bound), static_cast<unsigned long long>(n.faulted_cycles));
            std::fflush(stdout);
        }
    }
    std::fclose(sink);
    const auto ms = [](double us) { return us / 1000.0; };
    std::printf("cycle time over %ld cycles: median %.2f ms, p99 %.2f ms, p99.99 %.2f ms, max %.2f ms (10 us bins)\n",
                o.cycles, ms(histogram->quantile_us(0.5)), ms(histogram->quantile_us(0.99)),
                ms(histogram->quantile_us(0.9999)), ms(static_cast<double>(histogram->max_us())));
    std::printf(
        "missed deadlines (cycle > budget %.1f ms, wall clock): %llu; of those, over the budget in the "
        "thread's own CPU time: %llu (the most CPU time among them: %.2f ms); the most CPU time of any "
        "cycle, loading its frames included: %.2f ms\n",
        static_cast<double>(cfg.budget_us) / 1000.0, static_cast<unsigned long long>(n.missed_deadlines),
        static_cast<unsigned long long>(n.missed_by_cpu), static_cast<double>(n.missed_worst_cpu_us) / 1000.0,
        static_cast<double>(n.worst_cpu_us) / 1000.0);
    std::printf("cycles that allocated: %llu (%llu allocations)\n",
                static_cast<unsigned long long>(n.cycles_that_allocated),
                static_cast<unsigned long long>(n.allocations));
    std::printf(
        "work bound: rays %llu, voxel steps %llu; most in a cycle: rays %llu, voxel steps %llu%s; "
        "cycles over it: %llu\n",
        static_cast<unsigned long long>(bound.rays), static_cast<unsigned long long>(bound.voxel_steps),
        static_cast<unsigned long long>(n.most_rays), static_cast<unsigned long long>(n.most_steps),
        ray_method ? "" : " (footprint: voxel steps not compared)", static_cast<unsigned long long>(n.over_work_bound));
    std::printf(
        "cycles with a fault other than an overrun: %llu; cycles that reported an overrun: %llu; stop "
        "requested in %llu cycles\n",
        static_cast<unsigned long long>(n.faulted_cycles), static_cast<unsigned long long>(n.overrun_cycles),
        static_cast<unsigned long long>(n.stop_cycles));
    std::printf(
        "scene rounds whose stop starts in another cycle or lasts otherwise (more than one cycle) than in the "
        "second round: %llu; rounds not compared because a fault was latched in them: %llu, or in the round before: "
        "%llu\n",
        static_cast<unsigned long long>(n.rounds_that_differ), static_cast<unsigned long long>(n.rounds_with_a_fault),
        static_cast<unsigned long long>(n.rounds_after_a_fault));
    std::printf("CAN frames encoded: %zu; peak resident memory %.1f MiB; load average %.1f at the end\n", sender.frames,
                peak_rss_mib(), load_average());
    // Failures: a cycle whose own work (CPU time) exceeded the budget, an allocation, work over the
    // bound, a fault other than an overrun, a fault-free round that decided otherwise, no stop at all,
    // or a wall-clock overrun the controller did not report. A wall-clock overrun with the cycle's CPU
    // time within the budget is the host's (a wait for a core): counted and printed, and the
    // controller's reaction (kCycleOverrun, the stop) is checked, but it does not fail the soak.
    const bool ok = n.missed_by_cpu == 0U && n.cycles_that_allocated == 0U && n.over_work_bound == 0U &&
                    n.faulted_cycles == 0U && n.rounds_that_differ == 0U && n.stop_cycles > 0U &&
                    n.overrun_cycles >= n.missed_deadlines;
    if (n.missed_deadlines > n.missed_by_cpu) {
        std::printf(
            "soak: %llu wall-clock overruns with the cycle's CPU time within the budget: the host's, each "
            "reported by the controller as kCycleOverrun (the stop)\n",
            static_cast<unsigned long long>(n.missed_deadlines - n.missed_by_cpu));
    }
    std::printf("soak: %s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
