// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzzes the recorded depth image decoder (depth_npy.hpp) over a byte buffer (no files): it must never
// crash or read out of bounds, and an accepted image must be a (height, width) array of '<u2' or '<f4'
// lying wholly inside the input, whose reading the controller's check then takes or refuses cleanly.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/io/depth_npy.hpp"

using namespace cellguard;

namespace {
std::uint16_t g_raw[64 * 64];
float g_metres[64 * 64];

void require(bool condition) {
    if (!condition) {
        __builtin_trap();
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The size the header claims when it is 2-d and small, so that valid inputs reach the reading; else 4 x 3.
    int width = 4;
    int height = 3;
    NpyHeader header;
    if (parse_npy_header(data, size, header).ok() && header.ndim == 2U && header.shape[0] >= 1U &&
        header.shape[0] <= 64U && header.shape[1] >= 1U && header.shape[1] <= 64U) {
        height = static_cast<int>(header.shape[0]);
        width = static_cast<int>(header.shape[1]);
    }
    NpyDepthImage image;
    const IoStatus st = decode_npy_depth(data, size, width, height, image);
    if (!st.ok()) {
        require(st.message()[0] != '\0');  // every error says what is wrong
        require(image.pixels == nullptr);
        return 0;
    }
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    require(image.count == pixels);
    require(image.dtype == NpyDtype::kUInt16 || image.dtype == NpyDtype::kFloat32);
    const std::size_t bytes = pixels * npy_item_size(image.dtype);
    require(image.pixels >= data && static_cast<std::size_t>(image.pixels - data) + bytes == size);
    SensorReading r;
    r.intrinsics = PinholeIntrinsics{};
    r.intrinsics.width = width;
    r.intrinsics.height = height;
    r.intrinsics.fx = 50.0;
    r.intrinsics.fy = 50.0;
    if (image.dtype == NpyDtype::kUInt16) {
        std::memcpy(g_raw, image.pixels, bytes);
        r.kind = SensorDataKind::kDepthImageU16;
        r.depth_u16 = Span<const std::uint16_t>(g_raw, pixels);
    } else {
        std::memcpy(g_metres, image.pixels, bytes);
        r.kind = SensorDataKind::kDepthImage;
        r.depth = Span<const float>(g_metres, pixels);
    }
    require(validate_sensor_reading(r).ok());  // any values: a reading of the right size is well formed
    for (std::size_t i = 0; i < pixels && image.dtype == NpyDtype::kUInt16; ++i) {
        const float d = depth_value(r, i);  // raw 0: NaN (no reading); else raw * 0.001 m: no wrap-around
        require(g_raw[i] == 0U ? d != d : (d >= 0.0009F && d <= 65.6F));
    }
    return 0;
}
