// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file device_clock.hpp
/// A camera's time stamps mapped to CLOCK_MONOTONIC, checked frame by frame.
/// Pure arithmetic: no camera library, no OS call, no heap (the window is a
/// fixed array), so it is unit-tested with synthetic sequences.
///
/// Model: a frame captured at device time d arrives at monotonic time
/// r = d + offset + latency, latency >= 0. The offset is estimated as the
/// smallest (r - d) over the last `window` accepted frames (a min filter:
/// the frame with the least delivery delay); a frame's mapped stamp is
/// d + estimate, which is never after its receive time.
///
/// Every frame is checked before it is used:
/// - device time increasing (strictly) over the previous frame; otherwise
///   kNotIncreasing (the device clock stepped back or the frame repeated);
/// - (r - d) - estimate >= -max_stamp_error_us: otherwise kJumpForward (the
///   device clock stepped forward, or the mapped stamp would lie after the
///   frame's arrival by more than the error allowed);
/// - (r - d) - estimate <= max_stamp_error_us: otherwise kOutsideError (the
///   device clock stepped back, or the frame arrived later than allowed: the
///   two cannot be told apart from one frame, and both are refused). The
///   estimate is kept (a step back can only make stamps older, never newer):
///   a late frame costs only itself; after `restart_frames` such frames in a
///   row that agree with each other the clock is taken as stepped back and
///   their smallest (r - d) becomes the estimate for the frames after them;
/// - skew: every `skew_interval_us` of device time the drift of the estimate
///   since the last check must stay within max_skew_ppm of the device time
///   elapsed plus skew_allowance_us (the estimate itself moves by the
///   changes of the least delivery delay); otherwise kSkew. The limit must allow
///   CLOCK_MONOTONIC's own NTP slew (at most 500 ppm) plus the camera
///   crystal's error (typically below 100 ppm): the default is 1000 ppm.
/// Any other refused frame gets no stamp and is counted; the estimate is dropped and
/// learnt again from the next `restart_frames` frames that agree with each
/// other (all within max_stamp_error_us of each other, device time
/// increasing): the first restart_frames - 1 of them are refused as
/// kLearning, the last is the first one accepted again. A frame that does
/// not agree starts the candidate set anew. At start the first estimate is
/// learnt the same way.
#ifndef CELLGUARD_PORT_DEVICE_CLOCK_HPP
#define CELLGUARD_PORT_DEVICE_CLOCK_HPP

#include <array>
#include <cstddef>
#include <cstdint>

namespace cellguard::linux_port {

/// Most frames in the min filter's window.
constexpr std::size_t kMaxDeviceClockWindow = 64U;

/// The mapping's limits (see the file comment).
struct DeviceClockParams {
    std::size_t window = 16U;                   ///< accepted frames in the min filter, 1..kMaxDeviceClockWindow
    std::uint64_t max_stamp_error_us = 20000U;  ///< most (r - d) may differ from the estimate
    double max_skew_ppm = 1000.0;               ///< most drift of the estimate, ppm of device time
    std::uint64_t skew_interval_us = 5000000U;  ///< device time between two skew checks (> 0)
    std::uint64_t skew_allowance_us = 2000U;    ///< drift allowed beyond max_skew_ppm at each check
    std::uint32_t restart_frames = 4U;          ///< consistent frames that (re)establish the estimate (>= 1)
};

/// True when @p p can be used: window 1..kMaxDeviceClockWindow, a positive
/// error, skew limit and skew interval, restart_frames >= 1.
[[nodiscard]] bool valid(const DeviceClockParams& p) noexcept;

/// What the mapping made of one frame.
enum class StampVerdict : std::uint8_t {
    kAccepted = 0,       ///< mono_us is the frame's capture time on CLOCK_MONOTONIC
    kLearning = 1,       ///< no estimate yet (start or after a refusal): no stamp
    kNotIncreasing = 2,  ///< device time not after the previous frame's
    kJumpForward = 3,    ///< (r - d) below the estimate by more than the error allowed
    kOutsideError = 4,   ///< (r - d) above the estimate by more than the error allowed
    kSkew = 5,           ///< the estimate drifted faster than max_skew_ppm
};

/// A short name of @p v ("accepted", "jump forward", ...).
[[nodiscard]] const char* to_string(StampVerdict v) noexcept;

/// One frame's mapping.
struct MappedStamp {
    StampVerdict verdict = StampVerdict::kLearning;  ///< see StampVerdict
    std::uint64_t mono_us = 0U;                      ///< kAccepted: the capture time, CLOCK_MONOTONIC microseconds
};

/// See the file comment. Not thread-safe: one thread maps one camera's frames.
class DeviceClock {
public:
    /// A mapping with @p params (invalid parameters: every frame is refused as kLearning).
    explicit DeviceClock(const DeviceClockParams& params) noexcept;

    /// Maps the frame with device time stamp @p device_us (microseconds of
    /// the camera's clock) received at @p receive_us (CLOCK_MONOTONIC
    /// microseconds) and checks it. Allocates nothing.
    [[nodiscard]] MappedStamp map(std::uint64_t device_us, std::uint64_t receive_us) noexcept;
    /// Drops the estimate (a reconnected camera's clock restarted): the next
    /// frames learn it again. Counters are kept.
    void restart() noexcept;

    /// True while an estimate is held (the last frame was accepted).
    [[nodiscard]] bool locked() const noexcept { return locked_; }
    /// The current estimate of (monotonic - device), microseconds (valid when locked()).
    [[nodiscard]] std::int64_t offset_us() const noexcept { return estimate_; }
    /// The last skew measured (ppm, 0 before the first check).
    [[nodiscard]] double last_skew_ppm() const noexcept { return last_skew_ppm_; }
    /// Frames refused since construction (every verdict but kAccepted and kLearning).
    [[nodiscard]] std::uint64_t refused() const noexcept { return refused_; }
    /// Frames refused as kLearning after a refusal (not after start or restart()).
    [[nodiscard]] std::uint64_t relearning() const noexcept { return relearning_; }
    /// Times the estimate was established (1 after a clean start).
    [[nodiscard]] std::uint64_t locks() const noexcept { return locks_; }

private:
    MappedStamp learn(std::int64_t sample, std::uint64_t device_us) noexcept;
    MappedStamp refuse(StampVerdict v) noexcept;
    MappedStamp late(std::int64_t sample, std::uint64_t device_us) noexcept;
    void push(std::int64_t sample) noexcept;
    [[nodiscard]] std::int64_t window_min() const noexcept;

    DeviceClockParams params_;
    bool params_ok_;
    bool locked_ = false;
    bool has_previous_ = false;
    bool after_refusal_ = false;  ///< learning again after a refusal (not after start or restart())
    std::uint64_t previous_device_us_ = 0U;
    std::array<std::int64_t, kMaxDeviceClockWindow> window_{};  ///< accepted (or candidate) samples, a ring
    std::size_t window_count_ = 0U;
    std::size_t window_next_ = 0U;
    std::int64_t estimate_ = 0;
    std::uint32_t candidate_frames_ = 0U;  ///< learning: consistent frames so far
    std::uint32_t late_count_ = 0U;        ///< locked: kOutsideError frames in a row that agree
    std::int64_t late_low_ = 0;            ///< their smallest (r - d)
    std::int64_t late_high_ = 0;           ///< their largest (r - d)
    std::uint64_t anchor_device_us_ = 0U;  ///< skew: device time of the last check
    std::int64_t anchor_estimate_ = 0;     ///< skew: the estimate then
    double last_skew_ppm_ = 0.0;
    std::uint64_t refused_ = 0U;
    std::uint64_t relearning_ = 0U;
    std::uint64_t locks_ = 0U;
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_DEVICE_CLOCK_HPP
