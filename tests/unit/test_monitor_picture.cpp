// Verifies the monitor's configuration picture (apps/monitor: png.hpp,
// picture.hpp): the PNG writer's file is valid (signature, IHDR, chunk
// CRC-32s, zlib header, stored or fixed-Huffman deflate blocks, Adler-32) and decodes to the
// image written; the zones are drawn where they are, in the top view and in
// the sensor view; the background is grey.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "cellguard/crc32.hpp"
#include "cellguard/host/png.hpp"
#include "cellguard/log_odds.hpp"
#include "cellguard/monitor/picture.hpp"

using namespace cellguard;
using namespace cellguard::monitor;
using cellguard::host::adler32;
using cellguard::host::IndexedImage;

namespace {

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
    return (std::uint32_t{b.at(at)} << 24U) | (std::uint32_t{b.at(at + 1U)} << 16U) |
           (std::uint32_t{b.at(at + 2U)} << 8U) | std::uint32_t{b.at(at + 3U)};
}

/// Deflate bits, LSB first (RFC 1951); Huffman codes are read MSB first.
class BitReader {
public:
    BitReader(const std::vector<std::uint8_t>& data, std::size_t from) : data_(data), bit_(from * 8U) {}
    unsigned bits(int count) {
        unsigned v = 0U;
        for (int i = 0; i < count; ++i) {
            v |= next() << static_cast<unsigned>(i);
        }
        return v;
    }
    unsigned next() {
        REQUIRE(bit_ / 8U < data_.size());
        const unsigned b = (data_[bit_ / 8U] >> (bit_ % 8U)) & 1U;
        ++bit_;
        return b;
    }
    std::size_t byte_after() const { return (bit_ + 7U) / 8U; }
    void align() { bit_ = byte_after() * 8U; }

private:
    const std::vector<std::uint8_t>& data_;
    std::size_t bit_;
};

/// One literal/length symbol of the fixed Huffman code.
unsigned fixed_symbol(BitReader& r) {
    unsigned code = 0U;
    for (int i = 0; i < 7; ++i) {
        code = (code << 1U) | r.next();
    }
    if (code <= 23U) {
        return 256U + code;
    }
    code = (code << 1U) | r.next();
    if (code >= 0x30U && code <= 0xBFU) {
        return code - 0x30U;
    }
    if (code >= 0xC0U && code <= 0xC7U) {
        return 280U + code - 0xC0U;
    }
    code = (code << 1U) | r.next();
    REQUIRE(code >= 0x190U);
    return 144U + code - 0x190U;
}

/// Inflates stored and fixed-Huffman blocks from @p p; @p p ends after the last block.
std::vector<std::uint8_t> inflate(const std::vector<std::uint8_t>& z, std::size_t& p, int& blocks) {
    static const unsigned len_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                          31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static const int len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    std::vector<std::uint8_t> out;
    BitReader r(z, p);
    bool final_block = false;
    while (!final_block) {
        final_block = r.bits(1) != 0U;
        const unsigned type = r.bits(2);
        REQUIRE(type <= 1U);  // stored or fixed Huffman
        ++blocks;
        if (type == 0U) {
            r.align();
            const unsigned len = r.bits(16);
            const unsigned nlen = r.bits(16);
            CHECK((len ^ 0xFFFFU) == nlen);
            for (unsigned i = 0U; i < len; ++i) {
                out.push_back(static_cast<std::uint8_t>(r.bits(8)));
            }
            continue;
        }
        for (unsigned sym = fixed_symbol(r); sym != 256U; sym = fixed_symbol(r)) {
            if (sym < 256U) {
                out.push_back(static_cast<std::uint8_t>(sym));
                continue;
            }
            REQUIRE(sym <= 285U);
            const unsigned length = len_base[sym - 257U] + r.bits(len_extra[sym - 257U]);
            unsigned dcode = 0U;
            for (int i = 0; i < 5; ++i) {
                dcode = (dcode << 1U) | r.next();
            }
            REQUIRE(dcode <= 3U);  // the writer only uses distances 1 to 4
            const std::size_t distance = dcode + 1U;
            REQUIRE(distance <= out.size());
            for (unsigned i = 0U; i < length; ++i) {
                out.push_back(out[out.size() - distance]);
            }
        }
    }
    p = r.byte_after();
    return out;
}

/// A PNG decoded by this test's own reader (only what encode_png writes:
/// 8-bit RGB or indexed, filter 0, stored or fixed-Huffman deflate blocks); every check is a CHECK.
struct Decoded {
    bool ok = false;
    std::uint32_t width = 0U;
    std::uint32_t height = 0U;
    std::uint8_t colour = 0U;           // IHDR colour type
    std::vector<std::uint8_t> rgb;      // RGB bytes, or palette indices when indexed
    std::vector<std::uint8_t> palette;  // PLTE, when present
    int chunks = 0;
    int blocks = 0;
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
            d.colour = png[at + 17U];
            CHECK((d.colour == 2U || d.colour == 3U));  // RGB or indexed
            CHECK(png[at + 18U] == 0U);
            CHECK(png[at + 19U] == 0U);
            CHECK(png[at + 20U] == 0U);
            ihdr = true;
        } else if (type == "PLTE") {
            CHECK(len % 3U == 0U);
            d.palette.assign(png.begin() + static_cast<std::ptrdiff_t>(at + 8U),
                             png.begin() + static_cast<std::ptrdiff_t>(at + 8U + len));
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
    // zlib: header, stored or fixed-Huffman blocks, Adler-32.
    REQUIRE(idat.size() >= 6U);
    CHECK((idat[0] * 256U + idat[1]) % 31U == 0U);
    CHECK((idat[0] & 0x0FU) == 8U);
    std::size_t p = 2U;
    const std::vector<std::uint8_t> raw = inflate(idat, p, d.blocks);
    REQUIRE(p + 4U == idat.size());
    CHECK(be32(idat, p) == adler32(raw.data(), raw.size()));
    const std::size_t row = std::size_t{d.width} * (d.colour == 3U ? 1U : 3U);
    REQUIRE(raw.size() == (row + 1U) * d.height);
    for (std::uint32_t y = 0U; y < d.height; ++y) {
        const std::uint8_t filter = raw[y * (row + 1U)];
        REQUIRE((filter == 0U || filter == 2U));  // None or Up
        for (std::size_t x = 0U; x < row; ++x) {
            const std::uint8_t above = y > 0U && filter == 2U ? d.rgb[(y - 1U) * row + x] : std::uint8_t{0U};
            d.rgb.push_back(static_cast<std::uint8_t>(raw[y * (row + 1U) + 1U + x] + above));
        }
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
TEST_CASE("png: a large image is compressed and decodes to the same pixels, bad sizes are refused") {
    RgbImage img = RgbImage::filled(300, 200, 0, 0, 0);
    for (std::size_t i = 0U; i < img.rgb.size(); ++i) {
        img.rgb[i] = static_cast<std::uint8_t>(i * 7U);
    }
    const std::vector<std::uint8_t> png = encode_png(img);
    CHECK(png.size() < img.rgb.size() / 10U);
    const Decoded d = decode(png);
    REQUIRE(d.ok);
    CHECK(d.blocks == 1);
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
    CHECK(d.colour == 3U);
    CHECK(d.width == 7U);
    CHECK(d.height == 5U);
    CHECK(d.chunks == 4);
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
    ZoneError err;
    const CompiledZones zones =
        CompiledZones::compile(g, {zc.data(), zc.size()}, {mask.data(), mask.size()}).value();
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
