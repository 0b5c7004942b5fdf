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

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/io/png.hpp"
#include "cellguard/monitor/picture.hpp"
#include "test_robot.hpp"

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

namespace {

bool bluish(const RgbImage& img, int x, int y) {
    const std::size_t o = img.offset(x, y);
    return img.rgb[o + 2U] > img.rgb[o] + 60 && img.rgb[o + 2U] > img.rgb[o + 1U] + 40;
}

bool has_colour(const RgbImage& img, int x, int y, PictureColour c) {
    const std::size_t o = img.offset(x, y);
    return img.rgb[o] == c.r && img.rgb[o + 1U] == c.g && img.rgb[o + 2U] == c.b;
}

/// The decoded PNG of @p img as an image (the checks below read what the file holds).
RgbImage png_round_trip(const RgbImage& img) {
    const Decoded d = decode(encode_png(img));
    REQUIRE(d.ok);
    REQUIRE(d.colour == PNG_COLOR_TYPE_RGB);
    return RgbImage{static_cast<int>(d.width), static_cast<int>(d.height), d.rgb};
}

PlacedCapsule capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) {
    PlacedCapsule c;
    for (int i = 0; i < 3; ++i) {
        c.a[i] = a[i];
        c.b[i] = b[i];
    }
    c.radius = r;
    return c;
}

double segment_distance(const Eigen::Vector3d& p, const PlacedCapsule& c) {
    const Eigen::Vector3d a(c.a[0], c.a[1], c.a[2]);
    const Eigen::Vector3d ab = Eigen::Vector3d(c.b[0], c.b[1], c.b[2]) - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - a - t * ab).norm();
}

/// The smallest distance from the floor point (x, y) to the capsules' surfaces, projected onto the floor.
double floor_distance(const RobotPose& pose, double x, double y) {
    double d = 1e9;
    for (std::uint8_t i = 0U; i < pose.count; ++i) {
        PlacedCapsule flat = pose.capsules[i];
        flat.a[2] = 0.0;
        flat.b[2] = 0.0;
        d = std::min(d, segment_distance(Eigen::Vector3d(x, y, 0.0), flat) - flat.radius);
    }
    return d;
}

/// The smallest distance from the ray o + t d (0.5 <= t <= 4 m, sampled every millimetre) to the capsules' surfaces.
double ray_distance(const RobotPose& pose, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    double best = 1e9;
    for (double t = 0.5; t < 4.0; t += 0.001) {
        for (std::uint8_t i = 0U; i < pose.count; ++i) {
            best = std::min(best, segment_distance(o + t * d, pose.capsules[i]) - pose.capsules[i].radius);
        }
    }
    return best;
}

/// A 4 m x 4 m x 2 m cell of 10 cm voxels with one protective zone, and a
/// camera 3 m above its centre looking straight down.
struct RobotPictureCell {
    GridGeometry g = GridGeometry::make(Eigen::Vector3d(-2.0, -2.0, 0.0), 0.1, GridDims{40, 40, 20}).value();
    std::vector<std::uint32_t> mask = std::vector<std::uint32_t>(g.voxel_count());
    std::vector<ZoneConfig> zc = std::vector<ZoneConfig>(1);
    CompiledZones zones;
    std::vector<std::int16_t> prior = std::vector<std::int16_t>(g.voxel_count(), -200);
    PictureRobot robot;
    PictureInput in;

    RobotPictureCell() {
        zc[0].kind = ZoneKind::kProtective;
        zc[0].shape = ZoneShape::kBox;
        zc[0].box_min = Eigen::Vector3d(0.5, -0.8, 0.0);
        zc[0].box_max = Eigen::Vector3d(1.0, -0.4, 1.0);
        zones = CompiledZones::compile(g, {zc.data(), zc.size()}, {mask.data(), mask.size()}).value();
        // A pillar at the origin (1 m, radius 0.1) and an arm from its top along +x (1 m, radius 0.08).
        robot.name = "test";
        robot.pose.count = 2U;
        robot.pose.capsules[0] = capsule({0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 0.1);
        robot.pose.capsules[1] = capsule({0.0, 0.0, 1.0}, {1.0, 0.0, 1.0}, 0.08);
        robot.pose_source = "all joints 0";
        robot.margin_m = 0.25;
        robot.rings = {PictureRing{1.2, "S_p speed class 0 (full)", "S_p0", PictureColour{200, 0, 200}}};
        in.title = "robot";
        in.grid = g;
        in.zones = &zones;
        in.zone_names = {"press"};
        in.prior = {prior.data(), prior.size()};
        PictureSensor cam;
        cam.name = "overhead";
        Eigen::Matrix3d r;
        r.col(0) = Eigen::Vector3d(1.0, 0.0, 0.0);
        r.col(1) = Eigen::Vector3d(0.0, -1.0, 0.0);
        r.col(2) = Eigen::Vector3d(0.0, 0.0, -1.0);
        cam.pose.linear() = r;
        cam.pose.translation() = Eigen::Vector3d(0.0, 0.0, 3.0);
        cam.intrinsics = PinholeIntrinsics{200.0, 200.0, 79.5, 59.5, 160, 120};
        in.sensors = {cam};
        in.robot = &robot;
    }
    RobotPictureCell(const RobotPictureCell&) = delete;
    RobotPictureCell& operator=(const RobotPictureCell&) = delete;
};

/// The direction of sensor-view picture pixel (px, py) (relative to the view's corner), as the picture casts it.
Eigen::Vector3d view_ray(const PictureSensor& s, const PictureLayout& layout, int px, int py) {
    const PinholeIntrinsics& k = s.intrinsics;
    const double u = (px + 0.5) / layout.view_scale - 0.5;
    const double v = (py + 0.5) / layout.view_scale - 0.5;
    return (s.pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0)).normalized();
}

/// The sensor-view picture pixel of world point @p p.
void view_pixel(const PictureSensor& s, const PictureLayout& layout, const Eigen::Vector3d& p, int& x, int& y) {
    const Eigen::Vector3d c = s.pose.inverse() * p;
    const PinholeIntrinsics& k = s.intrinsics;
    x = layout.view_x + static_cast<int>((k.fx * c.x() / c.z() + k.cx + 0.5) * layout.view_scale);
    y = layout.view_y + static_cast<int>((k.fy * c.y() / c.z() + k.cy + 0.5) * layout.view_scale);
}

}  // namespace

// verifies: SR-SYS-004
TEST_CASE("picture: the robot's capsules are drawn where they are, from above and from the sensor") {
    const RobotPictureCell cell;
    PictureLayout layout;
    const RgbImage img = png_round_trip(render_config_picture(cell.in, &layout));
    int px = 0;
    int py = 0;
    // Top view: voxel column centres on the pillar (0.05, 0.05) and on the arm (0.55, 0.05) are robot blue.
    top_view_pixel(layout, cell.g, 20, 20, px, py);
    CHECK(bluish(img, px, py));
    top_view_pixel(layout, cell.g, 25, 20, px, py);
    CHECK(bluish(img, px, py));
    top_view_pixel(layout, cell.g, 29, 20, px, py);  // (0.95, 0.05): the arm's end
    CHECK(bluish(img, px, py));
    // Beside the arm (0.55, 0.25), beyond its end (1.25, 0.05) and behind the pillar (-0.25, 0.05): free space.
    for (const std::pair<int, int>& at : {std::pair{25, 22}, std::pair{32, 20}, std::pair{17, 20}}) {
        const int ix = at.first;  // plain names: clang 14 cannot capture structured bindings in doctest's lambdas
        const int iy = at.second;
        top_view_pixel(layout, cell.g, ix, iy, px, py);
        CHECK_MESSAGE(!bluish(img, px, py), ix << "," << iy);
        CHECK_MESSAGE(neutral(img, px, py), ix << "," << iy);
    }
    // The arm's footprint edge: blue up to 0.08 m from its axis, not beyond (a pixel's margin).
    const double m = cell.g.voxel_size() / layout.voxel_px;
    top_view_pixel(layout, cell.g, 25, 20, px, py);
    for (int row = layout.top_y; row < layout.top_y + 40 * layout.voxel_px; ++row) {
        const double y = top_view_point(layout, cell.g, px, row).y();
        if (std::abs(std::abs(y) - 0.08) > 1.5 * m) {
            const bool robot = bluish(img, px, row) && !has_colour(img, px, row, kRobotMarginColour);
            CHECK_MESSAGE(robot == (std::abs(y) < 0.08), "y " << y);
        }
    }
    // Sensor view: the pillar's top and the arm's middle, seen from above, are blue; the floor beside them is not.
    const PictureSensor& cam = cell.in.sensors[0];
    view_pixel(cam, layout, Eigen::Vector3d(0.0, 0.0, 1.1), px, py);
    CHECK(bluish(img, px, py));
    view_pixel(cam, layout, Eigen::Vector3d(0.5, 0.0, 1.08), px, py);
    CHECK(bluish(img, px, py));
    view_pixel(cam, layout, Eigen::Vector3d(0.5, 0.6, 0.0), px, py);
    CHECK_FALSE(bluish(img, px, py));
    view_pixel(cam, layout, Eigen::Vector3d(0.75, -0.6, 0.5), px, py);  // the zone, in front of the floor
    CHECK(reddish(img, px, py));
}

// verifies: SR-SYS-004
TEST_CASE("picture: the S_p ring is at its distance from the capsules, the mask margin's outline at the margin") {
    const RobotPictureCell cell;
    PictureLayout layout;
    const RgbImage img = png_round_trip(render_config_picture(cell.in, &layout));
    const PictureColour ring = cell.robot.rings[0].colour;
    const double m = cell.g.voxel_size() / layout.voxel_px;
    // Along the row through y = 0.05 towards -x, and the column through x = 0.05 towards +y, the ring
    // (1.2 m from the pillar's surface: 1.3 m from its axis) lies where it should, within a pixel and a half.
    int cx = 0;
    int cy = 0;
    top_view_pixel(layout, cell.g, 20, 20, cx, cy);
    const double expected = std::sqrt(1.3 * 1.3 - 0.05 * 0.05);
    double sum = 0.0;
    int n = 0;
    for (int px = layout.top_x; px < cx; ++px) {
        if (has_colour(img, px, cy, ring)) {
            sum += top_view_point(layout, cell.g, px, cy).x();
            ++n;
        }
    }
    REQUIRE(n >= 1);
    CHECK(n <= 3);
    CHECK(std::abs(sum / n + expected) <= 1.5 * m);
    sum = 0.0;
    n = 0;
    for (int py = layout.top_y; py < cy; ++py) {
        if (has_colour(img, cx, py, ring)) {
            sum += top_view_point(layout, cell.g, cx, py).y();
            ++n;
        }
    }
    REQUIRE(n >= 1);
    CHECK(n <= 3);
    CHECK(std::abs(sum / n - expected) <= 1.5 * m);
    // Every ring pixel, and every pixel of the margin's dashed outline, in the top view lies within a pixel
    // of its distance from the capsules' floor footprint.
    int ring_pixels = 0;
    int margin_pixels = 0;
    for (int py = layout.top_y; py < layout.top_y + 40 * layout.voxel_px; ++py) {
        for (int px = layout.top_x; px < layout.top_x + 40 * layout.voxel_px; ++px) {
            const Eigen::Vector2d p = top_view_point(layout, cell.g, px, py);
            const double d = floor_distance(cell.robot.pose, p.x(), p.y());
            if (has_colour(img, px, py, ring)) {
                ++ring_pixels;
                CHECK_MESSAGE(std::abs(d - 1.2) <= 1.01 * m, px << "," << py);
            }
            if (has_colour(img, px, py, kRobotMarginColour)) {
                ++margin_pixels;
                CHECK_MESSAGE(std::abs(d - 0.25) <= 1.01 * m, px << "," << py);
            }
        }
    }
    CHECK(ring_pixels > 500);  // 2 pixels wide around most of a 1.3 m radius
    CHECK(margin_pixels > 100);
    // The margin's outline in the sensor view: the edge of the silhouette of the capsules grown by the margin.
    const PictureSensor& cam = cell.in.sensors[0];
    int view_margin = 0;
    for (int py = 0; py < layout.view_h; ++py) {
        for (int px = 0; px < layout.view_w; ++px) {
            if (has_colour(img, layout.view_x + px, layout.view_y + py, kRobotMarginColour)) {
                ++view_margin;
                const double d = ray_distance(cell.robot.pose, cam.pose.translation(), view_ray(cam, layout, px, py));
                CHECK_MESSAGE(std::abs(d - 0.25) < 0.015, px << "," << py << ": " << d);
            }
        }
    }
    CHECK(view_margin > 50);
}

// verifies: SR-SYS-004
TEST_CASE("picture: without a robot nothing of it is drawn, and cases and the robot add legend lines") {
    RobotPictureCell cell;
    const RgbImage with = render_config_picture(cell.in);
    cell.in.robot = nullptr;
    const RgbImage without = render_config_picture(cell.in);
    CHECK(with.height > without.height);
    int drawn = 0;
    for (int y = 0; y < without.height; ++y) {
        for (int x = 0; x < without.width; ++x) {
            drawn += has_colour(without, x, y, kRobotMarginColour) ||
                             has_colour(without, x, y, cell.robot.rings[0].colour)
                         ? 1
                         : 0;
        }
    }
    CHECK(drawn == 0);
    cell.in.cases = {PictureCase{0, "work", 1U}, PictureCase{3, "idle", 0U}};
    const RgbImage cases = render_config_picture(cell.in);
    CHECK(cases.height > without.height);  // a heading and a line per case
}

// verifies: SR-SYS-004
TEST_CASE("picture: the robot is drawn at the demo trajectory's first keyframe, else at joints 0, with its distances") {
    const RobotModel arm = test::make_test_arm(0.5, -0.25, 0.0);
    MonitorConfig cfg;
    cfg.robot.margin_m = 0.2;
    SeparationParams& sp = cfg.robot.separation;
    sp.reaction_time_s = 0.3;
    sp.class_count = 2U;
    sp.classes[0] = SpeedClassLimits{0.5, 0.2, 0.05};
    sp.classes[1] = SpeedClassLimits{0.25, 0.1, 0.0125};
    sp.reduced_class = 1U;
    sp.slowdown_time_s = 0.2;
    sp.intrusion_distance_m = 0.85;
    sim::JointTrajectory trajectory;
    sim::Keyframe k0;
    k0.t = 0.5;
    k0.q = test::test_arm_joints(-1.5, 0.4, 1.1, 0.2, 0.0, 0.3);
    sim::Keyframe k1 = k0;
    k1.t = 2.0;
    k1.q.q[0] = 1.0;
    trajectory.keyframes = {k0, k1};
    const PictureRobot at_keyframe = picture_robot(cfg, arm, trajectory);
    const RobotPose expected = test::test_arm_pose(arm, k0.q);
    REQUIRE(at_keyframe.pose.count == expected.count);
    for (std::uint8_t i = 0U; i < expected.count; ++i) {
        for (int j = 0; j < 3; ++j) {
            CHECK(at_keyframe.pose.capsules[i].a[j] == expected.capsules[i].a[j]);
            CHECK(at_keyframe.pose.capsules[i].b[j] == expected.capsules[i].b[j]);
        }
    }
    CHECK(at_keyframe.pose_source.find("first keyframe (t = 0.50 s)") != std::string::npos);
    CHECK(at_keyframe.name == "cellguard_test_arm");
    CHECK(at_keyframe.margin_m == 0.2);
    // One ring per speed class and the reduced-speed distance, each in its own colour.
    REQUIRE(at_keyframe.rings.size() == 3U);
    CHECK(at_keyframe.rings[0].distance_m == protective_separation_distance(sp, 0U));
    CHECK(at_keyframe.rings[1].distance_m == protective_separation_distance(sp, 1U));
    CHECK(at_keyframe.rings[2].distance_m == reduced_speed_distance(sp));
    CHECK(at_keyframe.rings[0].name.find("(full)") != std::string::npos);
    CHECK(at_keyframe.rings[1].name.find("(reduced)") != std::string::npos);
    for (std::size_t i = 0U; i < 3U; ++i) {
        for (std::size_t j = i + 1U; j < 3U; ++j) {
            const PictureColour a = at_keyframe.rings[i].colour;
            const PictureColour b = at_keyframe.rings[j].colour;
            CHECK((a.r != b.r || a.g != b.g || a.b != b.b));
        }
    }
    // No trajectory (no demo scene): all joints 0, the arm straight up from its base.
    const PictureRobot at_zero = picture_robot(cfg, arm, sim::JointTrajectory{});
    CHECK(at_zero.pose_source.find("all joints 0") != std::string::npos);
    CHECK(at_zero.joints.count == 6U);
    const PlacedCapsule& flange = at_zero.pose.capsules[at_zero.pose.count - 1U];
    CHECK(flange.b[0] == doctest::Approx(0.5));
    CHECK(flange.b[1] == doctest::Approx(-0.25));
    CHECK(flange.b[2] == doctest::Approx(test::kArmStraightHeight));
}
