// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's CAN port (can_port.hpp).
#include "cellguard/monitor/can_port.hpp"

#include <algorithm>

namespace cellguard::monitor {

linux_port::SocketCanStatus CanPort::open_interface(const std::string& name, MonotonicClock& clock) {
    (void)close();
    kind_ = Kind::kNone;
    const linux_port::SocketCanStatus st = socket_.open(name.c_str());
    if (st.ok()) {
        kind_ = Kind::kInterface;
        target_ = name;
        clock_ = &clock;
        empty_seen_us_ = clock.now_us();  // nothing read yet: a frame waiting now arrived after the socket opened
    }
    return st;
}

IoStatus CanPort::open_log(const std::string& path, const std::string& interface_name, MonotonicClock& clock) {
    (void)close();
    kind_ = Kind::kNone;
    const IoStatus st = log_.open(path.c_str(), interface_name.c_str(), clock);
    if (st.ok()) {
        kind_ = Kind::kLog;
        target_ = path;
    }
    return st;
}

void CanPort::use_sender(CanSender& sender) noexcept {
    (void)close();
    sender_ = &sender;
    kind_ = Kind::kSender;
}

bool CanPort::send(const CanFrame& frame) noexcept {
    bool sent = false;
    switch (kind_) {
        case Kind::kInterface: sent = socket_.send(frame); break;
        case Kind::kLog: sent = log_.send(frame); break;
        case Kind::kSender: sent = sender_->send(frame); break;
        case Kind::kNone: break;
    }
    if (sent) {
        ++sent_;
        if (tap_ != nullptr) {
            tap_->on_frame(frame, TapDirection::kSent);
        }
    }
    return sent;
}

std::uint16_t CanPort::detail_faults() noexcept {
    switch (kind_) {
        case Kind::kInterface: drain(); return socket_.active_faults();
        case Kind::kSender: return sender_->detail_faults();
        case Kind::kLog:
        case Kind::kNone: break;
    }
    return 0U;
}

void CanPort::drain() noexcept {
    if (kind_ != Kind::kInterface) {
        return;
    }
    constexpr int kMaxFramesPerDrain = 256;  // bounds the work when the bus floods
    CanFrame rx{};
    linux_port::ReceiveStamp stamp{};
    for (int n = 0; n < kMaxFramesPerDrain; ++n) {
        const std::uint64_t before_us = clock_->now_us();
        const linux_port::SocketCan::ReceiveOutcome r = socket_.receive(rx, stamp);
        if (r == linux_port::SocketCan::ReceiveOutcome::kNothing) {
            empty_seen_us_ = before_us;  // every later frame arrived after this
            return;
        }
        // The frame's age on the real-time clock, paired with this clock read at the same moment (the
        // tightest of up to three monotonic readings around a real-time one, after the read). Read on
        // opposite sides of the call, or with a preemption between them, the two clocks would shift
        // the frame's arrival by the preemption: two frames of one sample came out in reverse order
        // ('time went backwards') or a copy late, in the vcan VM under load.
        const std::uint64_t read_us = std::max(
            before_us, linux_port::pair_with_realtime(stamp, [this]() { return clock_->now_us(); }));
        if (r == linux_port::SocketCan::ReceiveOutcome::kFailed) {
            return;
        }
        if (r != linux_port::SocketCan::ReceiveOutcome::kFrame) {
            continue;
        }
        bool from_kernel = false;
        // FIFO: a frame read after another did not arrive before it.
        const std::uint64_t arrival = std::max(
            linux_port::arrival_monotonic_us(stamp, read_us, empty_seen_us_, &from_kernel), last_arrival_us_);
        last_arrival_us_ = arrival;
        ++(from_kernel ? rx_kernel_stamped_ : rx_bound_stamped_);
        if (rx_count_ == rx_.size()) {
            rx_head_ = (rx_head_ + 1U) % rx_.size();
            --rx_count_;
            ++rx_dropped_;
        }
        const std::size_t slot = (rx_head_ + rx_count_) % rx_.size();
        rx_[slot] = rx;
        rx_arrival_us_[slot] = arrival;
        ++rx_count_;
    }
}

bool CanPort::take_received(CanFrame& out, std::uint64_t& arrival_us) noexcept {
    if (rx_count_ == 0U) {
        return false;
    }
    out = rx_[rx_head_];
    arrival_us = rx_arrival_us_[rx_head_];
    rx_head_ = (rx_head_ + 1U) % rx_.size();
    --rx_count_;
    if (tap_ != nullptr) {
        tap_->on_frame(out, TapDirection::kReceived);
    }
    return true;
}

bool CanPort::close() noexcept {
    const bool ok = kind_ != Kind::kLog || log_.close();
    socket_.close();
    return ok;
}

void CanPort::write_summary(std::FILE* out, bool log_ok) const noexcept {
    switch (kind_) {
        case Kind::kInterface:
            static_cast<void>(std::fprintf(out,
                                           "summary: CAN frames sent on %s; %llu frames received with the kernel's "
                                           "time stamp, %llu stamped at the earliest bound\n",
                                           target_.c_str(), static_cast<unsigned long long>(rx_kernel_stamped_),
                                           static_cast<unsigned long long>(rx_bound_stamped_)));
            break;
        case Kind::kLog:
            static_cast<void>(std::fprintf(out, "summary: %zu CAN frames written to %s%s\n", log_.lines(),
                                           target_.c_str(), log_ok ? "" : " (WRITE ERROR)"));
            break;
        case Kind::kSender:
        case Kind::kNone: static_cast<void>(std::fprintf(out, "summary: %zu CAN frames sent\n", sent_)); break;
    }
}

}  // namespace cellguard::monitor
