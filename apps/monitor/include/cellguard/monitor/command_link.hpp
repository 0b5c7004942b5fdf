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
///   (non-blocking) is fed to the receiver, stamped with the cycle's start.
/// Neither allocates per cycle.
#ifndef CELLGUARD_MONITOR_COMMAND_LINK_HPP
#define CELLGUARD_MONITOR_COMMAND_LINK_HPP

#include <cstdint>

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

/// Source of the PLC's command frames (see the file comment).
class CommandLink {
public:
    /// Feeds the frames that arrived to the receiver and polls it at @p now_us.
    [[nodiscard]] virtual CommandPoll poll(std::uint64_t now_us) noexcept = 0;
    /// Command frames handed to the receiver so far.
    [[nodiscard]] virtual std::uint64_t frames_received() const noexcept = 0;

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
    SimulatedPlcLink(const CommandReceiverConfig& config, CanSender* bus) noexcept;
    /// The command of the next sample (sent at the next poll). Without one, nothing is sent.
    void set_command(const RobotCommand& command) noexcept;
    /// Stops sending for good, whatever set_command says later (a PLC that
    /// fell silent: the receiver's SCT and the command age follow).
    void go_silent() noexcept { silent_ = true; }
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept override;
    [[nodiscard]] std::uint64_t frames_received() const noexcept override { return frames_; }
    /// The receiver.
    [[nodiscard]] const CommandReceiver& receiver() const noexcept { return receiver_; }

private:
    PlcCommandSender sender_;
    CommandReceiver receiver_;
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
    SocketCanCommandLink(const CommandReceiverConfig& config, CanPort& port) noexcept;
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept override;
    [[nodiscard]] std::uint64_t frames_received() const noexcept override { return frames_; }

private:
    CommandReceiver receiver_;
    CanPort* port_;
    std::uint64_t frames_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_COMMAND_LINK_HPP
