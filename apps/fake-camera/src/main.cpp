// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-fake-camera: serves the sensors of a monitor configuration (the
// built-in paper demo by default) as fake GigE Vision depth cameras on
// loopback (fake_gige_camera.hpp), each frame the simulator's image of the
// demo scenario at that moment, exactly as the monitor's simulated source
// renders it (cell::SimulatedFrameSource), as uint16 depth.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "cellguard/fake_camera/demo_frames.hpp"
#include "cellguard/fake_camera/fake_gige_camera.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/monitor/monitor_cell.hpp"

using namespace cellguard;
using fake_camera::FakeCameraFaults;
using fake_camera::FakeCameraSettings;
using fake_camera::FakeGigeCamera;
using fake_camera::FrameRequest;

namespace {

constexpr const char* kProgram = "cellguard-fake-camera";

struct Options {
    std::string config_path;                 ///< --config; empty: the built-in demo
    std::vector<std::string> sensors;        ///< --sensor; empty: all
    std::vector<std::string> addresses;      ///< --address, one per served sensor
    std::vector<std::string> serials;        ///< --serial, one per served sensor
    double scale_m = 0.0;                    ///< --scale; 0: the sensor's camera.depth_scale, else 1 mm
    double offset_m = 0.0;                   ///< --offset (with --scale)
    double frame_rate_hz = 0.0;              ///< --frame-rate; 0: one frame per cycle period
    long frames = 0;                         ///< --frames; 0: unbounded
    double duration_s = 0.0;                 ///< --duration; 0: unbounded
    std::vector<std::string> fault_sensors;  ///< --fault-sensor; empty: all
    FakeCameraFaults faults;                 ///< the fault options
    std::string stop_mode = "silent";        ///< --stop-mode
    int wrong_width = 0, wrong_height = 0;   ///< --wrong-resolution
    bool no_coord3d = false;                 ///< --no-coord3d
    double clock_offset_ms = 0.0;            ///< --clock-offset-ms
    bool dither = false;                     ///< --dither
    bool empty = false;                      ///< --empty
    long prerender = 0;                      ///< --prerender: scenario cycles rendered at start (0: none)
    std::string scenario_start = "all";      ///< --scenario-start
};

double number_value(const std::string& name, const std::string& text, double lo, double hi) {
    std::size_t used = 0U;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0U;
    }
    if (used != text.size() || !(v >= lo && v <= hi)) {
        host::reject(name + " expects a number " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text +
                     "'");
    }
    return v;
}

void size_value(const std::string& name, const std::string& text, int& w, int& h) {
    const std::size_t x = text.find('x');
    long lw = 0;
    long lh = 0;
    if (x == std::string::npos || !host::parse_integer(text.substr(0U, x), 1, 2048, lw) ||
        !host::parse_integer(text.substr(x + 1U), 1, 2048, lh)) {
        host::reject(name + " expects WIDTHxHEIGHT (1..2048 each), got '" + text + "'");
    }
    w = static_cast<int>(lw);
    h = static_cast<int>(lh);
}

host::OptionRef frame_option(host::CommandLine& cli, const std::string& name, std::int64_t& target,
                             const std::string& help) {
    return cli.value(name, "N", help,
                     [&target, name](const std::string& v) { target = host::integer_value(name, v, 0, 1000000000L); });
}

void add_fault_options(host::CommandLine& cli, Options& o) {
    FakeCameraFaults& f = o.faults;
    cli.value("--loss", "PERMILLE", "drop each GVSP packet with this probability per thousand (10 = 1 %)",
              [&f](const std::string& v) {
                  f.lost_packets_per_mille = static_cast<std::uint32_t>(host::integer_value("--loss", v, 0, 1000));
              });
    frame_option(cli, "--freeze-at", f.frozen_from_frame, "from frame N on, resend the image of frame N-1");
    frame_option(cli, "--stamp-jump-at", f.stamp_jump_at_frame, "at frame N the device clock jumps by --stamp-jump-ms");
    cli.value("--stamp-jump-ms", "MS", "the jump (default 1000; may be negative)", [&f](const std::string& v) {
        f.stamp_jump_ms = host::integer_value("--stamp-jump-ms", v, -3600000L, 3600000L);
    });
    frame_option(cli, "--stop-at", f.stop_at_frame, "from frame N on, send nothing (see --stop-mode)");
    cli.choice("--stop-mode", o.stop_mode, {"silent", "power-off"},
               "silent (stream stops, control still answers; the default) or power-off (the\n"
               "camera disappears: no control either)");
    cli.value(
        "--restart-after-ms", "MS", "after a power-off stop, come back as a new camera at its defaults",
        [&f](const std::string& v) { f.restart_after_ms = host::integer_value("--restart-after-ms", v, 0, 3600000L); });
    cli.value("--wrong-resolution", "WxH", "serve this image size instead of the configured one",
              [&o](const std::string& v) { size_value("--wrong-resolution", v, o.wrong_width, o.wrong_height); });
    cli.flag("--no-coord3d", o.no_coord3d, "the camera does not offer Coord3D_C16 (a wrong pixel format)");
    frame_option(cli, "--resize-at", f.resize_at_frame, "after frame N-1, Width and Height change to --resize");
    cli.value("--resize", "WxH", "the size of --resize-at",
              [&f](const std::string& v) { size_value("--resize", v, f.resize_width, f.resize_height); });
    cli.value("--clock-offset-ms", "MS", "device clock at power-on (default 0)",
              [&o](const std::string& v) { o.clock_offset_ms = number_value("--clock-offset-ms", v, 0.0, 1e12); });
    cli.value("--fault-sensor", "NAME", "apply the faults to this sensor only (repeatable; default all)",
              [&o](const std::string& v) { o.fault_sensors.push_back(v); });
}

/// Reads the command line into @p o: -1 to run, else the exit status.
int parse_args(int argc, char** argv, Options& o) {
    host::CommandLine cli(kProgram, "cellguard-fake-camera [--demo | --config FILE] [options]",
                          "Serves the sensors of the monitor's configuration as fake GigE Vision depth\n"
                          "cameras (Coord3D_C16 with the SFNC Scan3d features) on loopback: sensor k (from 1)\n"
                          "on 127.0.0.(k+1) unless --address says otherwise, each frame the simulator's\n"
                          "image of the demo scenario cycle of that moment (cycle n from the moment every\n"
                          "camera streams, one cycle per period), converted to uint16 with --scale.",
                          "SIGINT / SIGTERM stop it and print the frame counts.\n"
                          "Exit status: 0 done, 1 a camera could not start, 2 bad command line or configuration.");
    o.faults.stamp_jump_ms = 1000;
    bool demo_flag = false;  // the default anyway: the flag only excludes --config
    const host::OptionRef demo = cli.flag("--demo", demo_flag, "the built-in paper demo's sensors (the default)");
    const host::OptionRef config = cli.text("--config", o.config_path, "FILE", "a monitor configuration (TOML)");
    demo.excludes(config);
    cli.value("--sensor", "NAME", "serve this sensor (repeatable; default all)",
              [&o](const std::string& v) { o.sensors.push_back(v); });
    cli.value("--address", "A", "address of the next served sensor (repeatable, in order; 127.0.0.0/8)",
              [&o](const std::string& v) { o.addresses.push_back(v); });
    cli.value("--serial", "S", "serial of the next served sensor (repeatable; default CG-<name>)",
              [&o](const std::string& v) { o.serials.push_back(v); });
    cli.value("--scale", "M", "metres per raw unit (default: the sensor's camera.depth_scale, else 0.001)",
              [&o](const std::string& v) { o.scale_m = number_value("--scale", v, 1e-6, 1.0); });
    cli.value("--offset", "M", "metres added to raw * scale (default: camera.depth_offset, else 0)",
              [&o](const std::string& v) { o.offset_m = number_value("--offset", v, -100.0, 100.0); });
    cli.value("--frame-rate", "HZ", "scenario cycles per second and the cameras' power-on rate (default: 1 / period)",
              [&o](const std::string& v) { o.frame_rate_hz = number_value("--frame-rate", v, 0.1, 1000.0); });
    cli.value("--frames", "N", "stop after every camera made N frames",
              [&o](const std::string& v) { o.frames = host::integer_value("--frames", v, 1, 1000000000L); });
    cli.value("--duration", "S", "stop after S seconds",
              [&o](const std::string& v) { o.duration_s = number_value("--duration", v, 0.001, 1e6); });
    cli.value("--prerender", "N",
              "render scenario cycles 0..N-1 of every camera at start and serve those, the last one for\n"
              "every later cycle (for a still scene from cycle N-1 on: the real cell's person stops at\n"
              "cycle 50): the camera threads then only copy, so that timing runs measure the monitor",
              [&o](const std::string& v) { o.prerender = host::integer_value("--prerender", v, 1, 100000L); });
    cli.flag("--empty", o.empty,
             "serve the empty cell (the reference scene without the demo's person), as at commissioning:\n"
             "for recording the background views (cellguard-monitor --write-background)");
    cli.flag("--dither", o.dither,
             "odd frames: one pixel 1 raw unit deeper, so that no two frames are bit-identical\n"
             "(a real sensor's noise; for the monitor's frozen-image check, which the simulator's\n"
             "still scenes would otherwise trip)");
    cli.choice("--scenario-start", o.scenario_start, {"all", "first", "signal"},
               "when scenario cycle 0 starts: all (the first frame after every served camera\n"
               "streams; the default), first (the first frame of any camera) or signal (at\n"
               "SIGUSR1, which also arms the faults: their frames count from it; until then\n"
               "every camera serves cycle 0. For tests that start the scene when the monitor\n"
               "runs its first cycle, whatever its start-up took)");
    add_fault_options(cli, o);
    return cli.parse(argc, argv);
}

/// One served sensor: its frames and camera.
struct Served {
    std::string name;
    std::unique_ptr<fake_camera::DemoFrames> frames;
    bool streamed = false;  ///< it made a frame (camera thread's)
    std::unique_ptr<FakeGigeCamera> camera;
};

// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): written by the signal handler; a volatile sig_atomic_t global is the one portable way
volatile std::sig_atomic_t g_stop = 0;
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): written by the SIGUSR1 handler, as g_stop
volatile std::sig_atomic_t g_start = 0;
extern "C" void on_signal(int sig) { g_stop = sig; }
extern "C" void on_start(int /*sig*/) { g_start = 1; }

bool wanted(const std::vector<std::string>& names, const std::string& name) {
    return names.empty() || std::find(names.begin(), names.end(), name) != names.end();
}

/// The camera settings of sensor @p spec (served as number @p k from 0, config index @p index).
/// The camera settings of sensor @p s (@p spec: its simulator view), served as number @p k
/// from 0, number @p index in the configuration. Address and serial: the options, else the
/// sensor's [sensors.camera] table, else 127.0.0.(index + 2) and "CG-<name>".
FakeCameraSettings camera_settings(const Options& o, const cell::SensorSettings& s, const sim::SensorSpec& spec,
                                   std::size_t k, std::size_t index, double rate_hz) {
    FakeCameraSettings c;
    const cell::CameraSettings& table = s.camera;
    c.address = k < o.addresses.size()                    ? o.addresses[k]
                : table.enabled && !table.address.empty() ? table.address
                                                          : "127.0.0." + std::to_string(index + 2U);
    const std::string& named = !table.expected_serial.empty() ? table.expected_serial : table.serial;
    c.serial = k < o.serials.size()              ? o.serials[k]
               : table.enabled && !named.empty() ? named
                                                 : ("CG-" + spec.name).substr(0U, 15U);
    const bool from_table = o.scale_m == 0.0 && table.enabled && table.has_depth_scale;
    const double scale_m = o.scale_m > 0.0 ? o.scale_m : from_table ? table.depth_scale_m : 0.001;
    const double offset_m = o.scale_m > 0.0 ? o.offset_m : from_table ? table.depth_offset_m : o.offset_m;
    const PinholeIntrinsics in = spec.intrinsics();
    c.width = spec.width;
    c.height = spec.height;
    c.power_on_format = fake_camera::PixelFormat::kMono16;  // the client sets Coord3D_C16, again after a reboot
    c.frame_rate_hz = rate_hz;
    c.coordinate_scale = scale_m * 1000.0;  // Scan3dDistanceUnit millimetre
    c.coordinate_offset = offset_m * 1000.0;
    c.focal_length_px = in.fx;
    c.aspect_ratio = in.fy / in.fx;
    c.principal_point_u = in.cx;
    c.principal_point_v = in.cy;
    c.faults_from_start = o.scenario_start != "signal";
    if (wanted(o.fault_sensors, spec.name)) {
        c.faults = o.faults;
        c.faults.power_off_at_stop = o.stop_mode == "power-off";
        c.offers_coord3d_c16 = !o.no_coord3d;
        c.clock_offset_ns = static_cast<std::uint64_t>(o.clock_offset_ms * 1e6);
        if (o.wrong_width > 0) {
            c.width = o.wrong_width;
            c.height = o.wrong_height;
        }
    }
    return c;
}

/// Makes the served sensors of @p cfg; false with @p error on a bad selection.
bool make_served(const Options& o, const cell::MonitorConfig& cfg, fake_camera::ScenarioClock& clock, double rate,
                 std::vector<std::unique_ptr<Served>>& out, std::string& error) {
    for (std::size_t i = 0U; i < cfg.sensors.size(); ++i) {
        const cell::SensorSettings& s = cfg.sensors[i];
        if (!wanted(o.sensors, s.name)) {
            continue;
        }
        const sim::SensorSpec spec = monitor::to_spec(s, true, error);
        if (!error.empty()) {
            return false;
        }
        auto served = std::make_unique<Served>();
        served->name = s.name;
        const FakeCameraSettings c = camera_settings(o, s, spec, out.size(), i, rate);
        std::vector<std::pair<int, int>> sizes;
        if (c.width != spec.width || c.height != spec.height) {
            sizes.emplace_back(c.width, c.height);  // --wrong-resolution: another model at the same place
        }
        if (c.faults.resize_at_frame >= 0) {
            sizes.emplace_back(c.faults.resize_width, c.faults.resize_height);
        }
        served->frames = std::make_unique<fake_camera::DemoFrames>(
            spec, sizes, c.coordinate_scale / 1000.0, c.coordinate_offset / 1000.0,
            o.empty ? cell::FrameScene::kEmpty : cell::FrameScene::kDemo);
        if (o.prerender > 0) {
            served->frames->prerender(static_cast<std::uint64_t>(o.prerender));
        }
        Served* p = served.get();
        const bool dithered = o.dither;
        served->camera = std::make_unique<FakeGigeCamera>(
            c, [p, &clock, dithered](const FrameRequest& r, std::uint16_t* image) {
                const bool first = !p->streamed;
                p->streamed = true;
                p->frames->render(clock.cycle(first, r.monotonic_ns), r.width, r.height, image);
                if (dithered) {
                    fake_camera::dither(r.frame, static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height),
                                        image);
                }
            });
        out.push_back(std::move(served));
    }
    for (const std::string& name : o.sensors) {
        if (std::none_of(out.begin(), out.end(), [&name](const auto& s) { return s->name == name; })) {
            error = "--sensor '" + name + "': no such sensor in the configuration";
            return false;
        }
    }
    return true;
}

void print_serving(const Served& s) {
    const FakeCameraSettings& c = s.camera->settings();
    std::printf("serving sensor '%s' at %s serial %s %dx%d %s, scale %g mm, offset %g mm, fx %.3f cx %.3f cy %.3f\n",
                s.name.c_str(), c.address.c_str(), c.serial.c_str(), c.width, c.height,
                c.offers_coord3d_c16 ? "Mono16 and Coord3D_C16" : "Mono16 only (no Coord3D_C16)", c.coordinate_scale,
                c.coordinate_offset, c.focal_length_px, c.principal_point_u, c.principal_point_v);
}

/// Serves until a bound, a signal, or every camera is done; SIGUSR1 starts @p clock and arms the faults.
void serve(const Options& o, fake_camera::ScenarioClock& clock, std::vector<std::unique_ptr<Served>>& served) {
    const auto t0 = std::chrono::steady_clock::now();
    bool started = false;
    while (g_stop == 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (g_start != 0 && !started) {
            started = true;
            const auto now = std::chrono::steady_clock::now().time_since_epoch();
            const auto now_ns = static_cast<std::uint64_t>(
                std::chrono::duration_cast<std::chrono::nanoseconds>(now).count());
            clock.start(now_ns);
            for (const auto& s : served) {
                s->camera->arm_faults();
            }
            std::printf("scenario started at t=%.3fs\n", static_cast<double>(now_ns) * 1e-9);
            static_cast<void>(std::fflush(stdout));
        }
        bool all_done = o.frames > 0;
        for (auto& s : served) {
            s->camera->poll();
            const bool gone = !s->camera->running();
            all_done = all_done && (gone || s->camera->counts().frames >= static_cast<std::uint64_t>(o.frames));
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (all_done || (o.duration_s > 0.0 && elapsed >= o.duration_s)) {
            break;
        }
    }
}

/// The program: -1 never; the exit status.
int run(int argc, char** argv) {
    Options opt;
    if (const int status = parse_args(argc, argv, opt); status >= 0) {
        return status;
    }
    cell::ConfigLoad load;
    if (opt.config_path.empty()) {
        load.ok = true;
        load.config = cell::demo_config();
    } else {
        load = cell::load_monitor_config(opt.config_path);
    }
    if (!load.ok) {
        static_cast<void>(std::fprintf(stderr, "%s: configuration error: %s\n", kProgram, load.error.c_str()));
        return 2;
    }
    if (!load.config.demo_scene.empty()) {
        static_cast<void>(
            std::fprintf(stderr, "%s: demo.scene cells are not served (the paper demo's scenario only)\n", kProgram));
        return 2;
    }
    const std::uint64_t period_ns = opt.frame_rate_hz > 0.0 ? static_cast<std::uint64_t>(1e9 / opt.frame_rate_hz)
                                                            : load.config.period_us * 1000U;
    const auto selected = static_cast<std::size_t>(
        std::count_if(load.config.sensors.begin(), load.config.sensors.end(),
                      [&opt](const cell::SensorSettings& s) { return wanted(opt.sensors, s.name); }));
    const std::size_t start_after = opt.scenario_start == "all" ? selected : opt.scenario_start == "first" ? 1U : 0U;
    fake_camera::ScenarioClock clock(period_ns, start_after);  // 0: at SIGUSR1
    static_cast<void>(std::signal(SIGUSR1, on_start));  // before any camera is announced: a test may send it then
    std::vector<std::unique_ptr<Served>> served;
    std::string error;
    if (!make_served(opt, load.config, clock, 1e9 / static_cast<double>(period_ns), served, error)) {
        static_cast<void>(std::fprintf(stderr, "%s: %s\n", kProgram, error.c_str()));
        return 2;
    }
    for (auto& s : served) {
        if (!s->camera->start(error)) {
            static_cast<void>(std::fprintf(stderr, "%s: sensor '%s': %s\n", kProgram, s->name.c_str(), error.c_str()));
            return 1;
        }
        print_serving(*s);
    }
    if (start_after == 0U) {
        std::printf("scenario waits for SIGUSR1 to pid %ld\n", static_cast<long>(getpid()));
    }
    static_cast<void>(std::fflush(stdout));
    static_cast<void>(std::signal(SIGINT, on_signal));
    static_cast<void>(std::signal(SIGTERM, on_signal));
    serve(opt, clock, served);
    for (auto& s : served) {
        s->camera->power_off();
        const fake_camera::FakeCameraCounts n = s->camera->counts();
        std::printf(
            "sensor '%s': %llu frames, %llu rendered, %llu frozen, %llu stopped, %llu other format, "
            "%llu restarts\n",
            s->name.c_str(), static_cast<unsigned long long>(n.frames), static_cast<unsigned long long>(n.rendered),
            static_cast<unsigned long long>(n.frozen), static_cast<unsigned long long>(n.stopped),
            static_cast<unsigned long long>(n.other_format), static_cast<unsigned long long>(n.restarts));
        if (n.fault_ns != 0U) {  // the same clock as the paced monitor's t= (CLOCK_MONOTONIC)
            std::printf("sensor '%s': fault at t=%.3fs\n", s->name.c_str(), static_cast<double>(n.fault_ns) * 1e-9);
        }
    }
    return 0;
}
}  // namespace

int main(int argc, char** argv) {
    // An exception reaching here (out of memory, a library's std::exception) ends the run with its message.
    try {
        return run(argc, argv);
    } catch (const std::exception& ex) {
        static_cast<void>(std::fprintf(stderr, "%s: stopped by an unexpected error: %s\n", kProgram, ex.what()));
    } catch (...) {
        static_cast<void>(std::fprintf(stderr, "%s: stopped by an unexpected error\n", kProgram));
    }
    return 1;
}
