// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's CAN port (can_port.hpp).
#include "cellguard/monitor/can_port.hpp"

namespace cellguard::monitor {

linux_port::SocketCanStatus CanPort::open_interface(const std::string& name) {
    (void)close();
    kind_ = Kind::kNone;
    const linux_port::SocketCanStatus st = socket_.open(name.c_str());
    if (st.ok()) {
        kind_ = Kind::kInterface;
        target_ = name;
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
    }
    return sent;
}

std::uint16_t CanPort::detail_faults() noexcept {
    switch (kind_) {
        case Kind::kInterface: return socket_.detail_faults();
        case Kind::kSender: return sender_->detail_faults();
        case Kind::kLog:
        case Kind::kNone: break;
    }
    return 0U;
}

bool CanPort::close() noexcept {
    const bool ok = kind_ != Kind::kLog || log_.close();
    socket_.close();
    return ok;
}

void CanPort::write_summary(std::FILE* out, bool log_ok) const noexcept {
    switch (kind_) {
        case Kind::kInterface:
            static_cast<void>(std::fprintf(out, "summary: CAN frames sent on %s\n", target_.c_str()));
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
