// Minimal PNG writer: stored deflate blocks, CRC-32 per chunk, Adler-32.
#include "cellguard/monitor/png.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>

#include "cellguard/crc32.hpp"

namespace cellguard::monitor {
namespace {

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    out.push_back(static_cast<std::uint8_t>(v >> 24U));
    out.push_back(static_cast<std::uint8_t>(v >> 16U));
    out.push_back(static_cast<std::uint8_t>(v >> 8U));
    out.push_back(static_cast<std::uint8_t>(v));
}

/// Appends a chunk: length, type, data, CRC-32 over type and data.
void put_chunk(std::vector<std::uint8_t>& out, const char (&type)[5], const std::vector<std::uint8_t>& data) {
    put_u32(out, static_cast<std::uint32_t>(data.size()));
    const std::size_t crc_from = out.size();
    for (std::size_t i = 0U; i < 4U; ++i) {
        out.push_back(static_cast<std::uint8_t>(type[i]));
    }
    out.insert(out.end(), data.begin(), data.end());
    put_u32(out, crc32(Span<const std::uint8_t>(out.data() + crc_from, out.size() - crc_from)));
}

}  // namespace

RgbImage RgbImage::filled(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    RgbImage img;
    img.width = w;
    img.height = h;
    const std::size_t n = static_cast<std::size_t>(w > 0 ? w : 0) * static_cast<std::size_t>(h > 0 ? h : 0);
    img.rgb.resize(n * 3U);
    for (std::size_t i = 0U; i < n; ++i) {
        img.rgb[3U * i] = r;
        img.rgb[3U * i + 1U] = g;
        img.rgb[3U * i + 2U] = b;
    }
    return img;
}

std::uint32_t adler32(const std::uint8_t* data, std::size_t size) {
    constexpr std::uint32_t kMod = 65521U;
    std::uint32_t a = 1U;
    std::uint32_t b = 0U;
    for (std::size_t i = 0U; i < size; ++i) {
        a = (a + data[i]) % kMod;
        b = (b + a) % kMod;
    }
    return (b << 16U) | a;
}

std::vector<std::uint8_t> encode_png(const RgbImage& image) {
    if (image.width < 1 || image.height < 1 ||
        image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3U) {
        return {};
    }
    const auto w = static_cast<std::uint32_t>(image.width);
    const auto h = static_cast<std::uint32_t>(image.height);
    // Raw scanlines: filter byte 0, then the row's RGB bytes.
    const std::size_t row_bytes = static_cast<std::size_t>(w) * 3U;
    std::vector<std::uint8_t> raw;
    raw.reserve((row_bytes + 1U) * h);
    for (std::uint32_t y = 0U; y < h; ++y) {
        raw.push_back(0U);
        const auto* row = image.rgb.data() + static_cast<std::size_t>(y) * row_bytes;
        raw.insert(raw.end(), row, row + row_bytes);
    }
    // zlib stream: CMF/FLG (deflate, 32 KiB window, no dictionary, check
    // bits so that (CMF * 256 + FLG) % 31 == 0), stored blocks of at most
    // 65535 bytes, Adler-32 of the raw data.
    std::vector<std::uint8_t> z;
    z.reserve(raw.size() + raw.size() / 65535U * 5U + 16U);
    z.push_back(0x78U);
    z.push_back(0x01U);
    std::size_t pos = 0U;
    do {
        const std::size_t n = raw.size() - pos < 65535U ? raw.size() - pos : 65535U;
        const bool last = pos + n == raw.size();
        z.push_back(last ? 1U : 0U);  // BFINAL, BTYPE 00 (stored)
        const auto len = static_cast<std::uint16_t>(n);
        const auto nlen = static_cast<std::uint16_t>(~len);
        z.push_back(static_cast<std::uint8_t>(len & 0xFFU));
        z.push_back(static_cast<std::uint8_t>(len >> 8U));
        z.push_back(static_cast<std::uint8_t>(nlen & 0xFFU));
        z.push_back(static_cast<std::uint8_t>(nlen >> 8U));
        z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos),
                 raw.begin() + static_cast<std::ptrdiff_t>(pos + n));
        pos += n;
    } while (pos < raw.size());
    put_u32(z, adler32(raw.data(), raw.size()));

    std::vector<std::uint8_t> png = {0x89U, 'P', 'N', 'G', '\r', '\n', 0x1AU, '\n'};
    std::vector<std::uint8_t> ihdr;
    put_u32(ihdr, w);
    put_u32(ihdr, h);
    ihdr.push_back(8U);  // bit depth
    ihdr.push_back(2U);  // colour type: RGB
    ihdr.push_back(0U);  // compression: deflate
    ihdr.push_back(0U);  // filter method 0
    ihdr.push_back(0U);  // no interlace
    put_chunk(png, "IHDR", ihdr);
    put_chunk(png, "IDAT", z);
    put_chunk(png, "IEND", {});
    return png;
}

bool write_png(const std::string& path, const RgbImage& image, std::string& error) {
    const std::vector<std::uint8_t> png = encode_png(image);
    if (png.empty()) {
        error = "invalid image size";
        return false;
    }
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        error = path + ": " + std::strerror(errno);
        return false;
    }
    const bool ok = std::fwrite(png.data(), 1U, png.size(), f) == png.size();
    const bool closed = std::fclose(f) == 0;
    if (!ok || !closed) {
        error = path + ": write failed";
        return false;
    }
    return true;
}

}  // namespace cellguard::monitor
