// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Tests of recorded depth images (apps/host depth_npy.hpp, depth_input.hpp,
// the `depth_files` configuration and apps/monitor record_depth_frames): the
// file format as numpy writes it, every refusal, replay through the camera
// path bit for bit, and a recording of the monitor's own sources replayed.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/depth_input.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/io/depth_npy.hpp"
#include "cellguard/monitor/background_recording.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "temp_dir.hpp"

using namespace cellguard;

using cellguard::test::TempDir;

namespace {

std::vector<std::uint8_t> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// A depth file's header with its dict text replaced by @p dict (padded as numpy pads).
std::vector<std::uint8_t> with_dict(const std::string& dict, std::size_t data_bytes) {
    std::string header = dict;
    while ((10U + header.size() + 1U) % 64U != 0U) {
        header += ' ';
    }
    header += '\n';
    std::vector<std::uint8_t> bytes = {0x93U,
                                       'N',
                                       'U',
                                       'M',
                                       'P',
                                       'Y',
                                       1U,
                                       0U,
                                       static_cast<std::uint8_t>(header.size() & 0xFFU),
                                       static_cast<std::uint8_t>(header.size() >> 8U)};
    bytes.insert(bytes.end(), header.begin(), header.end());
    bytes.resize(bytes.size() + data_bytes, 0x11U);
    return bytes;
}

cell::CameraReadingParams params_for(int width, int height) {
    cell::CameraReadingParams p;
    p.intrinsics.width = width;
    p.intrinsics.height = height;
    p.intrinsics.fx = 300.0;
    p.intrinsics.fy = 300.0;
    p.intrinsics.cx = (width - 1) / 2.0;
    p.intrinsics.cy = (height - 1) / 2.0;
    p.pose.translation() = Eigen::Vector3d(0.5, -0.25, 2.0);
    p.depth_scale_m = 0.00025F;
    p.depth_offset_m = 0.1F;
    p.max_range = 6.0F;
    return p;
}

}  // namespace

// verifies: SR-SYS-011
TEST_CASE("depth npy: written as numpy.save writes a (height, width) array, read back bit for bit") {
    TempDir dir("depth");
    const int w = 5;
    const int h = 3;
    std::vector<std::uint16_t> raw(static_cast<std::size_t>(w * h));
    for (std::size_t i = 0; i < raw.size(); ++i) {
        raw[i] = static_cast<std::uint16_t>(i * 4001U);
    }
    const std::string u16 = dir.path() + "/u16.npy";
    REQUIRE(write_npy_depth_u16(u16.c_str(), Span<const std::uint16_t>(raw.data(), raw.size()), w, h).ok());
    const std::vector<std::uint8_t> bytes = file_bytes(u16);
    // numpy 1.24's header for np.save(f, np.zeros((3, 5), '<u2')): 128 bytes in all.
    const std::string dict = "{'descr': '<u2', 'fortran_order': False, 'shape': (3, 5), }";
    REQUIRE(bytes.size() == 128U + raw.size() * 2U);
    CHECK(std::string(bytes.begin() + 10, bytes.begin() + 10 + static_cast<long>(dict.size())) == dict);
    CHECK(bytes[127] == '\n');
    CHECK(bytes[8] == 118U);
    CHECK(npy_depth_file_bytes(NpyDtype::kUInt16, w, h) == bytes.size());

    NpyDepthImage image;
    REQUIRE(decode_npy_depth(bytes.data(), bytes.size(), w, h, image).ok());
    CHECK(image.dtype == NpyDtype::kUInt16);
    REQUIRE(image.count == raw.size());
    CHECK(std::memcmp(image.pixels, raw.data(), raw.size() * 2U) == 0);

    std::vector<float> metres = {0.0F, 1.5F, std::numeric_limits<float>::quiet_NaN(), 3.25F, -1.0F, 7.0F};
    const std::string f32 = dir.path() + "/f32.npy";
    REQUIRE(write_npy_depth_f32(f32.c_str(), Span<const float>(metres.data(), metres.size()), 3, 2).ok());
    std::vector<std::uint8_t> scratch(4096);
    REQUIRE(read_npy_depth(f32.c_str(), 3, 2, Span<std::uint8_t>(scratch.data(), scratch.size()), image).ok());
    CHECK(image.dtype == NpyDtype::kFloat32);
    CHECK(std::memcmp(image.pixels, metres.data(), metres.size() * 4U) == 0);
    NpyDtype probed = NpyDtype::kUInt8;
    REQUIRE(probe_npy_depth(f32.c_str(), 3, 2, probed).ok());
    CHECK(probed == NpyDtype::kFloat32);
}

// verifies: SR-SYS-011
TEST_CASE("depth npy: every malformed or mismatched file is refused with a reason") {
    const std::size_t data = 3U * 5U * 2U;
    NpyDepthImage image;
    const auto refuse = [&](const std::vector<std::uint8_t>& b, ErrorCode code, const char* words) {
        const IoStatus st = decode_npy_depth(b.data(), b.size(), 5, 3, image);
        CAPTURE(st.message());
        CHECK_FALSE(st.ok());
        CHECK(st.error() == code);
        CHECK(std::string(st.message()).find(words) != std::string::npos);
        CHECK(image.pixels == nullptr);
    };
    const std::vector<std::uint8_t> good = with_dict("{'descr': '<u2', 'fortran_order': False, 'shape': (3, 5), }",
                                                     data);
    REQUIRE(decode_npy_depth(good.data(), good.size(), 5, 3, image).ok());
    refuse(with_dict("{'descr': '<u2', 'fortran_order': False, 'shape': (5, 3), }", data), ErrorCode::kGeometryMismatch,
           "(height, width) = (3, 5)");
    refuse(with_dict("{'descr': '<u2', 'fortran_order': False, 'shape': (1, 3, 5), }", data),
           ErrorCode::kGeometryMismatch, "3 dimensions");
    refuse(with_dict("{'descr': '<u2', 'fortran_order': False, 'shape': (15,), }", data), ErrorCode::kGeometryMismatch,
           "1 dimensions");
    refuse(with_dict("{'descr': '<i2', 'fortran_order': False, 'shape': (3, 5), }", data), ErrorCode::kUnsupportedType,
           "'<i2' is not a depth image's");
    refuse(with_dict("{'descr': '>u2', 'fortran_order': False, 'shape': (3, 5), }", data), ErrorCode::kUnsupportedType,
           "big-endian");
    refuse(with_dict("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 5), }", data), ErrorCode::kUnsupportedType,
           "'<f8'");
    refuse(with_dict("{'descr': '<u2', 'fortran_order': True, 'shape': (3, 5), }", data), ErrorCode::kMalformedInput,
           "fortran");
    refuse(with_dict("{'descr': '<u2', 'fortran_order': False, 'shape': (3, 5), }", data - 1U),
           ErrorCode::kTruncatedInput, "the shape needs 30");
    refuse(with_dict("{'descr': '<u2', 'fortran_order': False, 'shape': (3, 5), }", data + 2U),
           ErrorCode::kMalformedInput, "2 bytes after the data");
    std::vector<std::uint8_t> magic = good;
    magic[1] = 'n';
    refuse(magic, ErrorCode::kBadMagic, "");
    for (std::size_t cut = 0; cut < 128U; cut += 7U) {  // every cut inside the header: refused, nothing read past it
        const std::vector<std::uint8_t> head(good.begin(), good.begin() + static_cast<long>(cut));
        CHECK_FALSE(decode_npy_depth(head.data(), head.size(), 5, 3, image).ok());
    }
    CHECK(decode_npy_depth(good.data(), good.size(), 0, 3, image).error() == ErrorCode::kInvalidArgument);
    CHECK(decode_npy_depth(good.data(), good.size(), 5, kNpyDepthMaxSide + 1, image).error() ==
          ErrorCode::kInvalidArgument);

    TempDir dir("depth");
    const std::string path = dir.path() + "/big.npy";
    put_bytes(path, good);
    std::vector<std::uint8_t> small(good.size() - 1U);
    const IoStatus st = read_npy_depth(path.c_str(), 5, 3, Span<std::uint8_t>(small.data(), small.size()), image);
    CHECK(st.error() == ErrorCode::kStorageTooSmall);
    CHECK(std::string(st.message()).find(path) == 0U);
    CHECK_FALSE(
        read_npy_depth((dir.path() + "/none.npy").c_str(), 5, 3, Span<std::uint8_t>(small.data(), small.size()), image)
            .ok());
}

// verifies: SR-SYS-011
TEST_CASE("depth input: recorded images replay as the camera path's readings, refused ones fault") {
    TempDir dir("depth");
    const int w = 8;
    const int h = 6;
    const cell::CameraReadingParams p = params_for(w, h);
    std::vector<std::uint16_t> raw(static_cast<std::size_t>(w * h));
    for (std::size_t i = 0; i < raw.size(); ++i) {
        raw[i] = static_cast<std::uint16_t>(i % 7U == 0U ? 0U : 4000U + i);  // raw 0: no reading
    }
    const std::string a = dir.path() + "/a.npy";
    const std::string b = dir.path() + "/b.npy";
    REQUIRE(write_npy_depth_u16(a.c_str(), Span<const std::uint16_t>(raw.data(), raw.size()), w, h).ok());
    raw[3] = 9999U;
    REQUIRE(write_npy_depth_u16(b.c_str(), Span<const std::uint16_t>(raw.data(), raw.size()), w, h).ok());

    cell::DepthFileFrameSource source("cam", {a, b}, p, true);
    SensorReading r;
    cell::FrameStatus status;
    for (std::uint64_t cycle = 0U; cycle < 4U; ++cycle) {  // a, b, a, b
        const test::ThreadAllocationScope allocations;
        REQUIRE(source.load_frame(cycle, r, status));
        CHECK(allocations.allocations() == 0U);  // the monitor's cycle allocates nothing
        CHECK(status.ok);
        CHECK_FALSE(status.has_stamp);  // stamped with the cycle's start
        CHECK(std::string(status.file) == (cycle % 2U == 0U ? a : b));
        CHECK(r.kind == SensorDataKind::kDepthImageU16);
        REQUIRE(r.depth_u16.size() == raw.size());
        CHECK(r.depth_u16[3] == (cycle % 2U == 0U ? 4003U : 9999U));
        CHECK(r.depth_scale == p.depth_scale_m);
        CHECK(r.depth_offset == p.depth_offset_m);
        CHECK(r.max_range == p.max_range);
        CHECK(r.intrinsics.width == w);
        CHECK(r.pose.isApprox(p.pose, 0.0));
        CHECK(validate_sensor_reading(r).ok());
    }
    CHECK(source.counts().used == 4U);

    // The same images for a sensor configured with '<f4' files: refused.
    cell::DepthFileFrameSource metres_only("cam", {a}, p, false);
    CHECK_FALSE(metres_only.load_frame(0U, r, status));
    CHECK(std::string(status.reason).find("'<u2'") != std::string::npos);
    CHECK_FALSE(validate_sensor_reading(r).ok());  // the controller refuses it: frame inconsistent

    // A file replaced after start by one of another size: refused, no crash; the next good one is used.
    const std::vector<std::uint16_t> wrong(static_cast<std::size_t>(h * w), 1000U);
    REQUIRE(write_npy_depth_u16(b.c_str(), Span<const std::uint16_t>(wrong.data(), wrong.size()), h, w).ok());
    CHECK_FALSE(source.load_frame(1U, r, status));
    CHECK(std::string(status.reason).find(b) == 0U);
    CHECK_FALSE(validate_sensor_reading(r).ok());
    CHECK(source.load_frame(2U, r, status));
    CHECK(source.counts().refused == 1U);
    // Replaced by a '<f4' file of the right shape (metres where the recording is raw units): refused too.
    const std::vector<float> metres(static_cast<std::size_t>(w * h), 2.0F);
    REQUIRE(write_npy_depth_f32(b.c_str(), Span<const float>(metres.data(), metres.size()), w, h).ok());
    CHECK_FALSE(source.load_frame(3U, r, status));
    CHECK(std::string(status.reason).find("a '<f4' image where the sensor's recording is '<u2'") != std::string::npos);
    CHECK_FALSE(validate_sensor_reading(r).ok());
    CHECK(source.counts().refused == 2U);

    // '<f4' metres: a kDepthImage reading, NaN and 0 kept as no reading.
    std::vector<float> depth(static_cast<std::size_t>(w * h), 2.5F);
    depth[0] = std::numeric_limits<float>::quiet_NaN();
    depth[1] = 0.0F;
    REQUIRE(write_npy_depth_f32(b.c_str(), Span<const float>(depth.data(), depth.size()), w, h).ok());
    cell::DepthFileFrameSource floats("cam", {b}, p, false);
    REQUIRE(floats.load_frame(0U, r, status));
    CHECK(r.kind == SensorDataKind::kDepthImage);
    REQUIRE(r.depth.size() == depth.size());
    CHECK(std::memcmp(r.depth.data(), depth.data(), depth.size() * 4U) == 0);
}

// verifies: SR-CFG-001
TEST_CASE("depth input: depth_files is checked when the configuration loads") {
    TempDir dir("depth");
    const std::string base = cell::demo_config_text();
    const std::string anchor = "max_range = 10.0\n";  // the end of sensor 0 ('lidar-a', 176 x 144)
    auto with = [&](const std::string& lines) {
        std::string t = base;
        t.insert(t.find(anchor) + anchor.size(), lines + "\n");
        return t;
    };
    const auto load = [&](const std::string& lines) {
        return cell::parse_monitor_config(with(lines), "cell.toml", dir.path());
    };
    std::vector<float> metres(176U * 144U, 2.0F);
    std::vector<std::uint16_t> raw(176U * 144U, 2000U);
    std::filesystem::create_directory(dir.path() + "/rec");
    for (const char* n : {"rec/f-1.npy", "rec/f-0.npy"}) {
        REQUIRE(write_npy_depth_f32((dir.path() + "/" + n).c_str(), Span<const float>(metres.data(), metres.size()),
                                    176, 144)
                    .ok());
    }
    REQUIRE(write_npy_depth_u16((dir.path() + "/raw.npy").c_str(), Span<const std::uint16_t>(raw.data(), raw.size()),
                                176, 144)
                .ok());
    REQUIRE(write_npy_depth_f32((dir.path() + "/small.npy").c_str(), Span<const float>(metres.data(), 176U * 100U), 176,
                                100)
                .ok());
    std::filesystem::create_directory(dir.path() + "/empty");

    const cell::ConfigLoad by_dir = load("depth_files = \"rec\"");
    CAPTURE(by_dir.error);
    REQUIRE(by_dir.ok);
    REQUIRE(by_dir.config.sensors[0].recording.files.size() == 2U);
    CHECK(by_dir.config.sensors[0].recording.files[0] == dir.path() + "/rec/f-0.npy");  // name order
    CHECK_FALSE(by_dir.config.sensors[0].recording.raw);
    CHECK(by_dir.config.sensors[1].recording.files.empty());

    const cell::ConfigLoad raw_ok = load(
        "depth_files = [\"raw.npy\", \"raw.npy\"]\ndepth_scale = 0.0005\ndepth_offset = 0.0");
    CAPTURE(raw_ok.error);
    REQUIRE(raw_ok.ok);
    CHECK(raw_ok.config.sensors[0].recording.raw);
    CHECK(raw_ok.config.sensors[0].recording.depth_scale_m == 0.0005);

    const auto refused = [&](const std::string& lines, const char* words) {
        const cell::ConfigLoad l = load(lines);
        CAPTURE(lines);
        CAPTURE(l.error);
        CHECK_FALSE(l.ok);
        CHECK(l.error.find(words) != std::string::npos);
    };
    refused("depth_files = [\"raw.npy\"]", "give depth_scale");
    refused("depth_files = \"rec\"\ndepth_scale = 0.001\ndepth_offset = 0.0", "'<u2' files only");
    refused("depth_scale = 0.001\ndepth_offset = 0.0", "this sensor has none");
    refused("depth_files = [\"rec/f-0.npy\", \"raw.npy\"]\ndepth_scale = 0.001\ndepth_offset = 0.0",
            "sensors[0].depth_files[1]: dtype '<u2' differs");
    refused("depth_files = [\"small.npy\"]", "(height, width) = (144, 176)");
    refused("depth_files = \"empty\"", "no .npy file in");
    refused("depth_files = \"missing\"", "cannot read the directory");
    refused("depth_files = []", "one or more file paths");
    refused("depth_files = [\"raw.npy\"]\ndepth_scale = 2.0\ndepth_offset = 0.0", "(0, 1]");
    refused("depth_files = \"rec\"\npcd_files = [\"rec/f-0.npy\"]", "a sensor reads one input");
}

// verifies: SR-SYS-011
TEST_CASE("depth input: the monitor's recording of its sources replays the same readings bit for bit") {
    TempDir dir("depth");
    const cell::ConfigLoad load = cell::parse_monitor_config(cell::demo_config_text(), "cell.toml", dir.path());
    REQUIRE(load.ok);
    monitor::MonitorCell cell;
    REQUIRE_FALSE(cell.configure(load.config).failed());
    std::vector<std::unique_ptr<cell::SimulatedFrameSource>> sims;
    std::vector<cell::FrameSource*> sources;
    for (const sim::SensorSpec& spec : cell.specs) {
        sims.push_back(std::make_unique<cell::SimulatedFrameSource>(spec));
        sources.push_back(sims.back().get());
    }
    class Steps final : public monitor::RecordingTime {
    public:
        std::uint64_t now_us() noexcept override { return now; }
        void pause(std::uint64_t us) noexcept override { now += us; }
        std::uint64_t now = 0U;
    } time;
    monitor::DepthRecording rec;
    rec.dir = dir.path() + "/rec";
    rec.frames = 3;
    std::vector<monitor::RecordedSensor> counts;
    const monitor::SetupError e = monitor::record_depth_frames(cell, sources, rec, time, counts, nullptr);
    CAPTURE(e.message);
    REQUIRE_FALSE(e.failed());
    REQUIRE(counts.size() == cell.specs.size());
    for (std::size_t s = 0; s < cell.specs.size(); ++s) {
        CHECK(counts[s].frames == 3U);
        std::vector<std::string> files;
        for (int k = 0; k < 3; ++k) {
            char name[40];
            std::snprintf(name, sizeof name, "/frame-%06d.npy", k);
            files.push_back(rec.dir + "/" + cell.specs[s].name + name);
        }
        cell::CameraReadingParams p;
        p.pose = cell.specs[s].pose();
        p.intrinsics = cell.specs[s].intrinsics();
        p.max_range = cell.specs[s].max_range;
        cell::DepthFileFrameSource replay(cell.specs[s].name, files, p, false);
        cell::SimulatedFrameSource again(cell.specs[s]);
        for (std::uint64_t k = 0U; k < 3U; ++k) {  // frame k of the simulated source (its dither included)
            SensorReading want;
            SensorReading got;
            cell::FrameStatus ws;
            cell::FrameStatus gs;
            REQUIRE(again.load_frame(k, want, ws));
            REQUIRE(replay.load_frame(k, got, gs));
            CHECK(got.kind == want.kind);
            REQUIRE(got.depth.size() == want.depth.size());
            CHECK(std::memcmp(got.depth.data(), want.depth.data(), want.depth.size() * sizeof(float)) == 0);
            CHECK(got.pose.isApprox(want.pose, 0.0));
            CHECK(std::memcmp(&got.intrinsics, &want.intrinsics, sizeof want.intrinsics) == 0);
            CHECK(got.max_range == want.max_range);
        }
    }
    rec.frames = 0;
    CHECK(monitor::record_depth_frames(cell, sources, rec, time, counts, nullptr).exit_status == 2);
}
