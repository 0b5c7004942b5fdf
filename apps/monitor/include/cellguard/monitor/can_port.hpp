/// @file can_port.hpp
/// The monitor's CAN port: the CanSender its CanSafetyOutput sends through,
/// one of a SocketCAN interface (port/linux socketcan.hpp), a candump log
/// file (candump_log.hpp) or another CanSender (a test's, a future
/// transport). Before each cycle poll_faults() drains the interface's receive
/// queue, so that CAN error frames reach its fault monitor, and gives the CAN
/// detail faults for the diagnostics frame. Sending allocates nothing.
#ifndef CELLGUARD_MONITOR_CAN_PORT_HPP
#define CELLGUARD_MONITOR_CAN_PORT_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "cellguard/linux/candump_log.hpp"
#include "cellguard/linux/io_status.hpp"
#include "cellguard/linux/socketcan.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/can/safety_output.hpp"

namespace cellguard::monitor {

/// See the file comment.
class CanPort final : public CanSender {  // NOLINT(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
public:
    /// What the port sends on.
    enum class Kind : std::uint8_t {
        kNone = 0,       ///< nothing opened: every send fails
        kInterface = 1,  ///< a SocketCAN interface
        kLog = 2,        ///< a candump log file
        kSender = 3,     ///< a CanSender given to use_sender()
    };

    /// Opens SocketCAN interface @p name (closing what was open).
    linux_port::SocketCanStatus open_interface(const std::string& name);
    /// Creates the candump log @p path whose lines name @p interface_name and
    /// take their time from @p clock (which must outlive the port).
    IoStatus open_log(const std::string& path, const std::string& interface_name, MonotonicClock& clock);
    /// Sends through @p sender (which must outlive the port).
    void use_sender(CanSender& sender) noexcept;

    /// Sends @p frame; false when it was not sent (written, for a log).
    bool send(const CanFrame& frame) noexcept override;
    /// Before a cycle: reads what waits on the interface (at most 64 frames)
    /// and returns the interface's CAN detail faults (0 for the other kinds).
    std::uint16_t poll_faults() noexcept;
    /// Frames sent (written, for a log) so far.
    [[nodiscard]] std::size_t frames_sent() const noexcept { return sent_; }
    /// What the port sends on.
    [[nodiscard]] Kind kind() const noexcept { return kind_; }
    /// The interface name or the log's path ("" otherwise).
    [[nodiscard]] const std::string& target() const noexcept { return target_; }

    /// Ends the output: a log is flushed and closed. False when writing the
    /// log failed at any time; true for the other kinds.
    bool close() noexcept;
    /// The summary line: "summary: CAN frames sent on IF" for an interface,
    /// "summary: N CAN frames written to PATH" (with " (WRITE ERROR)" when
    /// @p log_ok is false) for a log, "summary: N CAN frames sent" otherwise.
    void write_summary(std::FILE* out, bool log_ok) const noexcept;

private:
    Kind kind_ = Kind::kNone;
    std::string target_;
    linux_port::SocketCan socket_;
    linux_port::CandumpLogWriter log_;
    CanSender* sender_ = nullptr;
    std::size_t sent_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_CAN_PORT_HPP
