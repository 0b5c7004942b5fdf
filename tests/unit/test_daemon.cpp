// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monitor as a daemon (daemon.hpp): the watchdog device is on by default, a machine without one
// is said and the monitor runs, a device that cannot be used is an error naming the opt-out, and the opt-out turns
// the device off.
#include "cellguard/monitor/daemon.hpp"

#include <doctest/doctest.h>

#include <string>

#include "cellguard/host/cell/config.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

/// The demo's configuration without its opt-out of the watchdog device.
cell::MonitorConfig without_watchdog_opt_out() {
    cell::MonitorConfig cfg = cell::demo_config();
    for (auto it = cfg.opt_outs.begin(); it != cfg.opt_outs.end(); ++it) {
        if (it->name == "watchdog_device") {
            cfg.opt_outs.erase(it);
            break;
        }
    }
    return cfg;
}

}  // namespace

// verifies: SR-WDG-006
TEST_CASE("monitor: without a watchdog device the monitor says so and runs, and the opt-out turns the device off") {
    const cell::MonitorConfig on = without_watchdog_opt_out();
    const cell::MonitorConfig off = cell::demo_config();  // paper-cell.toml opts out (a demonstration)
    REQUIRE(cell::opted_out(off, "watchdog_device"));
    // The choice: the default device unless the configuration opts out; --watchdog names another.
    const WatchdogChoice by_default = choose_watchdog("", on);
    CHECK(by_default.path == "/dev/watchdog");
    CHECK(by_default.if_present);
    CHECK(by_default.error.empty());
    const WatchdogChoice named = choose_watchdog("/dev/watchdog1", on);
    CHECK(named.path == "/dev/watchdog1");
    CHECK_FALSE(named.if_present);
    const WatchdogChoice none = choose_watchdog("", off);
    CHECK(none.path.empty());
    CHECK(none.error.empty());
    CHECK(choose_watchdog("/dev/watchdog1", off).error.find("opt_out.watchdog_device") != std::string::npos);

    // A default device that does not exist: said, the run goes on without one.
    DaemonOptions absent;
    absent.watchdog_path = "/nonexistent-cellguard-test/watchdog";
    absent.watchdog_if_present = true;
    Daemon quiet(on, absent);
    CHECK_FALSE(quiet.open_watchdog(on).failed());
    CHECK(quiet.watchdog_path().empty());
    // The same path named on the command line must open: an error.
    absent.watchdog_if_present = false;
    Daemon named_absent(on, absent);
    CHECK(named_absent.open_watchdog(on).exit_status == 2);
    // A default "device" that exists but is no watchdog (its timeout ioctl fails): an error naming the opt-out;
    // nothing is armed.
    DaemonOptions not_a_watchdog;
    not_a_watchdog.watchdog_path = "/dev/null";
    not_a_watchdog.watchdog_if_present = true;
    Daemon refused(on, not_a_watchdog);
    const SetupError e = refused.open_watchdog(on);
    CAPTURE(e.message);
    CHECK(e.exit_status == 2);
    CHECK(e.message.find("opt_out.watchdog_device") != std::string::npos);
    // No path (the opt-out): nothing opened, no error.
    Daemon opted(off, DaemonOptions{});
    CHECK_FALSE(opted.open_watchdog(off).failed());
    CHECK(opted.watchdog_path().empty());
}
