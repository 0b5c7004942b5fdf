// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Scene files of the simulated workcell (TOML, toml++), and walking people.
#include "cellguard/host/sim/scene_file.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <initializer_list>
#include <sstream>
#include <utility>

#include "cellguard/host/io/toml_loader.hpp"

namespace cellguard::sim {

namespace {
constexpr double kPi = 3.14159265358979323846;
/// Scene files may include others at most this deep; deeper is an error (it also bounds the recursion).
constexpr int kMaxIncludeDepth = 8;

/// The loader's error: "file:line:column: key: what".
using SceneError = host::TomlError;

/// The shared checked getters plus the scene files' own (ranges, [[tables]]).
class Loader : public host::TomlLoader {
public:
    using TomlLoader::TomlLoader;

    /// A number in [lo, hi] (or the fallback when absent).
    double ranged_or(const toml::table& t, const std::string& path, const char* key, double lo, double hi,
                     double fallback) const {
        if (!t.contains(key)) {
            return fallback;
        }
        const double v = number(t, path, key);
        if (v < lo || v > hi) {
            std::ostringstream m;
            m << "expected a number in [" << lo << ", " << hi << "], got " << v;
            fail(t.get(key)->source(), join(path, key), m.str());
        }
        return v;
    }

    const toml::array& tables(const toml::table& root, const char* key) const {
        const toml::node* n = root.get(key);
        if (!n->is_array_of_tables()) {
            fail(n->source(), key, std::string("expected [[") + key + "]] tables");
        }
        return *n->as_array();
    }
};

NoiseModel load_noise(const Loader& L, const toml::table& s, const std::string& path, SensorKind kind) {
    NoiseModel m;
    m.kind = kind;
    const toml::node* n = s.get("noise");
    if (n == nullptr) {
        return m;
    }
    const std::string p = path + ".noise";
    if (!n->is_table()) {
        L.fail(n->source(), p, "expected a table");
    }
    const toml::table& t = *n->as_table();
    if (kind == SensorKind::kFlashLidar) {
        L.check_keys(t, p,
                     {"range_sigma_base_m", "range_sigma_per_m", "mixed_pixel_edge_m", "mixed_pixel_probability"});
        FlashLidarNoise& q = m.lidar;
        q.range_sigma_base_m = L.ranged_or(t, p, "range_sigma_base_m", 0.0, 1.0, q.range_sigma_base_m);
        q.range_sigma_per_m = L.ranged_or(t, p, "range_sigma_per_m", 0.0, 1.0, q.range_sigma_per_m);
        q.mixed_pixel_edge_m = L.ranged_or(t, p, "mixed_pixel_edge_m", 0.0, 100.0, q.mixed_pixel_edge_m);
        q.mixed_pixel_probability = L.ranged_or(t, p, "mixed_pixel_probability", 0.0, 1.0, q.mixed_pixel_probability);
    } else if (kind == SensorKind::kStereo) {
        L.check_keys(t, p,
                     {"baseline_m", "disparity_sigma_px", "disparity_quantum_px", "min_disparity_px",
                      "missing_probability", "edge_missing_m", "edge_missing_probability"});
        StereoNoise& q = m.stereo;
        q.baseline_m = L.ranged_or(t, p, "baseline_m", 1e-3, 10.0, q.baseline_m);
        q.disparity_sigma_px = L.ranged_or(t, p, "disparity_sigma_px", 0.0, 100.0, q.disparity_sigma_px);
        q.disparity_quantum_px = L.ranged_or(t, p, "disparity_quantum_px", 0.0, 100.0, q.disparity_quantum_px);
        q.min_disparity_px = L.ranged_or(t, p, "min_disparity_px", 0.0, 10000.0, q.min_disparity_px);
        q.missing_probability = L.ranged_or(t, p, "missing_probability", 0.0, 1.0, q.missing_probability);
        q.edge_missing_m = L.ranged_or(t, p, "edge_missing_m", 0.0, 100.0, q.edge_missing_m);
        q.edge_missing_probability = L.ranged_or(t, p, "edge_missing_probability", 0.0, 1.0,
                                                 q.edge_missing_probability);
    } else {
        L.check_keys(t, p, {});
    }
    return m;
}

void load_sensors(const Loader& L, const toml::table& root, SceneFile& f) {
    const toml::array& arr = L.tables(root, "sensor");
    std::size_t i = 0U;
    for (const toml::node& node : arr) {
        const toml::table& s = *node.as_table();
        const std::string p = "sensor[" + std::to_string(i++) + "]";
        L.check_keys(s, p,
                     {"name", "kind", "position", "target", "width", "height", "hfov_deg", "vfov_deg", "focal_px",
                      "max_range", "noise"});
        SensorSpec spec;
        spec.name = L.string_or(s, p, "name", p);
        const std::string kind_name = L.string_or(s, p, "kind", "");
        SensorKind kind = SensorKind::kIdeal;
        if (kind_name == "flash_lidar") {
            kind = SensorKind::kFlashLidar;
        } else if (kind_name == "stereo") {
            kind = SensorKind::kStereo;
        } else if (kind_name != "ideal") {
            L.fail(s.source(), p + ".kind", R"(expected "ideal", "flash_lidar" or "stereo")");
        }
        spec.position = L.vec3(s, p, "position");
        spec.target = L.vec3(s, p, "target");
        if ((spec.target - spec.position).norm() < 1e-6 ||
            (spec.target - spec.position).normalized().cross(Eigen::Vector3d::UnitZ()).norm() < 1e-6) {
            L.fail(s.source(), p + ".target", "the optical axis must have a length and must not be vertical");
        }
        spec.width = static_cast<std::int32_t>(L.integer(s, p, "width", 1, 640));
        spec.height = static_cast<std::int32_t>(L.integer(s, p, "height", 1, 480));
        if (s.contains("focal_px")) {
            if (s.contains("hfov_deg") || s.contains("vfov_deg")) {
                L.fail(s.source(), p + ".focal_px", "give either focal_px or the fields of view, not both");
            }
            const double f_px = L.ranged_or(s, p, "focal_px", 1.0, 1e5, 1.0);
            spec.hfov_deg = 2.0 * std::atan(0.5 * spec.width / f_px) * 180.0 / kPi;
            spec.vfov_deg = 2.0 * std::atan(0.5 * spec.height / f_px) * 180.0 / kPi;
        } else {
            spec.hfov_deg = L.number(s, p, "hfov_deg");
            spec.vfov_deg = L.number(s, p, "vfov_deg");
            if (!(spec.hfov_deg > 0.0 && spec.hfov_deg < 170.0 && spec.vfov_deg > 0.0 && spec.vfov_deg < 170.0)) {
                L.fail(s.source(), p, "fields of view must lie in (0, 170) degrees");
            }
        }
        spec.max_range = static_cast<float>(L.ranged_or(s, p, "max_range", 0.01, 100.0, 10.0));
        f.sensors.push_back(spec);
        f.noise.push_back(load_noise(L, s, p, kind));
    }
}

void load_boxes(const Loader& L, const toml::table& root, SceneFile& f) {
    const toml::array& arr = L.tables(root, "box");
    std::size_t i = 0U;
    for (const toml::node& node : arr) {
        const toml::table& t = *node.as_table();
        const std::string p = "box[" + std::to_string(i++) + "]";
        L.check_keys(t, p, {"center", "size", "yaw_deg", "role"});
        Box b;
        b.center = L.vec3(t, p, "center");
        b.size = L.vec3(t, p, "size");
        if (!(b.size.minCoeff() > 0.0)) {
            L.fail(t.source(), p + ".size", "edge lengths must be greater than 0");
        }
        b.yaw = L.number_or(t, p, "yaw_deg", 0.0) * kPi / 180.0;
        const std::string role = L.string_or(t, p, "role", "");
        if (role != "background" && role != "foreground") {
            L.fail(t.source(), p + ".role", R"(expected "background" or "foreground")");
        }
        b.background = role == "background";
        f.scene.boxes.push_back(b);
    }
}

void load_people(const Loader& L, const toml::table& root, SceneFile& f) {
    const toml::array& arr = L.tables(root, "person");
    std::size_t i = 0U;
    for (const toml::node& node : arr) {
        const toml::table& t = *node.as_table();
        const std::string p = "person[" + std::to_string(i++) + "]";
        L.check_keys(t, p, {"height_m", "speed_mps", "start_s", "path", "loop"});
        PersonSpec person;
        person.height_m = L.ranged_or(t, p, "height_m", 0.3, 2.5, person.height_m);
        person.speed_mps = L.ranged_or(t, p, "speed_mps", 0.0, 10.0, person.speed_mps);
        person.start_s = L.ranged_or(t, p, "start_s", 0.0, 1e6, person.start_s);
        person.loop = L.boolean_or(t, p, "loop", false);
        const toml::node& path = L.require(t, p, "path");
        const toml::array* pa = path.as_array();
        if (pa == nullptr || pa->empty()) {
            L.fail(path.source(), p + ".path", "expected an array of [x, y] waypoints");
        }
        bool dwell = false;
        for (const toml::node& w : *pa) {
            const toml::array* wa = w.as_array();
            const bool three = wa != nullptr && wa->size() == 3U;
            const std::vector<double> xy = L.numbers(w, p + ".path", three ? 3U : 2U);
            person.path.emplace_back(xy[0], xy[1]);
            person.dwell_s.push_back(three ? xy[2] : 0.0);
            if (three && !(xy[2] >= 0.0 && xy[2] <= 1e6)) {
                L.fail(w.source(), p + ".path", "a waypoint's dwell time must lie in [0, 1e6] s");
            }
            dwell = dwell || three;
        }
        if (!dwell) {
            person.dwell_s.clear();
        } else if (!(person.speed_mps > 0.0)) {
            L.fail(t.source(), p + ".speed_mps", "a path with dwell times needs a speed > 0");
        }
        f.people.push_back(person);
    }
}

/// An included file's path: absolute as given, else relative to the including file's directory.
std::string include_path(const std::string& base_dir, const std::string& name) {
    if ((!name.empty() && name[0] == '/') || base_dir.empty()) {
        return name;
    }
    std::string path = base_dir;
    path += '/';
    path += name;
    return path;
}

// The place of node @p n for errors found after loading.
SourcePlace place_of(const std::string& source, const toml::node& n) {
    return SourcePlace{source, static_cast<int>(n.source().begin.line), static_cast<int>(n.source().begin.column)};
}

// One keyframe: t and joints (finite numbers, checked as read), and its place.
Keyframe load_keyframe(const Loader& L, const std::string& source, const toml::table& t, const std::string& p) {
    L.check_keys(t, p, {"t", "joints"});
    Keyframe f;
    f.place = place_of(source, t);
    f.t = L.number(t, p, "t");
    const toml::node& joints = L.require(t, p, "joints");
    const toml::array* a = joints.as_array();
    if (a == nullptr || a->empty() || a->size() > kMaxRobotJoints) {
        L.fail(joints.source(), p + ".joints", "expected an array of 1 to 7 joint positions (rad or m)");
    }
    std::size_t j = 0U;
    for (const toml::node& e : *a) {
        f.q.q[j] = L.as_number(e, p + ".joints[" + std::to_string(j) + "]");
        ++j;
    }
    f.q.count = static_cast<std::uint8_t>(a->size());
    return f;
}

void load_robot(const Loader& L, const std::string& source, const std::string& base_dir, const toml::table& root,
                SceneFile& f) {
    const toml::node& n = *root.get("robot");
    if (!n.is_table()) {
        L.fail(n.source(), "robot", "expected a [robot] table");
    }
    const toml::table& t = *n.as_table();
    L.check_keys(t, "robot", {"model", "position", "yaw_deg", "keyframe"});
    RobotScenario& r = f.robot;
    r.present = true;
    const std::string model = L.string_or(t, "robot", "model", "");
    r.model = model.empty() ? model : include_path(base_dir, model);
    r.position = L.vec3(t, "robot", "position");
    r.yaw = L.number_or(t, "robot", "yaw_deg", 0.0) * kPi / 180.0;
    const toml::node& keys = L.require(t, "robot", "keyframe");
    if (!keys.is_array_of_tables() || keys.as_array()->empty()) {
        L.fail(keys.source(), "robot.keyframe", "expected [[robot.keyframe]] tables");
    }
    std::size_t i = 0U;
    for (const toml::node& k : *keys.as_array()) {
        r.trajectory.keyframes.push_back(
            load_keyframe(L, source, *k.as_table(), "robot.keyframe[" + std::to_string(i++) + "]"));
    }
    const std::string error = check_trajectory_values(r.trajectory);
    if (!error.empty()) {
        throw SceneError(error);
    }
}

void load_commands(const Loader& L, const std::string& source, const toml::table& root, SceneFile& f) {
    std::size_t i = 0U;
    for (const toml::node& node : L.tables(root, "command")) {
        const toml::table& t = *node.as_table();
        const std::string p = "command[" + std::to_string(i++) + "]";
        L.check_keys(t, p, {"t", "case", "speed_class"});
        CommandStep s;
        s.place = place_of(source, t);
        s.t = L.number(t, p, "t");
        s.monitoring_case = static_cast<std::uint8_t>(L.integer(t, p, "case", 0, kMaxMonitoringCases - 1));
        s.speed_class = static_cast<std::uint8_t>(L.integer_or(t, p, "speed_class", 0, kSpeedClasses - 1, 0));
        f.commands.steps.push_back(s);
    }
    const std::string error = check_schedule(f.commands);
    if (!error.empty()) {
        throw SceneError(error);
    }
}

SceneLoad parse_scene_depth(const std::string& text, const std::string& source_name, const std::string& base_dir,
                            int depth);

// NOLINTNEXTLINE(misc-no-recursion): includes nested more than 8 deep are an error (kMaxIncludeDepth), so the recursion is bounded
SceneLoad load_scene_file_depth(const std::string& path, int depth) {
    std::string text;
    std::string dir;
    if (!host::read_text_file(path, text, dir)) {
        SceneLoad out;
        out.error = path + ": cannot open the scene file";
        return out;
    }
    return parse_scene_depth(text, path, dir, depth);
}

/// What the included files give: their boxes and people, and the first
/// sensors, robot and schedule found (used when the including file has none).
struct Included {
    SceneFile scene;
    bool have_sensors = false;
};

// NOLINTNEXTLINE(misc-no-recursion): includes nested more than 8 deep are an error (kMaxIncludeDepth), so the recursion is bounded
Included load_includes(const Loader& L, const toml::node& n, const std::string& base_dir, int depth) {
    Included included;
    const toml::array* a = n.as_array();
    if (a == nullptr) {
        L.fail(n.source(), "include", "expected an array of file names");
    }
    if (depth >= kMaxIncludeDepth) {
        L.fail(n.source(), "include", "includes nested more than 8 deep");
    }
    SceneFile& f = included.scene;
    for (const toml::node& e : *a) {
        if (!e.is_string()) {
            L.fail(e.source(), "include", "expected an array of file names");
        }
        const SceneLoad sub = load_scene_file_depth(include_path(base_dir, e.as_string()->get()), depth + 1);
        if (!sub.ok) {
            L.fail(e.source(), "include", sub.error);
        }
        f.scene.boxes.insert(f.scene.boxes.end(), sub.scene.scene.boxes.begin(), sub.scene.scene.boxes.end());
        f.people.insert(f.people.end(), sub.scene.people.begin(), sub.scene.people.end());
        if (!sub.scene.sensors.empty() && !included.have_sensors) {
            f.sensors = sub.scene.sensors;
            f.noise = sub.scene.noise;
            included.have_sensors = true;
        }
        if (sub.scene.robot.present && !f.robot.present) {
            f.robot = sub.scene.robot;
        }
        if (!sub.scene.commands.steps.empty() && f.commands.steps.empty()) {
            f.commands = sub.scene.commands;
        }
    }
    return included;
}

// The file's own content after its includes' (@p included).
void load_content(const Loader& L, const std::string& source_name, const std::string& base_dir, const toml::table& root,
                  Included& included, SceneFile& f) {
    f.scene.boxes = std::move(included.scene.scene.boxes);
    f.people = std::move(included.scene.people);
    if (root.contains("sensor")) {
        load_sensors(L, root, f);
    } else if (included.have_sensors) {
        f.sensors = std::move(included.scene.sensors);
        f.noise = std::move(included.scene.noise);
    } else {
        f.sensors = paper_sensors();
        f.noise = paper_noise_models();
    }
    if (root.contains("box")) {
        load_boxes(L, root, f);
    }
    if (root.contains("person")) {
        load_people(L, root, f);
    }
    if (root.contains("robot")) {
        load_robot(L, source_name, base_dir, root, f);
    } else {
        f.robot = std::move(included.scene.robot);
    }
    if (root.contains("command")) {
        load_commands(L, source_name, root, f);
    } else {
        f.commands = std::move(included.scene.commands);
    }
}

// NOLINTNEXTLINE(misc-no-recursion): includes nested more than 8 deep are an error (kMaxIncludeDepth), so the recursion is bounded
SceneLoad parse_scene_depth(const std::string& text, const std::string& source_name, const std::string& base_dir,
                            int depth) {
    SceneLoad out;
    try {
        const toml::table root = toml::parse(text, source_name);
        const Loader L(source_name);
        L.check_keys(
            root, "",
            {"name", "description", "seed", "include", "floor", "sensor", "box", "person", "robot", "command"});
        SceneFile& f = out.scene;
        f.name = L.string_or(root, "", "name", "");
        f.description = L.string_or(root, "", "description", "");
        f.seed = root.contains("seed") ? static_cast<std::uint64_t>(L.integer(root, "", "seed", 0, INT64_MAX)) : 1U;
        f.scene.floor = L.boolean_or(root, "", "floor", true);
        Included included;
        if (root.contains("include")) {
            included = load_includes(L, *root.get("include"), base_dir, depth);
        }
        load_content(L, source_name, base_dir, root, included, f);
        out.ok = true;
    } catch (const toml::parse_error& e) {
        out.error = host::toml_syntax_error(source_name, e);
        out.scene = SceneFile{};
    } catch (const SceneError& e) {
        out.error = e.message;
        out.scene = SceneFile{};
    }
    return out;
}
}  // namespace

SceneLoad parse_scene(const std::string& text, const std::string& source_name, const std::string& base_dir) {
    return parse_scene_depth(text, source_name, base_dir, 0);
}

SceneLoad load_scene_file(const std::string& path) { return load_scene_file_depth(path, 0); }

namespace {
// Segment @p i of @p person's walk: path[i] -> path[i + 1], and for a loop
// the closing segment path.back() -> path.front() last.
std::size_t segment_count(const PersonSpec& person) noexcept {
    const std::size_t n = person.path.size();
    const std::size_t open = n > 1U ? n - 1U : 0U;
    return person.loop && n > 2U ? open + 1U : open;
}

void segment(const PersonSpec& person, std::size_t i, Eigen::Vector2d& from, Eigen::Vector2d& to) noexcept {
    from = person.path[i];
    to = i + 1U < person.path.size() ? person.path[i + 1U] : person.path.front();
}

// Where along the path the person stands at arc length s, and the heading there.
void walk_to(const PersonSpec& person, double s, Eigen::Vector2d& pos, Eigen::Vector2d& heading) noexcept {
    const std::size_t count = segment_count(person);
    Eigen::Vector2d from;
    Eigen::Vector2d to;
    double total = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        segment(person, i, from, to);
        total += (to - from).norm();
    }
    if (total <= 0.0) {
        return;
    }
    s = person.loop ? std::fmod(s, total) : std::fmin(s, total);
    for (std::size_t i = 0; i < count; ++i) {
        segment(person, i, from, to);
        const double len = (to - from).norm();
        if (len <= 0.0) {
            continue;
        }
        heading = (to - from) / len;
        if (s <= len) {
            pos = from + s * heading;
            return;
        }
        s -= len;
        pos = to;
    }
}
}  // namespace

namespace {
// The distance walked @p tau seconds after the start when the person stands
// dwell_s[i] seconds at waypoint i on arriving there (waypoint 0: at the start).
double walked_with_dwell(const PersonSpec& person, double tau) noexcept {
    const std::size_t count = segment_count(person);
    Eigen::Vector2d from;
    Eigen::Vector2d to;
    double period = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        segment(person, i, from, to);
        period += person.dwell_s[i] + (to - from).norm() / person.speed_mps;
    }
    if (person.loop && period > 0.0) {
        tau = std::fmod(tau, period);
    }
    double s = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        tau -= person.dwell_s[i];
        if (tau <= 0.0) {
            return s;
        }
        segment(person, i, from, to);
        const double len = (to - from).norm();
        if (tau * person.speed_mps <= len) {
            return s + tau * person.speed_mps;
        }
        tau -= len / person.speed_mps;
        s += len;
    }
    return s;
}
}  // namespace

double person_arc_length(const PersonSpec& person, double t) noexcept {
    if (person.dwell_s.size() != person.path.size() || !(person.speed_mps > 0.0) || !(t > person.start_s)) {
        return std::fmax(0.0, person.speed_mps * (t - person.start_s));  // no dwelling: speed * t, as always
    }
    return walked_with_dwell(person, t - person.start_s);
}

Eigen::Vector2d person_position(const PersonSpec& person, double t) noexcept {
    Eigen::Vector2d pos = person.path.empty() ? Eigen::Vector2d::Zero() : person.path.front();
    Eigen::Vector2d heading(1.0, 0.0);
    walk_to(person, person_arc_length(person, t), pos, heading);
    return pos;
}

void person_boxes_into(const PersonSpec& person, double t, PersonBoxes& out) noexcept {
    // Where along the path: arc length s = speed * (t - start).
    Eigen::Vector2d pos = person.path.empty() ? Eigen::Vector2d::Zero() : person.path.front();
    Eigen::Vector2d heading(1.0, 0.0);
    const double stride_phase = person_arc_length(person, t);
    walk_to(person, stride_phase, pos, heading);
    const double yaw = std::atan2(heading.y(), heading.x());
    const double h = person.height_m;
    const double k = h / 1.75;  // widths scale with height
    // Gait: legs and arms swing along the heading, one stride every 1.4 m.
    const double swing = 0.12 * k * std::sin(2.0 * kPi * stride_phase / 1.4);
    const Eigen::Vector2d side(-heading.y(), heading.x());
    std::size_t n = 0U;
    auto add = [&](double forward, double lateral, double z_low, double z_high, double sx, double sy) {
        Box& b = out[n++];
        const Eigen::Vector2d c = pos + forward * heading + lateral * side;
        b.center = Eigen::Vector3d(c.x(), c.y(), 0.5 * (z_low + z_high));
        b.size = Eigen::Vector3d(sx, sy, z_high - z_low);
        b.yaw = yaw;
        b.background = false;
    };
    const double hip = 0.47 * h;
    const double shoulder = 0.81 * h;
    add(swing, 0.09 * k, 0.0, hip, 0.13 * k, 0.12 * k);                    // left leg
    add(-swing, -0.09 * k, 0.0, hip, 0.13 * k, 0.12 * k);                  // right leg
    add(0.0, 0.0, hip, shoulder, 0.22 * k, 0.38 * k);                      // torso
    add(-0.8 * swing, 0.245 * k, 0.45 * h, shoulder, 0.09 * k, 0.09 * k);  // left arm
    add(0.8 * swing, -0.245 * k, 0.45 * h, shoulder, 0.09 * k, 0.09 * k);  // right arm
    add(0.0, 0.0, shoulder, 0.86 * h, 0.10 * k, 0.10 * k);                 // neck
    add(0.01 * k, 0.0, 0.86 * h, h, 0.20 * k, 0.16 * k);                   // head
    add(0.0, 0.0, 0.40 * h, hip, 0.20 * k, 0.36 * k);                      // hips
}

std::vector<Box> person_boxes(const PersonSpec& person, double t) {
    PersonBoxes boxes;
    person_boxes_into(person, t, boxes);
    return {boxes.begin(), boxes.end()};
}

Scene scene_at(const SceneFile& file, double t) {
    Scene s = file.scene;
    for (const PersonSpec& p : file.people) {
        for (const Box& b : person_boxes(p, t)) {
            s.boxes.push_back(b);
        }
    }
    return s;
}

void place_robot_base(const RobotScenario& robot, RobotModel& model) noexcept {
    for (int i = 0; i < 3; ++i) {
        model.base_xyz[i] = robot.position[i];
    }
    model.base_wxyz[0] = std::cos(0.5 * robot.yaw);
    model.base_wxyz[1] = 0.0;
    model.base_wxyz[2] = 0.0;
    model.base_wxyz[3] = std::sin(0.5 * robot.yaw);
}

Scene background_of(const Scene& scene) {
    Scene s;
    s.floor = scene.floor;
    for (const Box& b : scene.boxes) {
        if (b.background) {
            s.boxes.push_back(b);
        }
    }
    return s;
}

}  // namespace cellguard::sim
