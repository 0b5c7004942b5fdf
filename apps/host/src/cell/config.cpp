// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's TOML configuration loader (toml++).
#include "cellguard/host/cell/config.hpp"

#include <sys/stat.h>
#include <toml++/toml.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "config_loader.hpp"

namespace cellguard::cell {
using config_detail::Loader;
using config_detail::ms_to_us;
namespace {

void load_grid(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const std::string p = "grid";
    const toml::table& t = L.table(root, "", "grid");
    L.check_keys(t, p, {"origin", "voxel_size", "dims"});
    c.grid.origin = L.vec3(t, p, "origin");
    c.grid.voxel_size = L.number(t, p, "voxel_size");
    L.positive(t, p, "voxel_size", c.grid.voxel_size);
    const toml::node& d = L.require(t, p, "dims");
    const toml::array* a = d.as_array();
    if (a == nullptr || a->size() != 3U) {
        L.fail(d.source(), "grid.dims", "expected an array of 3 integers");
    }
    for (std::size_t i = 0U; i < 3U; ++i) {
        const std::optional<std::int64_t> v = (*a)[i].value_exact<std::int64_t>();
        if (!v || *v < 1 || *v > static_cast<std::int64_t>(kMaxDimension)) {
            L.fail((*a)[i].source(), "grid.dims", "expected integers in 1.." + std::to_string(kMaxDimension));
        }
        c.grid.dims[i] = static_cast<int>(*v);
    }
    const Result<GridGeometry> g = GridGeometry::make(
        c.grid.origin, c.grid.voxel_size,
        GridDims{static_cast<std::int32_t>(c.grid.dims[0]), static_cast<std::int32_t>(c.grid.dims[1]),
                 static_cast<std::int32_t>(c.grid.dims[2])});
    if (!g.ok()) {
        L.fail(t.source(), "grid", std::string("not a valid grid: ") + to_string(g.error()));
    }
}

void load_zones(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const toml::node* n = root.get("zones");
    if (n == nullptr || !n->is_array_of_tables() || n->as_array()->empty()) {
        L.fail(n != nullptr ? n->source() : root.source(), "zones", "expected one or more [[zones]] tables");
    }
    const toml::array& arr = *n->as_array();
    if (arr.size() > kMaxZonesInFrame) {
        L.fail(n->source(), "zones",
               "at most " + std::to_string(kMaxZonesInFrame) + " zones (one safety CAN frame carries 16)");
    }
    for (std::size_t i = 0U; i < arr.size(); ++i) {
        const toml::table& t = *arr.get(i)->as_table();
        const std::string p = "zones[" + std::to_string(i) + "]";
        L.check_keys(t, p,
                     {"name", "kind", "shape", "min", "max", "polygon", "z_min", "z_max", "min_foreground_voxels",
                      "max_unseen_voxels"});
        ZoneSettings z;
        z.line = static_cast<int>(t.source().begin.line);
        z.name = L.string(t, p, "name");
        const std::string kind = L.string(t, p, "kind");
        if (kind == "protective") {
            z.zone.kind = ZoneKind::kProtective;
        } else if (kind == "warning") {
            z.zone.kind = ZoneKind::kWarning;
        } else {
            L.fail(t.get("kind")->source(), p + ".kind", R"(expected "protective" or "warning", got ")" + kind + "\"");
        }
        const std::string shape = L.string(t, p, "shape");
        if (shape == "box") {
            z.zone.shape = ZoneShape::kBox;
            z.zone.box_min = L.vec3(t, p, "min");
            z.zone.box_max = L.vec3(t, p, "max");
            if (!(z.zone.box_min.array() < z.zone.box_max.array()).all()) {
                L.fail(t.get("max")->source(), p + ".max", "every coordinate must be greater than in min");
            }
        } else if (shape == "prism") {
            z.zone.shape = ZoneShape::kPrism;
            const toml::node& poly = L.require(t, p, "polygon");
            const toml::array* pa = poly.as_array();
            if (pa == nullptr || pa->size() < 3U || pa->size() > kMaxPolygonVertices) {
                L.fail(poly.source(), p + ".polygon",
                       "expected 3.." + std::to_string(kMaxPolygonVertices) + " vertices [x, y]");
            }
            for (std::size_t k = 0U; k < pa->size(); ++k) {
                const std::vector<double> v = L.numbers(*pa->get(k), p + ".polygon[" + std::to_string(k) + "]", 2U);
                z.zone.polygon[k] = PolygonVertex{v[0], v[1]};
            }
            z.zone.polygon_size = pa->size();
            z.zone.z_min = L.number(t, p, "z_min");
            z.zone.z_max = L.number(t, p, "z_max");
            if (!(z.zone.z_min < z.zone.z_max)) {
                L.fail(t.get("z_max")->source(), p + ".z_max", "must be greater than z_min");
            }
        } else {
            L.fail(t.get("shape")->source(), p + ".shape", R"(expected "box" or "prism", got ")" + shape + "\"");
        }
        z.zone.min_foreground_voxels = static_cast<std::uint32_t>(
            L.integer_or(t, p, "min_foreground_voxels", 1, 1000000, 1));
        z.zone.max_unseen_voxels = static_cast<std::uint32_t>(L.integer_or(t, p, "max_unseen_voxels", 0, 1000000, 0));
        c.zones.push_back(z);
    }
}

/// Probability thresholds by default: the paper's figures' t_f and P(fore) >= 0.05 (P(acc) >= 0.1).
constexpr double kDefaultForegroundProbability = 0.73;  // log-odds 255
constexpr double kDefaultAccessibleMinPFore = 0.05;     // log-odds -754

/// The old raw log-odds key @p old of [thresholds] is refused, naming @p replacement and the probability its value meant.
void refuse_log_odds_key(const Loader& L, const toml::table& t, const char* old, const char* replacement) {
    const toml::node* n = t.get(old);
    if (n == nullptr) {
        return;
    }
    std::string meant;
    if (const std::optional<std::int64_t> v = n->value_exact<std::int64_t>();
        v && *v >= kLogOddsMin && *v <= kLogOddsMax) {
        char text[64];
        static_cast<void>(std::snprintf(text, sizeof text, " (%lld log-odds units is %.6g)", static_cast<long long>(*v),
                                        probability_from_log_odds(static_cast<std::int16_t>(*v))));
        meant = text;
    }
    L.fail(n->source(), Loader::join("thresholds", old),
           std::string("raw log-odds are no longer accepted; write thresholds.") + replacement + " as a probability" +
               meant);
}

/// The [thresholds] table (optional): t_f and the accessible-space minimum
/// as probabilities, stored as log-odds rounded to the nearest 1/256 nat
/// (log_odds_from_probability: 0.73 -> 255, 0.05 -> -754).
void load_thresholds(const Loader& L, const toml::table& root, MonitorConfig& c) {
    if (!root.contains("thresholds")) {
        return;
    }
    const std::string p = "thresholds";
    const toml::table& t = L.table(root, "", "thresholds");
    refuse_log_odds_key(L, t, "foreground", "foreground_probability");
    refuse_log_odds_key(L, t, "accessible_min_prior", "accessible_min_p_fore");
    L.check_keys(t, p, {"foreground_probability", "accessible_min_p_fore"});
    const double tf = L.number_or(t, p, "foreground_probability", kDefaultForegroundProbability);
    if (!(tf > 0.0 && tf < 1.0)) {
        L.fail(t.get("foreground_probability")->source(), "thresholds.foreground_probability",
               "expected a probability strictly between 0 and 1");
    }
    c.foreground_threshold = log_odds_from_probability(tf);
    const double am = L.number_or(t, p, "accessible_min_p_fore", kDefaultAccessibleMinPFore);
    if (!(am > 0.0 && am <= 0.5)) {
        L.fail(t.get("accessible_min_p_fore")->source(), "thresholds.accessible_min_p_fore",
               "expected a probability in (0, 0.5] (a prior's P(fore) = P(acc) / 2 is at most 0.5)");
    }
    c.accessible_min_prior = log_odds_from_probability(am);
}

/// The [prior] table: a prior image file or a prior built from simulated background frames.
void load_prior(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir) {
    const toml::table& t = L.table(root, "", "prior");
    L.check_keys(t, "prior", {"source", "file", "background_file", "background_frames"});
    const std::string src = L.string(t, "prior", "source");
    if (src == "file") {
        c.prior.source = PriorSource::kFile;
        c.prior.file = L.string(t, "prior", "file");
        if (c.prior.file.empty()) {
            L.fail(t.get("file")->source(), "prior.file", "must not be empty");
        }
        if (c.prior.file[0] != '/') {
            c.prior.file = base_dir + "/" + c.prior.file;
        }
        if (t.contains("background_file")) {  // the sensors' commissioned views, written with the prior
            c.prior.background_file = L.string(t, "prior", "background_file");
            if (c.prior.background_file.empty()) {
                L.fail(t.get("background_file")->source(), "prior.background_file", "must not be empty");
            }
            if (c.prior.background_file[0] != '/') {
                c.prior.background_file = base_dir + "/" + c.prior.background_file;
            }
        }
    } else if (src == "simulated-background") {
        c.prior.source = PriorSource::kSimulatedBackground;
        if (t.contains("background_file")) {
            L.fail(t.get("background_file")->source(), "prior.background_file",
                   "only with source = \"file\": the simulated background makes its views in memory");
        }
        c.prior.background_frames = static_cast<int>(L.integer_or(t, "prior", "background_frames", 1, 1000, 8));
        // The monitor's prior is probabilistic: space seen free must fall below t_E (min_background_frames).
        const std::uint32_t need = min_background_frames(AccessibilityParams{}, SensorModelTable{});
        if (static_cast<std::uint32_t>(c.prior.background_frames) < need) {
            L.fail(t.get("background_frames")->source(), "prior.background_frames",
                   "at least " + std::to_string(need) + " frames for the probabilistic prior, got " +
                       std::to_string(c.prior.background_frames));
        }
    } else {
        L.fail(t.get("source")->source(), "prior.source",
               R"(expected "file" or "simulated-background", got ")" + src + "\"");
    }
}

/// The [fusion] table (optional): the fusion method of depth images and
/// footprint fusion's exact step and cores.
void load_fusion(const Loader& L, const toml::table& root, MonitorConfig& c) {
    if (!root.contains("fusion")) {
        return;
    }
    const std::string p = "fusion";
    const toml::table& t = L.table(root, "", "fusion");
    // Footprint fusion's per-frame budget is gone (its work is bounded by the cameras and the grid
    // now): a file that still sets it is told so, not silently changed.
    if (t.contains("exact_pixel_budget")) {
        L.fail(t.get("exact_pixel_budget")->source(), Loader::join(p, "exact_pixel_budget"),
               "no longer exists: footprint fusion has no per-frame budget (its work is bounded by the cameras and "
               "the grid, exact_footprint_max per voxel); delete the key");
    }
    L.check_keys(t, p, {"method", "exact_footprint_max", "threads"});
    FusionSettings& f = c.fusion;
    f.line = static_cast<int>(t.source().begin.line);
    const std::string method = L.string_or(t, p, "method", "ray");
    if (method == "ray") {
        f.method = FusionMethod::kRay;
    } else if (method == "footprint") {
        f.method = FusionMethod::kFootprint;
    } else {
        L.fail(t.get("method")->source(), "fusion.method", R"(expected "ray" or "footprint", got ")" + method + "\"");
    }
    // The exact step's limit and the cores are footprint fusion's: given with "ray" they would silently do nothing.
    for (const char* key : {"exact_footprint_max", "threads"}) {
        if (f.method == FusionMethod::kRay && t.contains(key)) {
            L.fail(t.get(key)->source(), Loader::join(p, key), R"(applies only to method = "footprint")");
        }
    }
    f.params.exact_footprint_max = static_cast<std::uint32_t>(
        L.integer_or(t, p, "exact_footprint_max", 0, 65536, f.params.exact_footprint_max));
    f.threads = static_cast<int>(L.integer_or(t, p, "threads", 1, kMaxFusionThreads, 1));
}

/// The [depth_filter] table (optional): the depth filter before fusion,
/// every filter off unless given; one that is on needs the reason.
void load_depth_filter(const Loader& L, const toml::table& root, MonitorConfig& c) {
    if (!root.contains("depth_filter")) {
        return;
    }
    const std::string p = "depth_filter";
    const toml::table& t = L.table(root, "", "depth_filter");
    L.check_keys(t, p,
                 {"edge_jump_percent", "edge_jump_min_m", "edge_radius", "background_tolerance_percent",
                  "speckle_min_neighbours", "reason"});
    DepthConditioning& f = c.depth_filter.filter;
    const auto bounded = [&](const char* key, double hi, const char* expected) {
        const double v = L.number_or(t, p, key, 0.0);
        if (!(v >= 0.0 && v <= hi)) {
            L.fail(t.get(key)->source(), Loader::join(p, key), expected);
        }
        return v;
    };
    f.edge_jump_per_m = bounded("edge_jump_percent", 50.0, "expected 0 to 50 (per cent of the depth)") / 100.0;
    f.edge_jump_min_m = bounded("edge_jump_min_m", 1.0, "expected 0 to 1 (metres)");
    f.background_tolerance_per_m = bounded("background_tolerance_percent", 20.0,
                                           "expected 0 to 20 (per cent of the empty cell's depth)") /
                                   100.0;
    f.edge_radius = static_cast<int>(L.integer_or(t, p, "edge_radius", 1, 4, 1));
    f.speckle_min_neighbours = static_cast<int>(L.integer_or(t, p, "speckle_min_neighbours", 0, 8, 0));
    const bool edge = f.edge_jump_per_m > 0.0 || f.edge_jump_min_m > 0.0;
    if (!edge && t.contains("edge_radius")) {
        L.fail(t.get("edge_radius")->source(), "depth_filter.edge_radius",
               "applies only with the edge filter on (edge_jump_percent or edge_jump_min_m above 0)");
    }
    c.depth_filter.reason = L.string_or(t, p, "reason", "");
    const bool stated = c.depth_filter.reason.find_first_not_of(" \t") != std::string::npos;
    if (f.on() && !stated) {
        L.fail(t.source(), "depth_filter.reason",
               "a filter is on: state why, and the detection capability measured with it (cellguard-detection), "
               "in reason = \"...\"");
    }
    if (!f.on() && t.contains("reason")) {
        L.fail(t.get("reason")->source(), "depth_filter.reason", "every filter is off: delete the reason");
    }
}

/// The [can] table's clock-rate check against the PLC's samples (off without command_period_ms).
void load_clock_rate(const Loader& L, const toml::table& t, MonitorConfig& c) {
    const std::string p = "can";
    ClockRateConfig& r = c.can.clock_rate;
    r.nominal_period_us = static_cast<std::uint64_t>(L.integer_or(t, p, "command_period_ms", 0, 10000, 0)) * 1000U;
    r.window_periods = static_cast<std::uint32_t>(L.integer_or(t, p, "clock_rate_window", 10, 100000, 50));
    const double percent = L.number_or(t, p, "clock_rate_tolerance_percent", 2.0);
    if (!(percent >= 0.1 && percent <= 50.0)) {
        L.fail(t.get("clock_rate_tolerance_percent")->source(), "can.clock_rate_tolerance_percent",
               "expected 0.1 .. 50 (percent)");
    }
    r.tolerance_ppm = static_cast<std::uint32_t>(std::lround(percent * 10000.0));
}

/// The [can] table: the CAN interface or log and the safety channel's IDs.
void load_can(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const toml::table& t = L.table(root, "", "can");
    const std::string p = "can";
    L.check_keys(t, p,
                 {"interface", "log_file", "log_interface", "safety_id", "diagnostics_id", "safety_data_id",
                  "diagnostics_data_id", "data_id_mode", "separation_id", "separation_data_id", "command_id",
                  "command_period_ms", "clock_rate_window", "clock_rate_tolerance_percent"});
    c.can.interface_name = L.string_or(t, p, "interface", "");
    c.can.log_file = L.string_or(t, p, "log_file", c.can.log_file);
    c.can.log_interface_name = L.string_or(t, p, "log_interface", c.can.log_interface_name);
    if (c.can.log_interface_name.empty() || c.can.log_interface_name.size() > 15U ||
        c.can.log_interface_name.find_first_of(" ()#\t") != std::string::npos) {
        L.fail(t.get("log_interface")->source(), "can.log_interface",
               "expected 1..15 characters without blanks, '(', ')' or '#'");
    }
    if (c.can.interface_name.empty() && c.can.log_file.empty()) {
        L.fail(t.source(), "can.log_file", "give an interface or a log file");
    }
    SafetyChannelConfig& ch = c.can.channel;
    ch.safety_can_id = static_cast<std::uint32_t>(L.integer_or(t, p, "safety_id", 0, 0x7FE, kDefaultSafetyCanId));
    ch.diagnostics_can_id = static_cast<std::uint32_t>(
        L.integer_or(t, p, "diagnostics_id", 0, 0x7FF, kDefaultDiagnosticsCanId));
    ch.safety_data_id = static_cast<std::uint16_t>(
        L.integer_or(t, p, "safety_data_id", 0, 0xFFFF, kDefaultSafetyDataId));
    ch.diagnostics_data_id = static_cast<std::uint16_t>(
        L.integer_or(t, p, "diagnostics_data_id", 0, 0xFFFF, kDefaultDiagnosticsDataId));
    const std::string mode = L.string_or(t, p, "data_id_mode", "both");
    if (mode == "both") {
        ch.data_id_mode = E2eP01DataIdMode::kBoth;
    } else if (mode == "alt") {
        ch.data_id_mode = E2eP01DataIdMode::kAlt;
    } else if (mode == "low") {
        ch.data_id_mode = E2eP01DataIdMode::kLow;
    } else if (mode == "nibble") {
        ch.data_id_mode = E2eP01DataIdMode::kNibble;
    } else {
        L.fail(t.get("data_id_mode")->source(), "can.data_id_mode",
               R"(expected "both", "alt", "low" or "nibble", got ")" + mode + "\"");
    }
    ch.separation_can_id = static_cast<std::uint32_t>(
        L.integer_or(t, p, "separation_id", 0, 0x7FF, ch.separation_can_id));
    ch.separation_data_id = static_cast<std::uint16_t>(
        L.integer_or(t, p, "separation_data_id", 0, 0xFFFF, ch.separation_data_id));
    c.can.command.base_can_id = static_cast<std::uint32_t>(
        L.integer_or(t, p, "command_id", 0, 0x7FA, c.can.command.base_can_id));
    c.can.command.data_id_mode = ch.data_id_mode;
    load_clock_rate(L, t, c);
    if (!check_channel_config(ch).ok() || !check_channels_compatible(ch, c.can.command).ok()) {
        L.fail(
            t.source(), "can",
            "invalid channel: the CAN IDs (safety, safety + 1, diagnostics, separation, command_id .. command_id + 5) "
            "must differ and the data IDs must be valid for the mode and distinguishable");
    }
}

/// The background checks of the [cycle] table (after [sensors]: it checks them).
void load_background_checks(const Loader& L, const toml::table& t, MonitorConfig& c) {
    const double match = L.number_or(t, "cycle", "background_match", kDefaultBackgroundMatch);
    // An absent key is reported at the table (its default is on).
    const toml::source_region where = t.contains("background_match") ? t.get("background_match")->source() : t.source();
    if (!(match >= 0.0 && match <= 1.0)) {
        L.fail(where, "cycle.background_match", "expected 0 (off) to 1");
    }
    // Recorded (pcd_files) sensors are compared per direction bin of their
    // view (SR-BKG-009): with a prior file, the view must come from the
    // recorded frames (prior.background_file), not from the simulator.
    for (const SensorSettings& s : c.sensors) {
        if (match > 0.0 && !s.pcd_files.empty() && c.prior.source == PriorSource::kFile &&
            c.prior.background_file.empty()) {
            L.fail(where, "cycle.background_match",
                   "is on, but recorded sensor '" + s.name +
                       "' has no view of the empty cell: give prior.background_file (written by cellguard-prior "
                       "--write-background from the recorded frames), or set background_match = 0");
        }
    }
    c.background_match = static_cast<float>(match);
    const double tolerance = L.number_or(t, "cycle", "background_tolerance_m", 0.05);
    if (!(tolerance > 0.0 && tolerance <= 1.0)) {
        L.fail(t.get("background_tolerance_m")->source(), "cycle.background_tolerance_m",
               "expected more than 0, at most 1 m");
    }
    c.background_tolerance_m = static_cast<float>(tolerance);
    c.background_changed_pixels = static_cast<std::uint32_t>(
        L.integer_or(t, "cycle", "background_changed_pixels", 0, 10000000, kDefaultBackgroundChangedPixels));
    c.background_changed_cycles = static_cast<std::uint32_t>(
        L.integer_or(t, "cycle", "background_changed_cycles", 0, 1000, kDefaultBackgroundChangedCycles));
}

/// The [cycle] table: period, budget, frame age, background checks (after [sensors]: it checks them).
void load_cycle(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const toml::table& t = L.table(root, "", "cycle");
    L.check_keys(
        t, "cycle",
        {"period_ms", "budget_ms", "max_frame_age_ms", "table_check_kib", "zone_check_kib", "max_repeated_frames",
         "background_match", "background_tolerance_m", "background_changed_pixels", "background_changed_cycles"});
    const double period = L.number(t, "cycle", "period_ms");
    if (!(period >= 1.0 && period <= 10000.0)) {
        L.fail(t.get("period_ms")->source(), "cycle.period_ms", "expected 1..10000 ms");
    }
    c.period_us = ms_to_us(period);
    const double budget = L.number_or(t, "cycle", "budget_ms", period);
    if (!(budget > 0.0 && budget <= period)) {
        L.fail(t.get("budget_ms")->source(), "cycle.budget_ms", "expected more than 0 and at most period_ms");
    }
    c.budget_us = ms_to_us(budget);
    const double age = L.number_or(t, "cycle", "max_frame_age_ms", 2.0 * period);
    if (!(age > 0.0 && age <= 60000.0)) {
        L.fail(t.get("max_frame_age_ms")->source(), "cycle.max_frame_age_ms", "expected more than 0, at most 60000");
    }
    c.max_frame_age_us = ms_to_us(age);
    c.table_check_bytes = static_cast<std::size_t>(L.integer_or(t, "cycle", "table_check_kib", 1, 65536, 1024)) * 1024U;
    c.zone_check_bytes = static_cast<std::size_t>(L.integer_or(t, "cycle", "zone_check_kib", 1, 65536, 16)) * 1024U;
    c.max_repeated_frames = static_cast<std::uint32_t>(
        L.integer_or(t, "cycle", "max_repeated_frames", 0, 1000, kDefaultMaxRepeatedFrames));
    load_background_checks(L, t, c);
}

/// The [restart_interlock] table: delay, reset, recovery after a fault.
void load_restart_interlock(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const toml::table& t = L.table(root, "", "restart_interlock");
    const std::string p = "restart_interlock";
    L.check_keys(t, p, {"delay_ms", "reset_required", "fault_recovery_cycles"});
    const double delay = L.number(t, p, "delay_ms");
    if (!(delay >= 0.0 && delay <= 600000.0)) {
        L.fail(t.get("delay_ms")->source(), p + ".delay_ms", "expected 0..600000 ms");
    }
    c.restart_delay_us = ms_to_us(delay);
    c.reset_required = L.boolean_or(t, p, "reset_required", true);  // off only with opt_out.reset_required
    c.fault_recovery_cycles = static_cast<std::uint32_t>(L.integer_or(t, p, "fault_recovery_cycles", 1, 100000, 10));
}

/// The [demo] table (optional): the number of demo cycles.
void load_demo(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir) {
    if (root.contains("demo")) {
        const toml::table& t = L.table(root, "", "demo");
        L.check_keys(t, "demo", {"cycles", "scene"});
        c.demo_cycles = static_cast<int>(L.integer_or(t, "demo", "cycles", 1, 1000000, 60));
        c.demo_scene = L.string_or(t, "demo", "scene", "");
        if (!c.demo_scene.empty() && c.demo_scene[0] != '/' && c.demo_scene.rfind("builtin:", 0) != 0) {
            c.demo_scene.insert(0U, base_dir + "/");
        }
    }
}

/// The tables after [grid], [sensors] and [zones].
void load_rest(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir) {
    load_thresholds(L, root, c);
    load_prior(L, root, c, base_dir);
    load_fusion(L, root, c);
    load_depth_filter(L, root, c);
    load_can(L, root, c);
    load_cycle(L, root, c);
    load_restart_interlock(L, root, c);
    load_demo(L, root, c, base_dir);
    config_detail::load_cases(L, root, c);
    config_detail::load_robot(L, root, c, base_dir);
    config_detail::load_opt_out(L, root, c);
}

}  // namespace

ConfigLoad parse_monitor_config(const std::string& text, const std::string& source_name, const std::string& base_dir) {
    ConfigLoad out;
    try {
        const toml::table root = toml::parse(text, source_name);
        const Loader L(source_name);
        L.check_keys(root, "",
                     {"grid", "sensors", "zones", "thresholds", "prior", "fusion", "depth_filter", "can", "cycle",
                      "restart_interlock", "demo", "cases", "robot", "separation", "speed_classes", "opt_out"});
        MonitorConfig c;
        c.source = source_name;
        load_grid(L, root, c);
        config_detail::load_sensors(L, root, c, base_dir);
        load_zones(L, root, c);
        load_rest(L, root, c, base_dir);
        out.config = c;
        out.ok = true;
    } catch (const toml::parse_error& e) {
        out.error = host::toml_syntax_error(source_name, e);
    } catch (const host::TomlError& e) {
        out.error = e.message;
    }
    return out;
}

ConfigLoad load_monitor_config(const std::string& path) {
    std::string text;
    std::string dir;
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        ConfigLoad out;
        out.error = path + ": cannot open the configuration file: " + std::strerror(errno);
        return out;
    }
    if (!S_ISREG(st.st_mode)) {  // a directory opens as an empty stream: say so, not "grid: missing table"
        ConfigLoad out;
        out.error = path + ": not a configuration file (" +
                    (S_ISDIR(st.st_mode) ? "a directory" : "not a regular file") +
                    "); give a TOML file, e.g. apps/monitor/config/paper-cell.toml";
        return out;
    }
    if (!host::read_text_file(path, text, dir)) {
        ConfigLoad out;
        out.error = path + ": cannot open the configuration file";
        return out;
    }
    return parse_monitor_config(text, path, dir);
}

MonitorConfig demo_config() {
    const ConfigLoad l = parse_monitor_config(demo_config_text(), "<built-in demo config>");
    if (!l.ok) {  // the built-in text is tested by test_monitor_config.cpp
        static_cast<void>(
            std::fprintf(stderr, "cellguard-monitor: built-in demo configuration: %s\n", l.error.c_str()));
        std::abort();
    }
    return l.config;
}

MonitorConfig robot_cell_demo_config() {
    const ConfigLoad l = parse_monitor_config(builtin_text("robot-cell.toml"), "<built-in robot-cell config>");
    if (!l.ok) {  // the built-in text is tested by test_monitor_config.cpp
        static_cast<void>(
            std::fprintf(stderr, "cellguard-monitor: built-in robot-cell configuration: %s\n", l.error.c_str()));
        std::abort();
    }
    return l.config;
}

bool read_config_text(const std::string& path, std::string& text) {
    if (path.rfind("builtin:", 0) == 0) {
        const char* t = builtin_text(path.substr(8U));
        if (t == nullptr) {
            return false;
        }
        text = t;
        return true;
    }
    std::string dir;
    return host::read_text_file(path, text, dir);
}

Eigen::Isometry3d sensor_pose(const SensorSettings& s) {
    if (s.has_target) {
        sim::SensorSpec spec;
        spec.position = s.position;
        spec.target = s.target;
        return spec.pose();
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = s.rotation.normalized().toRotationMatrix();
    pose.translation() = s.position;
    return pose;
}

PinholeIntrinsics sensor_intrinsics(const SensorSettings& s) {
    sim::SensorSpec spec;
    spec.width = s.width;
    spec.height = s.height;
    spec.hfov_deg = s.hfov_deg;
    spec.vfov_deg = s.vfov_deg;
    if (s.intrinsics_source != IntrinsicsSource::kFieldOfView) {
        spec.set_intrinsics(s.fx, s.fy, s.cx, s.cy);
    }
    return spec.intrinsics();
}

}  // namespace cellguard::cell
