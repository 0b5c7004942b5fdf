// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file daemon_observers.hpp
/// The monitor as a daemon: two cycle observers (cycle_observer.hpp).
///
/// EventLog turns the cycles into log lines with a syslog priority, queued
/// on port/linux's LogQueue (log_queue.hpp; a writer thread writes them to
/// the journal or the terminal): never a line per cycle, only changes:
/// - a zone's state: warning when it becomes INTRUDED, UNSEEN or FAULT,
///   notice when it becomes CLEAR;
/// - the protective stop: warning when it is requested after a cycle without
///   it (with the zones and faults of that cycle), notice at the release;
/// - each fault: error when it latches (sensor faults, the camera's, and the
///   CAN output's among them), notice when it clears;
/// - a heartbeat at info every heartbeat period of CLOCK_MONOTONIC: cycles,
///   stop cycles, the longest cycle since the last heartbeat and overall,
///   the faults latched now, log lines dropped.
/// Lines end with "(cycle K)". Formatting goes into the queue's slots: no
/// allocation; a full queue drops the line and counts it.
///
/// ServiceStatus sends, through port/linux's ServiceNotifier (service.hpp),
/// STATUS= when the stop, the warning or the latched faults change.
/// WATCHDOG=1 is WatchdogFeed's (watchdog_feed.hpp): after healthy cycles only.
#ifndef CELLGUARD_MONITOR_DAEMON_OBSERVERS_HPP
#define CELLGUARD_MONITOR_DAEMON_OBSERVERS_HPP

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/port/log_queue.hpp"
#include "cellguard/port/service.hpp"

namespace cellguard::monitor {

/// Default heartbeat period, microseconds (10 s).
constexpr std::uint64_t kDefaultHeartbeatUs = 10000000U;

/// What an EventLog counted.
struct EventCounts {
    std::uint64_t cycles = 0U;        ///< cycles seen
    std::uint64_t stop_cycles = 0U;   ///< cycles with the stop requested
    std::uint64_t stops = 0U;         ///< stops requested after a cycle without one
    std::uint64_t lines = 0U;         ///< lines queued
    std::uint64_t heartbeats = 0U;    ///< heartbeat lines queued
    std::uint64_t max_cycle_us = 0U;  ///< the longest cycle
};

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class EventLog final : public CycleObserver {
public:
    /// Logs the cycles of a monitor configured by @p cfg (zone names; must
    /// outlive the log) into @p queue, a heartbeat every @p heartbeat_us
    /// (0: none).
    EventLog(const cell::MonitorConfig& cfg, linux_port::LogQueue& queue,
             std::uint64_t heartbeat_us = kDefaultHeartbeatUs) noexcept;

    /// See the file comment.
    void after_cycle(const CycleView& cycle) noexcept override;
    /// Queues the heartbeat line now (also at the end of a run).
    void heartbeat(int k) noexcept;
    /// What was counted.
    [[nodiscard]] const EventCounts& counts() const noexcept { return counts_; }

private:
    // NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
    void line(linux_port::LogPriority priority, const char* format, ...) noexcept __attribute__((format(printf, 3, 4)));
    void log_zones(const CycleView& cycle) noexcept;
    void log_stop(const CycleView& cycle) noexcept;
    void log_faults(const CycleView& cycle) noexcept;

    const cell::MonitorConfig* cfg_;
    linux_port::LogQueue* queue_;
    std::uint64_t heartbeat_us_;
    std::uint64_t next_heartbeat_us_ = 0U;
    bool first_ = true;
    bool stopped_ = false;
    std::uint32_t faults_ = 0U;
    std::array<ZoneState, kMaxZones> zones_{};
    std::uint64_t period_max_us_ = 0U;
    EventCounts counts_{};
};

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class ServiceStatus final : public CycleObserver {
public:
    /// Reports through @p notifier (must outlive this).
    explicit ServiceStatus(linux_port::ServiceNotifier& notifier) noexcept : notifier_(&notifier) {}
    /// See the file comment.
    void after_cycle(const CycleView& cycle) noexcept override;

private:
    linux_port::ServiceNotifier* notifier_;
    bool first_ = true;
    bool stop_ = false;
    bool warning_ = false;
    std::uint32_t faults_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_DAEMON_OBSERVERS_HPP
