// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file stl_reference.hpp
/// STL triangle meshes, binary and ASCII, read by the project's own reader:
/// the independent reference the tests compare the mesh library's reading
/// with (commissioning reads meshes through mesh.hpp since issue 39; this
/// reader was the product's until then). Tests only (heap).
///
/// Which form: a file whose size is exactly 84 + 50 n bytes, n being the
/// little-endian uint32 at byte 80, is binary (even when its 80-byte header
/// starts with "solid", as some exporters write); otherwise a file that
/// starts with "solid" (after white space) is ASCII; anything else is
/// refused (a binary file whose size disagrees with its count is named as
/// such).
///
/// ASCII grammar, keywords case-sensitive as the format defines them:
/// `solid [name]` to the end of its line, then facets
/// `facet normal ni nj nk outer loop vertex x y z (three times) endloop
/// endfacet`, then `endsolid [name]` to the end of its line; several solids
/// may follow each other. Numbers are decimal (strtod).
///
/// Refused, with a message naming the line (ASCII) or triangle (binary):
/// input over kStlMaxBytes, more than kStlMaxTriangles triangles, no
/// triangle at all, NaN or infinity in any vertex or normal, a truncated
/// file, trailing bytes after a binary file's triangles, and any ASCII
/// token out of place. Normals are checked but not used.
#ifndef CELLGUARD_TEST_STL_REFERENCE_HPP
#define CELLGUARD_TEST_STL_REFERENCE_HPP

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/host/io/io_status.hpp"

namespace cellguard::test {

/// Largest STL input, bytes (a robot link's mesh is a few MB).
constexpr std::size_t kStlMaxBytes = std::size_t{64} << 20U;
/// Most triangles of one STL file.
constexpr std::size_t kStlMaxTriangles = 1000000U;

/// A triangle mesh as read: three vertices per triangle, in file order, in
/// the file's units (URDF: metres, before the mesh's scale).
struct StlMesh {
    std::vector<Eigen::Vector3d> vertices;  ///< 3 * triangle_count vertices
    std::size_t triangle_count = 0U;        ///< triangles read
    bool ascii = false;                     ///< the input was ASCII STL
};

/// Parses the STL file held in @p data (@p size bytes) into @p mesh
/// (replaced). Errors: kCapacityExceeded (too large, too many triangles),
/// kTruncatedInput, kMalformedInput (wrong size, bad ASCII, no triangle),
/// kNonFiniteValue (NaN or infinity).
IoStatus parse_stl(const std::uint8_t* data, std::size_t size, StlMesh& mesh);

/// Reads and parses the STL file at @p path. Errors: parse_stl's, and
/// kInvalidArgument when the file cannot be opened or read; the message
/// starts with the path.
IoStatus read_stl_file(const std::string& path, StlMesh& mesh);

}  // namespace cellguard::test

#endif  // CELLGUARD_TEST_STL_REFERENCE_HPP
