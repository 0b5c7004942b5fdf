// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/safety_logic.hpp"

namespace cellguard {

SafetyLogic::SafetyLogic(const SafetyLogicConfig& config, const CompiledZones& zones) noexcept
    : config_(config), zones_(&zones) {
    CG_ENFORCE(config.fault_recovery_cycles >= 1U, "fault_recovery_cycles must be at least 1");
    seal_.seal(state_crc());
}

std::uint32_t SafetyLogic::state_crc() const noexcept {
    Crc32 crc;
    seal_add(crc, config_.restart_delay_us);
    seal_add(crc, config_.reset_required);
    seal_add(crc, config_.fault_recovery_cycles);
    seal_add(crc, zones_);
    seal_add(crc, latched_);
    for (const std::uint32_t c : clean_cycles_) {
        seal_add(crc, c);
    }
    seal_add(crc, have_time_);
    seal_add(crc, last_now_us_);
    seal_add(crc, zone_stop_);
    seal_add(crc, clear_running_);
    seal_add(crc, clear_since_us_);
    seal_add(crc, last_reset_);
    seal_add(crc, state_failed_);
    return crc.value();
}

std::uint32_t SafetyLogic::latch_faults(const SafetyInputs& in) noexcept {
    std::uint32_t detected = in.detected_faults & kAllFaults;
    if (in.zones == nullptr || in.zones->count != zones_->size()) {
        detected |= fault_bit(Fault::kZoneEvaluation);
    }
    if (have_time_ && in.now_us <= last_now_us_) {
        detected |= fault_bit(Fault::kClockFault);
    }
    // Latch, and count fault-free cycles for the recoverable ones.
    latched_ |= detected;
    for (std::uint8_t f = 0U; f < kFaultCount; ++f) {
        const std::uint32_t bit = 1U << f;
        if ((detected & bit) != 0U) {
            clean_cycles_[f] = 0U;
        } else if ((latched_ & bit) != 0U && (bit & kNonRecoverableFaults) == 0U) {
            if (++clean_cycles_[f] >= config_.fault_recovery_cycles) {
                latched_ &= ~bit;
                clean_cycles_[f] = 0U;
            }
        }
    }
    if (!have_time_ || in.now_us > last_now_us_) {
        last_now_us_ = in.now_us;  // a clock that went back does not move the reference back
    }
    have_time_ = true;
    return latched_;
}

void SafetyLogic::step_interlock(bool protective_clear, bool reset_input, std::uint64_t now_us,
                                 SafetyOutputs& out) noexcept {
    const bool reset_edge = reset_input && !last_reset_;
    last_reset_ = reset_input;
    if (!protective_clear) {
        clear_running_ = false;
        zone_stop_ = true;
        out.interlock_holding = false;
    } else if (!zone_stop_) {
        out.interlock_holding = false;  // already running and still clear
    } else {
        if (!clear_running_) {
            clear_running_ = true;
            clear_since_us_ = now_us;
        }
        const bool delay_over = now_us - clear_since_us_ >= config_.restart_delay_us;
        const bool released = delay_over && (!config_.reset_required || reset_edge);
        zone_stop_ = !released;
        out.interlock_holding = !released;
    }
}

SafetyOutputs SafetyLogic::step(const SafetyInputs& in) noexcept {
    SafetyOutputs out;  // the safe state
    if (state_failed_ || !seal_.matches(state_crc())) {
        // The state or the configuration copy changed since the last step
        // (H-MEM-3): latch kInternalCheck and stop, reading neither the zones'
        // pointer nor the configuration, which may be the corrupted part.
        state_failed_ = true;  // from now on only this path: the state is not trusted again
        latched_ |= fault_bit(Fault::kInternalCheck);
        zone_stop_ = true;
        clear_running_ = false;
        out.latched_faults = latched_;
        out.fault_zone_mask = in.active_zones;
        out.interlock_holding = false;
        out.reduced_speed = true;
        out_ = out;
        seal_.seal(state_crc());
        return out;
    }
    out.latched_faults = latch_faults(in);
    const bool faulted = out.latched_faults != 0U;
    const std::uint32_t active = in.active_zones & all_zone_bits(zones_->size());
    std::uint32_t not_clear = 0U;
    if (faulted || in.zones == nullptr) {
        out.fault_zone_mask = active;
        not_clear = out.fault_zone_mask;
    } else {
        out.intruded_mask = in.zones->intruded_mask & active;
        out.unseen_mask = in.zones->unseen_mask & active;
        not_clear = in.zones->not_clear_mask & active;
    }
    // Which zones are protective, read from the zones every cycle (their
    // settings are CRC-checked every cycle, SR-CTRL-010) rather than kept in
    // a copy of our own; any kind other than kWarning counts as protective.
    std::uint32_t warning_mask = 0U;
    std::uint32_t protective_mask = 0U;
    for (std::size_t z = 0U; z < zones_->size(); ++z) {
        const std::uint32_t bit = 1U << z;
        if (zones_->config(z).kind == ZoneKind::kWarning) {
            warning_mask |= bit;
        } else {
            protective_mask |= bit;
        }
    }
    out.warning = (not_clear & warning_mask) != 0U;
    const bool protective_clear = !faulted && (not_clear & protective_mask) == 0U;
    step_interlock(protective_clear, in.reset_input, in.now_us, out);

    // Speed and separation: outside the interlock; anything but kFull and
    // kReduced (a value outside the enumeration included) is a stop.
    out.separation_stop = in.speed_request != SpeedRequest::kFull && in.speed_request != SpeedRequest::kReduced;
    out.reduced_speed = in.speed_request != SpeedRequest::kFull;
    out.stop_requested = zone_stop_ || out.separation_stop;
    out.interlock_holding = out.interlock_holding && !out.separation_stop;
    out_ = out;
    seal_.seal(state_crc());
    return out;
}

}  // namespace cellguard
