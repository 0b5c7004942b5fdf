// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// When the monitor feeds its watchdogs (watchdog_feed.hpp).
#include "cellguard/monitor/watchdog_feed.hpp"

namespace cellguard::monitor {

const char* to_string(FeedRefusal refusal) noexcept {
    switch (refusal) {
        case FeedRefusal::kNone: return "fed";
        case FeedRefusal::kNoNewCycle: return "no new cycle";
        case FeedRefusal::kOverBudget: return "cycle over budget";
        case FeedRefusal::kNonRecoverableFault: return "non-recoverable fault latched";
    }
    return "unknown";
}

FeedRefusal decide_feed(const FeedInput& in, std::uint64_t budget_us, std::uint64_t last_cycle) noexcept {
    if (in.cycle <= last_cycle) {
        return FeedRefusal::kNoNewCycle;
    }
    if (in.cycle_us > budget_us) {
        return FeedRefusal::kOverBudget;
    }
    if ((in.latched_faults & kWatchdogStopFaults) != 0U) {
        return FeedRefusal::kNonRecoverableFault;
    }
    return FeedRefusal::kNone;
}

void WatchdogFeed::note(FeedRefusal refusal, int k) noexcept {
    if (refusal != last_ && log_ != nullptr) {
        if (refusal == FeedRefusal::kNone) {
            static_cast<void>(log_->push(linux_port::LogPriority::kNotice, "watchdog: fed again (cycle %d)", k));
        } else {
            static_cast<void>(
                log_->push(linux_port::LogPriority::kError, "watchdog: not fed: %s (cycle %d)", to_string(refusal), k));
        }
    }
    last_ = refusal;
}

void WatchdogFeed::after_cycle(const CycleView& cycle) noexcept {
    const FeedInput in{cycle.report->cycle, cycle.cycle_us, cycle.report->safety.latched_faults};
    const FeedRefusal refusal = decide_feed(in, budget_us_, last_cycle_);
    if (in.cycle > last_cycle_) {
        last_cycle_ = in.cycle;
    }
    note(refusal, cycle.k);
    switch (refusal) {
        case FeedRefusal::kNone: break;
        case FeedRefusal::kNoNewCycle: ++counts_.no_new_cycle; return;
        case FeedRefusal::kOverBudget: ++counts_.over_budget; return;
        case FeedRefusal::kNonRecoverableFault: ++counts_.non_recoverable; return;
    }
    ++counts_.fed;
    if (notifier_ != nullptr) {
        static_cast<void>(notifier_->watchdog(cycle.now_us));
    }
    if (device_ != nullptr && device_->is_open() && !device_->keepalive()) {
        ++counts_.device_failures;
    }
}

}  // namespace cellguard::monitor
