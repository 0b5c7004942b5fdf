// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's sources of the PLC's command (command_link.hpp).
#include "cellguard/monitor/command_link.hpp"

#include <algorithm>

namespace cellguard::monitor {

CommandReceiverConfig command_receiver_config(const cell::MonitorConfig& cfg) {
    CommandReceiverConfig rc;
    rc.channel = cfg.can.command;
    rc.link.watchdog_us = link_watchdog_us(cfg);
    rc.sct_us = std::max<std::uint64_t>(cell::command_age_limit_us(cfg), rc.sample_window_us + 1U);
    return rc;
}

ClockRateConfig clock_rate_config(const cell::MonitorConfig& cfg) { return cfg.can.clock_rate; }

std::uint64_t link_watchdog_us(const cell::MonitorConfig& cfg) noexcept {
    const std::uint64_t two_periods = cfg.period_us > UINT64_MAX / 2U ? UINT64_MAX : 2U * cfg.period_us;
    const std::uint64_t w = two_periods > UINT64_MAX - cfg.budget_us ? UINT64_MAX : two_periods + cfg.budget_us;
    return std::max<std::uint64_t>(w, 1U);
}

PlcReceiverConfig plc_receiver_config(const cell::MonitorConfig& cfg) {
    PlcReceiverConfig rc;
    rc.channel = cfg.can.channel;
    rc.link.watchdog_us = link_watchdog_us(cfg);
    rc.srvt_us = cfg.period_us / 2U;
    rc.sct_us = 3U * cfg.period_us;
    rc.expected_zone_count = static_cast<std::uint8_t>(std::min<std::size_t>(cfg.zones.size(), 255U));
    return rc;
}

bool takes_commands(const cell::MonitorConfig& cfg) noexcept { return cfg.robot.enabled || !cfg.cases.empty(); }

CheckedReceiver::CheckedReceiver(const CommandReceiverConfig& config, const ClockRateConfig& rate,
                                 bool standalone_link) noexcept
    : receiver_(config), rate_(rate), standalone_link_(standalone_link && config.link.enabled) {}

void CheckedReceiver::on_standalone_link(const CanFrame& frame, std::uint64_t now_us) noexcept {
    // A cell without commands: the PLC's link frame closes no sample. Its
    // checks keep the echo the controller sends honest; the PLC's receiver
    // bounds the age of the controller's frames (command_link.hpp).
    const LinkFault f = receiver_.link().on_standalone_frame(frame, now_us);
    if (f == LinkFault::kNone) {
        ++standalone_.accepted;
    } else {
        ++standalone_.refused;
        standalone_.last = f;
    }
}

void CheckedReceiver::on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
    if (standalone_link_ && frame.id == receiver_.config().link.peer.can_id) {
        on_standalone_link(frame, now_us);
        return;
    }
    const CommandStatus s = receiver_.on_frame(frame, now_us);
    if (s.fault_events != fault_events_) {
        fault_events_ = s.fault_events;
        rate_.restart();  // the link broke: its own checks act; the next good sample starts a new window
    }
    if (s.good_samples != good_samples_) {
        good_samples_ = s.good_samples;
        const CommandInput& sample = receiver_.last_sample();
        static_cast<void>(rate_.on_sample(sample.counter, sample.received_us));
    }
}

SimulatedPlcLink::SimulatedPlcLink(const CommandReceiverConfig& config, const PlcReceiverConfig& plc, CanSender* bus,
                                   const ClockRateConfig& rate) noexcept
    : sender_(config.channel), plc_(plc), receiver_(config, rate), bus_(bus) {}

void SimulatedPlcLink::set_command(const RobotCommand& command) noexcept {
    command_ = command;
    has_command_ = true;
}

CommandPoll SimulatedPlcLink::poll(std::uint64_t now_us) noexcept {
    // The PLC's clock: a fixed lead before the cycle's start, never before what it saw last.
    const std::uint64_t lead = now_us > kSimulatedCommandLeadUs ? now_us - kSimulatedCommandLeadUs : 0U;
    plc_time_us_ = std::max(plc_time_us_, lead);
    const std::uint64_t arrival = plc_time_us_;
    plc_sees(plc_.poll(arrival));  // the PLC's cycle: its receiver's time checks
    if (!silent_) {
        const bool link = receiver_.receiver().config().link.enabled;
        CanFrame out[kCommandFramesPerSample + 1U] = {};
        std::size_t n = 0U;
        bool alone = false;
        if (has_command_ && link) {
            const LinkFields fields = plc_.next_link(arrival);
            const Result<LinkedCommandFrames> frames = sender_.next_sample(command_, fields,
                                                                           receiver_.receiver().config().link.peer);
            if (frames.ok()) {
                for (const CanFrame& f : frames.value().sample.frame) {
                    out[n++] = f;
                }
                out[n++] = frames.value().link;
            }
        } else if (has_command_) {
            const Result<CommandFrames> frames = sender_.next_sample(command_);
            if (frames.ok()) {
                for (const CanFrame& f : frames.value().frame) {
                    out[n++] = f;
                }
            }
        } else if (link) {
            // No command to send (a cell without commands): the link frame alone, on its own E2E counter.
            const Result<CanFrame> frame = encode_link_frame(plc_.next_link(arrival), standalone_counter_,
                                                             plc_.config().link.own, Span<const CanFrame>());
            if (frame.ok()) {
                standalone_counter_ = e2e_p01_next_counter(standalone_counter_);
                out[n++] = frame.value();
                alone = true;
            }
        }
        for (std::size_t i = 0U; i < n; ++i) {
            if (bus_ != nullptr) {
                static_cast<void>(bus_->send(out[i]));  // the log shows the PLC's frames; a failed write is the log's
            }
            if (alone) {
                receiver_.on_standalone_link(out[i], arrival);
            } else {
                receiver_.on_frame(out[i], arrival);
            }
            ++frames_;
        }
    }
    return receiver_.poll(now_us);
}

void SimulatedPlcLink::on_sent(const CycleFrames& frames, std::uint64_t now_us) noexcept {
    plc_time_us_ = std::max(plc_time_us_, now_us);
    const std::uint64_t t = plc_time_us_;
    plc_sees(plc_.on_frame(frames.safety, t));
    plc_sees(plc_.on_frame(frames.inverted, t));
    if (frames.has_link) {
        plc_sees(plc_.on_frame(frames.link, t));
    }
    plc_sees(plc_.on_frame(frames.diagnostics, t));
    if (frames.has_separation) {
        plc_sees(plc_.on_frame(frames.separation, t));
    }
}

void SimulatedPlcLink::plc_sees(const ReceiverStatus& s) noexcept { plc_status_ = s; }

SocketCanCommandLink::SocketCanCommandLink(const CommandReceiverConfig& config, CanPort& port,
                                           const ClockRateConfig& rate, bool standalone_link) noexcept
    : receiver_(config, rate, standalone_link), port_(&port) {}

CommandPoll SocketCanCommandLink::poll(std::uint64_t now_us) noexcept {
    port_->drain();
    CanFrame f{};
    std::uint64_t arrival_us = 0U;
    while (port_->take_received(f, arrival_us)) {
        // Its arrival, not this cycle's start: the SRVT and the sample window are measured on real arrival times.
        receiver_.on_frame(f, std::min(arrival_us, now_us));
        ++frames_;
    }
    return receiver_.poll(now_us);
}

}  // namespace cellguard::monitor
