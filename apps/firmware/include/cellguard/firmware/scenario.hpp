// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file scenario.hpp
/// The firmware's canned run, the same code on every target: the prior
/// image (generated/prior.cgprior, embedded in read-only data: flash on the
/// MCU) is checked with load_prior_image and its payload bound in place,
/// two zones are compiled, and the SafetyController runs a fixed script of
/// cycles on canned depth frames (generated/frames.bin, checked with
/// CannedFrames::parse; both files rendered on the host by
/// cellguard-firmware-gen). Every cycle's results are folded into a CRC-32
/// digest, so that the x86-64, aarch64 and Cortex-M7 builds can be
/// compared bit for bit.
///
/// What the digest covers, per cycle in order: the cycle number; the fused
/// frame grid (every log-odds value and observed flag); the fusion counts;
/// each zone's state and foreground and unseen counts; the detected faults;
/// the safety outputs; every CAN frame sent (ID, DLC, data). Timing is
/// measured, not computed, so it is left out: the report's timing fields
/// and, in the diagnostics frame, the E2E CRC byte and the CycleTime and
/// MaxCycleTime bits (32..53) are not digested.
#ifndef CELLGUARD_FIRMWARE_SCENARIO_HPP
#define CELLGUARD_FIRMWARE_SCENARIO_HPP

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/can/safety_output.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::firmware {

/// Where the run's text lines go (semihosting on the board, stdout on a host).
class TextSink {
public:
    /// Writes @p text (NUL-terminated, no newline added).
    virtual void write(const char* text) noexcept = 0;

protected:
    TextSink() = default;
    ~TextSink() = default;
    TextSink(const TextSink&) = default;
    TextSink& operator=(const TextSink&) = default;
    TextSink(TextSink&&) = default;
    TextSink& operator=(TextSink&&) = default;
};

/// Outcome of run_scenario.
struct ScenarioSummary {
    bool setup_ok = false;         ///< prior, zones and CAN output were accepted
    std::uint32_t cycles = 0U;     ///< cycles run
    std::uint32_t digest = 0U;     ///< CRC-32 over every cycle's digested content
    std::uint32_t prior_crc = 0U;  ///< SafetyController::prior_crc
    /// Cycle timing from the controller's monitor (measured, not digested;
    /// filled by run_scenario and run_footprint_scenario only).
    std::uint64_t cycle_us_max = 0U;  ///< longest cycle, us
    std::uint64_t cycle_us_sum = 0U;  ///< all cycles, us
    std::uint64_t fuse_us_max = 0U;   ///< longest fusion stage (CycleStage::kFuse), us
};

/// Number of cycles in the script.
constexpr std::uint32_t kScenarioCycles = 8U;

/// Number of zones the scenario compiles.
constexpr std::size_t kScenarioZones = 2U;

/// The scenario's zones in the paper's cell (paper_grid_geometry(), the
/// simulator's reference scene): zone 0 is protective, on the free floor in
/// front of the first background box (x 0.0 to 0.4 m, y 0.2 to 0.6 m, z up to
/// 1.2 m, at most 20 unseen voxels); zone 1 is a warning zone across it
/// (x -0.8 to 0.8 m, y 0.45 to 0.75 m, z up to 1.2 m, at most 40 unseen
/// voxels). The host tests of the SafetyController use the same two zones.
[[nodiscard]] std::array<ZoneConfig, kScenarioZones> scenario_zone_configs() noexcept;

/// The scenario's controller configuration for @p sensor_count sensors: no
/// restart delay unless set_restart_delay() gave one (the interlock is not
/// under test in the canned run), recovery from a fault
/// after 2 good cycles, and a generous 10 s cycle budget, so that timing
/// cannot change the results. The host tests of the SafetyController start
/// from it.
[[nodiscard]] ControllerConfig scenario_controller_config(std::size_t sensor_count) noexcept;

/// The painted stack every later scenario_controller_config() hands its
/// controller (ControllerConfig::stack); nullptr (the default): none.
void set_stack_check(const StackPaint* paint) noexcept;

/// The restart delay every later scenario_controller_config() gives its
/// controller (ControllerLogicConfig::restart_delay_us; default 0, the
/// canned run's). A delay above 0 makes every start, a watchdog's reset
/// included, begin with the stop requested (SR-LOGIC-001).
void set_restart_delay(std::uint64_t delay_us) noexcept;

/// Runs the script: prints one line per cycle ("cycle N ...") and a last
/// line "digest 0x%08x" to @p text, sends every cycle's CAN frames through
/// @p can. Uses static storage for the grid and the zone mask (not
/// re-entrant). @p clock only times the cycles; results do not depend on it
/// as long as a cycle stays within its (generous, 10 s) budget.
[[nodiscard]] ScenarioSummary run_scenario(MonotonicClock& clock, CanSender& can, TextSink& text) noexcept;

/// Runs the same script with the controller fusing by footprint fusion
/// (ControllerConfig::footprint, FusionMethod::kFootprint, one core): one
/// footprint workspace in static storage (a depth pyramid for the largest
/// canned image, 160 x 120, and the fusion scratch as its opinions; the
/// controller gets no ray scratch). Prints the same lines as run_scenario,
/// each prefixed "footprint ", the last "footprint digest 0x%08x". Uses the
/// same static storage as run_scenario (not re-entrant).
[[nodiscard]] ScenarioSummary run_footprint_scenario(MonotonicClock& clock, CanSender& can, TextSink& text) noexcept;

/// Writes @p value as "0x" and eight lowercase hex digits plus a NUL into @p out.
void format_hex32(std::uint32_t value, char (&out)[11]) noexcept;
/// Writes @p value in decimal plus a NUL into @p out.
void format_decimal(std::uint64_t value, char (&out)[21]) noexcept;

}  // namespace cellguard::firmware

#endif  // CELLGUARD_FIRMWARE_SCENARIO_HPP
