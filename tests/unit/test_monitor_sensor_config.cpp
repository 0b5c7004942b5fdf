// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the monitor configuration speaks calibration (issue 19): a
// sensor's pinhole intrinsics (fx, fy, cx, cy, or "device" for a live
// camera) instead of its field of view, a pose quaternion by named keys,
// thresholds as probabilities, a live camera's [sensors.camera] table; the old
// forms are refused with a message naming the new ones, every error names the
// key and its line.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/cell/config.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

/// The demo text with the first occurrence of @p from replaced by @p to (which must exist).
std::string edited(const std::string& text, const std::string& from, const std::string& to) {
    std::string out = text;
    const std::size_t at = out.find(from);
    REQUIRE_MESSAGE(at != std::string::npos, from);
    out.replace(at, from.size(), to);
    return out;
}

std::string edited(const std::string& from, const std::string& to) { return edited(demo_config_text(), from, to); }

/// Line (1-based) of the first line of @p text that starts with @p needle
/// (the demo's comments quote the keys too).
int line_of(const std::string& text, const std::string& needle) {
    const std::size_t at = text.find("\n" + needle);
    REQUIRE_MESSAGE(at != std::string::npos, needle);
    int line = 2;
    for (std::size_t i = 0U; i < at; ++i)
        line += text[i] == '\n' ? 1 : 0;
    return line;
}

/// Loads @p text, which must fail at the line of @p at with a message holding @p what.
void check_refused(const std::string& text, const std::string& at, const std::string& what) {
    const ConfigLoad l = parse_monitor_config(text, "cell.toml");
    CAPTURE(l.error);
    CHECK_FALSE(l.ok);
    CHECK(l.error.find("cell.toml:" + std::to_string(line_of(text, at)) + ":") == 0U);
    CHECK(l.error.find(what) != std::string::npos);
}

/// Loads @p text, which must succeed.
MonitorConfig loaded(const std::string& text) {
    const ConfigLoad l = parse_monitor_config(text, "cell.toml");
    REQUIRE_MESSAGE(l.ok, l.error);
    return l.config;
}

/// An [opt_out] entry (the demo text ends with its [opt_out] table) for the
/// cameras these tests open by address alone, without expected_serial.
const std::string kIdentityOptOut = "camera_identity_check = \"a test of the camera table's keys\"\n";
/// The first sensor's (lidar-a, 176 x 144) field of view.
const std::string kFov0 = "fov = [43.6, 34.6]";
/// The demo with a [sensors.camera] table of @p keys for the first sensor.
std::string with_camera(const std::string& keys) {
    const bool by_address_alone = keys.find("address") != std::string::npos &&
                                  keys.find("expected_serial") == std::string::npos;
    return edited("max_range = 10.0\n", "max_range = 10.0\n[sensors.camera]\n" + keys + "\n") +
           (by_address_alone ? kIdentityOptOut : std::string());
}

}  // namespace

// verifies: SR-CFG-014, SR-CFG-001
TEST_CASE("sensor config: intrinsics fx, fy, cx, cy replace the field of view, exactly one of the two") {
    const MonitorConfig fov = loaded(demo_config_text());
    CHECK(fov.sensors[0].intrinsics_source == IntrinsicsSource::kFieldOfView);
    CHECK(fov.sensors[0].hfov_deg == 43.6);
    const MonitorConfig k = loaded(edited(kFov0, "intrinsics = { fx = 220.0, fy = 225.0, cx = 90.25, cy = 70.0 }"));
    const SensorSettings& s = k.sensors[0];
    CHECK(s.intrinsics_source == IntrinsicsSource::kConfig);
    CHECK(s.fx == 220.0);
    CHECK(s.fy == 225.0);
    CHECK(s.cx == 90.25);
    CHECK(s.cy == 70.0);
    CHECK(s.hfov_deg == doctest::Approx(2.0 * std::atan(88.0 / 220.0) * 180.0 / M_PI).epsilon(1e-12));
    CHECK(s.vfov_deg == doctest::Approx(2.0 * std::atan(72.0 / 225.0) * 180.0 / M_PI).epsilon(1e-12));
    CHECK(k.sensors[1].intrinsics_source == IntrinsicsSource::kFieldOfView);

    const std::string both = edited(kFov0, kFov0 + "\nintrinsics = { fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0 }");
    check_refused(both, "intrinsics =", "sensors[0].fov: give exactly one of fov and intrinsics");
    check_refused(edited(kFov0 + "\n", ""), "[[sensors]]", "sensors[0].fov: give exactly one of fov and intrinsics");
}

// verifies: SR-CFG-014, SR-CFG-001
TEST_CASE("sensor config: every bad intrinsics value names its key and line") {
    const auto bad = [](const std::string& table, const std::string& what) {
        CAPTURE(table);
        check_refused(edited(kFov0, "intrinsics = " + table), "intrinsics =", what);
    };
    bad("{ fx = 0.0, fy = 200.0, cx = 80.0, cy = 70.0 }", "sensors[0].intrinsics.fx: must be greater than 0");
    bad("{ fx = 200.0, fy = -1.0, cx = 80.0, cy = 70.0 }", "sensors[0].intrinsics.fy: must be greater than 0");
    bad("{ fx = inf, fy = 200.0, cx = 80.0, cy = 70.0 }", "sensors[0].intrinsics.fx: expected a finite number");
    bad("{ fx = nan, fy = 200.0, cx = 80.0, cy = 70.0 }", "sensors[0].intrinsics.fx: expected a finite number");
    bad("{ fx = 200.0, fy = 200.0, cx = 176.0, cy = 70.0 }", "sensors[0].intrinsics.cx: expected a column in [0, 176)");
    bad("{ fx = 200.0, fy = 200.0, cx = -0.5, cy = 70.0 }", "sensors[0].intrinsics.cx: expected a column in [0, 176)");
    bad("{ fx = 200.0, fy = 200.0, cx = 80.0, cy = 144.0 }", "sensors[0].intrinsics.cy: expected a row in [0, 144)");
    bad("{ fx = 200.0, fy = 200.0, cx = 80.0 }", "sensors[0].intrinsics.cy: missing key");
    bad("{ fx = 200.0, fy = 200.0, cx = 80.0, cy = 70.0, k1 = 0.1 }", "sensors[0].intrinsics.k1: unknown key");
    bad("{ fx = \"200\", fy = 200.0, cx = 80.0, cy = 70.0 }", "sensors[0].intrinsics.fx: expected a number");
    bad("[200.0, 200.0, 80.0, 70.0]", R"(expected { fx = ..., fy = ..., cx = ..., cy = ... } (pixels) or "device")");
    bad("\"factory\"", "sensors[0].intrinsics: expected {");
    bad("\"device\"", "sensors[0].intrinsics: \"device\" needs a [sensors.camera] table");
    // The edges of the image are allowed.
    CHECK(parse_monitor_config(edited(kFov0, "intrinsics = { fx = 1e-3, fy = 1e6, cx = 0.0, cy = 143.999 }"), "c").ok);
}

// verifies: SR-CFG-015
TEST_CASE("sensor config: rotation by named keys w, x, y, z, the array form refused naming the new one") {
    const std::string target = "target = [0.0, 0.0, 0.0]\nresolution = [176, 144]";
    const auto with_rotation = [&target](const std::string& r) {
        return edited(target, "rotation = " + r + "\nresolution = [176, 144]");
    };
    const double h = std::sqrt(0.5);
    // Any key order; 7 decimals: the norm is 1 within 1e-6 but not exactly (normalised when loaded).
    const MonitorConfig c = loaded(with_rotation("{ x = 0.0, y = 0.0, z = 0.7071068, w = 0.7071068 }"));
    CHECK_FALSE(c.sensors[0].has_target);
    CHECK(c.sensors[0].rotation.norm() == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(c.sensors[0].rotation.w() == doctest::Approx(h).epsilon(1e-6));
    CHECK(c.sensors[0].rotation.z() == doctest::Approx(h).epsilon(1e-6));
    CHECK(c.sensors[0].rotation.x() == 0.0);
    const MonitorConfig exact = loaded(with_rotation("{ w = 0.5, x = -0.5, y = 0.5, z = -0.5 }"));
    CHECK(exact.sensors[0].rotation.coeffs() == Eigen::Vector4d(-0.5, 0.5, -0.5, 0.5));  // Eigen stores x, y, z, w

    std::string t = with_rotation("[0.0, 0.0, 0.0, 1.0]");
    check_refused(t, "rotation =", "sensors[0].rotation: the array form [w, x, y, z] is no longer accepted");
    check_refused(t, "rotation =", "a ROS tf2 quaternion is written x, y, z, w");
    check_refused(t, "rotation =", "rotation = { w = ..., x = ..., y = ..., z = ... }");
    check_refused(with_rotation("{ w = 0.7071, x = 0.0, y = 0.0, z = 0.7071 }"), "rotation =",
                  "sensors[0].rotation: expected a unit quaternion (norm within 1e-6 of 1), got norm 0.99999");
    check_refused(with_rotation("{ w = 1.0, x = 0.0, y = 0.0 }"), "rotation =", "sensors[0].rotation.z: missing key");
    check_refused(with_rotation("{ w = 1.0, x = 0.0, y = 0.0, z = 0.0, s = 1.0 }"),
                  "rotation =", "sensors[0].rotation.s: unknown key");
    check_refused(with_rotation("\"identity\""), "rotation =", "sensors[0].rotation: expected a quaternion");
    check_refused(with_rotation("{ w = 0.0, x = 0.0, y = 0.0, z = 0.0 }"), "rotation =", "got norm 0");
}

// verifies: SR-CFG-016
TEST_CASE("sensor config: thresholds are probabilities, converted to the defaults' log-odds by nearest rounding") {
    // The converted defaults are today's defaults, exactly.
    CHECK(log_odds_from_probability(0.73) == 255);
    CHECK(log_odds_from_probability(0.05) == -754);
    const MonitorConfig demo = demo_config();
    CHECK(demo.foreground_threshold == 255);
    CHECK(demo.accessible_min_prior == -754);
    const MonitorConfig none = loaded(edited(
        "[thresholds]\nforeground_probability = 0.73   # t_f: foreground when P(fore) >= this (stored as log-odds "
        "255)\naccessible_min_p_fore = 0.05    # unseen counts voxels whose prior P(fore) is at least this (-754)\n",
        ""));
    CHECK(none.foreground_threshold == 255);  // no [thresholds] table: the same defaults
    CHECK(none.accessible_min_prior == -754);
    const MonitorConfig empty = loaded(edited(
        "foreground_probability = 0.73   # t_f: foreground when P(fore) >= this (stored as log-odds "
        "255)\naccessible_min_p_fore = 0.05    # unseen counts voxels whose prior P(fore) is at least this (-754)\n",
        ""));
    CHECK(empty.foreground_threshold == 255);  // an empty table: the same defaults
    CHECK(empty.accessible_min_prior == -754);

    const MonitorConfig c = loaded(edited("foreground_probability = 0.73", "foreground_probability = 0.9"));
    CHECK(c.foreground_threshold == log_odds_from_probability(0.9));
    CHECK(c.foreground_threshold == 562);  // round(256 ln 9) = round(562.49)
    const MonitorConfig a = loaded(edited("accessible_min_p_fore = 0.05", "accessible_min_p_fore = 0.5"));
    CHECK(a.accessible_min_prior == 0);
    // Saturating: a probability below e^-128 is the smallest finite log-odds, never the sentinel.
    const MonitorConfig tiny = loaded(edited("foreground_probability = 0.73", "foreground_probability = 1e-300"));
    CHECK(tiny.foreground_threshold == kLogOddsMin);

    std::string t = edited("foreground_probability = 0.73", "foreground = 255");
    check_refused(t, "foreground = 255", "thresholds.foreground: raw log-odds are no longer accepted");
    check_refused(t, "foreground = 255",
                  "write thresholds.foreground_probability as a probability (255 log-odds units is 0.730");
    t = edited("accessible_min_p_fore = 0.05", "accessible_min_prior = -754");
    check_refused(t, "accessible_min_prior", "thresholds.accessible_min_prior: raw log-odds are no longer accepted");
    check_refused(t, "accessible_min_prior",
                  "thresholds.accessible_min_p_fore as a probability (-754 log-odds units is 0.0499");
    t = edited("accessible_min_p_fore = 0.05", "accessible_min_prior = \"low\"");
    check_refused(t, "accessible_min_prior", "write thresholds.accessible_min_p_fore as a probability");
    for (const char* v : {"0.0", "1.0", "1.5", "-0.2", "\"high\""}) {
        CAPTURE(v);
        t = edited("foreground_probability = 0.73", std::string("foreground_probability = ") + v);
        check_refused(t, "foreground_probability", "thresholds.foreground_probability: expected a");
    }
    for (const char* v : {"0.0", "0.51", "1.0"}) {
        CAPTURE(v);
        t = edited("accessible_min_p_fore = 0.05", std::string("accessible_min_p_fore = ") + v);
        check_refused(t, "accessible_min_p_fore",
                      "thresholds.accessible_min_p_fore: expected a probability in (0, 0.5]");
    }
    t = edited("accessible_min_p_fore = 0.05", "accessible_min = 0.05");
    check_refused(t, "accessible_min = ", "thresholds.accessible_min: unknown key");
}

// verifies: SR-CFG-017
TEST_CASE("sensor config: a camera table with every key, defaults, and intrinsics from the device") {
    const MonitorConfig d = loaded(with_camera("address = \"127.0.0.1\""));
    const CameraSettings& c = d.sensors[0].camera;
    CHECK(c.enabled);
    CHECK(c.line == line_of(with_camera("address = \"127.0.0.1\""), "[sensors.camera]"));
    CHECK(c.address == "127.0.0.1");
    CHECK(c.pixel_format == CameraPixelFormat::kCoord3dC16);
    CHECK_FALSE(c.has_depth_scale);
    CHECK(c.frame_rate_hz == 30.0);
    CHECK(c.packet_size == 0);
    CHECK(c.socket_buffer_bytes == 1048576);
    CHECK(c.reconnect_interval_us == 1000000U);
    CHECK(c.max_stamp_error_us == 20000U);
    CHECK_FALSE(d.sensors[1].camera.enabled);

    const MonitorConfig f = loaded(
        edited(with_camera("serial = \"22501234\"\nexpected_serial = \"22501234\"\npixel_format = \"Mono16\"\n"
                           "depth_scale = 0.00025\ndepth_offset = -0.5\nframe_rate = 0.1\npacket_size = 8192\n"
                           "socket_buffer_kib = 65536\nreconnect_interval_ms = 2500\nmax_stamp_error_ms = 7.5"),
               kFov0, "intrinsics = \"device\""));
    const CameraSettings& g = f.sensors[0].camera;
    CHECK(f.sensors[0].intrinsics_source == IntrinsicsSource::kDevice);
    CHECK(f.sensors[0].fx == 0.0);  // filled in when the camera is opened
    CHECK(g.serial == "22501234");
    CHECK(g.expected_serial == "22501234");
    CHECK(g.pixel_format == CameraPixelFormat::kMono16);
    CHECK(g.has_depth_scale);
    CHECK(g.depth_scale_m == 0.00025);
    CHECK(g.depth_offset_m == -0.5);
    CHECK(g.frame_rate_hz == 0.1);
    CHECK(g.packet_size == 8192);
    CHECK(g.socket_buffer_bytes == 65536 * 1024);
    CHECK(g.reconnect_interval_us == 2500000U);
    CHECK(g.max_stamp_error_us == 7500U);
    const MonitorConfig id = loaded(with_camera("id = \"Aravis-Fake-GV01\"\nexpected_serial = \"GV01\""));
    CHECK(id.sensors[0].camera.device_id == "Aravis-Fake-GV01");
    CHECK(id.sensors[0].camera.expected_serial == "GV01");
    // An inline table is the same table.
    const MonitorConfig inl = loaded(
        edited("max_range = 10.0\n", "max_range = 10.0\ncamera = { address = \"127.0.0.2\" }\n") + kIdentityOptOut);
    CHECK(inl.sensors[0].camera.address == "127.0.0.2");
}

// verifies: SR-CFG-017
TEST_CASE("sensor config: real-cell.toml's commented camera example loads when uncommented") {
    std::ifstream in(std::string(CELLGUARD_SOURCE_DIR) + "/apps/monitor/config/real-cell.toml");
    std::stringstream all;
    all << in.rdbuf();
    const std::string text = all.str();
    std::size_t at = text.find("# A live GigE Vision camera instead");
    REQUIRE(at != std::string::npos);
    std::string snippet;
    for (at = text.find('\n', at) + 1U; text.compare(at, 1U, "#") == 0; at = text.find('\n', at) + 1U) {
        const std::string line = text.substr(at, text.find('\n', at) - at);
        if (line.rfind("#   ", 0) == 0) {
            snippet += line.substr(4U) + "\n";
        }
    }
    std::string cell = edited(text, "fov = [58.0, 45.0]\nmax_range = 10.0\n", "max_range = 10.0\n" + snippet);
    const ConfigLoad l = parse_monitor_config(cell, "real-cell.toml");
    const std::string why = l.error + "\n" + snippet;
    REQUIRE_MESSAGE(l.ok, why);
    CHECK(l.config.sensors[0].intrinsics_source == IntrinsicsSource::kDevice);
    CHECK(l.config.sensors[0].camera.address == "192.168.10.11");
    CHECK(l.config.sensors[0].camera.expected_serial == "22501234");
    CHECK(l.config.sensors[1].intrinsics_source == IntrinsicsSource::kFieldOfView);
}

// verifies: SR-CFG-017
TEST_CASE("sensor config: every bad camera key or value names it and its line") {
    const auto bad = [](const std::string& keys, const std::string& at, const std::string& what) {
        CAPTURE(keys);
        check_refused(with_camera(keys), at, what);
    };
    for (const char* a : {"256.0.0.1", "1.2.3", "01.2.3.4", "1.2.3.4.5", "1.2.3.4 ", "a.b.c.d", "", "1..2.3",
                          "1.2.3.1000", "-1.2.3.4", "localhost"}) {
        bad(std::string("address = \"") + a + "\"", "address", "sensors[0].camera.address: expected an IPv4 address");
    }
    for (const char* a : {"0.0.0.0", "255.255.255.255", "224.0.0.1", "239.255.255.250"}) {
        bad(std::string("address = \"") + a + "\"", "address", "sensors[0].camera.address: expected one camera's");
    }
    bad("address = 127", "address", "sensors[0].camera.address: expected a string");
    bad("address = \"127.0.0.1\"\nserial = \"X\"", "[sensors.camera]",
        "sensors[0].camera.address: give exactly one of address, serial and id");
    bad("expected_serial = \"X\"", "[sensors.camera]", "give exactly one of address, serial and id");
    bad("serial = \"\"", "serial", "sensors[0].camera.serial: expected 1..64 printable ASCII characters");
    bad("serial = \" 12\"", "serial", "sensors[0].camera.serial: expected 1..64");
    bad("serial = \"a\\u0001b\"", "serial", "sensors[0].camera.serial: expected 1..64");
    bad("id = \"" + std::string(129U, 'x') + "\"", "id =", "sensors[0].camera.id: expected 1..128");
    bad("serial = \"A1\"\nexpected_serial = \"A2\"", "expected_serial",
        "sensors[0].camera.expected_serial: differs from serial");
    bad("address = \"127.0.0.1\"\npixel_format = \"Mono8\"", "pixel_format",
        R"(sensors[0].camera.pixel_format: expected "Coord3D_C16" or "Mono16", got "Mono8")");
    bad("address = \"127.0.0.1\"\npixel_format = \"Mono16\"", "[sensors.camera]",
        "sensors[0].camera.depth_scale: Mono16 carries no depth scale");
    bad("address = \"127.0.0.1\"\ndepth_scale = 0.001", "depth_scale",
        "sensors[0].camera.depth_offset: give both depth_scale and depth_offset, or neither");
    bad("address = \"127.0.0.1\"\ndepth_offset = 0.0", "depth_offset",
        "sensors[0].camera.depth_scale: give both depth_scale and depth_offset, or neither");
    bad("address = \"127.0.0.1\"\ndepth_scale = 0.0\ndepth_offset = 0.0", "depth_scale",
        "sensors[0].camera.depth_scale: expected metres per unit in (0, 1]");
    bad("address = \"127.0.0.1\"\ndepth_scale = 0.001\ndepth_offset = 101.0", "depth_offset",
        "sensors[0].camera.depth_offset: expected metres in [-100, 100]");
    bad("address = \"127.0.0.1\"\nframe_rate = 0.09", "frame_rate", "sensors[0].camera.frame_rate: expected frames");
    bad("address = \"127.0.0.1\"\nframe_rate = 1000.5", "frame_rate", "sensors[0].camera.frame_rate");
    bad("address = \"127.0.0.1\"\npacket_size = 575", "packet_size",
        "sensors[0].camera.packet_size: expected 0 (the camera's) or bytes in 576..9000, got 575");
    bad("address = \"127.0.0.1\"\npacket_size = 9001", "packet_size",
        "sensors[0].camera.packet_size: expected an integer in 0..9000");
    bad("address = \"127.0.0.1\"\npacket_size = 1500.0", "packet_size",
        "sensors[0].camera.packet_size: expected an integer");
    bad("address = \"127.0.0.1\"\nsocket_buffer_kib = 63", "socket_buffer_kib",
        "sensors[0].camera.socket_buffer_kib: expected an integer in 64..65536");
    bad("address = \"127.0.0.1\"\nreconnect_interval_ms = 99", "reconnect_interval_ms",
        "sensors[0].camera.reconnect_interval_ms: expected 100..600000 ms");
    bad("address = \"127.0.0.1\"\nmax_stamp_error_ms = 0", "max_stamp_error_ms",
        "sensors[0].camera.max_stamp_error_ms: expected 1..10000 ms");
    bad("address = \"127.0.0.1\"\nexposure = 10", "exposure", "sensors[0].camera.exposure: unknown key");
    // Recorded frames and a live camera exclude each other (the files are not opened first).
    check_refused(edited(with_camera("address = \"127.0.0.1\""), "max_range = 10.0\n",
                         "max_range = 10.0\npcd_files = [\"frame.pcd\"]\n"),
                  "[sensors.camera]",
                  "sensors[0].camera: a sensor reads either recorded frames (pcd_files) or a live camera");
    // One camera for two sensors.
    std::string two = with_camera("address = \"127.0.0.3\"");
    two = edited(two, "name = \"lidar-b\"", "name = \"lidar-b\"\ncamera = { address = \"127.0.0.3\" }");
    check_refused(two, "camera = {", "sensors[1].camera: the same camera as sensors[0] ('lidar-a')");
    check_refused(edited("max_range = 10.0\n", "max_range = 10.0\ncamera = \"127.0.0.1\"\n"),
                  "camera = ", "sensors[0].camera: expected a table");
}
