// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file png.hpp
/// The host programs' PNG writer, on libpng (Debian libpng-dev): 8-bit RGB
/// or 8-bit indexed colour, no interlace, per row filter None or Up, zlib's
/// default compression. Flat-coloured images shrink well.
#ifndef CELLGUARD_HOST_IO_PNG_HPP
#define CELLGUARD_HOST_IO_PNG_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace cellguard::host {

/// An 8-bit RGB image, row-major from the top-left pixel.
struct RgbImage {
    int width = 0;                  ///< columns
    int height = 0;                 ///< rows
    std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes

    /// A @p w x @p h image filled with (@p r, @p g, @p b).
    static RgbImage filled(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b);
    /// Byte offset of pixel (@p x, @p y); the pixel must be inside.
    [[nodiscard]] std::size_t offset(int x, int y) const {
        return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3U;
    }
};

/// An indexed-colour image: one palette index per pixel, row-major.
struct IndexedImage {
    int width = 0;                                     ///< columns
    int height = 0;                                    ///< rows
    std::vector<std::uint8_t> pixels;                  ///< width * height palette indices
    std::vector<std::array<std::uint8_t, 3>> palette;  ///< RGB entries, 1 to 256
};

/// The PNG file of @p image (width and height 1..1,000,000, libpng's
/// limit, and rgb of the right size; else an empty vector).
std::vector<std::uint8_t> encode_png(const RgbImage& image);

/// The PNG file of @p image (width and height 1..1,000,000, pixels of the
/// right size, 1 to 256 palette entries covering every index used; else an
/// empty vector).
std::vector<std::uint8_t> encode_png(const IndexedImage& image);

/// Writes encode_png(@p image) to @p path; false with @p error set when the
/// image is invalid, libpng refuses it ("PNG: " and libpng's message) or the
/// file cannot be written (the message names @p path).
bool write_png(const std::string& path, const RgbImage& image, std::string& error);

/// Writes encode_png(@p image) to @p path; false with @p error set when the
/// image is invalid, libpng refuses it ("PNG: " and libpng's message) or the
/// file cannot be written (the message names @p path).
bool write_png(const std::string& path, const IndexedImage& image, std::string& error);

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_PNG_HPP
