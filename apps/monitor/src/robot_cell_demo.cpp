// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The simulated side of a robot cell (robot_cell_demo.hpp).
#include "cellguard/monitor/robot_cell_demo.hpp"

#include <cstdio>

namespace cellguard::monitor {

CaseCellDemo::CaseCellDemo(std::uint8_t monitoring_case, SimulatedPlcLink& plc) noexcept : plc_(&plc) {
    command_.monitoring_case = monitoring_case;
}

void CaseCellDemo::before_cycle(int /*k*/, double /*t_s*/) noexcept {
    command_.reset_request = operator_.pressed();
    plc_->set_command(command_);
}

void CaseCellDemo::after_cycle(const CycleReport& report) noexcept { operator_.after_cycle(report); }

void CaseCellDemo::describe(const char* scene, char* out, std::size_t capacity) const noexcept {
    static_cast<void>(std::snprintf(out, capacity, "%s%s", scene, command_.reset_request ? " reset" : ""));
}

RobotCellDemo::RobotCellDemo(const cell::MonitorConfig& cfg, MonitorCell& cell, SimulatedPlcLink& plc) noexcept
    : cell_(&cell), plc_(&plc), reduced_class_(cfg.robot.separation.reduced_class) {}

void RobotCellDemo::before_cycle(int /*k*/, double t_s) noexcept {
    if (started_) {
        static_cast<void>(clock_.advance(t_s - last_t_s_, last_request_));
    }
    started_ = true;
    last_t_s_ = t_s;
    cell_->simulation.update(t_s, clock_.time());
    command_ = cell_->simulation.command(cell_->robot.crc);
    if (last_request_ == SpeedRequest::kReduced) {
        command_.speed_class = reduced_class_;  // the robot obeys: it moves at the reduced class
    }
    command_.reset_request = operator_.pressed();
    plc_->set_command(command_);
}

void RobotCellDemo::after_cycle(const CycleReport& report) noexcept {
    last_request_ = report.robot.speed_request;
    operator_.after_cycle(report);
}

void RobotCellDemo::describe(const char* /*scene*/, char* out, std::size_t capacity) const noexcept {
    static_cast<void>(std::snprintf(out, capacity, "robot program %6.2fs cmd case %u class %u%s", clock_.time(),
                                    command_.monitoring_case, command_.speed_class,
                                    command_.reset_request ? " reset" : ""));
}

}  // namespace cellguard::monitor
