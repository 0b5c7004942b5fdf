// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file can_port.hpp
/// The monitor's CAN port: the CanSender its CanSafetyOutput sends through,
/// one of a SocketCAN interface (the Linux port's SocketCan, cellguard/port/can.hpp),
/// a candump log file (cellguard/host/io/candump_log.hpp) or another
/// CanSender (a test's, a future transport). Its detail faults are those of
/// the sender in use (the interface's: the port drains the socket when
/// asked, error frames to the fault monitor, data frames, such as the PLC's
/// command frames, into a bounded receive queue). Sending and receiving
/// allocate nothing.
#ifndef CELLGUARD_MONITOR_CAN_PORT_HPP
#define CELLGUARD_MONITOR_CAN_PORT_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "cellguard/can/can_sender.hpp"
#include "cellguard/host/io/candump_log.hpp"
#include "cellguard/host/io/io_status.hpp"
#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/port/can.hpp"
#include "cellguard/safety/clock.hpp"

namespace cellguard::monitor {

/// Data frames the port keeps between two reads of its receive queue.
constexpr std::size_t kReceiveQueueFrames = 64U;

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class CanPort final : public CanSender {
public:
    /// What the port sends on.
    enum class Kind : std::uint8_t {
        kNone = 0,       ///< nothing opened: every send fails
        kInterface = 1,  ///< a SocketCAN interface
        kLog = 2,        ///< a candump log file
        kSender = 3,     ///< a CanSender given to use_sender()
    };

    /// Opens SocketCAN interface @p name (closing what was open); received
    /// frames are stamped on @p clock (the cycle's clock, which must outlive
    /// the port): see take_received.
    linux_port::SocketCanStatus open_interface(const std::string& name, MonotonicClock& clock);
    /// Creates the candump log @p path whose lines name @p interface_name and
    /// take their time from @p clock (which must outlive the port).
    IoStatus open_log(const std::string& path, const std::string& interface_name, MonotonicClock& clock);
    /// Sends through @p sender (which must outlive the port).
    void use_sender(CanSender& sender) noexcept;

    /// Sends @p frame; false when it was not sent (written, for a log).
    bool send(const CanFrame& frame) noexcept override;
    /// The detail faults of the sender in use (SocketCan::detail_faults for
    /// an interface; 0 for a log or nothing).
    [[nodiscard]] std::uint16_t detail_faults() noexcept override;
    /// Reads every frame waiting on an interface (error frames go to its
    /// fault monitor, data frames into the receive queue with their arrival
    /// time; when the queue is full the oldest frame is dropped and counted).
    /// Other kinds: nothing.
    void drain() noexcept;
    /// Takes the oldest queued data frame into @p out and its arrival on the
    /// port's clock into @p arrival_us: the kernel's receive time stamp moved
    /// to that clock (linux_port::arrival_monotonic_us, with the clock read
    /// just after the frame's read, as the real-time clock is), never earlier
    /// than the last time the socket was seen empty nor than the frame before
    /// it (the socket's queue is first in, first out), never later than the read;
    /// without a usable kernel stamp that earliest time (the safe side for
    /// every age check). False when none is queued.
    [[nodiscard]] bool take_received(CanFrame& out, std::uint64_t& arrival_us) noexcept;
    /// Received data frames whose arrival came from the kernel's stamp, and those that got the earliest bound.
    [[nodiscard]] std::uint64_t kernel_stamped() const noexcept { return rx_kernel_stamped_; }
    /// See kernel_stamped().
    [[nodiscard]] std::uint64_t bound_stamped() const noexcept { return rx_bound_stamped_; }
    /// Data frames dropped because the receive queue was full.
    [[nodiscard]] std::uint64_t receive_dropped() const noexcept { return rx_dropped_; }
    /// Shows every frame sent and every received frame taken to @p tap
    /// (nullptr: none); cycle_observer.hpp.
    void set_tap(CanFrameTap* tap) noexcept { tap_ = tap; }
    /// Frames sent (written, for a log) so far.
    [[nodiscard]] std::size_t frames_sent() const noexcept { return sent_; }
    /// What the port sends on.
    [[nodiscard]] Kind kind() const noexcept { return kind_; }
    /// The interface name or the log's path ("" otherwise).
    [[nodiscard]] const std::string& target() const noexcept { return target_; }

    /// Ends the output: a log is flushed and closed. False when writing the
    /// log failed at any time; true for the other kinds.
    bool close() noexcept;
    /// The summary line: "summary: CAN frames sent on IF; K frames received
    /// with the kernel's time stamp, B stamped at the earliest bound" for an interface,
    /// "summary: N CAN frames written to PATH" (with " (WRITE ERROR)" when
    /// @p log_ok is false) for a log, "summary: N CAN frames sent" otherwise.
    void write_summary(std::FILE* out, bool log_ok) const noexcept;

private:
    Kind kind_ = Kind::kNone;
    std::string target_;
    linux_port::SocketCan socket_;
    CandumpLogWriter log_;
    CanSender* sender_ = nullptr;
    CanFrameTap* tap_ = nullptr;
    std::size_t sent_ = 0U;
    MonotonicClock* clock_ = nullptr;     ///< an interface's: stamps received frames
    std::uint64_t empty_seen_us_ = 0U;    ///< when a read last found the socket empty
    std::uint64_t last_arrival_us_ = 0U;  ///< the last queued frame's arrival: the next is never earlier (FIFO)
    std::array<CanFrame, kReceiveQueueFrames> rx_{};                  ///< ring of received data frames
    std::array<std::uint64_t, kReceiveQueueFrames> rx_arrival_us_{};  ///< their arrival times
    std::uint64_t rx_kernel_stamped_ = 0U;
    std::uint64_t rx_bound_stamped_ = 0U;
    std::size_t rx_head_ = 0U;   ///< oldest frame
    std::size_t rx_count_ = 0U;  ///< frames queued
    std::uint64_t rx_dropped_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_CAN_PORT_HPP
