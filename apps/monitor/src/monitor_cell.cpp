// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's start-up: sensors, grid, zones, prior, ray tables (monitor_cell.hpp).
#include "cellguard/monitor/monitor_cell.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "cellguard/base/crc32.hpp"
#include "cellguard/grid/depth_pyramid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/io/background_files.hpp"
#include "cellguard/host/io/prior_files.hpp"
#include "cellguard/host/io/urdf_import.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/safety/cycle.hpp"

namespace cellguard::monitor {
namespace {

// printf to @p out, or nothing when it is nullptr.
// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
__attribute__((format(printf, 2, 3))) void say(std::FILE* out, const char* format, ...) {
    if (out == nullptr) {
        return;
    }
    va_list args;
    va_start(args, format);
    static_cast<void>(std::vfprintf(out, format, args));
    va_end(args);
}

// A failed step with exit status @p status and a printf-formatted message.
// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
__attribute__((format(printf, 2, 3))) SetupError failure(int status, const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string text(n > 0 ? static_cast<std::size_t>(n) : 0U, '\0');
    static_cast<void>(std::vsnprintf(text.data(), text.size() + 1U, format, again));
    va_end(again);
    return SetupError{status, text};
}

// "FILE: " for a configuration loaded from a file ("" for a built-in one).
std::string where(const cell::MonitorConfig& cfg) {
    return cfg.source.empty() || cfg.source[0] == '<' ? std::string() : cfg.source + ": ";
}

// The prior image file of @p cfg, copied into @p prior.
SetupError read_prior(const cell::MonitorConfig& cfg, const GridGeometry& g, std::vector<std::int16_t>& prior,
                      std::uint32_t& payload_crc, std::FILE* out) {
    std::vector<std::uint8_t> bytes;
    PriorImageView view;
    const IoStatus st = read_prior_image_file(cfg.prior.file.c_str(), g, bytes, view);
    // The configuration names a prior file that cannot be used: a configuration error (exit status 2).
    if (!st.ok()) {
        return failure(2, "configuration error: %sprior.file: %s", where(cfg).c_str(), st.message());
    }
    if (!view.copy_to({prior.data(), prior.size()}).ok()) {
        return failure(2, "configuration error: %sprior.file: %s does not fit the grid", where(cfg).c_str(),
                       cfg.prior.file.c_str());
    }
    payload_crc = view.header().payload_crc;
    say(out, "prior: %s\n", cfg.prior.file.c_str());
    return {};
}

#if CELLGUARD_HOST_URDF
// What the URDF import needs from [robot]: the PLC's joint order, the stroke joints, the base, the URDF's folder.
host::UrdfImportOptions urdf_options(const cell::RobotSettings& robot) {
    host::UrdfImportOptions options;
    options.joint_order = robot.joints;
    options.stroke_joints = robot.stroke_joints;
    options.base_xyz = robot.base;
    options.base_rotation = Eigen::Quaterniond(
        Eigen::AngleAxisd(robot.base_yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
    const std::size_t slash = robot.urdf.find_last_of('/');
    options.base_directory = slash == std::string::npos ? "." : robot.urdf.substr(0U, slash);
    return options;
}
#endif

// The robot of @p cfg as a checked model: the URDF imported in the PLC's joint order at the configured base.
SetupError import_robot(const cell::MonitorConfig& cfg, RobotModel& model) {
#if CELLGUARD_HOST_URDF
    std::string text;
    if (!cell::read_config_text(cfg.robot.urdf, text)) {
        return failure(2, "configuration error: line %d: robot.urdf: cannot read '%s'", cfg.robot.line,
                       cfg.robot.urdf.c_str());
    }
    host::UrdfImport imported;
    const IoStatus st = host::import_urdf_text(text, urdf_options(cfg.robot), imported);
    if (!st.ok()) {
        return failure(2, "configuration error: line %d: robot.urdf '%s': %s", cfg.robot.line, cfg.robot.urdf.c_str(),
                       st.message());
    }
    model = imported.model;
    return {};
#else
    static_cast<void>(model);
    return failure(2, "configuration error: line %d: robot: this build has no URDF import (liburdfdom-dev)",
                   cfg.robot.line);
#endif
}

// The scene file of cfg.demo_scene.
SetupError read_scene(const cell::MonitorConfig& cfg, sim::SceneFile& scene) {
    std::string text;
    if (!cell::read_config_text(cfg.demo_scene, text)) {
        return failure(2, "configuration error: demo.scene: cannot read '%s'", cfg.demo_scene.c_str());
    }
    const std::size_t slash = cfg.demo_scene.find_last_of('/');
    const sim::SceneLoad load = sim::parse_scene(text, cfg.demo_scene,
                                                 slash == std::string::npos ? "" : cfg.demo_scene.substr(0U, slash));
    if (!load.ok) {
        return failure(2, "configuration error: demo.scene: %s", load.error.c_str());
    }
    scene = load.scene;
    return {};
}

}  // namespace

sim::Scene MonitorCell::background_scene() const { return has_scene ? scene.scene : sim::reference_scene(); }

void attach_robot(ControllerConfig& cc, const cell::MonitorConfig& cfg, MonitorCell& cell) {
    if (cell.has_cases) {
        cc.cases = &cell.cases;
    }
    if (!cell.robot_image.empty()) {
        cc.robot.model = &cell.robot.model;
        cc.robot.image_crc = cell.robot.crc;
        cc.robot.mask_margin_m = cfg.robot.margin_m;
        cc.robot.separation = cfg.robot.separation;
        cc.robot.mask = {cell.robot_mask.data(), cell.robot_mask.size()};
    }
    if (cell.has_cases || !cell.robot_image.empty()) {
        cc.max_command_age_us = cell::command_age_limit_us(cfg);
    }
}

sim::SensorSpec to_spec(const cell::SensorSettings& s, bool simulated_background, std::string& error) {
    sim::SensorSpec spec;
    spec.name = s.name;
    spec.position = s.position;
    spec.width = s.width;
    spec.height = s.height;
    spec.hfov_deg = s.hfov_deg;
    spec.vfov_deg = s.vfov_deg;
    if (s.intrinsics_source != cell::IntrinsicsSource::kFieldOfView) {  // fx..cy configured or read from the camera
        if (!(s.fx > 0.0 && s.fy > 0.0)) {
            error = "line " + std::to_string(s.line) + ": sensor '" + s.name +
                    "': intrinsics = \"device\" not yet read from the camera";
        }
        spec.set_intrinsics(s.fx, s.fy, s.cx, s.cy);
    }
    spec.max_range = static_cast<float>(s.max_range);
    if (s.has_target) {
        spec.target = s.target;
        if (std::abs((s.target - s.position).normalized().z()) > 0.999) {
            error =
                "line " + std::to_string(s.line) + ": sensor '" + s.name +
                "': looking straight up or down needs `rotation` (the simulator derives the roll from the vertical)";
        }
    } else {
        const Eigen::Matrix3d r = s.rotation.toRotationMatrix();
        spec.target = s.position + r.col(2);
        // Only the simulator derives the roll; a recorded sensor takes its pose as given (sensor_pose),
        // unless the simulator must render its view of the empty cell for the prior.
        if ((s.pcd_files.empty() || simulated_background) && !spec.pose().linear().isApprox(r, 1e-6)) {
            error = "line " + std::to_string(s.line) + ": sensor '" + s.name +
                    "': the simulator supports only rotations without roll (x axis horizontal)" +
                    (s.pcd_files.empty() ? std::string()
                                         : std::string("; it renders this recorded sensor's view for "
                                                       "prior.source = \"simulated-background\": use a prior file"));
        }
    }
    return spec;
}

SetupError check_start_settings(const cell::MonitorConfig& cfg) {
    const bool has_command = cfg.robot.enabled || !cfg.cases.empty();
    if (cfg.reset_required && !has_command) {
        return SetupError{
            2,
            "configuration error: restart_interlock.reset_required is true (the default), but this cell has no "
            "PLC command (no [robot], no [[cases]]), and the reset request travels in the command (part A, "
            "ResetRequest): its restart interlock would hold the stop for good after the first one. Give the cell "
            "its command, or let the PLC hold the restart until its reset button is pressed (safety manual, "
            "section 4.4) and set reset_required = false with [opt_out] reset_required = \"<reason>\""};
    }
    return {};
}

void print_opt_outs(const cell::MonitorConfig& cfg, std::FILE* out) {
    for (const cell::OptOut& o : cfg.opt_outs) {
        static_cast<void>(std::fprintf(out, "opt-out: %s off (%s): %s; lost: %s\n", o.name.c_str(), o.setting.c_str(),
                                       o.reason.c_str(), o.loses.c_str()));
    }
}

ControllerConfig controller_config(const cell::MonitorConfig& cfg) {
    ControllerConfig cc;
    cc.sensor_count = cfg.sensors.size();
    cc.logic.restart_delay_us = cfg.restart_delay_us;
    cc.logic.reset_required = cfg.reset_required;
    cc.logic.fault_recovery_cycles = cfg.fault_recovery_cycles;
    cc.zones.foreground_threshold = cfg.foreground_threshold;
    cc.zones.accessible_min_prior = cfg.accessible_min_prior;
    cc.max_frame_age_us = cfg.max_frame_age_us;
    cc.cycle_budget_us = cfg.budget_us;
    cc.table_check_slice_bytes = cfg.table_check_bytes;
    cc.max_repeated_frames = cfg.max_repeated_frames;
    cc.zone_check_slice_bytes = cfg.zone_check_bytes;
    return cc;
}

void attach_fusion(ControllerConfig& cc, const cell::MonitorConfig& cfg, const MonitorCell& cell, TaskRunner* runner) {
    if (cfg.fusion.method != FusionMethod::kFootprint) {
        return;
    }
    cc.footprint.method = FusionMethod::kFootprint;
    cc.footprint.params = cfg.fusion.params;
    cc.footprint.workspaces = {cell.footprint_spaces.data(), cell.footprint_spaces.size()};
    cc.footprint.runner = runner;
}

SetupError MonitorCell::configure(const cell::MonitorConfig& cfg) {
    grid = GridGeometry::make(cfg.grid.origin, cfg.grid.voxel_size,
                              GridDims{cfg.grid.dims[0], cfg.grid.dims[1], cfg.grid.dims[2]})
               .value();
    specs.clear();
    for (const cell::SensorSettings& s : cfg.sensors) {
        std::string error;
        specs.push_back(to_spec(s, cfg.prior.source == cell::PriorSource::kSimulatedBackground, error));
        if (!error.empty()) {
            return failure(2, "configuration error: %s", error.c_str());
        }
    }
    std::vector<ZoneConfig> zone_configs;
    for (const cell::ZoneSettings& z : cfg.zones) {
        zone_configs.push_back(z.zone);
    }
    zone_mask.assign(grid.voxel_count(), 0U);
    const Result<CompiledZones, ZoneError> compiled = CompiledZones::compile(
        grid, {zone_configs.data(), zone_configs.size()}, {zone_mask.data(), zone_mask.size()});
    if (!compiled.ok()) {
        const ZoneError zone_error = compiled.error();
        const cell::ZoneSettings& z = cfg.zones[std::min(zone_error.zone, cfg.zones.size() - 1U)];
        const Eigen::Vector3d lo = cfg.grid.origin;
        const Eigen::Vector3d hi = lo + cfg.grid.voxel_size *
                                            Eigen::Vector3d(cfg.grid.dims[0], cfg.grid.dims[1], cfg.grid.dims[2]);
        return failure(2,
                       "configuration error: %sline %d: zone '%s': %s (%s); the grid spans x %.3f..%.3f, "
                       "y %.3f..%.3f, z %.3f..%.3f m",
                       where(cfg).c_str(), z.line, z.name.c_str(), zone_error.reason, to_string(zone_error.code),
                       lo.x(), hi.x(), lo.y(), hi.y(), lo.z(), hi.z());
    }
    zones = compiled.value();
    frame_log_odds.assign(grid.voxel_count(), 0);
    frame_observed.assign(grid.voxel_count(), 0U);
    fusion_scratch.assign(grid.voxel_count(), 0);
    prior.assign(grid.voxel_count(), 0);
    frame_grid = EvidenceGrid::make(grid, {frame_log_odds.data(), frame_log_odds.size()},
                                    {frame_observed.data(), frame_observed.size()})
                     .value();
    return {};
}

SetupError MonitorCell::configure_robot(const cell::MonitorConfig& cfg, std::FILE* out) {
    std::vector<std::uint32_t> masks;
    for (const cell::CaseSettings& k : cfg.cases) {
        masks.push_back(k.zone_mask);
    }
    has_cases = !masks.empty();
    const Result<MonitoringCases, CaseError> made = has_cases
                                                        ? MonitoringCases::make(zones, {masks.data(), masks.size()})
                                                        : Result<MonitoringCases, CaseError>(
                                                              MonitoringCases::all_zones(zones));
    if (!made.ok()) {
        return failure(2, "configuration error: cases[%zu]: %s", made.error().case_number, made.error().reason);
    }
    cases = made.value();
    has_scene = !cfg.demo_scene.empty();
    if (has_scene) {
        SetupError e = read_scene(cfg, scene);
        if (e.failed()) {
            return e;
        }
    }
    if (!cfg.robot.enabled) {
        return {};
    }
    return configure_robot_model(cfg, out);
}

SetupError MonitorCell::configure_robot_model(const cell::MonitorConfig& cfg, std::FILE* out) {
    RobotModel imported_model;
    SetupError imported = import_robot(cfg, imported_model);
    if (imported.failed()) {
        return imported;
    }
    robot_image.assign(kRobotImageMaxBytes, 0U);
    const Result<std::size_t, RobotModelError> written = write_robot_image(imported_model,
                                                                           {robot_image.data(), robot_image.size()});
    if (!written.ok()) {
        return failure(2, "configuration error: robot: %s (item %zu)", written.error().reason, written.error().index);
    }
    robot_image.resize(written.value());
    const Result<LoadedRobot, RobotModelError> loaded = load_robot_image({robot_image.data(), robot_image.size()});
    if (!loaded.ok()) {  // not reached: the image was just written from a checked model
        return failure(1, "robot image: %s", loaded.error().reason);
    }
    robot = loaded.value();
    robot_mask.assign(grid.voxel_count(), 0U);
    if (has_scene && scene.robot.present) {
        if ((scene.robot.position - cfg.robot.base).norm() > 1e-9) {
            return failure(2, "configuration error: robot.base differs from the scene's robot position");
        }
        const std::string e = sim::RobotCellSimulation::make(scene, robot.model,
                                                             static_cast<std::uint8_t>(cases.count()), simulation);
        if (!e.empty()) {
            return failure(2, "configuration error: demo.scene: %s", e.c_str());
        }
    }
    const SeparationParams& sp = cfg.robot.separation;
    say(out,
        "robot: %s, %u links, %u joints, %u capsules; image %zu bytes, CRC-32 0x%08x, robot id 0x%04x; "
        "mask margin %.3f m\n",
        robot.model.name, robot.model.link_count, robot.model.joint_count, robot.model.capsule_count,
        robot_image.size(), robot.crc, robot_id(robot.crc), cfg.robot.margin_m);
    const double d_mm = cfg.robot.detection_capability_mm;
    char d_text[48] = "not stated";
    if (d_mm > 0.0) {
        static_cast<void>(std::snprintf(d_text, sizeof d_text, "d %.0f mm", d_mm));
    }
    say(out, "separation: intrusion distance C %.3f m, detection capability %s (ISO 13855: C >= %.3f m)\n",
        sp.intrusion_distance_m, d_text, cell::minimum_intrusion_distance(d_mm));
    for (std::uint8_t k = 0U; k < sp.class_count; ++k) {
        say(out, "separation: speed class %u: S_p %.3f m\n", k, protective_separation_distance(sp, k));
    }
    say(out, "separation: reduced speed below %.3f m; %zu monitoring cases\n", reduced_speed_distance(sp),
        cases.count());
    return {};
}

SetupError MonitorCell::build_prior(const cell::MonitorConfig& cfg, std::FILE* out, PriorMethod method) {
    if (cfg.prior.source == cell::PriorSource::kFile) {
        return read_prior(cfg, grid, prior, prior_payload_crc, out);
    }
    std::vector<std::int16_t> bg_lo(grid.voxel_count());
    std::vector<std::uint8_t> bg_ob(grid.voxel_count());
    EvidenceGrid bg = EvidenceGrid::make(grid, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    bg.clear();
    const sim::SimulatedFrame empty = sim::render_frame(specs, background_scene());
    for (int i = 0; i < cfg.prior.background_frames; ++i) {
        if (!fuse_background_frame(bg, frame_grid, {empty.readings.data(), empty.readings.size()}, model,
                                   {fusion_scratch.data(), fusion_scratch.size()})
                 .ok()) {
            return failure(1, "background: fusing the empty frames failed");
        }
    }
    background_observed = bg_ob;
    AccessibilityParams params;
    params.method = method;
    const AccessibilityScratchSize size = accessibility_scratch_size(grid.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    const Status st = compute_accessibility_prior(
        bg, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
        {prior.data(), prior.size()}, {});
    if (!st.ok()) {
        return failure(1, "prior: computing the accessibility prior failed: %s", to_string(st.error()));
    }
    // The payload's CRC as a prior image would hold it: the values as int16 little-endian.
    std::vector<std::uint8_t> payload(2U * prior.size());
    for (std::size_t i = 0U; i < prior.size(); ++i) {
        const auto bits = static_cast<std::uint16_t>(prior[i]);
        payload[2U * i] = static_cast<std::uint8_t>(bits & 0xFFU);
        payload[2U * i + 1U] = static_cast<std::uint8_t>(bits >> 8U);
    }
    prior_payload_crc = crc32(Span<const std::uint8_t>(payload.data(), payload.size()));
    say(out, "prior: %s accessibility prior from %d simulated empty frames\n", sim::method_name(method),
        cfg.prior.background_frames);
    return {};
}

SetupError MonitorCell::build_tables(const cell::MonitorConfig& cfg, std::FILE* out) {
    layout = sim::render_frame(specs, background_scene());
    tables.clear();
    tables.resize(specs.size());
    std::size_t total_steps = 0U;
    std::size_t total_bytes = 0U;
    const bool footprint = cfg.fusion.method == FusionMethod::kFootprint;
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        if (!cfg.sensors[s].pcd_files.empty() || footprint) {
            continue;  // recorded point clouds, and footprint fusion: fused without a table
        }
        const Status t = tables[s].build(grid, layout.readings[s]);
        if (!t.ok()) {
            return failure(1, "sensor '%s': ray table: %s", specs[s].name.c_str(), to_string(t.error()));
        }
        total_steps += tables[s].table().step_count();
        total_bytes += tables[s].storage_bytes();
    }
    SetupError views = attach_backgrounds(cfg, out);
    if (views.failed()) {
        return views;
    }
    const Span<const SensorReading> readings{layout.readings.data(), layout.readings.size()};
    // The worst-case work of one cycle (cycle.hpp); tests/bench/bench_cycle turns it into time.
    work = compute_work_bound(grid, readings, zones);
    if (footprint) {
        SetupError made = allocate_footprint_workspaces(out);
        if (made.failed()) {
            return made;
        }
        work = with_footprint_fusion(work, grid, readings, cfg.fusion.params);
    } else {
        say(out, "ray tables: %zu sensors, %zu steps (%.1f MB)\n", specs.size(), total_steps,
            static_cast<double>(total_bytes) / 1e6);
    }
    say(out, "work bound per cycle: %llu rays, %llu voxel steps, %llu grid-pass voxels, %llu zone updates",
        static_cast<unsigned long long>(work.rays), static_cast<unsigned long long>(work.voxel_steps),
        static_cast<unsigned long long>(work.grid_voxels), static_cast<unsigned long long>(work.zone_updates));
    if (footprint) {
        say(out, ", %llu footprint units", static_cast<unsigned long long>(work.footprint_units));
    }
    say(out, "\n");
    return {};
}

SetupError MonitorCell::attach_backgrounds(const cell::MonitorConfig& cfg, std::FILE* out) {
    // Commissioned views of the empty cell (cycle.background_match > 0):
    // read from prior.background_file, checked against the prior's CRC and
    // each sensor's name, size, pose and intrinsics; without one, the
    // simulated sensors' renders of the empty scene, like their tables.
    background_views.clear();
    std::vector<BackgroundSensorIdentity> expected;
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        const cell::SensorSettings& settings = cfg.sensors[s];
        expected.push_back(settings.pcd_files.empty()
                               ? background_identity(specs[s].name, layout.readings[s])
                               : point_view_identity(settings.name, cell::sensor_pose(settings),
                                                     recorded_view_grid(settings.hfov_deg, settings.vfov_deg,
                                                                        settings.width, settings.height)));
    }
    if (!cfg.prior.background_file.empty()) {
        const IoStatus st = read_background_views(cfg.prior.background_file.c_str(), prior_payload_crc, expected,
                                                  background_views);
        if (!st.ok()) {
            return failure(1, "background views: %s", st.message());
        }
        say(out, "background views: %s (%zu sensors, prior CRC 0x%08x)\n", cfg.prior.background_file.c_str(),
            background_views.size(), prior_payload_crc);
    } else {
        // A recorded (point-set) sensor's view from its render of the empty
        // scene, the frame its part of the prior is made of, as points.
        background_views.assign(specs.size(), {});
        for (std::size_t s = 0U; s < specs.size(); ++s) {
            if (cfg.sensors[s].pcd_files.empty() || !(cfg.background_match > 0.0F)) {
                continue;  // a depth sensor's view is its render; with the checks off none is compared
            }
            PointViewBuilder builder(direction_grid_of(expected[s]));
            if (!builder.add(layout.readings[s])) {
                return failure(1, "sensor '%s': its direction-grid view is refused (field of view or bins)",
                               specs[s].name.c_str());
            }
            background_views[s] = builder.values();
        }
    }
    backgrounds.assign(specs.size(), BackgroundReference{});
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        const std::vector<float>& view = background_views[s];
        if (expected[s].kind == kBackgroundViewDirectionGrid) {
            const std::size_t bins = view.size() / 2U;
            backgrounds[s].grid = direction_grid_of(expected[s]);
            backgrounds[s].depth = Span<const float>(view.data(), bins);
            backgrounds[s].nearest = Span<const float>(view.data() + bins, bins);
        } else {
            backgrounds[s].depth = view.empty() ? layout.readings[s].depth
                                                : Span<const float>(view.data(), view.size());
        }
        backgrounds[s].tolerance_m = cfg.background_tolerance_m;
        backgrounds[s].min_match_fraction = cfg.background_match;
        backgrounds[s].max_longer_pixels = cfg.background_changed_pixels;
        backgrounds[s].changed_cycles = cfg.background_changed_cycles;
    }
    if (cfg.background_match > 0.0F) {
        say(out,
            "background check: every frame must show %.0f %% of its sensor's view of the empty cell (within %.0f mm); "
            "more than %u pixels beyond it in %u frames in a row: changed background, the prior fault for good\n",
            100.0 * static_cast<double>(cfg.background_match), 1000.0 * static_cast<double>(cfg.background_tolerance_m),
            cfg.background_changed_pixels, cfg.background_changed_cycles);
    }
    return {};
}

SetupError MonitorCell::allocate_footprint_workspaces(std::FILE* out) {
    // One workspace per sensor (the sensors can then run as parallel tasks),
    // allocated here once: the cycle allocates nothing.
    footprint_storage.clear();
    footprint_storage.resize(specs.size());
    footprint_spaces.assign(specs.size(), FootprintWorkspace{});
    // Each workspace's pyramid holds the largest image: fuse_frame_footprint
    // checks every workspace against every sensor's image.
    std::size_t cells = 0U;
    for (const sim::SensorSpec& spec : specs) {
        cells = std::max(cells, depth_pyramid_cells(spec.width, spec.height));
    }
    std::size_t bytes = 0U;
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        FootprintStorage& st = footprint_storage[s];
        st.pyramid_min.assign(cells, 0.0F);
        st.pyramid_max.assign(cells, 0.0F);
        st.pyramid_invalid.assign(cells, 0U);
        st.opinions.assign(grid.voxel_count(), 0);
        footprint_spaces[s] = FootprintWorkspace{{st.pyramid_min.data(), cells},
                                                 {st.pyramid_max.data(), cells},
                                                 {st.pyramid_invalid.data(), cells},
                                                 {st.opinions.data(), st.opinions.size()}};
        bytes += cells * (2U * sizeof(float) + 1U) + st.opinions.size() * sizeof(std::int16_t);
    }
    // Footprint tables, made here from the cameras' poses (the cycle reads them): only when every
    // sensor is a camera, so that sensor i is fused through workspace i, whose table is its own.
    bool all_cameras = true;
    for (const SensorReading& r : layout.readings) {
        all_cameras = all_cameras && is_depth_image(r.kind);
    }
    std::size_t entries = 0U;
    for (std::size_t s = 0U; s < specs.size() && all_cameras; ++s) {
        FootprintStorage& st = footprint_storage[s];
        st.entries.resize(footprint_table_entries(grid, layout.readings[s]));
        st.table = FootprintTable(Span<FootprintEntry>(st.entries.data(), st.entries.size()));
        const Status made = st.table.make(grid, layout.readings[s], model);
        if (!made.ok()) {
            return failure(1, "sensor '%s': footprint table: %s", specs[s].name.c_str(), to_string(made.error()));
        }
        footprint_spaces[s].table = &st.table;
        entries += st.entries.size();
    }
    // Which kernel runs depends on the CPU: timing measured on one machine holds for another only with the same.
    const bool avx2 = resolve_fusion_kernel(FootprintParams{}.kernel) ==
                      FusionKernel::kAvx2;  // no configuration key: the default
    say(out,
        "footprint fusion: %zu sensors, no ray tables; workspaces %.1f MB, footprint tables %.1f MB (%zu voxels in "
        "view)%s; hit pass and pooling: %s\n",
        specs.size(), static_cast<double>(bytes) / 1e6, static_cast<double>(entries * sizeof(FootprintEntry)) / 1e6,
        entries, all_cameras ? "" : "; none: not every sensor is a camera", avx2 ? "AVX2 (this CPU has it)" : "scalar");
    return {};
}

void MonitorCell::write_footprint_summary(std::FILE* out) const {
    std::uint64_t makes = 0U;
    std::size_t made_tables = 0U;
    for (const FootprintStorage& st : footprint_storage) {
        makes += st.table.makes();
        made_tables += st.table.entries().empty() ? 0U : 1U;
    }
    if (made_tables > 0U) {
        static_cast<void>(std::fprintf(out, "summary: footprint tables: %zu, made %llu times (%s)\n", made_tables,
                                       static_cast<unsigned long long>(makes),
                                       makes == made_tables ? "once each, at start" : "again during the run"));
    }
}

}  // namespace cellguard::monitor
