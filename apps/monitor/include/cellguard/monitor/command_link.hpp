// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file command_link.hpp
/// Where the monitor's cycle gets the PLC's command from. Each cycle the
/// link hands every command frame that arrived to the controller's
/// CommandReceiver (lib/can/command_receiver.hpp) and polls it at the
/// cycle's start: the CommandPoll goes to the controller. Two links:
/// - the simulated PLC of the robot-cell demo: each cycle it encodes the
///   simulation's command with the PLC-side sender (plc_command_sender.hpp,
///   the code a PLC ports), puts the six frames on the monitor's CAN port
///   (the log or the interface, as a PLC on the same bus would) and feeds
///   them to the receiver, stamped a fixed lead before the cycle starts;
/// - a SocketCAN interface: every frame waiting on the CAN port's socket
///   (non-blocking) is fed to the receiver with its kernel receive stamp.
/// Both feed each good sample the receiver accepts to the clock-rate check
/// (lib/can/clock_rate_check.hpp; on when [can] command_period_ms is set):
/// the PLC's oscillator as a second time base for the controller's clock. A
/// receiver fault restarts the check's window (a PLC that stops is the
/// receiver's SCT, not a clock fault). The simulated PLC is stamped on the
/// controller's own clock and sends once per executed cycle (a skipped
/// period looks like a fast clock): the monitor gives it no rate check
/// (main.cpp); the unit tests exercise the wiring through it.
/// Neither allocates per cycle.
#ifndef CELLGUARD_MONITOR_COMMAND_LINK_HPP
#define CELLGUARD_MONITOR_COMMAND_LINK_HPP

#include <cstdint>

#include "cellguard/can/clock_rate_check.hpp"
#include "cellguard/can/command_receiver.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard::monitor {

/// The command receiver's configuration for the cell of @p cfg, as the
/// monitor and its log check use it: the command channel, SCT the command's
/// age limit (command_age_limit_us), at least the sample window + 1 us; the
/// other limits the receiver's defaults (copies within 10 ms, the six frames
/// within 20 ms).
[[nodiscard]] CommandReceiverConfig command_receiver_config(const cell::MonitorConfig& cfg);

/// The clock-rate check's configuration for the cell of @p cfg ([can] command_period_ms, ...).
[[nodiscard]] ClockRateConfig clock_rate_config(const cell::MonitorConfig& cfg);

/// A CommandReceiver and the ClockRateCheck fed by its good samples.
class CheckedReceiver {
public:
    /// @p config must pass CommandReceiver::check_config, @p rate ClockRateCheck::check_config.
    CheckedReceiver(const CommandReceiverConfig& config, const ClockRateConfig& rate) noexcept;
    /// Hands @p frame, received at @p now_us, to the receiver; a new good
    /// sample goes to the rate check, a new receiver fault restarts its window.
    void on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;
    /// The receiver's poll at @p now_us.
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept { return receiver_.poll(now_us); }
    /// The receiver.
    [[nodiscard]] const CommandReceiver& receiver() const noexcept { return receiver_; }
    /// The rate check.
    [[nodiscard]] const ClockRateCheck& rate() const noexcept { return rate_; }

private:
    CommandReceiver receiver_;
    ClockRateCheck rate_;
    std::uint32_t good_samples_ = 0U;
    std::uint32_t fault_events_ = 0U;
};

/// Source of the PLC's command frames (see the file comment).
class CommandLink {
public:
    /// Feeds the frames that arrived to the receiver and polls it at @p now_us.
    [[nodiscard]] virtual CommandPoll poll(std::uint64_t now_us) noexcept = 0;
    /// Command frames handed to the receiver so far.
    [[nodiscard]] virtual std::uint64_t frames_received() const noexcept = 0;
    /// The clock-rate check on this link's samples.
    [[nodiscard]] virtual const ClockRateCheck& clock_rate() const noexcept = 0;

protected:
    CommandLink() = default;
    ~CommandLink() = default;
    CommandLink(const CommandLink&) = default;
    CommandLink& operator=(const CommandLink&) = default;
    CommandLink(CommandLink&&) = default;
    CommandLink& operator=(CommandLink&&) = default;
};

/// How long before a cycle's start the simulated PLC's frames arrive, microseconds.
constexpr std::uint64_t kSimulatedCommandLeadUs = 5000U;

/// The robot-cell demo's PLC (see the file comment).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class SimulatedPlcLink final : public CommandLink {
public:
    /// A PLC that sends through @p bus (nullptr: frames go to the receiver only).
    SimulatedPlcLink(const CommandReceiverConfig& config, CanSender* bus, const ClockRateConfig& rate = {}) noexcept;
    /// The command of the next sample (sent at the next poll). Without one, nothing is sent.
    void set_command(const RobotCommand& command) noexcept;
    /// Stops sending for good, whatever set_command says later (a PLC that
    /// fell silent: the receiver's SCT and the command age follow).
    void go_silent() noexcept { silent_ = true; }
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept override;
    [[nodiscard]] std::uint64_t frames_received() const noexcept override { return frames_; }
    [[nodiscard]] const ClockRateCheck& clock_rate() const noexcept override { return receiver_.rate(); }
    /// The receiver.
    [[nodiscard]] const CommandReceiver& receiver() const noexcept { return receiver_.receiver(); }

private:
    PlcCommandSender sender_;
    CheckedReceiver receiver_;
    CanSender* bus_;
    RobotCommand command_{};
    bool has_command_ = false;
    bool silent_ = false;
    std::uint64_t frames_ = 0U;
};

/// Command frames from the CAN port's SocketCAN interface.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class SocketCanCommandLink final : public CommandLink {
public:
    /// Reads from @p port (an interface; other kinds give no frames).
    SocketCanCommandLink(const CommandReceiverConfig& config, CanPort& port, const ClockRateConfig& rate = {}) noexcept;
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept override;
    [[nodiscard]] std::uint64_t frames_received() const noexcept override { return frames_; }
    [[nodiscard]] const ClockRateCheck& clock_rate() const noexcept override { return receiver_.rate(); }

private:
    CheckedReceiver receiver_;
    CanPort* port_;
    std::uint64_t frames_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_COMMAND_LINK_HPP
