// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-monitor-check-log: checks a candump log written by
// `cellguard-monitor --demo` as the robot's PLC would receive it: the PLC-side
// receiver gets every frame at its time stamp and is polled on the log's clock
// up to the end of the run; every frame decodes, every inverted copy matches,
// the receiver never enters the safe state once recovered, and the stop
// request appears in the cycle in which the scripted person enters the
// protective zone (and not in the cycle before). With --demo robot-cell the
// log of `cellguard-monitor --demo robot-cell`: also its separation frames and
// the simulated PLC's command frames, read by the controller's command
// receiver. The checks themselves are check_demo_log (demo_log_check.hpp).
#include <cstdio>
#include <string>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cli.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/monitor/demo_log_check.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;

namespace {

constexpr const char* kProgram = "cellguard-monitor-check-log";

constexpr const char* kDescription =
    "Checks the candump log LOG of `cellguard-monitor --demo --cycles CYCLES` as the\n"
    "robot's PLC would receive it: each frame goes to the PLC-side receiver at its time\n"
    "stamp, and the receiver is polled every 1 ms of log time up to the end of the run\n"
    "(the first frame's time plus CYCLES periods), with SRVT half a period and SCT three\n"
    "periods. Fails on a malformed line, a counter out of sequence, a mismatching copy,\n"
    "any receiver fault (frames that stop early, a frame late past the SRVT, a pair\n"
    "split by more than the SRVT), a wrong line count, or a stop request that is not\n"
    "in the cycle in which the scripted person enters the protective zone.\n"
    "--demo robot-cell: the log of `cellguard-monitor --demo robot-cell`; also checks\n"
    "every separation frame (E2E, its counter, consistent with the safety frame) and\n"
    "reads the PLC's command frames with the controller's command receiver: no fault\n"
    "after start-up, and each cycle that used a valid command echoes its case; the\n"
    "stop is released after start-up and requested again when the person comes.\n"
    "--config FILE: the log of `cellguard-monitor --config FILE` (a cell that renders\n"
    "the paper's scripted person, e.g. apps/monitor/config/real-cell.toml).";

constexpr const char* kFooter =
    "Exit status: 0 the log passes, 1 it fails (one FAIL line each on stderr),\n"
    "2 bad command line or unreadable log.";

}  // namespace

int main(int argc, char** argv) {
    host::CommandLine cli(kProgram, "cellguard-monitor-check-log [--demo NAME | --config FILE] LOG CYCLES",
                          kDescription, kFooter);
    std::string log;
    std::string demo = "paper-cell";
    int cycles = 0;
    std::string config_path;
    int budget_ms = 0;
    const host::OptionRef demo_opt = cli.choice("--demo", demo, {"paper-cell", "robot-cell"},
                                                "the demo that wrote the log: paper-cell (the default) or robot-cell");
    cli.text("--config", config_path, "FILE", "the configuration file of the run that wrote the log (not with --demo)");
    cli.integer("--budget-ms", budget_ms, 1, 60000, "MS",
                "the run's --budget-ms, if it had one: the session link's watchdog time is two periods plus the "
                "cycle budget, as in the monitor");
    cli.argument("LOG", "the candump log", [&log](const std::string& v) { log = v; });
    cli.argument("CYCLES", "the demo's --cycles, 1.." + std::to_string(kDemoLogMaxCycles),
                 [&cycles](const std::string& v) {
                     cycles = static_cast<int>(host::integer_value("CYCLES", v, 1, kDemoLogMaxCycles));
                 });
    if (const int status = cli.parse(argc, argv); status >= 0) {
        return status;
    }
    if (demo_opt.count() > 0U && !config_path.empty()) {
        static_cast<void>(std::fprintf(stderr, "%s: --demo and --config exclude each other\n", kProgram));
        return host::kExitUsage;
    }
    ConfigLoad load;  // moved into, not copied: nothing here throws past main
    if (config_path.empty()) {
        load.ok = true;
        load.config = demo == "robot-cell" ? robot_cell_demo_config() : demo_config();
    } else {
        load = load_monitor_config(config_path);
    }
    if (!load.ok) {
        static_cast<void>(std::fprintf(stderr, "%s: configuration error: %s\n", kProgram, load.error.c_str()));
        return host::kExitUsage;
    }
    if (budget_ms > 0) {
        load.config.budget_us = static_cast<std::uint64_t>(budget_ms) * 1000U;
    }
    const DemoLogCheck r = check_demo_log_file(log, cycles, load.config);
    for (const std::string& f : r.failures) {
        static_cast<void>(std::fprintf(stderr, "%s: %s\n", r.input_ok ? "FAIL" : kProgram, f.c_str()));
    }
    if (!r.input_ok) {
        return host::kExitUsage;
    }
    std::printf("%s\n", r.summary.c_str());
    return r.passed() ? 0 : 1;
}
