/// @file png.hpp
/// A small PNG writer for the evaluation's renders: 8-bit indexed colour,
/// one IDAT, deflate with the fixed Huffman code and run-length matches
/// (distance 1) after a per-row None or Up filter. Flat-coloured images
/// shrink well; no zlib needed.
#ifndef CELLGUARD_EVAL_PNG_HPP
#define CELLGUARD_EVAL_PNG_HPP

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace cellguard::eval {

/// An indexed-colour image: one palette index per pixel, row-major.
struct IndexedImage {
    int width = 0;                                   ///< columns
    int height = 0;                                  ///< rows
    std::vector<std::uint8_t> pixels;                ///< width * height palette indices
    std::vector<std::array<std::uint8_t, 3>> palette;  ///< RGB entries, at most 256
};

/// The PNG file bytes of @p image (palette must cover every index used).
std::vector<std::uint8_t> encode_png(const IndexedImage& image);

/// Writes @p image to @p path; false when the file cannot be written.
bool write_png(const std::string& path, const IndexedImage& image);

}  // namespace cellguard::eval

#endif  // CELLGUARD_EVAL_PNG_HPP
