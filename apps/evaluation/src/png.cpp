#include "png.hpp"

#include <cstddef>
#include <cstdio>

namespace cellguard::eval {

namespace {

std::uint32_t crc32_of(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0xFFFFFFFFU) {
    static std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256U; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) {
                c = (c & 1U) != 0U ? 0xEDB88320U ^ (c >> 1U) : c >> 1U;
            }
            t[i] = c;
        }
        return t;
    }();
    for (std::size_t i = 0; i < n; ++i) {
        crc = table[(crc ^ data[i]) & 0xFFU] ^ (crc >> 8U);
    }
    return crc;
}

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

void match(BitWriter& w, std::uint32_t length) {  // distance 1, length 3..258
    static const std::uint32_t base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                           31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static const int extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    std::uint32_t code = 28U;
    while (base[code] > length) {
        --code;
    }
    literal_or_length(w, 257U + code);
    w.bits(length - base[code], extra[code]);
    w.code(0U, 5);  // distance code 0: distance 1
}

std::vector<std::uint8_t> deflate_fixed(const std::vector<std::uint8_t>& data) {
    BitWriter w;
    w.bits(1U, 1);  // final block
    w.bits(1U, 2);  // fixed Huffman codes
    std::size_t i = 0;
    while (i < data.size()) {
        std::size_t run = 0;
        if (i > 0U) {
            while (i + run < data.size() && run < 258U && data[i + run] == data[i - 1U]) {
                ++run;
            }
        }
        if (run >= 3U) {
            match(w, static_cast<std::uint32_t>(run));
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

void chunk(std::vector<std::uint8_t>& out, const char* type, const std::vector<std::uint8_t>& body) {
    put_u32(out, static_cast<std::uint32_t>(body.size()));
    const std::size_t start = out.size();
    for (int i = 0; i < 4; ++i) {
        out.push_back(static_cast<std::uint8_t>(type[i]));
    }
    out.insert(out.end(), body.begin(), body.end());
    put_u32(out, crc32_of(out.data() + start, out.size() - start) ^ 0xFFFFFFFFU);
}

std::size_t transitions(const std::vector<std::uint8_t>& row) {
    std::size_t n = 0;
    for (std::size_t i = 1; i < row.size(); ++i) {
        n += row[i] != row[i - 1U] ? 1U : 0U;
    }
    return n;
}

}  // namespace

std::vector<std::uint8_t> encode_png(const IndexedImage& image) {
    const auto w = static_cast<std::size_t>(image.width);
    const auto h = static_cast<std::size_t>(image.height);
    // Filtered scanlines: per row None or Up, whichever has fewer value changes.
    std::vector<std::uint8_t> raw;
    raw.reserve(h * (w + 1U));
    std::vector<std::uint8_t> none(w);
    std::vector<std::uint8_t> up(w);
    for (std::size_t y = 0; y < h; ++y) {
        for (std::size_t x = 0; x < w; ++x) {
            const std::uint8_t v = image.pixels[y * w + x];
            const std::uint8_t above = y > 0U ? image.pixels[(y - 1U) * w + x] : std::uint8_t{0U};
            none[x] = v;
            up[x] = static_cast<std::uint8_t>(v - above);
        }
        const bool use_up = transitions(up) < transitions(none);
        raw.push_back(use_up ? 2U : 0U);
        const std::vector<std::uint8_t>& row = use_up ? up : none;
        raw.insert(raw.end(), row.begin(), row.end());
    }
    std::vector<std::uint8_t> z = {0x78U, 0x01U};
    const std::vector<std::uint8_t> deflated = deflate_fixed(raw);
    z.insert(z.end(), deflated.begin(), deflated.end());
    std::uint32_t a = 1U;
    std::uint32_t b = 0U;
    for (const std::uint8_t v : raw) {
        a = (a + v) % 65521U;
        b = (b + a) % 65521U;
    }
    put_u32(z, (b << 16U) | a);

    std::vector<std::uint8_t> out = {0x89U, 'P', 'N', 'G', 0x0DU, 0x0AU, 0x1AU, 0x0AU};
    std::vector<std::uint8_t> ihdr;
    put_u32(ihdr, static_cast<std::uint32_t>(image.width));
    put_u32(ihdr, static_cast<std::uint32_t>(image.height));
    ihdr.push_back(8U);  // bit depth
    ihdr.push_back(3U);  // indexed colour
    ihdr.push_back(0U);  // deflate
    ihdr.push_back(0U);  // adaptive filtering
    ihdr.push_back(0U);  // no interlace
    chunk(out, "IHDR", ihdr);
    std::vector<std::uint8_t> plte;
    for (const auto& c : image.palette) {
        plte.insert(plte.end(), c.begin(), c.end());
    }
    chunk(out, "PLTE", plte);
    chunk(out, "IDAT", z);
    chunk(out, "IEND", {});
    return out;
}

bool write_png(const std::string& path, const IndexedImage& image) {
    const std::vector<std::uint8_t> bytes = encode_png(image);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        return false;
    }
    const bool ok = std::fwrite(bytes.data(), 1U, bytes.size(), f) == bytes.size();
    return std::fclose(f) == 0 && ok;
}

}  // namespace cellguard::eval
