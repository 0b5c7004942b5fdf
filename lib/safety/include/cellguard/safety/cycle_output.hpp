// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file cycle_output.hpp
/// What one cycle of the executive produced, and the interface through which
/// it leaves the controller (the CAN output, a log, a test).
#ifndef CELLGUARD_SAFETY_CYCLE_OUTPUT_HPP
#define CELLGUARD_SAFETY_CYCLE_OUTPUT_HPP

#include <cstdint>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/safety/cycle.hpp"
#include "cellguard/safety/robot_command.hpp"
#include "cellguard/safety/safety_logic.hpp"
#include "cellguard/safety/zone_evaluation.hpp"

namespace cellguard {

/// The robot side of one cycle: the monitoring case applied, the command it
/// came from, and speed and separation monitoring's result. Without a robot
/// configured: case 0, no command, speed request kFull, distance "far".
struct RobotReport {
    bool configured = false;            ///< a robot (and its command) is part of this cell
    std::uint8_t active_case = 0U;      ///< monitoring case whose zones this cycle evaluated, 0..15
    bool command_valid = false;         ///< this cycle used a good, timely command that fits the cell
    std::uint8_t command_counter = 0U;  ///< E2E counter of that command (0 when none)
    std::uint64_t command_age_us = 0U;  ///< cycle start minus the command's arrival
    std::uint8_t command_check = 0U;    ///< why the command was refused (JointCheck or a case error), 0 = none
    /// The reset level the command gave the restart interlock: its ResetRequest when it
    /// was used, held high when it was refused or missing (so only a press after a
    /// valid release is an edge); false in a cell that expects no command.
    bool command_reset = false;
    SpeedRequest speed_request = SpeedRequest::kFull;  ///< speed and separation monitoring's request
    std::uint16_t distance_mm = 65535U;                ///< separation distance (65535: nothing within range)
    std::uint16_t required_mm = 0U;   ///< protective separation distance S_p of the current speed class
    std::uint32_t robot_voxels = 0U;  ///< voxels marked as the robot's
};

/// Everything one cycle produced.
struct CycleReport {
    std::uint64_t cycle = 0U;            ///< cycle number, from 1
    std::uint64_t started_us = 0U;       ///< clock at the cycle's start
    SafetyOutputs safety{};              ///< stop, warning, latched faults, zone bits
    ZoneEvaluation zones{};              ///< per-zone counts and states (before fault override)
    FusionStats fusion{};                ///< fusion counts of all sensors
    std::uint32_t detected_faults = 0U;  ///< faults detected in this cycle
    CycleTiming timing{};  ///< the previous cycle's stage timing (this one is still running when published)
    CycleTiming worst{};   ///< the worst stage timing so far
    RobotReport robot{};   ///< monitoring case, command and separation of this cycle
};

/// Where a cycle's result goes (the CAN port, a log, a test).
class CycleOutput {
public:
    /// Sends @p report; returns false when sending failed (a CAN error).
    virtual bool publish(const CycleReport& report) noexcept = 0;

protected:
    CycleOutput() = default;
    ~CycleOutput() = default;
    CycleOutput(const CycleOutput&) = default;
    CycleOutput& operator=(const CycleOutput&) = default;
    CycleOutput(CycleOutput&&) = default;
    CycleOutput& operator=(CycleOutput&&) = default;
};

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_CYCLE_OUTPUT_HPP
