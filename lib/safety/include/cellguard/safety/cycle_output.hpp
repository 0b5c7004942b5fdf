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
#include "cellguard/safety/safety_logic.hpp"
#include "cellguard/safety/zone_evaluation.hpp"

namespace cellguard {

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
