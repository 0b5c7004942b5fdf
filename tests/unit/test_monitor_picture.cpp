// Verifies the monitor's configuration picture (apps/monitor: png.hpp,
// picture.hpp): the PNG writer's file is valid (signature, IHDR, chunk
// CRC-32s, zlib header, stored deflate blocks, Adler-32) and decodes to the
// image written; the zones are drawn where they are, in the top view and in
// the sensor view; the background is grey.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "cellguard/crc32.hpp"
#include "cellguard/log_odds.hpp"
#include "cellguard/monitor/picture.hpp"
#include "cellguard/monitor/png.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
    return (std::uint32_t{b.at(at)} << 24U) | (std::uint32_t{b.at(at + 1U)} << 16U) |
           (std::uint32_t{b.at(at + 2U)} << 8U) | std::uint32_t{b.at(at + 3U)};
}

/// A PNG decoded by this test's own reader (only what encode_png writes:
/// 8-bit RGB, filter 0, stored deflate blocks); every check is a CHECK.
struct Decoded {
    bool ok = false;
    std::uint32_t width = 0U;
    std::uint32_t height = 0U;
    std::vector<std::uint8_t> rgb;
    int chunks = 0;
    int stored_blocks = 0;
};

Decoded decode(const std::vector<std::uint8_t>& png) {
    Decoded d;
    const std::vector<std::uint8_t> sig = {0x89U, 'P', 'N', 'G', '\r', '\n', 0x1AU, '\n'};
    REQUIRE(png.size() > sig.size());
    CHECK(std::vector<std::uint8_t>(png.begin(), png.begin() + 8) == sig);
    std::size_t at = 8U;
    std::vector<std::uint8_t> idat;
    bool ihdr = false;
    bool iend = false;
    while (at + 12U <= png.size()) {
        const std::uint32_t len = be32(png, at);
        REQUIRE(at + 12U + len <= png.size());
        const std::string type(png.begin() + static_cast<std::ptrdiff_t>(at + 4U),
                               png.begin() + static_cast<std::ptrdiff_t>(at + 8U));
        const std::uint32_t crc = be32(png, at + 8U + len);
        CHECK_MESSAGE(crc == crc32(Span<const std::uint8_t>(png.data() + at + 4U, len + 4U)), type);
        ++d.chunks;
        if (type == "IHDR") {
            REQUIRE(len == 13U);
            d.width = be32(png, at + 8U);
            d.height = be32(png, at + 12U);
            CHECK(png[at + 16U] == 8U);  // bit depth
            CHECK(png[at + 17U] == 2U);  // RGB
            CHECK(png[at + 18U] == 0U);
            CHECK(png[at + 19U] == 0U);
            CHECK(png[at + 20U] == 0U);
            ihdr = true;
        } else if (type == "IDAT") {
            idat.insert(idat.end(), png.begin() + static_cast<std::ptrdiff_t>(at + 8U),
                        png.begin() + static_cast<std::ptrdiff_t>(at + 8U + len));
        } else if (type == "IEND") {
            CHECK(len == 0U);
            iend = true;
        }
        at += 12U + len;
    }
    CHECK(at == png.size());
    CHECK(ihdr);
    CHECK(iend);
    // zlib: header, stored blocks, Adler-32.
    REQUIRE(idat.size() >= 6U);
    CHECK((idat[0] * 256U + idat[1]) % 31U == 0U);
    CHECK((idat[0] & 0x0FU) == 8U);
    std::size_t p = 2U;
    std::vector<std::uint8_t> raw;
    bool final_block = false;
    while (!final_block) {
        REQUIRE(p + 5U <= idat.size());
        final_block = (idat[p] & 1U) != 0U;
        CHECK((idat[p] >> 1U & 3U) == 0U);  // stored
        const unsigned len = idat[p + 1U] | (unsigned{idat[p + 2U]} << 8U);
        const unsigned nlen = idat[p + 3U] | (unsigned{idat[p + 4U]} << 8U);
        CHECK((len ^ 0xFFFFU) == nlen);
        p += 5U;
        REQUIRE(p + len <= idat.size());
        raw.insert(raw.end(), idat.begin() + static_cast<std::ptrdiff_t>(p),
                   idat.begin() + static_cast<std::ptrdiff_t>(p + len));
        p += len;
        ++d.stored_blocks;
    }
    REQUIRE(p + 4U == idat.size());
    CHECK(be32(idat, p) == adler32(raw.data(), raw.size()));
    const std::size_t row = std::size_t{d.width} * 3U;
    REQUIRE(raw.size() == (row + 1U) * d.height);
    for (std::uint32_t y = 0U; y < d.height; ++y) {
        CHECK(raw[y * (row + 1U)] == 0U);  // filter: none
        d.rgb.insert(d.rgb.end(), raw.begin() + static_cast<std::ptrdiff_t>(y * (row + 1U) + 1U),
                     raw.begin() + static_cast<std::ptrdiff_t>((y + 1U) * (row + 1U)));
    }
    d.ok = true;
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
    CHECK(d.width == 3U);
    CHECK(d.height == 2U);
    CHECK(d.chunks == 3);
    CHECK(d.rgb == img.rgb);
    CHECK(adler32(reinterpret_cast<const std::uint8_t*>("Wikipedia"), 9U) == 0x11E60398U);
}

// verifies: SR-SYS-001
TEST_CASE("png: an image larger than one stored block spans several blocks, bad sizes are refused") {
    RgbImage img = RgbImage::filled(300, 200, 0, 0, 0);
    for (std::size_t i = 0U; i < img.rgb.size(); ++i) {
        img.rgb[i] = static_cast<std::uint8_t>(i * 7U);
    }
    const Decoded d = decode(encode_png(img));
    REQUIRE(d.ok);
    CHECK(d.stored_blocks == 3);  // 200 * 901 bytes = 180,200 = 65535 + 65535 + 49130
    CHECK(d.rgb == img.rgb);
    RgbImage bad = img;
    bad.rgb.pop_back();
    CHECK(encode_png(bad).empty());
    CHECK(encode_png(RgbImage{}).empty());
    std::string error;
    CHECK_FALSE(write_png("/nonexistent-dir/x.png", img, error));
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
    ZoneError err;
    const CompiledZones zones =
        CompiledZones::compile(g, {zc.data(), zc.size()}, {mask.data(), mask.size()}, &err).value();
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
