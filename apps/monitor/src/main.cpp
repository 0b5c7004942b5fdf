// cellguard-monitor: the protective-zone monitor on Linux. Runs the cycle
// executive on the (simulated) workcell and sends the CAN safety output on a
// SocketCAN interface or into a candump log. This file holds the command
// line and the wiring; the start-up is monitor_cell.hpp, the cycle
// monitor_loop.hpp.
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/host/cli.hpp"
#include "cellguard/linux/monotonic_clock.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/config.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/frame_source.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/pcd_input.hpp"
#include "cellguard/monitor/picture.hpp"

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

/// Prints why a start-up step stopped; returns its exit status.
int fail(const SetupError& e) {
    std::fprintf(stderr, "cellguard-monitor: %s\n", e.message.c_str());
    return e.exit_status;
}

/// The configuration: the demo's or the file's, with the command line's overrides.
SetupError load_config(const Options& opt, MonitorConfig& cfg) {
    if (opt.demo) {
        cfg = demo_config();
    } else {
        const ConfigLoad load = load_monitor_config(opt.config_path);
        if (!load.ok) {
            return SetupError{2, "configuration error: " + load.error};
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
    return {};
}

/// The CAN output: the configured SocketCAN interface, else the candump log.
SetupError open_can(const MonitorConfig& cfg, CycleClock& clock, CanPort& can) {
    if (!cfg.can.interface_name.empty()) {
        const linux_port::SocketCanStatus st = can.open_interface(cfg.can.interface_name);
        if (!st.ok()) {
            return SetupError{1, "CAN interface '" + cfg.can.interface_name + "': " + linux_port::to_string(st.error) +
                                     " (" + std::strerror(st.sys_errno) + ")"};
        }
        std::printf("CAN: SocketCAN interface %s\n", cfg.can.interface_name.c_str());
        return {};
    }
    const IoStatus st = can.open_log(cfg.can.log_file, cfg.can.log_interface_name, clock);
    if (!st.ok()) {
        return SetupError{1, std::string("CAN log: ") + st.message()};
    }
    std::printf("CAN: candump log %s (interface name %s)\n", cfg.can.log_file.c_str(),
                cfg.can.log_interface_name.c_str());
    return {};
}

/// --picture: the configuration drawn to a PNG.
int write_picture(const Options& opt, const MonitorConfig& cfg, const MonitorCell& cell) {
    std::string error;
    const std::string title =
        "cellguard zones: " + (opt.demo ? std::string("built-in demo (paper-cell.toml)") : opt.config_path);
    if (!write_config_picture(opt.picture, title, cfg, cell.grid, cell.zones, cell.specs,
                              {cell.prior.data(), cell.prior.size()}, opt.picture_sensor, error)) {
        std::fprintf(stderr, "cellguard-monitor: picture: %s\n", error.c_str());
        return 1;
    }
    std::printf("picture: %s\n", opt.picture.c_str());
    return 0;
}

/// One frame source per sensor: its recorded PCD files, else the simulator.
std::vector<std::unique_ptr<FrameSource>> make_sources(const MonitorConfig& cfg, const MonitorCell& cell) {
    std::vector<std::unique_ptr<FrameSource>> sources;
    for (std::size_t s = 0U; s < cfg.sensors.size(); ++s) {
        const sim::SensorSpec& spec = cell.specs[s];
        if (cfg.sensors[s].pcd_files.empty()) {
            sources.push_back(std::make_unique<SimulatedFrameSource>(spec));
        } else {
            sources.push_back(std::make_unique<PcdFrameSource>(spec.name, cfg.sensors[s].pcd_files,
                                                               sensor_pose(cfg.sensors[s]), spec.width, spec.height,
                                                               spec.max_range));
        }
    }
    return sources;
}

}  // namespace

int main(int argc, char** argv) {
    const Options opt = parse_args(argc, argv);
    // Every prior and ray-table check reads these tables; a corrupt table would pass a
    // bad prior or fail a good one (hazard H-MEM-2), so they are checked before anything else.
    if (!cellguard::crc32_table_self_test()) {
        std::fprintf(stderr, "cellguard-monitor: start-up self-test: the CRC-32 tables in memory are corrupt\n");
        return 1;
    }
    MonitorConfig cfg;
    SetupError e = load_config(opt, cfg);
    if (e.failed()) {
        return fail(e);
    }
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    if (opt.realtime) {
        enter_realtime();
    }
    MonitorCell cell;  // grid, sensors, zones; then, after the CAN output, the prior and the ray tables
    if ((e = cell.configure(cfg)).failed()) {
        return fail(e);
    }
    linux_port::LinuxMonotonicClock real_clock;
    CycleClock clock(opt.paced, real_clock);
    CanPort can;
    if (opt.picture.empty() && (e = open_can(cfg, clock, can)).failed()) {  // the picture needs no CAN output
        return fail(e);
    }
    if ((e = cell.build_prior(cfg, stdout)).failed()) {
        return fail(e);
    }
    if (!opt.picture.empty()) {
        return write_picture(opt, cfg, cell);
    }
    if ((e = cell.build_tables(cfg, stdout)).failed()) {
        return fail(e);
    }
    const std::vector<std::unique_ptr<FrameSource>> owned = make_sources(cfg, cell);
    std::vector<FrameSource*> sources;
    for (const std::unique_ptr<FrameSource>& s : owned) {
        sources.push_back(s.get());
    }
    MonitorLoop loop(cfg, cell, sources, can, clock, opt.quiet ? nullptr : stdout);
    if (!loop.status().ok()) {
        std::fprintf(stderr, "cellguard-monitor: CAN output refused: %s\n", to_string(loop.status().error()));
        return 2;
    }
    std::printf("prior CRC-32 0x%08X, %zu zones, period %.1f ms, %d cycles%s\n", loop.controller().prior_crc(),
                cell.zones.size(), static_cast<double>(cfg.period_us) / 1000.0, cfg.demo_cycles,
                opt.paced ? ", paced" : "");
    for (std::size_t s = 0U; s < cfg.sensors.size(); ++s) {
        if (!cfg.sensors[s].pcd_files.empty()) {
            std::printf("input: sensor '%s' from %zu recorded PCD frames\n", cfg.sensors[s].name.c_str(),
                        cfg.sensors[s].pcd_files.size());
        }
    }
    const RunResult run = run_cycles(loop, cfg.demo_cycles, cfg.period_us, opt.paced, g_stop_signal);
    const bool log_ok = can.close();
    loop.write_summary(stdout, run, log_ok);
    return loop.exit_status(stderr, log_ok);
}
