// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/safety_controller.hpp"

namespace cellguard {

SafetyController::SafetyController(const ControllerConfig& config, EvidenceGrid& frame_grid,
                                   Span<std::int16_t> fusion_scratch, Span<const std::int16_t> prior,
                                   const CompiledZones& zones, const SensorModelTable& model, MonotonicClock& clock,
                                   CycleOutput* output) noexcept
    : config_(config),
      grid_(&frame_grid),
      scratch_(fusion_scratch),
      prior_(prior),
      zones_(&zones),
      model_(&model),
      clock_(&clock),
      output_(output),
      logic_(config.logic, zones),
      monitor_(config.cycle_budget_us),
      prior_check_(as_bytes(prior)),
      zone_mask_check_(as_bytes(zones.membership())),
      zone_settings_crc_(zones.settings_crc()) {
    CG_ENFORCE(config.prior_check_slice_bytes > 0U, "prior_check_slice_bytes must be positive");
    CG_ENFORCE(config.table_check_slice_bytes > 0U, "table_check_slice_bytes must be positive");
    CG_ENFORCE(config.zone_check_slice_bytes > 0U, "zone_check_slice_bytes must be positive");
    if (prior.size() != frame_grid.voxel_count()) {
        construction_faults_ |= fault_bit(Fault::kPriorCheckFailed);
    }
    if (!(zones.geometry() == frame_grid.geometry()) || config.sensor_count == 0U ||
        config.sensor_count > kMaxSensors) {
        construction_faults_ |= fault_bit(Fault::kInternalCheck);
    }
}

bool SafetyController::step_zone_checks() noexcept {
    // The settings every cycle (a few hundred bytes); the mask in slices.
    zone_settings_failed_ = zone_settings_failed_ || zones_->settings_crc() != zone_settings_crc_;
    const bool mask_failed = zone_mask_check_.step(config_.zone_check_slice_bytes);
    return zone_settings_failed_ || mask_failed;
}

bool SafetyController::step_table_check(Span<const SensorInput> sensors) noexcept {
    // One sensor's table per cycle, the sensors in turn; a sensor without a
    // table (or without a frame this cycle) passes its turn.
    if (table_check_sensor_ >= sensors.size() || table_check_sensor_ >= kMaxSensors) {
        table_check_sensor_ = 0U;
    }
    if (table_check_sensor_ < sensors.size()) {
        const std::size_t slot = table_check_sensor_;  // < kMaxSensors: reset above
        ++table_check_sensor_;
        const RayTable* table = sensors[slot].table;
        if (table != nullptr && step_one_table(table_checks_[slot], *table, config_.table_check_slice_bytes)) {
            table_failed_ = true;
        }
    }
    return table_failed_;
}

bool SafetyController::step_one_table(TableCheck& slot, const RayTable& table, std::size_t slice_bytes) noexcept {
    // The table's regions and limits as they are now: a check that no longer
    // reads them, or limits that no longer match the words the regions hold,
    // mean the table object itself changed.
    const RayTableSignatureRegions regions = table.signature_regions();
    const Span<const SignatureRegion> now(regions.data(), regions.size());
    if (slot.table != &table) {
        slot = TableCheck{&table, SignatureCheck(now, table.storage_crc())};
    }
    const bool slice_failed = slot.check.step(slice_bytes);
    return slice_failed || !slot.check.reads(now) || !table.limits_intact();
}

bool SafetyController::frame_is_frozen(std::size_t slot, const SensorInput& input) noexcept {
    if (config_.max_repeated_frames == 0U || slot >= kMaxSensors) {
        return false;
    }
    FrameHistory& h = frame_history_[slot];
    const std::uint64_t fingerprint = reading_fingerprint(input.reading);
    // The same frame delivered again (same time stamp) is not a new frame:
    // the age limit covers it.
    if (h.seen && input.captured_us != h.captured_us) {
        const bool same = fingerprint == h.fingerprint;
        h.repeats = !same ? 0U : (h.repeats == UINT32_MAX ? h.repeats : h.repeats + 1U);
    }
    h.seen = true;
    h.captured_us = input.captured_us;
    h.fingerprint = fingerprint;
    return h.repeats >= config_.max_repeated_frames;
}

bool SafetyController::shows_background(const SensorInput& input) noexcept {
    if (input.background == nullptr) {
        return true;
    }
    if (input.reading.kind != SensorDataKind::kDepthImage) {
        return false;  // a reference is a depth image: a point set cannot show it
    }
    const Result<BackgroundMatch> m = match_background(input.reading.depth, *input.background);
    return m.ok() && background_seen(m.value(), input.background->min_match_fraction);
}

std::uint32_t SafetyController::fuse_sensors(Span<const SensorInput> sensors, std::uint64_t now,
                                             FusionStats& stats) noexcept {
    std::uint32_t faults = 0U;
    if (sensors.size() != config_.sensor_count) {
        faults |= fault_bit(Fault::kSensorMissing);
    }
    for (std::size_t slot = 0U; slot < sensors.size(); ++slot) {
        const SensorInput& s = sensors[slot];
        if (!s.present) {
            faults |= fault_bit(Fault::kSensorMissing);
            continue;
        }
        if (s.captured_us > now || now - s.captured_us > config_.max_frame_age_us || frame_is_frozen(slot, s)) {
            faults |= fault_bit(Fault::kSensorStale);
            continue;
        }
        if (!shows_background(s)) {
            faults |= fault_bit(Fault::kFrameInconsistent);
            continue;
        }
        const Result<FusionStats> r = (s.table != nullptr && s.reading.kind == SensorDataKind::kDepthImage)
                                          ? s.table->fuse(*grid_, s.reading.depth, *model_)
                                          : fuse_sensor(*grid_, s.reading, *model_, scratch_, config_.rasterization);
        if (!r.ok()) {
            faults |= fault_bit(Fault::kFrameInconsistent);
            continue;
        }
        stats.add(r.value());
    }
    return faults;
}

const CycleReport& SafetyController::run_cycle(Span<const SensorInput> sensors, bool reset_input) noexcept {
    const std::uint64_t start = clock_->now_us();
    monitor_.begin(start);
    CycleReport r;
    r.cycle = report_.cycle + 1U;
    r.started_us = start;
    std::uint32_t detected = pending_faults_ | construction_faults_;
    pending_faults_ = 0U;

    grid_->clear();
    detected |= fuse_sensors(sensors, start, r.fusion);
    monitor_.end_stage(CycleStage::kFuse, clock_->now_us());

    const bool zones_ok = (construction_faults_ == 0U) &&
                          evaluate_zones(*grid_, prior_, *zones_, config_.zones, r.zones).ok();
    if (!zones_ok) {
        detected |= fault_bit(Fault::kZoneEvaluation);
    }
    if (prior_check_.step(config_.prior_check_slice_bytes)) {
        detected |= fault_bit(Fault::kPriorCheckFailed);
    }
    const bool table_failed = step_table_check(sensors);
    const bool zones_failed = step_zone_checks();  // both every cycle: constant work
    if (table_failed || zones_failed) {
        detected |= fault_bit(Fault::kInternalCheck);
    }
    monitor_.end_stage(CycleStage::kSubtractAndZones, clock_->now_us());

    SafetyInputs in;
    in.now_us = start;
    in.zones = zones_ok ? &r.zones : nullptr;
    in.detected_faults = detected;
    in.reset_input = reset_input;
    r.safety = logic_.step(in);
    r.detected_faults = detected;
    r.timing = monitor_.last();
    r.worst = monitor_.worst();
    monitor_.end_stage(CycleStage::kLogic, clock_->now_us());

    report_ = r;
    if (output_ != nullptr && !output_->publish(report_)) {
        pending_faults_ |= fault_bit(Fault::kCanError);
    }
    monitor_.end_stage(CycleStage::kOutput, clock_->now_us());
    if (monitor_.end(clock_->now_us())) {
        pending_faults_ |= fault_bit(Fault::kCycleOverrun);
    }
    return report_;
}

}  // namespace cellguard
