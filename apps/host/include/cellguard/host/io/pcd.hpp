// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file pcd.hpp
/// PCL point cloud files (.pcd) as sensor input: the reader takes x, y, z of
/// every point as float, skips points with a NaN or infinite coordinate and
/// counts them, and reports the width, height (organised clouds) and
/// viewpoint. A small writer (x y z only) serves tests and tools.
///
/// Reads PCD v0.7, and 0.6 / 0.5 headers where they say the same things:
/// - Header lines in this order, each at most once: VERSION, FIELDS, SIZE,
///   TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA. COUNT (default 1
///   each) and VIEWPOINT (default 0 0 0 1 0 0 0) may be left out; so may WIDTH
///   and HEIGHT together before v0.7 (then WIDTH = POINTS, HEIGHT = 1), and
///   before v0.7 FIELDS may be spelt COLUMNS. Lines starting with '#' and blank
///   lines are skipped; lines end in "\n" or "\r\n".
/// - Field types F (SIZE 4 or 8), I and U (SIZE 1, 2 or 4), COUNT >= 1; at
///   most kPcdMaxFields fields. Fields x, y and z must exist once each with
///   COUNT 1. WIDTH, HEIGHT >= 1 and POINTS == WIDTH * HEIGHT. VIEWPOINT is
///   7 finite numbers (tx ty tz qw qx qy qz) with a unit quaternion (+-1e-3).
/// - DATA ascii: one point per line, COUNT values per field, each checked
///   against its type and size. DATA binary: POINTS records of the fields in
///   order, little-endian. DATA binary_compressed (v0.7 only): uint32
///   compressed size, uint32 uncompressed size (must be POINTS * point size),
///   then LZF data that decompresses to all values of field 1, then of field
///   2, and so on (structure of arrays).
/// - After binary and compressed data only zero bytes may follow (PCL pads
///   its files so; the real Kinect frames carry such padding); anything else,
///   or too little data, is an error. After ASCII data only blank lines.
///
/// Every error is an IoStatus whose message names the line or byte offset.
#ifndef CELLGUARD_HOST_IO_PCD_HPP
#define CELLGUARD_HOST_IO_PCD_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"
#include "cellguard/host/io/io_status.hpp"

namespace cellguard {

/// How the point data is stored (the DATA line).
enum class PcdDataKind : std::uint8_t {
    kAscii = 0,             ///< text, one point per line
    kBinary = 1,            ///< little-endian records, one per point
    kBinaryCompressed = 2,  ///< LZF-compressed structure of arrays
};

/// The TYPE of a field.
enum class PcdFieldType : std::uint8_t {
    kFloat = 0,     ///< F: IEEE float (SIZE 4) or double (SIZE 8)
    kSigned = 1,    ///< I: two's-complement integer (SIZE 1, 2, 4)
    kUnsigned = 2,  ///< U: unsigned integer (SIZE 1, 2, 4)
};

/// Most fields a header may declare.
constexpr std::size_t kPcdMaxFields = 64;
/// Longest field name plus its terminating NUL.
constexpr std::size_t kPcdMaxFieldName = 32;
/// Largest COUNT of one field.
constexpr std::uint32_t kPcdMaxCount = 1U << 16U;
/// Largest point data (POINTS * point size) the reader accepts, bytes.
constexpr std::uint64_t kPcdMaxDataBytes = std::uint64_t{1} << 30U;
/// Largest file read_pcd reads, bytes.
constexpr std::uint64_t kPcdMaxFileBytes = std::uint64_t{2} << 30U;

/// One field of the header.
struct PcdField {
    char name[kPcdMaxFieldName] = {};          ///< FIELDS entry
    std::uint32_t size = 0;                    ///< SIZE entry: bytes of one value
    PcdFieldType type = PcdFieldType::kFloat;  ///< TYPE entry
    std::uint32_t count = 1;                   ///< COUNT entry: values per point
    std::size_t offset = 0;                    ///< byte offset of the field in a point record
};

/// The VIEWPOINT line: sensor position and orientation (a unit quaternion).
struct PcdViewpoint {
    double tx = 0.0;  ///< translation x
    double ty = 0.0;  ///< translation y
    double tz = 0.0;  ///< translation z
    double qw = 1.0;  ///< quaternion w
    double qx = 0.0;  ///< quaternion x
    double qy = 0.0;  ///< quaternion y
    double qz = 0.0;  ///< quaternion z
};

/// What a .pcd header says.
struct PcdHeader {
    std::uint32_t version_minor = 7;         ///< 5, 6 or 7 (VERSION 0.5 / 0.6 / 0.7)
    std::size_t field_count = 0;             ///< number of fields
    PcdField fields[kPcdMaxFields] = {};     ///< the fields, in file order
    std::uint32_t width = 0;                 ///< WIDTH: points per row
    std::uint32_t height = 0;                ///< HEIGHT: rows (1 for an unorganised cloud)
    PcdViewpoint viewpoint{};                ///< VIEWPOINT
    std::uint64_t points = 0;                ///< POINTS
    PcdDataKind data = PcdDataKind::kAscii;  ///< DATA
    std::size_t point_bytes = 0;             ///< bytes of one point record (sum of SIZE * COUNT)
    std::size_t data_offset = 0;             ///< bytes from the start of the file to the data
    std::size_t x_field = 0;                 ///< index of field x
    std::size_t y_field = 0;                 ///< index of field y
    std::size_t z_field = 0;                 ///< index of field z
};

/// One point's coordinates, as float (metres in the sensor frame).
struct PcdPoint {
    float x = 0.0F;  ///< x
    float y = 0.0F;  ///< y
    float z = 0.0F;  ///< z
};

/// What reading a cloud found.
struct PcdCloudInfo {
    std::uint32_t width = 0;                 ///< WIDTH
    std::uint32_t height = 0;                ///< HEIGHT
    PcdViewpoint viewpoint{};                ///< VIEWPOINT
    PcdDataKind data = PcdDataKind::kAscii;  ///< DATA
    std::uint64_t points = 0;                ///< POINTS (= width * height)
    std::uint64_t finite_points = 0;         ///< points whose x, y, z are all finite
    std::uint64_t nonfinite_points = 0;      ///< points with a NaN or infinite coordinate
    std::uint64_t written = 0;               ///< points written to the caller's buffer
};

/// Reading options.
struct PcdReadOptions {
    /// false (default): only finite points are written. true: every point is
    /// written in file order, non-finite ones as stored (to keep an organised
    /// cloud's layout, e.g. to write it again).
    bool keep_nonfinite = false;
};

/// Parses and checks the header of a .pcd file held in @p data (@p size
/// bytes, the whole file or at least its header). Errors: kUnsupportedVersion,
/// kUnsupportedType (a TYPE/SIZE this reader cannot read, or x/y/z with COUNT
/// != 1), kMalformedInput (keyword order, counts, values, missing x/y/z),
/// kTruncatedInput (no DATA line), kCapacityExceeded (too many fields, data
/// above kPcdMaxDataBytes).
IoStatus parse_pcd_header(const std::uint8_t* data, std::size_t size, PcdHeader& header) noexcept;

/// Decompresses LZF data @p in (@p in_size bytes) into @p out, which must
/// receive exactly @p out_size bytes. Every literal run and back-reference
/// is checked: input never read past its end (kTruncatedInput), output never
/// written past @p out_size and back-references never reaching before the
/// start of the output (kMalformedInput), and the output must come out
/// exactly @p out_size bytes long (kMalformedInput).
IoStatus lzf_decompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out, std::size_t out_size) noexcept;

/// Decodes a whole .pcd file held in memory: x, y, z of the points go to
/// @p out (finite points only, unless @p options.keep_nonfinite), counts and
/// header facts to @p info (filled even when @p out is too small).
/// Errors: those of parse_pcd_header; kTruncatedInput / kMalformedInput on
/// data that does not match the header (message with line or offset);
/// kCapacityExceeded when @p out holds fewer points than are to be written,
/// or when the decompression buffer cannot be allocated.
IoStatus decode_pcd(const std::uint8_t* data, std::size_t size, Span<PcdPoint> out, PcdCloudInfo& info,
                    PcdReadOptions options = PcdReadOptions{}) noexcept;

/// Reads the file at @p path (at most kPcdMaxFileBytes) and decodes it with
/// decode_pcd; messages start with the path. Errors also: kInvalidArgument with
/// the OS message when the file cannot be opened or read.
IoStatus read_pcd(const char* path, Span<PcdPoint> out, PcdCloudInfo& info,
                  PcdReadOptions options = PcdReadOptions{}) noexcept;

/// Writes @p points (exactly @p width * @p height of them, row by row) as a
/// PCD v0.7 file with fields x y z (F 4) in the given DATA kind; floats in
/// ASCII are written with the fewest digits that read back to the same value.
/// binary_compressed is written as valid LZF made of literal runs only (no
/// compression). Errors: kInvalidArgument (count mismatch, width or height 0,
/// a non-finite viewpoint, or with the OS message when the file cannot be written).
IoStatus write_pcd(const char* path, Span<const PcdPoint> points, std::uint32_t width, std::uint32_t height,
                   const PcdViewpoint& viewpoint, PcdDataKind kind) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_PCD_HPP
