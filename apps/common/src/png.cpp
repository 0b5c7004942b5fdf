// PNG writer: per-row None/Up filter, fixed-Huffman deflate with run-length
// matches, Adler-32, CRC-32 per chunk.
#include "cellguard/host/png.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "cellguard/crc32.hpp"

namespace cellguard::host {
namespace {

/// Deflate bit writer: bits go LSB first; Huffman codes are emitted MSB first.
class BitWriter {
public:
    void bits(std::uint32_t value, int count) {
        for (int i = 0; i < count; ++i) {
            put((value >> static_cast<unsigned>(i)) & 1U);
        }
    }
    void code(std::uint32_t value, int count) {
        for (int i = count - 1; i >= 0; --i) {
            put((value >> static_cast<unsigned>(i)) & 1U);
        }
    }
    std::vector<std::uint8_t> finish() {
        if (used_ > 0) {
            out_.push_back(current_);
        }
        return out_;
    }

private:
    void put(std::uint32_t bit) {
        current_ = static_cast<std::uint8_t>(current_ | (bit << static_cast<unsigned>(used_)));
        if (++used_ == 8) {
            out_.push_back(current_);
            current_ = 0U;
            used_ = 0;
        }
    }
    std::vector<std::uint8_t> out_;
    std::uint8_t current_ = 0U;
    int used_ = 0;
};

void literal_or_length(BitWriter& w, std::uint32_t symbol) {
    if (symbol <= 143U) {
        w.code(0x30U + symbol, 8);
    } else if (symbol <= 255U) {
        w.code(0x190U + (symbol - 144U), 9);
    } else if (symbol <= 279U) {
        w.code(symbol - 256U, 7);
    } else {
        w.code(0xC0U + (symbol - 280U), 8);
    }
}

/// A match of @p length (3..258) at @p distance (1..4, codes 0..3 have no extra bits).
void match(BitWriter& w, std::uint32_t length, std::uint32_t distance) {
    static const std::uint32_t base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                           31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static const int extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    std::uint32_t code = 28U;
    while (base[code] > length) {
        --code;
    }
    literal_or_length(w, 257U + code);
    w.bits(length - base[code], extra[code]);
    w.code(distance - 1U, 5);
}

/// One final fixed-Huffman block of @p data, repeats at @p distance as matches.
std::vector<std::uint8_t> deflate_fixed(const std::vector<std::uint8_t>& data, std::size_t distance) {
    BitWriter w;
    w.bits(1U, 1);  // final block
    w.bits(1U, 2);  // fixed Huffman codes
    std::size_t i = 0;
    while (i < data.size()) {
        std::size_t run = 0;
        if (i >= distance) {
            while (i + run < data.size() && run < 258U && data[i + run] == data[i + run - distance]) {
                ++run;
            }
        }
        if (run >= 3U) {
            match(w, static_cast<std::uint32_t>(run), static_cast<std::uint32_t>(distance));
            i += run;
        } else {
            literal_or_length(w, data[i]);
            ++i;
        }
    }
    literal_or_length(w, 256U);  // end of block
    return w.finish();
}

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

std::size_t transitions(const std::vector<std::uint8_t>& row) {
    std::size_t n = 0;
    for (std::size_t i = 1; i < row.size(); ++i) {
        n += row[i] != row[i - 1U] ? 1U : 0U;
    }
    return n;
}

bool valid_size(int width, int height, std::size_t bytes, std::size_t bytes_per_pixel) {
    return width >= 1 && height >= 1 &&
           bytes == static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * bytes_per_pixel;
}

/// The PNG file of @p pixels (@p bytes_per_pixel bytes each, row-major) with
/// IHDR colour type @p colour_type and, when not empty, the PLTE @p palette.
std::vector<std::uint8_t> encode(int width, int height, std::uint8_t colour_type, std::size_t bytes_per_pixel,
                                 const std::vector<std::uint8_t>& pixels, const std::vector<std::uint8_t>& palette) {
    const std::size_t row_bytes = static_cast<std::size_t>(width) * bytes_per_pixel;
    const auto h = static_cast<std::size_t>(height);
    // Filtered scanlines: per row None or Up, whichever has fewer value changes.
    std::vector<std::uint8_t> raw;
    raw.reserve(h * (row_bytes + 1U));
    std::vector<std::uint8_t> none(row_bytes);
    std::vector<std::uint8_t> up(row_bytes);
    for (std::size_t y = 0; y < h; ++y) {
        for (std::size_t x = 0; x < row_bytes; ++x) {
            const std::uint8_t v = pixels[y * row_bytes + x];
            const std::uint8_t above = y > 0U ? pixels[(y - 1U) * row_bytes + x] : std::uint8_t{0U};
            none[x] = v;
            up[x] = static_cast<std::uint8_t>(v - above);
        }
        const bool use_up = transitions(up) < transitions(none);
        raw.push_back(use_up ? 2U : 0U);
        const std::vector<std::uint8_t>& row = use_up ? up : none;
        raw.insert(raw.end(), row.begin(), row.end());
    }
    // zlib stream: CMF/FLG (deflate, 32 KiB window, no dictionary, check
    // bits so that (CMF * 256 + FLG) % 31 == 0), the block, Adler-32.
    std::vector<std::uint8_t> z = {0x78U, 0x01U};
    const std::vector<std::uint8_t> deflated = deflate_fixed(raw, bytes_per_pixel);
    z.insert(z.end(), deflated.begin(), deflated.end());
    put_u32(z, adler32(raw.data(), raw.size()));

    std::vector<std::uint8_t> png = {0x89U, 'P', 'N', 'G', '\r', '\n', 0x1AU, '\n'};
    std::vector<std::uint8_t> ihdr;
    put_u32(ihdr, static_cast<std::uint32_t>(width));
    put_u32(ihdr, static_cast<std::uint32_t>(height));
    ihdr.push_back(8U);  // bit depth
    ihdr.push_back(colour_type);
    ihdr.push_back(0U);  // compression: deflate
    ihdr.push_back(0U);  // filter method 0 (adaptive)
    ihdr.push_back(0U);  // no interlace
    put_chunk(png, "IHDR", ihdr);
    if (!palette.empty()) {
        put_chunk(png, "PLTE", palette);
    }
    put_chunk(png, "IDAT", z);
    put_chunk(png, "IEND", {});
    return png;
}

bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& png, std::string& error) {
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
    if (!valid_size(image.width, image.height, image.rgb.size(), 3U)) {
        return {};
    }
    return encode(image.width, image.height, 2U, 3U, image.rgb, {});
}

std::vector<std::uint8_t> encode_png(const IndexedImage& image) {
    if (!valid_size(image.width, image.height, image.pixels.size(), 1U) || image.palette.empty() ||
        image.palette.size() > 256U) {
        return {};
    }
    std::vector<std::uint8_t> plte;
    for (const auto& c : image.palette) {
        plte.insert(plte.end(), c.begin(), c.end());
    }
    for (const std::uint8_t index : image.pixels) {
        if (index >= image.palette.size()) {
            return {};
        }
    }
    return encode(image.width, image.height, 3U, 1U, image.pixels, plte);
}

bool write_png(const std::string& path, const RgbImage& image, std::string& error) {
    return write_bytes(path, encode_png(image), error);
}

bool write_png(const std::string& path, const IndexedImage& image, std::string& error) {
    return write_bytes(path, encode_png(image), error);
}

}  // namespace cellguard::host
