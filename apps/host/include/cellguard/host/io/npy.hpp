// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file npy.hpp
/// NumPy .npy files for grids: export for inspection in Python, import of a
/// background grid G_B.
///
/// Writes format version 1.0 exactly as numpy.save does (magic "\x93NUMPY",
/// version, little-endian header length, the header dict
/// `{'descr': ..., 'fortran_order': False, 'shape': (nz, ny, nx), }` with
/// numpy's spare spaces, padded with spaces to a multiple of 64 bytes and
/// ended by '\n', then the data in C order). Reads versions 1.0 and 2.0.
///
/// A grid of dims (nx, ny, nz) is stored with shape (nz, ny, nx), so that in
/// Python `a[z, y, x]` is the voxel with linear index x + nx * (y + ny * z)
/// (grid.hpp). Three dtypes: int16 log-odds ('<i2'), float32 probability
/// ('<f4') and uint8 observed flags ('|u1'; '<u1' and '>u1' are read too).
///
/// Reading checks, and rejects with a message: the magic, the version, the
/// header length against the input, the header dict (exactly the keys descr,
/// fortran_order and shape; fortran_order False; shape a tuple of decimal
/// integers; the header ends in '\n'), the dtype and shape against the ones
/// the caller expects, big-endian dtypes, and the input size against the
/// shape (short input and trailing bytes both fail). It never reads past the
/// input. The data goes straight into caller storage. This file assumes a
/// little-endian host (checked at compile time).
#ifndef CELLGUARD_HOST_IO_NPY_HPP
#define CELLGUARD_HOST_IO_NPY_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/host/io/io_status.hpp"

namespace cellguard {

/// The element types cellguard stores in .npy files.
enum class NpyDtype : std::uint8_t {
    kInt16 = 1,    ///< '<i2': log-odds
    kFloat32 = 2,  ///< '<f4': probability
    kUInt8 = 3,    ///< '|u1': observed flags
    kUInt16 = 4,   ///< '<u2': a depth camera's raw depth image (depth_npy.hpp)
};

/// The descr string numpy writes for @p dtype ("<i2", "<f4", "|u1", "<u2").
const char* npy_descr(NpyDtype dtype) noexcept;
/// Bytes per element of @p dtype.
std::size_t npy_item_size(NpyDtype dtype) noexcept;

/// Most dimensions a parsed header may have.
constexpr std::size_t kNpyMaxDims = 8;
/// Longest header (the dict plus padding, without the magic, version and
/// length field) this reader accepts; numpy's own are 118 bytes or so.
constexpr std::size_t kNpyMaxHeaderBytes = 65535;
/// Bytes of a version 1.0 preamble: magic (6), version (2), header length (2).
constexpr std::size_t kNpyPreambleV1 = 10;
/// Bytes of a version 2.0 preamble: magic (6), version (2), header length (4).
constexpr std::size_t kNpyPreambleV2 = 12;

/// What a .npy header says.
struct NpyHeader {
    std::uint8_t major_version = 0;         ///< 1 or 2
    std::uint8_t minor_version = 0;         ///< 0
    NpyDtype dtype = NpyDtype::kUInt8;      ///< element type
    std::size_t ndim = 0;                   ///< number of dimensions (0 for a scalar)
    std::uint64_t shape[kNpyMaxDims] = {};  ///< extent of each dimension, C order
    std::size_t data_offset = 0;            ///< bytes from the start of the file to the data
    std::uint64_t element_count = 0;        ///< product of the shape
    std::uint64_t data_bytes = 0;           ///< element_count * item size
};

/// Parses and checks the preamble and header dict of a .npy file held in
/// @p data (@p size bytes: the whole file or at least its header). Does not
/// look at the data. Errors: kBadMagic, kUnsupportedVersion (not 1.0 or 2.0),
/// kTruncatedInput (input ends inside the preamble or header),
/// kMalformedInput (header dict wrong, fortran_order True, header too long),
/// kUnsupportedType (a dtype other than the three, big-endian included),
/// kCapacityExceeded (more than kNpyMaxDims dimensions, or a size overflow).
IoStatus parse_npy_header(const std::uint8_t* data, std::size_t size, NpyHeader& header) noexcept;

/// Checks a parsed header against what the caller expects: @p dtype, shape
/// (nz, ny, nx) of @p dims, and a file of exactly @p total_size bytes.
/// Errors: kInvalidArgument (a dimension of @p dims < 1), kUnsupportedType
/// (dtype), kGeometryMismatch (shape), kTruncatedInput (file shorter than the
/// data), kMalformedInput (trailing bytes).
IoStatus check_npy_layout(const NpyHeader& header, NpyDtype dtype, GridDims dims, std::uint64_t total_size) noexcept;

/// Checks that a file of exactly @p total_size bytes holds the data @p header
/// describes after its header, no more and no less. Errors: kTruncatedInput
/// (file shorter than the data), kMalformedInput (trailing bytes). The last
/// step of check_npy_layout and check_npy_depth_layout (depth_npy.hpp).
IoStatus check_npy_data_size(const NpyHeader& header, std::uint64_t total_size) noexcept;

/// The .npy preamble and header numpy writes (version 1.0) for an array of
/// @p dtype and shape (nz, ny, nx), into @p out; @p length receives its size
/// (a multiple of 64). Errors: kInvalidArgument (a dimension < 1),
/// kStorageTooSmall (@p out too small; 256 bytes always suffice).
IoStatus format_npy_header(NpyDtype dtype, GridDims dims, Span<std::uint8_t> out, std::size_t& length) noexcept;
/// format_npy_header for any shape: @p ndim (1..3) extents of @p shape, C order, each >= 1.
IoStatus format_npy_header_shape(NpyDtype dtype, const std::uint64_t* shape, std::size_t ndim, Span<std::uint8_t> out,
                                 std::size_t& length) noexcept;

/// Decodes a whole .npy file held in memory into @p out (at least
/// nx * ny * nz elements; the first that many are written). All the checks of
/// parse_npy_header and check_npy_layout apply; kStorageTooSmall when @p out
/// is too small.
IoStatus decode_npy_int16(const std::uint8_t* data, std::size_t size, GridDims dims, Span<std::int16_t> out) noexcept;
/// decode_npy_int16 for float32 data.
IoStatus decode_npy_float32(const std::uint8_t* data, std::size_t size, GridDims dims, Span<float> out) noexcept;
/// decode_npy_int16 for uint8 data.
IoStatus decode_npy_uint8(const std::uint8_t* data, std::size_t size, GridDims dims, Span<std::uint8_t> out) noexcept;

/// Writes @p data (exactly nx * ny * nz elements, else kInvalidArgument) as
/// an int16 array of shape (nz, ny, nx) to @p path. Errors also: kInvalidArgument
/// (a dimension < 1), and kInvalidArgument with the OS message when the file
/// cannot be written (ErrorCode has no I/O error yet).
IoStatus write_npy_int16(const char* path, Span<const std::int16_t> data, GridDims dims) noexcept;
/// write_npy_int16 for float32 data.
IoStatus write_npy_float32(const char* path, Span<const float> data, GridDims dims) noexcept;
/// write_npy_int16 for uint8 data.
IoStatus write_npy_uint8(const char* path, Span<const std::uint8_t> data, GridDims dims) noexcept;

/// Reads the .npy file at @p path into @p out, with all the checks of
/// decode_npy_int16; the data is read straight into @p out. Errors also:
/// kInvalidArgument with the OS message when the file cannot be opened or read.
IoStatus read_npy_int16(const char* path, GridDims dims, Span<std::int16_t> out) noexcept;
/// read_npy_int16 for float32 data.
IoStatus read_npy_float32(const char* path, GridDims dims, Span<float> out) noexcept;
/// read_npy_int16 for uint8 data.
IoStatus read_npy_uint8(const char* path, GridDims dims, Span<std::uint8_t> out) noexcept;

/// Longest path write_grid_npy and read_grid_npy build from a prefix.
constexpr std::size_t kNpyMaxPath = 4096;

/// Writes @p grid as three files: `<prefix>_log_odds.npy` (int16),
/// `<prefix>_probability.npy` (float32, probability_from_log_odds of each
/// voxel) and `<prefix>_observed.npy` (uint8). Errors: kInvalidArgument (empty
/// grid, or a path longer than kNpyMaxPath), and those of write_npy_int16.
IoStatus write_grid_npy(const char* path_prefix, const EvidenceGrid& grid) noexcept;

/// Reads a background grid from an int16 log-odds file and a uint8 observed
/// file into @p grid, whose geometry (set by the caller) gives the expected
/// shape. Checks every value: observed flags are 0 or 1, and no log-odds is
/// the kNeverForeground sentinel (a background grid never holds it); else
/// kMalformedInput naming the voxel. On any error @p grid is cleared (unknown
/// and unobserved everywhere), so no partial data is left behind.
IoStatus read_background_npy(const char* log_odds_path, const char* observed_path, EvidenceGrid& grid) noexcept;

/// read_background_npy from `<prefix>_log_odds.npy` and `<prefix>_observed.npy`,
/// the files write_grid_npy writes.
IoStatus read_grid_npy(const char* path_prefix, EvidenceGrid& grid) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_NPY_HPP
