// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzzes the .pcd header parser, the point decoder (ascii, binary, binary_compressed) and the LZF
// decompressor over a byte buffer (no files): they must never crash, read or write out of bounds, and their
// counts must agree with the header on success.
#include <cstddef>
#include <cstdint>

#include "cellguard/host/io/pcd.hpp"

using namespace cellguard;

namespace {
PcdPoint g_points[1024];
std::uint8_t g_lzf_out[8192];

void require(bool condition) {
    if (!condition) {
        __builtin_trap();
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static PcdHeader header;  // large (64 fields): keep it off the stack
    const IoStatus h = parse_pcd_header(data, size, header);
    if (h.ok()) {
        require(header.data_offset <= size);
        require(header.points == static_cast<std::uint64_t>(header.width) * header.height);
        require(header.x_field < header.field_count && header.y_field < header.field_count &&
                header.z_field < header.field_count);
    } else {
        require(h.message()[0] != '\0');
    }

    PcdCloudInfo info;
    const IoStatus st = decode_pcd(data, size, Span<PcdPoint>(g_points), info);
    require(info.written <= sizeof g_points / sizeof g_points[0]);
    if (st.ok()) {
        require(h.ok());
        require(info.finite_points + info.nonfinite_points == info.points);
        require(info.written == info.finite_points);
    }
    PcdReadOptions keep;
    keep.keep_nonfinite = true;
    const IoStatus all = decode_pcd(data, size, Span<PcdPoint>(g_points), info, keep);
    if (all.ok()) {
        require(info.written == info.points);
    }

    // The decompressor alone: first two bytes give the expected output size.
    if (size >= 2U) {
        const std::size_t out_size = (static_cast<std::size_t>(data[0]) | (static_cast<std::size_t>(data[1]) << 8U)) %
                                     (sizeof g_lzf_out + 1U);
        static_cast<void>(lzf_decompress(data + 2, size - 2U, g_lzf_out, out_size));
    }
    return 0;
}
