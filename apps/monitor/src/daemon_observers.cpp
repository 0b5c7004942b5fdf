// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The journal's event log and the service status (daemon_observers.hpp).
#include "cellguard/monitor/daemon_observers.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include "cellguard/monitor/monitor_loop.hpp"

namespace cellguard::monitor {
namespace {

using linux_port::LogPriority;

double ms(std::uint64_t us) noexcept { return static_cast<double>(us) / 1000.0; }

// The zones in @p state among the first @p count of @p r, comma-separated, into @p out.
void zones_in(const CycleReport& r, const cell::MonitorConfig& cfg, std::size_t count, ZoneState state, char* out,
              std::size_t capacity) noexcept {
    std::size_t length = 0U;
    out[0] = '\0';
    for (std::size_t z = 0U; z < count && length + 1U < capacity; ++z) {
        if (r.zones.zones[z].state == state) {
            const int n = std::snprintf(out + length, capacity - length, "%s%s", length == 0U ? "" : ",",
                                        cfg.zones[z].name.c_str());
            length = std::min(length + static_cast<std::size_t>(n > 0 ? n : 0), capacity - 1U);
        }
    }
    if (length == 0U) {
        static_cast<void>(std::snprintf(out, capacity, "-"));
    }
}

// Why @p r requests the stop, the first that applies: a protective zone intruded or unseen, the robot
// closer than its separation distance, a fault latched, else the restart interlock (not yet released).
void stop_reason(const CycleReport& r, const cell::MonitorConfig& cfg, std::size_t count, char* out,
                 std::size_t capacity) noexcept {
    bool intruded = false;
    bool unseen = false;
    for (std::size_t z = 0U; z < count; ++z) {
        if (cfg.zones[z].zone.kind == ZoneKind::kProtective) {
            intruded = intruded || r.zones.zones[z].state == ZoneState::kIntruded;
            unseen = unseen || r.zones.zones[z].state == ZoneState::kUnseen;
        }
    }
    if (intruded) {
        static_cast<void>(std::snprintf(out, capacity, "a protective zone intruded"));
    } else if (unseen) {
        static_cast<void>(std::snprintf(out, capacity, "a protective zone unseen"));
    } else if (r.robot.configured && r.robot.speed_request == SpeedRequest::kProtectiveStop &&
               r.robot.distance_mm < r.robot.required_mm) {
        static_cast<void>(std::snprintf(out, capacity, "separation: d %.2f m < S_p %.2f m",
                                        static_cast<double>(r.robot.distance_mm) / 1000.0,
                                        static_cast<double>(r.robot.required_mm) / 1000.0));
    } else if (r.safety.latched_faults != 0U) {
        static_cast<void>(std::snprintf(out, capacity, "a fault latched"));
    } else {
        static_cast<void>(std::snprintf(out, capacity, "restart interlock: not yet released"));
    }
}

}  // namespace

EventLog::EventLog(const cell::MonitorConfig& cfg, linux_port::LogQueue& queue, std::uint64_t heartbeat_us) noexcept
    : cfg_(&cfg), queue_(&queue), heartbeat_us_(heartbeat_us) {}

// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
void EventLog::line(LogPriority priority, const char* format, ...) noexcept {
    va_list args;
    va_start(args, format);
    if (queue_->vpush(priority, format, args)) {
        ++counts_.lines;
    }
    va_end(args);
}

void EventLog::after_cycle(const CycleView& cycle) noexcept {
    ++counts_.cycles;
    counts_.max_cycle_us = std::max(counts_.max_cycle_us, cycle.cycle_us);
    period_max_us_ = std::max(period_max_us_, cycle.cycle_us);
    if (cycle.report->safety.stop_requested) {
        ++counts_.stop_cycles;
    }
    log_zones(cycle);
    log_faults(cycle);
    log_stop(cycle);
    first_ = false;
    if (heartbeat_us_ != 0U) {
        if (next_heartbeat_us_ == 0U) {
            next_heartbeat_us_ = cycle.now_us + heartbeat_us_;
        } else if (cycle.now_us >= next_heartbeat_us_) {
            heartbeat(cycle.k);
            next_heartbeat_us_ = cycle.now_us + heartbeat_us_;
        }
    }
}

void EventLog::log_zones(const CycleView& cycle) noexcept {
    const std::size_t count = std::min(cfg_->zones.size(), kMaxZones);
    for (std::size_t z = 0U; z < count; ++z) {
        const ZoneState now = cycle.report->zones.zones[z].state;
        if (!first_ && now == zones_[z]) {
            continue;
        }
        if (!(first_ && now == ZoneState::kClear)) {  // the first cycle: only zones that are not clear
            line(now == ZoneState::kClear ? LogPriority::kNotice : LogPriority::kWarning,
                 "zone '%s' (%s): %s -> %s (cycle %d)", cfg_->zones[z].name.c_str(),
                 cfg_->zones[z].zone.kind == ZoneKind::kProtective ? "protective" : "warning",
                 first_ ? "start" : to_string(zones_[z]), to_string(now), cycle.k);
        }
        zones_[z] = now;
    }
}

void EventLog::log_faults(const CycleView& cycle) noexcept {
    const std::uint32_t now = cycle.report->safety.latched_faults;
    for (std::uint8_t f = 0U; f < kFaultCount; ++f) {
        const std::uint32_t bit = fault_bit(static_cast<Fault>(f));
        if ((now & bit) != 0U && (faults_ & bit) == 0U) {
            line(LogPriority::kError, "fault latched: %s (cycle %d)", to_string(static_cast<Fault>(f)), cycle.k);
        } else if ((now & bit) == 0U && (faults_ & bit) != 0U) {
            line(LogPriority::kNotice, "fault cleared: %s (cycle %d)", to_string(static_cast<Fault>(f)), cycle.k);
        }
    }
    faults_ = now;
}

void EventLog::log_stop(const CycleView& cycle) noexcept {
    const CycleReport& r = *cycle.report;
    const bool stop = r.safety.stop_requested;
    if (stop && (first_ || !stopped_)) {
        const std::size_t count = std::min(cfg_->zones.size(), kMaxZones);
        char intruded[160];
        char unseen[160];
        char faults[256];
        zones_in(r, *cfg_, count, ZoneState::kIntruded, intruded, sizeof intruded);
        zones_in(r, *cfg_, count, ZoneState::kUnseen, unseen, sizeof unseen);
        static_cast<void>(format_fault_names(r.safety.latched_faults, faults, sizeof faults));
        if (!first_) {
            ++counts_.stops;
        }
        char reason[96];
        stop_reason(r, *cfg_, count, reason, sizeof reason);
        line(LogPriority::kWarning, "%s (%s): intruded %s, unseen %s, faults %s (cycle %d)",
             first_ ? "stop requested at start-up" : "protective stop", reason, intruded, unseen, faults, cycle.k);
    } else if (!stop && (first_ || stopped_)) {
        line(LogPriority::kNotice, "stop released: the robot may run (cycle %d)", cycle.k);
    }
    stopped_ = stop;
}

void EventLog::heartbeat(int k) noexcept {
    char faults[256];
    static_cast<void>(format_fault_names(faults_, faults, sizeof faults));
    line(LogPriority::kInfo,
         "heartbeat: %llu cycles, %llu with the stop requested, %llu stops; longest cycle %.2f ms since the last "
         "heartbeat, %.2f ms in all; faults latched: %s; log lines dropped: %llu (cycle %d)",
         static_cast<unsigned long long>(counts_.cycles), static_cast<unsigned long long>(counts_.stop_cycles),
         static_cast<unsigned long long>(counts_.stops), ms(period_max_us_), ms(counts_.max_cycle_us), faults,
         static_cast<unsigned long long>(queue_->dropped()), k);
    ++counts_.heartbeats;
    period_max_us_ = 0U;
}

void ServiceStatus::after_cycle(const CycleView& cycle) noexcept {
    const SafetyOutputs& s = cycle.report->safety;
    if (first_ || s.stop_requested != stop_ || s.warning != warning_ || s.latched_faults != faults_) {
        char faults[256];
        char text[linux_port::kServiceStatusMax];
        static_cast<void>(format_fault_names(s.latched_faults, faults, sizeof faults));
        static_cast<void>(std::snprintf(text, sizeof text, "%s%s; faults %.150s (since cycle %d)",
                                        s.stop_requested ? "STOP" : "run", s.warning ? ", warning" : "", faults,
                                        cycle.k));
        static_cast<void>(notifier_->status(text));
        first_ = false;
        stop_ = s.stop_requested;
        warning_ = s.warning;
        faults_ = s.latched_faults;
    }
}

}  // namespace cellguard::monitor
