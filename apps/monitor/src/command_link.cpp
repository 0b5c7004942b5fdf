// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's sources of the PLC's command (command_link.hpp).
#include "cellguard/monitor/command_link.hpp"

#include <algorithm>

namespace cellguard::monitor {

CommandReceiverConfig command_receiver_config(const cell::MonitorConfig& cfg) {
    CommandReceiverConfig rc;
    rc.channel = cfg.can.command;
    // Session link off: the monitor's PLC and output speak protocol 0.1 until they are wired to the controller's link
    // endpoint (issue 33)
    rc.link.enabled = false;
    rc.sct_us = std::max<std::uint64_t>(cell::command_age_limit_us(cfg), rc.sample_window_us + 1U);
    return rc;
}

ClockRateConfig clock_rate_config(const cell::MonitorConfig& cfg) { return cfg.can.clock_rate; }

CheckedReceiver::CheckedReceiver(const CommandReceiverConfig& config, const ClockRateConfig& rate) noexcept
    : receiver_(config), rate_(rate) {}

void CheckedReceiver::on_frame(const CanFrame& frame, std::uint64_t now_us) noexcept {
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

SimulatedPlcLink::SimulatedPlcLink(const CommandReceiverConfig& config, CanSender* bus,
                                   const ClockRateConfig& rate) noexcept
    : sender_(config.channel), receiver_(config, rate), bus_(bus) {}

void SimulatedPlcLink::set_command(const RobotCommand& command) noexcept {
    command_ = command;
    has_command_ = true;
}

CommandPoll SimulatedPlcLink::poll(std::uint64_t now_us) noexcept {
    if (has_command_ && !silent_) {
        const Result<CommandFrames> frames = sender_.next_sample(command_);
        if (frames.ok()) {
            const std::uint64_t arrival = now_us > kSimulatedCommandLeadUs ? now_us - kSimulatedCommandLeadUs : 0U;
            for (const CanFrame& f : frames.value().frame) {
                if (bus_ != nullptr) {
                    static_cast<void>(bus_->send(f));  // the log shows the PLC's frames; a failed write is the log's
                }
                receiver_.on_frame(f, arrival);
                ++frames_;
            }
        }
    }
    return receiver_.poll(now_us);
}

SocketCanCommandLink::SocketCanCommandLink(const CommandReceiverConfig& config, CanPort& port,
                                           const ClockRateConfig& rate) noexcept
    : receiver_(config, rate), port_(&port) {}

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
