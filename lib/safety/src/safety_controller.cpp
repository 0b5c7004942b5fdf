// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/safety_controller.hpp"

#include <cmath>

#include "cellguard/base/saturating.hpp"
#include "cellguard/robot/robot_mask.hpp"

namespace cellguard {

namespace {

/// The robot model's bytes (empty without a robot).
SignatureRegion robot_bytes(const RobotModel* model) noexcept {
    return model == nullptr ? SignatureRegion{} : as_bytes(Span<const RobotModel>(model, 1U));
}

/// Feeds the bytes of the scalar @p value into @p crc.
template <typename T>
void add_to_crc(Crc32& crc, const T& value) noexcept {
    crc.update(as_bytes(Span<const T>(&value, 1U)));
}

/// The configuration's fields that the robot settings' CRC (checked every
/// cycle on its own) does not cover, field by field (never padding).
void add_config(Crc32& crc, const ControllerConfig& c) noexcept {
    seal_add(crc, c.logic.restart_delay_us);
    seal_add(crc, c.logic.reset_required);
    seal_add(crc, c.logic.fault_recovery_cycles);
    seal_add(crc, c.zones.foreground_threshold);
    seal_add(crc, c.zones.accessible_min_prior);
    const std::uint64_t sizes[] = {c.sensor_count,           c.max_frame_age_us,        c.max_repeated_frames,
                                   c.cycle_budget_us,        c.prior_check_slice_bytes, c.table_check_slice_bytes,
                                   c.zone_check_slice_bytes, c.robot_check_slice_bytes, c.crc_table_check_values};
    for (const std::uint64_t v : sizes) {
        seal_add(crc, v);
    }
    seal_add(crc, c.rasterization);
    seal_add(crc, c.footprint.method);
    seal_add(crc, c.footprint.params.exact_footprint_max);
    seal_add(crc, c.footprint.workspaces.data());
    seal_add(crc, c.footprint.workspaces.size());
    seal_add(crc, c.footprint.runner);
    seal_add(crc, c.cases);
    seal_add(crc, c.stack);
}

/// A signature check's reference, verdict and place in its pass.
void add_check(Crc32& crc, const SignatureCheck& check) noexcept {
    seal_add(crc, check.reference());
    seal_add(crc, check.failed());
    seal_add(crc, check.position());
    seal_add(crc, check.total_bytes());
}

/// Metres to whole millimetres, rounded up (forgiving 1e-6 mm, as
/// separation.cpp does) and saturated at kDistanceFarMm.
std::uint16_t ceil_mm(double metres) noexcept {
    const double mm = std::ceil(metres * 1000.0 - 1e-6);
    if (!(mm >= 0.0)) {
        return 0U;
    }
    return mm >= static_cast<double>(kDistanceFarMm) ? kDistanceFarMm : static_cast<std::uint16_t>(mm);
}

}  // namespace

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
      zone_settings_crc_(zones.settings_crc()),
      cases_(config.cases != nullptr ? *config.cases : MonitoringCases::all_zones(zones)),
      cases_crc_(cases_.settings_crc()),
      command_expected_(config.robot.model != nullptr || config.cases != nullptr),
      robot_check_(robot_bytes(config.robot.model)),
      robot_settings_crc_(robot_settings_crc()) {
    CG_ENFORCE(config.prior_check_slice_bytes > 0U, "prior_check_slice_bytes must be positive");
    CG_ENFORCE(config.table_check_slice_bytes > 0U, "table_check_slice_bytes must be positive");
    CG_ENFORCE(config.zone_check_slice_bytes > 0U, "zone_check_slice_bytes must be positive");
    CG_ENFORCE(config.robot_check_slice_bytes > 0U, "robot_check_slice_bytes must be positive");
    if (prior.size() != frame_grid.voxel_count()) {
        construction_faults_ |= fault_bit(Fault::kPriorCheckFailed);
    }
    if (!(zones.geometry() == frame_grid.geometry()) || config.sensor_count == 0U ||
        config.sensor_count > kMaxSensors) {
        construction_faults_ |= fault_bit(Fault::kInternalCheck);
    }
    CG_ENFORCE(config.crc_table_check_values >= 1U && config.crc_table_check_values <= 256U,
               "crc_table_check_values must be 1 to 256");
    check_robot_config(frame_grid);
    seal_.seal(state_crc());
}

std::uint32_t SafetyController::state_crc() const noexcept {
    Crc32 crc;
    add_config(crc, config_);
    add_state(crc);
    return crc.value();
}

void SafetyController::add_state(Crc32& crc) const noexcept {
    const void* const parts[] = {grid_, scratch_.data(), prior_.data(), zones_, model_, clock_, output_};
    for (const void* p : parts) {
        seal_add(crc, p);
    }
    seal_add(crc, scratch_.size());
    seal_add(crc, prior_.size());
    seal_add(crc, monitor_.budget_us());
    const std::uint32_t words[] = {pending_faults_, construction_faults_, zone_settings_crc_, cases_crc_,
                                   robot_settings_crc_};
    for (const std::uint32_t w : words) {
        seal_add(crc, w);
    }
    add_check(crc, prior_check_);
    add_check(crc, zone_mask_check_);
    add_check(crc, robot_check_);
    for (const TableCheck& t : table_checks_) {
        seal_add(crc, t.table);
        add_check(crc, t.check);
    }
    for (const FrameHistory& h : frame_history_) {
        seal_add(crc, h.seen);
        seal_add(crc, h.captured_us);
        seal_add(crc, h.fingerprint);
        seal_add(crc, h.repeats);
    }
    for (const std::uint32_t run : background_change_.streak) {
        seal_add(crc, run);
    }
    seal_add(crc, background_change_.latched);  // the changed-background latch
    const bool flags[] = {zone_settings_failed_, table_failed_, command_expected_, crc_table_check_.failed(),
                          memory_failed_};
    for (const bool f : flags) {
        seal_add(crc, f);
    }
    seal_add(crc, table_check_sensor_);
    seal_add(crc, active_case_);
    seal_add(crc, speed_class_);
    seal_add(crc, crc_table_check_.position());
    seal_add(crc, crc_table_check_.table());
}

void SafetyController::check_robot_config(const EvidenceGrid& frame_grid) noexcept {
    if (!cases_.fits(*zones_)) {
        construction_faults_ |= fault_bit(Fault::kInternalCheck);
    }
    const RobotCellConfig& robot = config_.robot;
    if (robot.model == nullptr) {
        return;
    }
    if (check_robot_model(*robot.model).code != ErrorCode::kOk || robot.mask.size() < frame_grid.voxel_count() ||
        !std::isfinite(robot.mask_margin_m) || robot.mask_margin_m < 0.0 ||
        !check_separation_params(robot.separation).ok()) {
        construction_faults_ |= fault_bit(Fault::kInternalCheck);
    }
}

std::uint32_t SafetyController::robot_settings_crc() const noexcept {
    // What the robot side reads of the configuration every cycle, field by
    // field (never padding: a copy of the controller need not keep it).
    const RobotCellConfig& r = config_.robot;
    const SeparationParams& p = r.separation;
    Crc32 crc;
    add_to_crc(crc, reinterpret_cast<std::uintptr_t>(
                        r.model));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): the address is the setting
    add_to_crc(crc, r.image_crc);
    add_to_crc(crc, r.mask_margin_m);
    add_to_crc(crc, reinterpret_cast<std::uintptr_t>(
                        r.mask.data()));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): as above
    add_to_crc(crc, r.mask.size());
    add_to_crc(crc, config_.max_command_age_us);
    const double reals[] = {p.human_speed_mps,      p.reaction_time_s,       p.slowdown_time_s,
                            p.intrusion_distance_m, p.sensing_uncertainty_m, p.robot_uncertainty_m};
    for (const double v : reals) {
        add_to_crc(crc, v);
    }
    for (const SpeedClassLimits& c : p.classes) {
        add_to_crc(crc, c.robot_speed_mps);
        add_to_crc(crc, c.stopping_time_s);
        add_to_crc(crc, c.stopping_distance_m);
    }
    add_to_crc(crc, p.class_count);
    add_to_crc(crc, p.reduced_class);
    add_to_crc(crc, p.min_foreground_voxels);
    add_to_crc(crc, p.min_hidden_voxels);
    return crc.value();
}

bool SafetyController::step_zone_checks() noexcept {
    // The settings every cycle (a few hundred bytes); the mask in slices.
    zone_settings_failed_ = zone_settings_failed_ || zones_->settings_crc() != zone_settings_crc_;
    zone_settings_failed_ = zone_settings_failed_ || cases_.settings_crc() != cases_crc_ ||
                            robot_settings_crc() != robot_settings_crc_;
    const bool mask_failed = zone_mask_check_.step(config_.zone_check_slice_bytes);
    return zone_settings_failed_ || mask_failed;
}

std::uint32_t SafetyController::step_integrity_checks(Span<const SensorInput> sensors) noexcept {
    std::uint32_t faults = 0U;
    if (prior_check_.step(config_.prior_check_slice_bytes)) {
        faults |= fault_bit(Fault::kPriorCheckFailed);
    }
    // All of them every cycle: constant work.
    const bool table_failed = step_table_check(sensors);
    const bool zones_failed = step_zone_checks();
    const bool robot_failed = robot_check_.step(config_.robot_check_slice_bytes);
    const bool crc_tables_failed = crc_table_check_.step(config_.crc_table_check_values);
    const bool stack_failed = config_.stack != nullptr && !config_.stack->guard_intact();
    if (crc_tables_failed || stack_failed) {
        memory_failed_ = true;  // latched: only a new controller clears it (the caller skips these checks once set)
    }
    if (table_failed || zones_failed || robot_failed || memory_failed_) {
        faults |= fault_bit(Fault::kInternalCheck);
    }
    return faults;
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
    const std::uint64_t fingerprint = reading_fingerprint(input.delivered != nullptr ? *input.delivered
                                                                                     : input.reading);
    // The same frame delivered again (same time stamp) is not a new frame:
    // the age limit covers it.
    if (h.seen && input.captured_us != h.captured_us) {
        const bool same = fingerprint == h.fingerprint;
        h.repeats = same ? saturating_increment(h.repeats) : 0U;
    }
    h.seen = true;
    h.captured_us = input.captured_us;
    h.fingerprint = fingerprint;
    return h.repeats >= config_.max_repeated_frames;
}

bool SafetyController::shows_background(std::size_t slot, const SensorInput& input) noexcept {
    if (input.background == nullptr) {
        return true;
    }
    // A point set is compared per direction bin (match_points); a reading
    // of another kind than its reference's is an error: refused.
    const Result<BackgroundMatch> m = match_background(input.reading, *input.background);
    if (!m.ok()) {
        return false;
    }
    background_change_.track(slot, m.value(), *input.background);
    return background_seen(m.value(), input.background->min_match_fraction);
}

bool SafetyController::accept_frame(std::size_t slot, const SensorInput& s, std::uint64_t now,
                                    std::uint32_t& faults) noexcept {
    if (!s.present) {
        faults |= fault_bit(Fault::kSensorMissing);
        return false;
    }
    if (s.captured_us > now || now - s.captured_us > config_.max_frame_age_us || frame_is_frozen(slot, s)) {
        faults |= fault_bit(Fault::kSensorStale);
        return false;
    }
    if (!shows_background(slot, s)) {
        faults |= fault_bit(Fault::kFrameInconsistent);
        return false;
    }
    return true;
}

std::uint32_t SafetyController::fuse_sensors(Span<const SensorInput> sensors, std::uint64_t now,
                                             FusionStats& stats) noexcept {
    std::uint32_t faults = 0U;
    if (sensors.size() != config_.sensor_count) {
        faults |= fault_bit(Fault::kSensorMissing);
    }
    const bool footprint = config_.footprint.method == FusionMethod::kFootprint;
    std::array<SensorReading, kMaxSensors> images{};
    // With a workspace per sensor, each image keeps its slot's workspace (and footprint table),
    // whichever slots before it were refused this cycle: else a stale camera would hand the next
    // camera's image to its own table, which would then be made again for that camera (and again
    // when the camera comes back), each time a whole table's work inside the cycle.
    const Span<const FootprintWorkspace> all_spaces = config_.footprint.workspaces;
    const bool own_spaces = all_spaces.size() >= sensors.size();
    std::array<FootprintWorkspace, kMaxSensors> spaces{};
    std::size_t image_count = 0U;
    for (std::size_t slot = 0U; slot < sensors.size(); ++slot) {
        const SensorInput& s = sensors[slot];
        if (!accept_frame(slot, s, now, faults)) {
            continue;
        }
        if (footprint && is_depth_image(s.reading.kind) && image_count < images.size()) {
            if (own_spaces) {
                spaces[image_count] = all_spaces[slot];
            }
            images[image_count++] = s.reading;  // fused together below
            continue;
        }
        const Result<FusionStats> r = (s.table != nullptr && is_depth_image(s.reading.kind))
                                          ? s.table->fuse(*grid_, s.reading, *model_)
                                          : fuse_sensor(*grid_, s.reading, *model_, scratch_, config_.rasterization);
        if (!r.ok()) {
            faults |= fault_bit(Fault::kFrameInconsistent);
            continue;
        }
        stats.add(r.value());
    }
    if (image_count > 0U) {
        TaskRunner* runner = config_.footprint.runner;
        if (runner == nullptr) {
            runner = &sequential_;  // one core, the reference
        }
        const Span<const FootprintWorkspace> image_spaces = own_spaces ? Span<const FootprintWorkspace>(spaces.data(),
                                                                                                        image_count)
                                                                       : all_spaces;
        const Result<FusionStats> r = fuse_frame_footprint(
            *grid_, Span<const SensorReading>(images.data(), image_count), *model_, image_spaces, *runner, nullptr,
            config_.footprint.params);
        if (!r.ok()) {
            faults |= fault_bit(Fault::kFrameInconsistent);  // none of them fused: the grid is untouched
        } else {
            stats.add(r.value());
        }
    }
    if (background_change_.latched != 0U) {
        faults |= fault_bit(Fault::kPriorCheckFailed);  // a changed background: the prior no longer fits
    }
    return faults;
}

Span<const std::uint8_t> SafetyController::apply_command(const CommandInput& command, std::uint64_t now,
                                                         RobotReport& report, std::uint32_t& detected) noexcept {
    report = RobotReport{};
    report.configured = config_.robot.model != nullptr;
    report.active_case = active_case_;
    if (!command_expected_) {
        return {};
    }
    if (command.valid) {
        report.command_counter = command.counter;
        report.command_age_us = now >= command.received_us ? now - command.received_us : 0U;
    }
    CommandLimits limits;
    limits.cases = &cases_;
    limits.robot = config_.robot.model;
    limits.image_crc = config_.robot.image_crc;
    limits.speed_classes = config_.robot.separation.class_count;
    limits.max_age_us = config_.max_command_age_us;
    const Result<CheckedCommand, CommandRefusal> checked = check_command(command, now, limits);
    if (!checked.ok()) {
        // No pose this cycle, not even the last good one: no robot mask. The reset level is
        // held high: a press counts only after a valid sample has shown the button released.
        detected |= fault_bit(Fault::kCommandInvalid);
        report.command_check = static_cast<std::uint8_t>(checked.error());
        report.command_reset = true;
        return {};
    }
    report.command_reset = command.command.reset_request;
    active_case_ = checked.value().monitoring_case;
    speed_class_ = checked.value().speed_class;
    report.active_case = active_case_;
    report.command_valid = true;
    if (config_.robot.model == nullptr) {
        return {};
    }
    return mask_robot(checked.value().joints, report, detected);
}

Span<const std::uint8_t> SafetyController::mask_robot(const JointPositions& joints, RobotReport& report,
                                                      std::uint32_t& detected) noexcept {
    if (construction_faults_ != 0U) {
        return {};  // a model or mask storage refused at construction is not used
    }
    place_robot(*config_.robot.model, joints, pose_);
    RobotMaskStats stats;
    const Span<std::uint8_t> mask = config_.robot.mask.subspan(0U, grid_->voxel_count());
    if (!mark_robot_voxels(grid_->geometry(), pose_, config_.robot.mask_margin_m, mask, stats).ok()) {
        detected |= fault_bit(Fault::kZoneEvaluation);
        return {};
    }
    report.robot_voxels = stats.marked;
    return {mask.data(), mask.size()};
}

SpeedRequest SafetyController::separate(Span<const std::uint8_t> robot_mask, std::uint32_t active_zones,
                                        RobotReport& report, std::uint32_t& detected) noexcept {
    if (config_.robot.model == nullptr) {
        return SpeedRequest::kFull;  // the report keeps its defaults: far, nothing required
    }
    const SeparationParams& params = config_.robot.separation;
    report.speed_request = SpeedRequest::kProtectiveStop;
    report.distance_mm = 0U;                                                // not measured: taken as touching
    if (params.class_count >= 1U && params.class_count <= kSpeedClasses) {  // else refused at construction
        report.required_mm = ceil_mm(protective_separation_distance(params, 0U));
    }
    if (robot_mask.empty()) {
        return SpeedRequest::kProtectiveStop;  // no pose this cycle
    }
    SeparationInputs in;
    in.frame_log_odds = Span<const std::int16_t>(grid_->log_odds().data(), grid_->voxel_count());
    in.observed = Span<const std::uint8_t>(grid_->observed().data(), grid_->voxel_count());
    in.prior = prior_;
    in.robot_mask = robot_mask;
    in.zone_membership = zones_->membership();
    in.active_zones = active_zones;
    in.foreground_threshold = config_.zones.foreground_threshold;
    in.accessible_min_prior = config_.zones.accessible_min_prior;
    SeparationResult result;
    if (!compute_separation(grid_->geometry(), in, pose_, params, speed_class_, result).ok()) {
        detected |= fault_bit(Fault::kZoneEvaluation);
        return SpeedRequest::kProtectiveStop;
    }
    report.speed_request = result.request;
    report.distance_mm = result.distance_mm;
    report.required_mm = result.required_mm;
    return result.request;
}

void SafetyController::report_faults(std::uint32_t faults) noexcept {
    const std::uint32_t add = faults & kAllFaults;
    if (add == 0U) {
        return;
    }
    const bool intact = seal_.matches(state_crc());
    pending_faults_ |= add;
    if (intact) {
        seal_.seal(state_crc());
    }
}

const CycleReport& SafetyController::run_cycle(Span<const SensorInput> sensors, bool reset_input) noexcept {
    return run_cycle(sensors, reset_input, CommandInput{});
}

const CycleReport& SafetyController::run_cycle(Span<const SensorInput> sensors, bool reset_input,
                                               const CommandInput& command) noexcept {
    // The state and the configuration copy as the last cycle left them
    // (H-MEM-3), before any of it is used. Once memory has failed, the cycle
    // only sends the stop: no stage reads a pointer or a setting that may be
    // corrupt (the clock and the output still are called, to send it).
    memory_failed_ = memory_failed_ || !seal_.matches(state_crc());
    const std::uint64_t start = clock_->now_us();
    monitor_.begin(start);
    CycleReport r;
    r.cycle = report_.cycle + 1U;
    r.started_us = start;
    std::uint32_t detected = pending_faults_ | construction_faults_;
    pending_faults_ = 0U;
    const bool work = !memory_failed_;
    if (work) {
        grid_->clear();
        detected |= fuse_sensors(sensors, start, r.fusion);
    }
    monitor_.end_stage(CycleStage::kFuse, clock_->now_us());

    ZoneEvaluationScope scope;
    bool zones_ok = false;
    SpeedRequest speed = SpeedRequest::kProtectiveStop;
    if (work) {
        scope.robot_mask = apply_command(command, start, r.robot, detected);
        scope.active_zones = cases_.contains(active_case_) ? cases_.zones_of(active_case_) : 0U;
        zones_ok = (construction_faults_ == 0U) &&
                   evaluate_zones(*grid_, prior_, *zones_, config_.zones, scope, r.zones).ok();
        speed = separate(scope.robot_mask, scope.active_zones, r.robot, detected);
        detected |= step_integrity_checks(sensors);
    }
    if (!zones_ok) {
        detected |= fault_bit(Fault::kZoneEvaluation);
    }
    if (memory_failed_) {
        detected |= fault_bit(Fault::kInternalCheck);
    }
    monitor_.end_stage(CycleStage::kSubtractAndZones, clock_->now_us());

    SafetyInputs in;
    in.now_us = start;
    in.zones = zones_ok ? &r.zones : nullptr;
    in.detected_faults = detected;
    // The reset: the caller's input or the PLC's ResetRequest (robot cells); SafetyLogic takes the edge.
    in.reset_input = reset_input || r.robot.command_reset;
    in.active_zones = scope.active_zones;
    in.speed_request = speed;
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
    seal_.seal(state_crc());
    return report_;
}

}  // namespace cellguard
