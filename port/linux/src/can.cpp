// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/port/can.hpp"

#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>

namespace cellguard::linux_port {
namespace {

constexpr std::uint16_t set_bits(std::uint16_t value, std::uint16_t bits) noexcept {
    return static_cast<std::uint16_t>(static_cast<unsigned>(value) | static_cast<unsigned>(bits));
}

constexpr std::uint16_t clear_bits(std::uint16_t value, std::uint16_t bits) noexcept {
    return static_cast<std::uint16_t>(static_cast<unsigned>(value) & ~static_cast<unsigned>(bits));
}

constexpr std::uint16_t kSendFaults = set_bits(
    set_bits(fault_bit(FaultCode::kCanTxBufferFull), fault_bit(FaultCode::kCanNetworkDown)),
    set_bits(fault_bit(FaultCode::kCanSendFailed), fault_bit(FaultCode::kCanControllerProblem)));

// Every fault this port raises is a CAN detail bit (ActiveFaults 9..14), never
// one of the safety logic's Fault bits 0..8 (the logic sees them as kCanError).
constexpr std::uint16_t kPortFaults = set_bits(set_bits(kSendFaults, fault_bit(FaultCode::kCanBusOff)),
                                               fault_bit(FaultCode::kCanErrorPassive));
static_assert(kPortFaults == kCanDetailFaultBits, "the port raises exactly the CAN detail fault bits");

// Controller status bits of an error frame's data[1], as unsigned masks.
constexpr unsigned kCtrlPassive = static_cast<unsigned>(CAN_ERR_CRTL_RX_PASSIVE) |
                                  static_cast<unsigned>(CAN_ERR_CRTL_TX_PASSIVE);
constexpr unsigned kCtrlOverflow = static_cast<unsigned>(CAN_ERR_CRTL_RX_OVERFLOW) |
                                   static_cast<unsigned>(CAN_ERR_CRTL_TX_OVERFLOW);
constexpr unsigned kCtrlWarning = static_cast<unsigned>(CAN_ERR_CRTL_RX_WARNING) |
                                  static_cast<unsigned>(CAN_ERR_CRTL_TX_WARNING);
constexpr unsigned kCtrlActive = static_cast<unsigned>(CAN_ERR_CRTL_ACTIVE);

/// Waits up to @p wait_us for @p fd to become writable (EINTR ends the wait early; the caller retries).
void wait_writable(int fd, std::uint32_t wait_us) noexcept {
    pollfd p{};
    p.fd = fd;
    p.events = POLLOUT;
    timespec timeout{};
    timeout.tv_sec = static_cast<time_t>(wait_us / 1000000U);
    timeout.tv_nsec = static_cast<long>(wait_us % 1000000U) * 1000L;
    (void)ppoll(&p, 1U, &timeout, nullptr);
}

/// CLOCK_REALTIME in nanoseconds.
std::int64_t realtime_ns() noexcept {
    timespec t{};
    (void)clock_gettime(CLOCK_REALTIME, &t);
    return static_cast<std::int64_t>(t.tv_sec) * 1000000000LL + static_cast<std::int64_t>(t.tv_nsec);
}

/// Fills @p stamp from the SCM_TIMESTAMPNS message of @p msg (if any) and the real-time clock now.
void read_stamp(msghdr& msg, ReceiveStamp& stamp) noexcept {
    stamp.read_realtime_ns = realtime_ns();
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS &&
            c->cmsg_len >= CMSG_LEN(sizeof(timespec))) {
            timespec t{};
            std::memcpy(&t, CMSG_DATA(c), sizeof(t));  // CMSG_DATA need not be aligned for timespec
            stamp.kernel_realtime_ns = static_cast<std::int64_t>(t.tv_sec) * 1000000000LL +
                                       static_cast<std::int64_t>(t.tv_nsec);
            stamp.kernel = stamp.kernel_realtime_ns > 0;
        }
    }
}

}  // namespace

const char* to_string(SocketCanError error) noexcept {
    switch (error) {
        case SocketCanError::kOk: return "ok";
        case SocketCanError::kInvalidInterfaceName: return "invalid CAN interface name";
        case SocketCanError::kNoSuchInterface: return "no such network interface";
        case SocketCanError::kCanNotSupported: return "the kernel has no CAN socket support";
        case SocketCanError::kNotACanInterface: return "the interface is not a CAN interface";
        case SocketCanError::kSocketSetupFailed: return "CAN socket setup failed";
        case SocketCanError::kNotOpen: return "CAN socket not open";
        case SocketCanError::kInvalidFrame: return "invalid CAN frame (ID above 11 bits or DLC above 8)";
        case SocketCanError::kTxBufferFull: return "CAN transmit queue full";
        case SocketCanError::kNetworkDown: return "CAN network down";
        case SocketCanError::kSendFailed: return "CAN send failed";
    }
    return "unknown SocketCAN error";
}

SendErrnoClass classify_send_errno(int err) noexcept {
    if (err == ENOBUFS || err == EAGAIN || err == EWOULDBLOCK) {
        return SendErrnoClass::kRetry;
    }
    if (err == ENETDOWN || err == ENODEV || err == ENXIO) {
        return SendErrnoClass::kNetworkDown;
    }
    return SendErrnoClass::kFailed;
}

ErrorFrameReport classify_error_frame(const can_frame& frame) noexcept {
    ErrorFrameReport r;
    if ((frame.can_id & CAN_ERR_FLAG) == 0U) {
        return r;
    }
    const std::uint32_t cls = frame.can_id & CAN_ERR_MASK;
    const unsigned ctrl = frame.len > 1U ? static_cast<unsigned>(frame.data[1]) : 0U;  // controller status
    std::uint16_t raised = ((cls & CAN_ERR_BUSOFF) != 0U) ? fault_bit(FaultCode::kCanBusOff) : std::uint16_t{0U};
    if ((cls & (CAN_ERR_TX_TIMEOUT | CAN_ERR_ACK | CAN_ERR_TRX)) != 0U) {
        raised = set_bits(raised, fault_bit(FaultCode::kCanControllerProblem));
    }
    if ((cls & CAN_ERR_CRTL) != 0U) {
        if ((ctrl & kCtrlPassive) != 0U) {
            raised = set_bits(raised, fault_bit(FaultCode::kCanErrorPassive));
        }
        if ((ctrl & kCtrlOverflow) != 0U) {
            raised = set_bits(raised, fault_bit(FaultCode::kCanControllerProblem));
        }
        r.warning = (ctrl & kCtrlWarning) != 0U;
        r.back_to_error_active = (ctrl & kCtrlActive) != 0U;
    }
    r.restarted = (cls & CAN_ERR_RESTARTED) != 0U;
    r.raised_faults = raised;
    return r;
}

KernelFrameKind classify_kernel_frame(const can_frame& frame, CanFrame& out) noexcept {
    if ((frame.can_id & CAN_ERR_FLAG) != 0U) {
        return KernelFrameKind::kError;
    }
    if ((frame.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG)) != 0U || frame.len > CAN_MAX_DLEN) {
        return KernelFrameKind::kIgnored;
    }
    CanFrame f{frame.can_id & CAN_SFF_MASK, frame.len, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    std::memcpy(f.data, frame.data, frame.len);
    out = f;
    return KernelFrameKind::kData;
}

SocketCanStatus to_kernel_frame(const CanFrame& frame, can_frame& out) noexcept {
    if (frame.id > kCanMaxStandardId || frame.dlc > kCanMaxDataLength) {
        return SocketCanStatus{SocketCanError::kInvalidFrame, 0};
    }
    can_frame k{};
    k.can_id = frame.id;
    k.len = frame.dlc;
    std::memcpy(k.data, frame.data, frame.dlc);
    out = k;
    return SocketCanStatus{};
}

void CanFaultMonitor::on_error_frame(const ErrorFrameReport& report) noexcept {
    if ((report.raised_faults & fault_bit(FaultCode::kCanBusOff)) != 0U) {
        restarted_since_bus_off_ = false;
    }
    if (report.restarted) {
        restarted_since_bus_off_ = true;
        active_ = clear_bits(active_, fault_bit(FaultCode::kCanErrorPassive));
    }
    if (report.back_to_error_active) {
        active_ = clear_bits(active_, fault_bit(FaultCode::kCanErrorPassive));
    }
    active_ = set_bits(active_, report.raised_faults);
}

void CanFaultMonitor::on_send(SocketCanError outcome) noexcept {
    switch (outcome) {
        case SocketCanError::kOk:
            active_ = clear_bits(active_, kSendFaults);
            if (restarted_since_bus_off_) {
                active_ = clear_bits(active_, fault_bit(FaultCode::kCanBusOff));
            }
            break;
        case SocketCanError::kTxBufferFull: active_ = set_bits(active_, fault_bit(FaultCode::kCanTxBufferFull)); break;
        case SocketCanError::kNetworkDown: active_ = set_bits(active_, fault_bit(FaultCode::kCanNetworkDown)); break;
        case SocketCanError::kInvalidFrame:  // a program error, reported as a failed send
        case SocketCanError::kNotOpen:
        case SocketCanError::kSendFailed:
        default: active_ = set_bits(active_, fault_bit(FaultCode::kCanSendFailed)); break;
    }
}

SocketCan::~SocketCan() { close(); }

SocketCan::SocketCan(SocketCan&& other) noexcept
    : fd_(other.fd_), config_(other.config_), monitor_(other.monitor_), last_receive_errno_(other.last_receive_errno_) {
    other.fd_ = -1;
}

SocketCan& SocketCan::operator=(SocketCan&& other) noexcept {
    if (this != &other) {
        close();
        fd_ = other.fd_;
        config_ = other.config_;
        monitor_ = other.monitor_;
        last_receive_errno_ = other.last_receive_errno_;
        other.fd_ = -1;
    }
    return *this;
}

SocketCanStatus SocketCan::open(const char* interface_name, const SocketCanConfig& config) noexcept {
    close();
    if (interface_name == nullptr || interface_name[0] == '\0' || strnlen(interface_name, IFNAMSIZ) >= IFNAMSIZ ||
        config.send_attempts == 0U) {
        return SocketCanStatus{SocketCanError::kInvalidInterfaceName, 0};
    }
    const unsigned index = if_nametoindex(interface_name);
    if (index == 0U) {
        return SocketCanStatus{SocketCanError::kNoSuchInterface, errno};
    }
    const int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0) {
        const int err = errno;
        const bool unsupported = err == EAFNOSUPPORT || err == EPROTONOSUPPORT;
        return SocketCanStatus{unsupported ? SocketCanError::kCanNotSupported : SocketCanError::kSocketSetupFailed,
                               err};
    }
    const can_err_mask_t mask = kErrorFrameMask;
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof(mask)) != 0) {
        const int err = errno;
        (void)::close(fd);
        return SocketCanStatus{SocketCanError::kSocketSetupFailed, err};
    }
    // Receive time stamps for the PLC's command frames (arrival_monotonic_us); a kernel that refuses
    // them leaves every frame unstamped, which the monitor reads on the safe side (the oldest possible arrival).
    const int on = 1;
    (void)setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on));
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(index);
    // The sockets API takes the generic sockaddr.
    if (bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
        const int err = errno;
        (void)::close(fd);
        const bool not_can = err == ENODEV || err == EINVAL;
        return SocketCanStatus{not_can ? SocketCanError::kNotACanInterface : SocketCanError::kSocketSetupFailed, err};
    }
    fd_ = fd;
    config_ = config;
    return SocketCanStatus{};
}

void SocketCan::close() noexcept {
    if (fd_ >= 0) {
        (void)::close(fd_);
        fd_ = -1;
    }
}

SocketCanStatus SocketCan::transmit(const CanFrame& frame) noexcept {
    SocketCanStatus status;
    can_frame k{};
    if (fd_ < 0) {
        status = SocketCanStatus{SocketCanError::kNotOpen, 0};
    } else {
        status = to_kernel_frame(frame, k);
    }
    for (std::uint8_t attempt = 0U; status.ok() && attempt < config_.send_attempts; ++attempt) {
        if (attempt > 0U) {
            wait_writable(fd_, config_.retry_wait_us);
        }
        const ssize_t n = ::write(fd_, &k, sizeof(k));
        if (n == static_cast<ssize_t>(sizeof(k))) {
            monitor_.on_send(SocketCanError::kOk);
            return SocketCanStatus{};
        }
        if (n >= 0) {
            status = SocketCanStatus{SocketCanError::kSendFailed, 0};  // short write
            break;
        }
        const int err = errno;
        switch (classify_send_errno(err)) {
            case SendErrnoClass::kRetry:
                if (attempt + 1U == config_.send_attempts) {
                    status = SocketCanStatus{SocketCanError::kTxBufferFull, err};
                }
                break;
            case SendErrnoClass::kNetworkDown: status = SocketCanStatus{SocketCanError::kNetworkDown, err}; break;
            case SendErrnoClass::kFailed: status = SocketCanStatus{SocketCanError::kSendFailed, err}; break;
        }
    }
    monitor_.on_send(status.error);
    return status;
}

std::int64_t realtime_now_ns() noexcept { return realtime_ns(); }

std::uint64_t arrival_monotonic_us(const ReceiveStamp& stamp, std::uint64_t read_mono_us, std::uint64_t not_before_us,
                                   bool* from_kernel) noexcept {
    bool kernel = false;
    std::uint64_t arrival = std::min(not_before_us, read_mono_us);
    if (stamp.kernel && stamp.read_realtime_ns >= stamp.kernel_realtime_ns) {
        const auto age_us = static_cast<std::uint64_t>(stamp.read_realtime_ns - stamp.kernel_realtime_ns) / 1000U;
        if (age_us <= read_mono_us && read_mono_us - age_us >= not_before_us) {
            arrival = read_mono_us - age_us;
            kernel = true;
        }
    }
    if (from_kernel != nullptr) {
        *from_kernel = kernel;
    }
    return arrival;
}

SocketCan::ReceiveOutcome SocketCan::receive(CanFrame& out) noexcept {
    ReceiveStamp ignored{};
    return receive(out, ignored);
}

SocketCan::ReceiveOutcome SocketCan::receive(CanFrame& out, ReceiveStamp& stamp) noexcept {
    stamp = ReceiveStamp{};
    if (fd_ < 0) {
        last_receive_errno_ = EBADF;
        return ReceiveOutcome::kFailed;
    }
    can_frame k{};
    iovec io{&k, sizeof(k)};
    alignas(cmsghdr) std::array<unsigned char, CMSG_SPACE(sizeof(timespec))> control{};
    msghdr msg{};
    msg.msg_iov = &io;
    msg.msg_iovlen = 1U;
    msg.msg_control = control.data();
    msg.msg_controllen = control.size();
    const ssize_t n = ::recvmsg(fd_, &msg, 0);
    if (n >= 0) {
        read_stamp(msg, stamp);
    }
    if (n < 0) {
        const int err = errno;
        if (err == EAGAIN || err == EWOULDBLOCK) {
            return ReceiveOutcome::kNothing;
        }
        last_receive_errno_ = err;
        return ReceiveOutcome::kFailed;
    }
    if (n != static_cast<ssize_t>(sizeof(k))) {
        return ReceiveOutcome::kIgnoredFrame;  // not a classic CAN frame
    }
    switch (classify_kernel_frame(k, out)) {
        case KernelFrameKind::kData: return ReceiveOutcome::kFrame;
        case KernelFrameKind::kError:
            monitor_.on_error_frame(classify_error_frame(k));
            return ReceiveOutcome::kErrorFrame;
        case KernelFrameKind::kIgnored: return ReceiveOutcome::kIgnoredFrame;
    }
    return ReceiveOutcome::kIgnoredFrame;
}

std::uint16_t SocketCan::detail_faults() noexcept {
    if (is_open()) {
        CanFrame rx{};
        int read = 0;
        while (read < kMaxFramesPerPoll && receive(rx) != ReceiveOutcome::kNothing) {
            ++read;
        }
    }
    return active_faults();
}

}  // namespace cellguard::linux_port
