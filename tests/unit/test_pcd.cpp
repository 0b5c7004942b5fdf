// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies pcd.hpp: PCD reading (ascii, binary, binary_compressed) on real Kinect frames and synthetic clouds,
// the LZF decompressor's bounds checks, the writer, and the rejection of malformed files.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cellguard/host/io/pcd.hpp"
#include "temp_dir.hpp"

using namespace cellguard;

using cellguard::test::TempDir;

namespace {

const char* const kFrames[] = {
    CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142255.814212.pcd",
    CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142256.068683.pcd",
    CELLGUARD_TEST_DATA_DIR "/kinect-frames/frame_20121214T142256.332395.pcd",
};
constexpr std::size_t kFramePoints = 640U * 480U;

IoStatus decode(const std::string& file, PcdCloudInfo& info, std::vector<PcdPoint>& points,
                PcdReadOptions options = PcdReadOptions{}) {
    points.assign(64, PcdPoint{});
    const IoStatus st = decode_pcd(reinterpret_cast<const std::uint8_t*>(file.data()), file.size(),
                                   Span<PcdPoint>(points.data(), points.size()), info, options);
    points.resize(static_cast<std::size_t>(info.written));
    return st;
}

bool contains(const IoStatus& st, const char* text) { return std::strstr(st.message(), text) != nullptr; }

bool same_bits(const PcdPoint& a, const PcdPoint& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void append_f32(std::string& s, float v) {
    char b[4];
    std::memcpy(b, &v, 4);
    s.append(b, 4);
}
void append_u32(std::string& s, std::uint32_t v) {
    for (unsigned k = 0; k < 4U; ++k) {
        s.push_back(static_cast<char>((v >> (8U * k)) & 0xFFU));
    }
}
template <typename T>
void append_raw(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
}

/// LZF literal run (1..32 bytes).
std::string lzf_literal(const std::string& bytes) {
    REQUIRE((!bytes.empty() && bytes.size() <= 32U));
    return std::string(1, static_cast<char>(bytes.size() - 1U)) + bytes;
}
/// LZF back-reference copying @p len (3..264) bytes from @p distance (1..8192) back.
std::string lzf_backref(std::size_t len, std::size_t distance) {
    std::string out;
    const std::size_t l = len - 2U;
    const std::size_t d = distance - 1U;
    if (l < 7U) {
        out.push_back(static_cast<char>((l << 5U) | (d >> 8U)));
    } else {
        out.push_back(static_cast<char>((7U << 5U) | (d >> 8U)));
        out.push_back(static_cast<char>(l - 7U));
    }
    out.push_back(static_cast<char>(d & 0xFFU));
    return out;
}

const std::string kXyzHeader =
    "# .PCD v0.7 - Point Cloud Data file format\n"
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
    "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n";

}  // namespace

// verifies: SR-IO-002
TEST_CASE("pcd: the three real Kinect frames read as 640 x 480 organised clouds with NaN for invalid pixels") {
    std::vector<PcdPoint> points(kFramePoints);
    std::vector<PcdPoint> all(kFramePoints);
    for (const char* path : kFrames) {
        CAPTURE(path);
        PcdCloudInfo info;
        const IoStatus st = read_pcd(path, Span<PcdPoint>(points.data(), points.size()), info);
        REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
        CHECK(info.data == PcdDataKind::kBinaryCompressed);
        CHECK(info.width == 640U);
        CHECK(info.height == 480U);
        CHECK(info.points == kFramePoints);
        CHECK(info.finite_points + info.nonfinite_points == kFramePoints);
        CHECK(info.written == info.finite_points);
        // About 12 % of a Kinect frame has no depth (measured 11.6-11.7 % on these three).
        CHECK(info.nonfinite_points > kFramePoints / 20U);
        CHECK(info.nonfinite_points < kFramePoints / 4U);
        CHECK(info.viewpoint.qw == 0.0);
        CHECK(info.viewpoint.qx == 1.0);
        std::size_t out_of_range = 0;
        for (std::size_t i = 0; i < info.written; ++i) {
            const PcdPoint& p = points[i];
            // An office seen by a Kinect: depth 0.5-5 m in front of the camera, within a few metres across.
            if (!(p.z > 0.5F && p.z < 5.0F && std::fabs(p.x) < 3.0F && std::fabs(p.y) < 3.0F)) {
                ++out_of_range;
            }
        }
        CHECK(out_of_range == 0U);

        // Kept in file order, the NaN pixels are exactly the ones skipped.
        PcdCloudInfo all_info;
        PcdReadOptions keep;
        keep.keep_nonfinite = true;
        REQUIRE(read_pcd(path, Span<PcdPoint>(all.data(), all.size()), all_info, keep).ok());
        REQUIRE(all_info.written == kFramePoints);
        std::size_t nan_points = 0;
        std::size_t j = 0;
        bool same_order = true;
        for (const PcdPoint& p : all) {
            if (std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z)) {
                ++nan_points;
            } else {
                same_order = same_order && same_bits(p, points[j++]);
            }
        }
        CHECK(nan_points == info.nonfinite_points);
        CHECK(j == info.written);
        CHECK(same_order);
    }
}

// verifies: SR-IO-002
TEST_CASE("pcd: a real frame written as ascii, binary and binary_compressed reads back to the same points") {
    TempDir dir("pcd");
    std::vector<PcdPoint> all(kFramePoints);
    std::vector<PcdPoint> finite(kFramePoints);
    PcdCloudInfo all_info;
    PcdCloudInfo info;
    PcdReadOptions keep;
    keep.keep_nonfinite = true;
    REQUIRE(read_pcd(kFrames[1], Span<PcdPoint>(all.data(), all.size()), all_info, keep).ok());
    REQUIRE(read_pcd(kFrames[1], Span<PcdPoint>(finite.data(), finite.size()), info).ok());
    struct Kind {
        PcdDataKind kind;
        const char* name;
    };
    const Kind kinds[] = {{PcdDataKind::kAscii, "ascii.pcd"},
                          {PcdDataKind::kBinary, "binary.pcd"},
                          {PcdDataKind::kBinaryCompressed, "compressed.pcd"}};
    std::vector<PcdPoint> back(kFramePoints);
    for (const Kind& k : kinds) {
        CAPTURE(k.name);
        const std::string path = dir.file(k.name);
        const IoStatus w = write_pcd(path.c_str(), Span<const PcdPoint>(all.data(), all.size()), 640U, 480U,
                                     all_info.viewpoint, k.kind);
        REQUIRE_MESSAGE(w.ok(), std::string(w.message()));
        PcdCloudInfo back_info;
        const IoStatus r = read_pcd(path.c_str(), Span<PcdPoint>(back.data(), back.size()), back_info);
        REQUIRE_MESSAGE(r.ok(), std::string(r.message()));
        CHECK(back_info.data == k.kind);
        CHECK(back_info.width == 640U);
        CHECK(back_info.height == 480U);
        CHECK(back_info.finite_points == info.finite_points);
        CHECK(back_info.nonfinite_points == info.nonfinite_points);
        CHECK(back_info.viewpoint.qx == 1.0);
        REQUIRE(back_info.written == info.written);
        CHECK(std::memcmp(back.data(), finite.data(), static_cast<std::size_t>(info.written) * sizeof(PcdPoint)) == 0);
    }
}

// verifies: SR-IO-002
TEST_CASE("pcd: ascii fields of every type and count are checked and x, y, z are taken from their places") {
    const std::string file =
        "VERSION 0.7\nFIELDS a x rgb y z n\nSIZE 1 4 4 8 2 4\nTYPE I F U F I F\nCOUNT 1 1 1 1 1 3\n"
        "WIDTH 4\nHEIGHT 1\nPOINTS 4\nDATA ascii\n"
        "-5 1.5 4294967295 2.25 -7 0 0 0\n"
        "\n"
        "3 nan 0 inf 2 1 1 1\r\n"
        "+4  -0.5\t10 1e2 32767 1 2 3\n"
        "-1 0 0 -nan 2 1 1 1\n";
    PcdCloudInfo info;
    std::vector<PcdPoint> points;
    const IoStatus st = decode(file, info, points);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    CHECK(info.data == PcdDataKind::kAscii);
    CHECK(info.finite_points == 2U);
    CHECK(info.nonfinite_points == 2U);
    CHECK(info.viewpoint.qw == 1.0);  // default when VIEWPOINT is left out
    REQUIRE(points.size() == 2U);
    CHECK(points[0].x == 1.5F);
    CHECK(points[0].y == 2.25F);
    CHECK(points[0].z == -7.0F);
    CHECK(points[1].x == -0.5F);
    CHECK(points[1].y == 100.0F);
    CHECK(points[1].z == 32767.0F);
}

// verifies: SR-IO-002
TEST_CASE("pcd: binary records with padding fields, doubles and integers decode, zero padding after them is allowed") {
    std::string file =
        "VERSION 0.7\nFIELDS _ x y z rgb\nSIZE 1 8 2 4 4\nTYPE U F U I F\nCOUNT 3 1 1 1 1\n"
        "WIDTH 1\nHEIGHT 2\nVIEWPOINT 1 2 3 0.5 0.5 0.5 0.5\nPOINTS 2\nDATA binary\n";
    const std::size_t header = file.size();
    for (int i = 0; i < 2; ++i) {
        file.append("\x01\x02\x03", 3);
        append_raw(file, i == 0 ? 0.125 : std::nan(""));
        append_raw(file, static_cast<std::uint16_t>(65535U - static_cast<unsigned>(i)));
        append_raw(file, static_cast<std::int32_t>(-100000 * (i + 1)));
        append_f32(file, 7.0F);
    }
    PcdCloudInfo info;
    std::vector<PcdPoint> points;
    IoStatus st = decode(file, info, points);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    CHECK(file.size() - header == 2U * 21U);
    CHECK(info.width == 1U);
    CHECK(info.height == 2U);
    CHECK(info.viewpoint.tz == 3.0);
    CHECK(info.finite_points == 1U);
    CHECK(info.nonfinite_points == 1U);
    REQUIRE(points.size() == 1U);
    CHECK(points[0].x == 0.125F);
    CHECK(points[0].y == 65535.0F);
    CHECK(points[0].z == -100000.0F);

    file.append(100, '\0');
    CHECK(decode(file, info, points).ok());
    file.back() = '\x01';
    st = decode(file, info, points);
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(contains(st, "not all zero"));
}

// verifies: SR-IO-002
TEST_CASE("pcd: binary_compressed data is decompressed and read as one array per field") {
    // x = 1 for all 4 points (literal + back-reference), y = 2 (short references), z = 10..13 (literal).
    std::string soa;
    std::string x_bytes;
    append_f32(x_bytes, 1.0F);
    std::string y_bytes;
    append_f32(y_bytes, 2.0F);
    std::string z_bytes;
    for (int i = 0; i < 4; ++i) {
        append_f32(z_bytes, 10.0F + static_cast<float>(i));
    }
    const std::string lzf = lzf_literal(x_bytes) + lzf_backref(12, 4) + lzf_literal(y_bytes) + lzf_backref(8, 4) +
                            lzf_backref(4, 4) + lzf_literal(z_bytes);
    std::string file =
        "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 2\n"
        "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA binary_compressed\n";
    append_u32(file, static_cast<std::uint32_t>(lzf.size()));
    append_u32(file, 48U);
    file += lzf;
    PcdCloudInfo info;
    std::vector<PcdPoint> points;
    const IoStatus st = decode(file, info, points);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    CHECK(info.data == PcdDataKind::kBinaryCompressed);
    REQUIRE(points.size() == 4U);
    for (std::size_t i = 0; i < 4U; ++i) {
        CHECK(points[i].x == 1.0F);
        CHECK(points[i].y == 2.0F);
        CHECK(points[i].z == 10.0F + static_cast<float>(i));
    }
}

// verifies: SR-IO-002
TEST_CASE("lzf: overlapping back-references repeat bytes, every out-of-bounds reference or run is refused") {
    std::uint8_t out[16] = {};
    const std::string run = lzf_literal("a") + lzf_backref(9, 1);
    IoStatus st = lzf_decompress(reinterpret_cast<const std::uint8_t*>(run.data()), run.size(), out, 10);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    CHECK(std::memcmp(out, "aaaaaaaaaa", 10) == 0);

    struct Case {
        const char* what;
        std::string in;
        std::size_t out_size;
        ErrorCode code;
        const char* message;
    };
    const Case cases[] = {
        {"reference with no output yet", lzf_backref(3, 1), 8, ErrorCode::kMalformedInput, "before the start"},
        {"reference before the start", lzf_literal("ab") + lzf_backref(3, 3), 8, ErrorCode::kMalformedInput,
         "reaches 1 bytes before the start"},
        {"far reference before the start", lzf_literal("ab") + lzf_backref(100, 8192), 200, ErrorCode::kMalformedInput,
         "before the start"},
        {"literal past the input",
         std::string("\x05"
                     "ab",
                     3),
         8, ErrorCode::kTruncatedInput, "past the end of the input"},
        {"length byte missing", lzf_literal("a") + std::string("\xE0", 1), 20, ErrorCode::kTruncatedInput,
         "length byte missing"},
        {"offset byte missing", lzf_literal("a") + std::string("\x20", 1), 20, ErrorCode::kTruncatedInput,
         "offset byte missing"},
        {"literal past the output", lzf_literal("abcd"), 3, ErrorCode::kMalformedInput, "overflows the output"},
        {"reference past the output", lzf_literal("a") + lzf_backref(8, 1), 5, ErrorCode::kMalformedInput,
         "overflows the output"},
        {"output too short", lzf_literal("ab"), 3, ErrorCode::kMalformedInput, "decompressed to 2 bytes, expected 3"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        std::uint8_t buf[256] = {};
        REQUIRE(c.out_size <= sizeof buf);
        st = lzf_decompress(reinterpret_cast<const std::uint8_t*>(c.in.data()), c.in.size(), buf, c.out_size);
        CHECK(st.error() == c.code);
        CHECK_MESSAGE(contains(st, c.message), std::string(st.message()));
    }
}

// verifies: SR-IO-002
TEST_CASE("pcd: old headers are read: 0.6 without WIDTH and HEIGHT, 0.5 with COLUMNS") {
    PcdCloudInfo info;
    std::vector<PcdPoint> points;
    IoStatus st = decode("VERSION .6\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n", info,
                         points);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    CHECK(info.width == 2U);
    CHECK(info.height == 1U);
    REQUIRE(points.size() == 2U);
    CHECK(points[1].z == 6.0F);
    std::string bin = "VERSION 0.5\nCOLUMNS z y x\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nPOINTS 1\nDATA binary\n";
    append_f32(bin, 1.0F);
    append_f32(bin, 2.0F);
    append_f32(bin, 3.0F);
    st = decode(bin, info, points);
    REQUIRE_MESSAGE(st.ok(), std::string(st.message()));
    REQUIRE(points.size() == 1U);
    CHECK(points[0].x == 3.0F);
    CHECK(points[0].z == 1.0F);
}

// verifies: SR-IO-002
TEST_CASE("pcd: each malformed header is refused with a message naming the line") {
    struct Case {
        const char* what;
        std::string file;
        ErrorCode code;
        const char* message;
    };
    const std::string data = "DATA ascii\n1 2 3\n4 5 6\n";
    const std::string fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
    const std::string size = "WIDTH 2\nHEIGHT 1\nPOINTS 2\n";
    std::string many_fields = "VERSION 0.7\nFIELDS x y z";
    for (int i = 0; i < 62; ++i) {
        many_fields += " f";
    }
    many_fields += "\n";
    const Case cases[] = {
        {"SIZE count", "# c\nVERSION 0.7\nFIELDS x y z rgba\nSIZE 4 4 4\n", ErrorCode::kMalformedInput,
         "line 4: FIELDS has 4 names but SIZE has 3"},
        {"TYPE count", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F\n", ErrorCode::kMalformedInput,
         "line 4: FIELDS has 3 names but TYPE has 2"},
        {"COUNT count", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1 1\n",
         ErrorCode::kMalformedInput, "line 5: FIELDS has 3 names but COUNT has 4"},
        {"order", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nCOUNT 1 1 1\n",
         ErrorCode::kMalformedInput, "line 6: COUNT after WIDTH"},
        {"repeated keyword", "VERSION 0.7\n" + fields + "WIDTH 2\nWIDTH 2\n", ErrorCode::kMalformedInput,
         "line 7: second WIDTH line"},
        {"unknown keyword", "VERSION 0.7\nFOO 1\n", ErrorCode::kMalformedInput, "line 2: unknown keyword 'FOO'"},
        {"COLUMNS in 0.7", "VERSION 0.7\nCOLUMNS x y z\n", ErrorCode::kMalformedInput, "unknown keyword 'COLUMNS'"},
        {"no VERSION", fields + size + data, ErrorCode::kMalformedInput, "line 1: FIELDS before VERSION"},
        {"SIZE without FIELDS", "VERSION 0.7\nSIZE 4\n", ErrorCode::kMalformedInput, "SIZE without a FIELDS line"},
        {"HEIGHT without WIDTH", "VERSION 0.7\n" + fields + "HEIGHT 1\n", ErrorCode::kMalformedInput,
         "HEIGHT without a WIDTH line"},
        {"WIDTH without HEIGHT", "VERSION 0.7\n" + fields + "WIDTH 2\nPOINTS 2\n" + data, ErrorCode::kMalformedInput,
         "WIDTH without HEIGHT"},
        {"0.7 without WIDTH", "VERSION 0.7\n" + fields + "POINTS 2\n" + data, ErrorCode::kMalformedInput,
         "needs WIDTH and HEIGHT"},
        {"no DATA", "VERSION 0.7\n" + fields + size, ErrorCode::kTruncatedInput, "without a DATA line"},
        {"unended line", "VERSION 0.7", ErrorCode::kTruncatedInput, "not ended by a newline"},
        {"empty input", "", ErrorCode::kTruncatedInput, "without a DATA line"},
        {"F with SIZE 2", "VERSION 0.7\nFIELDS x y z\nSIZE 4 2 4\nTYPE F F F\n", ErrorCode::kUnsupportedType,
         "field 'y' has TYPE F with SIZE 2"},
        {"U with SIZE 8", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 8\nTYPE F F U\n", ErrorCode::kUnsupportedType,
         "TYPE U with SIZE 8"},
        {"SIZE 3", "VERSION 0.7\nFIELDS x y z\nSIZE 4 3 4\n", ErrorCode::kMalformedInput, "is not 1, 2, 4 or 8"},
        {"TYPE X", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F X F\n", ErrorCode::kMalformedInput,
         "TYPE 'X' of field 'y' is not F, I or U"},
        {"COUNT 0", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 0 1\n", ErrorCode::kMalformedInput,
         "COUNT '0' of field 'y'"},
        {"POINTS mismatch", "VERSION 0.7\n" + fields + "WIDTH 2\nHEIGHT 1\nPOINTS 3\n" + data,
         ErrorCode::kMalformedInput, "POINTS 3 but WIDTH x HEIGHT = 2 x 1 = 2"},
        {"WIDTH 0", "VERSION 0.7\n" + fields + "WIDTH 0\n", ErrorCode::kMalformedInput, "WIDTH '0'"},
        {"WIDTH not a number", "VERSION 0.7\n" + fields + "WIDTH 2x\n", ErrorCode::kMalformedInput, "WIDTH '2x'"},
        {"no z", "VERSION 0.7\nFIELDS x y w\nSIZE 4 4 4\nTYPE F F F\n" + size + data, ErrorCode::kMalformedInput,
         "no field 'z'"},
        {"x twice", "VERSION 0.7\nFIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\n" + size + data,
         ErrorCode::kMalformedInput, "field 'x' appears 2 times"},
        {"x with COUNT 2", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 2 1 1\n" + size + data,
         ErrorCode::kUnsupportedType, "field 'x' has COUNT 2"},
        {"VERSION 0.8", "VERSION 0.8\n", ErrorCode::kUnsupportedVersion, "VERSION 0.8"},
        {"compressed in 0.6", "VERSION 0.6\n" + fields + size + "DATA binary_compressed\n",
         ErrorCode::kUnsupportedVersion, "needs VERSION 0.7"},
        {"VIEWPOINT count", "VERSION 0.7\n" + fields + "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0\n",
         ErrorCode::kMalformedInput, "VIEWPOINT takes 7 values, found 6"},
        {"VIEWPOINT quaternion", "VERSION 0.7\n" + fields + "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 0 0 0 0\n",
         ErrorCode::kMalformedInput, "not a unit quaternion"},
        {"VIEWPOINT NaN", "VERSION 0.7\n" + fields + "WIDTH 2\nHEIGHT 1\nVIEWPOINT nan 0 0 1 0 0 0\n",
         ErrorCode::kMalformedInput, "'nan' is not a finite number"},
        {"DATA kind", "VERSION 0.7\n" + fields + size + "DATA text\n", ErrorCode::kMalformedInput, "DATA 'text'"},
        {"DATA with two values", "VERSION 0.7\n" + fields + size + "DATA ascii binary\n", ErrorCode::kMalformedInput,
         "DATA takes 1 value, found 2"},
        {"binary in the header", std::string("VERSION 0.7\nFIELDS x\x01 y z\n"), ErrorCode::kMalformedInput,
         "line 2: byte 0x01 is not header text"},
        {"too many fields", many_fields, ErrorCode::kCapacityExceeded, "at most 64 fields"},
        {"long field name", "VERSION 0.7\nFIELDS x y z abcdefghijabcdefghijabcdefghijab\n", ErrorCode::kMalformedInput,
         "longer than 31 characters"},
        {"data too large", "VERSION 0.7\n" + fields + "WIDTH 100000\nHEIGHT 100000\nPOINTS 10000000000\n" + data,
         ErrorCode::kCapacityExceeded, "exceed the limit"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        PcdCloudInfo info;
        std::vector<PcdPoint> points;
        const IoStatus st = decode(c.file, info, points);
        CHECK(st.error() == c.code);
        CHECK_MESSAGE(contains(st, c.message), std::string(st.message()));
        CHECK(std::strncmp(st.message(), "pcd: ", 5) == 0);
    }
}

// verifies: SR-IO-002
TEST_CASE("pcd: data that does not match its header is refused") {
    struct Case {
        const char* what;
        std::string file;
        ErrorCode code;
        const char* message;
    };
    const std::string ascii = kXyzHeader + "DATA ascii\n";
    std::string bin = kXyzHeader + "DATA binary\n";
    for (int i = 0; i < 5; ++i) {
        append_f32(bin, 1.0F);
    }
    const std::string comp = kXyzHeader + "DATA binary_compressed\n";
    std::string lit;
    for (int i = 0; i < 24; ++i) {
        lit.push_back('\0');
    }
    std::string good_comp = comp;
    append_u32(good_comp, 25U);
    append_u32(good_comp, 24U);
    good_comp += lzf_literal(lit);
    std::string wrong_size = comp;
    append_u32(wrong_size, 25U);
    append_u32(wrong_size, 20U);
    wrong_size += lzf_literal(lit);
    std::string past_end = comp;
    append_u32(past_end, 26U);
    append_u32(past_end, 24U);
    past_end += lzf_literal(lit);
    std::string zero_size = comp;
    append_u32(zero_size, 0U);
    append_u32(zero_size, 24U);
    std::string bad_lzf = comp;
    append_u32(bad_lzf, 3U);
    append_u32(bad_lzf, 24U);
    bad_lzf += lzf_literal("a") + std::string("\x20", 1);
    std::string slack = good_comp + std::string("\x00\x00\x07", 3);
    const Case cases[] = {
        {"ascii too few values", ascii + "1 2\n4 5 6\n", ErrorCode::kMalformedInput,
         "line 12: point 0 has 2 values, the fields need 3"},
        {"ascii too many values", ascii + "1 2 3\n4 5 6 7 8\n", ErrorCode::kMalformedInput,
         "line 13: point 1 has 5 values"},
        {"ascii not a number", ascii + "1 2 abc\n4 5 6\n", ErrorCode::kMalformedInput, "value 'abc' of field 'z'"},
        {"ascii float out of range", ascii + "1 2 1e39\n4 5 6\n", ErrorCode::kMalformedInput, "out of range for F 4"},
        {"ascii fewer lines", ascii + "1 2 3\n", ErrorCode::kTruncatedInput, "ascii data has 1 points, POINTS is 2"},
        {"ascii more lines", ascii + "1 2 3\n4 5 6\n7 8 9\n", ErrorCode::kMalformedInput,
         "line 14: more data lines than POINTS 2"},
        {"ascii U1 out of range",
         "VERSION 0.7\nFIELDS x y z c\nSIZE 4 4 4 1\nTYPE F F F U\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 "
         "256\n",
         ErrorCode::kMalformedInput, "value '256' of field 'c' is not a valid U 1"},
        {"ascii I1 out of range",
         "VERSION 0.7\nFIELDS x y z c\nSIZE 4 4 4 1\nTYPE F F F I\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 "
         "-129\n",
         ErrorCode::kMalformedInput, "value '-129' of field 'c' is not a valid I 1"},
        {"ascii U negative",
         "VERSION 0.7\nFIELDS x y z c\nSIZE 4 4 4 4\nTYPE F F F U\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 -1\n",
         ErrorCode::kMalformedInput, "not a valid U 4"},
        {"binary truncated", bin, ErrorCode::kTruncatedInput,
         "binary data is 20 bytes, POINTS x point size = 2 x 12 = 24"},
        {"compressed sizes cut", comp + "\x01\x02", ErrorCode::kTruncatedInput, "inside its two size fields"},
        {"compressed wrong uncompressed size", wrong_size, ErrorCode::kMalformedInput,
         "uncompressed size 20 differs from POINTS x point size"},
        {"compressed size past the end", past_end, ErrorCode::kTruncatedInput, "compressed size 26 runs past the end"},
        {"compressed size 0", zero_size, ErrorCode::kMalformedInput, "cannot expand"},
        {"compressed bad lzf", bad_lzf, ErrorCode::kTruncatedInput, "lzf: input offset 2"},
        {"compressed non-zero slack", slack, ErrorCode::kMalformedInput, "not all zero"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        PcdCloudInfo info;
        std::vector<PcdPoint> points;
        const IoStatus st = decode(c.file, info, points);
        CHECK(st.error() == c.code);
        CHECK_MESSAGE(contains(st, c.message), std::string(st.message()));
    }
    PcdCloudInfo info;
    std::vector<PcdPoint> points;
    const IoStatus ok = decode(good_comp, info, points);
    CHECK_MESSAGE(ok.ok(), std::string(ok.message()));
    CHECK(info.finite_points == 2U);
}

// verifies: SR-IO-002
TEST_CASE("pcd: a buffer too small for the points is refused, and the counts are still reported") {
    const std::string file = kXyzHeader + "DATA ascii\n1 2 3\nnan 5 6\n";
    PcdPoint one[1];
    PcdCloudInfo info;
    IoStatus st = decode_pcd(reinterpret_cast<const std::uint8_t*>(file.data()), file.size(), Span<PcdPoint>(one),
                             info);
    CHECK(st.ok());  // one finite point fits
    CHECK(info.written == 1U);
    PcdReadOptions keep;
    keep.keep_nonfinite = true;
    st = decode_pcd(reinterpret_cast<const std::uint8_t*>(file.data()), file.size(), Span<PcdPoint>(one), info, keep);
    CHECK(st.error() == ErrorCode::kCapacityExceeded);
    CHECK(contains(st, "2 points to write, the buffer holds 1"));
    CHECK(info.finite_points == 1U);
    CHECK(info.nonfinite_points == 1U);
    CHECK(info.written == 1U);
}

// verifies: SR-IO-002
TEST_CASE("pcd: files that cannot be read or written are reported with their path") {
    TempDir dir("pcd");
    PcdPoint points[2] = {{1.0F, 2.0F, 3.0F}, {4.0F, 5.0F, 6.0F}};
    PcdCloudInfo info;
    IoStatus st = read_pcd(dir.file("none.pcd").c_str(), Span<PcdPoint>(points), info);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    CHECK(contains(st, "none.pcd"));
    st = write_pcd(dir.file("a.pcd").c_str(), Span<const PcdPoint>(points), 3U, 1U, PcdViewpoint{},
                   PcdDataKind::kAscii);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    PcdViewpoint bad;
    bad.tx = std::nan("");
    st = write_pcd(dir.file("a.pcd").c_str(), Span<const PcdPoint>(points), 2U, 1U, bad, PcdDataKind::kAscii);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    st = write_pcd("/nonexistent-dir/a.pcd", Span<const PcdPoint>(points), 2U, 1U, PcdViewpoint{},
                   PcdDataKind::kBinary);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    CHECK(contains(st, "/nonexistent-dir/a.pcd"));
    // A file with a bad header names the file and the line.
    const std::string path = dir.file("b.pcd");
    std::FILE* f = std::fopen(path.c_str(), "wb");
    REQUIRE(f != nullptr);
    std::fputs("VERSION 0.7\nFIELDS x y z rgba\nSIZE 4 4 4\n", f);
    std::fclose(f);
    st = read_pcd(path.c_str(), Span<PcdPoint>(points), info);
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(contains(st, "b.pcd: pcd: line 3: FIELDS has 4 names but SIZE has 3"));
}
