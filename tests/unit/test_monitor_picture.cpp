// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the monitor's configuration picture (apps/monitor: png.hpp,
// picture.hpp): the PNG writer's files read back with libpng (its reader
// checks the signature, every chunk's CRC-32 and the zlib stream's
// Adler-32) to the image written, and libpng's refusals are error results;
// the zones are drawn where they are, in the top view and in the sensor
// view; the background is grey.
#include <doctest/doctest.h>
#include <png.h>

#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/io/png.hpp"
#include "cellguard/monitor/picture.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;
using cellguard::host::IndexedImage;

namespace {

/// A PNG as libpng reads it.
struct Decoded {
    bool ok = false;
    std::string error;  // libpng's message when not ok
    std::uint32_t width = 0U;
    std::uint32_t height = 0U;
    int bit_depth = 0;
    int colour = -1;  // IHDR colour type
    int interlace = -1;
    std::vector<std::uint8_t> rgb;      // RGB bytes, or palette indices when indexed
    std::vector<std::uint8_t> palette;  // PLTE, when present
    std::size_t unread = 0U;            // bytes after IEND
};

/// The input and the first error, shared with libpng's callbacks.
struct ReadState {
    const std::vector<std::uint8_t>* png = nullptr;
    std::size_t at = 0U;
    char error[160] = {};
};

void read_error(png_structp png, png_const_charp message) {
    auto* state = static_cast<ReadState*>(png_get_error_ptr(png));
    std::snprintf(state->error, sizeof(state->error), "%s", message);
    png_longjmp(png, 1);
}

void read_warning(png_structp /*png*/, png_const_charp /*message*/) {}

void read_bytes(png_structp png, png_bytep out, png_size_t size) {
    auto* state = static_cast<ReadState*>(png_get_io_ptr(png));
    if (size > state->png->size() - state->at) {
        png_error(png, "read past the end of the file");
    }
    std::memcpy(out, state->png->data() + state->at, size);
    state->at += size;
}

/// Reads @p state's PNG into @p d with libpng; false on any error libpng
/// raises (a longjmp back here; @p d lives in the caller's frame).
bool read_png(ReadState& state, Decoded& d) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, read_error, read_warning);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        return false;
    }
    if (setjmp(png_jmpbuf(png)) != 0) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_set_read_fn(png, &state, read_bytes);
    png_read_info(png, info);
    d.width = png_get_image_width(png, info);
    d.height = png_get_image_height(png, info);
    d.bit_depth = png_get_bit_depth(png, info);
    d.colour = png_get_color_type(png, info);
    d.interlace = png_get_interlace_type(png, info);
    png_colorp palette = nullptr;
    int entries = 0;
    if (png_get_PLTE(png, info, &palette, &entries) != 0U) {
        for (int i = 0; i < entries; ++i) {
            d.palette.insert(d.palette.end(), {palette[i].red, palette[i].green, palette[i].blue});
        }
    }
    const std::size_t row = png_get_rowbytes(png, info);
    d.rgb.resize(row * d.height);
    for (std::uint32_t y = 0U; y < d.height; ++y) {
        png_read_row(png, d.rgb.data() + y * row, nullptr);
    }
    png_read_end(png, nullptr);  // the chunks after the image data, IEND, their CRCs
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

/// @p png decoded by libpng: 8 bits per sample, RGB or indexed, no interlace
/// and nothing after IEND, else not ok.
Decoded decode(const std::vector<std::uint8_t>& png) {
    Decoded d;
    ReadState state;
    state.png = &png;
    d.ok = read_png(state, d);
    d.error = state.error;
    d.unread = png.size() - state.at;
    CHECK_MESSAGE(d.ok, d.error);
    CHECK(d.bit_depth == 8);
    CHECK((d.colour == PNG_COLOR_TYPE_RGB || d.colour == PNG_COLOR_TYPE_PALETTE));
    CHECK(d.interlace == PNG_INTERLACE_NONE);
    CHECK(d.unread == 0U);
    return d;
}

bool reddish(const RgbImage& img, int x, int y) {
    const std::size_t o = img.offset(x, y);
    return img.rgb[o] > img.rgb[o + 1U] + 60 && img.rgb[o] > img.rgb[o + 2U] + 60;
}

bool yellowish(const RgbImage& img, int x, int y) {
    const std::size_t o = img.offset(x, y);
    return img.rgb[o] > img.rgb[o + 2U] + 60 && img.rgb[o + 1U] > img.rgb[o + 2U] + 40;
}

bool neutral(const RgbImage& img, int x, int y) {
    const std::size_t o = img.offset(x, y);
    const int r = img.rgb[o];
    const int g = img.rgb[o + 1U];
    const int b = img.rgb[o + 2U];
    return std::abs(r - g) < 8 && std::abs(g - b) < 8;
}

int grey_level(const RgbImage& img, int x, int y) { return img.rgb[img.offset(x, y)]; }

}  // namespace

// verifies: SR-SYS-001
TEST_CASE("png: a small image encodes to a valid PNG that decodes to the same pixels") {
    RgbImage img = RgbImage::filled(3, 2, 10, 20, 30);
    img.rgb[img.offset(2, 1)] = 255U;
    const std::vector<std::uint8_t> png = encode_png(img);
    const Decoded d = decode(png);
    REQUIRE(d.ok);
    CHECK(d.colour == PNG_COLOR_TYPE_RGB);
    CHECK(d.width == 3U);
    CHECK(d.height == 2U);
    CHECK(d.rgb == img.rgb);
    // The reader is strict: a flipped bit in the last chunk (IEND's CRC) and a cut file are refused.
    std::vector<std::uint8_t> bad = png;
    bad.back() ^= 1U;
    ReadState state;
    state.png = &bad;
    Decoded refused;
    CHECK_FALSE(read_png(state, refused));
    CHECK(std::string(state.error).find("CRC") != std::string::npos);
    bad.assign(png.begin(), png.end() - 20);
    ReadState cut;
    cut.png = &bad;
    CHECK_FALSE(read_png(cut, refused));
}

// verifies: SR-SYS-001
TEST_CASE("png: a large image is compressed and decodes to the same pixels, bad sizes are refused") {
    RgbImage img = RgbImage::filled(300, 200, 0, 0, 0);
    for (std::size_t i = 0U; i < img.rgb.size(); ++i) {
        img.rgb[i] = static_cast<std::uint8_t>(i * 7U);
    }
    const std::vector<std::uint8_t> png = encode_png(img);
    CHECK(png.size() < img.rgb.size() / 10U);
    const Decoded d = decode(png);
    REQUIRE(d.ok);
    CHECK(d.rgb == img.rgb);
    RgbImage bad = img;
    bad.rgb.pop_back();
    CHECK(encode_png(bad).empty());
    CHECK(encode_png(RgbImage{}).empty());
    std::string error;
    CHECK_FALSE(write_png("/nonexistent-dir/x.png", img, error));
    CHECK(error.find("/nonexistent-dir/x.png") != std::string::npos);
    // Wider than libpng writes (1,000,000 columns): libpng's error is an error result, not a crash.
    const RgbImage too_wide = RgbImage::filled(1000001, 1, 1, 2, 3);
    CHECK(encode_png(too_wide).empty());
    error.clear();
    CHECK_FALSE(write_png("/nonexistent-dir/x.png", too_wide, error));
    CHECK(error.rfind("PNG: ", 0U) == 0U);
    // The writer's state is per call: the next image after a refused one is written whole.
    CHECK(decode(encode_png(img)).rgb == img.rgb);
}

// verifies: SR-SYS-001
TEST_CASE("png: an indexed image encodes with its palette and decodes to the same indices, bad ones are refused") {
    IndexedImage img;
    img.width = 7;
    img.height = 5;
    img.palette = {{{0U, 0U, 0U}}, {{200U, 30U, 30U}}, {{128U, 128U, 128U}}};
    for (int i = 0; i < img.width * img.height; ++i) {
        img.pixels.push_back(static_cast<std::uint8_t>(i / 4 % 3));
    }
    const Decoded d = decode(encode_png(img));
    REQUIRE(d.ok);
    CHECK(d.colour == PNG_COLOR_TYPE_PALETTE);
    CHECK(d.width == 7U);
    CHECK(d.height == 5U);
    CHECK(d.rgb == img.pixels);
    CHECK(d.palette == std::vector<std::uint8_t>{0U, 0U, 0U, 200U, 30U, 30U, 128U, 128U, 128U});
    IndexedImage bad = img;
    bad.pixels[3] = 3U;  // beyond the palette
    CHECK(encode_png(bad).empty());
    bad = img;
    bad.palette.clear();
    CHECK(encode_png(bad).empty());
    std::string error;
    CHECK_FALSE(host::write_png("/nonexistent-dir/x.png", img, error));
    CHECK(error.find("/nonexistent-dir/x.png") != std::string::npos);
}

// verifies: SR-SYS-001
TEST_CASE("picture: zones and background are drawn where they are, from above and from the sensor") {
    // A 2 m x 1.6 m x 1 m grid of 10 cm voxels; a protective box, a warning
    // prism; a background block (never foreground) in one corner.
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(0.0, 0.0, 0.0), 0.1, GridDims{20, 16, 10}).value();
    std::vector<ZoneConfig> zc(2);
    zc[0].kind = ZoneKind::kProtective;
    zc[0].shape = ZoneShape::kBox;
    zc[0].box_min = Eigen::Vector3d(0.2, 0.2, 0.0);
    zc[0].box_max = Eigen::Vector3d(0.6, 0.6, 0.8);
    zc[1].kind = ZoneKind::kWarning;
    zc[1].shape = ZoneShape::kPrism;
    zc[1].polygon[0] = PolygonVertex{1.2, 0.9};
    zc[1].polygon[1] = PolygonVertex{1.8, 0.9};
    zc[1].polygon[2] = PolygonVertex{1.8, 1.5};
    zc[1].polygon_size = 3U;
    zc[1].z_min = 0.0;
    zc[1].z_max = 0.5;
    std::vector<std::uint32_t> mask(g.voxel_count());
    const CompiledZones zones = CompiledZones::compile(g, {zc.data(), zc.size()}, {mask.data(), mask.size()}).value();
    std::vector<std::int16_t> prior(g.voxel_count(), -200);
    for (int z = 0; z < 5; ++z) {
        for (int y = 12; y < 16; ++y) {
            for (int x = 0; x < 4; ++x) {
                prior[g.index_of(VoxelCoord{x, y, z})] = kNeverForeground;
            }
        }
    }
    PictureInput in;
    in.title = "test";
    in.grid = g;
    in.zones = &zones;
    in.zone_names = {"press", "aisle"};
    in.prior = {prior.data(), prior.size()};
    // A camera 3 m above the grid's centre looking straight down: x right = world x, y down = world -y.
    PictureSensor cam;
    cam.name = "overhead";
    Eigen::Matrix3d r;
    r.col(0) = Eigen::Vector3d(1.0, 0.0, 0.0);
    r.col(1) = Eigen::Vector3d(0.0, -1.0, 0.0);
    r.col(2) = Eigen::Vector3d(0.0, 0.0, -1.0);
    cam.pose.linear() = r;
    cam.pose.translation() = Eigen::Vector3d(1.0, 0.8, 3.0);
    cam.intrinsics = PinholeIntrinsics{200.0, 200.0, 79.5, 59.5, 160, 120};
    cam.max_range = 10.0;
    in.sensors = {cam};
    PictureLayout layout;
    const RgbImage img = render_config_picture(in, &layout);
    REQUIRE(img.width > 0);
    CHECK(layout.voxel_px >= 8);

    // Top view: the centre of each zone's footprint has its colour; a free
    // column is white; the background corner is grey.
    int px = 0;
    int py = 0;
    top_view_pixel(layout, g, 3, 3, px, py);  // inside the protective box (voxels 2..5)
    CHECK(reddish(img, px, py));
    top_view_pixel(layout, g, 16, 11, px, py);  // inside the warning triangle
    CHECK(yellowish(img, px, py));
    CHECK_FALSE(reddish(img, px, py));
    top_view_pixel(layout, g, 10, 4, px, py);  // no zone, no background
    CHECK(neutral(img, px, py));
    CHECK(grey_level(img, px, py) > 240);
    top_view_pixel(layout, g, 1, 14, px, py);  // background block
    CHECK(neutral(img, px, py));
    CHECK(grey_level(img, px, py) < 220);
    // Red exactly in the protective footprint's columns (2..5 x 2..5).
    for (int iy = 0; iy < 16; ++iy) {
        for (int ix = 0; ix < 20; ++ix) {
            top_view_pixel(layout, g, ix, iy, px, py);
            const bool in_box = ix >= 2 && ix <= 5 && iy >= 2 && iy <= 5;
            if (ix == 4 && iy == 4) {
                continue;  // the zone's number is written here, on white
            }
            CHECK_MESSAGE(reddish(img, px, py) == in_box, ix << "," << iy);
        }
    }

    // Sensor view: the protective box's centre projects onto a red pixel.
    const Eigen::Vector3d c = cam.pose.inverse() * Eigen::Vector3d(0.4, 0.4, 0.4);
    const double u = 200.0 * c.x() / c.z() + 79.5;
    const double v = 200.0 * c.y() / c.z() + 59.5;
    const int vx = layout.view_x + static_cast<int>((u + 0.5) * layout.view_scale);
    const int vy = layout.view_y + static_cast<int>((v + 0.5) * layout.view_scale);
    CHECK(reddish(img, vx, vy));
    const Eigen::Vector3d f = cam.pose.inverse() * Eigen::Vector3d(1.0, 0.4, 0.4);  // free space
    const int fx = layout.view_x + static_cast<int>((200.0 * f.x() / f.z() + 80.0) * layout.view_scale);
    const int fy = layout.view_y + static_cast<int>((200.0 * f.y() / f.z() + 60.0) * layout.view_scale);
    CHECK(neutral(img, fx, fy));
    CHECK(grey_level(img, fx, fy) > 240);

    // And the file round-trips.
    const Decoded d = decode(encode_png(img));
    REQUIRE(d.ok);
    CHECK(d.width == static_cast<std::uint32_t>(img.width));
    CHECK(d.rgb == img.rgb);
}

// verifies: SR-SYS-001
TEST_CASE("picture: the font draws printable ASCII and advances six pixels a character") {
    RgbImage img = RgbImage::filled(200, 20, 255, 255, 255);
    CHECK(draw_text(img, 2, 2, "Az09", PictureColour{0, 0, 0}, 1) == 2 + 4 * 6);
    int dark = 0;
    for (std::size_t i = 0U; i < img.rgb.size(); i += 3U) {
        dark += img.rgb[i] == 0U ? 1 : 0;
    }
    CHECK(dark > 20);
}
