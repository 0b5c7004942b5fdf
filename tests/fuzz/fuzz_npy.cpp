// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzzes the .npy parser and decoders over a byte buffer (no files): they must never crash, read out of
// bounds or accept a header whose data would lie outside the input.
#include <cstddef>
#include <cstdint>

#include "cellguard/host/io/npy.hpp"

using namespace cellguard;

namespace {
std::int16_t g_i16[4096];
float g_f32[4096];
std::uint8_t g_u8[4096];

void require(bool condition) {
    if (!condition) {
        __builtin_trap();
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    NpyHeader header;
    const IoStatus st = parse_npy_header(data, size, header);
    if (st.ok()) {
        require(header.data_offset <= size);
        require(header.ndim <= kNpyMaxDims);
        require(header.major_version == 1U || header.major_version == 2U);
    } else {
        require(st.message()[0] != '\0');  // every error says what is wrong
    }
    // Decode with the shape the header claims when it is small and 3-d, so that
    // valid inputs reach the copy; otherwise with a fixed shape.
    GridDims dims{4, 4, 4};
    if (st.ok() && header.ndim == 3U && header.shape[0] >= 1U && header.shape[0] <= 16U && header.shape[1] >= 1U &&
        header.shape[1] <= 16U && header.shape[2] >= 1U && header.shape[2] <= 16U) {
        dims = GridDims{static_cast<std::int32_t>(header.shape[2]), static_cast<std::int32_t>(header.shape[1]),
                        static_cast<std::int32_t>(header.shape[0])};
    }
    const IoStatus a = decode_npy_int16(data, size, dims, Span<std::int16_t>(g_i16));
    const IoStatus b = decode_npy_float32(data, size, dims, Span<float>(g_f32));
    const IoStatus c = decode_npy_uint8(data, size, dims, Span<std::uint8_t>(g_u8));
    // At most one dtype can match, and only when the header parsed.
    require(static_cast<int>(a.ok()) + static_cast<int>(b.ok()) + static_cast<int>(c.ok()) <= 1);
    require(st.ok() || (!a.ok() && !b.ok() && !c.ok()));
    return 0;
}
