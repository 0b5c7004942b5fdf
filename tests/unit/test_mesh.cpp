// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies mesh.hpp: STL, COLLADA and OBJ read through the mesh library in a child process, the same vertices as the
// project's own STL reader on every public robot mesh, COLLADA's unit applied and its up axis dropped as ROS does,
// and every refusal: bad files, and a child that crashes, hangs, exceeds its memory or answers wrongly.
// Requirements: SR-ROB-105
#include <doctest/doctest.h>

#if defined(CELLGUARD_HOST_URDF) && CELLGUARD_HOST_URDF  // the mesh library comes with the URDF import

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "cellguard/host/io/mesh.hpp"
#include "stl_reference.hpp"
#include "temp_dir.hpp"

using namespace cellguard;
using cellguard::host::Mesh;
using cellguard::host::MeshLimits;
using cellguard::test::TempDir;

namespace {

void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

/// A tetrahedron in COLLADA 1.4.1, in @p unit metres per unit, with @p up_axis, its node translated by (10, 0, 0).
std::string collada(double unit, const char* up_axis) {
    return std::string(R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="u" meter=")") +
           std::to_string(unit) + R"("/><up_axis>)" + up_axis + R"(</up_axis></asset>
  <library_geometries>
    <geometry id="tet" name="tet"><mesh>
      <source id="tet-pos">
        <float_array id="tet-pos-array" count="12">0 0 0 100 0 0 0 100 0 0 0 100</float_array>
        <technique_common><accessor source="#tet-pos-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="tet-vtx"><input semantic="POSITION" source="#tet-pos"/></vertices>
      <triangles count="4"><input semantic="VERTEX" source="#tet-vtx" offset="0"/>
        <p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="n" name="n"><translate>10 0 0</translate>
      <instance_geometry url="#tet"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

/// The largest coordinate of each axis over @p mesh's vertices.
Eigen::Vector3d top(const Mesh& mesh) {
    Eigen::Vector3d m = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
    for (const Eigen::Vector3d& v : mesh.vertices) {
        m = m.cwiseMax(v);
    }
    return m;
}

int crashing_child(const char* /*path*/, int /*fd*/) {
    std::raise(SIGSEGV);
    return 0;
}

int hanging_child(const char* /*path*/, int /*fd*/) {
    std::this_thread::sleep_for(std::chrono::seconds(30));
    return 0;
}

int greedy_child(const char* /*path*/, int /*fd*/) {
    std::vector<char> hog(std::size_t{1} << 30U, 'x');  // a gigabyte, over the 256 MiB limit the test sets
    return hog[12345] == 'x' ? 0 : 1;
}

int silent_child(const char* /*path*/, int /*fd*/) { return 0; }

int failing_child(const char* /*path*/, int /*fd*/) { return 7; }

int garbage_child(const char* /*path*/, int fd) {
    const std::string junk(1000U, 'j');
    return ::write(fd, junk.data(), junk.size()) == static_cast<ssize_t>(junk.size()) ? 0 : 1;
}

int nan_child(const char* /*path*/, int fd) {
    return host::write_mesh_answer(fd, {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, NAN}, 1U, 1.0) ? 0 : 1;
}

int line_child(const char* /*path*/, int fd) {
    return host::write_mesh_answer(fd, {0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0}, 2U, 1.0) ? 0 : 1;
}

int empty_child(const char* /*path*/, int fd) { return host::write_mesh_answer(fd, {}, 0U, 1.0) ? 0 : 1; }

/// Reads @p path with @p child in place of the mesh library, expecting a refusal holding @p needle.
void refused_with(const std::string& path, MeshLimits limits, host::MeshChild child, const std::string& needle) {
    limits.child = child;
    Mesh mesh;
    const IoStatus st = host::read_mesh_file(path, mesh, limits);
    CHECK_FALSE(st.ok());
    INFO("message: " << st.message());
    CHECK(std::string(st.message()).find(needle) != std::string::npos);
    CHECK(std::string(st.message()).find(path) != std::string::npos);
    CHECK(mesh.vertices.empty());
}

}  // namespace

// verifies: SR-ROB-105
TEST_CASE("mesh: every public robot's STL mesh gives the mesh library the same vertices as the project's reader") {
    std::size_t files = 0U;
    const std::string root = std::string(CELLGUARD_SOURCE_DIR) + "/tests/data/robots";
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".stl" && ext != ".STL") {
            continue;
        }
        Mesh mesh;
        const IoStatus st = host::read_mesh_file(entry.path().string(), mesh);
        REQUIRE_MESSAGE(st.ok(), st.message());
        test::StlMesh reference;
        REQUIRE(test::read_stl_file(entry.path().string(), reference).ok());
        CHECK(mesh.format == "stl");
        CHECK(mesh.unit == 1.0);
        CHECK(mesh.faces == reference.triangle_count);
        REQUIRE(mesh.vertices.size() == reference.vertices.size());
        bool same = true;
        for (std::size_t v = 0U; v < mesh.vertices.size(); ++v) {
            same = same && mesh.vertices[v] == reference.vertices[v];
        }
        CHECK_MESSAGE(same, entry.path().string());
        ++files;
    }
    CHECK(files == 36U);  // UR5e 7, Panda 10, Gen3 8, two Jaco2 parts, FANUC M-900iA 9
}

// verifies: SR-ROB-105
TEST_CASE("mesh: the maker's COLLADA files give the vertices of its own STL exports of the same parts") {
    const std::string dir = std::string(CELLGUARD_SOURCE_DIR) + "/tests/data/robots/kinova_jaco2_parts/meshes/";
    auto sorted = [](std::vector<Eigen::Vector3d> v) {
        std::sort(v.begin(), v.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
            return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
        });
        return v;
    };
    for (const char* part : {"finger_distal", "ring_small"}) {
        Mesh dae;
        const IoStatus st = host::read_mesh_file(dir + part + ".dae", dae);
        REQUIRE_MESSAGE(st.ok(), st.message());
        test::StlMesh stl;
        REQUIRE(test::read_stl_file(dir + part + ".STL", stl).ok());
        CHECK(dae.unit == 1.0);
        CHECK(dae.faces == stl.triangle_count);
        REQUIRE(dae.vertices.size() == stl.vertices.size());
        const std::vector<Eigen::Vector3d> a = sorted(dae.vertices);
        const std::vector<Eigen::Vector3d> b = sorted(stl.vertices);
        double worst = 0.0;
        for (std::size_t k = 0U; k < a.size(); ++k) {
            worst = std::max(worst, (a[k] - b[k]).norm());
        }
        INFO(std::string(part) << ": largest difference " << worst << " m");
        CHECK(worst < 1e-6);
    }
}

// verifies: SR-ROB-105
TEST_CASE("mesh: COLLADA's unit applies, its up axis is dropped as ROS's tools do, node transforms apply") {
    const TempDir dir("mesh-dae");
    for (const char* up : {"Z_UP", "Y_UP", "X_UP"}) {
        const std::string path = dir.path() + "/tet-" + up + ".dae";
        write_text(path, collada(0.001, up));
        Mesh mesh;
        const IoStatus st = host::read_mesh_file(path, mesh);
        REQUIRE_MESSAGE(st.ok(), st.message());
        CHECK(mesh.format == "dae");
        CHECK(mesh.unit == doctest::Approx(0.001));
        // 100 mm edges from (10 mm, 0, 0): the same numbers whatever the file's up axis.
        const Eigen::Vector3d m = top(mesh);
        CHECK(m.x() == doctest::Approx(0.110));
        CHECK(m.y() == doctest::Approx(0.100));
        CHECK(m.z() == doctest::Approx(0.100));
    }
    const std::string metres = dir.path() + "/tet-m.DAE";
    write_text(metres, collada(1.0, "Z_UP"));
    Mesh mesh;
    REQUIRE(host::read_mesh_file(metres, mesh).ok());
    CHECK(top(mesh).x() == doctest::Approx(110.0));
}

// verifies: SR-ROB-105
TEST_CASE("mesh: an OBJ file's vertices, faces of any size") {
    const TempDir dir("mesh-obj");
    const std::string path = dir.path() + "/quad.obj";
    write_text(path,
               "# a pyramid\nv 0 0 0\nv 0.2 0 0\nv 0.2 0.1 0\nv 0 0.1 0\nv 0.1 0.05 0.3\n"
               "f 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n");
    Mesh mesh;
    const IoStatus st = host::read_mesh_file(path, mesh);
    REQUIRE_MESSAGE(st.ok(), st.message());
    CHECK(mesh.format == "obj");
    CHECK(mesh.faces == 5U);
    const Eigen::Vector3d m = top(mesh);
    CHECK(m.x() == doctest::Approx(0.2));
    CHECK(m.y() == doctest::Approx(0.1));
    CHECK(m.z() == doctest::Approx(0.3));
}

// verifies: SR-ROB-105
TEST_CASE("mesh: missing, oversized, unknown, unreadable, empty and degenerate files are refused naming the file") {
    const TempDir dir("mesh-bad");
    Mesh mesh;
    const std::string missing = dir.path() + "/none.stl";
    CHECK(std::string(host::read_mesh_file(missing, mesh).message()).find("none.stl: cannot open") !=
          std::string::npos);
    const std::string ply = dir.path() + "/part.ply";
    write_text(ply, "ply\n");
    CHECK(host::read_mesh_file(ply, mesh).error() == ErrorCode::kUnsupportedType);
    const std::string big = dir.path() + "/big.stl";
    write_text(big, "solid x\n");
    std::filesystem::resize_file(big, host::kMeshMaxBytes + 1U);  // sparse: refused before it is read
    CHECK(host::read_mesh_file(big, mesh).error() == ErrorCode::kCapacityExceeded);
    const std::string junk = dir.path() + "/junk.stl";
    write_text(junk, std::string(300U, '\x7f'));
    const IoStatus junk_st = host::read_mesh_file(junk, mesh);
    CHECK(junk_st.error() == ErrorCode::kMalformedInput);
    const std::string empty = dir.path() + "/empty.obj";
    write_text(empty, "# nothing\n");
    CHECK_FALSE(host::read_mesh_file(empty, mesh).ok());
    const std::string flat = dir.path() + "/line.obj";
    write_text(flat, "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n");
    const IoStatus line_st = host::read_mesh_file(flat, mesh);
    CHECK_FALSE(line_st.ok());
    CHECK(mesh.vertices.empty());
    const std::string broken = dir.path() + "/broken.dae";
    write_text(broken, collada(0.001, "Z_UP").substr(0U, 700U));
    CHECK(host::read_mesh_file(broken, mesh).error() == ErrorCode::kMalformedInput);
}

// verifies: SR-ROB-105
TEST_CASE("mesh: a child that crashes, hangs, exceeds its memory or answers wrongly is a refusal, never a mesh") {
    const TempDir dir("mesh-child");
    const std::string path = dir.path() + "/part.stl";
    write_text(path, "solid x\nendsolid x\n");
    // A generous wait for the children that end at once (a loaded CI machine forks slowly), a short one for the
    // child that never ends.
    MeshLimits limits;
    limits.timeout_ms = 20000;
    limits.memory_bytes = std::size_t{256} << 20U;
    MeshLimits impatient = limits;
    impatient.timeout_ms = 500;
    refused_with(path, limits, crashing_child, "died of signal 11");
    refused_with(path, impatient, hanging_child, "took over 500 ms");
    refused_with(path, limits, greedy_child, "the mesh library's process");
    refused_with(path, limits, silent_child, "gave no answer");
    refused_with(path, limits, failing_child, "exited with status 7");
    refused_with(path, limits, garbage_child, "malformed answer");
    refused_with(path, limits, nan_child, "vertex 2 is not finite");
    refused_with(path, limits, line_child, "degenerate: its 4 vertices lie in one point or on one line");
    refused_with(path, limits, empty_child, "no vertex: an empty mesh");
}

#endif
