// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the URDF import (urdf_import.hpp) on three arms as their makers publish them (tests/data/robots: a UR5e,
// a Franka Panda with its hand, a Kinova Gen3): each commissions, and in random poses (the Panda's fingers at random
// points of their stroke too) the controller's kinematics place every capsule where an independent forward
// kinematics (Eigen over liburdfdom's model, written here) puts its link, and every vertex of every collision mesh
// lies inside a capsule of its link (a finger's: of the hand).
// A FANUC M-900iA/260L (ROS-Industrial) adds an arm whose parallel links are mimic joints of joint 3.
// Requirements: SR-ROB-101, SR-ROB-102, SR-ROB-108, SR-ROB-109, SR-ROB-111
#include <doctest/doctest.h>

#if defined(CELLGUARD_HOST_URDF) && CELLGUARD_HOST_URDF  // a cross build has no liburdfdom (apps/host/CMakeLists.txt)

#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/host/io/urdf_import.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "stl_reference.hpp"

using namespace cellguard;
using cellguard::host::UrdfImport;
using cellguard::host::UrdfImportOptions;

namespace {

/// One public robot: its URDF, the PLC's joint order and the gripper's stroke joints.
struct PublicRobot {
    const char* urdf;
    std::vector<std::string> joints;
    std::vector<std::string> strokes;
};

PublicRobot ur5e() {
    return {
        "ur5e/ur5e.urdf",
        {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"},
        {}};
}

PublicRobot panda() {
    return {"panda/panda.urdf",
            {"panda_joint1", "panda_joint2", "panda_joint3", "panda_joint4", "panda_joint5", "panda_joint6",
             "panda_joint7"},
            {"panda_finger_joint1"}};
}

PublicRobot gen3() {
    return {"kinova_gen3/kinova_gen3.urdf",
            {"joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6", "joint_7"},
            {}};
}

PublicRobot fanuc_m900() {
    return {"fanuc_m900ia260l/fanuc_m900ia260l.urdf",
            {"joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"},
            {}};
}

std::string robots_dir() { return std::string(CELLGUARD_SOURCE_DIR) + "/tests/data/robots/"; }

UrdfImport commission(const PublicRobot& robot) {
    UrdfImportOptions o;
    o.joint_order = robot.joints;
    o.stroke_joints = robot.strokes;
    o.base_xyz = Eigen::Vector3d(0.3, -0.2, 0.1);
    o.base_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
    UrdfImport r;
    const IoStatus st = host::import_urdf_file(robots_dir() + robot.urdf, o, r);
    REQUIRE_MESSAGE(st.ok(), st.message());
    return r;
}

urdf::ModelInterfaceSharedPtr parse(const PublicRobot& robot) {
    std::ifstream in(robots_dir() + robot.urdf);
    std::stringstream text;
    text << in.rdbuf();
    urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text.str());
    REQUIRE(model);
    return model;
}

Eigen::Isometry3d isometry(const urdf::Pose& p) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translate(Eigen::Vector3d(p.position.x, p.position.y, p.position.z));
    t.rotate(Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized());
    return t;
}

/// Forward kinematics written for this test: every link's frame in the world at joint values @p q (by joint
/// name; a mimic joint follows its master; joints not given stand at 0).
void frames(const urdf::ModelInterface& model, const urdf::LinkConstSharedPtr& link, const Eigen::Isometry3d& at,
            const std::map<std::string, double>& q, std::map<std::string, Eigen::Isometry3d>& out) {
    out[link->name] = at;
    for (const urdf::JointSharedPtr& joint : link->child_joints) {
        Eigen::Isometry3d t = at * isometry(joint->parent_to_joint_origin_transform);
        double v = q.count(joint->name) != 0U ? q.at(joint->name) : 0.0;
        if (joint->mimic) {
            v = joint->mimic->multiplier * q.at(joint->mimic->joint_name) + joint->mimic->offset;
        }
        const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
        if (joint->type == urdf::Joint::REVOLUTE || joint->type == urdf::Joint::CONTINUOUS) {
            t.rotate(Eigen::AngleAxisd(v, axis.normalized()));
        } else if (joint->type == urdf::Joint::PRISMATIC) {
            t.translate(v * axis.normalized());
        }
        frames(model, model.getLink(joint->child_link_name), t, q, out);
    }
}

/// Random positions within each movable joint's limits (continuous: +-2 pi), stroke joints included.
std::map<std::string, double> random_pose(const urdf::ModelInterface& model, std::mt19937_64& rng) {
    std::map<std::string, double> q;
    for (const auto& [name, joint] : model.joints_) {
        if (joint->mimic || joint->type == urdf::Joint::FIXED) {
            continue;
        }
        const bool continuous = joint->type == urdf::Joint::CONTINUOUS;
        const double lo = continuous ? -6.28 : joint->limits->lower;
        const double hi = continuous ? 6.28 : joint->limits->upper;
        q[name] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    return q;
}

Eigen::Vector3d vec(const double (&v)[3]) { return {v[0], v[1], v[2]}; }

/// The model link that carries link @p name's capsules: its own, or for a folded finger its anchor's.
std::size_t carrier(const UrdfImport& r, const std::string& name) {
    for (std::size_t i = 0U; i < r.link_names.size(); ++i) {
        if (r.link_names[i] == name) {
            return i;
        }
    }
    for (const host::FoldedCapsule& f : r.folded) {
        if (f.link == name) {
            return carrier(r, f.anchor);
        }
    }
    FAIL("link " << name << " is neither in the model nor folded");
    return 0U;
}

/// The vertices of link @p link's collision meshes in the link frame (origin and scale applied).
std::vector<Eigen::Vector3d> mesh_vertices(const std::string& dir, const urdf::Link& link) {
    std::vector<Eigen::Vector3d> out;
    for (const urdf::CollisionSharedPtr& c : link.collision_array) {
        REQUIRE(c->geometry->type == urdf::Geometry::MESH);
        const auto& mesh = dynamic_cast<const urdf::Mesh&>(*c->geometry);
        test::StlMesh stl;
        REQUIRE(test::read_stl_file(dir + mesh.filename, stl).ok());
        const Eigen::Isometry3d origin = isometry(c->origin);
        const Eigen::Vector3d scale(mesh.scale.x, mesh.scale.y, mesh.scale.z);
        for (const Eigen::Vector3d& v : stl.vertices) {
            out.push_back(origin * v.cwiseProduct(scale));
        }
    }
    return out;
}

/// Checks @p robot in @p poses random poses; returns the vertices checked.
std::size_t check_poses(const PublicRobot& robot, int poses, std::uint64_t seed) {
    const UrdfImport r = commission(robot);
    const urdf::ModelInterfaceSharedPtr model = parse(robot);
    const std::string dir = robots_dir() + std::string(robot.urdf).substr(0U, std::string(robot.urdf).find('/') + 1U);
    std::map<std::string, std::vector<Eigen::Vector3d>> vertices;
    for (const auto& [name, link] : model->links_) {
        vertices[name] = mesh_vertices(dir, *link);
    }
    const Eigen::Isometry3d base = Eigen::Translation3d(vec(r.model.base_xyz)) *
                                   Eigen::Quaterniond(r.model.base_wxyz[0], r.model.base_wxyz[1], r.model.base_wxyz[2],
                                                      r.model.base_wxyz[3]);
    std::mt19937_64 rng(seed);
    std::size_t checked = 0U;
    for (int p = 0; p < poses; ++p) {
        const std::map<std::string, double> q = random_pose(*model, rng);
        JointPositions jp;
        jp.count = r.model.joint_count;
        for (std::size_t k = 0U; k < robot.joints.size(); ++k) {
            jp.q[k] = q.at(robot.joints[k]);
        }
        RobotPose placed;
        place_robot(r.model, jp, placed);
        std::map<std::string, Eigen::Isometry3d> world;
        frames(*model, model->getRoot(), base, q, world);
        // The controller's capsules sit where the independent kinematics put their links.
        double worst_place = 0.0;
        for (std::size_t k = 0U; k < r.model.capsule_count; ++k) {
            const RobotCapsule& c = r.model.capsules[k];
            const Eigen::Isometry3d& t = world.at(r.link_names[c.link]);
            worst_place = std::max({worst_place, (t * vec(c.a) - vec(placed.capsules[k].a)).norm(),
                                    (t * vec(c.b) - vec(placed.capsules[k].b)).norm()});
        }
        CHECK(worst_place < 1e-12);
        // Every mesh vertex inside a capsule of the link that carries it.
        bool all_inside = true;
        for (const auto& [name, points] : vertices) {
            const std::size_t link = points.empty() ? 0U : carrier(r, name);
            for (const Eigen::Vector3d& v : points) {
                const Eigen::Vector3d w = world.at(name) * v;
                double excess = 1e300;
                for (std::size_t k = 0U; k < placed.count; ++k) {
                    const PlacedCapsule& c = placed.capsules[k];
                    if (c.link == link) {
                        excess = std::min(excess, host::segment_distance(w, vec(c.a), vec(c.b)) - c.radius);
                    }
                }
                all_inside = all_inside && excess <= 1e-9;
                ++checked;
            }
        }
        CHECK_MESSAGE(all_inside, robot.urdf << " pose " << p);
    }
    return checked;
}

}  // namespace

// verifies: SR-ROB-109
TEST_CASE("public robots: a UR5e, a Panda with its gripper and a Kinova Gen3 commission within the capacities") {
    const UrdfImport ur = commission(ur5e());
    CHECK(ur.model.link_count == 9U);
    CHECK(ur.model.joint_count == 6U);
    CHECK(ur.model.capsule_count == 7U);
    const UrdfImport pa = commission(panda());
    CHECK(pa.model.link_count == 10U);  // 12 in the URDF: the two fingers folded into the hand
    CHECK(pa.model.joint_count == 7U);  // the fingers' joints do not go over CAN
    CHECK(pa.model.capsule_count == 11U);
    REQUIRE(pa.folded.size() == 2U);
    CHECK(pa.folded[0].anchor == "panda_hand");
    // The fingers' 40 mm stroke costs about 21 mm of radius on each finger's capsule.
    CHECK(pa.folded[0].envelope.radius - pa.folded[0].original.radius == doctest::Approx(0.0212).epsilon(0.05));
    const UrdfImport g3 = commission(gen3());
    CHECK(g3.model.link_count == 8U);
    CHECK(g3.model.joint_count == 7U);
    CHECK(g3.model.capsule_count == 8U);
    // Each survives the robot image.
    for (const UrdfImport* r : {&ur, &pa, &g3}) {
        std::vector<std::uint8_t> bytes(kRobotImageMaxBytes);
        const auto written = write_robot_image(r->model, Span<std::uint8_t>(bytes.data(), bytes.size()));
        REQUIRE(written.ok());
        CHECK(load_robot_image(Span<const std::uint8_t>(bytes.data(), written.value())).ok());
    }
    // Without naming the fingers, the Panda has 8 joints to send: refused with what to do.
    PublicRobot bare = panda();
    bare.strokes.clear();
    UrdfImportOptions o;
    o.joint_order = bare.joints;
    UrdfImport r;
    const IoStatus st = host::import_urdf_file(robots_dir() + bare.urdf, o, r);
    CHECK_FALSE(st.ok());
    CHECK(std::string(st.message()).find("8 movable joints to send, at most 7 (name a gripper's fingers stroke") !=
          std::string::npos);
    CHECK(std::string(st.message()).find("panda_finger_joint1") != std::string::npos);
}

// verifies: SR-ROB-109
TEST_CASE("public robots: in 25 random poses each, the capsules sit on the links and hold every mesh vertex") {
    CHECK(check_poses(ur5e(), 25, 1U) > 10000U);
    CHECK(check_poses(panda(), 25, 2U) > 10000U);
    CHECK(check_poses(gen3(), 25, 3U) > 10000U);
}

// verifies: SR-ROB-111
TEST_CASE("public robots: a FANUC M-900iA/260L's parallel links follow joint 3 as mimics and hold every vertex") {
    const UrdfImport r = commission(fanuc_m900());
    CHECK(r.model.link_count == 9U);
    CHECK(r.model.joint_count == 6U);
    CHECK(r.model.capsule_count == 9U);
    int mimics = 0;
    for (std::size_t i = 0U; i < r.model.link_count; ++i) {
        const RobotLink& l = r.model.links[i];
        if (l.mimic) {
            ++mimics;
            CHECK(l.command_index == 2U);  // joint_3
            CHECK(std::abs(l.mimic_multiplier) == 1.0);
            CHECK(l.max_velocity == r.model.links[3].max_velocity);  // no limit in the file: its master's
        }
    }
    CHECK(mimics == 2);
    CHECK(robot_image_version(r.model) == kRobotImageMimicFormatVersion);
    std::vector<std::uint8_t> bytes(kRobotImageMaxBytes);
    const auto written = write_robot_image(r.model, Span<std::uint8_t>(bytes.data(), bytes.size()));
    REQUIRE(written.ok());
    CHECK(written.value() == robot_image_size(9U, 9U, kRobotImageMimicFormatVersion));
    CHECK(load_robot_image(Span<const std::uint8_t>(bytes.data(), written.value())).ok());
    // The independent kinematics moves plink_1 and plink_2 by joint_3 x -1 and x 1 as the URDF's <mimic> says.
    CHECK(check_poses(fanuc_m900(), 25, 4U) > 5000U);
}

#endif
