// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor as a daemon (daemon.hpp).
#include "cellguard/monitor/daemon.hpp"
#include "cellguard/port/clock.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <utility>

#include "cellguard/host/version.hpp"

namespace cellguard::monitor {

void TimedObservers::after_cycle(const CycleView& cycle) noexcept {
    const std::uint64_t start = linux_port::monotonic_now_us();
    list.after_cycle(cycle);
    const std::uint64_t us = linux_port::monotonic_now_us() - start;
    max_us = std::max(max_us, us);
    total_us += us;
    ++calls;
}

Daemon::Daemon(const cell::MonitorConfig& cfg, const DaemonOptions& opt)
    : queue_(kLogQueueLines),
      writer_(queue_, STDERR_FILENO, linux_port::journal_stream_matches(STDERR_FILENO)),
      events_(cfg, queue_, opt.heartbeat_us),
      status_(notifier_),
      feed_(&notifier_, &watchdog_, cfg.budget_us, &queue_),
      opt_(opt) {}

WatchdogChoice choose_watchdog(const std::string& option, const cell::MonitorConfig& cfg) {
    WatchdogChoice c;
    const bool opted_out = cell::opted_out(cfg, "watchdog_device");
    if (!option.empty()) {
        c.path = option;
        if (opted_out) {
            c.error = "--watchdog " + option + " and the configuration's opt_out.watchdog_device contradict each other";
        }
    } else if (!opted_out) {
        c.path = kDefaultWatchdogDevice;  // on by default; absent: said, not an error
        c.if_present = true;
    }
    return c;
}

SetupError Daemon::open_watchdog(const cell::MonitorConfig& cfg) {
    if (opt_.watchdog_path.empty()) {
        if (cell::opted_out(cfg, "watchdog_device")) {
            std::printf("watchdog: no device (opt_out.watchdog_device)\n");
            queue_.push(linux_port::LogPriority::kWarning, "watchdog: no device (opt_out.watchdog_device)");
        }
        return {};
    }
    struct stat st {};
    if (opt_.watchdog_if_present && stat(opt_.watchdog_path.c_str(), &st) != 0 &&
        (errno == ENOENT || errno == ENOTDIR)) {
        std::printf(
            "watchdog: no device at %s (a chroot, a container or a machine without one): running without a "
            "hardware watchdog\n",
            opt_.watchdog_path.c_str());
        queue_.push(linux_port::LogPriority::kWarning, "watchdog: no device at %s: running without a hardware watchdog",
                    opt_.watchdog_path.c_str());
        opt_.watchdog_path.clear();
        return {};
    }
    const std::uint64_t timeout_us = static_cast<std::uint64_t>(opt_.watchdog_timeout_s) * 1000000U;
    if (timeout_us < 2U * cfg.period_us) {
        return SetupError{2, "--watchdog-timeout-s " + std::to_string(opt_.watchdog_timeout_s) +
                                 " is shorter than two cycle periods: the watchdog would reset a working monitor"};
    }
    if (!watchdog_.open(opt_.watchdog_path.c_str(), opt_.watchdog_timeout_s)) {
        return SetupError{
            2, std::string("watchdog: ") + watchdog_.message() +
                   (opt_.watchdog_if_present ? " (the default device; to run without it, add opt_out.watchdog_device: "
                                               "[opt_out] watchdog_device = \"<reason>\")"
                                             : "")};
    }
    std::printf("watchdog: %s armed, timeout %d s (asked for %d s), fed after healthy cycles\n",
                opt_.watchdog_path.c_str(), watchdog_.timeout_s(), opt_.watchdog_timeout_s);
    return {};
}

SetupError Daemon::attach(const cell::MonitorConfig& cfg, const MonitorCell& cell, CanPort& can, MonitorLoop& loop) {
    if (!writer_.start()) {
        return SetupError{1, "the event log's writer thread did not start"};
    }
    for (const cell::OptOut& o : cfg.opt_outs) {  // printed at start too (print_opt_outs)
        queue_.push(linux_port::LogPriority::kWarning, "opt-out: %s off: %s", o.name.c_str(), o.reason.c_str());
    }
    if (!opt_.snapshot_dir.empty()) {
        if (SetupError e = make_recorder(cfg, cell); e.failed()) {
            return e;
        }
        can.set_tap(recorder_.get());
    }
    if (SetupError e = open_watchdog(cfg); e.failed()) {
        return e;
    }
    static_cast<void>(observers_.list.add(&feed_));
    static_cast<void>(observers_.list.add(&events_));
    static_cast<void>(observers_.list.add(&status_));
    static_cast<void>(observers_.list.add(recorder_.get()));
    static_cast<void>(observers_.list.add(extra_));
    loop.set_observer(&observers_);
    if (notifier_.enabled()) {
        std::printf("service: notifying systemd, watchdog %s\n", notifier_.watchdog_interval_us() == 0U ? "off" : "on");
    }
    static_cast<void>(std::fflush(stdout));
    queue_.push(linux_port::LogPriority::kNotice, "cellguard-monitor %s: monitoring %zu zones, period %.1f ms",
                host::kVersion, cfg.zones.size(), static_cast<double>(cfg.period_us) / 1000.0);
    static_cast<void>(notifier_.ready("set up, cycles starting"));
    return {};
}

void Daemon::finish(const RunResult& run, const MonitorLoop& loop) {
    if (watchdog_.is_open() && !watchdog_.stop()) {
        queue_.push(linux_port::LogPriority::kError, "watchdog: %s: the orderly stop (magic 'V') failed",
                    opt_.watchdog_path.c_str());
    }
    static_cast<void>(notifier_.stopping(run.stopped_by_signal ? "stopping (signal)" : "stopping (cycles done)"));
    if (recorder_) {
        recorder_->finish();
    }
    events_.heartbeat(loop.stats().cycles_run - 1);
    queue_.push(linux_port::LogPriority::kNotice, "cellguard-monitor stopping after %d cycles%s",
                loop.stats().cycles_run, run.stopped_by_signal ? " (signal)" : "");
    writer_.stop();
}

void Daemon::write_summary(std::FILE* out) const {
    static_cast<void>(std::fprintf(out, "summary: event log: %llu lines, %llu dropped (queue full), %llu heartbeats\n",
                                   static_cast<unsigned long long>(events_.counts().lines),
                                   static_cast<unsigned long long>(queue_.dropped()),
                                   static_cast<unsigned long long>(events_.counts().heartbeats)));
    static_cast<void>(std::fprintf(
        out,
        "summary: observers (watchdog feed, event log, service%s) after each cycle: longest %.3f ms, mean %.3f ms\n",
        recorder_ ? ", snapshots" : "", static_cast<double>(observers_.max_us) / 1000.0,
        observers_.calls == 0U
            ? 0.0
            : static_cast<double>(observers_.total_us) / 1000.0 / static_cast<double>(observers_.calls)));
    const FeedCounts& f = feed_.counts();
    static_cast<void>(std::fprintf(
        out,
        "summary: watchdog feed: %llu healthy cycles fed, refused %llu over budget, %llu with a non-recoverable "
        "fault, %llu without a new cycle; device %s: %llu keepalives, %llu failed\n",
        static_cast<unsigned long long>(f.fed), static_cast<unsigned long long>(f.over_budget),
        static_cast<unsigned long long>(f.non_recoverable), static_cast<unsigned long long>(f.no_new_cycle),
        opt_.watchdog_path.empty() ? "none" : opt_.watchdog_path.c_str(),
        static_cast<unsigned long long>(watchdog_.counts().keepalives),
        static_cast<unsigned long long>(watchdog_.counts().failures)));
    if (notifier_.enabled()) {
        const linux_port::ServiceCounts& c = notifier_.counts();
        static_cast<void>(std::fprintf(out, "summary: service: %llu notifications sent (%llu watchdog), %llu failed\n",
                                       static_cast<unsigned long long>(c.sent),
                                       static_cast<unsigned long long>(c.watchdogs),
                                       static_cast<unsigned long long>(c.failed)));
    }
    if (recorder_) {
        const SnapshotCounts c = recorder_->counts();
        static_cast<void>(std::fprintf(
            out,
            "summary: snapshots: %llu stops after a release, %llu written, %llu skipped (one in progress), "
            "%llu failed, %llu old ones removed; longest copy in a stop cycle %.3f ms\n",
            static_cast<unsigned long long>(c.triggered), static_cast<unsigned long long>(c.written),
            static_cast<unsigned long long>(c.skipped), static_cast<unsigned long long>(c.failed),
            static_cast<unsigned long long>(c.removed), static_cast<double>(c.max_copy_us) / 1000.0));
        for (const std::string& p : recorder_->written_paths()) {
            static_cast<void>(std::fprintf(out, "summary: snapshot %s\n", p.c_str()));
        }
    }
}

SetupError Daemon::make_recorder(const cell::MonitorConfig& cfg, const MonitorCell& cell) {
    if (!cell.robot_image.empty()) {
        robot_ = std::make_unique<PictureRobot>(picture_robot(cfg, cell.robot.model, cell.simulation.trajectory()));
    }
    PictureInput picture;
    std::string error;
    if (!config_picture_input("", cfg, cell.grid, cell.zones, cell.specs, {cell.prior.data(), cell.prior.size()}, "",
                              robot_.get(), picture, error)) {
        return SetupError{2, "snapshot picture: " + error};
    }
    SnapshotSettings settings;
    settings.directory = opt_.snapshot_dir;
    settings.keep = opt_.snapshot_keep;
    settings.interface_name = cfg.can.interface_name.empty() ? cfg.can.log_interface_name : cfg.can.interface_name;
    recorder_ = std::make_unique<SnapshotRecorder>(settings, cfg, cell.frame_grid, std::move(picture));
    recorder_->set_log(&queue_);
    if (!recorder_->start(error)) {
        return SetupError{1, error};
    }
    std::printf("snapshots: into %s, %zu kept, %zu CAN frames before and after each stop\n", opt_.snapshot_dir.c_str(),
                settings.keep, settings.frames_around);
    return {};
}

}  // namespace cellguard::monitor
