// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
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
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/depth_input.hpp"
#include "cellguard/host/cell/filtered_frame_source.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/monitor/background_recording.hpp"
#include "cellguard/monitor/camera_startup.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/daemon.hpp"
#include "cellguard/monitor/live_view.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/picture.hpp"
#include "cellguard/monitor/robot_cell_demo.hpp"
#include "cellguard/monitor/web_content.hpp"
#ifdef CELLGUARD_MONITOR_HTTP
#include <sys/stat.h>

#include "cellguard/monitor/web_server.hpp"
#endif
#include "cellguard/port/clock.hpp"
#include "cellguard/port/worker_pool.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;

namespace {

// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): written by the signal handler; a volatile sig_atomic_t global is the one portable way
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

struct Options {
    bool demo = false;
    std::string demo_name;  ///< --demo's value: "" or "paper-cell" (the paper's cell), "robot-cell"
    std::string config_path;
    int cycles = -1;
    std::string log_file;
    std::string can_interface;
    bool paced = false;
    bool period_start = false;  ///< --period-start: paced by the period even with live cameras
    int budget_ms = -1;         ///< -1: the config's budget
    bool realtime = false;
    bool quiet = false;
    std::string picture;
    std::string write_background;  ///< --write-background: "" (run the monitor)
    int background_frames = 0;     ///< --background-frames (0: prior.background_frames)
    std::string record_depth;      ///< --record-depth: "" (run the monitor)
    std::string picture_sensor;
    std::string commands;        ///< --commands: "" (by the cell), "sim" or "can"
    std::string fusion;          ///< --fusion: "" (the config's), "ray" or "footprint"
    std::string snapshot_dir;    ///< --snapshot-dir: "" (no snapshots)
    int snapshot_keep = 10;      ///< --snapshot-keep
    int heartbeat_s = 10;        ///< --heartbeat-s (0: none)
    std::string watchdog;        ///< --watchdog: "" (the default device, kDefaultWatchdogDevice)
    int watchdog_timeout_s = 5;  ///< --watchdog-timeout-s
    bool forever = false;        ///< --forever: until SIGINT or SIGTERM
    std::string http;            ///< --http: "" (no browser view)
};

/// --http: the browser view, or in a build without CivetWeb, why not.
void add_http_option(host::CommandLine& cli, Options& o) {
#ifdef CELLGUARD_MONITOR_HTTP
    cli.text("--http", o.http, "ADDRESS:PORT",
             "serve the read-only browser view (zones, prior, live foreground, zone states,\n"
             "stop history) on ADDRESS:PORT; PORT or :PORT binds 127.0.0.1, port 0 a free\n"
             "port (printed); not a safety function (default: off)");
#else
    cli.text("--http", o.http, "ADDRESS:PORT",
             "the browser view: not in this build (CivetWeb, libcivetweb-dev, was not found)");
#endif
}

/// The options for what the monitor writes besides its CAN output: the
/// commissioning picture and background views, snapshots, the event log, the
/// watchdog device.
void add_output_options(host::CommandLine& cli, Options& o) {
    cli.text("--picture", o.picture, "FILE",
             "write a PNG of the grid, the background and the zones (with a robot: its\n"
             "capsules, mask margin and separation distances) from above and from one\nsensor, and exit");
    cli.text("--picture-sensor", o.picture_sensor, "S",
             "the sensor of that view, by name or number from 1 (default 1)");
    cli.text("--snapshot-dir", o.snapshot_dir, "DIR",
             "on each protective stop after a release, write a snapshot (the evidence grid\n"
             "as .npy, a picture as PNG, the CAN frames around the stop) into a new\n"
             "directory under DIR (default: no snapshots)");
    cli.integer("--snapshot-keep", o.snapshot_keep, 1, 10000, "N",
                "snapshots kept in DIR, oldest removed (default 10)");
    cli.integer("--heartbeat-s", o.heartbeat_s, 0, 86400, "S",
                "seconds between the event log's heartbeat lines on stderr (default 10, 0: none)");
    cli.text("--watchdog", o.watchdog, "DEV",
             "open the watchdog device DEV and feed it after each healthy cycle (within\n"
             "budget, no internal, clock or prior fault latched); the orderly end disarms it\n"
             "(default: /dev/watchdog where it exists; where none does the monitor says so\n"
             "and runs without; [opt_out] watchdog_device = \"<reason>\" in the configuration\n"
             "turns it off)");
    cli.integer("--watchdog-timeout-s", o.watchdog_timeout_s, 1, 3600, "S",
                "the watchdog device's timeout (default 5; at least two cycle periods)");
    cli.text("--write-background", o.write_background, "FILE",
             "commissioning: record every sensor's view of the EMPTY cell from its own frames\n"
             "(live cameras included), the per-pixel median of --background-frames frames,\n"
             "write it to FILE bound to the prior's CRC, and exit; then name FILE in\n"
             "[prior] background_file");
    cli.integer("--background-frames", o.background_frames, 1, 1000, "N",
                "frames per sensor for --write-background (default: prior.background_frames)");
    cli.text("--record-depth", o.record_depth, "DIR",
             "record --cycles distinct frames (default: demo.cycles) of every depth sensor\n"
             "(live cameras included) as .npy depth images into DIR/<sensor>/, and exit;\n"
             "a sensor's depth_files = \"DIR/<sensor>\" replays them");
}

/// Reads the command line into @p o: -1 to run, else the exit status (0
/// after --help or --version, 2 after a usage error). No arguments, or
/// options without --config: the built-in demo configuration.
int parse_args(int argc, char** argv, Options& o) {
    host::CommandLine cli("cellguard-monitor", "cellguard-monitor [--demo | --config FILE] [options]",
                          "Protective-zone monitor: fuses the workcell's depth sensors every cycle,\n"
                          "evaluates the protective and warning zones, and sends the CAN safety\n"
                          "output (safety frame, inverted copy, diagnostics frame) on a SocketCAN\n"
                          "interface or into a candump-format log. The sensor input is the workcell\n"
                          "simulator (a scripted person walking through the cell), or for sensors\n"
                          "with `pcd_files` or `depth_files` in the configuration, recorded PCD frames\n"
                          "or depth images (.npy), each checked, or live GigE Vision cameras.",
                          "SIGINT / SIGTERM stop it cleanly at the end of the current cycle.\n"
                          "Exit status: 0 done, 1 runtime error, 2 bad command line or configuration,\n"
                          "3 done but the CAN output failed in some cycle (the PLC may have missed frames).");
    const host::OptionRef demo = cli.choice("--demo", o.demo_name, {"", "paper-cell", "robot-cell"},
                                            "a built-in demo: paper-cell (the default, also with no arguments) or\n"
                                            "robot-cell (a 6-axis arm, its PLC and a person walking up to it)",
                                            true);
    const host::OptionRef config = cli.text("--config", o.config_path, "FILE",
                                            "load the configuration from a TOML file\n"
                                            "(example: apps/monitor/config/paper-cell.toml)");
    demo.excludes(config);
    const host::OptionRef cycles = cli.integer("--cycles", o.cycles, 1, 1000000, "N",
                                               "run N cycles (default: the config's demo.cycles, 60)");
    cli.flag("--forever", o.forever,
             "run until SIGINT or SIGTERM (as a service; the summary's cycle-time figures\n"
             "cover the first demo.cycles cycles, the longest cycle all of them)")
        .excludes(cycles);
    const host::OptionRef log = cli.text("--log", o.log_file, "FILE",
                                         "candump log path (default: the config's can.log_file)");
    const host::OptionRef can = cli.text("--can-interface", o.can_interface, "IF",
                                         "send on SocketCAN interface IF instead of the log");
    log.excludes(can);
    cli.choice("--commands", o.commands, {"sim", "can"},
               "where the PLC's command comes from: sim (the simulated PLC of a demo scene\n"
               "with a robot) or can (the frames on the SocketCAN interface, --can-interface;\n"
               "with a demo scene the scene stays simulated: an external PLC, as in the vcan\n"
               "test); default: sim with a demo scene and a robot, else can on an interface");
    cli.choice("--fusion", o.fusion, {"ray", "footprint"},
               "how depth images are fused, overriding the config's fusion.method: ray (per\n"
               "ray, the reference) or footprint (footprint fusion, for dense cameras)");
    cli.flag("--paced", o.paced,
             "one cycle per period on the real clock (default: as fast as possible, on\n"
             "simulated time: the decisions, the budget and the CAN log's times do not\n"
             "depend on the host's speed; the cycle times shown are real)");
    cli.flag("--period-start", o.period_start,
             "paced with live cameras: start each cycle at the next period, as without\n"
             "cameras (default: as soon as every camera has a new frame, half a period\n"
             "after the previous start at the earliest, 1.125 periods at the latest)");
    cli.integer("--budget-ms", o.budget_ms, 1, 60000, "MS",
                "cycle time budget (1..60000), overriding the config's cycle.budget_ms; for tests on\n"
                "emulators or loaded hosts, where the real budget is not the point");
    cli.flag("--realtime", o.realtime, "SCHED_FIFO, mlockall and CPU affinity where permitted");
    cli.flag("--quiet", o.quiet, "no per-cycle status lines");
    add_output_options(cli, o);
    add_http_option(cli, o);
    const int status = cli.parse(argc, argv);
    o.demo = demo.count() > 0U;
    if (o.config_path.empty()) {
        o.demo = true;  // no arguments, or options only: the built-in demo configuration
    }
    return status;
}

/// Real-time set-up: each step reports what it did or why it could not.
void enter_realtime() {
    sched_param sp{};
    sp.sched_priority = 50;
    if (sched_setscheduler(0, SCHED_FIFO, &sp) == 0) {
        std::printf("realtime: SCHED_FIFO priority 50\n");
    } else {
        std::printf(
            "realtime: SCHED_FIFO not permitted (%s); running with the normal scheduler "
            "(needs CAP_SYS_NICE or an rtprio limit)\n",
            std::strerror(errno));
    }
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
        std::printf("realtime: memory locked (mlockall)\n");
    } else {
        std::printf(
            "realtime: mlockall not permitted (%s); pages may be swapped (needs CAP_IPC_LOCK or a memlock limit)\n",
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
    static_cast<void>(std::fprintf(stderr, "cellguard-monitor: %s\n", e.message.c_str()));
    return e.exit_status;
}

/// --http's value: well formed, and an address this host can listen on now (exit status 2 otherwise).
SetupError check_http_argument(const Options& opt) {
    if (opt.http.empty()) {
        return {};
    }
#ifdef CELLGUARD_MONITOR_HTTP
    std::string address;
    int port = 0;
    std::string error;
    if (!parse_http_address(opt.http, address, port, error) || !can_listen_on(opt.http, address, port, error)) {
        return SetupError{2, error};
    }
    return {};
#else
    return SetupError{2, "--http: this build has no HTTP server (CivetWeb, libcivetweb-dev, was not found)"};
#endif
}

/// The configuration: the demo's or the file's, with the command line's
/// overrides, checked for what this monitor cannot honour; its opt-outs printed;
/// --http checked.
SetupError load_config(const Options& opt, MonitorConfig& cfg) {
    if (opt.demo) {
        cfg = opt.demo_name == "robot-cell" ? robot_cell_demo_config() : demo_config();
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
    if (opt.fusion == "ray") {
        cfg.fusion = FusionSettings{};  // footprint's limits and cores do not apply
    } else if (opt.fusion == "footprint") {
        cfg.fusion.method = FusionMethod::kFootprint;
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
    if (SetupError e = check_start_settings(cfg); e.failed()) {
        return e;
    }
    if (const WatchdogChoice w = choose_watchdog(opt.watchdog, cfg); !w.error.empty()) {
        return SetupError{2, w.error};
    }
    // Every argument is checked before any output is opened (issue 32: an --http address that
    // could not be bound ended the run after the CAN log had been opened).
    if (SetupError e = check_http_argument(opt); e.failed()) {
        return e;
    }
    print_opt_outs(cfg, stdout);  // each protection the configuration turns off, with its reason
    return {};
}

/// The CAN output: the configured SocketCAN interface, else the candump log.
SetupError open_can(const MonitorConfig& cfg, CycleClock& clock, CanPort& can) {
    if (!cfg.can.interface_name.empty()) {
        const linux_port::SocketCanStatus st = can.open_interface(cfg.can.interface_name, clock);
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

/// --picture: the configuration drawn to a PNG, with the robot when one is configured.
int write_picture(const Options& opt, const MonitorConfig& cfg, const MonitorCell& cell) {
    std::string error;
    const std::string demo = opt.demo_name.empty() ? std::string("paper-cell") : opt.demo_name;
    const std::string title = "cellguard zones: " + (opt.demo ? "built-in demo (" + demo + ".toml)" : opt.config_path);
    PictureRobot robot;
    const bool has_robot = !cell.robot_image.empty();
    if (has_robot) {  // the demo scene's trajectory, empty without one
        robot = picture_robot(cfg, cell.robot.model, cell.simulation.trajectory());
    }
    PictureInput in;
    bool ok = config_picture_input(title, cfg, cell.grid, cell.zones, cell.specs,
                                   {cell.prior.data(), cell.prior.size()}, opt.picture_sensor,
                                   has_robot ? &robot : nullptr, in, error);
    if (ok) {
        in.observed = {cell.background_observed.data(), cell.background_observed.size()};  // unseen zone parts hatched
        ok = host::write_png(opt.picture, render_config_picture(in), error);
    }
    if (!ok) {
        static_cast<void>(std::fprintf(stderr, "cellguard-monitor: picture: %s\n", error.c_str()));
        return 1;
    }
    std::printf("picture: %s\n", opt.picture.c_str());
    return 0;
}

/// A recorded depth sensor's source: its files through the camera path, with the cell's sensor model.
std::unique_ptr<FrameSource> make_depth_file_source(const SensorSettings& settings, const sim::SensorSpec& spec) {
    cell::CameraReadingParams p;
    p.pose = sensor_pose(settings);
    p.intrinsics = spec.intrinsics();
    p.depth_scale_m = static_cast<float>(settings.recording.depth_scale_m);
    p.depth_offset_m = static_cast<float>(settings.recording.depth_offset_m);
    p.max_range = spec.max_range;
    return std::make_unique<cell::DepthFileFrameSource>(settings.name, settings.recording.files, p,
                                                        settings.recording.raw);
}

/// Which scene a simulated sensor shows.
enum class SimulatedScene : std::uint8_t {
    kDemo = 0,   ///< the demo's: the scripted person, or a scene file's robot and persons
    kEmpty = 1,  ///< the empty cell (commissioning: the background's render, MonitorCell::layout)
};

/// The depth filter's line at start: its settings and reason, or that it is off.
void print_depth_filter(const MonitorConfig& cfg) {
    const cell::DepthConditioning& f = cfg.depth_filter.filter;
    if (!f.on()) {
        std::printf("depth filter: off (every reading is fused)\n");
        return;
    }
    std::printf(
        "depth filter: edge jump %.1f %% of depth, at least %.0f mm, radius %d; background tolerance %.1f %%; "
        "speckle %d of 8 (reason: %s)\n",
        100.0 * f.edge_jump_per_m, 1000.0 * f.edge_jump_min_m, f.edge_radius, 100.0 * f.background_tolerance_per_m,
        f.speckle_min_neighbours, cfg.depth_filter.reason.c_str());
}

/// @p sources with the configured depth filter in front of each depth sensor's
/// (depth_filter; recorded point clouds pass unfiltered), against its
/// commissioned view (MonitorCell::backgrounds); prints the filter's line.
std::vector<std::unique_ptr<FrameSource>> with_depth_filter(const MonitorConfig& cfg, const MonitorCell& cell,
                                                            std::vector<std::unique_ptr<FrameSource>> sources) {
    print_depth_filter(cfg);
    if (!cfg.depth_filter.filter.on()) {
        return sources;
    }
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        if (cfg.sensors[s].pcd_files.empty()) {
            sources[s] = std::make_unique<cell::FilteredFrameSource>(std::move(sources[s]), cell.backgrounds[s].depth,
                                                                     cell.specs[s].width, cell.specs[s].height,
                                                                     cfg.depth_filter.filter, cfg.sensors[s].name);
        }
    }
    return sources;
}

/// One frame source per sensor: its live camera, its recorded depth images or PCD files, else the simulator.
std::vector<std::unique_ptr<FrameSource>> make_sources(const MonitorConfig& cfg, const MonitorCell& cell,
                                                       MonitorCameras& cameras,
                                                       SimulatedScene scene = SimulatedScene::kDemo) {
    std::vector<std::unique_ptr<FrameSource>> sources;
    for (std::size_t s = 0U; s < cfg.sensors.size(); ++s) {
        const sim::SensorSpec& spec = cell.specs[s];
        if (cameras.has(s)) {
            sources.push_back(cameras.make_source(s, cfg.sensors[s], spec));
        } else if (!cfg.sensors[s].recording.files.empty()) {
            sources.push_back(make_depth_file_source(cfg.sensors[s], spec));
        } else if (scene == SimulatedScene::kEmpty && cfg.sensors[s].pcd_files.empty()) {
            sources.push_back(std::make_unique<EmptyCellFrameSource>(cell.layout.readings[s]));
        } else if (cell.has_scene) {
            sources.push_back(std::make_unique<SceneFrameSource>(spec, cell.simulation));
        } else if (cfg.sensors[s].pcd_files.empty()) {
            sources.push_back(std::make_unique<SimulatedFrameSource>(spec));
        } else {
            sources.push_back(std::make_unique<PcdFrameSource>(spec.name, cfg.sensors[s].pcd_files,
                                                               sensor_pose(cfg.sensors[s]), spec.width, spec.height,
                                                               spec.max_range));
        }
    }
    return sources;
}

/// The frame sources as the loop takes them: pointers to @p owned, in its order.
std::vector<FrameSource*> pointers_to(const std::vector<std::unique_ptr<FrameSource>>& owned) {
    std::vector<FrameSource*> sources;
    sources.reserve(owned.size());
    for (const std::unique_ptr<FrameSource>& s : owned) {
        sources.push_back(s.get());
    }
    return sources;
}

/// The real clock and pause for --write-background.
class RealRecordingTime final : public RecordingTime {
public:
    std::uint64_t now_us() noexcept override { return clock_.now_us(); }
    void pause(std::uint64_t us) noexcept override {
        timespec t{static_cast<std::time_t>(us / 1000000U), static_cast<long>((us % 1000000U) * 1000U)};
        while (nanosleep(&t, &t) != 0 && errno == EINTR) {
        }
    }

private:
    linux_port::LinuxMonotonicClock clock_;
};

/// How long a recording (--write-background, --record-depth) waits for @p frames frames of every
/// sensor: live cameras at their frame rate, plus their start: a generous bound, not a timing claim.
std::uint64_t recording_deadline_us(int frames, std::uint64_t period_us) {
    return 10000000U + static_cast<std::uint64_t>(frames) * 4U * std::max<std::uint64_t>(period_us, 100000U);
}

/// --write-background: records the views from the sensors' own frames and exits.
int write_background(const Options& opt, const MonitorConfig& cfg, MonitorCell& cell, MonitorCameras& cameras) {
    // The views' identities come from the sensors' layout (build_tables); the file to be
    // written is not read, even when the configuration already names it.
    MonitorConfig recording = cfg;
    recording.prior.background_file.clear();
    if (const SetupError e = cell.build_tables(recording, stdout); e.failed()) {
        return fail(e);
    }
    // Simulated sensors show the empty cell: the demo's person or robot must not enter the views.
    const std::vector<std::unique_ptr<FrameSource>> owned = make_sources(recording, cell, cameras,
                                                                         SimulatedScene::kEmpty);
    std::vector<FrameSource*> sources = pointers_to(owned);
    BackgroundRecording rec;
    rec.path = opt.write_background;
    rec.frames = opt.background_frames > 0 ? opt.background_frames : cfg.prior.background_frames;
    rec.deadline_us = recording_deadline_us(rec.frames, cfg.period_us);
    RealRecordingTime time;
    std::vector<RecordedSensor> counts;
    if (const SetupError e = record_background_views(cell, sources, rec, time, counts, stdout); e.failed()) {
        return fail(e);
    }
    return 0;
}

/// --record-depth: records every sensor's depth images as files and exits.
int record_depth(const Options& opt, const MonitorConfig& cfg, MonitorCell& cell, MonitorCameras& cameras) {
    if (const SetupError e = cell.build_tables(cfg, stdout); e.failed()) {
        return fail(e);
    }
    const std::vector<std::unique_ptr<FrameSource>> owned = make_sources(cfg, cell, cameras);
    std::vector<FrameSource*> sources = pointers_to(owned);
    DepthRecording rec;
    rec.dir = opt.record_depth;
    rec.frames = cfg.demo_cycles;
    rec.deadline_us = recording_deadline_us(rec.frames, cfg.period_us);
    RealRecordingTime time;
    std::vector<RecordedSensor> counts;
    if (const SetupError e = record_depth_frames(cell, sources, rec, time, counts, stdout); e.failed()) {
        return fail(e);
    }
    return 0;
}

/// A session value for this start, 1..255 and not @p other: random
/// (std::random_device), so consecutive starts differ with probability 254/255.
std::uint8_t new_link_session(std::uint8_t other) {
    std::random_device random;
    std::uint8_t session = 0U;
    while (session == 0U || session == other) {
        session = static_cast<std::uint8_t>(random() & 0xFFU);
    }
    return session;
}

/// The PLC's link for the cycle as --commands asks: the simulated PLC of a
/// demo scene with a robot, or of any run that does not send on a SocketCAN
/// interface (a log: it sends its link frames alone, protocol 0.2, so the
/// log shows both sides of the session link), else the interface's PLC;
/// @p e says why not when --commands asks for a source the cell lacks.
CommandLink* choose_commands(const Options& opt, const MonitorCell& cell, const CanPort& can, SimulatedPlcLink& plc,
                             SocketCanCommandLink& socket_commands, SetupError& e) {
    const bool scene_robot = cell.has_scene && !cell.robot_image.empty();
    const bool interface = can.kind() == CanPort::Kind::kInterface;
    if (opt.commands == "sim" && !scene_robot) {
        e = SetupError{2, "--commands sim needs a demo scene with a robot"};
    } else if (opt.commands == "can" && !interface) {
        e = SetupError{2, "--commands can needs a SocketCAN interface (--can-interface or can.interface)"};
    }
    if (scene_robot && opt.commands != "can") {
        return &plc;
    }
    return interface ? static_cast<CommandLink*>(&socket_commands) : &plc;
}

/// The simulated side around each cycle (nullptr: none). A demo scene with a
/// robot keeps moving (people, the robot's program) whichever link brings the
/// commands; a cell with monitoring cases and no robot, commanded by the
/// simulated PLC (@p simulated_plc), gets that PLC's case and its operator,
/// who presses reset while the restart interlock holds.
CycleHook* choose_hook(const MonitorConfig& cfg, const MonitorCell& cell, bool simulated_plc, RobotCellDemo& robot,
                       CaseCellDemo& cases) {
    if (cell.has_scene && !cell.robot_image.empty()) {
        return &robot;
    }
    if (!simulated_plc || cfg.robot.enabled || cfg.cases.empty()) {
        return nullptr;
    }
    std::printf(
        "commands: the simulated PLC selects case %d (%s); its operator presses reset while the restart "
        "interlock holds\n",
        cfg.cases.front().number, cfg.cases.front().name.c_str());
    return &cases;
}

/// Footprint fusion's runner for fusion.threads (nullptr: one core).
/// port/linux's WorkerPool for the fusion's sensor tasks when the
/// configuration asks for more than one thread (made once, before the first
/// cycle); nullptr: one core, the reference (the same grid, bit for bit).
std::unique_ptr<linux_port::WorkerPool> fusion_pool(const MonitorConfig& cfg) {
    if (cfg.fusion.method != FusionMethod::kFootprint || cfg.fusion.threads <= 1) {
        return nullptr;
    }
    auto pool = std::make_unique<linux_port::WorkerPool>(static_cast<std::size_t>(cfg.fusion.threads));
    std::printf("fusion: %zu worker threads\n", pool->concurrency());
    return pool;
}

/// The browser view (--http): the live view observer and the server started;
/// @p live and @p web stay empty without --http.
SetupError start_http(const Options& opt, const MonitorConfig& cfg, const MonitorCell& cell, Daemon& daemon,
                      const MonitorLoop& loop, std::unique_ptr<LiveView>& live, std::shared_ptr<void>& web) {
    if (opt.http.empty()) {
        return {};
    }
#ifdef CELLGUARD_MONITOR_HTTP
    WebServerSettings settings;
    std::string error;
    if (!parse_http_address(opt.http, settings.address, settings.port, error)) {
        return SetupError{2, error};
    }
    struct stat st {};
    settings.page_dir = stat(CELLGUARD_WEB_INSTALL_DIR "/index.html", &st) == 0 ? CELLGUARD_WEB_INSTALL_DIR
                                                                                : CELLGUARD_WEB_SOURCE_DIR;
    settings.snapshot_dir = opt.snapshot_dir;
    live = std::make_unique<LiveView>(cfg, cell.frame_grid, cell.prior.data(), cell.prior.size(), cell.zones);
    live->set_controller(&loop.controller());
    live->set_robot_mask(cell.robot_mask.data(), cell.robot_mask.size());
    auto server = std::make_shared<WebServer>(
        live->channel(),
        make_static_json(cfg, cell.grid, cell.prior.data(), cell.prior.size(), !opt.snapshot_dir.empty()));
    if (!server->start(settings, error)) {
        return SetupError{1, "--http: " + error};
    }
    daemon.add_observer(live.get());
    std::printf("http: serving on http://%s:%d/ (read-only view, not a safety function)\n", settings.address.c_str(),
                server->port());
    static_cast<void>(std::fflush(stdout));
    web = server;
    return {};
#else
    static_cast<void>(cfg);
    static_cast<void>(cell);
    static_cast<void>(daemon);
    static_cast<void>(loop);
    static_cast<void>(live);
    static_cast<void>(web);
    return SetupError{2, "--http: this build has no HTTP server (CivetWeb, libcivetweb-dev, was not found)"};
#endif
}

/// The browser view's summary line, after its server stopped.
void stop_http(const std::unique_ptr<LiveView>& live, std::shared_ptr<void>& web) {
#ifdef CELLGUARD_MONITOR_HTTP
    if (web) {
        auto* server = static_cast<WebServer*>(web.get());
        server->stop();
        const WebCounts c = server->counts();
        std::printf(
            "summary: http: %llu requests, %llu refused (4xx), %llu busy (503), %llu events sent; "
            "live view's copy after each cycle: longest %.3f ms\n",
            static_cast<unsigned long long>(c.requests), static_cast<unsigned long long>(c.refused),
            static_cast<unsigned long long>(c.busy), static_cast<unsigned long long>(c.events),
            static_cast<double>(live->max_us()) / 1000.0);
        web.reset();
    }
#else
    static_cast<void>(live);
    static_cast<void>(web);
#endif
}

/// The run after the set-up: the start lines, the daemon's observers, the
/// cycles (started by @p frames' cameras when not null, run_cycles), the
/// summary; returns the exit status.
int run_and_report(const Options& opt, const MonitorConfig& cfg, const MonitorCell& cell, CanPort& can,
                   MonitorLoop& loop, linux_port::FrameSignal* frames) {
    std::printf("prior CRC-32 0x%08X, %zu zones, period %.1f ms, %d cycles%s\n", loop.controller().prior_crc(),
                cell.zones.size(), static_cast<double>(cfg.period_us) / 1000.0, cfg.demo_cycles,
                opt.paced ? ", paced" : "");
    for (const SensorSettings& sensor : cfg.sensors) {
        if (!sensor.pcd_files.empty()) {
            std::printf("input: sensor '%s' from %zu recorded PCD frames\n", sensor.name.c_str(),
                        sensor.pcd_files.size());
        }
        if (!sensor.recording.files.empty()) {
            std::printf("input: sensor '%s' from %zu recorded depth images ('%s')\n", sensor.name.c_str(),
                        sensor.recording.files.size(), sensor.recording.raw ? "<u2" : "<f4");
        }
    }
    DaemonOptions dopt;
    dopt.heartbeat_us = static_cast<std::uint64_t>(opt.heartbeat_s) * 1000000U;
    dopt.snapshot_dir = opt.snapshot_dir;
    dopt.snapshot_keep = static_cast<std::size_t>(opt.snapshot_keep);
    const WatchdogChoice watchdog = choose_watchdog(opt.watchdog, cfg);  // checked at start (run_monitor)
    dopt.watchdog_path = watchdog.path;
    dopt.watchdog_if_present = watchdog.if_present;
    dopt.watchdog_timeout_s = opt.watchdog_timeout_s;
    Daemon daemon(cfg, dopt);
    std::unique_ptr<LiveView> live;
    std::shared_ptr<void> web;  // the WebServer (type-erased: absent from builds without CivetWeb)
    if (const SetupError e = start_http(opt, cfg, cell, daemon, loop, live, web); e.failed()) {
        return fail(e);
    }
    if (const SetupError e = daemon.attach(cfg, cell, can, loop); e.failed()) {
        return fail(e);
    }
    // The stack below this frame painted; the controller checks its guard band every cycle (H-MEM-3).
    if (const Status st = cycle_stack().start(); !st.ok()) {
        return fail(SetupError{1, std::string("stack painting refused: ") + to_string(st.error())});
    }
    const int cycles_to_run = opt.forever ? std::numeric_limits<int>::max() : cfg.demo_cycles;
    const RunResult run = run_cycles(loop, cycles_to_run, cfg.period_us, opt.paced, g_stop_signal,
                                     opt.period_start ? nullptr : frames);
    stop_http(live, web);
    daemon.finish(run, loop);
    const bool log_ok = can.close();
    loop.write_summary(stdout, run, log_ok);
    const StackPaint& stack = cycle_stack().paint();
    std::printf(
        "summary: cycle thread's stack: high-water mark %zu of %zu bytes painted below the run's frame, "
        "guard band (%zu bytes) %s\n",
        stack.high_water_bytes(), stack.region_bytes(), stack.guard_bytes(),
        stack.guard_intact() ? "intact" : "REACHED");
    daemon.write_summary(stdout);
    cell.write_footprint_summary(stdout);
    return loop.exit_status(stderr, log_ok);
}

/// Both ends' receiver configurations with their protocol 0.2 session values: each start takes a
/// new one, so that nothing sent before this start (a replay across the restart) is accepted by
/// the PLC, and the simulated PLC's own differs from it. False (after a message) when the
/// simulated PLC's receiver configuration is refused (period or zone count).
bool link_configs(const MonitorConfig& cfg, CommandReceiverConfig& receiver, PlcReceiverConfig& plc_receiver) {
    receiver = command_receiver_config(cfg);
    receiver.link.session = new_link_session(0U);
    plc_receiver = plc_receiver_config(cfg);
    plc_receiver.link.session = new_link_session(receiver.link.session);
    // The simulated PLC sends on the controller's own cycle and clock: no second time base (and paced,
    // a skipped period would look like a fast clock), so only a PLC on a CAN interface feeds the check.
    if (!PlcReceiver::check_config(plc_receiver).ok()) {
        static_cast<void>(std::fprintf(stderr,
                                       "cellguard-monitor: no valid PLC receiver for the simulated PLC "
                                       "(period or zone count)\n"));
        return false;
    }
    return true;
}

/// The monitor (main without its last-resort catch).
int run_monitor(int argc, char** argv) {
    Options opt;
    if (const int status = parse_args(argc, argv, opt); status >= 0) {
        return status;
    }
    // Every prior and ray-table check reads these tables; a corrupt table would pass a
    // bad prior or fail a good one (hazard H-MEM-2), so they are checked before anything else.
    if (!cellguard::crc32_table_self_test()) {
        static_cast<void>(
            std::fprintf(stderr, "cellguard-monitor: start-up self-test: the CRC-32 tables in memory are corrupt\n"));
        return 1;
    }
    MonitorConfig cfg;
    SetupError e = load_config(opt, cfg);
    if (e.failed()) {
        return fail(e);
    }
    static_cast<void>(std::signal(SIGINT, on_stop_signal));
    static_cast<void>(std::signal(SIGTERM, on_stop_signal));
    if (opt.realtime) {
        enter_realtime();
    }
    // Live cameras first: intrinsics "device" complete the sensors' configuration.
    MonitorCameras cameras;
    if (opt.picture.empty() && (e = cameras.open(cfg, opt.paced, stdout)).failed()) {
        return fail(e);
    }
    MonitorCell cell;  // grid, sensors, zones; then, after the CAN output, the prior and the ray tables
    if ((e = cell.configure(cfg)).failed() || (e = cell.configure_robot(cfg, stdout)).failed()) {
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
    if (!opt.write_background.empty() || !opt.record_depth.empty()) {  // commissioning: record and exit
        return !opt.write_background.empty() ? write_background(opt, cfg, cell, cameras)
                                             : record_depth(opt, cfg, cell, cameras);
    }
    if ((e = cell.build_tables(cfg, stdout)).failed()) {
        return fail(e);
    }
    const std::vector<std::unique_ptr<FrameSource>> owned = with_depth_filter(cfg, cell,
                                                                              make_sources(cfg, cell, cameras));
    std::vector<FrameSource*> sources = pointers_to(owned);
    CommandReceiverConfig receiver;
    PlcReceiverConfig plc_receiver;
    if (!link_configs(cfg, receiver, plc_receiver)) {
        return 2;
    }
    SimulatedPlcLink plc(receiver, plc_receiver, &can);
    // A cell without commands still has its PLC link: the PLC sends its link frame alone (command_link.hpp).
    SocketCanCommandLink socket_commands(receiver, can, clock_rate_config(cfg), !takes_commands(cfg));
    RobotCellDemo demo(cfg, cell, plc);
    CaseCellDemo case_demo(cfg.cases.empty() ? std::uint8_t{0U} : static_cast<std::uint8_t>(cfg.cases.front().number),
                           plc);
    CommandLink* const commands = choose_commands(opt, cell, can, plc, socket_commands, e);
    if (e.failed()) {
        return fail(e);
    }
    if (commands == &plc && cfg.can.clock_rate.nominal_period_us != 0U) {
        std::printf("clock rate: not checked: the simulated PLC has no clock of its own (can.command_period_ms)\n");
    }
    const std::unique_ptr<linux_port::WorkerPool> pool = fusion_pool(cfg);
    MonitorLoop loop(cfg, cell, sources, can, clock, opt.quiet ? nullptr : stdout, commands,
                     choose_hook(cfg, cell, commands == &plc, demo, case_demo), pool.get());
    if (!loop.status().ok()) {
        static_cast<void>(
            std::fprintf(stderr, "cellguard-monitor: CAN output refused: %s\n", to_string(loop.status().error())));
        return 2;
    }
    return run_and_report(opt, cfg, cell, can, loop, cameras.frame_signal());
}

}  // namespace

int main(int argc, char** argv) {
    // Configuration errors are reported and returned as exit statuses; an exception reaching here (out of memory, a
    // library's std::exception) ends the run with its message instead of std::terminate.
    try {
        return run_monitor(argc, argv);
    } catch (const std::exception& ex) {
        static_cast<void>(std::fprintf(stderr, "cellguard-monitor: stopped by an unexpected error: %s\n", ex.what()));
    } catch (...) {
        static_cast<void>(std::fprintf(stderr, "cellguard-monitor: stopped by an unexpected error\n"));
    }
    return 1;
}
