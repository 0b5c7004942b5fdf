// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the background view image (lib/prior background_image.hpp,
// apps/host background_files.hpp): written with the prior and bound to its
// CRC, refused at load for a changed byte, a truncated or extended file,
// another prior, another number of sensors, or a view of another sensor
// (name, size, pose, intrinsics); the per-pixel median of the commissioning
// frames; the prior tool writes it and the monitor loads it at start.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/io/background_files.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/prior/background_image.hpp"
#include "cellguard/prior_tool/prior_tool.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {

constexpr std::uint32_t kPriorCrc = 0x12345678U;

// Two small views: 4 x 2 and 3 x 1 pixels.
struct TwoViews {
    std::vector<float> a = {1.0F, 2.0F, 0.0F, 3.5F, 2.25F, 0.0F, 1.0F, 9.75F};
    std::vector<float> b = {0.5F, 0.0F, 4.0F};
    std::vector<BackgroundViewRecord> records;
    TwoViews() {
        BackgroundViewRecord ra;
        ra.identity.name_crc = 11U;
        ra.identity.width = 4U;
        ra.identity.height = 2U;
        ra.identity.position[0] = -1.9;
        ra.identity.intrinsics[0] = 100.0;
        ra.depth = Span<const float>(a.data(), a.size());
        BackgroundViewRecord rb = ra;
        rb.identity.name_crc = 22U;
        rb.identity.width = 3U;
        rb.identity.height = 1U;
        rb.depth = Span<const float>(b.data(), b.size());
        records = {ra, rb};
    }
    Span<const BackgroundViewRecord> span() const { return {records.data(), records.size()}; }
    std::vector<std::uint8_t> image() const {
        std::vector<std::uint8_t> out(background_image_size(span()));
        const Result<std::size_t> w = write_background_image(span(), kPriorCrc, 8U, {out.data(), out.size()});
        REQUIRE(w.ok());
        REQUIRE(w.value() == out.size());
        return out;
    }
};

BackgroundImageError check(const std::vector<std::uint8_t>& img, std::uint32_t sensors = 2U,
                           std::uint32_t prior = kPriorCrc) {
    return check_background_image({img.data(), img.size()}, sensors, prior).error();
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

// verifies: SR-BKG-001
TEST_CASE("background image: written views load back bit for bit, each only for its own sensor") {
    const TwoViews v;
    const std::vector<std::uint8_t> img = v.image();
    CHECK(img.size() == kBackgroundImageHeaderSize + 2U * kBackgroundRecordHeaderSize + 4U * (8U + 3U));
    const Result<BackgroundImageInfo, BackgroundImageError> info = check_background_image({img.data(), img.size()}, 2U,
                                                                                          kPriorCrc);
    REQUIRE(info.ok());
    CHECK(info.value().sensor_count == 2U);
    CHECK(info.value().frames == 8U);
    std::vector<float> out(8U, -1.0F);
    const auto a = load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 0U, v.records[0].identity,
                                        {out.data(), out.size()});
    REQUIRE(a.ok());
    CHECK(a.value() == 8U);
    CHECK(out == v.a);
    const auto b = load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 1U, v.records[1].identity,
                                        {out.data(), out.size()});
    REQUIRE(b.ok());
    CHECK(std::vector<float>(out.begin(), out.begin() + 3) == v.b);
    // Another sensor: name, size, a pose bit, intrinsics; the other record's identity.
    BackgroundSensorIdentity other = v.records[0].identity;
    other.name_crc = 12U;
    CHECK(load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 0U, other, {out.data(), out.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    other = v.records[0].identity;
    other.position[0] = std::nextafter(other.position[0], 0.0);
    CHECK(load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 0U, other, {out.data(), out.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    other = v.records[0].identity;
    other.intrinsics[0] = 100.5;
    CHECK(load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 0U, other, {out.data(), out.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    CHECK(load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 1U, v.records[0].identity,
                               {out.data(), out.size()})
              .error() == BackgroundImageError::kWrongSensor);
    std::vector<float> small(7U);
    CHECK(load_background_view({img.data(), img.size()}, 2U, kPriorCrc, 0U, v.records[0].identity,
                               {small.data(), small.size()})
              .error() == BackgroundImageError::kStorageTooSmall);
}

// verifies: SR-BKG-001
TEST_CASE("background image: every truncation, an extra byte and every flipped bit are refused") {
    const std::vector<std::uint8_t> img = TwoViews().image();
    for (std::size_t n = 0; n < img.size(); ++n) {
        const std::vector<std::uint8_t> cut(img.begin(), img.begin() + static_cast<std::ptrdiff_t>(n));
        CAPTURE(n);
        const BackgroundImageError e = check(cut);
        CHECK((e == BackgroundImageError::kTooShort || e == BackgroundImageError::kRecordTruncated));
    }
    std::vector<std::uint8_t> longer = img;
    longer.push_back(0U);
    CHECK(check(longer) == BackgroundImageError::kTrailingBytes);
    std::size_t refused = 0U;
    for (std::size_t i = 0; i < img.size(); ++i) {
        for (unsigned bit = 0; bit < 8U; ++bit) {
            std::vector<std::uint8_t> flipped = img;
            flipped[i] ^= static_cast<std::uint8_t>(1U << bit);
            refused += check(flipped) != BackgroundImageError::kNone ? 1U : 0U;
        }
    }
    CHECK(refused == 8U * img.size());  // CRC-32 detects every single-bit error
}

// verifies: SR-BKG-001
TEST_CASE("background image: another prior, another sensor count, and bad fields are refused with their reason") {
    const std::vector<std::uint8_t> img = TwoViews().image();
    CHECK(check(img, 2U, kPriorCrc ^ 1U) == BackgroundImageError::kPriorCrcMismatch);
    CHECK(check(img, 3U) == BackgroundImageError::kSensorCountMismatch);
    CHECK(check(img, 1U) == BackgroundImageError::kSensorCountMismatch);
    std::vector<std::uint8_t> magic = img;
    magic[3] = 'X';
    CHECK(check(magic) == BackgroundImageError::kBadMagic);
    std::vector<std::uint8_t> version = img;
    version[4] = 2U;
    CHECK(check(version) == BackgroundImageError::kUnsupportedVersion);
    std::vector<std::uint8_t> payload = img;
    payload.back() ^= 0x01U;
    CHECK(check(payload) == BackgroundImageError::kPayloadCrcMismatch);
    std::vector<std::uint8_t> record = img;
    record[kBackgroundImageHeaderSize + 4U] ^= 0x01U;  // the first record's width
    CHECK(check(record) == BackgroundImageError::kRecordHeaderCrcMismatch);
    for (const BackgroundImageError e :
         {BackgroundImageError::kTooShort, BackgroundImageError::kWrongSensor, BackgroundImageError::kDepthOutOfRange})
        CHECK(std::string(to_string(e)).find("background") != std::string::npos);
}

// verifies: SR-BKG-001
TEST_CASE("background image: the writer refuses bad depths, sizes, counts and frames") {
    TwoViews v;
    std::vector<std::uint8_t> out(4096U);
    const Span<std::uint8_t> o(out.data(), out.size());
    for (const float bad : {-0.5F, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        v.a[3] = bad;
        CHECK(write_background_image(v.span(), kPriorCrc, 8U, o).error() == ErrorCode::kInvalidArgument);
    }
    v.a[3] = 1.0F;
    CHECK(write_background_image(v.span(), kPriorCrc, 0U, o).error() == ErrorCode::kInvalidArgument);
    CHECK(write_background_image({}, kPriorCrc, 8U, o).error() == ErrorCode::kInvalidArgument);
    v.records[0].identity.width = 5U;  // 10 pixels, 8 depths
    CHECK(write_background_image(v.span(), kPriorCrc, 8U, o).error() == ErrorCode::kInvalidArgument);
    v.records[0].identity.width = 4U;
    std::vector<BackgroundViewRecord> nine(9U, v.records[1]);
    CHECK(write_background_image({nine.data(), nine.size()}, kPriorCrc, 8U, o).error() == ErrorCode::kInvalidArgument);
    CHECK(write_background_image(v.span(), kPriorCrc, 8U, o.subspan(0U, 100U)).error() == ErrorCode::kStorageTooSmall);
}

// verifies: SR-BKG-001
TEST_CASE("background image: the fuzz corpus's seeds, made by a separate script, are valid images") {
    for (const char* name : {"valid_one_sensor", "valid_two_sensors"}) {
        const std::vector<std::uint8_t> seed = read_bytes(
            std::string(CELLGUARD_SOURCE_DIR "/tests/fuzz/corpus/fuzz_background_image/") + name);
        REQUIRE(seed.size() > 1U);
        const std::vector<std::uint8_t> img(seed.begin() + 1, seed.end());
        const Span<const std::uint8_t> s(img.data(), img.size());
        CAPTURE(name);
        CHECK(check_background_image(s, load_le_u32(s, 8U), 0x12345678U).ok());
    }
}

// verifies: SR-BKG-002
TEST_CASE("background view: the per-pixel median of noisy frames, a pixel without readings in most frames has none") {
    BackgroundViewBuilder b(3U);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::vector<float>> frames = {
        {2.00F, 1.0F, nan}, {2.02F, 1.0F, 3.0F}, {1.98F, 1.0F, nan}, {2.01F, nan, nan}, {5.00F, 1.0F, 3.0F}};
    for (const std::vector<float>& f : frames) {
        SensorReading r;
        r.kind = SensorDataKind::kDepthImage;
        r.depth = Span<const float>(f.data(), f.size());
        CHECK(b.add(r));
    }
    SensorReading wrong;
    wrong.kind = SensorDataKind::kDepthImage;
    const std::vector<float> two = {1.0F, 1.0F};
    wrong.depth = Span<const float>(two.data(), two.size());
    CHECK_FALSE(b.add(wrong));
    SensorReading points;
    points.kind = SensorDataKind::kPointSet;  // no depth image: a point-set sensor's view is a direction grid
    CHECK_FALSE(b.add(points));
    CHECK(b.frames() == 5U);
    const std::vector<float> m = b.median();
    CHECK(m[0] == 2.01F);  // the outlier 5.00 does not move it
    CHECK(m[1] == 1.0F);
    CHECK(m[2] == 0.0F);  // readings in 2 of 5 frames: no reading
}

// verifies: SR-BKG-001, SR-BKG-002
TEST_CASE("background view: the prior tool writes it with the prior, the monitor loads it, and refuses a changed one") {
    char templ[] = "/tmp/cellguard_test_background_XXXXXX";
    REQUIRE(::mkdtemp(templ) != nullptr);
    const std::string dir = templ;
    std::ostringstream out;
    std::ostringstream err;
    const int status = prior_tool::run_prior_tool(
        {"--simulated", "--background-frames", "8", "--out", dir, "--write-background", dir + "/background.cgbv"}, out,
        err, false);
    INFO(out.str() << err.str());
    REQUIRE(status == prior_tool::kExitOk);
    CHECK(out.str().find("views of the empty cell, median of 8 frames") != std::string::npos);

    // The demo's cell with that prior and its views.
    std::string text = cell::demo_config_text();
    const std::string sim_prior =
        "source = \"simulated-background\"   # or \"file\", with file = \"path/to/prior.cgprior\"\n"
        "background_frames = 8\n";
    const std::size_t at = text.find(sim_prior);
    REQUIRE(at != std::string::npos);
    text.replace(
        at, sim_prior.size(),
        "source = \"file\"\nfile = \"" + dir + "/prior.cgprior\"\nbackground_file = \"" + dir + "/background.cgbv\"\n");
    const cell::ConfigLoad load = cell::parse_monitor_config(text, "cell.toml", dir);
    INFO(load.error);
    REQUIRE(load.ok);
    {
        monitor::MonitorCell c;
        REQUIRE_FALSE(c.configure(load.config).failed());
        REQUIRE_FALSE(c.build_prior(load.config, nullptr).failed());
        const monitor::SetupError e = c.build_tables(load.config, nullptr);
        INFO(e.message);
        REQUIRE_FALSE(e.failed());
        REQUIRE(c.background_views.size() == 4U);
        // The views are the renders of the empty cell (the simulator is noise-free).
        for (std::size_t s = 0; s < 4U; ++s) {
            for (std::size_t i = 0; i < c.background_views[s].size(); ++i) {
                const float d = c.layout.readings[s].depth[i];
                REQUIRE(c.background_views[s][i] == ((std::isfinite(d) && d > 0.0F) ? d : 0.0F));
            }
            CHECK(c.backgrounds[s].depth.data() == c.background_views[s].data());
        }
    }
    // A byte of the views changed, a sensor moved in the configuration: refused at start.
    std::vector<std::uint8_t> bytes = read_bytes(dir + "/background.cgbv");
    bytes[bytes.size() / 2U] ^= 0x10U;
    {
        std::ofstream f(dir + "/changed.cgbv", std::ios::binary);
        f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    }
    cell::MonitorConfig changed = load.config;
    changed.prior.background_file = dir + "/changed.cgbv";
    cell::MonitorConfig moved = load.config;
    moved.sensors[1].position.x() += 0.01;
    for (const cell::MonitorConfig* cfg : {&changed, &moved}) {
        monitor::MonitorCell c;
        REQUIRE_FALSE(c.configure(*cfg).failed());
        REQUIRE_FALSE(c.build_prior(*cfg, nullptr).failed());
        const monitor::SetupError e = c.build_tables(*cfg, nullptr);
        CHECK(e.failed());
        CHECK(e.message.find("background views:") != std::string::npos);
    }
    for (const char* f :
         {"prior.cgprior", "prior_flash.hpp", "p_acc.npy", "p_fore.npy", "background.cgbv", "changed.cgbv"})
        std::remove((dir + "/" + f).c_str());
    ::rmdir(dir.c_str());
}

// verifies: SR-BKG-005
TEST_CASE("background checks: on by default in the monitor's configuration, recorded sensors included") {
    // The demo text without the [cycle] keys that set them: the defaults apply.
    std::string text = cell::demo_config_text();
    for (const char* key : {"background_match = ", "background_tolerance_m = ", "background_changed_pixels = ",
                            "background_changed_cycles = ", "max_repeated_frames = "}) {
        const std::size_t at = text.find(std::string("\n") + key);
        REQUIRE(at != std::string::npos);
        text.erase(at + 1U, text.find('\n', at + 1U) - at);
    }
    const cell::ConfigLoad load = cell::parse_monitor_config(text, "cell.toml");
    INFO(load.error);
    REQUIRE(load.ok);
    CHECK(load.config.max_repeated_frames == 3U);
    CHECK(load.config.background_match == 0.5F);
    CHECK(load.config.background_tolerance_m == 0.05F);
    CHECK(load.config.background_changed_pixels == 20U);
    CHECK(load.config.background_changed_cycles == 3U);
    // The monitor hands them to every simulated sensor's reference.
    monitor::MonitorCell c;
    REQUIRE_FALSE(c.configure(load.config).failed());
    REQUIRE_FALSE(c.build_prior(load.config, nullptr).failed());
    REQUIRE_FALSE(c.build_tables(load.config, nullptr).failed());
    for (const BackgroundReference& r : c.backgrounds) {
        CHECK(r.min_match_fraction == 0.5F);
        CHECK(r.max_longer_pixels == 20U);
        CHECK(r.changed_cycles == 3U);
    }
    // A recorded sensor with the default: accepted, compared per direction bin (SR-BKG-009).
    std::string pcd = text;
    const std::string anchor = "max_range = 10.0\n";
    pcd.insert(pcd.find(anchor) + anchor.size(), "pcd_files = [\"pcd/recorded-ascii.pcd\"]\n");
    const cell::ConfigLoad recorded = cell::parse_monitor_config(pcd, "cell.toml",
                                                                 CELLGUARD_SOURCE_DIR "/apps/monitor/test");
    INFO(recorded.error);
    CHECK(recorded.ok);
    CHECK(recorded.config.background_match == 0.5F);
    // background_file only with a prior file.
    std::string sim_file = text;
    sim_file.insert(sim_file.find("background_frames = 8\n"), "background_file = \"views.cgbv\"\n");
    const cell::ConfigLoad wrong = cell::parse_monitor_config(sim_file, "cell.toml");
    CHECK_FALSE(wrong.ok);
    CHECK(wrong.error.find("prior.background_file") != std::string::npos);
}

// verifies: SR-BKG-006
TEST_CASE("simulated frames: odd cycles move the first reading one float step deeper, nothing else changes") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<float> d = {nan, 0.0F, 2.0F, 3.0F};
    cell::dither_depth(4U, {d.data(), d.size()});
    CHECK(d[2] == 2.0F);
    cell::dither_depth(5U, {d.data(), d.size()});
    CHECK(std::isnan(d[0]));
    CHECK(d[1] == 0.0F);
    CHECK(d[2] == std::nextafter(2.0F, 3.0F));
    CHECK(d[3] == 3.0F);
    // The monitor's source: the render, and in an odd cycle one pixel one step deeper, so that two frames
    // of a still cell never have the same fingerprint.
    const sim::SensorSpec spec = sim::paper_sensors()[0];
    cell::SimulatedFrameSource plain(spec, cell::FrameDither::kOff);
    cell::SimulatedFrameSource dithered(spec);
    for (const std::uint64_t k : {0U, 1U}) {
        SensorReading a;
        SensorReading b;
        cell::FrameStatus st;
        REQUIRE(plain.load_frame(k, a, st));
        REQUIRE(dithered.load_frame(k, b, st));
        std::size_t differing = 0U;
        for (std::size_t i = 0; i < a.depth.size(); ++i)
            differing += (a.depth[i] == b.depth[i]) ? 0U : 1U;
        CHECK(differing == k);
        CHECK((reading_fingerprint(a) == reading_fingerprint(b)) == (k == 0U));
    }
}

// verifies: SR-GEN-004
TEST_CASE("background image: every refusal has its own name, an unknown value the fallback") {
    test::check_enum_names<BackgroundImageError>(16U, "unknown background image error");
}

// verifies: SR-BKG-001
TEST_CASE("background image: a view beyond the sensor count, a refused image and oversized views are refused") {
    const TwoViews v;
    const std::vector<std::uint8_t> img = v.image();
    std::vector<float> out(8U, -1.0F);
    const Span<const std::uint8_t> in(img.data(), img.size());
    CHECK(load_background_view(in, 2U, kPriorCrc, 2U, v.records[0].identity, {out.data(), out.size()}).error() ==
          BackgroundImageError::kSensorCountMismatch);
    CHECK(load_background_view(in, 2U, kPriorCrc ^ 1U, 0U, v.records[0].identity, {out.data(), out.size()}).error() ==
          BackgroundImageError::kPriorCrcMismatch);
    CHECK(out == std::vector<float>(8U, -1.0F));  // nothing written on a refusal
    // Views wider or higher than 65535 pixels, or of no pixels, have no image size.
    for (const auto& wh : {std::pair<std::uint32_t, std::uint32_t>{65536U, 1U}, {1U, 65536U}, {0U, 1U}, {1U, 0U}}) {
        TwoViews big;
        big.records[0].identity.width = wh.first;
        big.records[0].identity.height = wh.second;
        CHECK(background_image_size(big.span()) == 0U);
        std::vector<std::uint8_t> o(4096U);
        CHECK(write_background_image(big.span(), kPriorCrc, 8U, {o.data(), o.size()}).error() ==
              ErrorCode::kInvalidArgument);
    }
    TwoViews large;  // the payload length field is 32 bits: 4 x 65535 x 16384 fits, 4 x 65535 x 65535 does not
    large.records[0].identity.width = 65535U;
    large.records[0].identity.height = 16384U;
    CHECK(background_image_size(large.span()) ==
          kBackgroundImageHeaderSize + 2U * kBackgroundRecordHeaderSize + 4U * (65535ULL * 16384U + 3U));
    large.records[0].identity.height = 65535U;
    CHECK(background_image_size(large.span()) == 0U);
}

namespace {

void store_u32(std::vector<std::uint8_t>& img, std::size_t at, std::uint32_t v) {
    for (std::size_t i = 0; i < 4U; ++i)
        img[at + i] = static_cast<std::uint8_t>((v >> (8U * i)) & 0xFFU);
}

// Recomputes the file header's CRC, so that a changed header field is judged by its value, not by the CRC.
void reseal_header(std::vector<std::uint8_t>& img) {
    store_u32(img, 28U, crc32(Span<const std::uint8_t>(img.data(), 28U)));
}

// Recomputes the payload CRC (when @p payload_bytes > 0) and the header CRC of the record at @p at.
void reseal_record(std::vector<std::uint8_t>& img, std::size_t at, std::size_t payload_bytes) {
    if (payload_bytes > 0U)
        store_u32(img, at + 108U,
                  crc32(Span<const std::uint8_t>(img.data() + at + kBackgroundRecordHeaderSize, payload_bytes)));
    store_u32(img, at + 116U, crc32(Span<const std::uint8_t>(img.data() + at, 116U)));
}

std::uint32_t bits(float f) {
    std::uint32_t b = 0U;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

// A valid 2 x 1 direction grid: 2 azimuth bins of 0.5 rad from -1 rad, 1 elevation bin from -0.25 rad.
DirectionGrid small_direction_grid() {
    DirectionGrid g;
    g.azimuth_min_rad = -1.0F;
    g.elevation_min_rad = -0.25F;
    g.bin_rad = 0.5F;
    g.azimuth_bins = 2U;
    g.elevation_bins = 1U;
    return g;
}

}  // namespace

// verifies: SR-BKG-001
TEST_CASE("background image: header fields that are wrong under a valid header CRC are refused as a bad header") {
    const std::vector<std::uint8_t> img = TwoViews().image();
    const auto with = [&](std::size_t at, std::uint32_t value, std::size_t bytes) {
        std::vector<std::uint8_t> changed = img;
        for (std::size_t i = 0; i < bytes; ++i)
            changed[at + i] = static_cast<std::uint8_t>((value >> (8U * i)) & 0xFFU);
        reseal_header(changed);
        return check(changed);
    };
    CHECK(with(6U, 33U, 2U) == BackgroundImageError::kBadHeader);  // header size
    CHECK(with(16U, 0U, 4U) == BackgroundImageError::kBadHeader);  // frames
    CHECK(with(20U, 2U, 4U) == BackgroundImageError::kBadHeader);  // statistic
    CHECK(with(24U, 1U, 4U) == BackgroundImageError::kBadHeader);  // reserved
    CHECK(with(16U, 1U, 4U) == BackgroundImageError::kNone);       // one frame is enough
    CHECK(with(8U, 0U, 4U) == BackgroundImageError::kSensorCountMismatch);
    std::vector<std::uint8_t> nine = img;
    store_u32(nine, 8U, 9U);
    reseal_header(nine);
    CHECK(check(nine, 9U) == BackgroundImageError::kSensorCountMismatch);  // above the maximum even when expected
    CHECK(with(12U, kPriorCrc ^ 0x100U, 4U) == BackgroundImageError::kPriorCrcMismatch);
}

// verifies: SR-BKG-001
TEST_CASE("background image: record fields that are wrong under a valid record CRC are refused as a bad record") {
    const TwoViews v;
    const std::vector<std::uint8_t> img = v.image();
    const std::size_t first = kBackgroundImageHeaderSize;
    const auto with = [&](std::size_t field, std::uint32_t value) {
        std::vector<std::uint8_t> changed = img;
        store_u32(changed, first + field, value);
        reseal_record(changed, first, 0U);
        return check(changed);
    };
    CHECK(with(4U, 0U) == BackgroundImageError::kBadRecord);     // width 0
    CHECK(with(8U, 0U) == BackgroundImageError::kBadRecord);     // height 0
    CHECK(with(12U, 2U) == BackgroundImageError::kBadRecord);    // unknown kind
    CHECK(with(104U, 36U) == BackgroundImageError::kBadRecord);  // payload length not 4 x 4 x 2
    CHECK(with(112U, 1U) == BackgroundImageError::kBadRecord);   // reserved
    CHECK(with(12U, 1U) == BackgroundImageError::kBadRecord);    // a direction grid with fx = 100 as azimuth_min
    CHECK(with(4U, 2U) == BackgroundImageError::kBadRecord);     // 2 x 2 pixels: payload length 32 differs
    // A depth below 0 or NaN under valid CRCs: refused by its value.
    const std::size_t payload = first + kBackgroundRecordHeaderSize;
    for (const float bad : {-1.0F, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        std::vector<std::uint8_t> changed = img;
        store_u32(changed, payload + 4U * 5U, bits(bad));
        reseal_record(changed, first, 4U * 8U);
        CAPTURE(bad);
        CHECK(check(changed) == BackgroundImageError::kDepthOutOfRange);
    }
}

// verifies: SR-BKG-001, SR-BKG-009
TEST_CASE(
    "background image: a direction grid view loads back, and the writer refuses a grid that is not exact binary32") {
    const std::vector<float> ranges = {4.0F, 0.0F, 1.5F, 0.0F};  // farthest per bin, then nearest
    BackgroundViewRecord r;
    r.identity.name_crc = 33U;
    r.identity = with_direction_grid(r.identity, small_direction_grid());
    r.depth = Span<const float>(ranges.data(), ranges.size());
    REQUIRE(background_view_values(r.identity) == 4U);
    std::vector<std::uint8_t> out(1024U);
    const Span<std::uint8_t> o(out.data(), out.size());
    const Result<std::size_t> w = write_background_image({&r, 1U}, kPriorCrc, 4U, o);
    REQUIRE(w.ok());
    const Span<const std::uint8_t> img(out.data(), w.value());
    std::vector<float> back(4U, -1.0F);
    const auto loaded = load_background_view(img, 1U, kPriorCrc, 0U, r.identity, {back.data(), back.size()});
    REQUIRE(loaded.ok());
    CHECK(back == ranges);
    // The same sensor as a depth image, or another grid, is another sensor.
    BackgroundSensorIdentity other = r.identity;
    other.kind = kBackgroundViewDepthImage;
    CHECK(load_background_view(img, 1U, kPriorCrc, 0U, other, {back.data(), back.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    other = r.identity;
    other.height = 2U;
    CHECK(load_background_view(img, 1U, kPriorCrc, 0U, other, {back.data(), back.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    other = r.identity;
    other.intrinsics[2] = 0.25;
    CHECK(load_background_view(img, 1U, kPriorCrc, 0U, other, {back.data(), back.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    other = r.identity;
    other.rotation[3] = -0.0;  // equal as a number, not bit for bit
    CHECK(load_background_view(img, 1U, kPriorCrc, 0U, other, {back.data(), back.size()}).error() ==
          BackgroundImageError::kWrongSensor);
    // Intrinsics that binary32 cannot hold, a fourth value, or an invalid grid: refused.
    for (int field = 0; field < 5; ++field) {
        BackgroundViewRecord bad = r;
        if (field < 3)
            bad.identity.intrinsics[field] += 0.1;  // -0.9, -0.15, 0.6: not binary32 values
        else if (field == 3)
            bad.identity.intrinsics[3] = 1.0;
        else
            bad.identity.intrinsics[0] = 3.0;  // 3 + 2 x 0.5 rad reaches beyond pi
        CAPTURE(field);
        CHECK(write_background_image({&bad, 1U}, kPriorCrc, 4U, o).error() == ErrorCode::kInvalidArgument);
    }
}

// verifies: SR-BKG-009
TEST_CASE("background image: a direction grid bin with its nearest beyond its farthest, or one range 0, is refused") {
    BackgroundViewRecord r;
    r.identity = with_direction_grid(r.identity, small_direction_grid());
    std::vector<std::uint8_t> out(1024U);
    const Span<std::uint8_t> o(out.data(), out.size());
    const std::vector<std::vector<float>> bad = {
        {4.0F, 0.0F, 4.5F, 0.0F},   // nearest 4.5 beyond farthest 4
        {4.0F, 0.0F, 0.0F, 0.0F},   // farthest only
        {4.0F, 2.0F, 1.0F, -1.0F},  // a negative range
    };
    for (const std::vector<float>& ranges : bad) {
        r.depth = Span<const float>(ranges.data(), ranges.size());
        CHECK(write_background_image({&r, 1U}, kPriorCrc, 4U, o).error() == ErrorCode::kInvalidArgument);
    }
    // The same in an image: written valid, then a nearest changed under valid CRCs.
    const std::vector<float> good = {4.0F, 0.0F, 1.5F, 0.0F};
    r.depth = Span<const float>(good.data(), good.size());
    const Result<std::size_t> w = write_background_image({&r, 1U}, kPriorCrc, 4U, o);
    REQUIRE(w.ok());
    const std::vector<std::uint8_t> img(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(w.value()));
    const std::size_t payload = kBackgroundImageHeaderSize + kBackgroundRecordHeaderSize;
    for (const float nearest : {4.5F, 0.0F}) {
        std::vector<std::uint8_t> changed = img;
        store_u32(changed, payload + 4U * 2U, bits(nearest));
        reseal_record(changed, kBackgroundImageHeaderSize, 16U);
        CAPTURE(nearest);
        CHECK(check(changed, 1U) == BackgroundImageError::kDepthOutOfRange);
    }
    std::vector<std::uint8_t> nearest_only = img;
    store_u32(nearest_only, payload + 4U * 3U, bits(2.0F));  // bin 1: a nearest range without a farthest one
    reseal_record(nearest_only, kBackgroundImageHeaderSize, 16U);
    CHECK(check(nearest_only, 1U) == BackgroundImageError::kDepthOutOfRange);
}
