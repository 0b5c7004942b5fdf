// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: prior image files on Linux, and the generated C++ source that puts a prior in flash.
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/io/prior_files.hpp"
#include "cellguard/prior/prior_image.hpp"

// The generated example is compiled into this test binary: the build itself
// proves that generated source compiles (with the grid macros it checks).
#define CELLGUARD_GRID_NX 4
#define CELLGUARD_GRID_NY 3
#define CELLGUARD_GRID_NZ 2
#include "data/prior_example.hpp"

using namespace cellguard;

namespace {

// The inputs tests/unit/data/prior_example.hpp was generated from.
GridGeometry example_geometry() {
    return GridGeometry::make(Eigen::Vector3d(-0.1, 0.25, 0.0), 0.05, GridDims{4, 3, 2}).value();
}
AccessibilityParams example_params() {
    AccessibilityParams p;
    p.method = PriorMethod::kProbabilistic;
    p.t_b = 0.51;
    p.t_e = 0.1;
    p.radius_voxels = 2;
    p.open_faces = kPaperOpenFaces;
    return p;
}
std::vector<std::int16_t> example_prior() {
    std::vector<std::int16_t> v(24);
    for (std::size_t i = 0; i < v.size(); ++i) {
        v[i] = i % 4U == 0U ? kNeverForeground : static_cast<std::int16_t>(-131 * static_cast<int>(i));
    }
    return v;
}
constexpr const char* kExampleNamespace = "cellguard_test::prior_example";

std::string example_path() { return std::string(CELLGUARD_SOURCE_DIR) + "/tests/unit/data/prior_example.hpp"; }

std::string temp_path(const char* name) {
    return "/tmp/cellguard_test_prior_files_" + std::to_string(::getpid()) + "_" + name;
}

std::vector<std::uint8_t> read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

struct Encoded {
    std::vector<std::uint8_t> bytes;
    PriorImageView view;
};

Encoded encoded_example() {
    Encoded e;
    const std::vector<std::int16_t> prior = example_prior();
    REQUIRE(encode_prior_image(example_geometry(), example_params(),
                               Span<const std::int16_t>(prior.data(), prior.size()), e.bytes)
                .ok());
    e.view = load_prior_image(Span<const std::uint8_t>(e.bytes.data(), e.bytes.size()), example_geometry()).value();
    return e;
}

}  // namespace

// verifies: SR-PRIOR-014
TEST_CASE("prior files: an image written to a file reads back byte for byte and loads") {
    const Encoded e = encoded_example();
    const std::string path = temp_path("roundtrip.cgpi");
    REQUIRE(write_prior_image_file(path.c_str(), e.view).ok());
    CHECK(read_all(path) == e.bytes);
    struct stat st {};
    CHECK(::stat((path + ".tmp").c_str(), &st) != 0);  // the temporary file is gone

    std::vector<std::uint8_t> bytes;
    PriorImageView view;
    PriorImageError why = PriorImageError::kTooShort;
    const IoStatus s = read_prior_image_file(path.c_str(), example_geometry(), bytes, view, &why);
    CHECK(s.ok());
    CHECK(why == PriorImageError::kNone);
    CHECK(bytes == e.bytes);
    CHECK(view.image().data() == bytes.data());
    const std::vector<std::int16_t> prior = example_prior();
    for (std::size_t i = 0; i < prior.size(); ++i)
        CHECK(view[i] == prior[i]);
    std::remove(path.c_str());
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: a corrupted or foreign file is refused with the loader's reason in the message") {
    Encoded e = encoded_example();
    const std::string path = temp_path("corrupt.cgpi");
    e.bytes[100] ^= 0x01U;  // payload
    {
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(e.bytes.data()), static_cast<std::streamsize>(e.bytes.size()));
    }
    std::vector<std::uint8_t> bytes;
    PriorImageView view;
    PriorImageError why = PriorImageError::kNone;
    IoStatus s = read_prior_image_file(path.c_str(), example_geometry(), bytes, view, &why);
    CHECK(s.error() == ErrorCode::kCrcMismatch);
    CHECK(why == PriorImageError::kPayloadCrcMismatch);
    CHECK(view.empty());
    CHECK(std::string(s.message()).find("payload CRC mismatch") != std::string::npos);
    CHECK(std::string(s.message()).find(path) != std::string::npos);

    e.bytes[100] ^= 0x01U;
    {
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(e.bytes.data()), static_cast<std::streamsize>(e.bytes.size()));
    }
    const GridGeometry other = GridGeometry::make(Eigen::Vector3d(-0.1, 0.25, 0.0), 0.05, GridDims{4, 3, 3}).value();
    s = read_prior_image_file(path.c_str(), other, bytes, view, &why);
    CHECK(s.error() == ErrorCode::kGeometryMismatch);
    CHECK(why == PriorImageError::kDimsMismatch);
    std::remove(path.c_str());
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: a missing file, a directory and an oversized file are refused before loading") {
    std::vector<std::uint8_t> bytes;
    PriorImageView view;
    PriorImageError why = PriorImageError::kTooShort;
    IoStatus s = read_prior_image_file("/nonexistent/cellguard/prior.cgpi", example_geometry(), bytes, view, &why);
    CHECK(s.error() == ErrorCode::kInvalidArgument);
    CHECK(why == PriorImageError::kNone);
    CHECK(std::string(s.message()).find("No such file") != std::string::npos);
    s = read_prior_image_file("/tmp", example_geometry(), bytes, view);
    CHECK(s.error() == ErrorCode::kInvalidArgument);
    CHECK(std::string(s.message()).find("not a regular file") != std::string::npos);

    const std::string path = temp_path("huge.cgpi");
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        REQUIRE(f != nullptr);
        std::fclose(f);
    }
    REQUIRE(::truncate(path.c_str(), static_cast<off_t>(kMaxPriorImageFileSize + 1U)) == 0);  // sparse
    s = read_prior_image_file(path.c_str(), example_geometry(), bytes, view);
    CHECK(s.error() == ErrorCode::kCapacityExceeded);
    REQUIRE(::truncate(path.c_str(), 10) == 0);
    s = read_prior_image_file(path.c_str(), example_geometry(), bytes, view, &why);
    CHECK(s.error() == ErrorCode::kBadMagic);
    CHECK(why == PriorImageError::kBadMagic);
    std::remove(path.c_str());
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: writing refuses an empty view and reports an unwritable path") {
    CHECK(write_prior_image_file(temp_path("x").c_str(), PriorImageView{}).error() == ErrorCode::kInvalidArgument);
    const Encoded e = encoded_example();
    const IoStatus s = write_prior_image_file("/nonexistent/cellguard/prior.cgpi", e.view);
    CHECK(s.error() == ErrorCode::kInvalidArgument);
    CHECK(std::string(s.message()).find("cannot create") != std::string::npos);
    std::vector<std::uint8_t> bytes;
    const std::vector<std::int16_t> too_few(23, 0);
    CHECK(encode_prior_image(example_geometry(), example_params(), Span<const std::int16_t>(too_few.data(), 23), bytes)
              .error() == ErrorCode::kGeometryMismatch);
    CHECK(bytes.empty());
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: the committed generated example is what the generator writes for its inputs") {
    const Encoded e = encoded_example();
    PriorSourceOptions options;
    options.name_space = kExampleNamespace;
    std::string text;
    REQUIRE(prior_source_text(e.view, options, text).ok());
    if (std::getenv("CELLGUARD_REGENERATE_PRIOR_EXAMPLE") != nullptr) {
        REQUIRE(write_prior_source_file(example_path().c_str(), e.view, options).ok());
    }
    // On a difference: rerun this test with CELLGUARD_REGENERATE_PRIOR_EXAMPLE=1, then rebuild.
    CHECK(read_text(example_path()) == text);
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: the compiled generated array equals the writer's image and passes the loader") {
    namespace ex = cellguard_test::prior_example;
    const Encoded e = encoded_example();
    REQUIRE(sizeof ex::kImage == e.bytes.size());
    CHECK(std::memcmp(ex::kImage, e.bytes.data(), e.bytes.size()) == 0);
    const Result<PriorImageView, PriorImageError> v = load_prior_image(Span<const std::uint8_t>(ex::kImage),
                                                                       example_geometry());
    REQUIRE(v.ok());
    const std::vector<std::int16_t> prior = example_prior();
    for (std::size_t i = 0; i < prior.size(); ++i)
        CHECK(v.value()[i] == prior[i]);
    CHECK(ex::kPayloadCrc == e.view.header().payload_crc);
    CHECK(ex::kHeaderCrc == e.view.header().header_crc);
    CHECK(ex::kPayloadCrc == crc32(e.view.payload()));
    CHECK(ex::kVoxelCount == 24U);
    CHECK(ex::kNx == 4);
    CHECK(ex::kNy == 3);
    CHECK(ex::kNz == 2);
    CHECK(ex::kMethod == static_cast<std::uint8_t>(PriorMethod::kProbabilistic));
    CHECK(ex::kRadiusVoxels == 2);
    CHECK(ex::kOpenFaces == kPaperOpenFaces);
    CHECK(ex::kVoxelSizeBits == e.view.header().voxel_size_bits);
    CHECK(ex::kOriginBits[1] == e.view.header().origin_bits[1]);
    CHECK(ex::kTbBits == e.view.header().t_b_bits);
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: generated source names its namespace, optional config header and grid checks") {
    const Encoded e = encoded_example();
    PriorSourceOptions options;
    options.name_space = "fw::prior";
    options.config_header = "fw/grid_config.hpp";
    std::string text;
    REQUIRE(prior_source_text(e.view, options, text).ok());
    CHECK(text.find("namespace fw::prior {") != std::string::npos);
    CHECK(text.find("#include \"fw/grid_config.hpp\"") < text.find("#if !defined(CELLGUARD_GRID_NX)"));
    CHECK(text.find("#ifndef CELLGUARD_GENERATED_PRIOR_FW__PRIOR_HPP") != std::string::npos);
    CHECK(text.find("static_assert(kNx == static_cast<std::int32_t>(CELLGUARD_GRID_NX)") != std::string::npos);

    const std::string path = temp_path("prior_source.hpp");
    REQUIRE(write_prior_source_file(path.c_str(), e.view, options).ok());
    CHECK(read_text(path) == text);
    std::remove(path.c_str());
}

// verifies: SR-PRIOR-014
TEST_CASE("prior files: generated source refuses a bad namespace, a bad include name and an empty view") {
    const Encoded e = encoded_example();
    std::string text = "untouched";
    for (const char* ns : {"", "1abc", "a:b", "a::", "::a", "a b", "a-b", "a:::b"}) {
        PriorSourceOptions o;
        o.name_space = ns;
        CHECK(prior_source_text(e.view, o, text).error() == ErrorCode::kInvalidArgument);
    }
    for (const char* inc : {"", "a\"b.hpp", "a\nb", "<x>", "a\\b"}) {
        PriorSourceOptions o;
        o.config_header = inc;
        CHECK(prior_source_text(e.view, o, text).error() == ErrorCode::kInvalidArgument);
    }
    CHECK(prior_source_text(PriorImageView{}, PriorSourceOptions{}, text).error() == ErrorCode::kInvalidArgument);
    CHECK(text == "untouched");
    PriorSourceOptions o;
    o.name_space = "a_1::_b2::C";
    CHECK(prior_source_text(e.view, o, text).ok());
}
