// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file mesh.hpp
/// A robot link's collision mesh as its maker ships it (STL, COLLADA .dae,
/// Wavefront OBJ), read through a maintained library (Debian's assimp) for
/// commissioning: the URDF importer (urdf_import.hpp) bounds each mesh by a
/// capsule computed from its vertices. Host side only (heap, fork).
///
/// Isolation: the mesh library runs in a child process (fork) with limits
/// on its memory (kMeshChildMemoryBytes) and CPU time
/// (kMeshChildCpuSeconds), and the parent waits at most kMeshTimeoutMs. The
/// child sends its vertices through a pipe; the parent checks what arrives
/// (counts, sizes, finite numbers). A crash, a hang, a limit hit or a
/// malformed answer is a refusal that says so: never a robot image.
///
/// Units: COLLADA files state theirs (<unit meter="...">); the mesh library
/// applies it, with the file's up axis, in the root node's transform. As
/// ROS's tools do, the up-axis rotation is dropped and the unit kept: the
/// root's transform must be a rotation times a uniform scale, and the
/// vertices are scaled by that scale. Every other node's transform applies.
/// STL and OBJ carry no unit: metres, as URDF reads them.
///
/// Refused, with the file's path: a missing or unreadable file, a file over
/// kMeshMaxBytes, a suffix other than .stl, .dae or .obj (any case), what
/// the library cannot read (its message), no vertex at all, more than
/// kMeshMaxVertices, NaN or infinity in a vertex, all vertices in one point
/// or on one line (degenerate), a root transform that is not a rotation
/// and a uniform scale.
#ifndef CELLGUARD_HOST_IO_MESH_HPP
#define CELLGUARD_HOST_IO_MESH_HPP

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "cellguard/host/io/io_status.hpp"

namespace cellguard::host {

/// Largest mesh file, bytes (a robot link's mesh is a few MB).
constexpr std::size_t kMeshMaxBytes = std::size_t{64} << 20U;
/// Most vertices of one mesh file (all its meshes and nodes together).
constexpr std::size_t kMeshMaxVertices = 3000000U;
/// The reading child's address-space limit, bytes.
constexpr std::size_t kMeshChildMemoryBytes = std::size_t{2} << 30U;
/// The reading child's CPU-time limit, seconds.
constexpr unsigned kMeshChildCpuSeconds = 20U;
/// How long the parent waits for the child's answer, milliseconds.
constexpr int kMeshTimeoutMs = 30000;

/// A mesh as read: every vertex of every mesh in the file, placed by its
/// node (the file's unit applied), in metres before the URDF's scale.
struct Mesh {
    std::vector<Eigen::Vector3d> vertices;  ///< vertices, node transforms and unit applied
    std::size_t faces = 0U;                 ///< faces of all meshes (informative)
    double unit = 1.0;                      ///< metres per file unit (COLLADA's <unit>; 1 otherwise)
    std::string format;                     ///< "stl", "dae" or "obj" (the suffix)
};

/// The child's work: read @p path and write the answer to @p fd (the
/// format is mesh.cpp's); returns the child's exit status.
using MeshChild = int (*)(const char* path, int fd);

/// Limits of the reading child, and what it runs.
struct MeshLimits {
    /// The child's RLIMIT_AS; 0: none (a sanitizer build, whose shadow
    /// memory is mapped before the fork and far beyond any useful limit).
    std::size_t memory_bytes = kMeshChildMemoryBytes;
    unsigned cpu_seconds = kMeshChildCpuSeconds;  ///< the child's RLIMIT_CPU
    int timeout_ms = kMeshTimeoutMs;              ///< the parent's wait for the whole answer
    /// nullptr: the mesh library. A test seam: a child that crashes, hangs
    /// or answers wrongly shows what the parent makes of it.
    MeshChild child = nullptr;
};

/// Reads the mesh at @p path in a child process (see the file comment).
/// Errors name @p path: kInvalidArgument (missing, unreadable, degenerate),
/// kUnsupportedType (suffix), kCapacityExceeded (size, vertices),
/// kNonFiniteValue, kMalformedInput (the library's refusal, a crash, a
/// hang, a limit hit, a malformed answer).
IoStatus read_mesh_file(const std::string& path, Mesh& mesh, const MeshLimits& limits = MeshLimits{});

/// Writes the answer of a child that read @p vertices (x, y, z each; @p
/// faces, @p unit as Mesh has them) to @p fd; false when the pipe fails.
/// What the mesh library's child sends; a test child may send it too.
bool write_mesh_answer(int fd, const std::vector<double>& vertices, std::size_t faces, double unit);

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_MESH_HPP
