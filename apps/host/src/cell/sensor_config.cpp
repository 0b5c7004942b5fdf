// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor configuration's [[sensors]] tables: pose (target or a named-key
// quaternion), image, intrinsics (fov, fx..cy or the device's), recorded
// frames or a live camera ([sensors.camera]).
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/io/depth_npy.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "config_loader.hpp"

namespace cellguard::cell::config_detail {
namespace {

/// How far from 1 a configured quaternion's norm may be.
constexpr double kUnitQuaternionTolerance = 1e-6;

/// `key` (`pcd_files`, `depth_files`): one or more paths of readable files (relative: to @p base_dir).
std::vector<std::string> load_file_list(const Loader& L, const toml::table& t, const std::string& p, const char* key,
                                        const std::string& base_dir) {
    const toml::node& n = *t.get(key);
    const toml::array* a = n.as_array();
    if (a == nullptr || a->empty()) {
        L.fail(n.source(), p + "." + key, "expected an array of one or more file paths");
    }
    std::vector<std::string> files;
    for (std::size_t k = 0U; k < a->size(); ++k) {
        const toml::node& e = *a->get(k);
        const std::string entry = p + "." + key + "[" + std::to_string(k) + "]";
        if (!e.is_string() || e.as_string()->get().empty()) {
            L.fail(e.source(), entry, "expected a non-empty path string");
        }
        std::string path = e.as_string()->get();
        if (path[0] != '/') {
            path.insert(0U, base_dir + "/");
        }
        if (!std::ifstream(path, std::ios::binary)) {
            L.fail(e.source(), entry, "cannot open '" + path + "'");
        }
        files.push_back(path);
    }
    return files;
}

/// `rotation = { w = ..., x = ..., y = ..., z = ... }`: a unit quaternion by
/// named keys. The old array form is refused: its order cannot be checked.
Eigen::Quaterniond load_rotation(const Loader& L, const toml::node& n, const std::string& key) {
    if (n.is_array()) {
        L.fail(n.source(), key,
               "the array form [w, x, y, z] is no longer accepted: a ROS tf2 quaternion is written x, y, z, w and "
               "would be read without an error as a different rotation; write rotation = { w = ..., x = ..., "
               "y = ..., z = ... }");
    }
    const toml::table* t = n.as_table();
    if (t == nullptr) {
        L.fail(n.source(), key, "expected a quaternion { w = ..., x = ..., y = ..., z = ... }");
    }
    L.check_keys(*t, key, {"w", "x", "y", "z"});
    const double w = L.number(*t, key, "w");
    const double x = L.number(*t, key, "x");
    const double y = L.number(*t, key, "y");
    const double z = L.number(*t, key, "z");
    const double norm = std::sqrt(w * w + x * x + y * y + z * z);
    if (!(std::fabs(norm - 1.0) <= kUnitQuaternionTolerance)) {
        char got[32];
        static_cast<void>(std::snprintf(got, sizeof got, "%.9g", norm));
        L.fail(
            n.source(), key,
            std::string("expected a unit quaternion (norm within 1e-6 of 1), got norm ") + got + "; give more digits");
    }
    return Eigen::Quaterniond(w, x, y, z).normalized();
}

/// `position` and exactly one of `target` and `rotation`.
void load_pose(const Loader& L, const toml::table& t, const std::string& p, SensorSettings& s) {
    s.position = L.vec3(t, p, "position");
    const bool has_target = t.contains("target");
    if (has_target == t.contains("rotation")) {
        L.fail(t.source(), p + ".target", "give exactly one of target and rotation");
    }
    if (has_target) {
        s.has_target = true;
        s.target = L.vec3(t, p, "target");
        if ((s.target - s.position).norm() < 1e-6) {
            L.fail(t.get("target")->source(), p + ".target", "must differ from the position");
        }
    } else {
        s.rotation = load_rotation(L, *t.get("rotation"), p + ".rotation");
    }
}

/// `resolution = [width, height]`.
void load_resolution(const Loader& L, const toml::table& t, const std::string& p, SensorSettings& s) {
    const toml::node& res = L.require(t, p, "resolution");
    const toml::array* ra = res.as_array();
    std::optional<std::int64_t> w;
    std::optional<std::int64_t> h;
    if (ra != nullptr && ra->size() == 2U) {
        w = (*ra)[0].value_exact<std::int64_t>();
        h = (*ra)[1].value_exact<std::int64_t>();
    }
    if (!w || !h || *w < 1 || *h < 1 || *w * *h > static_cast<std::int64_t>(kMaxReadingsPerSensor)) {
        L.fail(res.source(), p + ".resolution",
               "expected [width, height], positive integers, at most " + std::to_string(kMaxReadingsPerSensor) +
                   " pixels");
    }
    s.width = static_cast<int>(*w);
    s.height = static_cast<int>(*h);
}

/// `intrinsics = { fx = ..., fy = ..., cx = ..., cy = ... }`, pixels.
void load_pinhole(const Loader& L, const toml::table& k, const std::string& key, SensorSettings& s) {
    L.check_keys(k, key, {"fx", "fy", "cx", "cy"});
    s.fx = L.number(k, key, "fx");
    s.fy = L.number(k, key, "fy");
    s.cx = L.number(k, key, "cx");
    s.cy = L.number(k, key, "cy");
    L.positive(k, key, "fx", s.fx);
    L.positive(k, key, "fy", s.fy);
    if (!(s.cx >= 0.0 && s.cx < static_cast<double>(s.width))) {
        L.fail(k.get("cx")->source(), key + ".cx", "expected a column in [0, " + std::to_string(s.width) + ")");
    }
    if (!(s.cy >= 0.0 && s.cy < static_cast<double>(s.height))) {
        L.fail(k.get("cy")->source(), key + ".cy", "expected a row in [0, " + std::to_string(s.height) + ")");
    }
    set_sensor_intrinsics(s, s.fx, s.fy, s.cx, s.cy);  // and the fields of view for reports
}

/// Exactly one of `fov = [h, v]` and `intrinsics` (a table, or "device" for a
/// sensor with a camera: after load_camera).
void load_intrinsics(const Loader& L, const toml::table& t, const std::string& p, SensorSettings& s) {
    const toml::node* k = t.get("intrinsics");
    if ((k != nullptr) == t.contains("fov")) {
        L.fail(k != nullptr ? k->source() : t.source(), p + ".fov",
               R"(give exactly one of fov and intrinsics ({ fx, fy, cx, cy } or "device"))");
    }
    const std::string key = p + ".intrinsics";
    if (k == nullptr) {
        s.intrinsics_source = IntrinsicsSource::kFieldOfView;
        const std::vector<double> fov = L.numbers(*t.get("fov"), p + ".fov", 2U);
        if (!(fov[0] > 0.0 && fov[0] < 180.0 && fov[1] > 0.0 && fov[1] < 180.0)) {
            L.fail(t.get("fov")->source(), p + ".fov", "expected [horizontal, vertical] degrees, each in (0, 180)");
        }
        s.hfov_deg = fov[0];
        s.vfov_deg = fov[1];
    } else if (const toml::table* kt = k->as_table()) {
        s.intrinsics_source = IntrinsicsSource::kConfig;
        load_pinhole(L, *kt, key, s);
    } else if (k->is_string() && k->as_string()->get() == "device") {
        if (!s.camera.enabled) {
            L.fail(k->source(), key,
                   R"("device" needs a [sensors.camera] table (the intrinsics come from its Scan3d features))");
        }
        s.intrinsics_source = IntrinsicsSource::kDevice;  // fx..cy filled in when the camera is opened
    } else {
        L.fail(k->source(), key, R"(expected { fx = ..., fy = ..., cx = ..., cy = ... } (pixels) or "device")");
    }
}

/// True when @p text is an IPv4 dotted quad (four decimal numbers 0..255,
/// without leading zeros, which some parsers read as octal).
bool is_dotted_quad(const std::string& text, int& first_octet) {
    int parts = 0;
    std::size_t i = 0U;
    while (parts < 4) {
        const std::size_t start = i;
        int value = 0;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9' && i - start < 3U) {
            value = value * 10 + (text[i] - '0');
            ++i;
        }
        const std::size_t digits = i - start;
        if (digits == 0U || value > 255 || (digits > 1U && text[start] == '0')) {
            return false;
        }
        if (parts == 0) {
            first_octet = value;
        }
        ++parts;
        if (parts < 4) {
            if (i >= text.size() || text[i] != '.') {
                return false;
            }
            ++i;
        }
    }
    return i == text.size();
}

/// `camera.address`: a unicast IPv4 address.
void check_address(const Loader& L, const toml::table& t, const std::string& p, const std::string& address) {
    int first = 0;
    if (!is_dotted_quad(address, first)) {
        L.fail(t.get("address")->source(), p + ".address",
               "expected an IPv4 address a.b.c.d (0..255 each, no leading zeros), got \"" + address + "\"");
    }
    if (address == "0.0.0.0" || address == "255.255.255.255" || (first >= 224 && first <= 239)) {
        L.fail(t.get("address")->source(), p + ".address", "expected one camera's (unicast) address, got " + address);
    }
}

/// A serial number or device ID: 1..@p max printable ASCII characters,
/// without blanks at either end.
std::string camera_name(const Loader& L, const toml::table& t, const std::string& p, const char* key, std::size_t max) {
    std::string v = L.string(t, p, key);
    bool printable = !v.empty() && v.size() <= max && v.front() != ' ' && v.back() != ' ';
    for (const char ch : v) {
        printable = printable && ch >= 0x20 && ch <= 0x7E;
    }
    if (!printable) {
        L.fail(t.get(key)->source(), Loader::join(p, key),
               "expected 1.." + std::to_string(max) + " printable ASCII characters without blanks at either end");
    }
    return v;
}

/// camera.address | serial | id (exactly one) and expected_serial.
void load_camera_identity(const Loader& L, const toml::table& t, const std::string& p, CameraSettings& c) {
    const int openers = static_cast<int>(t.contains("address")) + static_cast<int>(t.contains("serial")) +
                        static_cast<int>(t.contains("id"));
    if (openers != 1) {
        L.fail(t.source(), p + ".address", "give exactly one of address, serial and id");
    }
    if (t.contains("address")) {
        c.address = L.string(t, p, "address");
        check_address(L, t, p, c.address);
    } else if (t.contains("serial")) {
        c.serial = camera_name(L, t, p, "serial", 64U);
    } else {
        c.device_id = camera_name(L, t, p, "id", 128U);
    }
    if (t.contains("expected_serial")) {
        c.expected_serial = camera_name(L, t, p, "expected_serial", 64U);
        if (!c.serial.empty() && c.expected_serial != c.serial) {
            L.fail(t.get("expected_serial")->source(), p + ".expected_serial",
                   "differs from serial: the camera opened by that serial would always be refused");
        }
    }
}

/// `depth_scale` (metres per raw unit, (0, 1]) and `depth_offset` (metres,
/// within +-kMaxSensorRange) of table @p t at @p p: a camera's or a recording's.
void load_depth_scale(const Loader& L, const toml::table& t, const std::string& p, double& scale, double& offset) {
    scale = L.number(t, p, "depth_scale");
    if (!(scale > 0.0 && scale <= 1.0)) {
        L.fail(t.get("depth_scale")->source(), p + ".depth_scale", "expected metres per unit in (0, 1]");
    }
    offset = L.number(t, p, "depth_offset");
    const auto range = static_cast<double>(kMaxSensorRange);
    if (!(std::fabs(offset) <= range)) {
        L.fail(t.get("depth_offset")->source(), p + ".depth_offset",
               "expected metres in [-" + std::to_string(static_cast<int>(range)) + ", " +
                   std::to_string(static_cast<int>(range)) + "]");
    }
}

/// `depth_files = "DIR"`: the .npy files in DIR (relative: to @p base_dir), in name order, at least one.
std::vector<std::string> load_npy_dir(const Loader& L, const toml::table& t, const std::string& p,
                                      const std::string& base_dir) {
    namespace fs = std::filesystem;
    const toml::node& n = *t.get("depth_files");
    std::string dir = n.as_string()->get();
    if (dir.empty()) {
        L.fail(n.source(), p + ".depth_files", "expected a directory or an array of .npy file paths");
    }
    if (dir[0] != '/') {
        dir.insert(0U, base_dir + "/");
    }
    std::error_code ec;
    std::vector<std::string> files;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->path().extension() == ".npy" && it->is_regular_file(ec)) {
            files.push_back(it->path().string());
        }
    }
    if (ec) {
        L.fail(n.source(), p + ".depth_files", "cannot read the directory '" + dir + "': " + ec.message());
    }
    if (files.empty()) {
        L.fail(n.source(), p + ".depth_files", "no .npy file in '" + dir + "'");
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// `depth_files` (recorded depth images, depth_input.hpp) with `depth_scale`
/// and `depth_offset` of sensor @p s (its resolution loaded): every file a
/// depth image of the sensor's size, all of one dtype; '<u2' files need the
/// scale and offset, '<f4' files (metres) refuse them.
void load_depth_recording(const Loader& L, const toml::table& t, const std::string& p, const std::string& base_dir,
                          SensorSettings& s) {
    const bool scale = t.contains("depth_scale") || t.contains("depth_offset");
    if (!t.contains("depth_files")) {
        if (scale) {
            L.fail(t.get(t.contains("depth_scale") ? "depth_scale" : "depth_offset")->source(), p + ".depth_scale",
                   "depth_scale and depth_offset describe recorded '<u2' depth_files (a live camera's go in "
                   "[sensors.camera]); this sensor has none");
        }
        return;
    }
    if (t.contains("pcd_files") || t.contains("camera")) {
        L.fail(t.get("depth_files")->source(), p + ".depth_files",
               "a sensor reads one input: recorded depth images (depth_files), recorded point sets (pcd_files) or "
               "a live camera ([sensors.camera])");
    }
    DepthRecordingSettings& r = s.recording;
    r.files = t.get("depth_files")->is_string() ? load_npy_dir(L, t, p, base_dir)
                                                : load_file_list(L, t, p, "depth_files", base_dir);
    NpyDtype first = NpyDtype::kFloat32;
    for (std::size_t k = 0U; k < r.files.size(); ++k) {
        NpyDtype dtype = NpyDtype::kFloat32;
        const IoStatus st = probe_npy_depth(r.files[k].c_str(), s.width, s.height, dtype);
        const std::string key = p + ".depth_files[" + std::to_string(k) + "]";
        if (!st) {
            L.fail(t.get("depth_files")->source(), key, st.message());
        }
        if (k == 0U) {
            first = dtype;
        } else if (dtype != first) {
            L.fail(t.get("depth_files")->source(), key,
                   std::string("dtype '") + npy_descr(dtype) + "' differs from the first file's '" + npy_descr(first) +
                       "': a sensor's recording has one dtype");
        }
    }
    r.raw = first == NpyDtype::kUInt16;
    if (r.raw && !(t.contains("depth_scale") && t.contains("depth_offset"))) {
        L.fail(t.get("depth_files")->source(), p + ".depth_scale",
               "the depth_files are '<u2' (raw units): give depth_scale (metres per unit) and depth_offset (metres)");
    }
    if (!r.raw && scale) {
        L.fail(t.get(t.contains("depth_scale") ? "depth_scale" : "depth_offset")->source(), p + ".depth_scale",
               "the depth_files are '<f4' (metres): depth_scale and depth_offset apply to '<u2' files only");
    }
    if (r.raw) {
        load_depth_scale(L, t, p, r.depth_scale_m, r.depth_offset_m);
    }
}

/// camera.pixel_format, depth_scale and depth_offset.
void load_camera_format(const Loader& L, const toml::table& t, const std::string& p, CameraSettings& c) {
    const std::string format = L.string_or(t, p, "pixel_format", "Coord3D_C16");
    if (format == "Coord3D_C16") {
        c.pixel_format = CameraPixelFormat::kCoord3dC16;
    } else if (format == "Mono16") {
        c.pixel_format = CameraPixelFormat::kMono16;
    } else {
        L.fail(t.get("pixel_format")->source(), p + ".pixel_format",
               R"(expected "Coord3D_C16" or "Mono16", got ")" + format + "\"");
    }
    const bool scale = t.contains("depth_scale");
    if (scale != t.contains("depth_offset")) {
        L.fail(t.get(scale ? "depth_scale" : "depth_offset")->source(), p + (scale ? ".depth_offset" : ".depth_scale"),
               "give both depth_scale and depth_offset, or neither (then the camera's Scan3d features)");
    }
    if (!scale && c.pixel_format == CameraPixelFormat::kMono16) {
        L.fail(t.source(), p + ".depth_scale",
               "Mono16 carries no depth scale: give depth_scale (metres per unit) and depth_offset (metres)");
    }
    if (scale) {
        c.has_depth_scale = true;
        load_depth_scale(L, t, p, c.depth_scale_m, c.depth_offset_m);
    }
}

/// camera.frame_rate, packet_size, socket_buffer_kib, reconnect_interval_ms, max_stamp_error_ms.
void load_camera_stream(const Loader& L, const toml::table& t, const std::string& p, CameraSettings& c) {
    c.frame_rate_hz = L.number_or(t, p, "frame_rate", c.frame_rate_hz);
    if (!(c.frame_rate_hz >= 0.1 && c.frame_rate_hz <= 1000.0)) {
        L.fail(t.get("frame_rate")->source(), p + ".frame_rate", "expected frames per second in 0.1..1000");
    }
    c.packet_size = static_cast<int>(L.integer_or(t, p, "packet_size", 0, 9000, c.packet_size));
    if (c.packet_size != 0 && c.packet_size < 576) {
        L.fail(t.get("packet_size")->source(), p + ".packet_size",
               "expected 0 (the camera's) or bytes in 576..9000, got " + std::to_string(c.packet_size));
    }
    c.socket_buffer_bytes = static_cast<int>(L.integer_or(t, p, "socket_buffer_kib", 64, 65536, 1024)) * 1024;
    const double reconnect = L.number_or(t, p, "reconnect_interval_ms", 1000.0);
    if (!(reconnect >= 100.0 && reconnect <= 600000.0)) {
        L.fail(t.get("reconnect_interval_ms")->source(), p + ".reconnect_interval_ms", "expected 100..600000 ms");
    }
    c.reconnect_interval_us = ms_to_us(reconnect);
    const double stamp = L.number_or(t, p, "max_stamp_error_ms", 20.0);
    if (!(stamp >= 1.0 && stamp <= 10000.0)) {
        L.fail(t.get("max_stamp_error_ms")->source(), p + ".max_stamp_error_ms", "expected 1..10000 ms");
    }
    c.max_stamp_error_us = ms_to_us(stamp);
}

/// The [sensors.camera] table of sensor @p p.
CameraSettings load_camera(const Loader& L, const toml::table& sensor, const std::string& sp) {
    const std::string p = sp + ".camera";
    const toml::table& t = L.table(sensor, sp, "camera");
    L.check_keys(t, p,
                 {"address", "serial", "id", "expected_serial", "pixel_format", "depth_scale", "depth_offset",
                  "frame_rate", "packet_size", "socket_buffer_kib", "reconnect_interval_ms", "max_stamp_error_ms"});
    CameraSettings c;
    c.enabled = true;
    c.line = static_cast<int>(t.source().begin.line);
    load_camera_identity(L, t, p, c);
    load_camera_format(L, t, p, c);
    load_camera_stream(L, t, p, c);
    if (sensor.contains("pcd_files")) {
        L.fail(t.source(), p,
               "a sensor reads either recorded frames (pcd_files) or a live camera ([sensors.camera]), not both");
    }
    return c;
}

/// A camera opened twice (the same address, serial or ID as an earlier sensor's) is refused.
void check_distinct_cameras(const Loader& L, const toml::table& t, const std::string& p,
                            const std::vector<SensorSettings>& earlier, const CameraSettings& c) {
    for (std::size_t j = 0U; j < earlier.size(); ++j) {
        const CameraSettings& o = earlier[j].camera;
        const bool same = o.enabled && ((!c.address.empty() && c.address == o.address) ||
                                        (!c.serial.empty() && c.serial == o.serial) ||
                                        (!c.device_id.empty() && c.device_id == o.device_id));
        if (same) {
            L.fail(t.get("camera")->source(), p + ".camera",
                   "the same camera as sensors[" + std::to_string(j) + "] ('" + earlier[j].name + "')");
        }
    }
}

}  // namespace

void load_sensors(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir) {
    const toml::node* n = root.get("sensors");
    if (n == nullptr || !n->is_array_of_tables() || n->as_array()->empty()) {
        L.fail(n != nullptr ? n->source() : root.source(), "sensors", "expected one or more [[sensors]] tables");
    }
    const toml::array& arr = *n->as_array();
    if (arr.size() > kMaxSensors) {
        L.fail(n->source(), "sensors", "at most " + std::to_string(kMaxSensors) + " sensors");
    }
    for (std::size_t i = 0U; i < arr.size(); ++i) {
        const toml::table& t = *arr.get(i)->as_table();
        const std::string p = "sensors[" + std::to_string(i) + "]";
        L.check_keys(t, p,
                     {"name", "position", "target", "rotation", "resolution", "fov", "intrinsics", "max_range",
                      "pcd_files", "depth_files", "depth_scale", "depth_offset", "camera"});
        SensorSettings s;
        s.line = static_cast<int>(t.source().begin.line);
        s.name = L.string(t, p, "name");
        load_pose(L, t, p, s);
        load_resolution(L, t, p, s);
        if (t.contains("camera")) {
            s.camera = load_camera(L, t, p);
            check_distinct_cameras(L, t, p, c.sensors, s.camera);
        }
        load_intrinsics(L, t, p, s);
        s.max_range = L.number(t, p, "max_range");
        if (!(s.max_range > 0.0 && s.max_range <= static_cast<double>(kMaxSensorRange))) {
            L.fail(t.get("max_range")->source(), p + ".max_range",
                   "expected metres in (0, " + std::to_string(kMaxSensorRange) + "]");
        }
        load_depth_recording(L, t, p, base_dir, s);
        if (t.contains("pcd_files")) {
            s.pcd_files = load_file_list(L, t, p, "pcd_files", base_dir);
        }
        c.sensors.push_back(s);
    }
}

}  // namespace cellguard::cell::config_detail

namespace cellguard::cell {

void set_sensor_intrinsics(SensorSettings& s, double fx, double fy, double cx, double cy) {
    sim::SensorSpec spec;
    spec.width = s.width;
    spec.height = s.height;
    spec.set_intrinsics(fx, fy, cx, cy);
    s.fx = fx;
    s.fy = fy;
    s.cx = cx;
    s.cy = cy;
    s.hfov_deg = spec.hfov_deg;
    s.vfov_deg = spec.vfov_deg;
}

}  // namespace cellguard::cell
