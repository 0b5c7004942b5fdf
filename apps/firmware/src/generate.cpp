// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-firmware-gen: renders the firmware's canned inputs on the host.
// Usage: cellguard-firmware-gen OUTPUT_DIR (and --help, --version)
// Writes prior.cgprior (the prior image, byte for byte the file cellguard-prior
// writes: write_prior_image_file) and frames.bin (four depth sensors at half
// the paper's resolution, three scenes; the format of
// cellguard/firmware/canned_frames.hpp); and for the robot-cell run
// (robot_scenario.hpp) robot.cgrobot (the demo arm's robot image),
// robot_prior.cgprior (the robot cell's prior) and robot_frames.bin (the
// robot cell's four sensors at a quarter of their resolution, five scenes
// with the arm rendered). Binary, little-endian, doubles and floats as their
// bit patterns, so the targets read the exact bits. src/embedded_data.S
// embeds the files as they are.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/firmware/canned_frames.hpp"
#include "cellguard/firmware/robot_scenario.hpp"

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/prior_files.hpp"
#include "cellguard/host/sim/robot_cell.hpp"
#include "cellguard/host/sim/scene_file.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/prior/prior_image.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_image.hpp"

using namespace cellguard;

namespace {

std::vector<sim::SensorSpec> firmware_sensors() {
    std::vector<sim::SensorSpec> s = sim::paper_sensors();
    for (sim::SensorSpec& spec : s) {  // half the resolution, same fields of view
        spec.width /= 2;
        spec.height /= 2;
    }
    return s;
}

sim::Scene with_person(double x, double y) {
    sim::Scene s = sim::reference_scene();
    s.boxes.push_back(sim::Box{{x, y, 0.85}, {0.3, 0.3, 1.7}, 0.0, false});
    return s;
}

bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    host::FilePtr f = host::open_file(path.c_str(), "wb");
    if (!f) {
        return false;
    }
    const bool ok = std::fwrite(bytes.data(), 1U, bytes.size(), f.get()) == bytes.size();
    return host::close_file(f) && ok;
}

/// Appends values little-endian, doubles and floats as their bit patterns.
class LeWriter {
public:
    void u32(std::uint32_t v) {
        for (unsigned i = 0U; i < 4U; ++i) {
            bytes_.push_back(static_cast<std::uint8_t>(v >> (8U * i)));
        }
    }
    void u64(std::uint64_t v) {
        u32(static_cast<std::uint32_t>(v));
        u32(static_cast<std::uint32_t>(v >> 32U));
    }
    void f64(double v) {
        std::uint64_t bits = 0U;
        std::memcpy(&bits, &v, sizeof(bits));
        u64(bits);
    }
    void f32(float v) {
        std::uint32_t bits = 0U;
        std::memcpy(&bits, &v, sizeof(bits));
        u32(bits);
    }
    void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
    void raw(const void* p, std::size_t n) {
        const auto* b = static_cast<const std::uint8_t*>(p);
        bytes_.insert(bytes_.end(), b, b + n);
    }
    void zeros(std::size_t n) { bytes_.insert(bytes_.end(), n, 0U); }
    void put_u32(std::size_t offset, std::uint32_t v) {
        for (unsigned i = 0U; i < 4U; ++i) {
            bytes_[offset + i] = static_cast<std::uint8_t>(v >> (8U * i));
        }
    }
    [[nodiscard]] std::size_t size() const { return bytes_.size(); }
    [[nodiscard]] const std::vector<std::uint8_t>& bytes() const { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
};

/// The frames blob (canned_frames.hpp): header, sensor records, scene
/// names, depth images scene-major, CRC-32.
std::vector<std::uint8_t> frames_blob(const std::vector<sim::SensorSpec>& sensors,
                                      const std::vector<const char*>& scene_names,
                                      const std::vector<sim::SimulatedFrame>& frames) {
    namespace L = cellguard::firmware::frames_layout;
    LeWriter w;
    w.raw(cellguard::firmware::kFramesMagic, sizeof(cellguard::firmware::kFramesMagic));
    w.u32(cellguard::firmware::kFramesFormatVersion);
    w.u32(static_cast<std::uint32_t>(sensors.size()));
    w.u32(static_cast<std::uint32_t>(frames.size()));
    w.u32(0U);  // the blob's size, set below
    w.u32(0U);  // reserved
    for (const sim::SensorSpec& s : sensors) {
        const Eigen::Matrix4d m = s.pose().matrix();
        const PinholeIntrinsics k = s.intrinsics();
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                w.f64(m(r, c));
            }
        }
        w.f64(k.fx);
        w.f64(k.fy);
        w.f64(k.cx);
        w.f64(k.cy);
        w.i32(k.width);
        w.i32(k.height);
        w.f32(s.max_range);
        w.zeros(4U);
    }
    for (std::size_t i = 0; i < frames.size(); ++i) {
        char name[L::kSceneNameBytes] = {};
        std::strncpy(name, scene_names.at(i), sizeof(name) - 1U);
        w.raw(name, sizeof(name));
    }
    for (const sim::SimulatedFrame& f : frames) {
        for (const std::vector<float>& depth : f.depth) {
            for (const float d : depth) {
                w.f32(d);
            }
        }
    }
    w.put_u32(L::kBlobSize, static_cast<std::uint32_t>(w.size() + L::kCrcBytes));
    w.u32(crc32(Span<const std::uint8_t>(w.bytes().data(), w.size())));
    return w.bytes();
}

/// Reads the command line: the output folder into @p dir and -1 to run, else
/// the exit status (0 after --help or --version, 2 after a usage error).
int parse_args(int argc, char** argv, std::string& dir) {
    host::CommandLine cli("cellguard-firmware-gen", "cellguard-firmware-gen OUTPUT_DIR",
                          "Renders the firmware's canned inputs on the host into the existing folder\n"
                          "OUTPUT_DIR: prior.cgprior (the prior image, as cellguard-prior writes it)\n"
                          "and frames.bin (four depth sensors at half the paper's resolution, three\n"
                          "scenes); for the robot-cell run robot.cgrobot (the demo arm's robot\n"
                          "image), robot_prior.cgprior and robot_frames.bin (five scenes with the\n"
                          "arm rendered); binary, doubles and floats as their exact bits. The\n"
                          "checked-in copies are in apps/firmware/generated.",
                          "Exit status: 0 written, 1 a computation or a write failed, 2 bad command line.");
    cli.argument("OUTPUT_DIR", "the existing folder the files go into", [&dir](const std::string& v) { dir = v; });
    return cli.parse(argc, argv);
}

/// The background prior of @p g into @p prior: eight frames of the empty
/// cell @p empty_cell fused into G_B, as in the controller's tests, then the accessibility
/// analysis with @p params. False (said on stderr) when a step fails.
bool background_prior(const GridGeometry& g, const std::vector<sim::SensorSpec>& sensors, const sim::Scene& empty_cell,
                      const AccessibilityParams& params, std::vector<std::int16_t>& prior) {
    const SensorModelTable model;
    std::vector<std::int16_t> frame_lo(g.voxel_count());
    std::vector<std::int16_t> bg_lo(g.voxel_count());
    std::vector<std::uint8_t> frame_ob(g.voxel_count());
    std::vector<std::uint8_t> bg_ob(g.voxel_count());
    EvidenceGrid frame =
        EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
    EvidenceGrid bg = EvidenceGrid::make(g, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    bg.clear();
    const sim::SimulatedFrame empty = sim::render_frame(sensors, empty_cell);
    std::vector<std::int16_t> scratch(g.voxel_count());
    for (int i = 0; i < 8; ++i) {
        if (!fuse_background_frame(bg, frame, {empty.readings.data(), empty.readings.size()}, model,
                                   {scratch.data(), scratch.size()})
                 .ok()) {
            static_cast<void>(std::fprintf(stderr, "fusion of the background failed\n"));
            return false;
        }
    }
    const AccessibilityScratchSize size = accessibility_scratch_size(g.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    if (!compute_accessibility_prior(bg, params,
                                     AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
                                     {prior.data(), prior.size()}, {})
             .ok()) {
        static_cast<void>(std::fprintf(stderr, "the accessibility prior failed\n"));
        return false;
    }
    return true;
}

/// @p prior as the prior image file DIR/@p name; false (said on stderr) when that fails.
bool write_prior_file(const std::string& dir, const char* name, const GridGeometry& g,
                      const AccessibilityParams& params, const std::vector<std::int16_t>& prior) {
    std::vector<std::uint8_t> image(prior_image_size(g.voxel_count()));
    if (!write_prior_image(g, params, {prior.data(), prior.size()}, {image.data(), image.size()}).ok()) {
        static_cast<void>(std::fprintf(stderr, "write_prior_image failed\n"));
        return false;
    }
    const Result<PriorImageView, PriorImageError> view = load_prior_image({image.data(), image.size()}, g);
    if (!view.ok() || !write_prior_image_file((dir + "/" + name).c_str(), view.value()).ok()) {
        static_cast<void>(std::fprintf(stderr, "writing %s failed\n", name));
        return false;
    }
    return true;
}

/// The three scenes' frames as DIR/frames.bin; false (said on stderr) when that fails.
bool write_frames_file(const std::string& dir, const std::vector<sim::SensorSpec>& sensors) {
    const std::vector<const char*> scene_names = {"empty", "person-in-warning-zone", "person-in-protective-zone"};
    const sim::Scene scenes[] = {sim::reference_scene(), with_person(-0.6, 0.6), with_person(0.2, 0.4)};
    std::vector<sim::SimulatedFrame> frames;
    for (const sim::Scene& scene : scenes) {
        frames.push_back(sim::render_frame(sensors, scene));
    }
    if (!write_bytes(dir + "/frames.bin", frames_blob(sensors, scene_names, frames))) {
        static_cast<void>(std::fprintf(stderr, "writing frames.bin failed\n"));
        return false;
    }
    return true;
}

/// A link of the demo arm: revolute, joint origin @p y, @p z in the parent
/// frame, unit axis y (@p axis_y) or z, limits +-@p limit, speed @p velocity.
RobotLink arm_joint(std::uint8_t parent, std::uint8_t index, double y, double z, bool axis_y, double limit,
                    double velocity) {
    RobotLink l;
    l.parent = parent;
    l.joint = JointType::kRevolute;
    l.command_index = index;
    l.origin_xyz[1] = y;
    l.origin_xyz[2] = z;
    l.axis[0] = 0.0;
    l.axis[1] = axis_y ? 1.0 : 0.0;
    l.axis[2] = axis_y ? 0.0 : 1.0;
    l.lower = -limit;
    l.upper = limit;
    l.max_velocity = velocity;
    return l;
}

/// A capsule of the demo arm on @p link from (0, ay, az) to (0, by, bz), radius @p r.
RobotCapsule arm_capsule(std::uint8_t link, double ay, double az, double by, double bz, double r) {
    RobotCapsule c;
    c.link = link;
    c.a[1] = ay;
    c.a[2] = az;
    c.b[1] = by;
    c.b[2] = bz;
    c.radius = r;
    return c;
}

/// The demo arm cellguard_arm6 as the URDF import makes it from
/// apps/monitor/config/robot-arm.urdf (joint order pan, shoulder lift,
/// elbow, wrist 1, 2, 3; base at the origin, not rotated), number for number:
/// its image is byte for byte the one cellguard-robot writes, CRC-32
/// 0xDE60A184 (kDemoArmImageCrc; the test
/// firmware_robot_image_is_the_demo_arm_urdf_import compares the files where
/// liburdfdom is installed). Built here rather than imported so that the
/// generator needs no liburdfdom (the aarch64 build has none) and the bytes
/// depend on no parser or libm: the +-2.78e-17 and +-6.94e-18 are the
/// import's rounding of its rotations by pi/2, kept so the bytes agree.
RobotModel demo_arm() {
    constexpr double kTwoPiLimit = 6.2832;  // the URDF's limits
    constexpr double kPiLimit = 3.1416;
    constexpr double kSlow = 2.0944;  // rad/s, base and shoulder
    constexpr double kFast = 3.1416;  // rad/s, elbow and wrists
    constexpr double kE17 = 2.7755575615628914e-17;
    constexpr double kE18 = 6.938893903907228e-18;
    RobotModel m;
    std::strncpy(m.name, "cellguard_arm6", sizeof m.name - 1U);
    m.link_count = 8U;
    m.joint_count = 6U;
    m.links[1] = arm_joint(0U, 0U, 0.0, 0.128, false, kTwoPiLimit, kSlow);  // shoulder_pan_joint
    m.links[2] = arm_joint(1U, 1U, 0.176, 0.0, true, kTwoPiLimit, kSlow);   // shoulder_lift_joint
    m.links[3] = arm_joint(2U, 2U, -0.137, 0.612, true, kPiLimit, kFast);   // elbow_joint
    m.links[4] = arm_joint(3U, 3U, 0.0, 0.572, true, kTwoPiLimit, kFast);   // wrist_1_joint
    m.links[5] = arm_joint(4U, 4U, 0.116, 0.0, false, kTwoPiLimit, kFast);  // wrist_2_joint
    m.links[6] = arm_joint(5U, 5U, 0.0, 0.116, true, kTwoPiLimit, kFast);   // wrist_3_joint
    RobotLink& tool = m.links[7];                                           // tool_joint, fixed, rpy (-pi/2, 0, 0)
    tool.parent = 6U;
    tool.origin_xyz[1] = 0.092;
    tool.origin_wxyz[0] = 0.7071067811865476;
    tool.origin_wxyz[1] = -0.7071067811865475;
    m.capsule_count = 8U;
    m.capsules[0] = arm_capsule(0U, 0.0, 0.0, 0.0, 0.128, 0.095);       // base_link cylinder
    m.capsules[1] = arm_capsule(1U, 0.175, -kE17, -0.075, kE17, 0.09);  // shoulder_link cylinder
    m.capsules[2] = arm_capsule(2U, 0.0, 0.0, 0.0, 0.612, 0.065);       // upper_arm_link: cylinder and spheres
    m.capsules[3] = arm_capsule(3U, 0.0, 0.0, 0.0, 0.572, 0.05);        // forearm_link: cylinder and spheres
    m.capsules[4] = arm_capsule(4U, 0.12, -kE18, 0.0, kE18, 0.045);     // wrist_1_link cylinder
    m.capsules[5] = arm_capsule(5U, 0.0, 0.0, 0.0, 0.12, 0.045);        // wrist_2_link cylinder
    m.capsules[6] = arm_capsule(6U, 0.092, -kE18, 0.0, kE18, 0.045);    // wrist_3_link cylinder
    m.capsules[7] = arm_capsule(7U, 0.0, 0.0, 0.0, 0.1, 0.05);          // tool_link box 80 x 60 x 100 mm
    return m;
}

/// The demo arm as DIR/robot.cgrobot, read back with load_robot_image into
/// @p loaded; false (said on stderr) when that fails or the CRC is not kDemoArmImageCrc.
bool write_robot_file(const std::string& dir, LoadedRobot& loaded) {
    std::vector<std::uint8_t> image(kRobotImageMaxBytes);
    const Result<std::size_t, RobotModelError> written = write_robot_image(demo_arm(), {image.data(), image.size()});
    if (!written.ok()) {
        static_cast<void>(std::fprintf(stderr, "write_robot_image failed: %s\n", written.error().reason));
        return false;
    }
    image.resize(written.value());
    const Result<LoadedRobot, RobotModelError> back = load_robot_image({image.data(), image.size()});
    if (!back.ok() || back.value().crc != firmware::kDemoArmImageCrc) {
        static_cast<void>(std::fprintf(stderr, "the robot image does not read back as the demo arm (CRC 0x%08x)\n",
                                       back.ok() ? back.value().crc : 0U));
        return false;
    }
    loaded = back.value();
    if (!write_bytes(dir + "/robot.cgrobot", image)) {
        static_cast<void>(std::fprintf(stderr, "writing robot.cgrobot failed\n"));
        return false;
    }
    return true;
}

/// The robot cell of apps/evaluation/scenes/robot-cell.toml (built into the
/// host floor): its static boxes and its four sensors at a quarter of their
/// resolution (same fields of view), into @p empty_cell and @p sensors.
bool robot_cell(sim::Scene& empty_cell, std::vector<sim::SensorSpec>& sensors) {
    std::string text;
    if (!cell::read_config_text("builtin:robot-cell-scene.toml", text)) {
        static_cast<void>(std::fprintf(stderr, "the built-in robot-cell scene is missing\n"));
        return false;
    }
    const sim::SceneLoad load = sim::parse_scene(text, "robot-cell.toml");
    if (!load.ok) {
        static_cast<void>(std::fprintf(stderr, "robot-cell scene: %s\n", load.error.c_str()));
        return false;
    }
    empty_cell = load.scene.scene;
    sensors = load.scene.sensors;
    for (sim::SensorSpec& spec : sensors) {
        spec.width /= 4;
        spec.height /= 4;
    }
    return true;
}

/// The robot scenes (robot_scenes()) as DIR/robot_frames.bin: the arm in
/// the pose its command reports (converted by the controller's own
/// joint_positions and placed by place_robot), a standing person.
bool write_robot_frames_file(const std::string& dir, const LoadedRobot& robot, const sim::Scene& empty_cell,
                             const std::vector<sim::SensorSpec>& sensors) {
    std::vector<const char*> names;
    std::vector<sim::SimulatedFrame> frames;
    for (const firmware::RobotScene& rs : firmware::robot_scenes()) {
        RobotCommand command;
        command.joint_count = static_cast<std::uint8_t>(firmware::kRobotScenarioJoints);
        command.robot_id = robot_id(robot.crc);
        const std::array<std::int16_t, firmware::kRobotScenarioJoints> raw = firmware::arm_pose_raw(rs.arm);
        for (std::size_t j = 0U; j < raw.size(); ++j) {
            command.joint_raw[j] = raw[j];
        }
        const Result<JointPositions, JointCheck> q = joint_positions(robot.model, robot.crc, command);
        if (!q.ok()) {
            static_cast<void>(std::fprintf(stderr, "scene %s: joints refused: %s\n", rs.name, to_string(q.error())));
            return false;
        }
        sim::Scene scene = empty_cell;
        place_robot(robot.model, q.value(), scene.robot);
        if (rs.person) {
            sim::PersonSpec person;
            person.start_s = 1.0;  // stands at the first waypoint at t = 0
            person.path = {Eigen::Vector2d(rs.person_x, rs.person_y), Eigen::Vector2d(rs.person_x + 1.0, rs.person_y)};
            for (const sim::Box& b : sim::person_boxes(person, 0.0)) {
                scene.boxes.push_back(b);
            }
        }
        static_cast<void>(
            std::printf("robot scene %s: person-robot distance %.3f m\n", rs.name, sim::person_robot_distance(scene)));
        names.push_back(rs.name);
        frames.push_back(sim::render_frame(sensors, scene));
    }
    if (!write_bytes(dir + "/robot_frames.bin", frames_blob(sensors, names, frames))) {
        static_cast<void>(std::fprintf(stderr, "writing robot_frames.bin failed\n"));
        return false;
    }
    return true;
}

/// The robot cell's files: robot.cgrobot, robot_prior.cgprior, robot_frames.bin.
bool write_robot_cell_files(const std::string& dir) {
    LoadedRobot robot;
    sim::Scene empty_cell;
    std::vector<sim::SensorSpec> sensors;
    if (!write_robot_file(dir, robot) || !robot_cell(empty_cell, sensors)) {
        return false;
    }
    const GridGeometry g = firmware::robot_cell_grid_geometry();
    const AccessibilityParams params;
    std::vector<std::int16_t> prior(g.voxel_count());
    return background_prior(g, sensors, empty_cell, params, prior) &&
           write_prior_file(dir, "robot_prior.cgprior", g, params, prior) &&
           write_robot_frames_file(dir, robot, empty_cell, sensors);
}

}  // namespace

int main(int argc, char** argv) {
    std::string dir;
    const int parse_status = parse_args(argc, argv, dir);
    if (parse_status >= 0) {
        return parse_status;
    }
    const GridGeometry g = paper_grid_geometry();
    const std::vector<sim::SensorSpec> sensors = firmware_sensors();
    const AccessibilityParams params;
    std::vector<std::int16_t> prior(g.voxel_count());
    if (!background_prior(g, sensors, sim::reference_scene(), params, prior) ||
        !write_prior_file(dir, "prior.cgprior", g, params, prior) || !write_frames_file(dir, sensors) ||
        !write_robot_cell_files(dir)) {
        return 1;
    }
    static_cast<void>(
        std::printf("cellguard-firmware-gen: wrote prior.cgprior, frames.bin, robot.cgrobot, robot_prior.cgprior and "
                    "robot_frames.bin to %s\n",
                    dir.c_str()));
    return 0;
}
