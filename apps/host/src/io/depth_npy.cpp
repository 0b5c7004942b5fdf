// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/depth_npy.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "cellguard/host/io/file.hpp"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "depth_npy.cpp writes little-endian .npy data as is: it needs a little-endian host");

namespace cellguard {

namespace {

bool side_valid(int side) noexcept { return side >= 1 && side <= kNpyDepthMaxSide; }

IoStatus os_error(const char* what, const char* path) noexcept {
    return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot %s: %s", path, what, std::strerror(errno));
}

IoStatus write_depth(const char* path, NpyDtype dtype, const void* data, std::size_t count, int width,
                     int height) noexcept {
    if (!side_valid(width) || !side_valid(height) ||
        count != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: npy: %zu pixels given for a %d x %d depth image",
                                 path, count, width, height);
    }
    const std::uint64_t shape[2] = {static_cast<std::uint64_t>(height), static_cast<std::uint64_t>(width)};
    std::uint8_t header[256];
    std::size_t length = 0U;
    const IoStatus st = format_npy_header_shape(dtype, shape, 2U, Span<std::uint8_t>(header), length);
    if (!st) {
        return st.prefixed(path);
    }
    host::FilePtr file = host::open_file(path, "wb");
    if (!file) {
        return os_error("create", path);
    }
    const std::size_t bytes = count * npy_item_size(dtype);
    if (std::fwrite(header, 1U, length, file.get()) != length || std::fwrite(data, 1U, bytes, file.get()) != bytes ||
        !host::close_file(file)) {
        return os_error("write", path);
    }
    return IoStatus{};
}

}  // namespace

IoStatus check_npy_depth_layout(const NpyHeader& header, int width, int height, std::uint64_t total_size) noexcept {
    if (!side_valid(width) || !side_valid(height)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: a depth image of %d x %d pixels is not accepted",
                                 width, height);
    }
    if (header.dtype != NpyDtype::kUInt16 && header.dtype != NpyDtype::kFloat32) {
        return IoStatus::failure(ErrorCode::kUnsupportedType,
                                 "npy: dtype '%s' is not a depth image's ('<u2' raw units or '<f4' metres)",
                                 npy_descr(header.dtype));
    }
    if (header.ndim != 2U || header.shape[0] != static_cast<std::uint64_t>(height) ||
        header.shape[1] != static_cast<std::uint64_t>(width)) {
        return IoStatus::failure(ErrorCode::kGeometryMismatch,
                                 "npy: a depth image of shape (height, width) = (%d, %d) expected; the file has %zu "
                                 "dimensions (%" PRIu64 ", %" PRIu64 ", ...)",
                                 height, width, header.ndim, header.ndim > 0U ? header.shape[0] : 0U,
                                 header.ndim > 1U ? header.shape[1] : 0U);
    }
    return check_npy_data_size(header, total_size);
}

IoStatus decode_npy_depth(const std::uint8_t* data, std::size_t size, int width, int height,
                          NpyDepthImage& image) noexcept {
    image = NpyDepthImage{};
    NpyHeader header;
    IoStatus st = parse_npy_header(data, size, header);
    if (!st) {
        return st;
    }
    st = check_npy_depth_layout(header, width, height, size);
    if (!st) {
        return st;
    }
    image.dtype = header.dtype;
    image.pixels = data + header.data_offset;
    image.count = static_cast<std::size_t>(header.element_count);
    return IoStatus{};
}

IoStatus read_npy_depth(const char* path, int width, int height, Span<std::uint8_t> scratch,
                        NpyDepthImage& image) noexcept {
    // The allocation-free read (the monitor's cycle allocates nothing).
    image = NpyDepthImage{};
    std::size_t got = 0U;
    IoStatus st = host::read_whole_file(path, scratch, got);
    if (st.error() == ErrorCode::kStorageTooSmall) {
        return IoStatus::failure(ErrorCode::kStorageTooSmall,
                                 "%s: npy: the file is larger than the %zu bytes a %d x %d depth image takes", path,
                                 scratch.size(), width, height);
    }
    if (!st) {
        return st;
    }
    st = decode_npy_depth(scratch.data(), got, width, height, image);
    return st ? st : st.prefixed(path);
}

IoStatus probe_npy_depth(const char* path, int width, int height, NpyDtype& dtype) noexcept {
    host::FilePtr file = host::open_file(path, "rb");
    if (!file) {
        return os_error("open", path);
    }
    struct stat info {};
    if (::fstat(::fileno(file.get()), &info) != 0) {
        return os_error("stat", path);
    }
    std::uint8_t head[4096];
    const std::size_t got = std::fread(head, 1U, sizeof head, file.get());
    NpyHeader header;
    IoStatus st = parse_npy_header(head, got, header);
    if (st) {
        st = check_npy_depth_layout(header, width, height, static_cast<std::uint64_t>(info.st_size));
    }
    if (!st) {
        return st.prefixed(path);
    }
    dtype = header.dtype;
    return IoStatus{};
}

std::size_t npy_depth_file_bytes(NpyDtype dtype, int width, int height) noexcept {
    if (!side_valid(width) || !side_valid(height) || (dtype != NpyDtype::kUInt16 && dtype != NpyDtype::kFloat32)) {
        return 0U;
    }
    const std::uint64_t shape[2] = {static_cast<std::uint64_t>(height), static_cast<std::uint64_t>(width)};
    std::uint8_t header[256];
    std::size_t length = 0U;
    if (!format_npy_header_shape(dtype, shape, 2U, Span<std::uint8_t>(header), length)) {
        return 0U;
    }
    return length + static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * npy_item_size(dtype);
}

IoStatus write_npy_depth_u16(const char* path, Span<const std::uint16_t> depth, int width, int height) noexcept {
    return write_depth(path, NpyDtype::kUInt16, depth.data(), depth.size(), width, height);
}

IoStatus write_npy_depth_f32(const char* path, Span<const float> depth, int width, int height) noexcept {
    return write_depth(path, NpyDtype::kFloat32, depth.data(), depth.size(), width, height);
}

}  // namespace cellguard
