// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies stl_reference.hpp (the tests' own STL reader): binary and ASCII STL meshes read exactly, and malformed,
// non-finite or oversized files refused.
// Requirements: SR-ROB-105
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "stl_reference.hpp"

using namespace cellguard;
using cellguard::test::parse_stl;
using cellguard::test::StlMesh;

namespace {

void put_float(std::vector<std::uint8_t>& out, float f) {
    std::uint32_t bits = 0U;
    std::memcpy(&bits, &f, sizeof(bits));
    for (int k = 0; k < 4; ++k) {
        out.push_back(static_cast<std::uint8_t>(bits >> (8U * static_cast<unsigned>(k))));
    }
}

/// A binary STL of @p triangles (9 floats each), header @p header, zero normals.
std::vector<std::uint8_t> binary_stl(const std::vector<std::vector<float>>& triangles, const std::string& header = "") {
    std::vector<std::uint8_t> out(80U, 0U);
    std::memcpy(out.data(), header.data(), std::min<std::size_t>(header.size(), 80U));
    const auto n = static_cast<std::uint32_t>(triangles.size());
    for (int k = 0; k < 4; ++k) {
        out.push_back(static_cast<std::uint8_t>(n >> (8U * static_cast<unsigned>(k))));
    }
    for (const std::vector<float>& t : triangles) {
        for (int k = 0; k < 3; ++k) {
            put_float(out, 0.0F);
        }
        for (const float v : t) {
            put_float(out, v);
        }
        out.push_back(0U);
        out.push_back(0U);
    }
    return out;
}

std::vector<std::uint8_t> bytes(const std::string& s) { return {s.begin(), s.end()}; }

IoStatus parse(const std::vector<std::uint8_t>& data, StlMesh& mesh) {
    return parse_stl(data.data(), data.size(), mesh);
}

const char* kAsciiTetra =
    "solid tetra\n"
    "  facet normal 0 0 -1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 1 0\n"
    "    endloop\n  endfacet\n"
    "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 0 1.5e0\n"
    "    endloop\n  endfacet\n"
    "endsolid tetra\n";

}  // namespace

// verifies: SR-ROB-105
TEST_CASE("stl: a binary file is read vertex for vertex") {
    StlMesh mesh;
    const auto data = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0.5F, -2, 3, 4, 5, 6, 7, 8, 9}});
    REQUIRE(parse(data, mesh).ok());
    CHECK_FALSE(mesh.ascii);
    CHECK(mesh.triangle_count == 2U);
    REQUIRE(mesh.vertices.size() == 6U);
    CHECK(mesh.vertices[1].x() == 1.0);
    CHECK(mesh.vertices[3].x() == 0.5);
    CHECK(mesh.vertices[3].y() == -2.0);
    CHECK(mesh.vertices[5].z() == 9.0);
}

// verifies: SR-ROB-105
TEST_CASE("stl: a binary file whose header starts with 'solid' is binary by its size") {
    StlMesh mesh;
    const auto data = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}}, "solid exported by a CAD tool");
    REQUIRE(parse(data, mesh).ok());
    CHECK_FALSE(mesh.ascii);
    CHECK(mesh.triangle_count == 1U);
}

// verifies: SR-ROB-105
TEST_CASE("stl: an ASCII file is read, several solids too") {
    StlMesh mesh;
    REQUIRE(parse(bytes(kAsciiTetra), mesh).ok());
    CHECK(mesh.ascii);
    CHECK(mesh.triangle_count == 2U);
    REQUIRE(mesh.vertices.size() == 6U);
    CHECK(mesh.vertices[5].z() == 1.5);
    REQUIRE(parse(bytes(std::string(kAsciiTetra) + "\r\n" + kAsciiTetra), mesh).ok());
    CHECK(mesh.triangle_count == 4U);
}

// verifies: SR-ROB-105
TEST_CASE("stl: NaN and infinity are refused, binary and ASCII") {
    StlMesh mesh;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    IoStatus st = parse(binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, nan, 0, 0, 1, 0}}), mesh);
    CHECK(st.error() == ErrorCode::kNonFiniteValue);
    CHECK(std::string(st.message()).find("triangle 1") != std::string::npos);
    std::string text = kAsciiTetra;
    text.replace(text.find("1.5e0"), 5U, "nan");
    st = parse(bytes(text), mesh);
    CHECK(st.error() == ErrorCode::kNonFiniteValue);
    CHECK(std::string(st.message()).find("line 13") != std::string::npos);
    text = kAsciiTetra;
    text.replace(text.find("1.5e0"), 5U, "1e999");
    CHECK(parse(bytes(text), mesh).error() == ErrorCode::kNonFiniteValue);
}

// verifies: SR-ROB-105
TEST_CASE("stl: truncated, padded, empty and malformed files are refused") {
    StlMesh mesh;
    auto data = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, 0, 1, 0}});
    data.pop_back();
    CHECK(parse(data, mesh).error() == ErrorCode::kTruncatedInput);
    data.push_back(0U);
    data.push_back(0U);
    CHECK(parse(data, mesh).error() == ErrorCode::kMalformedInput);  // a trailing byte
    CHECK(parse(binary_stl({}), mesh).error() == ErrorCode::kMalformedInput);
    CHECK(parse(bytes("solid empty\nendsolid empty\n"), mesh).error() == ErrorCode::kMalformedInput);
    CHECK(parse(bytes("tiny"), mesh).error() == ErrorCode::kTruncatedInput);
    std::string text = kAsciiTetra;
    text.replace(text.find("outer loop"), 10U, "outer lop");
    const IoStatus st = parse(bytes(text), mesh);
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(std::string(st.message()).find("line 3: expected 'loop', got 'lop'") != std::string::npos);
    text = kAsciiTetra;
    text.resize(text.find("endsolid"));
    CHECK(parse(bytes(text), mesh).error() == ErrorCode::kTruncatedInput);
    text = kAsciiTetra;
    text.replace(text.find("vertex 0 1 0"), 12U, "vertex 0 1");
    CHECK(parse(bytes(text), mesh).error() == ErrorCode::kMalformedInput);
}

// verifies: SR-ROB-105
TEST_CASE("stl: input over the size limit is refused before it is read") {
    StlMesh mesh;
    std::vector<std::uint8_t> big(test::kStlMaxBytes + 1U, 0U);
    CHECK(parse(big, mesh).error() == ErrorCode::kCapacityExceeded);
}

// verifies: SR-ROB-105
TEST_CASE("stl: a missing file is an error that names it") {
    StlMesh mesh;
    const IoStatus st = test::read_stl_file("/nonexistent/cellguard/mesh.stl", mesh);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    CHECK(std::string(st.message()).find("/nonexistent/cellguard/mesh.stl: cannot open") == 0U);
}
