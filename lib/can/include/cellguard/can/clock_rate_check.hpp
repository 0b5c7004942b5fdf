// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file clock_rate_check.hpp
/// The rate of the controller's clock (CLOCK_MONOTONIC on Linux, SysTick on
/// the Cortex-M7) against a second, independent time base: the PLC's
/// command samples (command_receiver.hpp). The PLC sends one sample per
/// nominal period T from its own oscillator and numbers them with the E2E
/// counter (0..14). Over a window of W PLC periods (counted by the counter,
/// so lost samples still count), the local time that passed between the
/// window's first and last sample, E, against W x T gives the local clock's
/// rate: deviation = (E - W T) / (W T). Beyond the tolerance the check
/// reports Fault::kClockFault (and stays faulted: the controller latches that
/// fault for good).
///
/// Fed with each good sample the receiver accepts (its counter and its
/// receive time stamp: on Linux the kernel's SocketCAN receive stamp), in
/// order. No heap, no OS calls, no floating point.
///
/// What is not a clock fault (the window restarts, no verdict):
/// - restart(): the command link broke (the receiver found a fault: the PLC
///   stopped, a sample was late or corrupt); the receiver's SCT and the
///   command's age are the checks for a PLC that stops;
/// - a step between two samples of more than max_gap_periods counter steps,
///   or longer than max_gap_periods x T of local time (many samples lost:
///   the counter, which wraps every 15 samples, could alias);
/// - a repeated counter (ignored) or local time going backwards (restart:
///   the receiver's kTimeWentBackwards).
///
/// Tolerance and window. Let J bound the error of one receive stamp against
/// the moment the PLC's period began (the PLC task's send jitter, bus
/// arbitration and the queue behind other frames, the kernel's stamping):
/// E is then known within 2 J, so the measured deviation is the true rate
/// error within +-2 J / (W T). A true error r is flagged for certain when
/// |r| > tolerance + 2 J / (W T) and never when |r| < tolerance - 2 J / (W T).
/// Defaults: T as configured, W = 50, tolerance 2 %: with T = 100 ms and
/// J = 10 ms the jitter term is 0.4 %, so a rate error of 0.5 % (or less)
/// is never flagged and one of 2.4 % (or more) always is, 5 % among them.
/// A clock whose rate is off from the start is found at the end of the
/// first window, W periods after the first good sample; one that starts to
/// drift in a running window at the latest at the end of the next window
/// (2 W periods). The check cannot tell which of the two oscillators is
/// off: either way the stop is the right reaction.
#ifndef CELLGUARD_CAN_CLOCK_RATE_CHECK_HPP
#define CELLGUARD_CAN_CLOCK_RATE_CHECK_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/safety/faults.hpp"

namespace cellguard {

/// Configuration of a ClockRateCheck; check with ClockRateCheck::check_config().
struct ClockRateConfig {
    /// The PLC's nominal sample period, microseconds (1 ms .. 10 s); 0 turns the check off.
    std::uint64_t nominal_period_us = 0U;
    std::uint32_t window_periods = 50U;    ///< W: PLC periods per window (10 .. 100000)
    std::uint32_t tolerance_ppm = 20000U;  ///< largest accepted |deviation|, ppm (1000 .. 500000: 0.1 % .. 50 %)
    std::uint8_t max_gap_periods = 7U;     ///< longest step between samples that keeps the window (1 .. 7)
};

/// What one sample gave.
enum class ClockRateVerdict : std::uint8_t {
    kPending = 0,          ///< the window is not complete yet (or the check is off, or it restarted)
    kWithinTolerance = 1,  ///< a window completed within the tolerance
    kOutOfTolerance = 2,   ///< a window completed beyond it: kClockFault
};

/// What the check counted.
struct ClockRateCounts {
    std::uint32_t samples = 0U;              ///< samples fed (saturating)
    std::uint32_t windows = 0U;              ///< windows completed (saturating)
    std::uint32_t restarts = 0U;             ///< windows dropped: restart(), a gap, time backwards (saturating)
    std::int32_t last_deviation_ppm = 0;     ///< the last completed window's deviation (+: local clock fast)
    std::int32_t max_abs_deviation_ppm = 0;  ///< the largest |deviation| of any completed window
};

/// See the file comment.
class ClockRateCheck {
public:
    /// kInvalidArgument unless the check is off (nominal_period_us 0) or
    /// every value is within the range its field names.
    [[nodiscard]] static Status check_config(const ClockRateConfig& config) noexcept;

    /// A check with no window yet. @p config must pass check_config (contract).
    explicit ClockRateCheck(const ClockRateConfig& config) noexcept;

    /// Whether the check runs (a nominal period is configured).
    [[nodiscard]] bool enabled() const noexcept { return config_.nominal_period_us != 0U; }

    /// Feeds the good sample with E2E @p counter (0..14; others restart the
    /// window) received at @p received_us on the controller's clock.
    ClockRateVerdict on_sample(std::uint8_t counter, std::uint64_t received_us) noexcept;

    /// The command link broke: the next sample starts a new window.
    void restart() noexcept;

    /// A window was beyond the tolerance (latched).
    [[nodiscard]] bool faulted() const noexcept { return faulted_; }
    /// fault_bit(kClockFault) once faulted, else 0: for the controller's detected faults.
    [[nodiscard]] std::uint32_t faults() const noexcept { return faulted_ ? fault_bit(Fault::kClockFault) : 0U; }
    /// What was counted.
    [[nodiscard]] const ClockRateCounts& counts() const noexcept { return counts_; }
    /// The configuration in use.
    [[nodiscard]] const ClockRateConfig& config() const noexcept { return config_; }

    /// The deviation in ppm of @p elapsed_us of local time over @p periods
    /// PLC periods of @p period_us each (+: local clock fast), saturated to
    /// the int32 range; 0 when periods or period_us is 0.
    [[nodiscard]] static std::int32_t deviation_ppm(std::uint64_t elapsed_us, std::uint64_t periods,
                                                    std::uint64_t period_us) noexcept;

private:
    void start_window(std::uint8_t counter, std::uint64_t received_us) noexcept;
    ClockRateVerdict finish_window(std::uint64_t received_us) noexcept;

    ClockRateConfig config_;
    bool have_last_ = false;
    std::uint8_t last_counter_ = 0U;
    std::uint64_t last_us_ = 0U;
    std::uint64_t window_start_us_ = 0U;
    std::uint64_t window_periods_ = 0U;  ///< counter steps since the window's first sample
    bool faulted_ = false;
    ClockRateCounts counts_{};
};

}  // namespace cellguard

#endif  // CELLGUARD_CAN_CLOCK_RATE_CHECK_HPP
