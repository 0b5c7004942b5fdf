// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file cycle_clock.hpp
/// The monitor's clock for the SafetyController. Paced (--paced, one cycle
/// per period): the source clock (CLOCK_MONOTONIC) unchanged, so a clock that
/// stops or steps back reaches the safety logic and latches kClockFault
/// (SR-LOGIC-007). Unpaced (the demo as fast as possible): simulated time
/// whose first reading in a cycle is exactly the cycle's simulated start
/// (so runs repeat: the restart delay and frame ages do not depend on how
/// long the host took between cycles), then advances with the source clock
/// (so stage times are real) and never repeats a value; there a stuck
/// source only shows as stage times of zero.
#ifndef CELLGUARD_MONITOR_CYCLE_CLOCK_HPP
#define CELLGUARD_MONITOR_CYCLE_CLOCK_HPP

#include <algorithm>
#include <cstdint>

#include "cellguard/safety/safety_controller.hpp"

namespace cellguard::monitor {

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class CycleClock final : public MonotonicClock {
public:
    /// @p source: the real clock (kept by reference, must outlive this).
    CycleClock(bool paced, MonotonicClock& source) noexcept : paced_(paced), source_(&source) {}

    /// Starts the next cycle at simulated time @p sim_us (ignored when paced).
    void start_cycle(std::uint64_t sim_us) noexcept {
        base_sim_ = paced_ ? source_->now_us() : std::max(sim_us, last_ + 1U);
        first_reading_ = true;  // unpaced: the real base is taken at the cycle's first reading
    }

    /// Paced: the source's reading. Unpaced: the simulated time.
    std::uint64_t now_us() noexcept override {
        if (paced_) {
            return source_->now_us();
        }
        if (first_reading_) {
            base_real_ = source_->now_us();  // the cycle's time starts at its first reading
            first_reading_ = false;
        }
        std::uint64_t v = base_sim_ + (source_->now_us() - base_real_);
        if (v <= last_) {
            v = last_ + 1U;
        }
        last_ = v;
        return v;
    }

    /// The time start_cycle took as the cycle's start.
    [[nodiscard]] std::uint64_t base() const noexcept { return base_sim_; }

private:
    bool paced_;
    MonotonicClock* source_;
    std::uint64_t base_real_ = 0U;  ///< unpaced: the source's time at the cycle's first reading
    std::uint64_t base_sim_ = 0U;
    std::uint64_t last_ = 0U;
    bool first_reading_ = false;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_CYCLE_CLOCK_HPP
