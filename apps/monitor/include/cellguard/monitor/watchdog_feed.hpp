// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file watchdog_feed.hpp
/// When the monitor feeds its watchdogs (the systemd watchdog, WATCHDOG=1
/// through service.hpp, and with --watchdog a watchdog device through
/// port/linux's watchdog.hpp): only after a healthy cycle. A cycle is
/// healthy exactly when (decide_feed, pure):
/// 1. the controller ran it: its report is a new one (CycleReport::cycle
///    greater than that of the last cycle decided on);
/// 2. it finished within its budget: the controller's cycle time, its
///    output included (CycleView::cycle_us), is at most the budget;
/// 3. no non-recoverable fault is latched: kInternalCheck (the controller's
///    own state, tables, zones or robot model no longer match their CRCs),
///    kClockFault (the clock stopped, stepped back, or runs at a wrong rate
///    against the PLC's samples) or kPriorCheckFailed (the prior in RAM no
///    longer matches its CRC). These stay latched until a restart, so once
///    one is raised the monitor stops feeding for good and the watchdog
///    restarts it (systemd) or resets the machine (the device): the restart
///    re-reads and re-checks everything and begins in the safe state.
/// A cycle in the safe state for any other reason (a person in a zone, a
/// sensor missing, the PLC's command invalid, the restart interlock) is a
/// healthy cycle: the controller is working and holds the stop itself.
/// A cycle that hangs never reaches the decision: nothing is fed.
#ifndef CELLGUARD_MONITOR_WATCHDOG_FEED_HPP
#define CELLGUARD_MONITOR_WATCHDOG_FEED_HPP

#include <cstdint>

#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/port/log_queue.hpp"
#include "cellguard/port/service.hpp"
#include "cellguard/port/watchdog.hpp"
#include "cellguard/safety/faults.hpp"

namespace cellguard::monitor {

/// The latched faults that stop the watchdog feed (see the file comment).
constexpr std::uint32_t kWatchdogStopFaults = fault_bit(Fault::kInternalCheck) | fault_bit(Fault::kClockFault) |
                                              fault_bit(Fault::kPriorCheckFailed);

/// Why a cycle did not feed the watchdogs. Values are stable (logged).
enum class FeedRefusal : std::uint8_t {
    kNone = 0,                 ///< fed: a healthy cycle
    kNoNewCycle = 1,           ///< the report is not newer than the last one decided on
    kOverBudget = 2,           ///< the cycle took longer than its budget
    kNonRecoverableFault = 3,  ///< kInternalCheck, kClockFault or kPriorCheckFailed latched
};
/// A short, static name for @p refusal.
[[nodiscard]] const char* to_string(FeedRefusal refusal) noexcept;

/// What decide_feed() looks at of one cycle.
struct FeedInput {
    std::uint64_t cycle = 0U;           ///< CycleReport::cycle
    std::uint64_t cycle_us = 0U;        ///< the controller's time for the cycle
    std::uint32_t latched_faults = 0U;  ///< SafetyOutputs::latched_faults after the cycle
};

/// kNone when the cycle @p in is healthy against a budget of @p budget_us and
/// @p last_cycle, the cycle number of the previous decision (0: none yet).
[[nodiscard]] FeedRefusal decide_feed(const FeedInput& in, std::uint64_t budget_us, std::uint64_t last_cycle) noexcept;

/// What a WatchdogFeed did.
struct FeedCounts {
    std::uint64_t fed = 0U;              ///< healthy cycles (both watchdogs fed, as each allows)
    std::uint64_t no_new_cycle = 0U;     ///< refused: kNoNewCycle
    std::uint64_t over_budget = 0U;      ///< refused: kOverBudget
    std::uint64_t non_recoverable = 0U;  ///< refused: kNonRecoverableFault
    std::uint64_t device_failures = 0U;  ///< the device's keepalive failed
};

/// The observer that feeds both watchdogs after each healthy cycle and logs
/// each change between fed and refused (with the reason).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class WatchdogFeed final : public CycleObserver {
public:
    /// Feeds @p notifier (its rate limit: one WATCHDOG=1 per half interval)
    /// and @p device (nullptr: none) after each healthy cycle of budget
    /// @p budget_us; logs to @p log (nullptr: none). All must outlive this.
    WatchdogFeed(linux_port::ServiceNotifier* notifier, linux_port::Watchdog* device, std::uint64_t budget_us,
                 linux_port::LogQueue* log) noexcept
        : notifier_(notifier), device_(device), budget_us_(budget_us), log_(log) {}
    /// See the file comment.
    void after_cycle(const CycleView& cycle) noexcept override;
    /// What was done.
    [[nodiscard]] const FeedCounts& counts() const noexcept { return counts_; }

private:
    void note(FeedRefusal refusal, int k) noexcept;

    linux_port::ServiceNotifier* notifier_;
    linux_port::Watchdog* device_;
    std::uint64_t budget_us_;
    linux_port::LogQueue* log_;
    std::uint64_t last_cycle_ = 0U;
    FeedRefusal last_ = FeedRefusal::kNone;
    FeedCounts counts_{};
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_WATCHDOG_FEED_HPP
