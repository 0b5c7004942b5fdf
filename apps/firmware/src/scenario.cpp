// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The firmware's canned run (scenario.hpp): the same source on the MCU and the hosts.
#include "cellguard/firmware/scenario.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/base/crc32.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/session_link.hpp"
#include "cellguard/firmware/canned_frames.hpp"
#include "cellguard/firmware/grid_config.hpp"
#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/prior/prior_image.hpp"
#include "cellguard/safety/cycle.hpp"
#include "cellguard/safety/zones.hpp"
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

// The frame grid and the zone membership mask: static storage (.bss).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the frame grid's storage, in .bss by design
GridStorage g_grid;
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): fusion's per-sensor working memory, in .bss by design
std::int16_t g_fusion_scratch[GridStorage::kVoxels];
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the zone mask's storage, in .bss by design
std::uint32_t g_zone_mask[GridStorage::kVoxels];

/// Cells of a depth pyramid over a @p width x @p height image, as
/// depth_pyramid_cells computes them (checked at run time against it).
constexpr std::size_t pyramid_cells(std::size_t width, std::size_t height) noexcept {
    std::size_t cells = width * height;
    while (width > 1U || height > 1U) {
        width = (width + 1U) / 2U;
        height = (height + 1U) / 2U;
        cells += width * height;
    }
    return cells;
}
/// The largest canned image: the paper's 320 x 240 sensors at half resolution.
constexpr std::int32_t kFootprintMaxWidth = 160;
/// Its rows.
constexpr std::int32_t kFootprintMaxHeight = 120;
/// Pyramid cells of the footprint run's one workspace (the sensors run one
/// after another through it, so the largest image sets its size).
constexpr std::size_t kFootprintPyramidCells = pyramid_cells(kFootprintMaxWidth, kFootprintMaxHeight);

/// The footprint run's depth pyramid (min, max, invalid flag per cell). Its
/// opinions use g_fusion_scratch: with every sensor a depth image fused by
/// footprint, the controller gets no ray scratch.
struct FootprintPyramidStorage {
    float min[kFootprintPyramidCells];
    float max[kFootprintPyramidCells];
    std::uint8_t invalid[kFootprintPyramidCells];
};
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): footprint fusion's pyramid, in .bss by design
FootprintPyramidStorage g_footprint_pyramid;

// The controller reads the prior image's payload in place as int16 values.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the prior payload is little-endian int16");

/// One cycle of the script.
struct Step {
    std::uint8_t scene;            // scene index in the frames blob
    std::uint8_t missing_sensors;  // bit s: sensor s delivers no frame this cycle
    bool reset;                    // level of the reset input
};
// Empty cell, a person in the warning zone, a person in the protective zone,
// empty again, a sensor missing, then recovery.
constexpr Step kScript[kScenarioCycles] = {{0U, 0U, false},   {1U, 0U, false}, {2U, 0U, false}, {0U, 0U, false},
                                           {0U, 0x4U, false}, {0U, 0U, false}, {0U, 0U, false}, {0U, 0U, false}};

}  // namespace

void format_hex32(std::uint32_t value, char (&out)[11]) noexcept {
    constexpr char kDigits[] = "0123456789abcdef";
    out[0] = '0';
    out[1] = 'x';
    for (std::size_t i = 0U; i < 8U; ++i) {
        out[2U + i] = kDigits[(value >> (28U - 4U * i)) & 0xFU];
    }
    out[10] = '\0';
}

void format_decimal(std::uint64_t value, char (&out)[21]) noexcept {
    char rev[20];
    std::size_t n = 0U;
    do {
        rev[n++] = static_cast<char>('0' + static_cast<int>(value % 10U));
        value /= 10U;
    } while (value != 0U && n < sizeof(rev));
    for (std::size_t i = 0U; i < n; ++i) {
        out[i] = rev[n - 1U - i];
    }
    out[n] = '\0';
}

std::array<ZoneConfig, kScenarioZones> scenario_zone_configs() noexcept {
    ZoneConfig protective;  // on the floor in front of a background box
    protective.box_min = Eigen::Vector3d(0.0, 0.2, 0.0);
    protective.box_max = Eigen::Vector3d(0.4, 0.6, 1.2);
    protective.max_unseen_voxels = 20U;
    ZoneConfig warning;
    warning.kind = ZoneKind::kWarning;
    warning.box_min = Eigen::Vector3d(-0.8, 0.45, 0.0);
    warning.box_max = Eigen::Vector3d(0.8, 0.75, 1.2);
    warning.max_unseen_voxels = 40U;
    return {protective, warning};
}

namespace {
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): set once by main, before the runs
const StackPaint* g_stack_check = nullptr;
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): set once by main, before the runs
std::uint64_t g_restart_delay_us = 0U;
}  // namespace

void set_stack_check(const StackPaint* paint) noexcept { g_stack_check = paint; }

void set_restart_delay(std::uint64_t delay_us) noexcept { g_restart_delay_us = delay_us; }

ControllerConfig scenario_controller_config(std::size_t sensor_count) noexcept {
    ControllerConfig config;
    config.stack = g_stack_check;
    config.sensor_count = sensor_count;
    config.logic.restart_delay_us = g_restart_delay_us;  // 0 unless set: the interlock is not under test here
    config.logic.fault_recovery_cycles = 2U;
    // Off, each with its reason (the library's defaults are on): the scenario
    // has no reset input (a release follows the delay alone, as the expected
    // digests record), and its simulated frames repeat bit for bit by design.
    config.logic.reset_required = false;
    config.max_repeated_frames = 0U;
    config.cycle_budget_us = 10000000U;  // generous: timing must not change the results
    return config;
}

namespace {

/// The prior image in flash: every check of load_prior_image (CRCs,
/// geometry, parameters, values), and the int16 symbol the controller reads
/// in place must be its payload. False (said on @p text) when not.
bool prior_in_flash_ok(const Result<PriorImageView, PriorImageError>& view, TextSink& text) noexcept {
    if (!view.ok()) {
        text.write("error: the prior image in flash fails its checks\n");
        return false;
    }
    if (static_cast<const void*>(cellguard_firmware_prior_values) !=
            static_cast<const void*>(view.value().payload().data()) ||
        view.value().voxel_count() != GridStorage::kVoxels) {
        text.write("error: the prior values symbol is not the image's payload\n");
        return false;
    }
    return true;
}

/// The canned frames: magic, version, sizes, CRC; the script's scenes must
/// exist. False (said on @p text) when not.
bool canned_frames_ok(const Result<CannedFrames>& frames, TextSink& text) noexcept {
    if (!frames.ok()) {
        text.write("error: the canned frames in flash fail their checks\n");
        return false;
    }
    for (const Step& step : kScript) {
        if (step.scene >= frames.value().scene_count()) {
            text.write("error: the script needs a scene the canned frames do not hold\n");
            return false;
        }
    }
    return true;
}

/// One line per cycle: scene, zone states with their counts, stop, warning, faults, the cycle's digest.
void write_cycle_line(const char* prefix, const CycleReport& r, const char* scene_name, std::uint32_t cycle_crc,
                      TextSink& text) noexcept {
    Line line;
    line.text(prefix).text("cycle ").dec(r.cycle).text(" scene ").text(scene_name);
    line.text(" zones ");
    for (std::size_t z = 0U; z < r.zones.count; ++z) {
        line.text(z == 0U ? "" : "/").text(to_string(r.zones.zones[z].state));
        line.text("(fg ").dec(r.zones.zones[z].foreground).text(" unseen ").dec(r.zones.zones[z].unseen).text(")");
    }
    line.text(" stop ").dec(r.safety.stop_requested ? 1U : 0U);
    line.text(" warning ").dec(r.safety.warning ? 1U : 0U);
    line.text(" faults ").hex(r.safety.latched_faults);
    line.text(" crc ").hex(cycle_crc).text("\n");
    text.write(line.c_str());
}

/// What one step of the script runs on.
/// The canned PLC's SCT: the canned run is not paced (its clock counts
/// readings on the host, runs on the board's timer on the target), so the
/// PLC's time checks are loose; the digest holds the frames, whose link
/// fields (sequence, session, echo) do not depend on time.
constexpr std::uint64_t kCannedPlcSctUs = 10000000U;

struct ScriptRun {
    SafetyController& controller;
    PlcReceiver& plc;                // the canned PLC's receiver: its link frames' fields
    LinkEndpoint& controller_link;   // the controller's link endpoint (a cell without commands)
    std::uint8_t& plc_link_counter;  // E2E counter of the PLC's link frames sent alone
    const CannedFrames& frames;
    const EvidenceGrid& frame_grid;
    MonotonicClock& clock;
    Digest& digest;
    TextSink& text;
    const char* prefix;  // before every line: "" or "footprint "
};

/// One cycle of the script: the step's frames (missing sensors absent), the
/// controller's cycle, the digest of its grid and report, the cycle's line.
void run_step(const ScriptRun& run, const Step& step) noexcept {
    run.digest.start_cycle();
    // Protocol 0.2, a cell without commands: before the cycle the PLC sends
    // its link frame alone (the echo of the controller's last sequence); the
    // controller's link endpoint checks it, and echoes it in its next frames.
    const std::uint64_t plc_now = run.clock.now_us();
    const Result<CanFrame> plc_link = encode_link_frame(run.plc.next_link(plc_now), run.plc_link_counter,
                                                        run.plc.config().link.own, Span<const CanFrame>());
    if (plc_link.ok()) {
        run.plc_link_counter = e2e_p01_next_counter(run.plc_link_counter);
        run.digest.u32(plc_link.value().id);
        run.digest.bytes(Span<const std::uint8_t>(plc_link.value().data, sizeof(plc_link.value().data)));
        static_cast<void>(run.controller_link.on_standalone_frame(plc_link.value(), run.clock.now_us()));
    }
    SensorInput inputs[kMaxCannedSensors];
    const std::uint64_t now = run.clock.now_us();
    for (std::size_t s = 0U; s < run.frames.sensor_count(); ++s) {
        inputs[s].reading = canned_reading(run.frames, s, step.scene);
        inputs[s].captured_us = now;
        inputs[s].present = ((static_cast<unsigned>(step.missing_sensors) >> s) & 1U) == 0U;
    }
    const CycleReport& r = run.controller.run_cycle(Span<const SensorInput>(inputs, run.frames.sensor_count()),
                                                    step.reset);
    digest_grid(run.frame_grid, run.digest);
    digest_report(r, run.digest);
    write_cycle_line(run.prefix, r, run.frames.scene_name(step.scene), run.digest.cycle(), run.text);
}

/// The closing lines: frames sent, the prior's CRC, the run's digest.
void write_totals(const char* prefix, const ScenarioSummary& summary, std::uint32_t frames_sent,
                  TextSink& text) noexcept {
    Line last;
    last.text(prefix).text("frames ").dec(frames_sent).text(" prior_crc ").hex(summary.prior_crc).text("\n");
    text.write(last.c_str());
    Line result;
    result.text(prefix).text("digest ").hex(summary.digest).text("\n");
    text.write(result.c_str());
}

/// How a run of the script fuses, and how its lines begin.
struct PaperRun {
    const char* prefix = "";              ///< before every line: "" or "footprint "
    FootprintFusionConfig footprint{};    ///< the controller's fusion method and workspaces
    Span<std::int16_t> fusion_scratch{};  ///< fuse_sensor's working memory (empty: none)
};

/// Whether every canned image's pyramid fits the footprint workspaces
/// (always true for the ray run). False (said on @p text) when not.
bool footprint_workspace_fits(const CannedFrames& frames, const PaperRun& how, TextSink& text) noexcept {
    if (how.footprint.method != FusionMethod::kFootprint) {
        return true;
    }
    for (std::size_t s = 0U; s < frames.sensor_count(); ++s) {
        const std::size_t cells = depth_pyramid_cells(frames.sensor(s).width, frames.sensor(s).height);
        for (const FootprintWorkspace& w : how.footprint.workspaces) {
            if (cells == 0U || w.pyramid_min.size() < cells || w.pyramid_max.size() < cells ||
                w.pyramid_invalid.size() < cells || w.opinions.size() < GridStorage::kVoxels) {
                text.write("error: a canned image's depth pyramid does not fit the footprint workspace\n");
                return false;
            }
        }
    }
    return true;
}

/// The paper cell's script (see run_scenario), fused as @p how says.
ScenarioSummary run_paper_cell(MonotonicClock& clock, CanSender& can, TextSink& text, const PaperRun& how) noexcept {
    ScenarioSummary summary;
    const GridGeometry geometry = paper_grid_geometry();
    const Result<PriorImageView, PriorImageError> view = load_prior_image(
        Span<const std::uint8_t>(cellguard_firmware_prior_image, cellguard_firmware_prior_image_size), geometry);
    if (!prior_in_flash_ok(view, text)) {
        return summary;
    }
    const Span<const std::int16_t> prior_values(cellguard_firmware_prior_values, GridStorage::kVoxels);
    const Result<CannedFrames> frames_result = CannedFrames::parse(
        Span<const std::uint8_t>(cellguard_firmware_frames, cellguard_firmware_frames_size),
        Span<const float>(cellguard_firmware_frames_f32, cellguard_firmware_frames_size / sizeof(float)));
    if (!canned_frames_ok(frames_result, text) || !footprint_workspace_fits(frames_result.value(), how, text)) {
        return summary;
    }
    const CannedFrames& frames = frames_result.value();

    const Result<EvidenceGrid> grid = EvidenceGrid::make(geometry,
                                                         Span<std::int16_t>(g_grid.log_odds, GridStorage::kVoxels),
                                                         Span<std::uint8_t>(g_grid.observed, GridStorage::kVoxels));
    const std::array<ZoneConfig, kScenarioZones> zone_configs = scenario_zone_configs();
    const Result<CompiledZones, ZoneError> zones = CompiledZones::compile(
        geometry, Span<const ZoneConfig>(zone_configs.data(), zone_configs.size()),
        Span<std::uint32_t>(g_zone_mask, GridStorage::kVoxels));
    if (!grid.ok() || !zones.ok()) {
        text.write("error: grid or zones refused\n");
        return summary;
    }

    Digest digest;
    SafetyOutputConfig output_config;
    output_config.zone_count = kScenarioZones;
    output_config.prior_crc = view.value().header().payload_crc;
    // Protocol 0.2: the canned PLC receives the controller's frames
    // (PlcTapSender) and sends its link frame alone every cycle (run_step).
    PlcReceiverConfig plc_config;
    plc_config.expected_zone_count = kScenarioZones;
    plc_config.sct_us = kCannedPlcSctUs;
    PlcReceiver plc(plc_config);
    LinkEndpoint controller_link(controller_link_config());
    std::uint8_t plc_link_counter = 0U;
    DigestingSender digesting(can, output_config.channel.diagnostics_can_id, digest);
    PlcTapSender sender(digesting, plc, clock);
    CanSafetyOutput output(output_config, sender, &controller_link);

    ControllerConfig config = scenario_controller_config(frames.sensor_count());
    config.footprint = how.footprint;
    const SensorModelTable model;
    EvidenceGrid frame_grid = grid.value();  // a view of g_grid
    SafetyController controller(config, frame_grid, how.fusion_scratch, prior_values, zones.value(), model, clock,
                                &output);
    summary.prior_crc = controller.prior_crc();
    if (!output.status().ok() || controller.prior_crc() != output_config.prior_crc) {
        text.write("error: CAN output refused or prior CRC differs from the image's payload CRC\n");
        return summary;
    }
    summary.setup_ok = true;

    const ScriptRun run{controller, plc,  controller_link, plc_link_counter, frames, frame_grid, clock,
                        digest,     text, how.prefix};
    for (const Step& step : kScript) {
        run_step(run, step);
        ++summary.cycles;
        const CycleTiming& t = controller.monitor().last();
        const std::uint64_t fuse_us = t.stage_us[static_cast<std::size_t>(CycleStage::kFuse)];
        summary.cycle_us_max = t.total_us > summary.cycle_us_max ? t.total_us : summary.cycle_us_max;
        summary.cycle_us_sum += t.total_us;
        summary.fuse_us_max = fuse_us > summary.fuse_us_max ? fuse_us : summary.fuse_us_max;
    }
    summary.digest = digest.total();
    write_totals(how.prefix, summary, digesting.frames(), text);
    return summary;
}

}  // namespace

namespace detail {

FirmwareStorage firmware_storage() noexcept {
    return FirmwareStorage{g_grid.log_odds, g_grid.observed, g_fusion_scratch, g_zone_mask};
}

}  // namespace detail

ScenarioSummary run_scenario(MonotonicClock& clock, CanSender& can, TextSink& text) noexcept {
    const PaperRun how{"", FootprintFusionConfig{}, Span<std::int16_t>(g_fusion_scratch, GridStorage::kVoxels)};
    return run_paper_cell(clock, can, text, how);
}

ScenarioSummary run_footprint_scenario(MonotonicClock& clock, CanSender& can, TextSink& text) noexcept {
    // One workspace: the sensors run one after another through it (one core).
    // Its opinions are g_fusion_scratch, which the controller then does not
    // get: every canned sensor is a depth image, fused by footprint.
    const FootprintWorkspace workspace{Span<float>(g_footprint_pyramid.min, kFootprintPyramidCells),
                                       Span<float>(g_footprint_pyramid.max, kFootprintPyramidCells),
                                       Span<std::uint8_t>(g_footprint_pyramid.invalid, kFootprintPyramidCells),
                                       Span<std::int16_t>(g_fusion_scratch, GridStorage::kVoxels)};
    PaperRun how{"footprint ", FootprintFusionConfig{}, Span<std::int16_t>()};
    how.footprint.method = FusionMethod::kFootprint;
    how.footprint.workspaces = Span<const FootprintWorkspace>(&workspace, 1U);
    return run_paper_cell(clock, can, text, how);
}

}  // namespace cellguard::firmware
