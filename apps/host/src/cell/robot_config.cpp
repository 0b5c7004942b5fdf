// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor configuration's robot side: monitoring cases, the robot and
// its command, speed and separation monitoring.
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "cellguard/safety/robot_command.hpp"
#include "config_loader.hpp"

namespace cellguard::cell {

double minimum_mask_margin(const RobotSettings& robot, std::uint64_t period_us) {
    constexpr double kReachForResolution = 2.0;  // metres from a joint to the farthest robot point, at most
    const double motion = robot.separation.classes[0].robot_speed_mps *
                          (static_cast<double>(robot.max_command_age_us + period_us) * 1e-6);
    const double resolution = static_cast<double>(robot.joints.size()) * 0.5 * kRevoluteJointUnitRad *
                              kReachForResolution;
    return motion + robot.separation.sensing_uncertainty_m + resolution;
}

std::uint64_t command_age_limit_us(const MonitorConfig& cfg) {
    return cfg.robot.enabled ? cfg.robot.max_command_age_us : 2U * cfg.period_us;
}

namespace config_detail {
namespace {

/// The zone mask of case table @p t from its zone names.
std::uint32_t case_zone_mask(const Loader& L, const toml::table& t, const std::string& p, const MonitorConfig& c,
                             std::vector<std::string>& names) {
    const toml::node& n = L.require(t, p, "zones");
    const toml::array* a = n.as_array();
    if (a == nullptr || a->empty()) {
        L.fail(n.source(), p + ".zones", "expected an array of one or more zone names");
    }
    std::uint32_t mask = 0U;
    for (const toml::node& e : *a) {
        const std::optional<std::string> name = e.value<std::string>();
        const auto it = std::find_if(c.zones.begin(), c.zones.end(),
                                     [&](const ZoneSettings& z) { return name && z.name == *name; });
        if (!name || it == c.zones.end()) {
            L.fail(e.source(), p + ".zones", "expected names of configured zones");
        }
        const std::uint32_t bit = 1U << static_cast<unsigned>(it - c.zones.begin());
        if ((mask & bit) != 0U) {
            L.fail(e.source(), p + ".zones", "zone '" + *name + "' named twice");
        }
        mask |= bit;
        names.push_back(*name);
    }
    return mask;
}

}  // namespace

void load_cases(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const toml::node* n = root.get("cases");
    if (n == nullptr) {
        return;
    }
    if (!n->is_array_of_tables() || n->as_array()->empty() || n->as_array()->size() > kMaxMonitoringCases) {
        L.fail(n->source(), "cases", "expected 1..16 [[cases]] tables");
    }
    const toml::array& arr = *n->as_array();
    for (std::size_t i = 0U; i < arr.size(); ++i) {
        const toml::table& t = *arr.get(i)->as_table();
        const std::string p = "cases[" + std::to_string(i) + "]";
        L.check_keys(t, p, {"number", "name", "zones"});
        CaseSettings k;
        k.line = static_cast<int>(t.source().begin.line);
        k.number = static_cast<int>(L.integer(t, p, "number", 0, kMaxMonitoringCases - 1));
        k.name = L.string(t, p, "name");
        k.zone_mask = case_zone_mask(L, t, p, c, k.zones);
        for (const CaseSettings& other : c.cases) {
            if (other.number == k.number) {
                L.fail(t.get("number")->source(), p + ".number", "case " + std::to_string(k.number) + " given twice");
            }
        }
        c.cases.push_back(k);
    }
    std::sort(c.cases.begin(), c.cases.end(),
              [](const CaseSettings& a, const CaseSettings& b) { return a.number < b.number; });
    if (c.cases.back().number + 1 != static_cast<int>(c.cases.size())) {
        L.fail(n->source(), "cases", "case numbers must be 0..N-1 without gaps");
    }
}

namespace {

/// The [[speed_classes]] tables: 1..4, class 0 full speed.
void load_speed_classes(const Loader& L, const toml::table& root, SeparationParams& sp) {
    const toml::node* n = root.get("speed_classes");
    if (n == nullptr || !n->is_array_of_tables() || n->as_array()->empty() || n->as_array()->size() > kSpeedClasses) {
        L.fail(n != nullptr ? n->source() : root.source(), "speed_classes",
               "a robot needs 1..4 [[speed_classes]] tables (class 0: full speed)");
    }
    const toml::array& arr = *n->as_array();
    for (std::size_t i = 0U; i < arr.size(); ++i) {
        const toml::table& t = *arr.get(i)->as_table();
        const std::string p = "speed_classes[" + std::to_string(i) + "]";
        L.check_keys(t, p, {"speed", "stopping_time_ms", "stopping_distance"});
        SpeedClassLimits& k = sp.classes[i];
        k.robot_speed_mps = L.number(t, p, "speed");
        k.stopping_time_s = L.number(t, p, "stopping_time_ms") * 1e-3;
        k.stopping_distance_m = L.number(t, p, "stopping_distance");
        if (!(k.robot_speed_mps > 0.0 && k.robot_speed_mps <= 10.0 && k.stopping_time_s >= 0.0 &&
              k.stopping_time_s <= 10.0 && k.stopping_distance_m >= 0.0 && k.stopping_distance_m <= 10.0)) {
            L.fail(t.source(), p, "expected speed in (0, 10] m/s, stopping time 0..10000 ms, distance 0..10 m");
        }
    }
    sp.class_count = static_cast<std::uint8_t>(arr.size());
}

/// A number of @p t in [lo, hi], with a message naming the unit.
double bounded(const Loader& L, const toml::table& t, const std::string& p, const char* key, double lo, double hi,
               const char* unit) {
    const double v = L.number(t, p, key);
    if (!(v >= lo && v <= hi)) {
        L.fail(t.get(key)->source(), p + "." + key,
               "expected " + std::to_string(lo) + ".." + std::to_string(hi) + " " + unit);
    }
    return v;
}

/// separation.intrusion_distance against the detection capability it rests on (ISO 13855).
void check_intrusion_distance(const Loader& L, const toml::table& t, const std::string& p, RobotSettings& r) {
    r.detection_capability_mm = 0.0;
    if (t.contains("detection_capability_mm")) {
        r.detection_capability_mm = bounded(L, t, p, "detection_capability_mm", 14.0, 200.0, "mm");
    }
    const double c_min = minimum_intrusion_distance(r.detection_capability_mm);
    if (r.separation.intrusion_distance_m < c_min - 1e-12) {
        const std::string why =
            r.detection_capability_mm > 0.0
                ? "ISO 13855 for detection_capability_mm = " + std::to_string(r.detection_capability_mm)
                : "no detection_capability_mm: a measured d is not stated, so ISO 13855's arm allowance";
        L.fail(t.get("intrusion_distance")->source(), p + ".intrusion_distance",
               "must be at least " + std::to_string(c_min) + " m (" + why + ")");
    }
}

/// The [separation] table.
void load_separation(const Loader& L, const toml::table& root, RobotSettings& r) {
    SeparationParams& sp = r.separation;
    const std::string p = "separation";
    const toml::table& t = L.table(root, "", "separation");
    L.check_keys(t, p,
                 {"human_speed", "reaction_time_ms", "slowdown_time_ms", "intrusion_distance", "sensing_uncertainty",
                  "robot_uncertainty", "min_foreground_voxels", "min_hidden_voxels", "reduced_class",
                  "detection_capability_mm"});
    sp.human_speed_mps = L.number_or(t, p, "human_speed", 1.6);
    if (!(sp.human_speed_mps >= 1.6 && sp.human_speed_mps <= 10.0)) {
        L.fail(t.get("human_speed")->source(), p + ".human_speed", "expected 1.6..10 m/s (ISO 13855: at least 1.6)");
    }
    sp.reaction_time_s = bounded(L, t, p, "reaction_time_ms", 0.0, 10000.0, "ms") * 1e-3;
    sp.slowdown_time_s = bounded(L, t, p, "slowdown_time_ms", 0.0, 10000.0, "ms") * 1e-3;
    sp.intrusion_distance_m = bounded(L, t, p, "intrusion_distance", 0.0, 2.0, "m");
    sp.sensing_uncertainty_m = bounded(L, t, p, "sensing_uncertainty", 0.0, 1.0, "m");
    sp.robot_uncertainty_m = bounded(L, t, p, "robot_uncertainty", 0.0, 1.0, "m");
    sp.min_foreground_voxels = static_cast<std::uint32_t>(L.integer_or(t, p, "min_foreground_voxels", 1, 64, 1));
    sp.min_hidden_voxels = static_cast<std::uint32_t>(L.integer_or(t, p, "min_hidden_voxels", 1, 64, 1));
    sp.reduced_class = static_cast<std::uint8_t>(L.integer(t, p, "reduced_class", 0, sp.class_count - 1));
    check_intrusion_distance(L, t, p, r);
}

/// Most names in [robot] stroke_joints (a gripper with many fingers; the import checks each).
constexpr std::size_t kMaxStrokeJointNames = 16U;

/// Appends the names of @p a to @p names: distinct, non-empty strings.
void load_joint_names(const Loader& L, const toml::array& a, const std::string& key, std::vector<std::string>& names) {
    for (const toml::node& e : a) {
        const std::optional<std::string> name = e.value<std::string>();
        if (!name || name->empty() || std::find(names.begin(), names.end(), *name) != names.end()) {
            L.fail(e.source(), key, "expected distinct, non-empty joint names");
        }
        names.push_back(*name);
    }
}

/// The [robot] table's own keys.
void load_robot_table(const Loader& L, const toml::table& t, RobotSettings& r, const std::string& base_dir) {
    const std::string p = "robot";
    L.check_keys(t, p, {"urdf", "joints", "stroke_joints", "base", "base_yaw_deg", "margin", "max_command_age_ms"});
    r.line = static_cast<int>(t.source().begin.line);
    r.urdf = L.string(t, p, "urdf");
    if (r.urdf.empty()) {
        L.fail(t.get("urdf")->source(), p + ".urdf", "must not be empty");
    }
    if (r.urdf[0] != '/' && r.urdf.rfind("builtin:", 0) != 0) {
        r.urdf = base_dir + "/" + r.urdf;
    }
    const toml::node& j = L.require(t, p, "joints");
    const toml::array* a = j.as_array();
    if (a == nullptr || a->empty() || a->size() > kMaxCommandJoints) {
        L.fail(j.source(), p + ".joints", "expected 1..7 joint names in the PLC's command order");
    }
    load_joint_names(L, *a, p + ".joints", r.joints);
    if (const toml::node* s = t.get("stroke_joints")) {
        const toml::array* sa = s->as_array();
        if (sa == nullptr || sa->size() > kMaxStrokeJointNames) {
            L.fail(s->source(), p + ".stroke_joints", "expected up to 16 joint names: a gripper's finger joints");
        }
        load_joint_names(L, *sa, p + ".stroke_joints", r.stroke_joints);
    }
    r.base = L.vec3(t, p, "base");
    r.base_yaw_deg = L.number_or(t, p, "base_yaw_deg", 0.0);
    if (!(std::fabs(r.base_yaw_deg) <= 360.0)) {
        L.fail(t.get("base_yaw_deg")->source(), p + ".base_yaw_deg", "expected -360..360 degrees");
    }
    r.margin_m = bounded(L, t, p, "margin", 0.0, 2.0, "m");
    r.max_command_age_us = ms_to_us(bounded(L, t, p, "max_command_age_ms", 1.0, 10000.0, "ms"));
}

}  // namespace

void load_robot(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir) {
    if (!root.contains("robot")) {
        for (const char* key : {"separation", "speed_classes"}) {
            if (root.contains(key)) {
                L.fail(root.get(key)->source(), key, "needs a [robot] table");
            }
        }
        return;
    }
    RobotSettings& r = c.robot;
    const toml::table& t = L.table(root, "", "robot");
    load_robot_table(L, t, r, base_dir);
    load_speed_classes(L, root, r.separation);
    load_separation(L, root, r);
    r.enabled = true;
    if (r.max_command_age_us < c.period_us) {
        L.fail(t.get("max_command_age_ms")->source(), "robot.max_command_age_ms", "must be at least one cycle period");
    }
    // T_r covers the detection path of the safety manual's 5.2 up to the
    // PLC: at least the oldest accepted frame and one cycle.
    const double path_s = static_cast<double>(c.max_frame_age_us + c.budget_us) * 1e-6;
    if (r.separation.reaction_time_s < path_s) {
        L.fail(root.get("separation")->source(), "separation.reaction_time_ms",
               "must be at least cycle.max_frame_age_ms + cycle.budget_ms (" + std::to_string(path_s * 1e3) +
                   " ms): the detection path before the PLC");
    }
    const double need = minimum_mask_margin(r, c.period_us);
    if (r.margin_m < need) {
        L.fail(t.get("margin")->source(), "robot.margin",
               "must be at least " + std::to_string(need) +
                   " m: class 0 speed x (max_command_age_ms + period) + sensing_uncertainty + joint resolution");
    }
    // A person at the mask's edge is at most margin + a voxel diagonal from
    // the robot: that must already be a stop in the slowest class.
    const double edge = r.margin_m + std::sqrt(3.0) * c.grid.voxel_size;
    for (std::uint8_t k = 0U; k < r.separation.class_count; ++k) {
        if (protective_separation_distance(r.separation, k) <= edge) {
            L.fail(t.get("margin")->source(), "robot.margin",
                   "the protective separation distance of speed class " + std::to_string(k) +
                       " must exceed margin + a voxel diagonal (" + std::to_string(edge) +
                       " m), or a person at the mask's edge would not stop the robot");
        }
    }
}

}  // namespace config_detail

double minimum_intrusion_distance(double d_mm) {
    if (d_mm > 0.0 && d_mm <= 40.0) {
        return std::max(0.0, 8.0 * (d_mm - 14.0)) * 1e-3;
    }
    return 0.85;
}

}  // namespace cellguard::cell
