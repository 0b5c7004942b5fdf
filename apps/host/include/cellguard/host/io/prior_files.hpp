// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file prior_files.hpp
/// The prior image on a Linux host: as a binary file (for the Linux daemon)
/// and as generated C++ source (for a firmware that keeps the prior in
/// flash). The format is prior_image.hpp's; these functions only move bytes
/// and never write an image that load_prior_image has not accepted.
///
/// Generated source: a header file, self-contained apart from the cellguard
/// include root, holding in namespace `options.name_space`:
/// - `kNx`, `kNy`, `kNz` (int32), `kVoxelCount`, the voxel size and origin
///   as binary64 bit patterns (`kVoxelSizeBits`, `kOriginBits[3]`), the
///   method and parameters (`kMethod`, `kTbBits`, `kTeBits`,
///   `kRadiusVoxels`, `kOpenFaces`) and both CRCs (`kPayloadCrc`,
///   `kHeaderCrc`);
/// - `kImage`: the image bytes, `inline constexpr std::uint8_t[]`, so one
///   copy lands in .rodata (flash) however many files include it;
/// - static_asserts that fail the build when the macros CELLGUARD_GRID_NX,
///   CELLGUARD_GRID_NY, CELLGUARD_GRID_NZ (the grid the firmware is compiled
///   for; from the build or from `options.config_header`, which is included
///   first) differ from the prior's grid, when they are not defined (#error),
///   when the library's format version or image size formula differ from
///   the ones the bytes were made with, and when the header bytes do not
///   match their CRC (computed at compile time) or the constants above.
/// The payload CRC is not computed at compile time (a large payload would
/// exceed the compilers' constexpr step limits): load_prior_image checks it
/// at start-up.
#ifndef CELLGUARD_HOST_IO_PRIOR_FILES_HPP
#define CELLGUARD_HOST_IO_PRIOR_FILES_HPP

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/host/io/io_status.hpp"
#include "cellguard/prior/accessibility_params.hpp"
#include "cellguard/prior/prior_image.hpp"

namespace cellguard {

/// Largest image file read_prior_image_file reads: the image of a grid of
/// kMaxVoxels voxels. Larger files are refused before anything is read.
constexpr std::size_t kMaxPriorImageFileSize = prior_image_size(kMaxVoxels);

/// Encodes @p prior into @p image (resized to exactly the image size) with
/// write_prior_image. Errors: those of write_prior_image, with a message;
/// kCapacityExceeded when the buffer cannot be allocated.
IoStatus encode_prior_image(const GridGeometry& geometry, const AccessibilityParams& params,
                            Span<const std::int16_t> prior, std::vector<std::uint8_t>& image) noexcept;

/// Writes the bytes of @p image (a view from load_prior_image) to @p path:
/// first to "<path>.tmp", flushed and fsync-ed, then renamed over @p path,
/// so @p path never holds half an image. Errors: kInvalidArgument for an
/// empty view, and kInvalidArgument with the OS message when a step fails
/// (ErrorCode has no I/O error).
IoStatus write_prior_image_file(const char* path, const PriorImageView& image) noexcept;

/// Reads the image file at @p path into @p bytes (resized to the file size)
/// and checks it with load_prior_image against @p expected_geometry; on
/// success @p view refers to bytes.data() (valid while @p bytes is not
/// changed). On failure @p view is left empty and, when @p reason is not
/// null, the loader's reason is stored there (kNone for an OS error).
/// Errors: the loader's ErrorCode with its to_string message; kInvalidArgument
/// with the OS message when the file cannot be opened, is not a regular
/// file, or cannot be read; kCapacityExceeded when it is larger than
/// kMaxPriorImageFileSize or the buffer cannot be allocated; kTruncatedInput
/// when the file shrinks while it is read.
IoStatus read_prior_image_file(const char* path, const GridGeometry& expected_geometry,
                               std::vector<std::uint8_t>& bytes, PriorImageView& view,
                               PriorImageError* reason = nullptr) noexcept;

/// Options of the generated source.
struct PriorSourceOptions {
    /// Namespace of the generated names: identifiers joined by "::".
    const char* name_space = "cellguard_prior";
    /// When not null: a header included (with quotes) before the
    /// CELLGUARD_GRID_NX/NY/NZ macros are checked, e.g. the firmware's grid
    /// configuration. Printable characters other than '"', '\\', '<', '>'.
    const char* config_header = nullptr;
};

/// The generated C++ header for @p image (a view from load_prior_image), in
/// @p text. Errors: kInvalidArgument for an empty view, a name_space that is
/// not identifiers joined by "::" or a config_header with a forbidden
/// character; kCapacityExceeded when the text cannot be allocated.
IoStatus prior_source_text(const PriorImageView& image, const PriorSourceOptions& options, std::string& text) noexcept;

/// prior_source_text written to @p path the way write_prior_image_file
/// writes (temporary file, fsync, rename). Errors: those of both.
IoStatus write_prior_source_file(const char* path, const PriorImageView& image,
                                 const PriorSourceOptions& options) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_PRIOR_FILES_HPP
