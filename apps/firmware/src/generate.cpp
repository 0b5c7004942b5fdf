// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-firmware-gen: renders the firmware's canned inputs on the host.
// Usage: cellguard-firmware-gen OUTPUT_DIR (and --help, --version)
// Writes prior.cgprior (the prior image, byte for byte the file cellguard-prior
// writes: write_prior_image_file) and frames.bin (four depth sensors at half
// the paper's resolution, three scenes; the format of
// cellguard/firmware/canned_frames.hpp). Binary, little-endian, doubles and
// floats as their bit patterns, so the targets read the exact bits.
// src/embedded_data.S embeds both files as they are.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/firmware/canned_frames.hpp"

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/prior_files.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/prior/prior_image.hpp"

using namespace cellguard;

namespace {

std::vector<sim::SensorSpec> firmware_sensors() {
    std::vector<sim::SensorSpec> s = sim::paper_sensors();
    for (sim::SensorSpec& spec : s) {  // half the resolution, same fields of view
        spec.width /= 2;
        spec.height /= 2;
    }
    return s;
}

sim::Scene with_person(double x, double y) {
    sim::Scene s = sim::reference_scene();
    s.boxes.push_back(sim::Box{{x, y, 0.85}, {0.3, 0.3, 1.7}, 0.0, false});
    return s;
}

bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    host::FilePtr f = host::open_file(path.c_str(), "wb");
    if (!f) {
        return false;
    }
    const bool ok = std::fwrite(bytes.data(), 1U, bytes.size(), f.get()) == bytes.size();
    return host::close_file(f) && ok;
}

/// Appends values little-endian, doubles and floats as their bit patterns.
class LeWriter {
public:
    void u32(std::uint32_t v) {
        for (unsigned i = 0U; i < 4U; ++i) {
            bytes_.push_back(static_cast<std::uint8_t>(v >> (8U * i)));
        }
    }
    void u64(std::uint64_t v) {
        u32(static_cast<std::uint32_t>(v));
        u32(static_cast<std::uint32_t>(v >> 32U));
    }
    void f64(double v) {
        std::uint64_t bits = 0U;
        std::memcpy(&bits, &v, sizeof(bits));
        u64(bits);
    }
    void f32(float v) {
        std::uint32_t bits = 0U;
        std::memcpy(&bits, &v, sizeof(bits));
        u32(bits);
    }
    void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
    void raw(const void* p, std::size_t n) {
        const auto* b = static_cast<const std::uint8_t*>(p);
        bytes_.insert(bytes_.end(), b, b + n);
    }
    void zeros(std::size_t n) { bytes_.insert(bytes_.end(), n, 0U); }
    void put_u32(std::size_t offset, std::uint32_t v) {
        for (unsigned i = 0U; i < 4U; ++i) {
            bytes_[offset + i] = static_cast<std::uint8_t>(v >> (8U * i));
        }
    }
    [[nodiscard]] std::size_t size() const { return bytes_.size(); }
    [[nodiscard]] const std::vector<std::uint8_t>& bytes() const { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
};

/// The frames blob (canned_frames.hpp): header, sensor records, scene
/// names, depth images scene-major, CRC-32.
std::vector<std::uint8_t> frames_blob(const std::vector<sim::SensorSpec>& sensors,
                                      const std::vector<const char*>& scene_names,
                                      const std::vector<sim::SimulatedFrame>& frames) {
    namespace L = cellguard::firmware::frames_layout;
    LeWriter w;
    w.raw(cellguard::firmware::kFramesMagic, sizeof(cellguard::firmware::kFramesMagic));
    w.u32(cellguard::firmware::kFramesFormatVersion);
    w.u32(static_cast<std::uint32_t>(sensors.size()));
    w.u32(static_cast<std::uint32_t>(frames.size()));
    w.u32(0U);  // the blob's size, set below
    w.u32(0U);  // reserved
    for (const sim::SensorSpec& s : sensors) {
        const Eigen::Matrix4d m = s.pose().matrix();
        const PinholeIntrinsics k = s.intrinsics();
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                w.f64(m(r, c));
            }
        }
        w.f64(k.fx);
        w.f64(k.fy);
        w.f64(k.cx);
        w.f64(k.cy);
        w.i32(k.width);
        w.i32(k.height);
        w.f32(s.max_range);
        w.zeros(4U);
    }
    for (std::size_t i = 0; i < frames.size(); ++i) {
        char name[L::kSceneNameBytes] = {};
        std::strncpy(name, scene_names.at(i), sizeof(name) - 1U);
        w.raw(name, sizeof(name));
    }
    for (const sim::SimulatedFrame& f : frames) {
        for (const std::vector<float>& depth : f.depth) {
            for (const float d : depth) {
                w.f32(d);
            }
        }
    }
    w.put_u32(L::kBlobSize, static_cast<std::uint32_t>(w.size() + L::kCrcBytes));
    w.u32(crc32(Span<const std::uint8_t>(w.bytes().data(), w.size())));
    return w.bytes();
}

/// Reads the command line: the output folder into @p dir and -1 to run, else
/// the exit status (0 after --help or --version, 2 after a usage error).
int parse_args(int argc, char** argv, std::string& dir) {
    host::CommandLine cli("cellguard-firmware-gen", "cellguard-firmware-gen OUTPUT_DIR",
                          "Renders the firmware's canned inputs on the host into the existing folder\n"
                          "OUTPUT_DIR: prior.cgprior (the prior image, as cellguard-prior writes it)\n"
                          "and frames.bin (four depth sensors at half the paper's resolution, three\n"
                          "scenes), binary, doubles and floats as their exact bits. The checked-in\n"
                          "copies are in apps/firmware/generated.",
                          "Exit status: 0 written, 1 a computation or a write failed, 2 bad command line.");
    cli.argument("OUTPUT_DIR", "the existing folder the two files go into", [&dir](const std::string& v) { dir = v; });
    return cli.parse(argc, argv);
}

/// The background prior of @p g into @p prior: eight frames of the empty
/// cell fused into G_B, as in the controller's tests, then the accessibility
/// analysis with @p params. False (said on stderr) when a step fails.
bool background_prior(const GridGeometry& g, const std::vector<sim::SensorSpec>& sensors,
                      const AccessibilityParams& params, std::vector<std::int16_t>& prior) {
    const SensorModelTable model;
    std::vector<std::int16_t> frame_lo(g.voxel_count());
    std::vector<std::int16_t> bg_lo(g.voxel_count());
    std::vector<std::uint8_t> frame_ob(g.voxel_count());
    std::vector<std::uint8_t> bg_ob(g.voxel_count());
    EvidenceGrid frame =
        EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
    EvidenceGrid bg = EvidenceGrid::make(g, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    bg.clear();
    const sim::SimulatedFrame empty = sim::render_frame(sensors, sim::reference_scene());
    std::vector<std::int16_t> scratch(g.voxel_count());
    for (int i = 0; i < 8; ++i) {
        if (!fuse_background_frame(bg, frame, {empty.readings.data(), empty.readings.size()}, model,
                                   {scratch.data(), scratch.size()})
                 .ok()) {
            static_cast<void>(std::fprintf(stderr, "fusion of the background failed\n"));
            return false;
        }
    }
    const AccessibilityScratchSize size = accessibility_scratch_size(g.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    if (!compute_accessibility_prior(bg, params,
                                     AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
                                     {prior.data(), prior.size()}, {})
             .ok()) {
        static_cast<void>(std::fprintf(stderr, "the accessibility prior failed\n"));
        return false;
    }
    return true;
}

/// @p prior as the prior image file DIR/prior.cgprior; false (said on stderr) when that fails.
bool write_prior_file(const std::string& dir, const GridGeometry& g, const AccessibilityParams& params,
                      const std::vector<std::int16_t>& prior) {
    std::vector<std::uint8_t> image(prior_image_size(g.voxel_count()));
    if (!write_prior_image(g, params, {prior.data(), prior.size()}, {image.data(), image.size()}).ok()) {
        static_cast<void>(std::fprintf(stderr, "write_prior_image failed\n"));
        return false;
    }
    const Result<PriorImageView, PriorImageError> view = load_prior_image({image.data(), image.size()}, g);
    if (!view.ok() || !write_prior_image_file((dir + "/prior.cgprior").c_str(), view.value()).ok()) {
        static_cast<void>(std::fprintf(stderr, "writing prior.cgprior failed\n"));
        return false;
    }
    return true;
}

/// The three scenes' frames as DIR/frames.bin; false (said on stderr) when that fails.
bool write_frames_file(const std::string& dir, const std::vector<sim::SensorSpec>& sensors) {
    const std::vector<const char*> scene_names = {"empty", "person-in-warning-zone", "person-in-protective-zone"};
    const sim::Scene scenes[] = {sim::reference_scene(), with_person(-0.6, 0.6), with_person(0.2, 0.4)};
    std::vector<sim::SimulatedFrame> frames;
    for (const sim::Scene& scene : scenes) {
        frames.push_back(sim::render_frame(sensors, scene));
    }
    if (!write_bytes(dir + "/frames.bin", frames_blob(sensors, scene_names, frames))) {
        static_cast<void>(std::fprintf(stderr, "writing frames.bin failed\n"));
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::string dir;
    const int parse_status = parse_args(argc, argv, dir);
    if (parse_status >= 0) {
        return parse_status;
    }
    const GridGeometry g = paper_grid_geometry();
    const std::vector<sim::SensorSpec> sensors = firmware_sensors();
    const AccessibilityParams params;
    std::vector<std::int16_t> prior(g.voxel_count());
    if (!background_prior(g, sensors, params, prior) || !write_prior_file(dir, g, params, prior) ||
        !write_frames_file(dir, sensors)) {
        return 1;
    }
    static_cast<void>(std::printf("cellguard-firmware-gen: wrote prior.cgprior and frames.bin to %s\n", dir.c_str()));
    return 0;
}
