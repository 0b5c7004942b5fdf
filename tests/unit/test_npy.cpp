// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies npy.hpp: .npy export and import of grids, byte-exact with numpy.save, and the rejection of malformed files.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/io/npy.hpp"
#include "temp_dir.hpp"

using namespace cellguard;

using cellguard::test::TempDir;

namespace {

std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::uint8_t> to_bytes(const std::string& s) { return {s.begin(), s.end()}; }

/// A .npy file with the given version, header dict (padded with spaces and
/// '\n' like numpy) and data bytes.
std::vector<std::uint8_t> make_npy(const std::string& dict, std::size_t data_bytes, int major = 1) {
    const std::size_t preamble = major == 1 ? 10U : 12U;
    std::string header = dict;
    while ((preamble + header.size() + 1U) % 64U != 0U) {
        header += ' ';
    }
    header += '\n';
    std::vector<std::uint8_t> out = {0x93, 'N', 'U', 'M', 'P', 'Y', static_cast<std::uint8_t>(major), 0};
    const std::size_t len = header.size();
    out.push_back(static_cast<std::uint8_t>(len & 0xFFU));
    out.push_back(static_cast<std::uint8_t>((len >> 8U) & 0xFFU));
    if (major != 1) {
        out.push_back(0);
        out.push_back(0);
    }
    out.insert(out.end(), header.begin(), header.end());
    for (std::size_t i = 0; i < data_bytes; ++i) {
        out.push_back(static_cast<std::uint8_t>(i * 7U));
    }
    return out;
}

const std::string kGoodDict = "{'descr': '<i2', 'fortran_order': False, 'shape': (2, 3, 4), }";
constexpr GridDims kDims{4, 3, 2};  // nx, ny, nz: shape (2, 3, 4)

IoStatus decode_i16(const std::vector<std::uint8_t>& file, GridDims dims = kDims) {
    std::int16_t out[64] = {};
    return decode_npy_int16(file.data(), file.size(), dims, Span<std::int16_t>(out));
}

bool contains(const IoStatus& st, const char* text) { return std::strstr(st.message(), text) != nullptr; }

}  // namespace

// verifies: SR-IO-001
TEST_CASE("npy: the header is byte for byte the one numpy.save writes") {
    // Taken from numpy 1.24 (np.save of np.zeros(shape, dtype)): 128 bytes,
    // the dict, spare spaces and padding, then '\n'.
    struct Case {
        NpyDtype dtype;
        GridDims dims;
        const char* dict;
    };
    const Case cases[] = {
        {NpyDtype::kInt16, GridDims{4, 3, 2}, "{'descr': '<i2', 'fortran_order': False, 'shape': (2, 3, 4), }"},
        {NpyDtype::kUInt8, GridDims{1, 1, 1}, "{'descr': '|u1', 'fortran_order': False, 'shape': (1, 1, 1), }"},
        {NpyDtype::kFloat32, GridDims{34, 30, 30}, "{'descr': '<f4', 'fortran_order': False, 'shape': (30, 30, 34), }"},
        {NpyDtype::kInt16, GridDims{256, 256, 128},
         "{'descr': '<i2', 'fortran_order': False, 'shape': (128, 256, 256), }"},
    };
    for (const Case& c : cases) {
        std::string expected("\x93NUMPY\x01\x00\x76\x00", 10);
        expected += c.dict;
        expected += std::string(127U - expected.size(), ' ');
        expected += '\n';
        REQUIRE(expected.size() == 128U);
        std::uint8_t buf[256];
        std::size_t length = 0;
        REQUIRE(format_npy_header(c.dtype, c.dims, Span<std::uint8_t>(buf), length).ok());
        CHECK(length == 128U);
        CHECK(std::string(reinterpret_cast<const char*>(buf), length) == expected);
    }
    std::uint8_t small[100];
    std::size_t length = 0;
    CHECK(format_npy_header(NpyDtype::kInt16, kDims, Span<std::uint8_t>(small), length).error() ==
          ErrorCode::kStorageTooSmall);
    CHECK(format_npy_header(NpyDtype::kInt16, GridDims{0, 1, 1}, Span<std::uint8_t>(small), length).error() ==
          ErrorCode::kInvalidArgument);
}

// verifies: SR-IO-001
TEST_CASE("npy: a written file is the header followed by the little-endian data in C order") {
    TempDir dir("npy");
    std::int16_t data[24];
    for (int i = 0; i < 24; ++i) {
        data[i] = static_cast<std::int16_t>(i * 1000 - 12000);
    }
    const std::string path = dir.file("a.npy");
    REQUIRE(write_npy_int16(path.c_str(), Span<const std::int16_t>(data), kDims).ok());
    const std::vector<std::uint8_t> file = read_bytes(path);
    REQUIRE(file.size() == 128U + 48U);
    CHECK(std::memcmp(file.data() + 10, kGoodDict.data(), kGoodDict.size()) == 0);
    CHECK(file[127] == '\n');
    for (std::size_t i = 0; i < 24U; ++i) {
        const auto v = static_cast<std::uint16_t>(data[i]);
        CHECK(file[128U + 2U * i] == (v & 0xFFU));
        CHECK(file[129U + 2U * i] == (v >> 8U));
    }
}

// verifies: SR-IO-001
TEST_CASE("npy: int16, float32 and uint8 arrays round-trip through files unchanged") {
    TempDir dir("npy");
    const GridDims dims{5, 4, 3};
    constexpr std::size_t n = 60;
    std::int16_t i16[n];
    float f32[n];
    std::uint8_t u8[n];
    for (std::size_t i = 0; i < n; ++i) {
        i16[i] = static_cast<std::int16_t>(static_cast<int>(i * 1097U % 65536U) - 32768);
        f32[i] = static_cast<float>(i) * 0.37F - 9.0F;
        u8[i] = static_cast<std::uint8_t>(i * 13U);
    }
    i16[0] = kNeverForeground;
    i16[1] = kLogOddsMax;
    f32[2] = std::numeric_limits<float>::quiet_NaN();
    f32[3] = -std::numeric_limits<float>::infinity();
    REQUIRE(write_npy_int16(dir.file("i.npy").c_str(), Span<const std::int16_t>(i16), dims).ok());
    REQUIRE(write_npy_float32(dir.file("f.npy").c_str(), Span<const float>(f32), dims).ok());
    REQUIRE(write_npy_uint8(dir.file("u.npy").c_str(), Span<const std::uint8_t>(u8), dims).ok());
    std::int16_t i16_in[n] = {};
    float f32_in[n] = {};
    std::uint8_t u8_in[n] = {};
    const IoStatus a = read_npy_int16(dir.file("i.npy").c_str(), dims, Span<std::int16_t>(i16_in));
    const IoStatus b = read_npy_float32(dir.file("f.npy").c_str(), dims, Span<float>(f32_in));
    const IoStatus c = read_npy_uint8(dir.file("u.npy").c_str(), dims, Span<std::uint8_t>(u8_in));
    REQUIRE_MESSAGE(a.ok(), std::string(a.message()));
    REQUIRE_MESSAGE(b.ok(), std::string(b.message()));
    REQUIRE_MESSAGE(c.ok(), std::string(c.message()));
    CHECK(std::memcmp(i16, i16_in, sizeof i16) == 0);
    CHECK(std::memcmp(f32, f32_in, sizeof f32) == 0);  // bitwise, NaN included
    CHECK(std::memcmp(u8, u8_in, sizeof u8) == 0);
    // The same bytes decode from memory.
    const std::vector<std::uint8_t> file = read_bytes(dir.file("f.npy"));
    float f32_mem[n] = {};
    REQUIRE(decode_npy_float32(file.data(), file.size(), dims, Span<float>(f32_mem)).ok());
    CHECK(std::memcmp(f32, f32_mem, sizeof f32) == 0);
}

// verifies: SR-IO-001
TEST_CASE("npy: writing refuses a data length that does not match the dimensions") {
    TempDir dir("npy");
    std::int16_t data[10] = {};
    CHECK(write_npy_int16(dir.file("x.npy").c_str(), Span<const std::int16_t>(data), kDims).error() ==
          ErrorCode::kInvalidArgument);
    CHECK(write_npy_int16(dir.file("x.npy").c_str(), Span<const std::int16_t>(data), GridDims{10, 1, 0}).error() ==
          ErrorCode::kInvalidArgument);
    const IoStatus st = write_npy_int16("/nonexistent-dir/x.npy", Span<const std::int16_t>(data), GridDims{10, 1, 1});
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    CHECK(contains(st, "/nonexistent-dir/x.npy"));
}

// verifies: SR-IO-001
TEST_CASE("npy: a grid exports as three files whose a[z, y, x] is voxel (x, y, z), and reads back") {
    TempDir dir("npy");
    const GridGeometry geometry = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{4, 3, 2}).value();
    static StaticEvidenceGridStorage<4, 3, 2> storage;
    EvidenceGrid grid = EvidenceGrid::make(geometry, storage.log_odds, storage.observed).value();
    for (std::int32_t z = 0; z < 2; ++z) {
        for (std::int32_t y = 0; y < 3; ++y) {
            for (std::int32_t x = 0; x < 4; ++x) {
                const std::size_t i = geometry.index_of(VoxelCoord{x, y, z});
                grid.log_odds()[i] = static_cast<std::int16_t>(100 * x + 10 * y + z - 200);
                grid.observed()[i] = static_cast<std::uint8_t>((x + y + z) % 2);
            }
        }
    }
    const std::string prefix = dir.file("bg");
    const IoStatus w = write_grid_npy(prefix.c_str(), grid);
    REQUIRE_MESSAGE(w.ok(), std::string(w.message()));

    // Index the raw files the way numpy does: C order over shape (nz, ny, nx).
    const std::vector<std::uint8_t> lo = read_bytes(prefix + "_log_odds.npy");
    const std::vector<std::uint8_t> pr = read_bytes(prefix + "_probability.npy");
    const std::vector<std::uint8_t> ob = read_bytes(prefix + "_observed.npy");
    REQUIRE(lo.size() == 128U + 48U);
    REQUIRE(pr.size() == 128U + 96U);
    REQUIRE(ob.size() == 128U + 24U);
    CHECK(std::memcmp(pr.data() + 10, "{'descr': '<f4'", 15) == 0);
    CHECK(std::memcmp(ob.data() + 10, "{'descr': '|u1'", 15) == 0);
    const std::size_t z = 1;
    const std::size_t y = 2;
    const std::size_t x = 3;
    const std::size_t c_index = (z * 3U + y) * 4U + x;
    std::int16_t v = 0;
    std::memcpy(&v, lo.data() + 128U + 2U * c_index, 2U);
    CHECK(v == 100 * 3 + 10 * 2 + 1 - 200);
    float p = 0.0F;
    std::memcpy(&p, pr.data() + 128U + 4U * c_index, 4U);
    CHECK(p == static_cast<float>(probability_from_log_odds(v)));
    CHECK(ob[128U + c_index] == (3 + 2 + 1) % 2);

    static StaticEvidenceGridStorage<4, 3, 2> back_storage;
    EvidenceGrid back = EvidenceGrid::make(geometry, back_storage.log_odds, back_storage.observed).value();
    const IoStatus r = read_grid_npy(prefix.c_str(), back);
    REQUIRE_MESSAGE(r.ok(), std::string(r.message()));
    CHECK(std::memcmp(storage.log_odds, back_storage.log_odds, sizeof storage.log_odds) == 0);
    CHECK(std::memcmp(storage.observed, back_storage.observed, sizeof storage.observed) == 0);

    // A grid of another shape refuses these files.
    const GridGeometry other = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{3, 4, 2}).value();
    EvidenceGrid wrong = EvidenceGrid::make(other, back_storage.log_odds, back_storage.observed).value();
    const IoStatus m = read_grid_npy(prefix.c_str(), wrong);
    CHECK(m.error() == ErrorCode::kGeometryMismatch);
    CHECK(contains(m, "(2, 3, 4)"));
    CHECK(contains(m, "(2, 4, 3)"));
}

// verifies: SR-IO-001
TEST_CASE("npy: a background grid with a bad value is refused and left cleared") {
    TempDir dir("npy");
    const GridDims dims{4, 3, 2};
    const GridGeometry geometry = GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, dims).value();
    std::int16_t lo[24] = {};
    std::uint8_t ob[24] = {};
    ob[5] = 2;
    REQUIRE(write_npy_int16(dir.file("lo.npy").c_str(), Span<const std::int16_t>(lo), dims).ok());
    REQUIRE(write_npy_uint8(dir.file("ob.npy").c_str(), Span<const std::uint8_t>(ob), dims).ok());
    static StaticEvidenceGridStorage<4, 3, 2> storage;
    EvidenceGrid grid = EvidenceGrid::make(geometry, storage.log_odds, storage.observed).value();
    IoStatus st = read_background_npy(dir.file("lo.npy").c_str(), dir.file("ob.npy").c_str(), grid);
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(contains(st, "observed flag 2"));
    CHECK(contains(st, "(1, 1, 0)"));
    CHECK(grid.observed_count() == 0U);

    ob[5] = 1;
    lo[7] = kNeverForeground;
    REQUIRE(write_npy_int16(dir.file("lo.npy").c_str(), Span<const std::int16_t>(lo), dims).ok());
    REQUIRE(write_npy_uint8(dir.file("ob.npy").c_str(), Span<const std::uint8_t>(ob), dims).ok());
    st = read_background_npy(dir.file("lo.npy").c_str(), dir.file("ob.npy").c_str(), grid);
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(contains(st, "sentinel"));
    CHECK(grid.observed_count() == 0U);
    CHECK(grid.log_odds()[7] == 0);

    lo[7] = kLogOddsMin;
    REQUIRE(write_npy_int16(dir.file("lo.npy").c_str(), Span<const std::int16_t>(lo), dims).ok());
    st = read_background_npy(dir.file("lo.npy").c_str(), dir.file("ob.npy").c_str(), grid);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    CHECK(grid.observed_count() == 1U);
    CHECK(grid.log_odds()[7] == kLogOddsMin);

    // A missing file: the OS error names the path.
    st = read_background_npy(dir.file("none.npy").c_str(), dir.file("ob.npy").c_str(), grid);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    CHECK(contains(st, "none.npy"));
    CHECK(grid.observed_count() == 0U);
}

// verifies: SR-IO-001
TEST_CASE("npy: a well-formed header in another spelling is read, version 2.0 too") {
    CHECK(decode_i16(make_npy(kGoodDict, 48)).ok());
    CHECK(decode_i16(make_npy("{\"shape\": (2,3,4,), \"descr\": \"<i2\", \"fortran_order\": False}", 48)).ok());
    CHECK(decode_i16(make_npy(kGoodDict, 48, 2)).ok());
    NpyHeader h;
    const std::vector<std::uint8_t> scalar = make_npy("{'descr': '|u1', 'fortran_order': False, 'shape': (), }", 1);
    REQUIRE(parse_npy_header(scalar.data(), scalar.size(), h).ok());
    CHECK(h.ndim == 0U);
    CHECK(h.element_count == 1U);
    const std::vector<std::uint8_t> v1d = make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (5,), }", 20);
    REQUIRE(parse_npy_header(v1d.data(), v1d.size(), h).ok());
    CHECK(h.ndim == 1U);
    CHECK(h.shape[0] == 5U);
    CHECK(h.data_bytes == 20U);
    CHECK(h.dtype == NpyDtype::kFloat32);
    CHECK(h.data_offset == 128U);
}

// verifies: SR-IO-001
TEST_CASE("npy: each malformed file is refused with its own error") {
    struct Case {
        const char* what;
        std::vector<std::uint8_t> file;
        ErrorCode code;
        const char* message;
    };
    std::vector<std::uint8_t> bad_magic = make_npy(kGoodDict, 48);
    bad_magic[1] = 'X';
    std::vector<std::uint8_t> v3 = make_npy(kGoodDict, 48);
    v3[6] = 3;
    std::vector<std::uint8_t> v11 = make_npy(kGoodDict, 48);
    v11[7] = 1;
    std::vector<std::uint8_t> long_header = make_npy(kGoodDict, 0);
    long_header[8] = 0xF0;
    std::vector<std::uint8_t> no_newline = make_npy(kGoodDict, 48);
    no_newline[127] = ' ';
    std::vector<std::uint8_t> truncated = make_npy(kGoodDict, 48);
    truncated.pop_back();
    std::vector<std::uint8_t> trailing = make_npy(kGoodDict, 49);
    const Case cases[] = {
        {"bad magic", bad_magic, ErrorCode::kBadMagic, "NUMPY"},
        {"empty input", {}, ErrorCode::kBadMagic, "NUMPY"},
        {"version 3.0", v3, ErrorCode::kUnsupportedVersion, "3.0"},
        {"version 1.1", v11, ErrorCode::kUnsupportedVersion, "1.1"},
        {"preamble cut", to_bytes(std::string("\x93NUMPY\x01\x00\x76", 9)), ErrorCode::kTruncatedInput,
         "header length"},
        {"header length past the end", long_header, ErrorCode::kTruncatedInput, "runs past the end"},
        {"header not ending in newline", no_newline, ErrorCode::kMalformedInput, "'\\n'"},
        {"missing key", make_npy("{'descr': '<i2', 'shape': (2, 3, 4), }", 48), ErrorCode::kMalformedInput,
         "no key 'fortran_order'"},
        {"unknown key", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (2, 3, 4), 'x': 1}", 48),
         ErrorCode::kMalformedInput, "unknown key 'x'"},
        {"duplicate key", make_npy("{'descr': '<i2', 'descr': '<i2', 'fortran_order': False, 'shape': (2, 3, 4)}", 48),
         ErrorCode::kMalformedInput, "twice"},
        {"fortran order", make_npy("{'descr': '<i2', 'fortran_order': True, 'shape': (2, 3, 4), }", 48),
         ErrorCode::kMalformedInput, "fortran_order is True"},
        {"wrong dtype", make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3, 4), }", 96),
         ErrorCode::kUnsupportedType, "expected '<i2'"},
        {"unsupported dtype", make_npy("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3, 4), }", 192),
         ErrorCode::kUnsupportedType, "'<f8' is not supported"},
        {"big-endian dtype", make_npy("{'descr': '>i2', 'fortran_order': False, 'shape': (2, 3, 4), }", 48),
         ErrorCode::kUnsupportedType, "big-endian"},
        {"structured dtype", make_npy("{'descr': [('a', '<i2')], 'fortran_order': False, 'shape': (2, 3, 4), }", 48),
         ErrorCode::kUnsupportedType, "descr"},
        {"wrong shape", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (2, 4, 3), }", 48),
         ErrorCode::kGeometryMismatch, "(2, 4, 3)"},
        {"two dimensions", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (6, 4), }", 48),
         ErrorCode::kGeometryMismatch, "(6, 4)"},
        {"shape not a tuple", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (24), }", 48),
         ErrorCode::kMalformedInput, "not a tuple"},
        {"negative dimension", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (-2, 3, 4), }", 48),
         ErrorCode::kMalformedInput, "non-negative integer"},
        {"huge shape", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (4294967296, 4294967296, 4), }", 48),
         ErrorCode::kCapacityExceeded, "overflows"},
        {"truncated data", truncated, ErrorCode::kTruncatedInput, "the shape needs 48"},
        {"trailing bytes", trailing, ErrorCode::kMalformedInput, "1 bytes after the data"},
        {"junk after dict", make_npy(kGoodDict + " x", 48), ErrorCode::kMalformedInput, "after the header dict"},
        {"unclosed dict", make_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (2, 3, 4), ", 48),
         ErrorCode::kMalformedInput, "header offset"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        const IoStatus st = decode_i16(c.file);
        CHECK(st.error() == c.code);
        CHECK_MESSAGE(contains(st, c.message), std::string(st.message()));
        CHECK(std::strncmp(st.message(), "npy: ", 5) == 0);
    }
}

// verifies: SR-IO-001
TEST_CASE("npy: a file is refused when it reaches a reader through a path, with the path in the message") {
    TempDir dir("npy");
    const std::string path = dir.file("bad.npy");
    write_bytes(path, make_npy("{'descr': '<i2', 'fortran_order': True, 'shape': (2, 3, 4), }", 48));
    std::int16_t out[24];
    IoStatus st = read_npy_int16(path.c_str(), kDims, Span<std::int16_t>(out));
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(contains(st, "bad.npy: npy: fortran_order"));
    write_bytes(path, to_bytes("\x93NUMPY"));
    st = read_npy_int16(path.c_str(), kDims, Span<std::int16_t>(out));
    CHECK(st.error() == ErrorCode::kTruncatedInput);
    std::vector<std::uint8_t> cut = make_npy(kGoodDict, 40);
    write_bytes(path, cut);
    st = read_npy_int16(path.c_str(), kDims, Span<std::int16_t>(out));
    CHECK(st.error() == ErrorCode::kTruncatedInput);
    write_bytes(path, make_npy(kGoodDict, 48));
    std::int16_t small[23];
    st = read_npy_int16(path.c_str(), kDims, Span<std::int16_t>(small));
    CHECK(st.error() == ErrorCode::kStorageTooSmall);
    st = read_npy_int16(path.c_str(), kDims, Span<std::int16_t>(out));
    CHECK_MESSAGE(st.ok(), std::string(st.message()));
}
