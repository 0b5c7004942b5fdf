// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies urdf_import.hpp: the demo arm's URDF as a RobotModel, the capsules of each geometry (meshes from STL
// included, each vertex inside), and every refusal naming its link, joint or file.
// Requirements: SR-ROB-101, SR-ROB-102, SR-ROB-103, SR-ROB-104, SR-ROB-106, SR-ROB-107, SR-ROB-108
#include <doctest/doctest.h>

#if defined(CELLGUARD_HOST_URDF) && CELLGUARD_HOST_URDF  // a cross build has no liburdfdom (apps/host/CMakeLists.txt)

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/host/io/urdf_import.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "stl_reference.hpp"
#include "temp_dir.hpp"

using namespace cellguard;
using cellguard::host::UrdfImport;
using cellguard::host::UrdfImportOptions;

using cellguard::test::TempDir;

namespace {

const char* const kArmOrder[] = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                 "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};

std::string arm_path() { return std::string(CELLGUARD_SOURCE_DIR) + "/apps/monitor/config/robot-arm.urdf"; }

UrdfImportOptions arm_options() {
    UrdfImportOptions o;
    o.joint_order.assign(std::begin(kArmOrder), std::end(kArmOrder));
    return o;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void write_text(const std::string& path, const std::string& text) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::ofstream out(path, std::ios::binary);
    out << text;
}

const char* const kLimit = R"(<limit lower="-1" upper="1" velocity="2" effort="1"/>)";
const char* const kSphere = R"(<collision><geometry><sphere radius="0.1"/></geometry></collision>)";

std::string link(const std::string& name, const std::string& body = kSphere) {
    return "<link name=\"" + name + "\">" + body + "</link>";
}

std::string joint(const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& type = "revolute",
                  const std::string& body = std::string(R"(<axis xyz="0 0 1"/>)") + kLimit) {
    return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" +
           child + "\"/><origin xyz=\"0 0 0.1\"/>" + body + "</joint>";
}

std::string robot(const std::string& body) { return "<robot name=\"test_robot\">" + body + "</robot>"; }

/// A root "base" and one revolute joint j1 to "arm" whose link body is @p arm_body.
std::string two_links(const std::string& arm_body = kSphere) {
    return robot(link("base") + link("arm", arm_body) + joint("j1", "base", "arm"));
}

UrdfImportOptions order(std::vector<std::string> names) {
    UrdfImportOptions o;
    o.joint_order = std::move(names);
    return o;
}

/// Imports @p text expecting a refusal whose message holds each of @p needles; returns the message.
std::string refusal(const std::string& text, const UrdfImportOptions& options, std::vector<std::string> needles) {
    UrdfImport r;
    const IoStatus st = host::import_urdf_text(text, options, r);
    CHECK_FALSE(st.ok());
    const std::string message = st.message();
    for (const std::string& needle : needles) {
        INFO("message: " << message);
        CHECK(message.find(needle) != std::string::npos);
    }
    return message;
}

std::string collision(const std::string& geometry, const std::string& origin = "") {
    return "<collision>" + origin + "<geometry>" + geometry + "</geometry></collision>";
}

bool near(double a, double b, double tol = 1e-9) { return std::abs(a - b) <= tol; }

/// Four triangles through the 8 corners of an x by y by z box (binary writer input).
std::vector<std::vector<float>> box_triangles(float x, float y, float z) {
    return {{0, 0, 0, x, 0, 0, 0, y, 0},
            {x, y, 0, x, 0, z, 0, y, z},
            {x, y, z, 0, 0, z, x, 0, 0},
            {0, y, 0, 0, 0, z, x, y, z}};
}

void write_binary_stl(const std::string& path, const std::vector<std::vector<float>>& triangles) {
    std::vector<std::uint8_t> out(80U, 0U);
    const auto n = static_cast<std::uint32_t>(triangles.size());
    auto put32 = [&out](std::uint32_t v) {
        for (int k = 0; k < 4; ++k) {
            out.push_back(static_cast<std::uint8_t>(v >> (8U * static_cast<unsigned>(k))));
        }
    };
    put32(n);
    for (const auto& t : triangles) {
        for (int k = 0; k < 3; ++k) {
            put32(0U);
        }
        for (const float f : t) {
            std::uint32_t bits = 0U;
            std::memcpy(&bits, &f, sizeof(bits));
            put32(bits);
        }
        out.push_back(0U);
        out.push_back(0U);
    }
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::ofstream file(path, std::ios::binary);
    file.write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
}

/// Checks that capsule @p c of @p model contains @p p (link frame).
bool contains(const RobotCapsule& c, const Eigen::Vector3d& p) {
    const Eigen::Vector3d a(c.a[0], c.a[1], c.a[2]);
    const Eigen::Vector3d b(c.b[0], c.b[1], c.b[2]);
    return host::segment_distance(p, a, b) <= c.radius + 1e-12;
}

}  // namespace

// verifies: SR-ROB-101
TEST_CASE("urdf import: the demo arm gives 8 links, 6 joints in the PLC's order and 8 capsules") {
    UrdfImport r;
    const IoStatus st = host::import_urdf_file(arm_path(), arm_options(), r);
    REQUIRE_MESSAGE(st.ok(), st.message());
    const RobotModel& m = r.model;
    CHECK(std::string(m.name) == "cellguard_arm6");
    CHECK(m.link_count == 8U);
    CHECK(m.joint_count == 6U);
    CHECK(m.capsule_count == 8U);
    const char* const links[] = {"base_link",    "shoulder_link", "upper_arm_link", "forearm_link",
                                 "wrist_1_link", "wrist_2_link",  "wrist_3_link",   "tool_link"};
    REQUIRE(r.link_names.size() == 8U);
    for (std::size_t i = 0U; i < 8U; ++i) {
        CHECK(r.link_names[i] == links[i]);
        if (i > 0U) {
            CHECK(m.links[i].parent == i - 1U);
        }
        if (i >= 1U && i <= 6U) {
            CHECK(m.links[i].joint == JointType::kRevolute);
            CHECK(m.links[i].command_index == i - 1U);
            CHECK(r.joint_names[i] == kArmOrder[i - 1U]);
        }
    }
    CHECK(m.links[7].joint == JointType::kFixed);
    CHECK(m.links[1].origin_xyz[2] == doctest::Approx(0.128));
    CHECK(m.links[2].max_velocity == doctest::Approx(2.0944));
    CHECK(m.links[3].lower == doctest::Approx(-3.1416));
    CHECK(m.links[3].upper == doctest::Approx(3.1416));
    CHECK(check_robot_model(m).code == ErrorCode::kOk);
}

// verifies: SR-ROB-102
TEST_CASE("urdf import: the demo arm's known capsules (box, merged cylinder and spheres, rotated cylinder)") {
    UrdfImport r;
    REQUIRE(host::import_urdf_file(arm_path(), arm_options(), r).ok());
    const RobotModel& m = r.model;
    // The gripper box 0.08 x 0.06 x 0.1 at z 0.05: along z, 0.1 long, radius half the 0.08 x 0.06 diagonal.
    const RobotCapsule& tool = m.capsules[7];
    CHECK(tool.link == 7U);
    CHECK(near(tool.a[2], 0.0));
    CHECK(near(tool.b[2], 0.1));
    CHECK(near(tool.radius, 0.05));
    // The upper arm's cylinder and its two end spheres: one capsule from the shoulder to the elbow.
    const RobotCapsule& upper = m.capsules[2];
    CHECK(upper.link == 2U);
    CHECK(near(upper.radius, 0.065));
    CHECK(near(std::abs(upper.b[2] - upper.a[2]), 0.612));
    // The shoulder housing, a cylinder turned about x: along y from -0.075 to 0.175.
    const RobotCapsule& shoulder = m.capsules[1];
    CHECK(near(std::min(shoulder.a[1], shoulder.b[1]), -0.075, 1e-12));
    CHECK(near(std::max(shoulder.a[1], shoulder.b[1]), 0.175, 1e-12));
    CHECK(near(shoulder.a[2], 0.0, 1e-12));
    bool merged = false;
    bool dropped = false;
    for (const std::string& note : r.notes) {
        merged = merged || note.find("link 'upper_arm_link': 2 sphere(s) merged") != std::string::npos;
        dropped = dropped || note.find("tcp") != std::string::npos;
    }
    CHECK(merged);
    CHECK(dropped);
}

// verifies: SR-ROB-101
TEST_CASE("urdf import: the demo arm, placed by the controller's kinematics, stands 1.43 m tall and reaches sideways") {
    UrdfImportOptions o = arm_options();
    o.base_xyz = Eigen::Vector3d(0.5, 0.0, 0.0);
    o.base_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2.0, Eigen::Vector3d::UnitZ()));
    UrdfImport r;
    REQUIRE(host::import_urdf_file(arm_path(), o, r).ok());
    JointPositions q;
    q.count = 6U;
    RobotPose pose;
    place_robot(r.model, q, pose);
    // Zero pose: upright; the wrists offset the tool along the arm's y, which the base's 90 deg turns into -x.
    const PlacedCapsule& tool = pose.capsules[7];
    CHECK(tool.b[0] == doctest::Approx(0.5 - (0.176 - 0.137 + 0.116 + 0.092 + 0.1)));
    CHECK(tool.b[1] == doctest::Approx(0.0));
    CHECK(tool.b[2] == doctest::Approx(0.128 + 0.612 + 0.572 + 0.116));
    // Shoulder lift +90 deg about the arm's y: the upper arm and forearm lie along the arm's x (the world's y).
    q.q[1] = M_PI / 2.0;
    place_robot(r.model, q, pose);
    const PlacedCapsule& forearm = pose.capsules[3];
    CHECK(std::max(forearm.a[1], forearm.b[1]) == doctest::Approx(0.612 + 0.572));
    CHECK(forearm.a[2] == doctest::Approx(0.128));
    CHECK(forearm.b[2] == doctest::Approx(0.128));
}

// verifies: SR-ROB-101
TEST_CASE("urdf import: the demo arm's model survives the robot image unchanged") {
    UrdfImport r;
    REQUIRE(host::import_urdf_file(arm_path(), arm_options(), r).ok());
    std::vector<std::uint8_t> bytes(kRobotImageMaxBytes);
    const auto written = write_robot_image(r.model, Span<std::uint8_t>(bytes.data(), bytes.size()));
    REQUIRE(written.ok());
    const auto loaded = load_robot_image(Span<const std::uint8_t>(bytes.data(), written.value()));
    REQUIRE(loaded.ok());
    const RobotModel& m = loaded.value().model;
    CHECK(std::string(m.name) == "cellguard_arm6");
    CHECK(m.capsule_count == r.model.capsule_count);
    CHECK(m.capsules[7].radius == r.model.capsules[7].radius);
    CHECK(m.links[3].upper == r.model.links[3].upper);
}

// verifies: SR-ROB-101
TEST_CASE("urdf import: the command positions follow the PLC's order, the base pose is applied") {
    UrdfImportOptions o = arm_options();
    std::swap(o.joint_order[0], o.joint_order[5]);
    o.base_xyz = Eigen::Vector3d(1.0, -2.0, 0.5);
    o.base_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
    UrdfImport r;
    REQUIRE(host::import_urdf_text(read_text(arm_path()), o, r).ok());
    CHECK(r.model.links[1].command_index == 5U);
    CHECK(r.model.links[6].command_index == 0U);
    CHECK(r.model.base_xyz[1] == -2.0);
    CHECK(r.model.base_wxyz[0] == doctest::Approx(std::cos(0.25)));
    CHECK(r.model.base_wxyz[3] == doctest::Approx(std::sin(0.25)));
}

// verifies: SR-ROB-103
TEST_CASE("urdf import: what liburdfdom drops silently is refused with its log naming the link") {
    const UrdfImportOptions o = order({"j1"});
    // <capsule> is not URDF 1.0: liburdfdom logs, drops it and the sphere after it, and returns a model.
    refusal(two_links(collision(R"(<capsule radius="0.1" length="0.2"/>)") + kSphere), o,
            {"Unknown geometry type 'capsule'", "Link [arm]"});
    refusal(two_links("<collision></collision>"), o, {"Link [arm]"});
    refusal(two_links(collision(R"(<box size="0.1 nan 0.1"/>)")), o, {"nan", "Link [arm]"});
    refusal(two_links(collision(R"(<mesh filename="m.stl" scale="2"/>)")), o, {"scale", "Link [arm]"});
}

// verifies: SR-ROB-103
TEST_CASE("urdf import: zero, negative and non-finite sizes are refused naming the link") {
    const UrdfImportOptions o = order({"j1"});
    refusal(two_links(collision(R"(<sphere radius="-0.1"/>)")), o, {"link 'arm'", "sphere radius -0.1"});
    refusal(two_links(collision(R"(<sphere radius="0"/>)")), o, {"link 'arm'", "must be > 0"});
    refusal(two_links(collision(R"(<cylinder radius="0.1" length="0"/>)")), o, {"link 'arm'", "cylinder length"});
    refusal(two_links(collision(R"(<box size="0.1 -0.2 0.1"/>)")), o, {"link 'arm'", "box size"});
    refusal(two_links(collision(R"(<mesh filename="m.stl" scale="1 -1 1"/>)")), o, {"link 'arm'", "scale"});
    refusal(two_links(collision(R"(<sphere radius="1e400"/>)")), o, {"arm"});
    refusal(two_links(collision(R"(<sphere radius="1.5"/>)")), o, {"link 'arm'", "radius 1.500 m"});
    UrdfImport r;
    REQUIRE(host::import_urdf_text(two_links(R"(<visual><geometry><sphere radius="0.1"/></geometry></visual>)"), o, r)
                .ok());
    CHECK(r.model.capsule_count == 1U);
    REQUIRE(r.notes.size() == 1U);
    CHECK(r.notes[0] == "link 'arm' has visual but no collision geometry: no capsule, not masked");
}

// verifies: SR-ROB-104
TEST_CASE("urdf import: bad axes are refused naming the joint, nearly unit ones normalised") {
    const UrdfImportOptions o = order({"j1"});
    const std::string lim = kLimit;
    auto with_axis = [&](const std::string& axis) {
        return robot(link("base") + link("arm") + joint("j1", "base", "arm", "revolute", axis + lim));
    };
    refusal(with_axis(R"(<axis xyz="0 0 0"/>)"), o, {"joint 'j1': zero axis"});
    refusal(with_axis(R"(<axis xyz="0 0 2"/>)"), o, {"joint 'j1'", "length 2"});
    refusal(with_axis(R"(<axis xyz="1 1 0"/>)"), o, {"joint 'j1'", "not 1"});
    refusal(with_axis(""), o, {"joint 'j1' (revolute) has no <axis>"});
    UrdfImport r;
    REQUIRE(host::import_urdf_text(with_axis(R"(<axis xyz="0.7071 0 0.7071"/>)"), o, r).ok());
    CHECK(std::hypot(r.model.links[1].axis[0], r.model.links[1].axis[2]) == doctest::Approx(1.0).epsilon(1e-12));
    REQUIRE(!r.notes.empty());
    CHECK(r.notes[0].find("joint 'j1': axis of length") != std::string::npos);
}

// verifies: SR-ROB-104
TEST_CASE("urdf import: joint limits: velocity, order, range, continuous joints, a zero pose outside") {
    const UrdfImportOptions o = order({"j1"});
    const std::string axis = R"(<axis xyz="0 0 1"/>)";
    auto with = [&](const std::string& type, const std::string& limit) {
        return robot(link("base") + link("arm") + joint("j1", "base", "arm", type, axis + limit));
    };
    refusal(with("revolute", R"(<limit lower="-1" upper="1" velocity="0" effort="1"/>)"), o,
            {"joint 'j1': velocity limit 0"});
    refusal(with("revolute", R"(<limit lower="-1" upper="1" velocity="-2" effort="1"/>)"), o, {"joint 'j1'"});
    refusal(with("revolute", R"(<limit lower="1" upper="-1" velocity="1" effort="1"/>)"), o,
            {"joint 'j1': lower limit 1 above upper limit -1"});
    refusal(with("revolute", R"(<limit lower="-7" upper="1" velocity="1" effort="1"/>)"), o,
            {"joint 'j1'", "command's range"});
    refusal(with("prismatic", R"(<limit lower="0" upper="3.5" velocity="1" effort="1"/>)"), o,
            {"joint 'j1'", "3.2767 m"});
    refusal(with("continuous", ""), o, {"joint 'j1': velocity limit 0"});
    refusal(with("revolute", R"(<limit velocity="1" effort="1"/>)"), o, {"joint 'j1': no range (lower = upper = 0)"});
    UrdfImport r;
    REQUIRE(host::import_urdf_text(with("continuous", R"(<limit velocity="3" effort="1"/>)"), o, r).ok());
    CHECK(r.model.links[1].joint == JointType::kRevolute);
    CHECK(r.model.links[1].lower == doctest::Approx(-2.0 * M_PI));
    CHECK(r.model.links[1].upper == doctest::Approx(2.0 * M_PI));
    // A real arm's zero pose may lie outside its limits.
    REQUIRE(host::import_urdf_text(with("revolute", R"(<limit lower="0.5" upper="1" velocity="1" effort="1"/>)"), o, r)
                .ok());
    REQUIRE(
        host::import_urdf_text(with("prismatic", R"(<limit lower="0" upper="0.5" velocity="0.2" effort="1"/>)"), o, r)
            .ok());
    CHECK(r.model.links[1].joint == JointType::kPrismatic);
}

// verifies: SR-ROB-104
TEST_CASE("urdf import: floating and planar joints are refused naming the joint") {
    const UrdfImportOptions none = order({});
    refusal(robot(link("base") + link("arm") + joint("free", "base", "arm", "floating", "")), none,
            {"joint 'free' is floating"});
    refusal(robot(link("base") + link("arm") + joint("plane", "base", "arm", "planar", R"(<axis xyz="0 0 1"/>)")), none,
            {"joint 'plane' is planar"});
}

namespace {

/// A palletizer's arm: pan j1 to "turret", lift j2 to "upper_arm", elbow j3 to "forearm"; a rear bar on the
/// turret that mimics the lift (@p bar_mimic: attributes of its <mimic>), and "wrist" on the forearm kept level
/// by a mimic of the elbow (x -1 + 0.2). Each link a 0.1 m sphere.
std::string palletizer(const std::string& bar_mimic = R"(joint="j2")") {
    const std::string y_axis = R"(<axis xyz="0 1 0"/>)";
    return robot(link("base") + link("turret") + link("upper_arm") + link("rear_bar") + link("forearm") +
                 link("wrist") + joint("j1", "base", "turret") +
                 joint("j2", "turret", "upper_arm", "revolute", y_axis + kLimit) +
                 joint("j3", "upper_arm", "forearm", "revolute", y_axis + kLimit) +
                 joint("bar", "turret", "rear_bar", "revolute", y_axis + "<mimic " + bar_mimic + "/>" + kLimit) +
                 joint("wrist_level", "forearm", "wrist", "revolute",
                       y_axis + R"(<mimic joint="j3" multiplier="-1" offset="0.2"/>)" +
                           R"(<limit lower="-1" upper="1.3" velocity="2" effort="1"/>)"));
}

std::size_t link_named(const UrdfImport& r, const std::string& name) {
    const auto it = std::find(r.link_names.begin(), r.link_names.end(), name);
    REQUIRE(it != r.link_names.end());
    return static_cast<std::size_t>(it - r.link_names.begin());
}

}  // namespace

// verifies: SR-ROB-111
TEST_CASE("urdf import: an arm joint's mimic follows its master, is not sent, and places as that position sent") {
    UrdfImport r;
    REQUIRE(host::import_urdf_text(palletizer(), order({"j1", "j2", "j3"}), r).ok());
    const RobotModel& m = r.model;
    CHECK(m.link_count == 6U);
    CHECK(m.joint_count == 3U);
    const RobotLink& bar = m.links[link_named(r, "rear_bar")];
    const RobotLink& level = m.links[link_named(r, "wrist")];
    CHECK(bar.mimic);
    CHECK(bar.command_index == 1U);
    CHECK(bar.mimic_multiplier == 1.0);
    CHECK(bar.mimic_offset == 0.0);
    CHECK(level.mimic);
    CHECK(level.command_index == 2U);
    CHECK(level.mimic_multiplier == -1.0);
    CHECK(level.mimic_offset == 0.2);
    CHECK_FALSE(m.links[link_named(r, "upper_arm")].mimic);
    CHECK(std::any_of(r.notes.begin(), r.notes.end(),
                      [](const std::string& n) { return n.find("joint 'wrist_level' mimics 'j3': not sent") == 0U; }));
    CHECK(robot_image_version(m) == kRobotImageMimicFormatVersion);
    // The reference: the same arm without <mimic>, all five joints sent, the followers at their positions.
    std::string plain = palletizer();
    for (const std::string tag : {R"(<mimic joint="j2"/>)", R"(<mimic joint="j3" multiplier="-1" offset="0.2"/>)"}) {
        plain.erase(plain.find(tag), tag.size());
    }
    UrdfImport reference;
    REQUIRE(host::import_urdf_text(plain, order({"j1", "j2", "j3", "bar", "wrist_level"}), reference).ok());
    REQUIRE(reference.model.capsule_count == m.capsule_count);
    for (const double lift : {-0.9, 0.0, 0.6}) {
        for (const double elbow : {-1.0, 0.3, 1.0}) {
            JointPositions q;
            q.count = 3U;
            q.q[0] = 0.4;
            q.q[1] = lift;
            q.q[2] = elbow;
            JointPositions q5 = q;
            q5.count = 5U;
            q5.q[3] = 1.0 * lift + 0.0;
            q5.q[4] = -1.0 * elbow + 0.2;
            RobotPose got;
            RobotPose want;
            place_robot(m, q, got);
            place_robot(reference.model, q5, want);
            for (std::size_t c = 0U; c < m.capsule_count; ++c) {
                INFO("capsule " << c << ", lift " << lift << ", elbow " << elbow);
                CHECK(std::memcmp(&got.capsules[c], &want.capsules[c], sizeof(PlacedCapsule)) == 0);
            }
        }
    }
}

// verifies: SR-ROB-111
TEST_CASE("urdf import: an arm joint's mimic that is sent, has a wrong ratio or follows a mimic is refused") {
    const UrdfImportOptions arm = order({"j1", "j2", "j3"});
    refusal(palletizer(), order({"j1", "j2", "j3", "bar"}),
            {"joint order: joint 'bar' mimics 'j2' and follows it: the PLC does not send it"});
    refusal(palletizer(R"(joint="j2" multiplier="2")"), arm,
            {"joint 'bar' mimics joint 'j2' (x 2 + 0)", "outside its own limits", "a wrong multiplier or offset?"});
    refusal(palletizer(R"(joint="j2" offset="0.5")"), arm, {"joint 'bar' mimics joint 'j2' (x 1 + 0.5)"});
    refusal(palletizer(R"(joint="j2" multiplier="0" offset="0")"), arm, {"joint 'bar': mimic multiplier 0"});
    refusal(palletizer(R"(joint="wrist_level")"), arm, {"joint 'bar' mimics joint 'wrist_level', itself a mimic"});
    refusal(palletizer(R"(joint="ghost")"), arm, {"joint 'bar' mimics joint 'ghost', which is not a movable joint"});
    // Without a velocity limit a mimic takes its master's x |multiplier|; a negative one is still refused.
    std::string slow = palletizer();
    const std::string bar_limit = R"(<mimic joint="j2"/><limit lower="-1" upper="1" velocity="2")";
    REQUIRE(slow.find(bar_limit) != std::string::npos);
    slow.replace(slow.find(bar_limit), bar_limit.size(),
                 R"(<mimic joint="j2"/><limit lower="-1" upper="1" velocity="0")");
    UrdfImport r;
    REQUIRE(host::import_urdf_text(slow, arm, r).ok());
    CHECK(r.model.links[link_named(r, "rear_bar")].max_velocity == 2.0);
    slow.replace(slow.find("velocity=\"0\""), 12, "velocity=\"-1\"");
    refusal(slow, arm, {"joint 'bar': velocity limit -1, must be > 0"});
}

namespace {

const char* const kFingerLimit = R"(<limit lower="0" upper="0.04" velocity="0.2" effort="20"/>)";

/// A Panda-like hand: j1 (revolute) to "hand", two prismatic fingers along +y and -y, the second a mimic of the
/// first with @p mimic (attributes of <mimic>), a 10 x 20 x 50 mm box on each finger.
std::string gripper(const std::string& mimic = R"(joint="finger_joint1")") {
    const std::string finger = collision(R"(<box size="0.01 0.02 0.05"/>)", R"(<origin xyz="0 0 0.025"/>)");
    return robot(
        link("base") + link("hand", collision(R"(<box size="0.05 0.2 0.06"/>)")) + link("left", finger) +
        link("right", finger) + joint("j1", "base", "hand") +
        joint("finger_joint1", "hand", "left", "prismatic", std::string(R"(<axis xyz="0 1 0"/>)") + kFingerLimit) +
        joint("finger_joint2", "hand", "right", "prismatic",
              std::string(R"(<axis xyz="0 -1 0"/><mimic )") + mimic + "/>" + kFingerLimit));
}

UrdfImportOptions gripper_options() {
    UrdfImportOptions o = order({"j1"});
    o.stroke_joints = {"finger_joint1"};
    return o;
}

}  // namespace

// verifies: SR-ROB-108
TEST_CASE("urdf import: a gripper's fingers, one a mimic, fold into the hand, enclosed over the whole stroke") {
    UrdfImport r;
    const IoStatus st = host::import_urdf_text(gripper(), gripper_options(), r);
    REQUIRE_MESSAGE(st.ok(), st.message());
    // base, hand: the fingers are no links of the model, no finger joint goes over CAN.
    CHECK(r.model.link_count == 2U);
    CHECK(r.model.joint_count == 1U);
    REQUIRE(r.model.capsule_count == 4U);  // the base's sphere, the hand's box, a finger's envelope each
    REQUIRE(r.folded.size() == 2U);
    CHECK(r.folded[0].anchor == "hand");
    CHECK(r.model.capsules[2].link == 1U);
    CHECK(r.model.capsules[3].link == 1U);
    // Each finger's box corners, at 2,001 positions of the stroke (finger 2 at -y, the mimic), inside its envelope.
    for (std::size_t f = 0U; f < 2U; ++f) {
        const RobotCapsule& c = r.model.capsules[2U + f];
        const std::string& name = r.folded[f].link;
        const double sign = name == "left" ? 1.0 : -1.0;
        bool all = true;
        for (int k = 0; k <= 2000; ++k) {
            const double q = 0.04 * k / 2000.0;
            for (int corner = 0; corner < 8; ++corner) {
                const Eigen::Vector3d p((corner & 1) != 0 ? 0.005 : -0.005, ((corner & 2) != 0 ? 0.01 : -0.01),
                                        ((corner & 4) != 0 ? 0.05 : 0.0));
                all = all && contains(c, p + Eigen::Vector3d(0.0, sign * q, 0.1));
            }
        }
        CHECK_MESSAGE(all, name);
    }
    // What it costs: the finger's 50 mm capsule swept 40 mm sideways: a capsule along the finger, thicker by
    // half the stroke (20 mm), and no more than a millimetre beyond that.
    const host::Capsule& before = r.folded[0].original;
    const host::Capsule& after = r.folded[0].envelope;
    MESSAGE("finger capsule radius " << before.radius << " -> " << after.radius << " m, volume "
                                     << host::capsule_volume(before) * 1e3 << " -> "
                                     << host::capsule_volume(after) * 1e3 << " L");
    CHECK(after.radius >= before.radius + 0.02);
    CHECK(after.radius <= before.radius + 0.021);
    CHECK((after.b - after.a).norm() == doctest::Approx(0.05).epsilon(0.02));
    bool noted = false;
    for (const std::string& note : r.notes) {
        noted = noted || note.find("link 'left' folded into 'hand' over its stroke") != std::string::npos;
    }
    CHECK(noted);
}

// verifies: SR-ROB-108
TEST_CASE("urdf import: a mimic ratio that drives the finger outside its own limits is refused as a wrong ratio") {
    refusal(gripper(R"(joint="finger_joint1" multiplier="2")"), gripper_options(),
            {"joint 'finger_joint2' mimics joint 'finger_joint1' (x 2 + 0)", "0 .. 0.08", "outside its own limits",
             "a wrong multiplier or offset?"});
    refusal(gripper(R"(joint="finger_joint1" offset="-0.01")"), gripper_options(), {"-0.01 .. 0.03"});
    refusal(gripper(R"(joint="ghost")"), gripper_options(), {"mimics joint 'ghost', which is not a movable joint"});
    // Named itself, a mimic is enclosed over its own limits (and the notes say so).
    UrdfImportOptions both = gripper_options();
    both.stroke_joints.emplace_back("finger_joint2");
    UrdfImport r;
    REQUIRE(host::import_urdf_text(gripper(R"(joint="finger_joint1" multiplier="2")"), both, r).ok());
    CHECK(r.folded.size() == 2U);
}

// verifies: SR-ROB-108
TEST_CASE("urdf import: stroke joints are movable joints of the URDF, named once, never also sent by the PLC") {
    UrdfImportOptions o = gripper_options();
    o.stroke_joints = {"nope"};
    refusal(gripper(), o, {"stroke joint 'nope' is not a movable joint of the URDF"});
    o.stroke_joints = {"finger_joint1", "finger_joint1"};
    refusal(gripper(), o, {"stroke joint 'finger_joint1' named twice"});
    o = order({"j1", "finger_joint1"});
    o.stroke_joints = {"finger_joint1"};
    refusal(gripper(), o, {"joint 'finger_joint1' is named both in the PLC's order and a stroke joint"});
    // The arm below a stroke joint cannot be sent by the PLC.
    o = order({"j1"});
    o.stroke_joints = {"j1"};
    refusal(gripper(), o, {"stroke joint", "j1"});
    o = order({});
    o.stroke_joints = {"j1"};
    refusal(gripper(), o, {"joint 'finger_joint1' moves below a stroke joint: name it a stroke joint too"});
    // Without naming the fingers: the missing joint says what to do.
    // A finger the PLC sends: its mimic follows it as an arm joint's mimic would.
    UrdfImport sent;
    REQUIRE(host::import_urdf_text(gripper(), order({"j1", "finger_joint1"}), sent).ok());
    CHECK(sent.model.joint_count == 2U);
    CHECK(sent.model.links[link_named(sent, "right")].mimic);
    refusal(gripper(R"(joint="j1")"), order({"j1", "finger_joint1"}),
            {"joint 'finger_joint2' mimics joint 'j1'", "a wrong multiplier or offset?"});
}

// verifies: SR-ROB-106
TEST_CASE("urdf import: the PLC's joint order names each movable joint once and nothing else") {
    const std::string text = robot(link("base") + link("a") + link("b") + joint("j1", "base", "a") +
                                   joint("fix", "a", "b", "fixed", ""));
    refusal(text, order({"j1", "nope"}), {"joint order: joint 'nope' is not in the URDF"});
    refusal(text, order({"j1", "fix"}), {"joint order: joint 'fix' is fixed"});
    refusal(text, order({"j1", "j1"}), {"joint order: joint 'j1' named twice"});
    refusal(text, order({}), {"movable joint 'j1' is missing"});
    refusal(text, order({"a", "b", "c", "d", "e", "f", "g", "h"}), {"joint order: 8 joints, at most 7"});
}

// verifies: SR-ROB-107
TEST_CASE("urdf import: broken trees are refused: two roots, a missing link, a link with two parents, a cycle") {
    const UrdfImportOptions o = order({"j1"});
    refusal(robot(link("base") + link("arm") + link("stray") + joint("j1", "base", "arm")), o, {"root"});
    refusal(robot(link("base") + link("arm") + joint("j1", "base", "ghost")), o, {"ghost"});
    refusal(robot(link("base") + link("a") + link("b") + joint("j1", "base", "a") + joint("j2", "base", "b") +
                  joint("j3", "a", "b")),
            order({"j1", "j2", "j3"}), {"link 'b' has two parent joints, 'j2' and 'j3'"});
    refusal(robot(link("a") + link("b") + joint("j1", "a", "b") + joint("j2", "b", "a")), order({"j1", "j2"}),
            {"root"});
    refusal("<robot name=\"x\"><link name=\"a\"></robot>", o, {"liburdfdom"});
}

// verifies: SR-ROB-107
TEST_CASE("urdf import: more than 16 links, 7 movable joints or 32 capsules are refused") {
    std::string body = link("l0");
    std::vector<std::string> names;
    for (int i = 1; i <= 16; ++i) {
        body += link("l" + std::to_string(i)) +
                joint("f" + std::to_string(i), "l" + std::to_string(i - 1), "l" + std::to_string(i), "fixed", "");
    }
    refusal(robot(body), order({}), {"17 links, at most 16"});
    body = link("l0");
    for (int i = 1; i <= 8; ++i) {
        body += link("l" + std::to_string(i)) +
                joint("j" + std::to_string(i), "l" + std::to_string(i - 1), "l" + std::to_string(i));
    }
    refusal(robot(body), order({}), {"8 movable joints", "at most 7"});
    std::string spheres;
    for (int i = 0; i < 33; ++i) {
        spheres += collision(R"(<sphere radius="0.01"/>)", "<origin xyz=\"" + std::to_string(0.1 * i) + " 0 0\"/>");
    }
    refusal(two_links(spheres), order({"j1"}), {"34 capsules after merging", "arm 33", "at most 32"});
}

// verifies: SR-ROB-102
TEST_CASE("urdf import: a cylinder and two spheres written with 1.57 merge into one capsule that contains them") {
    // A capsule along y written the common way: rpy 1.57 for pi/2, so the spheres miss the ends by 0.2 mm.
    const std::string parts = collision(R"(<cylinder radius="0.05" length="0.5"/>)",
                                        R"(<origin xyz="0 0 0" rpy="1.57 0 0"/>)") +
                              collision(R"(<sphere radius="0.05"/>)", R"(<origin xyz="0 0.25 0"/>)") +
                              collision(R"(<sphere radius="0.05"/>)", R"(<origin xyz="0 -0.25 0"/>)");
    UrdfImport r;
    REQUIRE(host::import_urdf_text(two_links(parts), order({"j1"}), r).ok());
    REQUIRE(r.model.capsule_count == 2U);  // the base's sphere and the arm's capsule
    const RobotCapsule& c = r.model.capsules[1];
    CHECK(c.radius > 0.05);
    CHECK(c.radius <= 0.05 + host::kUrdfMergeTolerance);
    // Every point of both spheres is inside: their far points along y and the sphere centres.
    for (const double y : {0.3, -0.3, 0.25, -0.25}) {
        CHECK(contains(c, Eigen::Vector3d(0.0, y, 0.0)));
    }
    // Without the tolerance the three parts stay three.
    UrdfImportOptions strict = order({"j1"});
    strict.merge_tolerance = 0.0;
    REQUIRE(host::import_urdf_text(two_links(parts), strict, r).ok());
    CHECK(r.model.capsule_count == 4U);
}

// verifies: SR-ROB-102
TEST_CASE("urdf import: STL meshes, binary and ASCII, package:// and relative: the capsule holds every vertex") {
    TempDir dir("urdf");
    write_binary_stl(dir.file("pkg/meshes/box.stl"), box_triangles(0.4F, 0.1F, 0.05F));
    const std::string ascii = read_text(std::string(CELLGUARD_TEST_DATA_DIR) + "/urdf/wedge.stl");
    REQUIRE(!ascii.empty());
    write_text(dir.file("meshes/wedge.stl"), ascii);
    const std::string arm = collision(R"(<mesh filename="package://cg_test/meshes/box.stl" scale="2 1 1"/>)",
                                      R"(<origin xyz="0.1 0 0" rpy="0 0 0.3"/>)") +
                            collision(R"(<mesh filename="meshes/wedge.stl"/>)");
    write_text(dir.file("robot.urdf"), two_links(arm));
    UrdfImportOptions o = order({"j1"});
    o.packages["cg_test"] = dir.file("pkg");
    o.merge_tolerance = 0.0;
    UrdfImport r;
    const IoStatus st = host::import_urdf_file(dir.file("robot.urdf"), o, r);
    REQUIRE_MESSAGE(st.ok(), st.message());
    REQUIRE(r.model.capsule_count == 3U);
    // Every vertex, scaled and placed by the collision origin, lies in its capsule.
    const Eigen::Isometry3d pose = Eigen::Translation3d(0.1, 0.0, 0.0) *
                                   Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
    for (const auto& t : box_triangles(0.4F, 0.1F, 0.05F)) {
        for (int v = 0; v < 3; ++v) {
            const Eigen::Vector3d p(2.0 * t[3 * v], t[3 * v + 1], t[3 * v + 2]);
            CHECK(contains(r.model.capsules[1], pose * p));
        }
    }
    CHECK(r.model.capsules[1].radius < 0.06);  // along the 0.8 m edge, not around it
    test::StlMesh wedge;
    REQUIRE(test::read_stl_file(std::string(CELLGUARD_TEST_DATA_DIR) + "/urdf/wedge.stl", wedge).ok());
    CHECK(wedge.ascii);
    for (const Eigen::Vector3d& p : wedge.vertices) {
        CHECK(contains(r.model.capsules[2], p));
    }
}

// verifies: SR-ROB-105
TEST_CASE("urdf import: a COLLADA mesh in millimetres and an OBJ mesh give capsules in metres that hold them") {
    TempDir dir("urdf-formats");
    // A 400 x 100 x 50 mm box as COLLADA in millimetres, and the same box in metres as OBJ.
    std::string corners;
    for (int k = 0; k < 8; ++k) {
        corners += std::to_string((k & 1) != 0 ? 400 : 0) + " " + std::to_string((k & 2) != 0 ? 100 : 0) + " " +
                   std::to_string((k & 4) != 0 ? 50 : 0) + " ";
    }
    write_text(
        dir.file("meshes/box.dae"),
        std::string(R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" )"
                    R"(version="1.4.1"><asset><unit meter="0.001"/><up_axis>Z_UP</up_axis></asset>)"
                    R"(<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="a" count="24">)") +
            corners +
            R"(</float_array><technique_common><accessor source="#a" count="8" stride="3"><param name="X" )"
            R"(type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor>)"
            R"(</technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/>)"
            R"(</vertices><triangles count="4"><input semantic="VERTEX" source="#v" offset="0"/>)"
            R"(<p>0 1 2 1 3 2 4 5 6 5 7 6</p></triangles></mesh></geometry></library_geometries>)"
            R"(<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/>)"
            R"(</node></visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene>)"
            R"(</COLLADA>)");
    write_text(dir.file("meshes/box.obj"),
               "v 0 0 0\nv 0.4 0 0\nv 0 0.1 0\nv 0.4 0.1 0\nv 0 0 0.05\nv 0.4 0 0.05\n"
               "v 0 0.1 0.05\nv 0.4 0.1 0.05\nf 1 2 3\nf 2 4 3\nf 5 6 7\nf 6 8 7\n");
    for (const char* file : {"meshes/box.dae", "meshes/box.obj"}) {
        write_text(dir.file("robot.urdf"), two_links(collision("<mesh filename=\"" + std::string(file) + "\"/>")));
        UrdfImport r;
        const IoStatus st = host::import_urdf_file(dir.file("robot.urdf"), order({"j1"}), r);
        REQUIRE_MESSAGE(st.ok(), st.message());
        const RobotCapsule& c = r.model.capsules[1];
        for (int k = 0; k < 8; ++k) {
            CHECK(contains(
                c, Eigen::Vector3d((k & 1) != 0 ? 0.4 : 0.0, (k & 2) != 0 ? 0.1 : 0.0, (k & 4) != 0 ? 0.05 : 0.0)));
        }
        CHECK(c.radius < 0.06);  // along the 0.4 m edge: metres, not millimetres
    }
}

// verifies: SR-ROB-105
TEST_CASE("urdf import: a mesh in the wrong unit is refused: millimetres read as metres, metres scaled as mm") {
    TempDir dir("urdf-units");
    write_binary_stl(dir.file("meshes/mm.stl"), box_triangles(400.0F, 100.0F, 50.0F));  // millimetres, no scale
    write_binary_stl(dir.file("meshes/m.stl"), box_triangles(0.4F, 0.1F, 0.05F));
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"(<mesh filename="meshes/mm.stl"/>)", "415.331"},
        {R"(<mesh filename="meshes/m.stl" scale="0.001 0.001 0.001"/>)", "0.000415331"}};
    for (const auto& [mesh, across] : cases) {
        write_text(dir.file("robot.urdf"), two_links(collision(mesh)));
        UrdfImport r;
        const IoStatus st = host::import_urdf_file(dir.file("robot.urdf"), order({"j1"}), r);
        CHECK_FALSE(st.ok());
        const std::string message = st.message();
        INFO("message: " << message);
        CHECK(message.find("link 'arm'") != std::string::npos);
        CHECK(message.find(across + " m across") != std::string::npos);
        CHECK(message.find("a mesh in the wrong unit?") != std::string::npos);
    }
    // The millimetre file with its scale stated is accepted.
    write_text(dir.file("robot.urdf"),
               two_links(collision(R"(<mesh filename="meshes/mm.stl" scale="0.001 0.001 0.001"/>)")));
    UrdfImport r;
    CHECK(host::import_urdf_file(dir.file("robot.urdf"), order({"j1"}), r).ok());
}

// verifies: SR-ROB-102
TEST_CASE("urdf import: unsupported and unresolvable meshes are refused naming the link and the file") {
    const UrdfImportOptions o = order({"j1"});
    auto mesh = [](const std::string& file) { return two_links(collision("<mesh filename=\"" + file + "\"/>")); };
    refusal(mesh("package://arm/meshes/forearm.dae"), o,
            {"link 'arm'", "package://arm/meshes/forearm.dae", "package 'arm' not given"});
    refusal(mesh("package://arm/meshes/forearm.stl"), o, {"link 'arm'", "package 'arm' not given"});
    refusal(mesh("file:///opt/arm/forearm.stl"), o, {"link 'arm'", "only package:// and paths relative"});
    refusal(mesh("/opt/arm/forearm.stl"), o, {"link 'arm'", "only package:// and paths relative"});
    refusal(mesh("meshes/forearm.stl"), o, {"link 'arm'", "needs the URDF's directory"});
    UrdfImportOptions with_dir = o;
    with_dir.base_directory = "/nonexistent/cellguard";
    refusal(mesh("meshes/forearm.stl"), with_dir, {"link 'arm'", "forearm.stl: cannot open"});
    refusal(mesh("meshes/forearm.obj"), with_dir, {"link 'arm'", "forearm.obj: cannot open"});
    refusal(mesh("meshes/forearm.ply"), with_dir, {"link 'arm'", "only STL, COLLADA (.dae) and OBJ meshes are read"});
}

// verifies: SR-ROB-102
TEST_CASE("urdf import: the bounding capsule of random clouds contains every point and is tight for a rod") {
    std::mt19937 rng(17U);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        std::vector<Eigen::Vector3d> points;
        const Eigen::Vector3d stretch(1.0 + 3.0 * std::abs(u(rng)), 0.2 + std::abs(u(rng)), 0.1 + std::abs(u(rng)));
        const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
        for (int i = 0; i < 200; ++i) {
            points.push_back(q * Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(stretch));
        }
        const host::Capsule c = host::bounding_capsule(points);
        for (const Eigen::Vector3d& p : points) {
            CHECK(host::segment_distance(p, c.a, c.b) <= c.radius);
        }
    }
    // Points on a rod of radius 0.05 from z = 0 to 1: a capsule of about that radius along z.
    std::vector<Eigen::Vector3d> rod;
    for (int i = 0; i <= 100; ++i) {
        for (int k = 0; k < 16; ++k) {
            const double a = 2.0 * M_PI * k / 16.0;
            rod.emplace_back(0.05 * std::cos(a), 0.05 * std::sin(a), 0.01 * i);
        }
    }
    const host::Capsule c = host::bounding_capsule(rod);
    CHECK(c.radius == doctest::Approx(0.05).epsilon(1e-6));
    CHECK(std::abs(c.b.z() - c.a.z()) == doctest::Approx(1.0).epsilon(1e-6));
}

#endif  // CELLGUARD_HOST_URDF
