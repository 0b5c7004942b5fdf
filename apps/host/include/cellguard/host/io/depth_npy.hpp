// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file depth_npy.hpp
/// Recorded depth images as NumPy .npy files: the camera path's file format
/// (a sensor's `depth_files`, cellguard-monitor --record-depth).
///
/// One file holds one frame of one camera: shape (height, width), C order, so
/// that in Python `a[v, u]` is the pixel in row v and column u, as the camera
/// delivers it, in one of two dtypes:
/// - '<u2' (uint16): the camera's raw values (GigE Vision Coord3D_C16,
///   RealSense Z16); metres = raw * depth_scale + depth_offset, which the
///   sensor's configuration gives; raw 0 = no reading;
/// - '<f4' (float32): metres along the optical axis; 0, NaN and infinities =
///   no reading.
/// Format version 1.0 as numpy.save writes it (npy.hpp), versions 1.0 and 2.0
/// read. Reading checks, and refuses with a message: everything npy.hpp
/// checks (magic, version, header dict, big-endian, trailing or missing
/// bytes), a dtype other than the two, and a shape other than
/// (height, width) of the sensor. The intrinsics are the sensor's
/// configuration, not the file's: a file says nothing about them.
#ifndef CELLGUARD_HOST_IO_DEPTH_NPY_HPP
#define CELLGUARD_HOST_IO_DEPTH_NPY_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"
#include "cellguard/host/io/io_status.hpp"
#include "cellguard/host/io/npy.hpp"

namespace cellguard {

/// A depth image decoded from a .npy file: where its pixels lie in the
/// caller's bytes (not aligned: copy them out with memcpy).
struct NpyDepthImage {
    NpyDtype dtype = NpyDtype::kUInt16;    ///< kUInt16 or kFloat32
    const std::uint8_t* pixels = nullptr;  ///< width * height values, little-endian, C order
    std::size_t count = 0U;                ///< width * height
};

/// Largest image side a depth file may have (a sanity bound on the header).
constexpr int kNpyDepthMaxSide = 16384;

/// Checks a parsed header against a depth image of @p width x @p height in a
/// file of exactly @p total_size bytes. Errors: kInvalidArgument (a side
/// outside 1..kNpyDepthMaxSide), kUnsupportedType (not '<u2' or '<f4'),
/// kGeometryMismatch (not two dimensions (height, width)), kTruncatedInput
/// (file shorter than the data), kMalformedInput (bytes after the data).
IoStatus check_npy_depth_layout(const NpyHeader& header, int width, int height, std::uint64_t total_size) noexcept;

/// Decodes a whole depth .npy file held in @p data (@p size bytes) for a
/// @p width x @p height sensor: every check of parse_npy_header and
/// check_npy_depth_layout; @p image then points into @p data.
IoStatus decode_npy_depth(const std::uint8_t* data, std::size_t size, int width, int height,
                          NpyDepthImage& image) noexcept;

/// Reads the file at @p path whole into @p scratch (its size: the most bytes
/// accepted; a larger file is refused with kStorageTooSmall) and decodes it
/// as decode_npy_depth does; @p image points into @p scratch. Allocates
/// nothing. Errors also: kInvalidArgument with the OS message when the file
/// cannot be opened or read.
IoStatus read_npy_depth(const char* path, int width, int height, Span<std::uint8_t> scratch,
                        NpyDepthImage& image) noexcept;

/// Checks the file at @p path as a depth image of @p width x @p height
/// without reading its pixels (its header, at most 4096 bytes, against its
/// size): what a configuration loader asks of a recording. @p dtype receives
/// the file's dtype. Errors: those of check_npy_depth_layout and
/// parse_npy_header, kInvalidArgument with the OS message.
IoStatus probe_npy_depth(const char* path, int width, int height, NpyDtype& dtype) noexcept;

/// Bytes of a version 1.0 depth file of @p width x @p height in @p dtype
/// (header and data), as write_npy_depth_* write it; 0 for a bad size or dtype.
std::size_t npy_depth_file_bytes(NpyDtype dtype, int width, int height) noexcept;

/// Writes @p depth (exactly width * height raw values) as a '<u2' image of
/// shape (height, width) to @p path. Errors: kInvalidArgument (size, or the
/// OS message when the file cannot be written).
IoStatus write_npy_depth_u16(const char* path, Span<const std::uint16_t> depth, int width, int height) noexcept;
/// write_npy_depth_u16 for a float32 image in metres ('<f4').
IoStatus write_npy_depth_f32(const char* path, Span<const float> depth, int width, int height) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_DEPTH_NPY_HPP
