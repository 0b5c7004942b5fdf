// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file daemon.hpp
/// The monitor as a daemon, wired around its loop: the event log on stderr
/// (the journal under systemd: daemon_observers.hpp, port/linux's
/// log_queue.hpp), the systemd notification (service.hpp) and the stop
/// snapshots (snapshot.hpp, with --snapshot-dir), all watching the loop
/// through one observer list that also times its calls (after the
/// controller's cycle, so not in its cycle time; the summary prints it).
/// Set up before the first cycle; nothing here allocates in a cycle.
#ifndef CELLGUARD_MONITOR_DAEMON_HPP
#define CELLGUARD_MONITOR_DAEMON_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/monitor/daemon_observers.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/picture.hpp"
#include "cellguard/monitor/snapshot.hpp"
#include "cellguard/monitor/watchdog_feed.hpp"
#include "cellguard/port/log_queue.hpp"
#include "cellguard/port/service.hpp"
#include "cellguard/port/watchdog.hpp"

namespace cellguard::monitor {

/// Lines the event log's queue holds (about 60 KiB); the cycle never waits for the writer.
constexpr std::size_t kLogQueueLines = 256U;

/// The daemon's command-line settings.
/// The watchdog device the monitor opens unless --watchdog names another
/// or the configuration opts out (opt_out.watchdog_device).
constexpr const char* kDefaultWatchdogDevice = "/dev/watchdog";

struct DaemonOptions {
    std::uint64_t heartbeat_us = kDefaultHeartbeatUs;  ///< --heartbeat-s in microseconds (0: none)
    std::string snapshot_dir;                          ///< --snapshot-dir ("": no snapshots)
    std::size_t snapshot_keep = 10U;                   ///< --snapshot-keep
    std::string watchdog_path;                         ///< --watchdog ("": no watchdog device)
    /// The device is the default one (kDefaultWatchdogDevice, not named by
    /// --watchdog): where none exists the monitor says so and runs without.
    bool watchdog_if_present = false;
    int watchdog_timeout_s = 5;  ///< --watchdog-timeout-s
};

/// The observers behind one, with the time their calls take.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class TimedObservers final : public CycleObserver {
public:
    /// Calls every observer of the list and times the calls on CLOCK_MONOTONIC.
    void after_cycle(const CycleView& cycle) noexcept override;
    ObserverList list;            ///< the observers
    std::uint64_t max_us = 0U;    ///< the longest call
    std::uint64_t total_us = 0U;  ///< all calls
    std::uint64_t calls = 0U;     ///< calls
};

/// The watchdog device the monitor opens (DaemonOptions' watchdog_path and
/// watchdog_if_present), or why the command line and the configuration
/// contradict each other (error non-empty).
struct WatchdogChoice {
    std::string path;         ///< "" : no device
    bool if_present = false;  ///< the default device: absent is said, not an error
    std::string error;        ///< --watchdog given and the configuration's opt_out.watchdog_device
};

/// @p option (--watchdog) when given (it must open); else
/// kDefaultWatchdogDevice, if present, unless @p cfg opts out
/// (opt_out.watchdog_device): then none. Both given: an error.
[[nodiscard]] WatchdogChoice choose_watchdog(const std::string& option, const cell::MonitorConfig& cfg);

/// See the file comment. Not copyable or movable: the loop keeps pointers into it.
class Daemon {
public:
    /// The log queue and writer, the event log and the service status for @p cfg.
    Daemon(const cell::MonitorConfig& cfg, const DaemonOptions& opt);
    Daemon(const Daemon&) = delete;
    Daemon& operator=(const Daemon&) = delete;
    Daemon(Daemon&&) = delete;
    Daemon& operator=(Daemon&&) = delete;
    ~Daemon() = default;

    /// Adds @p observer (the browser view's, live_view.hpp) to the list
    /// attach() hooks into the loop; call before attach().
    void add_observer(CycleObserver* observer) noexcept { extra_ = observer; }
    /// Starts the log writer and the snapshot writer, opens the watchdog
    /// device (--watchdog: a failure, or a timeout under two periods, is an
    /// error: the monitor does not run), hooks them into @p loop and @p can,
    /// and tells systemd the monitor is ready.
    [[nodiscard]] SetupError attach(const cell::MonitorConfig& cfg, const MonitorCell& cell, CanPort& can,
                                    MonitorLoop& loop);
    /// After the last cycle: the watchdog device's orderly stop (magic 'V'),
    /// STOPPING=1, the last snapshot, the last heartbeat, the log written out.
    void finish(const RunResult& run, const MonitorLoop& loop);
    /// The daemon's summary lines (event log, observers, service, snapshots) to @p out.
    void write_summary(std::FILE* out) const;

    /// Opens the watchdog device (attach() calls it): none without a path
    /// (said when the configuration opts out); the default device absent
    /// (watchdog_if_present): said at start and in the event log, the path
    /// cleared, no error; any other failure, or a timeout under two
    /// periods: an error (exit status 2) that names opt_out.watchdog_device
    /// for the default device.
    SetupError open_watchdog(const cell::MonitorConfig& cfg);
    /// The watchdog device in use ("" : none).
    [[nodiscard]] const std::string& watchdog_path() const noexcept { return opt_.watchdog_path; }

private:
    SetupError make_recorder(const cell::MonitorConfig& cfg, const MonitorCell& cell);

    linux_port::LogQueue queue_;
    linux_port::LogWriter writer_;
    linux_port::ServiceNotifier notifier_;
    EventLog events_;
    ServiceStatus status_;
    linux_port::Watchdog watchdog_;
    WatchdogFeed feed_;
    DaemonOptions opt_;
    std::unique_ptr<PictureRobot> robot_;
    std::unique_ptr<SnapshotRecorder> recorder_;
    TimedObservers observers_;
    CycleObserver* extra_ = nullptr;  ///< add_observer()'s (nullptr: none)
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_DAEMON_HPP
