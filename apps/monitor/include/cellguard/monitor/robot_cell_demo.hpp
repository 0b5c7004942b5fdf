// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_cell_demo.hpp
/// The simulated side of a robot cell (`--demo robot-cell`, or any
/// configuration with a demo.scene): before each cycle it moves the
/// simulation (people on the run's time, the robot along its trajectory on
/// the robot program's time) and gives the simulated PLC the command of that
/// moment; after it, the robot obeys the cycle's speed request (a
/// TrajectoryClock: full rate, the reduced rate, or standing still), and the
/// PLC reports the reduced speed class while the robot moves at it. The
/// cell's operator is simulated too: while the controller's restart
/// interlock holds the stop (zones clear, waiting for the delay or a
/// reset), the PLC's reset button is pressed for one sample and released
/// for the next, so each press is a rising edge of ResetRequest. A cell with
/// monitoring cases and no robot gets the same PLC and operator without the
/// robot (CaseCellDemo). Nothing allocates per cycle.
#ifndef CELLGUARD_MONITOR_ROBOT_CELL_DEMO_HPP
#define CELLGUARD_MONITOR_ROBOT_CELL_DEMO_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/sim/trajectory.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/safety/cycle_output.hpp"

namespace cellguard::monitor {

/// What the monitor's loop calls around each cycle (the robot-cell demo, a test).
class CycleHook {
public:
    /// Before cycle @p k, whose frames are taken at run time @p t_s seconds.
    virtual void before_cycle(int k, double t_s) noexcept = 0;
    /// After the cycle, with its report.
    virtual void after_cycle(const CycleReport& report) noexcept = 0;
    /// The hook's part of the status line (at most @p capacity - 1 characters),
    /// given the loop's own text of the scene (@p scene: the scripted person,
    /// live cameras or recorded frames), which it may keep or replace.
    virtual void describe(const char* scene, char* out, std::size_t capacity) const noexcept = 0;

protected:
    CycleHook() = default;
    ~CycleHook() = default;
    CycleHook(const CycleHook&) = default;
    CycleHook& operator=(const CycleHook&) = default;
    CycleHook(CycleHook&&) = default;
    CycleHook& operator=(CycleHook&&) = default;
};

/// The simulated operator at the PLC's reset button: pressed for one sample
/// and released for the next while the controller's restart interlock holds
/// the stop, so each press is a rising edge after a valid release.
class ResetOperator {
public:
    /// The level the next sample carries.
    [[nodiscard]] bool pressed() const noexcept { return pressed_; }
    /// Takes the cycle's report: press or release for the next sample.
    void after_cycle(const CycleReport& report) noexcept { pressed_ = report.safety.interlock_holding && !pressed_; }

private:
    bool pressed_ = false;
};

/// The simulated PLC of a cell with monitoring cases and no robot (for
/// example `real-cell.toml`): every sample selects one case, carries no
/// joints, and the operator presses reset as in the robot demo. It is what
/// lets such a cell keep `reset_required` on when no PLC is connected.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class CaseCellDemo final : public CycleHook {
public:
    /// Commands @p monitoring_case through @p plc, which must outlive it.
    CaseCellDemo(std::uint8_t monitoring_case, SimulatedPlcLink& plc) noexcept;
    void before_cycle(int k, double t_s) noexcept override;
    void after_cycle(const CycleReport& report) noexcept override;
    void describe(const char* scene, char* out, std::size_t capacity) const noexcept override;

    /// The last command the simulated PLC sent.
    [[nodiscard]] const RobotCommand& command() const noexcept { return command_; }

private:
    SimulatedPlcLink* plc_;
    ResetOperator operator_;
    RobotCommand command_{};
};

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class RobotCellDemo final : public CycleHook {
public:
    /// The demo of @p cell (configured with a scene and a robot) under
    /// @p cfg, commanding through @p plc. All must outlive it.
    RobotCellDemo(const cell::MonitorConfig& cfg, MonitorCell& cell, SimulatedPlcLink& plc) noexcept;
    void before_cycle(int k, double t_s) noexcept override;
    void after_cycle(const CycleReport& report) noexcept override;
    void describe(const char* scene, char* out, std::size_t capacity) const noexcept override;

    /// The robot program's time (trajectory time) of the last cycle, seconds.
    [[nodiscard]] double trajectory_time() const noexcept { return clock_.time(); }
    /// The last command the simulated PLC sent.
    [[nodiscard]] const RobotCommand& command() const noexcept { return command_; }

private:
    MonitorCell* cell_;
    SimulatedPlcLink* plc_;
    std::uint8_t reduced_class_;
    sim::TrajectoryClock clock_;
    double last_t_s_ = 0.0;
    bool started_ = false;
    SpeedRequest last_request_ = SpeedRequest::kFull;
    ResetOperator operator_;  ///< the simulated operator at the PLC's reset button
    RobotCommand command_{};
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_ROBOT_CELL_DEMO_HPP
