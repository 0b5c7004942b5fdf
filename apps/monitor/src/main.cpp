// cellguard-monitor: the protective-zone monitor on Linux. Runs the cycle
// executive on the (simulated) workcell and sends the CAN safety output on a
// SocketCAN interface or into a candump log.
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "cellguard/accessibility.hpp"
#include "cellguard/crc32.hpp"
#include "cellguard/host/cli.hpp"
#include "cellguard/host/owned_ray_table.hpp"
#include "cellguard/linux/candump_log.hpp"
#include "cellguard/linux/monotonic_clock.hpp"
#include "cellguard/linux/prior_files.hpp"
#include "cellguard/linux/socketcan.hpp"
#include "cellguard/monitor/config.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/pcd_input.hpp"
#include "cellguard/monitor/picture.hpp"
#include "cellguard/monitor/scenario.hpp"
#include "cellguard/safety_controller.hpp"
#include "cellguard/safety_output.hpp"
#include "cellguard/sim/workcell.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

const char* kUsage =
    "usage: cellguard-monitor [--demo | --config FILE] [options]\n"
    "\n"
    "Protective-zone monitor: fuses the workcell's depth sensors every cycle,\n"
    "evaluates the protective and warning zones, and sends the CAN safety\n"
    "output (safety frame, inverted copy, diagnostics frame) on a SocketCAN\n"
    "interface or into a candump-format log. The sensor input is the workcell\n"
    "simulator (a scripted person walking through the cell), or for sensors\n"
    "with `pcd_files` in the configuration, recorded PCD frames, each checked.\n"
    "\n"
    "  --demo              the built-in paper cell (the default with no arguments)\n"
    "  --config FILE       load the configuration from a TOML file\n"
    "                      (example: apps/monitor/config/paper-cell.toml)\n"
    "  --cycles N          run N cycles (default: the config's demo.cycles, 60)\n"
    "  --log FILE          candump log path (default: the config's can.log_file)\n"
    "  --can-interface IF  send on SocketCAN interface IF instead of the log\n"
    "  --paced             one cycle per period on the real clock (default: as fast as possible)\n"
    "  --budget-ms MS      cycle time budget, overriding the config's cycle.budget_ms (1..60000);\n"
    "                      for tests on emulators or loaded hosts, where the real budget is not the point\n"
    "  --realtime          SCHED_FIFO, mlockall and CPU affinity where permitted\n"
    "  --quiet             no per-cycle status lines\n"
    "  --picture FILE      write a PNG of the grid, the background and the zones\n"
    "                      (top view and one sensor's view) and exit\n"
    "  --picture-sensor S  the sensor of that view, by name or number from 1 (default 1)\n"
    "  --help              this text\n"
    "  --version           print the version and exit\n"
    "\n"
    "SIGINT / SIGTERM stop it cleanly at the end of the current cycle.\n"
    "Exit status: 0 done, 1 runtime error, 2 bad command line or configuration,\n"
    "3 done but the CAN output failed in some cycle (the PLC may have missed frames).\n";

struct Options {
    bool demo = false;
    std::string config_path;
    int cycles = -1;
    std::string log_file;
    std::string can_interface;
    bool paced = false;
    long budget_ms = -1;  ///< -1: the config's budget
    bool realtime = false;
    bool quiet = false;
    std::string picture;
    std::string picture_sensor;
};

[[noreturn]] void usage_error(const std::string& message) {
    std::fprintf(stderr, "cellguard-monitor: %s\nTry 'cellguard-monitor --help'.\n", message.c_str());
    std::exit(2);
}

Options parse_args(int argc, char** argv) {
    Options o;
    if (argc <= 1) {
        o.demo = true;
        return o;
    }
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* name) -> std::string {
            if (i + 1 >= argc || !host::is_option_value(argv[i + 1])) {
                usage_error(std::string(name) + " needs a value");
            }
            return argv[++i];
        };
        // The value of option @p name as an integer in [lo, hi]; anything else is a usage error.
        auto integer_value = [&](const char* name, long lo, long hi) -> long {
            const std::string v = value(name);
            char* end = nullptr;
            errno = 0;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (errno != 0 || end == v.c_str() || *end != '\0' || n < lo || n > hi) {
                usage_error(std::string(name) + " expects an integer " + std::to_string(lo) + ".." + std::to_string(hi) +
                            ", got '" + v + "'");
            }
            return n;
        };
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (a == "--version") {
            host::print_version("cellguard-monitor");
            std::exit(0);
        } else if (a == "--demo") {
            o.demo = true;
        } else if (a == "--config") {
            o.config_path = value("--config");
        } else if (a == "--cycles") {
            o.cycles = static_cast<int>(integer_value("--cycles", 1, 1000000));
        } else if (a == "--log") {
            o.log_file = value("--log");
        } else if (a == "--can-interface") {
            o.can_interface = value("--can-interface");
        } else if (a == "--paced") {
            o.paced = true;
        } else if (a == "--budget-ms") {
            o.budget_ms = integer_value("--budget-ms", 1, 60000);
        } else if (a == "--realtime") {
            o.realtime = true;
        } else if (a == "--quiet") {
            o.quiet = true;
        } else if (a == "--picture") {
            o.picture = value("--picture");
        } else if (a == "--picture-sensor") {
            o.picture_sensor = value("--picture-sensor");
        } else {
            usage_error("unknown argument '" + a + "'");
        }
    }
    if (o.demo && !o.config_path.empty()) {
        usage_error("--demo and --config exclude each other");
    }
    if (!o.demo && o.config_path.empty()) {
        o.demo = true;  // options only: the built-in demo configuration
    }
    if (!o.log_file.empty() && !o.can_interface.empty()) {
        usage_error("--log and --can-interface exclude each other");
    }
    return o;
}

/// Real-time set-up: each step reports what it did or why it could not.
void enter_realtime() {
    sched_param sp{};
    sp.sched_priority = 50;
    if (sched_setscheduler(0, SCHED_FIFO, &sp) == 0) {
        std::printf("realtime: SCHED_FIFO priority 50\n");
    } else {
        std::printf("realtime: SCHED_FIFO not permitted (%s); running with the normal scheduler "
                    "(needs CAP_SYS_NICE or an rtprio limit)\n",
                    std::strerror(errno));
    }
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
        std::printf("realtime: memory locked (mlockall)\n");
    } else {
        std::printf("realtime: mlockall not permitted (%s); pages may be swapped (needs CAP_IPC_LOCK or a memlock limit)\n",
                    std::strerror(errno));
    }
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof(set), &set) == 0) {
        int last = -1;
        for (int c = 0; c < CPU_SETSIZE; ++c) {
            if (CPU_ISSET(c, &set)) {
                last = c;
            }
        }
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(last, &one);
        if (last >= 0 && sched_setaffinity(0, sizeof(one), &one) == 0) {
            std::printf("realtime: pinned to CPU %d\n", last);
        } else {
            std::printf("realtime: CPU affinity not set (%s)\n", std::strerror(errno));
        }
    }
}

class SocketCanSender final : public CanSender {
public:
    explicit SocketCanSender(linux_port::SocketCan& can) : can_(&can) {}
    bool send(const CanFrame& frame) noexcept override { return can_->send(frame).ok(); }

private:
    linux_port::SocketCan* can_;
};

std::string fault_names(std::uint32_t mask) {
    if (mask == 0U) {
        return "-";
    }
    std::string s;
    for (std::uint8_t f = 0U; f < kFaultCount; ++f) {
        if ((mask & fault_bit(static_cast<Fault>(f))) != 0U) {
            s += (s.empty() ? "" : ",");
            s += to_string(static_cast<Fault>(f));
        }
    }
    return s;
}

sim::SensorSpec to_spec(const SensorSettings& s, bool simulated_background, std::string& error) {
    sim::SensorSpec spec;
    spec.name = s.name;
    spec.position = s.position;
    spec.width = s.width;
    spec.height = s.height;
    spec.hfov_deg = s.hfov_deg;
    spec.vfov_deg = s.vfov_deg;
    spec.max_range = static_cast<float>(s.max_range);
    if (s.has_target) {
        spec.target = s.target;
        if (std::abs((s.target - s.position).normalized().z()) > 0.999) {
            error = "line " + std::to_string(s.line) + ": sensor '" + s.name +
                    "': looking straight up or down needs `rotation` (the simulator derives the roll from the vertical)";
        }
    } else {
        const Eigen::Matrix3d r = s.rotation.toRotationMatrix();
        spec.target = s.position + r.col(2);
        // Only the simulator derives the roll; a recorded sensor takes its pose as given (sensor_pose),
        // unless the simulator must render its view of the empty cell for the prior.
        if ((s.pcd_files.empty() || simulated_background) && !spec.pose().linear().isApprox(r, 1e-6)) {
            error = "line " + std::to_string(s.line) + ": sensor '" + s.name +
                    "': the simulator supports only rotations without roll (x axis horizontal)" +
                    (s.pcd_files.empty() ? std::string()
                                         : std::string("; it renders this recorded sensor's view for "
                                                       "prior.source = \"simulated-background\": use a prior file"));
        }
    }
    return spec;
}

}  // namespace

int main(int argc, char** argv) {
    const Options opt = parse_args(argc, argv);
    // Every prior and ray-table check below reads these tables; a corrupt table would pass a
    // bad prior or fail a good one (hazard H-MEM-2), so they are checked before anything else.
    if (!cellguard::crc32_table_self_test()) {
        std::fprintf(stderr, "cellguard-monitor: start-up self-test: the CRC-32 tables in memory are corrupt\n");
        return 1;
    }
    MonitorConfig cfg;
    if (opt.demo) {
        cfg = demo_config();
    } else {
        const ConfigLoad load = load_monitor_config(opt.config_path);
        if (!load.ok) {
            std::fprintf(stderr, "cellguard-monitor: configuration error: %s\n", load.error.c_str());
            return 2;
        }
        cfg = load.config;
    }
    if (opt.cycles > 0) {
        cfg.demo_cycles = opt.cycles;
    }
    if (opt.budget_ms > 0) {
        cfg.budget_us = static_cast<std::uint64_t>(opt.budget_ms) * 1000U;
    }
    if (!opt.log_file.empty()) {
        cfg.can.log_file = opt.log_file;
        cfg.can.interface_name.clear();
    }
    if (!opt.can_interface.empty()) {
        cfg.can.interface_name = opt.can_interface;
    }

    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    if (opt.realtime) {
        enter_realtime();
    }

    // Grid, sensors, zones.
    const GridGeometry g =
        GridGeometry::make(cfg.grid.origin, cfg.grid.voxel_size, GridDims{cfg.grid.dims[0], cfg.grid.dims[1], cfg.grid.dims[2]})
            .value();
    std::vector<sim::SensorSpec> specs;
    for (const SensorSettings& s : cfg.sensors) {
        std::string error;
        specs.push_back(to_spec(s, cfg.prior.source == PriorSource::kSimulatedBackground, error));
        if (!error.empty()) {
            std::fprintf(stderr, "cellguard-monitor: configuration error: %s\n", error.c_str());
            return 2;
        }
    }
    std::vector<ZoneConfig> zone_configs;
    for (const ZoneSettings& z : cfg.zones) {
        zone_configs.push_back(z.zone);
    }
    std::vector<std::uint32_t> zone_mask(g.voxel_count());
    const Result<CompiledZones, ZoneError> compiled = CompiledZones::compile(
        g, {zone_configs.data(), zone_configs.size()}, {zone_mask.data(), zone_mask.size()});
    if (!compiled.ok()) {
        const ZoneError zone_error = compiled.error();
        const ZoneSettings& z = cfg.zones[std::min(zone_error.zone, cfg.zones.size() - 1U)];
        std::fprintf(stderr, "cellguard-monitor: configuration error: line %d: zone '%s': %s (%s)\n", z.line,
                     z.name.c_str(), zone_error.reason, to_string(zone_error.code));
        return 2;
    }
    const CompiledZones zones = compiled.value();

    // CAN output.
    linux_port::LinuxMonotonicClock real_clock;
    monitor::CycleClock clock(opt.paced, real_clock);
    linux_port::CandumpLogWriter log_writer;
    linux_port::SocketCan socket_can;
    SocketCanSender socket_sender(socket_can);
    CanSender* sender = nullptr;
    if (!opt.picture.empty()) {
        // The picture needs no CAN output.
    } else if (!cfg.can.interface_name.empty()) {
        const linux_port::SocketCanStatus st = socket_can.open(cfg.can.interface_name.c_str());
        if (!st.ok()) {
            std::fprintf(stderr, "cellguard-monitor: CAN interface '%s': %s (%s)\n", cfg.can.interface_name.c_str(),
                         linux_port::to_string(st.error), std::strerror(st.sys_errno));
            return 1;
        }
        sender = &socket_sender;
        std::printf("CAN: SocketCAN interface %s\n", cfg.can.interface_name.c_str());
    } else {
        const IoStatus st = log_writer.open(cfg.can.log_file.c_str(), cfg.can.log_interface_name.c_str(), clock);
        if (!st.ok()) {
            std::fprintf(stderr, "cellguard-monitor: CAN log: %s\n", st.message());
            return 1;
        }
        sender = &log_writer;
        std::printf("CAN: candump log %s (interface name %s)\n", cfg.can.log_file.c_str(),
                    cfg.can.log_interface_name.c_str());
    }

    // Evidence grids, sensor model, background and prior.
    SensorModelTable model;
    std::vector<std::int16_t> frame_lo(g.voxel_count()), prior(g.voxel_count());
    std::vector<std::uint8_t> frame_ob(g.voxel_count());
    std::vector<std::int16_t> fusion_scratch(g.voxel_count());  // fuse_sensor's per-sensor opinions
    EvidenceGrid frame_grid =
        EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
    if (cfg.prior.source == PriorSource::kFile) {
        std::vector<std::uint8_t> bytes;
        PriorImageView view;
        const IoStatus st = read_prior_image_file(cfg.prior.file.c_str(), g, bytes, view);
        if (!st.ok()) {
            std::fprintf(stderr, "cellguard-monitor: prior: %s\n", st.message());
            return 1;
        }
        if (!view.copy_to({prior.data(), prior.size()}).ok()) {
            std::fprintf(stderr, "cellguard-monitor: prior: %s does not fit the grid\n", cfg.prior.file.c_str());
            return 1;
        }
        std::printf("prior: %s\n", cfg.prior.file.c_str());
    } else {
        std::vector<std::int16_t> bg_lo(g.voxel_count());
        std::vector<std::uint8_t> bg_ob(g.voxel_count());
        EvidenceGrid bg = EvidenceGrid::make(g, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
        bg.clear();
        const sim::SimulatedFrame empty = sim::render_frame(specs, sim::reference_scene());
        for (int i = 0; i < cfg.prior.background_frames; ++i) {
            if (!fuse_background_frame(bg, frame_grid, {empty.readings.data(), empty.readings.size()}, model,
                                       {fusion_scratch.data(), fusion_scratch.size()})
                     .ok()) {
                std::fprintf(stderr, "cellguard-monitor: background: fusing the empty frames failed\n");
                return 1;
            }
        }
        AccessibilityParams params;
        const AccessibilityScratchSize size = accessibility_scratch_size(g.dims(), params);
        std::vector<std::uint32_t> words(size.words);
        std::vector<std::uint8_t> bytes(size.bytes);
        const Status st = compute_accessibility_prior(
            bg, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
            {prior.data(), prior.size()}, {});
        if (!st.ok()) {
            std::fprintf(stderr, "cellguard-monitor: prior: computing the accessibility prior failed: %s\n",
                         to_string(st.error()));
            return 1;
        }
        std::printf("prior: probabilistic accessibility prior from %d simulated empty frames\n",
                    cfg.prior.background_frames);
    }

    if (!opt.picture.empty()) {
        std::string error;
        const std::string title =
            "cellguard zones: " + (opt.demo ? std::string("built-in demo (paper-cell.toml)") : opt.config_path);
        if (!write_config_picture(opt.picture, title, cfg, g, zones, specs, {prior.data(), prior.size()},
                                  opt.picture_sensor, error)) {
            std::fprintf(stderr, "cellguard-monitor: picture: %s\n", error.c_str());
            return 1;
        }
        std::printf("picture: %s\n", opt.picture.c_str());
        return 0;
    }

    // Ray tables of the static sensors.
    const sim::SimulatedFrame layout = sim::render_frame(specs, sim::reference_scene());
    std::vector<host::OwnedRayTable> tables(specs.size());
    std::size_t total_steps = 0U;
    std::size_t total_bytes = 0U;
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        if (!cfg.sensors[s].pcd_files.empty()) {
            continue;  // recorded point clouds: fused without a table
        }
        const Status t = tables[s].build(g, layout.readings[s]);
        if (!t.ok()) {
            std::fprintf(stderr, "cellguard-monitor: sensor '%s': ray table: %s\n", specs[s].name.c_str(),
                         to_string(t.error()));
            return 1;
        }
        total_steps += tables[s].table().step_count();
        total_bytes += tables[s].storage_bytes();
    }
    // Commissioned views of the empty cell (cycle.background_match > 0): the
    // simulated sensors' renders of the reference scene, like their tables.
    std::vector<BackgroundReference> backgrounds(specs.size());
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        backgrounds[s].depth = layout.readings[s].depth;
        backgrounds[s].tolerance_m = cfg.background_tolerance_m;
        backgrounds[s].min_match_fraction = cfg.background_match;
    }
    if (cfg.background_match > 0.0F) {
        std::printf("background check: every frame must show %.0f %% of its sensor's view of the empty cell (within %.0f mm)\n",
                    100.0 * static_cast<double>(cfg.background_match),
                    1000.0 * static_cast<double>(cfg.background_tolerance_m));
    }
    std::printf("ray tables: %zu sensors, %zu steps (%.1f MB)\n", specs.size(), total_steps,
                static_cast<double>(total_bytes) / 1e6);
    // The worst-case work of one cycle (cycle.hpp); tests/bench/bench_cycle turns it into time.
    const CycleWorkBound work = compute_work_bound(g, {layout.readings.data(), layout.readings.size()}, zones);
    std::printf("work bound per cycle: %llu rays, %llu voxel steps, %llu grid-pass voxels, %llu zone updates\n",
                static_cast<unsigned long long>(work.rays), static_cast<unsigned long long>(work.voxel_steps),
                static_cast<unsigned long long>(work.grid_voxels), static_cast<unsigned long long>(work.zone_updates));

    ControllerConfig cc;
    cc.sensor_count = specs.size();
    cc.logic.restart_delay_us = cfg.restart_delay_us;
    cc.logic.reset_required = cfg.reset_required;
    cc.logic.fault_recovery_cycles = cfg.fault_recovery_cycles;
    cc.zones.foreground_threshold = cfg.foreground_threshold;
    cc.zones.accessible_min_prior = cfg.accessible_min_prior;
    cc.max_frame_age_us = cfg.max_frame_age_us;
    cc.cycle_budget_us = cfg.budget_us;
    cc.table_check_slice_bytes = cfg.table_check_bytes;
    cc.max_repeated_frames = cfg.max_repeated_frames;
    cc.zone_check_slice_bytes = cfg.zone_check_bytes;

    // The controller computes the prior CRC at construction; the output needs
    // it, so the output is bound after the controller through a forwarder.
    class Forward final : public CycleOutput {
    public:
        bool publish(const CycleReport& r) noexcept override { return target != nullptr && target->publish(r); }
        CanSafetyOutput* target = nullptr;
    } forward;
    SafetyController controller(cc, frame_grid, {fusion_scratch.data(), fusion_scratch.size()},
                                {prior.data(), prior.size()}, zones, model, clock, &forward);
    SafetyOutputConfig oc;
    oc.channel = cfg.can.channel;
    oc.zone_count = static_cast<std::uint8_t>(zones.size());
    oc.prior_crc = controller.prior_crc();
    CanSafetyOutput output(oc, *sender);
    if (!output.status().ok()) {
        std::fprintf(stderr, "cellguard-monitor: CAN output refused: %s\n", to_string(output.status().error()));
        return 2;
    }
    forward.target = &output;
    std::printf("prior CRC-32 0x%08X, %zu zones, period %.1f ms, %d cycles%s\n", controller.prior_crc(), zones.size(),
                static_cast<double>(cfg.period_us) / 1000.0, cfg.demo_cycles, opt.paced ? ", paced" : "");

    // Recorded frames (PCD files) for the sensors that have them.
    std::vector<std::unique_ptr<PcdFrameSource>> recorded(specs.size());
    const bool all_recorded = std::all_of(cfg.sensors.begin(), cfg.sensors.end(),
                                          [](const SensorSettings& s) { return !s.pcd_files.empty(); });
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        if (!cfg.sensors[s].pcd_files.empty()) {
            recorded[s] = std::make_unique<PcdFrameSource>(specs[s].name, cfg.sensors[s].pcd_files,
                                                           sensor_pose(cfg.sensors[s]),
                                                           specs[s].width, specs[s].height, specs[s].max_range);
            std::printf("input: sensor '%s' from %zu recorded PCD frames\n", specs[s].name.c_str(),
                        cfg.sensors[s].pcd_files.size());
        }
    }

    // The cycles.
    int cycles_run = 0, stop_cycles = 0, warning_cycles = 0, first_stop_after_release = -1, send_failures = 0;
    bool released = false;
    std::uint32_t faults_seen = 0U;
    int can_fault_cycles = 0;  // cycles that ended with the CAN-error fault latched
    std::uint64_t max_cycle_us = 0U;
    std::uint64_t skipped_periods = 0U;  // --paced: periods skipped after a cycle ran past its period
    timespec next{};
    clock_gettime(CLOCK_MONOTONIC, &next);
    const std::uint64_t sim_start_us = 1000000U;
    for (int k = 0; k < cfg.demo_cycles && g_stop_signal == 0; ++k) {
        if (opt.paced) {
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
            const auto advance = [&next, &cfg] {
                next.tv_nsec += static_cast<long>((cfg.period_us % 1000000U) * 1000U);
                next.tv_sec += static_cast<time_t>(cfg.period_us / 1000000U) + next.tv_nsec / 1000000000L;
                next.tv_nsec %= 1000000000L;
            };
            advance();
            // After a cycle that ran past its period the next start is
            // already over: skip the periods that are over instead of
            // running their cycles back to back (a burst).
            timespec now{};
            clock_gettime(CLOCK_MONOTONIC, &now);
            while (next.tv_sec < now.tv_sec || (next.tv_sec == now.tv_sec && next.tv_nsec <= now.tv_nsec)) {
                advance();
                ++skipped_periods;
            }
        }
        const PersonPosition person = demo_person(k);
        sim::Scene scene = sim::reference_scene();
        scene.boxes.push_back(person_box(person));
        const sim::SimulatedFrame frame = sim::render_frame(specs, scene);
        clock.start_cycle(sim_start_us + static_cast<std::uint64_t>(k) * cfg.period_us);
        std::vector<SensorInput> inputs(specs.size());
        for (std::size_t s = 0U; s < specs.size(); ++s) {
            inputs[s].reading = frame.readings[s];
            inputs[s].captured_us = clock.base();
            inputs[s].present = true;
            inputs[s].table = &tables[s].table();
            inputs[s].background = cfg.background_match > 0.0F ? &backgrounds[s] : nullptr;
            if (recorded[s]) {
                inputs[s].table = nullptr;
                inputs[s].background = nullptr;  // refused by the config loader; never compared
                const PcdFrameCheck c = recorded[s]->load(static_cast<std::uint64_t>(k), inputs[s].reading);
                if (!c.ok && !opt.quiet) {
                    std::printf("input: cycle %d sensor '%s': frame %s refused: %s\n", k, specs[s].name.c_str(),
                                c.file.c_str(), c.reason.c_str());
                }
            }
        }
        if (socket_can.is_open()) {
            CanFrame rx{};
            int drained = 0;
            while (socket_can.receive(rx) != linux_port::SocketCan::ReceiveOutcome::kNothing && ++drained < 64) {
            }
            output.set_can_detail_faults(socket_can.active_faults());
        }
        const std::size_t sent_before = log_writer.lines();
        const CycleReport& r = controller.run_cycle({inputs.data(), inputs.size()}, false);
        const std::uint64_t cycle_us = controller.monitor().last().total_us;
        max_cycle_us = std::max(max_cycle_us, cycle_us);
        ++cycles_run;
        faults_seen |= r.safety.latched_faults;
        if ((r.safety.latched_faults & fault_bit(Fault::kCanError)) != 0U) {
            ++can_fault_cycles;
        }
        if (!socket_can.is_open() && log_writer.lines() - sent_before != 3U) {
            ++send_failures;
        }
        if (r.safety.stop_requested) {
            ++stop_cycles;
            if (released && first_stop_after_release < 0) {
                first_stop_after_release = k;
            }
        } else {
            released = true;
        }
        if (r.safety.warning) {
            ++warning_cycles;
        }
        if (!opt.quiet) {
            std::string zs;
            for (std::size_t z = 0U; z < zones.size(); ++z) {
                zs += " " + cfg.zones[z].name + ":" + to_string(r.zones.zones[z].state);
            }
            // The scripted person exists only for simulated sensors: with recorded frames alone, say so instead.
            char scene_text[64];
            if (all_recorded) {
                std::snprintf(scene_text, sizeof scene_text, "recorded frames %-18s", "");
            } else {
                std::snprintf(scene_text, sizeof scene_text, "person (%5.2f,%5.2f) %-17s", person.x, person.y,
                              demo_phase(k));
            }
            std::printf("t=%7.3fs cycle %3d %s|%s | %-4s %-4s | faults %s | cycle %.2f ms\n",
                        static_cast<double>(clock.base() - sim_start_us) / 1e6, k, scene_text, zs.c_str(), r.safety.stop_requested ? "STOP" : "run", r.safety.warning ? "WARN" : "-",
                        fault_names(r.safety.latched_faults).c_str(), static_cast<double>(cycle_us) / 1000.0);
            std::fflush(stdout);
        }
    }
    const bool log_ok = socket_can.is_open() || log_writer.close();

    std::printf("\nsummary: %d cycles%s, stop requested in %d, warning in %d", cycles_run,
                g_stop_signal != 0 ? " (stopped by signal)" : "", stop_cycles, warning_cycles);
    if (first_stop_after_release >= 0) {
        std::printf(", first stop after release in cycle %d", first_stop_after_release);
    }
    std::printf("\nsummary: faults latched during the run: %s; longest cycle %.2f ms (budget %.1f ms), overruns %llu\n",
                fault_names(faults_seen).c_str(), static_cast<double>(max_cycle_us) / 1000.0,
                static_cast<double>(cfg.budget_us) / 1000.0,
                static_cast<unsigned long long>(controller.monitor().overruns()));
    if (opt.paced) {
        std::printf("summary: paced: %llu periods skipped after cycles that ran past their period\n",
                    static_cast<unsigned long long>(skipped_periods));
    }
    for (const std::unique_ptr<PcdFrameSource>& r : recorded) {
        if (r) {
            std::printf("summary: sensor '%s': %llu recorded frames used, %llu refused (frame inconsistent)\n",
                        r->name().c_str(), static_cast<unsigned long long>(r->used()),
                        static_cast<unsigned long long>(r->refused()));
        }
    }
    if (socket_can.is_open()) {
        std::printf("summary: CAN frames sent on %s\n", cfg.can.interface_name.c_str());
    } else {
        std::printf("summary: %zu CAN frames written to %s%s\n", log_writer.lines(), cfg.can.log_file.c_str(),
                    log_ok ? "" : " (WRITE ERROR)");
    }
    if (!log_ok || send_failures != 0) {
        std::fprintf(stderr, "cellguard-monitor: writing the CAN log failed\n");
        return 1;
    }
    if (can_fault_cycles != 0) {
        // A supervisor (systemd, the commissioning script) must not read
        // this run as clean: the safe state held, but frames were lost.
        std::fprintf(stderr, "cellguard-monitor: the CAN output failed: CAN-error fault latched in %d of %d cycles\n",
                     can_fault_cycles, cycles_run);
        return 3;
    }
    return 0;
}
