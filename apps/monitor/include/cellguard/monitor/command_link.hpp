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
///
/// Protocol 0.2, the session link (session_link.hpp), on in both: the
/// controller's LinkEndpoint is the receiver's (controller_link(): the CAN
/// safety output stamps its link frames from it). In a cell that takes
/// commands (a robot or monitoring cases) the PLC's link frame closes each
/// command sample (seven frames). A cell without either still has a PLC
/// link: the PLC sends its link frame alone every PLC cycle (CheckedReceiver
/// with standalone_link; LinkEndpoint::on_standalone_frame), so that the
/// controller echoes the PLC's sequence and the PLC's receiver bounds the
/// age of the controller's frames by the round trip on its own clock. A PLC
/// that sends nothing gets no echo: its receiver refuses every pair
/// (kNoEchoYet) and the machine stays stopped. The simulated PLC also plays
/// the PLC's receiving side: the controller's frames of each cycle
/// (on_sent) go to its PlcReceiver, whose link endpoint gives the fields of
/// its link frames.
/// Neither allocates per cycle.
#ifndef CELLGUARD_MONITOR_COMMAND_LINK_HPP
#define CELLGUARD_MONITOR_COMMAND_LINK_HPP

#include <cstdint>

#include "cellguard/can/clock_rate_check.hpp"
#include "cellguard/can/command_receiver.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_output.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard::monitor {

/// The session link's watchdog time W of both sides in the cell of @p cfg:
/// two controller periods plus the cycle budget (cfg.budget_us), 300 ms at
/// 100 ms with a budget of one period (saturating). The round trip it bounds
/// runs from the PLC's link frame to the controller's pair that echoes it:
/// the wait for the next cycle start (at most T), the cycle (at most the
/// budget) and the transfers; the data in use may be one period older at
/// the poll before the next pair; the PLC sends at least once a period.
[[nodiscard]] std::uint64_t link_watchdog_us(const cell::MonitorConfig& cfg) noexcept;

/// The command receiver's configuration for the cell of @p cfg, as the
/// monitor and its log check use it: the command channel, SCT the command's
/// age limit (command_age_limit_us), at least the sample window + 1 us, the
/// session link's watchdog link_watchdog_us; the
/// other limits the receiver's defaults (copies within 10 ms, the six frames
/// within 20 ms).
[[nodiscard]] CommandReceiverConfig command_receiver_config(const cell::MonitorConfig& cfg);

/// The clock-rate check's configuration for the cell of @p cfg ([can] command_period_ms, ...).
[[nodiscard]] ClockRateConfig clock_rate_config(const cell::MonitorConfig& cfg);

/// The PLC-side receiver's configuration for the cell of @p cfg, as the
/// simulated PLC and the demo log check use it: the output channel and zone
/// count, SRVT half a period, SCT three periods, the PLC's session link with
/// the watchdog link_watchdog_us.
[[nodiscard]] PlcReceiverConfig plc_receiver_config(const cell::MonitorConfig& cfg);

/// True when the cell of @p cfg takes the PLC's command (a robot or
/// monitoring cases): the PLC's link frame closes each command sample.
/// Otherwise the PLC sends its link frame alone (see the file comment).
[[nodiscard]] bool takes_commands(const cell::MonitorConfig& cfg) noexcept;

/// What the controller made of the PLC's link frames sent alone (a cell without commands).
struct StandaloneLinkCounts {
    std::uint32_t accepted = 0U;        ///< link frames that passed every check
    std::uint32_t refused = 0U;         ///< link frames refused (any LinkFault)
    LinkFault last = LinkFault::kNone;  ///< the last refusal's reason (kNone: none yet)
};

/// A CommandReceiver and the ClockRateCheck fed by its good samples.
class CheckedReceiver {
public:
    /// @p config must pass CommandReceiver::check_config, @p rate
    /// ClockRateCheck::check_config. @p standalone_link: the PLC's link
    /// frames come alone (a cell without commands; see the file comment).
    CheckedReceiver(const CommandReceiverConfig& config, const ClockRateConfig& rate,
                    bool standalone_link = false) noexcept;
    /// Hands @p frame, received at @p now_us, to the receiver (with
    /// standalone_link, a PLC link frame to the controller's link endpoint
    /// alone); a new good sample goes to the rate check, a new receiver
    /// fault restarts its window.
    void on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept;
    /// Hands @p frame, a PLC link frame sent alone and received at @p now_us,
    /// to the controller's link endpoint (LinkEndpoint::on_standalone_frame); counted in standalone().
    void on_standalone_link(const CanFrame& frame, std::uint64_t now_us) noexcept;
    /// The receiver's poll at @p now_us.
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept { return receiver_.poll(now_us); }
    /// The receiver.
    [[nodiscard]] const CommandReceiver& receiver() const noexcept { return receiver_; }
    /// The controller's link endpoint (the receiver's).
    [[nodiscard]] LinkEndpoint& link() noexcept { return receiver_.link(); }
    /// The rate check.
    [[nodiscard]] const ClockRateCheck& rate() const noexcept { return rate_; }
    /// The PLC's link frames sent alone (standalone_link).
    [[nodiscard]] const StandaloneLinkCounts& standalone() const noexcept { return standalone_; }

private:
    CommandReceiver receiver_;
    ClockRateCheck rate_;
    bool standalone_link_;
    StandaloneLinkCounts standalone_{};
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
    /// The controller's link endpoint: the CAN safety output's link frames take their fields from it.
    [[nodiscard]] virtual LinkEndpoint& controller_link() noexcept = 0;
    /// The frames the controller sent in the cycle, at @p now_us (a simulated PLC receives them).
    virtual void on_sent(const CycleFrames& frames, std::uint64_t now_us) noexcept = 0;
    /// The PLC's link frames sent alone (a cell without commands).
    [[nodiscard]] virtual const StandaloneLinkCounts& standalone_link() const noexcept = 0;

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
    /// A PLC that sends through @p bus (nullptr: frames go to the receiver
    /// only) and receives the controller's frames with a PlcReceiver of
    /// @p plc (which must pass PlcReceiver::check_config, with the link on
    /// when @p config has it on).
    SimulatedPlcLink(const CommandReceiverConfig& config, const PlcReceiverConfig& plc, CanSender* bus,
                     const ClockRateConfig& rate = {}) noexcept;
    /// The command of the next sample (sent at the next poll). Without one,
    /// the PLC sends its link frame alone (session link on) or nothing.
    void set_command(const RobotCommand& command) noexcept;
    /// Stops sending for good, whatever set_command says later (a PLC that
    /// fell silent: the receiver's SCT and the command age follow).
    void go_silent() noexcept { silent_ = true; }
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept override;
    [[nodiscard]] std::uint64_t frames_received() const noexcept override { return frames_; }
    [[nodiscard]] const ClockRateCheck& clock_rate() const noexcept override { return receiver_.rate(); }
    [[nodiscard]] LinkEndpoint& controller_link() noexcept override { return receiver_.link(); }
    void on_sent(const CycleFrames& frames, std::uint64_t now_us) noexcept override;
    [[nodiscard]] const StandaloneLinkCounts& standalone_link() const noexcept override {
        return receiver_.standalone();
    }
    /// The receiver.
    [[nodiscard]] const CommandReceiver& receiver() const noexcept { return receiver_.receiver(); }
    /// The PLC's receiver of the controller's frames: its last status.
    [[nodiscard]] const ReceiverStatus& plc_status() const noexcept { return plc_status_; }

private:
    void plc_sees(const ReceiverStatus& s) noexcept;

    PlcCommandSender sender_;
    PlcReceiver plc_;
    CheckedReceiver receiver_;
    CanSender* bus_;
    RobotCommand command_{};
    ReceiverStatus plc_status_{};
    std::uint64_t plc_time_us_ = 0U;        ///< the PLC's clock: never earlier than what it last saw
    std::uint8_t standalone_counter_ = 0U;  ///< E2E counter of the link frames sent alone
    bool has_command_ = false;
    bool silent_ = false;
    std::uint64_t frames_ = 0U;
};

/// Command frames from the CAN port's SocketCAN interface.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class SocketCanCommandLink final : public CommandLink {
public:
    /// Reads from @p port (an interface; other kinds give no frames);
    /// @p standalone_link: the PLC sends its link frames alone (takes_commands false).
    SocketCanCommandLink(const CommandReceiverConfig& config, CanPort& port, const ClockRateConfig& rate = {},
                         bool standalone_link = false) noexcept;
    [[nodiscard]] CommandPoll poll(std::uint64_t now_us) noexcept override;
    [[nodiscard]] std::uint64_t frames_received() const noexcept override { return frames_; }
    [[nodiscard]] const ClockRateCheck& clock_rate() const noexcept override { return receiver_.rate(); }
    [[nodiscard]] LinkEndpoint& controller_link() noexcept override { return receiver_.link(); }
    /// Nothing: the PLC on the bus receives the controller's frames itself.
    void on_sent(const CycleFrames& /*frames*/, std::uint64_t /*now_us*/) noexcept override {}
    [[nodiscard]] const StandaloneLinkCounts& standalone_link() const noexcept override {
        return receiver_.standalone();
    }

private:
    CheckedReceiver receiver_;
    CanPort* port_;
    std::uint64_t frames_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_COMMAND_LINK_HPP
