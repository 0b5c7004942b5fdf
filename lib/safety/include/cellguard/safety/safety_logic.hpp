// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file safety_logic.hpp
/// The safety logic: from zone states and detected faults to the protective
/// stop request, the warning, and the latched fault code, with a restart
/// interlock.
///
/// Rules (each is tested in test_safety_logic.cpp):
/// - The safe state is "protective stop requested". It holds at start-up
///   until the restart interlock releases it for the first time.
/// - A protective stop is requested in the same cycle in which any
///   protective zone is not CLEAR or any fault is latched.
/// - A warning is signalled while any warning zone is not CLEAR (no interlock).
/// - Restart interlock: once every protective zone is CLEAR and no fault is
///   latched, the stop is held until that has lasted restart_delay_us
///   without interruption, and, if reset_required, until a rising edge of the
///   reset input arrives after that time.
/// - Faults latch. A recoverable fault (sensor stale or missing, inconsistent
///   frame, cycle overrun, CAN error, zone evaluation error) clears after
///   fault_recovery_cycles consecutive cycles in which it is not detected;
///   then the restart interlock applies as above. A non-recoverable fault
///   (prior check failed, internal check failed, clock fault) stays latched
///   until the logic is re-initialised (a restart of the controller).
/// - The clock must advance: a cycle whose time is not later than the
///   previous cycle's latches a clock fault.
/// - Monitoring cases: only the zones of the active case (active_zones)
///   count; the other zones' bits are 0 in every output mask, and they
///   neither stop nor warn.
/// - Speed and separation monitoring (separation.hpp): a kProtectiveStop
///   request stops in the same cycle, but not through the restart
///   interlock: the stop ends in the first cycle whose request is not
///   kProtectiveStop (unless zones or faults hold it). This is the automatic
///   resumption of ISO/TS 15066 5.5.4 and ISO 10218-2: the person stays
///   detected while near the robot (unseen space counts as near), so the
///   stop's cause is observed going away, whereas the restart interlock
///   guards zones a person may have entered and then be hidden in. Faults
///   (a missing command, a separation that could not be computed) are
///   latched and go through the interlock as before. Any request other than
///   kFull sets reduced_speed (a stop also asks for at most reduced speed);
///   any value outside the enumeration counts as kProtectiveStop.
/// - Its own state is sealed (state_seal.hpp, hazard H-MEM-3): the latches,
///   the recovery counters, the interlock's timer and flags, the clock
///   reference and its copy of the configuration are CRC'd at the end of
///   each step and compared at the start of the next; a mismatch latches
///   kInternalCheck (non-recoverable) in that step, which then requests the
///   stop without reading its zones or configuration (every active zone FAULT).
#ifndef CELLGUARD_SAFETY_LOGIC_HPP
#define CELLGUARD_SAFETY_LOGIC_HPP

#include <cstdint>

#include "cellguard/base/state_seal.hpp"
#include "cellguard/safety/faults.hpp"
#include "cellguard/safety/robot_command.hpp"
#include "cellguard/safety/zone_evaluation.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard {

/// Configuration of the safety logic.
struct SafetyLogicConfig {
    std::uint64_t restart_delay_us = 1000000U;  ///< protective zones CLEAR this long before the stop is released
    /// Also wait for a rising edge of the reset input (default: on; a caller
    /// without a reset input turns it off only where the PLC holds the
    /// restart interlock, safety manual section 3).
    bool reset_required = true;
    std::uint32_t fault_recovery_cycles = 10U;  ///< fault-free cycles before a recoverable fault clears (>= 1)
};

/// Inputs of one cycle.
struct SafetyInputs {
    std::uint64_t now_us = 0U;              ///< monotonic time of this cycle, microseconds
    const ZoneEvaluation* zones = nullptr;  ///< this cycle's zone results (nullptr: not available -> fault)
    std::uint32_t detected_faults = 0U;     ///< fault bits detected this cycle
    bool reset_input = false;               ///< level of the reset input
    /// Zones of the active monitoring case (bit z: zone z); default all.
    std::uint32_t active_zones = 0xFFFFFFFFU;
    /// Speed and separation monitoring's request (kFull: none, or no robot).
    SpeedRequest speed_request = SpeedRequest::kFull;
};

/// Outputs of one cycle.
struct SafetyOutputs {
    bool stop_requested = true;          ///< protective stop requested (the safe state)
    bool warning = false;                ///< a warning zone is not CLEAR
    bool interlock_holding = true;       ///< the stop is held only by the restart interlock
    bool separation_stop = false;        ///< speed and separation monitoring requests the stop
    bool reduced_speed = false;          ///< speed and separation monitoring requests reduced speed (or a stop)
    std::uint32_t latched_faults = 0U;   ///< fault bits latched now
    std::uint32_t intruded_mask = 0U;    ///< active zones INTRUDED (all zones FAULT while a fault is latched: 0 here)
    std::uint32_t unseen_mask = 0U;      ///< active zones UNSEEN
    std::uint32_t fault_zone_mask = 0U;  ///< active zones in FAULT (all active ones, while a fault is latched)
};

/// The safety logic's state machine; one step() per cycle.
class SafetyLogic {
public:
    /// Starts in the safe state. @p zones gives each zone's kind; it must
    /// outlive the logic. Invalid config (fault_recovery_cycles of 0) is a
    /// contract violation: configuration is checked when it is loaded.
    SafetyLogic(const SafetyLogicConfig& config, const CompiledZones& zones) noexcept;

    /// Advances one cycle.
    SafetyOutputs step(const SafetyInputs& in) noexcept;

    /// The last outputs.
    [[nodiscard]] const SafetyOutputs& outputs() const noexcept { return out_; }

    /// CRC-32 of the sealed fields as they are now (see the file comment;
    /// public for the benchmark of its cost).
    [[nodiscard]] std::uint32_t state_crc() const noexcept;

private:
    friend struct SafetyLogicTestAccess;  ///< tests corrupt the sealed fields (tests/support)

    std::uint32_t latch_faults(const SafetyInputs& in) noexcept;
    void step_interlock(bool protective_clear, bool reset_input, std::uint64_t now_us, SafetyOutputs& out) noexcept;

    SafetyLogicConfig config_;
    const CompiledZones* zones_;
    SafetyOutputs out_{};
    std::uint32_t latched_ = 0U;
    std::uint32_t clean_cycles_[kFaultCount] = {};
    bool have_time_ = false;
    std::uint64_t last_now_us_ = 0U;
    bool zone_stop_ = true;  ///< the stop of zones and faults, through the restart interlock
    bool clear_running_ = false;
    std::uint64_t clear_since_us_ = 0U;
    bool last_reset_ = false;
    bool state_failed_ = false;  ///< the seal failed once: every later step is the stop (latched)
    StateSeal seal_{};           ///< state_crc() at the end of the last step (or construction)
};

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_LOGIC_HPP
