// cellguard-firmware-gen: renders the firmware's canned inputs on the host.
// Usage: cellguard-firmware-gen OUTPUT_DIR (and --help, --version)
// Writes firmware_prior.hpp (write_prior_source_file), prior_values.hpp (the
// same prior as an int16 array) and canned_frames.hpp (four depth sensors at
// half the paper's resolution, three scenes). Every double and float
// is written as a hexadecimal literal, so the targets read the exact bits.
#include <cstdio>
#include <string>
#include <vector>

#include "cellguard/prior/accessibility.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/prior_files.hpp"
#include "cellguard/prior/prior_image.hpp"
#include "cellguard/host/sim/workcell.hpp"

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

bool write_text(const std::string& path, const std::string& text) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) return false;
    const bool ok = std::fwrite(text.data(), 1U, text.size(), f) == text.size();
    return std::fclose(f) == 0 && ok;
}

std::string hex_double(double v) {
    char b[64];
    std::snprintf(b, sizeof(b), "%a", v);
    return b;
}

std::string hex_float(float v) {
    char b[64];
    std::snprintf(b, sizeof(b), "%aF", static_cast<double>(v));
    return b;
}

/// Reads the command line: the output folder into @p dir and -1 to run, else
/// the exit status (0 after --help or --version, 2 after a usage error).
int parse_args(int argc, char** argv, std::string& dir) {
    host::CommandLine cli("cellguard-firmware-gen", "cellguard-firmware-gen OUTPUT_DIR",
                          "Renders the firmware's canned inputs on the host into the existing folder\n"
                          "OUTPUT_DIR: firmware_prior.hpp (the prior image as flash source),\n"
                          "prior_values.hpp (the same prior as an int16 array) and canned_frames.hpp\n"
                          "(four depth sensors at half the paper's resolution, three scenes), every\n"
                          "double and float as a hexadecimal literal. The checked-in copies are in\n"
                          "apps/firmware/generated.",
                          "Exit status: 0 written, 1 a computation or a write failed, 2 bad command line.");
    cli.argument("OUTPUT_DIR", "the existing folder the three headers go into",
                 [&dir](const std::string& v) { dir = v; });
    return cli.parse(argc, argv);
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
    const SensorModelTable model;

    // The background prior: eight frames of the empty cell, as in the controller's tests.
    std::vector<std::int16_t> frame_lo(g.voxel_count()), bg_lo(g.voxel_count()), prior(g.voxel_count());
    std::vector<std::uint8_t> frame_ob(g.voxel_count()), bg_ob(g.voxel_count());
    EvidenceGrid frame = EvidenceGrid::make(g, {frame_lo.data(), frame_lo.size()}, {frame_ob.data(), frame_ob.size()}).value();
    EvidenceGrid bg = EvidenceGrid::make(g, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    bg.clear();
    const sim::SimulatedFrame empty = sim::render_frame(sensors, sim::reference_scene());
    std::vector<std::int16_t> scratch(g.voxel_count());
    for (int i = 0; i < 8; ++i) {
        if (!fuse_background_frame(bg, frame, {empty.readings.data(), empty.readings.size()}, model,
                                   {scratch.data(), scratch.size()})
                 .ok()) {
            std::fprintf(stderr, "fusion of the background failed\n");
            return 1;
        }
    }
    const AccessibilityParams params;
    const AccessibilityScratchSize size = accessibility_scratch_size(g.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    if (!compute_accessibility_prior(bg, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
                                     {prior.data(), prior.size()}, {})
             .ok()) {
        std::fprintf(stderr, "the accessibility prior failed\n");
        return 1;
    }
    std::vector<std::uint8_t> image(prior_image_size(g.voxel_count()));
    if (!write_prior_image(g, params, {prior.data(), prior.size()}, {image.data(), image.size()}).ok()) {
        std::fprintf(stderr, "write_prior_image failed\n");
        return 1;
    }
    const Result<PriorImageView> view = load_prior_image({image.data(), image.size()}, g);
    PriorSourceOptions options;
    options.name_space = "cellguard_firmware::prior";
    options.config_header = "cellguard/firmware/grid_config.hpp";
    if (!view.ok() || !write_prior_source_file((dir + "/firmware_prior.hpp").c_str(), view.value(), options).ok()) {
        std::fprintf(stderr, "writing firmware_prior.hpp failed\n");
        return 1;
    }

    std::string values =
        "// Generated by cellguard-firmware-gen (apps/firmware/src/generate.cpp). Do not edit.\n"
        "// The prior of firmware_prior.hpp as int16 values (linear index order), a const\n"
        "// array the SafetyController reads in place (flash on the MCU); run_scenario\n"
        "// checks it value by value against the CRC-checked image at start-up.\n"
        "#ifndef CELLGUARD_FIRMWARE_PRIOR_VALUES_HPP\n#define CELLGUARD_FIRMWARE_PRIOR_VALUES_HPP\n\n"
        "#include <cstdint>\n\nnamespace cellguard_firmware::prior {\n\n"
        "/// One prior value per voxel.\ninline constexpr std::int16_t kValues[" +
        std::to_string(prior.size()) + "] = {\n";
    for (std::size_t i = 0; i < prior.size(); ++i) {
        values += (i % 16U == 0U ? "    " : " ") + std::to_string(prior[i]) + ",";
        if (i % 16U == 15U || i + 1U == prior.size()) values += "\n";
    }
    values += "};\n\n}  // namespace cellguard_firmware::prior\n\n#endif  // CELLGUARD_FIRMWARE_PRIOR_VALUES_HPP\n";
    if (!write_text(dir + "/prior_values.hpp", values)) {
        std::fprintf(stderr, "writing prior_values.hpp failed\n");
        return 1;
    }

    const char* scene_names[] = {"empty", "person-in-warning-zone", "person-in-protective-zone"};
    const sim::Scene scenes[] = {sim::reference_scene(), with_person(-0.6, 0.6), with_person(0.2, 0.4)};
    std::string out =
        "// Generated by cellguard-firmware-gen (apps/firmware/src/generate.cpp). Do not edit.\n"
        "// The firmware's canned depth frames: the paper's four sensors at half\n"
        "// their resolution, three scenes of the simulated workcell. Poses and\n"
        "// intrinsics are binary64, depths binary32, as exact hexadecimal literals.\n"
        "#ifndef CELLGUARD_FIRMWARE_CANNED_FRAMES_HPP\n#define CELLGUARD_FIRMWARE_CANNED_FRAMES_HPP\n\n"
        "#include <cstddef>\n#include <cstdint>\n\nnamespace cellguard_firmware::canned {\n\n"
        "/// A depth sensor: pose rows (3 x 4, sensor -> workcell), pinhole intrinsics, range.\n"
        "struct CannedSensor {\n    double pose[12];\n    double fx, fy, cx, cy;\n    std::int32_t width, height;\n"
        "    float max_range;\n};\n\n/// Number of sensors.\ninline constexpr std::size_t kSensorCount = " +
        std::to_string(sensors.size()) + "U;\n/// Number of scenes.\ninline constexpr std::size_t kSceneCount = 3U;\n\n"
        "/// The sensors.\ninline constexpr CannedSensor kSensors[kSensorCount] = {\n";
    for (const sim::SensorSpec& s : sensors) {
        const Eigen::Matrix4d m = s.pose().matrix();
        const PinholeIntrinsics k = s.intrinsics();
        out += "    {{";
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) out += hex_double(m(r, c)) + (r == 2 && c == 3 ? "" : ", ");
        }
        out += "}, " + hex_double(k.fx) + ", " + hex_double(k.fy) + ", " + hex_double(k.cx) + ", " + hex_double(k.cy) +
               ", " + std::to_string(k.width) + ", " + std::to_string(k.height) + ", " + hex_float(s.max_range) + "},  // " +
               s.name + "\n";
    }
    out += "};\n\n/// Scene names.\ninline constexpr const char* kSceneNames[kSceneCount] = {";
    for (const char* n : scene_names) out += std::string("\"") + n + "\", ";
    out += "};\n\n";
    std::string table = "/// Depth image of sensor s in scene i: kDepth[i][s], width * height values, row-major.\n"
                        "inline constexpr const float* kDepth[kSceneCount][kSensorCount] = {\n";
    for (std::size_t i = 0; i < 3; ++i) {
        const sim::SimulatedFrame f = sim::render_frame(sensors, scenes[i]);
        table += "    {";
        for (std::size_t s = 0; s < sensors.size(); ++s) {
            const std::string name = "kDepth" + std::to_string(i) + "_" + std::to_string(s);
            out += "/// Scene " + std::to_string(i) + " (" + scene_names[i] + "), sensor " + sensors[s].name + ".\n";
            out += "inline constexpr float " + name + "[" + std::to_string(f.depth[s].size()) + "] = {\n";
            for (std::size_t p = 0; p < f.depth[s].size(); ++p) {
                out += (p % 8U == 0U ? "    " : " ") + hex_float(f.depth[s][p]) + ",";
                if (p % 8U == 7U || p + 1U == f.depth[s].size()) out += "\n";
            }
            out += "};\n";
            table += name + ", ";
        }
        table += "},\n";
    }
    out += table + "};\n\n}  // namespace cellguard_firmware::canned\n\n#endif  // CELLGUARD_FIRMWARE_CANNED_FRAMES_HPP\n";
    if (!write_text(dir + "/canned_frames.hpp", out)) {
        std::fprintf(stderr, "writing canned_frames.hpp failed\n");
        return 1;
    }
    std::printf("cellguard-firmware-gen: wrote firmware_prior.hpp, prior_values.hpp, canned_frames.hpp to %s\n", dir.c_str());
    return 0;
}
