// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file cycle_clock.hpp
/// The monitor's clock for the SafetyController. Paced (--paced, one cycle
/// per period): the source clock (CLOCK_MONOTONIC) unchanged, so a clock that
/// stops or steps back reaches the safety logic and latches kClockFault
/// (SR-LOGIC-007). Unpaced (the demo as fast as possible): simulated time
/// only. A cycle's readings are its simulated start, then one microsecond
/// more per reading, never a repeated value: the CAN log, the command
/// receiver's checks (the inverted copy's delay, the safeguard cycle time)
/// and the cycle budget see the same times whatever the host's load, so an
/// unpaced run repeats exactly (issue 32: real time added to the simulated
/// clock made a loaded host's run fail those checks). The real time of each
/// reading is kept (real_span_us) for the run's cycle-time figures, which
/// are measurements, not decisions. There a stuck source cannot show.
/// A measurement that wants the controller to see the host's real cycle
/// times on simulated cycle starts (the soak: its overruns reported by the
/// controller) asks for kSimulatedWithRealElapsed: each cycle starts at its
/// simulated time and advances with the source clock; its runs depend on
/// the host's load, so no test of logic uses it.
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
    /// The time the controller sees.
    enum class Mode : std::uint8_t {
        kPaced,                     ///< the source's, unchanged
        kSimulated,                 ///< the cycle's simulated start plus 1 us per reading
        kSimulatedWithRealElapsed,  ///< the cycle's simulated start plus the source's time since its first reading
    };

    /// @p paced: kPaced, else kSimulated. @p source: the real clock (kept by
    /// reference, must outlive this).
    CycleClock(bool paced, MonotonicClock& source) noexcept
        : CycleClock(paced ? Mode::kPaced : Mode::kSimulated, source) {}
    /// A clock of @p mode on @p source (kept by reference, must outlive this).
    CycleClock(Mode mode, MonotonicClock& source) noexcept
        : paced_(mode == Mode::kPaced), real_elapsed_(mode == Mode::kSimulatedWithRealElapsed), source_(&source) {}

    /// Starts the next cycle at simulated time @p sim_us (ignored when paced).
    void start_cycle(std::uint64_t sim_us) noexcept {
        base_sim_ = paced_ ? source_->now_us() : std::max(sim_us, last_ + 1U);
        readings_ = 0U;
    }

    /// Paced: the source's reading. Unpaced: the cycle's simulated start plus
    /// the readings taken in the cycle so far, in microseconds.
    std::uint64_t now_us() noexcept override {
        const std::uint64_t real = source_->now_us();
        if (paced_) {
            return real;
        }
        if (real_elapsed_) {
            if (readings_ == 0U) {
                real_[0] = real;  // the cycle's time starts at its first reading
            }
            ++readings_;
            const std::uint64_t v = base_sim_ + (real - real_[0]);
            last_ = v > last_ ? v : last_ + 1U;  // never a repeated value
            return last_;
        }
        if (readings_ < kRecorded) {
            real_[readings_] = real;
        }
        last_ = base_sim_ + readings_;  // after the last cycle's readings: start_cycle moved the base past them
        ++readings_;
        return last_;
    }

    /// The time start_cycle took as the cycle's start.
    [[nodiscard]] std::uint64_t base() const noexcept { return base_sim_; }

    /// The real time between two readings of this cycle, @p from_us and
    /// @p to_us as now_us returned them (paced: their difference; unpaced:
    /// the source's times of those readings; 0 when @p to_us is not after
    /// @p from_us or either is not a reading of this cycle).
    [[nodiscard]] std::uint64_t real_span_us(std::uint64_t from_us, std::uint64_t to_us) const noexcept {
        if (to_us <= from_us) {
            return 0U;
        }
        if (paced_ || real_elapsed_) {
            return to_us - from_us;
        }
        if (from_us < base_sim_ || to_us - base_sim_ >= std::min(readings_, kRecorded)) {
            return 0U;
        }
        const std::uint64_t a = real_[from_us - base_sim_];
        const std::uint64_t b = real_[to_us - base_sim_];
        return b > a ? b - a : 0U;
    }

private:
    static constexpr std::uint64_t kRecorded = 64U;  ///< readings per cycle with their real time kept
    bool paced_;
    bool real_elapsed_;  ///< kSimulatedWithRealElapsed
    MonotonicClock* source_;
    std::uint64_t base_sim_ = 0U;
    std::uint64_t last_ = 0U;
    std::uint64_t readings_ = 0U;         ///< unpaced: readings in this cycle
    std::uint64_t real_[kRecorded] = {};  ///< unpaced: the source's time at the first kRecorded of them
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_CYCLE_CLOCK_HPP
