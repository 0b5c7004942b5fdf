// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's start-up: sensors, grid, zones, prior, ray tables (monitor_cell.hpp).
#include "cellguard/monitor/monitor_cell.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/io/prior_files.hpp"
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

// The prior image file of @p cfg, copied into @p prior.
SetupError read_prior(const cell::MonitorConfig& cfg, const GridGeometry& g, std::vector<std::int16_t>& prior,
                      std::FILE* out) {
    std::vector<std::uint8_t> bytes;
    PriorImageView view;
    const IoStatus st = read_prior_image_file(cfg.prior.file.c_str(), g, bytes, view);
    if (!st.ok()) {
        return failure(1, "prior: %s", st.message());
    }
    if (!view.copy_to({prior.data(), prior.size()}).ok()) {
        return failure(1, "prior: %s does not fit the grid", cfg.prior.file.c_str());
    }
    say(out, "prior: %s\n", cfg.prior.file.c_str());
    return {};
}

}  // namespace

sim::SensorSpec to_spec(const cell::SensorSettings& s, bool simulated_background, std::string& error) {
    sim::SensorSpec spec;
    spec.name = s.name;
    spec.position = s.position;
    spec.width = s.width;
    spec.height = s.height;
    spec.hfov_deg = s.hfov_deg;
    spec.vfov_deg = s.vfov_deg;
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
        return failure(2, "configuration error: line %d: zone '%s': %s (%s)", z.line, z.name.c_str(), zone_error.reason,
                       to_string(zone_error.code));
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

SetupError MonitorCell::build_prior(const cell::MonitorConfig& cfg, std::FILE* out) {
    if (cfg.prior.source == cell::PriorSource::kFile) {
        return read_prior(cfg, grid, prior, out);
    }
    std::vector<std::int16_t> bg_lo(grid.voxel_count());
    std::vector<std::uint8_t> bg_ob(grid.voxel_count());
    EvidenceGrid bg = EvidenceGrid::make(grid, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    bg.clear();
    const sim::SimulatedFrame empty = sim::render_frame(specs, sim::reference_scene());
    for (int i = 0; i < cfg.prior.background_frames; ++i) {
        if (!fuse_background_frame(bg, frame_grid, {empty.readings.data(), empty.readings.size()}, model,
                                   {fusion_scratch.data(), fusion_scratch.size()})
                 .ok()) {
            return failure(1, "background: fusing the empty frames failed");
        }
    }
    AccessibilityParams params;
    const AccessibilityScratchSize size = accessibility_scratch_size(grid.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    const Status st = compute_accessibility_prior(
        bg, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
        {prior.data(), prior.size()}, {});
    if (!st.ok()) {
        return failure(1, "prior: computing the accessibility prior failed: %s", to_string(st.error()));
    }
    say(out, "prior: probabilistic accessibility prior from %d simulated empty frames\n", cfg.prior.background_frames);
    return {};
}

SetupError MonitorCell::build_tables(const cell::MonitorConfig& cfg, std::FILE* out) {
    layout = sim::render_frame(specs, sim::reference_scene());
    tables.clear();
    tables.resize(specs.size());
    std::size_t total_steps = 0U;
    std::size_t total_bytes = 0U;
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        if (!cfg.sensors[s].pcd_files.empty()) {
            continue;  // recorded point clouds: fused without a table
        }
        const Status t = tables[s].build(grid, layout.readings[s]);
        if (!t.ok()) {
            return failure(1, "sensor '%s': ray table: %s", specs[s].name.c_str(), to_string(t.error()));
        }
        total_steps += tables[s].table().step_count();
        total_bytes += tables[s].storage_bytes();
    }
    // Commissioned views of the empty cell (cycle.background_match > 0): the
    // simulated sensors' renders of the reference scene, like their tables.
    backgrounds.assign(specs.size(), BackgroundReference{});
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        backgrounds[s].depth = layout.readings[s].depth;
        backgrounds[s].tolerance_m = cfg.background_tolerance_m;
        backgrounds[s].min_match_fraction = cfg.background_match;
    }
    if (cfg.background_match > 0.0F) {
        say(out,
            "background check: every frame must show %.0f %% of its sensor's view of the empty cell (within %.0f mm)\n",
            100.0 * static_cast<double>(cfg.background_match),
            1000.0 * static_cast<double>(cfg.background_tolerance_m));
    }
    say(out, "ray tables: %zu sensors, %zu steps (%.1f MB)\n", specs.size(), total_steps,
        static_cast<double>(total_bytes) / 1e6);
    // The worst-case work of one cycle (cycle.hpp); tests/bench/bench_cycle turns it into time.
    const CycleWorkBound work = compute_work_bound(grid, {layout.readings.data(), layout.readings.size()}, zones);
    say(out, "work bound per cycle: %llu rays, %llu voxel steps, %llu grid-pass voxels, %llu zone updates\n",
        static_cast<unsigned long long>(work.rays), static_cast<unsigned long long>(work.voxel_steps),
        static_cast<unsigned long long>(work.grid_voxels), static_cast<unsigned long long>(work.zone_updates));
    return {};
}

}  // namespace cellguard::monitor
