// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// PNG writer on libpng: the image is written into memory, then to the file.
// libpng reports an error by calling the error function, which must not
// return: it copies the message and longjmps back to write_with_libpng(),
// which destroys libpng's state and returns false. No object with a
// destructor lives only between the setjmp and a jump (in
// write_with_libpng() after the setjmp, or in the callbacks), so the jump
// skips no destructor.
#include "cellguard/host/io/png.hpp"

#include "cellguard/host/io/file.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>

namespace cellguard::host {
namespace {

/// What the callbacks share with encode(): the output and the first error.
struct WriteState {
    std::vector<std::uint8_t>* out = nullptr;
    char error[160] = {};
};

void on_error(png_structp png, png_const_charp message) {
    auto* state = static_cast<WriteState*>(png_get_error_ptr(png));
    static_cast<void>(std::snprintf(state->error, sizeof(state->error), "%s", message));
    png_longjmp(png, 1);
}

void on_warning(png_structp /*png*/, png_const_charp /*message*/) {}

void on_write(png_structp png, png_bytep data, png_size_t size) {
    auto* state = static_cast<WriteState*>(png_get_io_ptr(png));
    bool stored = true;
    try {
        state->out->insert(state->out->end(), data, data + size);
    } catch (const std::bad_alloc&) {
        stored = false;
    }
    if (!stored) {
        png_error(png, "out of memory");  // outside the handler: longjmp leaves no exception behind
    }
}

void on_flush(png_structp /*png*/) {}

/// The pixels and header fields encode() writes.
struct Pixels {
    int width = 0;
    int height = 0;
    int colour_type = PNG_COLOR_TYPE_RGB;
    std::size_t row_bytes = 0U;
    const std::uint8_t* data = nullptr;
    png_color palette[256] = {};
    int palette_size = 0;
};

/// Appends the PNG file of @p p to @p state.out; false with @p state.error
/// set when libpng refuses the image or runs out of memory. 8 bits per
/// sample, no interlace, per row filter None or Up (libpng picks), zlib's
/// default level. @p state lives in the caller's frame: the jump back to the
/// setjmp below leaves it determinate.
bool write_with_libpng(const Pixels& p, WriteState& state) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, on_error, on_warning);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        static_cast<void>(std::snprintf(state.error, sizeof(state.error), "%s", "out of memory"));
        return false;
    }
    if (setjmp(png_jmpbuf(png)) != 0) {  // NOLINT(cert-err52-cpp): libpng's error handling
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &state, on_write, on_flush);
    png_set_IHDR(png, info, static_cast<png_uint_32>(p.width), static_cast<png_uint_32>(p.height), 8, p.colour_type,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (p.palette_size > 0) {
        png_set_PLTE(png, info, p.palette, p.palette_size);
    }
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE | PNG_FILTER_UP);
    png_write_info(png, info);
    for (int y = 0; y < p.height; ++y) {
        png_write_row(png, p.data + static_cast<std::size_t>(y) * p.row_bytes);
    }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

/// Appends the PNG file of @p p to @p out; false with @p error set ("PNG: "
/// and libpng's message).
bool encode(const Pixels& p, std::vector<std::uint8_t>& out, std::string& error) {
    WriteState state;
    state.out = &out;
    if (!write_with_libpng(p, state)) {
        error = std::string("PNG: ") + state.error;
        return false;
    }
    return true;
}

bool valid_size(int width, int height, std::size_t bytes, std::size_t bytes_per_pixel) {
    return width >= 1 && height >= 1 &&
           bytes == static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * bytes_per_pixel;
}

/// The PNG of @p image in @p out; false with @p error set.
bool encode_rgb(const RgbImage& image, std::vector<std::uint8_t>& out, std::string& error) {
    if (!valid_size(image.width, image.height, image.rgb.size(), 3U)) {
        error = "invalid image size";
        return false;
    }
    Pixels p;
    p.width = image.width;
    p.height = image.height;
    p.row_bytes = static_cast<std::size_t>(image.width) * 3U;
    p.data = image.rgb.data();
    return encode(p, out, error);
}

/// The PNG of @p image in @p out; false with @p error set.
bool encode_indexed(const IndexedImage& image, std::vector<std::uint8_t>& out, std::string& error) {
    if (!valid_size(image.width, image.height, image.pixels.size(), 1U) || image.palette.empty() ||
        image.palette.size() > 256U) {
        error = "invalid image size or palette";
        return false;
    }
    for (const std::uint8_t index : image.pixels) {
        if (index >= image.palette.size()) {
            error = "a pixel's index is beyond the palette";
            return false;
        }
    }
    Pixels p;
    p.width = image.width;
    p.height = image.height;
    p.colour_type = PNG_COLOR_TYPE_PALETTE;
    p.row_bytes = static_cast<std::size_t>(image.width);
    p.data = image.pixels.data();
    for (std::size_t i = 0U; i < image.palette.size(); ++i) {
        p.palette[i] = png_color{image.palette[i][0], image.palette[i][1], image.palette[i][2]};
    }
    p.palette_size = static_cast<int>(image.palette.size());
    return encode(p, out, error);
}

bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& png, std::string& error) {
    FilePtr f = open_file(path.c_str(), "wb");
    if (!f) {
        error = path + ": " + std::strerror(errno);
        return false;
    }
    const bool ok = std::fwrite(png.data(), 1U, png.size(), f.get()) == png.size();
    const bool closed = close_file(f);
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

std::vector<std::uint8_t> encode_png(const RgbImage& image) {
    std::vector<std::uint8_t> png;
    std::string error;
    return encode_rgb(image, png, error) ? png : std::vector<std::uint8_t>{};
}

std::vector<std::uint8_t> encode_png(const IndexedImage& image) {
    std::vector<std::uint8_t> png;
    std::string error;
    return encode_indexed(image, png, error) ? png : std::vector<std::uint8_t>{};
}

bool write_png(const std::string& path, const RgbImage& image, std::string& error) {
    std::vector<std::uint8_t> png;
    return encode_rgb(image, png, error) && write_bytes(path, png, error);
}

bool write_png(const std::string& path, const IndexedImage& image, std::string& error) {
    std::vector<std::uint8_t> png;
    return encode_indexed(image, png, error) && write_bytes(path, png, error);
}

}  // namespace cellguard::host
