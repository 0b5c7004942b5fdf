// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A camera's time stamps mapped to CLOCK_MONOTONIC (device_clock.hpp).
#include "cellguard/port/device_clock.hpp"

#include <algorithm>
#include <cmath>

namespace cellguard::linux_port {

bool valid(const DeviceClockParams& p) noexcept {
    return p.window >= 1U && p.window <= kMaxDeviceClockWindow && p.max_stamp_error_us > 0U &&
           p.max_stamp_error_us < (std::uint64_t{1} << 62U) && std::isfinite(p.max_skew_ppm) && p.max_skew_ppm > 0.0 &&
           p.skew_interval_us > 0U && p.restart_frames >= 1U && p.skew_allowance_us < (std::uint64_t{1} << 52U);
}

const char* to_string(StampVerdict v) noexcept {
    switch (v) {
        case StampVerdict::kAccepted: return "accepted";
        case StampVerdict::kLearning: return "learning the offset";
        case StampVerdict::kNotIncreasing: return "device time not increasing";
        case StampVerdict::kJumpForward: return "device time jumped forward";
        case StampVerdict::kOutsideError: return "device time jumped back or the frame arrived late";
        case StampVerdict::kSkew: return "device clock skew beyond the limit";
    }
    return "unknown";
}

DeviceClock::DeviceClock(const DeviceClockParams& params) noexcept : params_(params), params_ok_(valid(params)) {}

void DeviceClock::restart() noexcept {
    locked_ = false;
    after_refusal_ = false;
    late_count_ = 0U;
    has_previous_ = false;
    window_count_ = 0U;
    window_next_ = 0U;
    candidate_frames_ = 0U;
}

void DeviceClock::push(std::int64_t sample) noexcept {
    window_[window_next_] = sample;
    window_next_ = (window_next_ + 1U) % params_.window;
    window_count_ = std::min(window_count_ + 1U, params_.window);
}

std::int64_t DeviceClock::window_min() const noexcept {
    return *std::min_element(window_.begin(), window_.begin() + static_cast<std::ptrdiff_t>(window_count_));
}

MappedStamp DeviceClock::refuse(StampVerdict v) noexcept {
    ++refused_;
    after_refusal_ = true;
    locked_ = false;
    window_count_ = 0U;
    window_next_ = 0U;
    candidate_frames_ = 0U;
    late_count_ = 0U;
    return MappedStamp{v, 0U};
}

MappedStamp DeviceClock::learn(std::int64_t sample, std::uint64_t device_us) noexcept {
    if (window_count_ > 0U) {
        const auto [lo, hi] = std::minmax_element(window_.begin(),
                                                  window_.begin() + static_cast<std::ptrdiff_t>(window_count_));
        const std::int64_t low = std::min(*lo, sample);
        const std::int64_t high = std::max(*hi, sample);
        if (static_cast<std::uint64_t>(high - low) > params_.max_stamp_error_us) {
            window_count_ = 0U;  // disagrees with the candidates: start anew from this frame
            window_next_ = 0U;
            candidate_frames_ = 0U;
        }
    }
    push(sample);
    ++candidate_frames_;
    if (candidate_frames_ < params_.restart_frames) {
        if (after_refusal_) {
            ++relearning_;
        }
        return MappedStamp{StampVerdict::kLearning, 0U};
    }
    locked_ = true;
    after_refusal_ = false;
    ++locks_;
    estimate_ = window_min();
    anchor_device_us_ = device_us;
    anchor_estimate_ = estimate_;
    return MappedStamp{StampVerdict::kAccepted,
                       static_cast<std::uint64_t>(static_cast<std::int64_t>(device_us) + estimate_)};
}

MappedStamp DeviceClock::late(std::int64_t sample, std::uint64_t device_us) noexcept {
    ++refused_;
    const auto error = static_cast<std::int64_t>(params_.max_stamp_error_us);
    if (late_count_ > 0U && (std::max(late_high_, sample) - std::min(late_low_, sample) > error)) {
        late_count_ = 0U;  // not the same step: start counting anew
    }
    late_low_ = late_count_ == 0U ? sample : std::min(late_low_, sample);
    late_high_ = late_count_ == 0U ? sample : std::max(late_high_, sample);
    if (++late_count_ >= params_.restart_frames) {
        // restart_frames consistent late frames: the device clock stepped back; the new estimate holds from the next frame.
        window_count_ = 0U;
        window_next_ = 0U;
        push(late_low_);
        estimate_ = late_low_;
        anchor_device_us_ = device_us;
        anchor_estimate_ = estimate_;
        late_count_ = 0U;
        ++locks_;
    }
    return MappedStamp{StampVerdict::kOutsideError, 0U};
}

MappedStamp DeviceClock::map(std::uint64_t device_us, std::uint64_t receive_us) noexcept {
    constexpr std::uint64_t kLimit = std::uint64_t{1} << 62U;  // both clocks far below: the subtraction cannot overflow
    if (!params_ok_ || device_us >= kLimit || receive_us >= kLimit) {
        return MappedStamp{StampVerdict::kLearning, 0U};
    }
    const std::int64_t sample = static_cast<std::int64_t>(receive_us) - static_cast<std::int64_t>(device_us);
    const bool increasing = !has_previous_ || device_us > previous_device_us_;
    has_previous_ = true;
    previous_device_us_ = device_us;
    if (!increasing) {
        return refuse(StampVerdict::kNotIncreasing);
    }
    if (!locked_) {
        return learn(sample, device_us);
    }
    const auto error = static_cast<std::int64_t>(params_.max_stamp_error_us);
    if (sample - estimate_ < -error) {
        return refuse(StampVerdict::kJumpForward);
    }
    if (sample - estimate_ > error) {
        return late(sample, device_us);
    }
    late_count_ = 0U;
    push(sample);
    estimate_ = window_min();
    const std::uint64_t elapsed = device_us - anchor_device_us_;
    if (elapsed >= params_.skew_interval_us) {
        const auto drift = static_cast<double>(estimate_ - anchor_estimate_);
        last_skew_ppm_ = drift * 1e6 / static_cast<double>(elapsed);
        const double allowed = params_.max_skew_ppm * 1e-6 * static_cast<double>(elapsed) +
                               static_cast<double>(params_.skew_allowance_us);
        if (std::abs(drift) > allowed) {
            return refuse(StampVerdict::kSkew);
        }
        anchor_device_us_ = device_us;
        anchor_estimate_ = estimate_;
    }
    return MappedStamp{StampVerdict::kAccepted,
                       static_cast<std::uint64_t>(static_cast<std::int64_t>(device_us) + estimate_)};
}

}  // namespace cellguard::linux_port
