// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file can.hpp
/// The Linux port's CAN: SocketCan, a CanSender (can_sender.hpp) on a raw
/// SocketCAN socket bound to one interface, non-blocking, with bounded send
/// retries; send errors and CAN error frames become cellguard fault codes
/// (FaultCode in safety_frame.hpp) with a defined recovery, which it reports
/// itself as its detail faults (CanSender::detail_faults) for the
/// diagnostics frame.
///
/// Error classification is done by pure functions (classify_send_errno,
/// classify_error_frame, classify_kernel_frame) and a small state machine
/// (CanFaultMonitor), so that it is unit-tested without a CAN kernel.
///
/// Subscribed error classes (CAN_RAW_ERR_FILTER, kErrorFrameMask): TX
/// timeout, controller problems, missing ACK, bus-off, controller restarted,
/// transceiver status. Protocol violations and bus errors are not subscribed
/// (they can flood; the controller's error counters and state already summarise them).
///
/// Fault codes and their recovery (CanFaultMonitor):
/// | fault                  | raised by                                         | cleared by |
/// |------------------------|---------------------------------------------------|------------|
/// | kCanBusOff             | CAN_ERR_BUSOFF                                    | a CAN_ERR_RESTARTED frame, then an accepted send |
/// | kCanErrorPassive       | CAN_ERR_CRTL RX/TX passive                        | CAN_ERR_CRTL_ACTIVE, or a restart |
/// | kCanControllerProblem  | CAN_ERR_CRTL RX/TX overflow, CAN_ERR_TX_TIMEOUT, CAN_ERR_ACK, CAN_ERR_TRX | the next accepted send |
/// | kCanTxBufferFull       | ENOBUFS / EAGAIN on every one of the bounded attempts | the next accepted send |
/// | kCanNetworkDown        | ENETDOWN, ENODEV, ENXIO                           | the next accepted send |
/// | kCanSendFailed         | any other send errno, a short write               | the next accepted send |
/// "Accepted" means the kernel took the frame (write() returned the whole frame);
/// that it reached the PLC is what the PLC's SCT check confirms.
#ifndef CELLGUARD_PORT_CAN_HPP
#define CELLGUARD_PORT_CAN_HPP

#include <linux/can.h>
#include <linux/can/error.h>

#include <cstdint>

#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/can_sender.hpp"
#include "cellguard/can/safety_frame.hpp"

namespace cellguard::linux_port {

/// Why a SocketCAN operation failed.
enum class SocketCanError : std::uint8_t {
    kOk = 0,                ///< success
    kInvalidInterfaceName,  ///< empty, or too long for IFNAMSIZ
    kNoSuchInterface,       ///< no network interface has this name
    kCanNotSupported,       ///< socket(PF_CAN) failed: the kernel has no CAN support
    kNotACanInterface,      ///< bind() refused the interface (exists, but is not CAN)
    kSocketSetupFailed,     ///< another socket(), setsockopt() or bind() failure
    kNotOpen,               ///< the socket is not open
    kInvalidFrame,          ///< frame to send: ID above 11 bits or DLC above 8
    kTxBufferFull,          ///< ENOBUFS / EAGAIN on every attempt
    kNetworkDown,           ///< the interface is down
    kSendFailed,            ///< another send error, or a short write
};
/// A short, static description of @p error (never nullptr).
[[nodiscard]] const char* to_string(SocketCanError error) noexcept;

/// Result of a SocketCAN operation: the error and the errno behind it (0 if none).
struct [[nodiscard]] SocketCanStatus {
    SocketCanError error = SocketCanError::kOk;  ///< what failed
    int sys_errno = 0;                           ///< errno of the failed system call, 0 if none
    /// True on success.
    [[nodiscard]] bool ok() const noexcept { return error == SocketCanError::kOk; }
};

/// How a send errno is handled.
enum class SendErrnoClass : std::uint8_t {
    kRetry = 0,        ///< queue full (ENOBUFS, EAGAIN): retry within the bound
    kNetworkDown = 1,  ///< interface down (ENETDOWN, ENODEV, ENXIO): no retry
    kFailed = 2,       ///< anything else: no retry
};
/// Classifies the errno of a failed send (pure).
[[nodiscard]] SendErrnoClass classify_send_errno(int err) noexcept;

/// Error classes subscribed with CAN_RAW_ERR_FILTER.
constexpr std::uint32_t kErrorFrameMask = CAN_ERR_TX_TIMEOUT | CAN_ERR_CRTL | CAN_ERR_ACK | CAN_ERR_BUSOFF |
                                          CAN_ERR_RESTARTED | CAN_ERR_TRX;

/// What one CAN error frame reports.
struct ErrorFrameReport {
    std::uint16_t raised_faults = 0U;   ///< FaultCode bits the frame raises
    bool restarted = false;             ///< the controller restarted (after bus-off)
    bool back_to_error_active = false;  ///< the controller is error-active again
    bool warning = false;               ///< an error counter reached the warning level (reported, not a fault)
};
/// Classifies an error frame (CAN_ERR_FLAG set) as the kernel delivers it (pure).
/// A frame without CAN_ERR_FLAG reports nothing.
[[nodiscard]] ErrorFrameReport classify_error_frame(const can_frame& frame) noexcept;

/// What a frame read from the socket is.
enum class KernelFrameKind : std::uint8_t {
    kData = 0,   ///< a standard-ID data frame: converted to CanFrame
    kError = 1,  ///< an error frame: see classify_error_frame
    kIgnored =
        2,  ///< extended-ID or remote frame, or DLC > 8: never passed on (an extended ID could alias a safety ID)
};
/// Classifies @p frame and, for kData, writes it to @p out (pure).
[[nodiscard]] KernelFrameKind classify_kernel_frame(const can_frame& frame, CanFrame& out) noexcept;

/// Converts @p frame for the kernel; kInvalidFrame if its ID exceeds 11 bits or its DLC 8 (pure).
[[nodiscard]] SocketCanStatus to_kernel_frame(const CanFrame& frame, can_frame& out) noexcept;

/// Active CAN faults and their recovery (see the table in the file comment).
class CanFaultMonitor {
public:
    /// Applies one error frame.
    void on_error_frame(const ErrorFrameReport& report) noexcept;
    /// Applies the outcome of one send (kOk = the kernel accepted the frame).
    void on_send(SocketCanError outcome) noexcept;
    /// FaultCode bits now active.
    [[nodiscard]] std::uint16_t active_faults() const noexcept { return active_; }

private:
    std::uint16_t active_ = 0U;
    bool restarted_since_bus_off_ = false;
};

/// When a received frame reached the kernel: the socket's receive time
/// stamp (SO_TIMESTAMPNS, CLOCK_REALTIME) and CLOCK_REALTIME read right
/// after the frame was read, so that the frame's age at the read is known
/// without trusting the real-time clock's absolute value.
struct ReceiveStamp {
    bool kernel = false;                  ///< the kernel stamped the frame
    std::int64_t kernel_realtime_ns = 0;  ///< that stamp
    std::int64_t read_realtime_ns = 0;    ///< CLOCK_REALTIME just after the read
};

/// The arrival of a received frame on the caller's monotonic clock (pure):
/// @p read_mono_us (the caller's clock at the read) minus the frame's age at
/// the read (read_realtime_ns - kernel_realtime_ns), accepted only inside
/// [@p not_before_us, @p read_mono_us]: the frame cannot have arrived before
/// the socket was last seen empty, nor after it was read. Without a kernel
/// stamp, or when the age falls outside that window (the real-time clock
/// stepped between arrival and read), @p not_before_us: the oldest the frame
/// can be, so that every age and timing check on it errs on the side of the
/// stop. @p from_kernel (optional) tells which.
[[nodiscard]] std::uint64_t arrival_monotonic_us(const ReceiveStamp& stamp, std::uint64_t read_mono_us,
                                                 std::uint64_t not_before_us, bool* from_kernel = nullptr) noexcept;

/// CLOCK_REALTIME now, in nanoseconds (the clock of the kernel's receive stamps).
[[nodiscard]] std::int64_t realtime_now_ns() noexcept;

/// Reads @p stamp's read_realtime_ns again, paired with @p mono_now (the
/// caller's monotonic clock), and returns that clock's reading at the same
/// moment: the middle of two monotonic readings around the real-time one,
/// the pair whose readings lie closest together of up to three tries (the
/// first within @p tight_us ends them). A thread preempted between the two
/// clocks' readings would otherwise shift the frame's arrival by the
/// preemption (seen: two frames of one PLC sample dated in reverse order,
/// and a copy dated milliseconds late, in the vcan VM under load). Pure but
/// for the clocks; @p gap_us (optional) gets the chosen pair's spread.
template <typename MonoNow>
[[nodiscard]] std::uint64_t pair_with_realtime(ReceiveStamp& stamp, MonoNow&& mono_now, std::uint64_t tight_us = 50U,
                                               std::uint64_t* gap_us = nullptr) noexcept {
    std::uint64_t best_mid = 0U;
    std::uint64_t best_gap = ~std::uint64_t{0U};
    for (int i = 0; i < 3 && best_gap > tight_us; ++i) {
        const std::uint64_t m1 = mono_now();
        const std::int64_t real = realtime_now_ns();
        const std::uint64_t m2 = mono_now();
        const std::uint64_t gap = m2 >= m1 ? m2 - m1 : 0U;
        if (gap < best_gap) {
            best_gap = gap;
            best_mid = m1 + gap / 2U;
            stamp.read_realtime_ns = real;
        }
    }
    if (gap_us != nullptr) {
        *gap_us = best_gap;
    }
    return best_mid;
}

/// Send behaviour.
struct SocketCanConfig {
    std::uint8_t send_attempts = 3U;     ///< write() attempts per frame, >= 1
    std::uint32_t retry_wait_us = 200U;  ///< longest wait for the socket to be writable between attempts
};

/// A raw CAN socket on one interface; move-only, closed by its destructor.
/// A send blocks at most (send_attempts - 1) * retry_wait_us.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class SocketCan final : public CanSender {
public:
    /// What receive() found.
    enum class ReceiveOutcome : std::uint8_t {
        kFrame = 0,         ///< a data frame, written to the caller's CanFrame
        kErrorFrame = 1,    ///< an error frame, applied to the fault monitor
        kIgnoredFrame = 2,  ///< an extended-ID, remote or oversized frame, dropped
        kNothing = 3,       ///< no frame waiting
        kFailed = 4,        ///< read() failed; see last_receive_errno()
    };

    /// A closed socket.
    SocketCan() noexcept = default;
    /// Closes the socket.
    ~SocketCan();
    SocketCan(const SocketCan&) = delete;
    SocketCan& operator=(const SocketCan&) = delete;
    /// Takes over @p other's socket.
    SocketCan(SocketCan&& other) noexcept;
    /// Closes this socket and takes over @p other's.
    SocketCan& operator=(SocketCan&& other) noexcept;

    /// Opens a raw CAN socket on @p interface_name (e.g. "can0", "vcan0"):
    /// non-blocking, subscribed to kErrorFrameMask, bound to the interface.
    /// A socket already open is closed first. On failure the socket stays closed.
    SocketCanStatus open(const char* interface_name, const SocketCanConfig& config = SocketCanConfig{}) noexcept;
    /// Closes the socket (no-op when closed).
    void close() noexcept;
    /// True while a socket is open.
    [[nodiscard]] bool is_open() const noexcept { return fd_ >= 0; }

    /// Sends @p frame with the bounded retries; the outcome also goes to the fault monitor.
    SocketCanStatus transmit(const CanFrame& frame) noexcept;
    /// transmit() as a CanSender: true when the kernel accepted the frame.
    bool send(const CanFrame& frame) noexcept override { return transmit(frame).ok(); }
    /// Reads one frame without blocking.
    [[nodiscard]] ReceiveOutcome receive(CanFrame& out) noexcept;
    /// Reads one frame without blocking, with its receive time stamp
    /// (open() asks the kernel for SO_TIMESTAMPNS; a kernel that refuses
    /// leaves stamp.kernel false).
    [[nodiscard]] ReceiveOutcome receive(CanFrame& out, ReceiveStamp& stamp) noexcept;
    /// errno of the last kFailed receive.
    [[nodiscard]] int last_receive_errno() const noexcept { return last_receive_errno_; }

    /// FaultCode bits now active, as last seen (no socket read).
    [[nodiscard]] std::uint16_t active_faults() const noexcept { return monitor_.active_faults(); }
    /// The detail faults for this cycle's diagnostics frame: reads what waits
    /// on the socket (at most kMaxFramesPerPoll frames, so that error frames
    /// reach the fault monitor; data frames are dropped), then active_faults().
    [[nodiscard]] std::uint16_t detail_faults() noexcept override;

    /// Frames detail_faults() reads at most per call.
    static constexpr int kMaxFramesPerPoll = 64;

private:
    int fd_ = -1;
    SocketCanConfig config_{};
    CanFaultMonitor monitor_{};
    int last_receive_errno_ = 0;
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_CAN_HPP
