// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The firmware's robot-cell run (robot_scenario.hpp): the same source on the MCU and the hosts.
#include "cellguard/firmware/robot_scenario.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/can/command_receiver.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/firmware/canned_frames.hpp"
#include "cellguard/firmware/grid_config.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/prior/prior_image.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "cellguard/safety/monitoring_cases.hpp"
#include "embedded_data.hpp"
#include "scenario_common.hpp"

namespace cellguard::firmware {
namespace {

using detail::canned_reading;
using detail::Digest;
using detail::digest_grid;
using detail::digest_report;
using detail::DigestingSender;
using detail::Line;
using detail::PlcTapSender;

using GridStorage = StaticEvidenceGridStorage<CELLGUARD_GRID_NX, CELLGUARD_GRID_NY, CELLGUARD_GRID_NZ>;

// The robot mask (one byte per voxel) and the loaded robot: static storage (.bss).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the robot mask's storage, in .bss by design
std::uint8_t g_robot_mask[GridStorage::kVoxels];
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the robot model the controller reads, in .bss by design
LoadedRobot g_robot;

/// The run's own time: the cycle's start, then one microsecond per reading.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class ScriptClock final : public MonotonicClock {
public:
    void set(std::uint64_t t) noexcept { t_ = t; }
    std::uint64_t now_us() noexcept override { return ++t_; }

private:
    std::uint64_t t_ = 0U;
};

/// One cycle of the script: the scene (and with it the arm's pose the PLC
/// reports) and the PLC's case and speed class.
struct RobotStep {
    std::uint8_t scene;            // scene index in the robot frames blob
    std::uint8_t monitoring_case;  // the case the PLC asks for
    std::uint8_t speed_class;      // the robot's speed class the PLC reports
};
// The arm works at A (case 0), carries (case 2), works at B (case 1); a
// person walks up (reduced speed), the PLC drops to class 1, the person
// comes near (protective stop), and leaves (the stop resumes by itself).
constexpr RobotStep kRobotScript[kRobotScenarioCycles] = {{0U, 0U, 0U}, {0U, 0U, 0U}, {1U, 2U, 0U}, {2U, 1U, 0U},
                                                          {3U, 1U, 0U}, {4U, 1U, 1U}, {4U, 1U, 1U}, {2U, 1U, 1U}};

/// The first cycle's start on the run's clock (the PLC sends from 160 ms before it).
constexpr std::uint64_t kFirstCycleUs = 1000000U;
/// The PLC's sample period and the arrival of its samples before a cycle's start.
constexpr std::uint64_t kPlcPeriodUs = 50000U;
constexpr std::uint64_t kLastSampleLeadUs = 10000U;
/// Frames of one sample arrive this far apart.
constexpr std::uint64_t kFrameGapUs = 100U;
/// The controller's and the receiver's command age limit (the demo's max_command_age_ms).
constexpr std::uint64_t kMaxCommandAgeUs = 200000U;

/// Digests the robot side of @p r and the robot mask @p mask.
void digest_robot(const RobotReport& r, Span<const std::uint8_t> mask, Digest& d) noexcept {
    d.u8(r.configured ? 1U : 0U);
    d.u8(r.active_case);
    d.u8(r.command_valid ? 1U : 0U);
    d.u8(r.command_counter);
    d.u64(r.command_age_us);
    d.u8(r.command_check);
    d.u8(static_cast<std::uint8_t>(r.speed_request));
    d.u32(r.distance_mm);
    d.u32(r.required_mm);
    d.u32(r.robot_voxels);
    d.bytes(mask);
}

/// What the robot-cell run works on.
struct RobotRun {
    SafetyController& controller;
    const CannedFrames& frames;
    const EvidenceGrid& frame_grid;
    PlcCommandSender& plc;
    PlcReceiver& plc_receiver;  // the PLC's side of the session link (its link frames' fields)
    CommandReceiver& receiver;
    ScriptClock& clock;
    Digest& digest;
    TextSink& text;
};

/// The PLC's samples for the cycle starting at @p start: @p samples of
/// them, kPlcPeriodUs apart, the last kLastSampleLeadUs before the start,
/// each encoded by the PLC's sender and received frame by frame. Digests
/// every frame. False when the sender refuses the command.
bool send_plc_samples(const RobotRun& run, const RobotCommand& command, std::uint64_t start,
                      std::uint32_t samples) noexcept {
    for (std::uint32_t s = samples; s > 0U; --s) {
        const std::uint64_t at = start - kLastSampleLeadUs - (s - 1U) * kPlcPeriodUs;
        const Result<LinkedCommandFrames> frames = run.plc.next_sample(command, run.plc_receiver.next_link(at),
                                                                       run.plc_receiver.config().link.own);
        if (!frames.ok()) {
            return false;
        }
        std::uint64_t t = at;
        const auto send = [&run, &t](const CanFrame& f) {
            run.digest.u32(f.id);
            run.digest.u8(f.dlc);
            run.digest.bytes(Span<const std::uint8_t>(f.data, sizeof(f.data)));
            static_cast<void>(run.receiver.on_frame(f, t));
            t += kFrameGapUs;
        };
        for (const CanFrame& f : frames.value().sample.frame) {
            send(f);
        }
        send(frames.value().link);  // protocol 0.2: the PLC's link frame closes the sample
    }
    return true;
}

/// One line per cycle: scene, command, case, speed request, distances, zones, stop, warning, faults, digest.
void write_robot_line(const CycleReport& r, const CommandPoll& poll, const char* scene_name, std::uint32_t crc,
                      TextSink& text) noexcept {
    Line line;
    line.text("robot cycle ").dec(r.cycle).text(" scene ").text(scene_name);
    line.text(" command ").text(poll.status.valid ? "valid" : "invalid");
    line.text(" case ").dec(r.robot.active_case).text(" ").text(to_string(r.robot.speed_request));
    line.text(" d ").dec(r.robot.distance_mm).text(" mm S_p ").dec(r.robot.required_mm).text(" mm");
    line.text(" robot_voxels ").dec(r.robot.robot_voxels).text(" zones ");
    for (std::size_t z = 0U; z < r.zones.count; ++z) {
        line.text(z == 0U ? "" : "/").text(to_string(r.zones.zones[z].state));
    }
    line.text(" stop ").dec(r.safety.stop_requested ? 1U : 0U);
    line.text(" warning ").dec(r.safety.warning ? 1U : 0U);
    line.text(" faults ").hex(r.safety.latched_faults);
    line.text(" crc ").hex(crc).text("\n");
    text.write(line.c_str());
}

/// Cycle @p k (from 0) of the script: the PLC's samples, the receiver's
/// poll, the controller's cycle on the step's frames, the digest, the line.
bool run_robot_step(const RobotRun& run, std::uint32_t k, const RobotStep& step) noexcept {
    run.digest.start_cycle();
    const RobotScene scene = robot_scenes()[step.scene];
    RobotCommand command;
    command.monitoring_case = step.monitoring_case;
    command.speed_class = step.speed_class;
    command.joint_count = static_cast<std::uint8_t>(kRobotScenarioJoints);
    command.robot_id = robot_id(kDemoArmImageCrc);  // the PLC's commissioned robot id
    const std::array<std::int16_t, kRobotScenarioJoints> raw = arm_pose_raw(scene.arm);
    for (std::size_t j = 0U; j < raw.size(); ++j) {
        command.joint_raw[j] = raw[j];
    }
    const std::uint64_t start = kFirstCycleUs + k * kRobotScenarioPeriodUs;
    // Two samples a cycle; before the first cycle the PLC has been sending
    // for a while: four samples, enough for the receiver's recovery.
    if (!send_plc_samples(run, command, start, k == 0U ? 4U : 2U)) {
        run.text.write("error: the PLC's sender refused the command\n");
        return false;
    }
    const CommandPoll poll = run.receiver.poll(start);
    run.digest.u8(poll.status.valid ? 1U : 0U);
    run.digest.u8(static_cast<std::uint8_t>(poll.status.fault));
    run.clock.set(start);
    SensorInput inputs[kMaxCannedSensors];
    for (std::size_t s = 0U; s < run.frames.sensor_count(); ++s) {
        inputs[s].reading = canned_reading(run.frames, s, step.scene);
        inputs[s].captured_us = start;
        inputs[s].present = true;
    }
    const CycleReport& r = run.controller.run_cycle(Span<const SensorInput>(inputs, run.frames.sensor_count()), false,
                                                    poll.input);
    digest_grid(run.frame_grid, run.digest);
    digest_report(r, run.digest);
    digest_robot(r.robot, Span<const std::uint8_t>(g_robot_mask, run.frame_grid.voxel_count()), run.digest);
    write_robot_line(r, poll, run.frames.scene_name(step.scene), run.digest.cycle(), run.text);
    return true;
}

/// The robot image in flash: load_robot_image's checks (magic, version,
/// size, CRC, the model), the demo arm's CRC (the robot id the PLC was
/// commissioned with) and its six joints. Copies the model into g_robot.
/// False (said on @p text) when not. Not inlined: the loader's result
/// (about 4 KB) then stays off the stack of zone compilation, the run's peak.
[[gnu::noinline]] bool robot_in_flash_ok(TextSink& text) noexcept {
    const Result<LoadedRobot, RobotModelError> loaded = load_robot_image(
        Span<const std::uint8_t>(cellguard_firmware_robot_image, cellguard_firmware_robot_image_size));
    if (!loaded.ok()) {
        text.write("error: the robot image in flash fails its checks\n");
        return false;
    }
    if (loaded.value().crc != kDemoArmImageCrc || loaded.value().model.joint_count != kRobotScenarioJoints) {
        text.write("error: the robot image in flash is not the commissioned robot\n");
        return false;
    }
    g_robot = loaded.value();
    Line line;
    line.text("robot ").text(g_robot.model.name).text(" image ").dec(cellguard_firmware_robot_image_size);
    line.text(" bytes crc ").hex(g_robot.crc).text("\n");
    text.write(line.c_str());
    return true;
}

/// The robot cell's prior in flash, checked against its grid, its payload
/// the int16 symbol; the robot frames, their scenes the script's. False
/// (said on @p text) when not.
bool robot_cell_data_ok(const Result<PriorImageView, PriorImageError>& view, const Result<CannedFrames>& frames,
                        std::size_t voxels, TextSink& text) noexcept {
    if (!view.ok() ||
        static_cast<const void*>(cellguard_firmware_robot_prior_values) !=
            static_cast<const void*>(view.value().payload().data()) ||
        view.value().voxel_count() != voxels || voxels > GridStorage::kVoxels) {
        text.write("error: the robot cell's prior in flash fails its checks\n");
        return false;
    }
    if (!frames.ok() || frames.value().scene_count() != kRobotScenes) {
        text.write("error: the robot cell's canned frames fail their checks\n");
        return false;
    }
    return true;
}

/// The controller's configuration: the zones-only run's, with the robot
/// (g_robot, the demo's margin and separation parameters, g_robot_mask for
/// @p voxels voxels), @p cases and the command age limit.
ControllerConfig robot_controller_config(std::size_t sensor_count, const MonitoringCases& cases,
                                         std::size_t voxels) noexcept {
    ControllerConfig config = scenario_controller_config(sensor_count);
    config.cases = &cases;
    config.max_command_age_us = kMaxCommandAgeUs;
    config.robot.model = &g_robot.model;
    config.robot.image_crc = g_robot.crc;
    config.robot.mask_margin_m = kRobotScenarioMaskMargin;
    config.robot.separation = robot_scenario_separation();
    config.robot.mask = Span<std::uint8_t>(g_robot_mask, voxels);
    return config;
}

/// Prints the run's frame count and prior CRC, the canned PLC's accepted pairs and the digest.
void report_robot_run(const ScenarioSummary& summary, std::uint32_t frames, std::uint32_t plc_pairs_accepted,
                      TextSink& text) noexcept {
    Line last;
    last.text("robot frames ").dec(frames).text(" prior_crc ").hex(summary.prior_crc).text("\n");
    last.text("robot plc pairs accepted ").dec(plc_pairs_accepted).text("\n");
    text.write(last.c_str());
    Line result;
    result.text("robot digest ").hex(summary.digest).text("\n");
    text.write(result.c_str());
}

}  // namespace

ScenarioSummary run_robot_scenario(CanSender& can, TextSink& text) noexcept {
    ScenarioSummary summary;
    if (!robot_in_flash_ok(text)) {
        return summary;
    }
    const GridGeometry geometry = robot_cell_grid_geometry();
    const std::size_t voxels = geometry.voxel_count();
    const Result<PriorImageView, PriorImageError> view = load_prior_image(
        Span<const std::uint8_t>(cellguard_firmware_robot_prior_image, cellguard_firmware_robot_prior_image_size),
        geometry);
    const Result<CannedFrames> frames_result = CannedFrames::parse(
        Span<const std::uint8_t>(cellguard_firmware_robot_frames, cellguard_firmware_robot_frames_size),
        Span<const float>(cellguard_firmware_robot_frames_f32, cellguard_firmware_robot_frames_size / sizeof(float)));
    if (!robot_cell_data_ok(view, frames_result, voxels, text)) {
        return summary;
    }
    const CannedFrames& frames = frames_result.value();
    const detail::FirmwareStorage storage = detail::firmware_storage();
    const Result<EvidenceGrid> grid = EvidenceGrid::make(geometry, Span<std::int16_t>(storage.log_odds, voxels),
                                                         Span<std::uint8_t>(storage.observed, voxels));
    const std::array<ZoneConfig, kRobotScenarioZones> zone_configs = robot_scenario_zone_configs();
    const Result<CompiledZones, ZoneError> zones = CompiledZones::compile(
        geometry, Span<const ZoneConfig>(zone_configs.data(), zone_configs.size()),
        Span<std::uint32_t>(storage.zone_mask, voxels));
    if (!grid.ok() || !zones.ok()) {
        text.write("error: robot cell grid or zones refused\n");
        return summary;
    }
    const std::array<std::uint32_t, kRobotScenarioCases> case_masks = robot_scenario_case_masks();
    const Result<MonitoringCases, CaseError> cases = MonitoringCases::make(
        zones.value(), Span<const std::uint32_t>(case_masks.data(), case_masks.size()));
    if (!cases.ok()) {
        text.write("error: monitoring cases refused\n");
        return summary;
    }

    Digest digest;
    SafetyOutputConfig output_config;
    output_config.zone_count = kRobotScenarioZones;
    output_config.prior_crc = view.value().header().payload_crc;
    ScriptClock clock;
    // Protocol 0.2 in both directions: the canned PLC receives the
    // controller's frames (PlcTapSender) and echoes its link frames; the
    // controller's link endpoint is its command receiver's.
    PlcReceiverConfig plc_config;
    plc_config.expected_zone_count = kRobotScenarioZones;
    plc_config.sct_us = 3U * kRobotScenarioPeriodUs;
    PlcReceiver plc_receiver(plc_config);
    DigestingSender digesting(can, output_config.channel.diagnostics_can_id, digest);
    PlcTapSender sender(digesting, plc_receiver, clock);
    CommandReceiverConfig receiver_config;
    receiver_config.sct_us = kMaxCommandAgeUs;
    PlcCommandSender plc(receiver_config.channel);
    CommandReceiver receiver(receiver_config);
    CanSafetyOutput output(output_config, sender, &receiver.link());

    const ControllerConfig config = robot_controller_config(frames.sensor_count(), cases.value(), voxels);
    const SensorModelTable model;
    EvidenceGrid frame_grid = grid.value();  // a view of the firmware's grid storage
    const Span<const std::int16_t> prior_values(cellguard_firmware_robot_prior_values, voxels);
    SafetyController controller(config, frame_grid, Span<std::int16_t>(storage.fusion_scratch, voxels), prior_values,
                                zones.value(), model, clock, &output);
    summary.prior_crc = controller.prior_crc();
    if (!output.status().ok() || controller.prior_crc() != output_config.prior_crc) {
        text.write("error: CAN output refused or robot cell prior CRC differs from the image's payload CRC\n");
        return summary;
    }
    summary.setup_ok = true;

    const RobotRun run{controller, frames, frame_grid, plc, plc_receiver, receiver, clock, digest, text};
    for (std::uint32_t k = 0U; k < kRobotScenarioCycles; ++k) {
        if (!run_robot_step(run, k, kRobotScript[k])) {
            return summary;
        }
        ++summary.cycles;
    }
    summary.digest = digest.total();
    report_robot_run(summary, digesting.frames(), sender.accepted(), text);
    return summary;
}

}  // namespace cellguard::firmware
