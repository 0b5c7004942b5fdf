/// @file png.hpp
/// A minimal PNG writer for the configuration picture: 8-bit RGB, no
/// interlace, every scanline with filter 0, the zlib stream made of stored
/// (uncompressed) deflate blocks with its Adler-32, each chunk with its CRC-32
/// (lib/'s crc32.hpp is the PNG CRC). No dependency beyond lib/.
#ifndef CELLGUARD_MONITOR_PNG_HPP
#define CELLGUARD_MONITOR_PNG_HPP

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace cellguard::monitor {

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

/// Adler-32 of @p size bytes at @p data (RFC 1950).
std::uint32_t adler32(const std::uint8_t* data, std::size_t size);

/// The PNG file of @p image (width and height 1..2^31 - 1 and rgb of the
/// right size, else an empty vector).
std::vector<std::uint8_t> encode_png(const RgbImage& image);

/// Writes encode_png(@p image) to @p path; false with @p error set when the
/// image is invalid or the file cannot be written.
bool write_png(const std::string& path, const RgbImage& image, std::string& error);

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_PNG_HPP
