// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: cellguard-prior (apps/prior), the commissioning tool that turns
// a background into the prior image, the flash source and P(acc)/P(fore) .npy
// files. The tool runs in-process through run_prior_tool, exactly as main() runs it.
#include <doctest/doctest.h>

#if __has_include("cellguard/prior_tool/prior_tool.hpp")

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/io/depth_npy.hpp"
#include "cellguard/host/io/npy.hpp"
#include "cellguard/host/io/pcd.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/prior/prior_image.hpp"
#include "cellguard/prior_tool/prior_tool.hpp"
#include "temp_dir.hpp"

using namespace cellguard;
using namespace cellguard::prior_tool;

using cellguard::test::TempDir;

namespace {

struct Run {
    int status = -1;
    std::string out;
    std::string err;
};

Run run_tool(const std::vector<std::string>& args) {
    std::ostringstream out;
    std::ostringstream err;
    Run r;
    r.status = run_prior_tool(args, out, err, false);
    r.out = out.str();
    r.err = err.str();
    return r;
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::vector<std::uint8_t> bytes;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
        return bytes;
    }
    std::uint8_t buf[65536];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof(buf), f)) > 0) {
        bytes.insert(bytes.end(), buf, buf + n);
    }
    std::fclose(f);
    return bytes;
}

bool write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        return false;
    }
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    return std::fclose(f) == 0 && ok;
}

bool exists(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0;
}

/// The simulated empty paper cell fused over @p frames frames, the way the
/// monitor and cellguard-firmware-gen build it (written out here, not through
/// the tool, so that the tool is checked against lib directly).
void simulated_background(BackgroundGrid& bg, int frames) {
    const GridGeometry g = paper_grid_geometry();
    REQUIRE(bg.allocate(g).ok());
    std::vector<std::int16_t> lo(g.voxel_count());
    std::vector<std::uint8_t> ob(g.voxel_count());
    EvidenceGrid frame = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
    const sim::SimulatedFrame empty = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    const SensorModelTable model;
    std::vector<std::int16_t> scratch(g.voxel_count());
    // The frames are all the same: fused once, accumulated @p frames times (the same G_B, bit for bit).
    frame.clear();
    REQUIRE(fuse_frame(frame, {empty.readings.data(), empty.readings.size()}, model, {scratch.data(), scratch.size()})
                .ok());
    for (int i = 0; i < frames; ++i) {
        REQUIRE(accumulate_background(bg.grid, frame).ok());
    }
}

/// The prior lib computes directly for @p bg.
std::vector<std::int16_t> direct_prior(const EvidenceGrid& bg, const AccessibilityParams& params) {
    const AccessibilityScratchSize size = accessibility_scratch_size(bg.geometry().dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    std::vector<std::int16_t> prior(bg.voxel_count());
    REQUIRE(compute_accessibility_prior(
                bg, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
                {prior.data(), prior.size()}, {})
                .ok());
    return prior;
}

/// The prior values of the image file at @p path, checked against @p g.
std::vector<std::int16_t> image_values(const std::string& path, const GridGeometry& g,
                                       AccessibilityParams* params = nullptr) {
    const std::vector<std::uint8_t> bytes = read_bytes(path);
    const Result<PriorImageView, PriorImageError> view = load_prior_image({bytes.data(), bytes.size()}, g);
    INFO("loader: " << to_string(view.error()));
    REQUIRE(view.ok());
    std::vector<std::int16_t> values(view.value().voxel_count());
    REQUIRE(view.value().copy_to({values.data(), values.size()}).ok());
    if (params != nullptr) {
        *params = view.value().params();
    }
    return values;
}

std::vector<float> read_float_npy(const std::string& path, GridDims dims) {
    std::vector<float> v(static_cast<std::size_t>(dims.nx) * static_cast<std::size_t>(dims.ny) *
                         static_cast<std::size_t>(dims.nz));
    const IoStatus st = read_npy_float32(path.c_str(), dims, {v.data(), v.size()});
    INFO(st.message());
    REQUIRE(st.ok());
    return v;
}

std::vector<std::string> paper_placement() { return {"--origin", "-0.85,-0.75,0", "--voxel-size", "0.05"}; }

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

/// A .npy file with an arbitrary header dict and @p data_bytes zero bytes of data.
std::vector<std::uint8_t> raw_npy(const std::string& dict, std::size_t data_bytes) {
    std::string header = dict;
    while ((10U + header.size() + 1U) % 64U != 0U) {
        header += ' ';
    }
    header += '\n';
    std::string b = "\x93NUMPY";
    b += '\x01';
    b += '\x00';
    b += static_cast<char>(header.size() & 0xFFU);
    b += static_cast<char>(header.size() >> 8U);
    b += header;
    b.append(data_bytes, '\0');
    return std::vector<std::uint8_t>(b.begin(), b.end());
}

}  // namespace

// verifies: SR-PRIOR-015
TEST_CASE(
    "prior tool: the simulated cell gives an image the loader accepts, equal to lib's prior of the same background") {
    TempDir dir("prior-tool");
    const Run r = run_tool({"--simulated", "--out", dir / "out"});
    INFO(r.err);
    REQUIRE(r.status == kExitOk);
    CHECK(r.err.empty());  // no progress bar when stderr is not a terminal
    CHECK(r.out.find("verified:") != std::string::npos);
    CHECK(r.out.find("34 x 30 x 30 voxels of 0.05 m from (-0.85, -0.75, 0)") != std::string::npos);

    AccessibilityParams params;
    const std::vector<std::int16_t> values = image_values(dir / "out/prior.cgprior", paper_grid_geometry(), &params);
    // The paper's defaults are recorded in the header.
    CHECK(params.method == PriorMethod::kProbabilistic);
    CHECK(params.t_b == 0.51);
    CHECK(params.t_e == 0.1);
    CHECK(params.radius_voxels == 2);
    CHECK(params.open_faces == kPaperOpenFaces);
    // A grid of another origin is refused: the geometry is really checked.
    const std::vector<std::uint8_t> bytes = read_bytes(dir / "out/prior.cgprior");
    const GridGeometry shifted =
        GridGeometry::make(Eigen::Vector3d(-0.8, -0.75, 0.0), 0.05, paper_grid_geometry().dims()).value();
    CHECK_FALSE(load_prior_image({bytes.data(), bytes.size()}, shifted).ok());

    BackgroundGrid bg;
    simulated_background(bg, 8);
    CHECK(values == direct_prior(bg.grid, AccessibilityParams{}));

    // The flash source names the same CRC as the image.
    const std::vector<std::uint8_t> src = read_bytes(dir / "out/prior_flash.hpp");
    const std::string text(src.begin(), src.end());
    PriorImageHeader header = read_prior_image_header({bytes.data(), bytes.size()}).value();
    char crc[32];
    std::snprintf(crc, sizeof(crc), "0x%08xU", header.payload_crc);
    CHECK(text.find(std::string("kPayloadCrc = ") + crc) != std::string::npos);
    CHECK(text.find("namespace cellguard_prior {") != std::string::npos);
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: the .npy outputs are float32 of shape (nz, ny, nx) with P(fore) = P(acc) / 2") {
    TempDir dir("prior-tool");
    for (const char* method : {"probabilistic", "thresholded"}) {
        CAPTURE(method);
        const std::string out = dir / method;
        const Run r = run_tool({"--simulated", "--method", method, "--out", out});
        INFO(r.err);
        REQUIRE(r.status == kExitOk);
        const GridGeometry g = paper_grid_geometry();
        for (const char* name : {"p_acc.npy", "p_fore.npy"}) {
            const std::vector<std::uint8_t> file = read_bytes(out + "/" + name);
            NpyHeader h;
            REQUIRE(parse_npy_header(file.data(), file.size(), h).ok());
            CHECK(h.dtype == NpyDtype::kFloat32);
            REQUIRE(h.ndim == 3U);
            CHECK(h.shape[0] == 30U);  // nz
            CHECK(h.shape[1] == 30U);  // ny
            CHECK(h.shape[2] == 34U);  // nx
        }
        const std::vector<float> acc = read_float_npy(out + "/p_acc.npy", g.dims());
        const std::vector<float> fore = read_float_npy(out + "/p_fore.npy", g.dims());
        const std::vector<std::int16_t> prior = image_values(out + "/prior.cgprior", g);
        std::size_t mismatches = 0, out_of_range = 0, inconsistent = 0, accessible = 0;
        for (std::size_t i = 0; i < acc.size(); ++i) {
            mismatches += fore[i] != acc[i] / 2.0F ? 1U : 0U;
            out_of_range += !(acc[i] >= 0.0F && acc[i] <= 1.0F) ? 1U : 0U;
            accessible += acc[i] > 0.0F ? 1U : 0U;
            if (std::string(method) == "thresholded") {
                // P(acc) in {0, 1}; the prior is 0 (P(fore) 0.5) or the sentinel (P(fore) 0).
                inconsistent += (acc[i] == 1.0F && prior[i] == 0) || (acc[i] == 0.0F && prior[i] == kNeverForeground)
                                    ? 0U
                                    : 1U;
            } else {
                // The prior is the log-odds of P(fore), to within the rounding of P(acc) to float.
                const double p = static_cast<double>(fore[i]);
                inconsistent += (p > 1e-30 && std::abs(std::log(p / (1.0 - p)) * 256.0 - prior[i]) > 1.0) ? 1U : 0U;
            }
        }
        CHECK(mismatches == 0U);
        CHECK(out_of_range == 0U);
        CHECK(inconsistent == 0U);
        CHECK(accessible > acc.size() / 2U);  // the empty cell is mostly accessible
        CHECK(accessible < acc.size());       // but not the floor
    }
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: a background .npy round trip gives the prior lib computes directly, for all four methods") {
    TempDir dir("prior-tool");
    BackgroundGrid bg;
    simulated_background(bg, 8);
    const std::string prefix = dir / "bg";
    REQUIRE(write_grid_npy(prefix.c_str(), bg.grid).ok());  // bg_log_odds.npy, bg_probability.npy, bg_observed.npy
    for (const char* method : {"probabilistic", "thresholded", "thresholded-baseline", "probabilistic-baseline"}) {
        CAPTURE(method);
        AccessibilityParams params;
        REQUIRE(parse_method(method, params.method));
        params.radius_voxels = 1;
        params.t_e = 0.2;
        params.open_faces = static_cast<std::uint8_t>(kPaperOpenFaces | kFaceMaxZ);
        const std::vector<std::int16_t> expected = direct_prior(bg.grid, params);
        const std::vector<std::string> analysis = {"--method", method, "--radius",     "1",
                                                   "--te",     "0.2",  "--open-faces", "xmin,xmax,ymin,ymax,zmax"};

        // int16 log-odds; the observed flags come from the sibling file.
        Run r = run_tool(concat(concat({"--background-npy", prefix + "_log_odds.npy", "--out", dir / "i16"}, analysis),
                                paper_placement()));
        INFO(r.err);
        REQUIRE(r.status == kExitOk);
        CHECK(r.out.find(prefix + "_observed.npy") != std::string::npos);
        AccessibilityParams recorded;
        CHECK(image_values(dir / "i16/prior.cgprior", paper_grid_geometry(), &recorded) == expected);
        CHECK(recorded.method == params.method);
        CHECK(recorded.radius_voxels == 1);
        CHECK(recorded.t_e == 0.2);
        CHECK(recorded.open_faces == params.open_faces);

        // float32 probability with explicit observed flags: the same prior.
        r = run_tool(concat(concat({"--background-npy", prefix + "_probability.npy", "--observed",
                                    prefix + "_observed.npy", "--out", dir / "f32"},
                                   analysis),
                            paper_placement()));
        INFO(r.err);
        REQUIRE(r.status == kExitOk);
        CHECK(image_values(dir / "f32/prior.cgprior", paper_grid_geometry()) == expected);
    }
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: without observed flags, voxels with no evidence count as unobserved") {
    TempDir dir("prior-tool");
    BackgroundGrid bg;
    simulated_background(bg, 2);
    // A stretch of unobserved voxels with stale log-odds would be wrong input;
    // here: log-odds 0 and observed in the grid, which the tool cannot know.
    const std::string path = dir / "grid.npy";  // not *_log_odds.npy: no sibling lookup
    REQUIRE(write_npy_int16(path.c_str(), {bg.log_odds.data(), bg.log_odds.size()}, paper_grid_geometry().dims()).ok());
    for (std::size_t i = 0; i < bg.log_odds.size(); ++i) {
        bg.observed[i] = bg.log_odds[i] != 0 ? 1U : 0U;
    }
    const Run r = run_tool(concat({"--background-npy", path, "--out", dir / "out"}, paper_placement()));
    INFO(r.err);
    REQUIRE(r.status == kExitOk);
    CHECK(r.out.find("derived") != std::string::npos);
    CHECK(image_values(dir / "out/prior.cgprior", paper_grid_geometry()) ==
          direct_prior(bg.grid, AccessibilityParams{}));
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: bad input files exit 2 with one line naming the file and the problem, and write nothing") {
    TempDir dir("prior-tool");
    const GridDims dims = paper_grid_geometry().dims();
    const std::size_t n = paper_grid_geometry().voxel_count();
    std::vector<std::uint8_t> flags(n, 1U);
    std::vector<float> probs(n, 0.2F);
    std::vector<std::int16_t> lo(n, -300);

    REQUIRE(write_npy_uint8((dir / "u8.npy").c_str(), {flags.data(), n}, dims).ok());
    REQUIRE(write_bytes(dir / "2d.npy",
                        raw_npy("{'descr': '<i2', 'fortran_order': False, 'shape': (30, 1020), }", 2U * n)));
    REQUIRE(write_bytes(dir / "f64.npy",
                        raw_npy("{'descr': '<f8', 'fortran_order': False, 'shape': (30, 30, 34), }", 8U * n)));
    REQUIRE(write_npy_int16((dir / "trunc.npy").c_str(), {lo.data(), n}, dims).ok());
    REQUIRE(::truncate((dir / "trunc.npy").c_str(), 1000) == 0);
    probs[123] = std::numeric_limits<float>::quiet_NaN();
    REQUIRE(write_npy_float32((dir / "nan.npy").c_str(), {probs.data(), n}, dims).ok());
    probs[123] = 1.5F;
    REQUIRE(write_npy_float32((dir / "big.npy").c_str(), {probs.data(), n}, dims).ok());
    lo[7] = kNeverForeground;
    REQUIRE(write_npy_int16((dir / "sentinel.npy").c_str(), {lo.data(), n}, dims).ok());
    lo[7] = -300;
    REQUIRE(write_npy_int16((dir / "ok.npy").c_str(), {lo.data(), n}, dims).ok());
    flags[9] = 2U;
    REQUIRE(write_npy_uint8((dir / "flags2.npy").c_str(), {flags.data(), n}, dims).ok());
    REQUIRE(write_bytes(dir / "not.npy", {'h', 'e', 'l', 'l', 'o'}));

    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    const std::string out = dir / "out";
    const std::vector<Case> cases = {
        {{"--background-npy", dir / "u8.npy"}, "u8.npy: dtype is uint8"},
        {{"--background-npy", dir / "2d.npy"}, "2d.npy: shape (30, 1020) has 2 dimensions"},
        {{"--background-npy", dir / "f64.npy"}, "f64.npy: npy: dtype"},
        {{"--background-npy", dir / "trunc.npy"}, "trunc.npy: npy: data"},
        {{"--background-npy", dir / "missing.npy"}, "missing.npy: cannot open: No such file or directory"},
        {{"--background-npy", dir.path()}, ": not a regular file"},
        {{"--background-npy", dir / "not.npy"}, "not.npy: npy: input does not start with"},
        {{"--background-npy", dir / "nan.npy"}, "nan.npy: voxel (x 21, y 3, z 0) is NaN"},
        {{"--background-npy", dir / "big.npy"}, "big.npy: voxel (x 21, y 3, z 0) is 1.5, not a probability"},
        {{"--background-npy", dir / "sentinel.npy"}, "sentinel.npy: voxel (x 7, y 0, z 0) holds -32768"},
        {{"--background-npy", dir / "ok.npy", "--observed", dir / "flags2.npy"},
         "flags2.npy: voxel (x 9, y 0, z 0) is 2"},
        {{"--background-npy", dir / "ok.npy", "--observed", dir / "u8-missing.npy"}, "u8-missing.npy: cannot open"},
        {{"--background-npy", dir / "ok.npy", "--dims", "34,30,31"},
         "ok.npy: shape (30, 30, 34) is a 34 x 30 x 30 grid, expected 34 x 30 x 31"},
    };
    for (const Case& c : cases) {
        const Run r = run_tool(concat(concat(c.args, paper_placement()), {"--out", out}));
        CAPTURE(r.err);
        CAPTURE(c.message);
        CHECK(r.status == kExitInputError);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK(r.err.rfind("cellguard-prior: ", 0) == 0);
        CHECK(r.err.find('\n') == r.err.size() - 1U);  // exactly one line
        CHECK_FALSE(exists(out + "/prior.cgprior"));
    }
    // The same good file passes: the refusals above are the files', not the set-up's.
    const Run good = run_tool(concat({"--background-npy", dir / "ok.npy", "--out", out}, paper_placement()));
    INFO(good.err);
    CHECK(good.status == kExitOk);
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: bad option values exit 2 with one line naming the option") {
    TempDir dir("prior-tool");
    const std::string out = dir / "out";
    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    const std::vector<Case> cases = {
        {{"--radius", "9"}, "--radius expects an integer 0..8"},
        {{"--radius", "-1"}, "--radius expects"},
        {{"--radius", "2.5"}, "--radius expects"},
        {{"--te", "1"}, "--te expects a probability strictly between 0 and 1, got '1'"},
        {{"--tb", "nan"}, "--tb expects"},
        {{"--tb", "0"}, "--tb expects"},
        {{"--method", "dijkstra"}, "--method expects"},
        {{"--open-faces", "xmin,up"}, "--open-faces expects"},
        {{"--open-faces", "xmin,xmin"}, "--open-faces expects"},
        {{"--origin", "1,2"}, "--origin expects X,Y,Z"},
        {{"--voxel-size", "-0.05"}, "--voxel-size expects a positive length"},
        {{"--dims", "0,30,30"}, "--dims expects NX,NY,NZ"},
        {{"--background-frames", "0"}, "--background-frames expects"},
        {{"--simulated", "--background-frames", "2"},
         "2 background frame(s) are too few for the probabilistic method: it needs at least 3"},
        {{"--namespace", "not a namespace"}, "--namespace 'not a namespace'"},
        {{"--bogus"}, "unknown argument '--bogus'"},
        {{"--simulated", "--background-npy", "x.npy"}, "--simulated excludes --background-npy"},
        {{"--observed", "x.npy"}, "--observed requires --background-npy"},
        {{"--frames", "somewhere"}, "--frames requires --config"},
        {{"--background-npy", "x.npy"}, "needs the grid's placement"},
        {{"--config", dir / "missing.toml"}, "configuration: "},
    };
    for (const Case& c : cases) {
        const Run r = run_tool(concat(c.args, {"--out", out}));
        CAPTURE(r.err);
        CAPTURE(c.message);
        CHECK(r.status == kExitInputError);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK(r.err.find('\n') == r.err.size() - 1U);
        CHECK_FALSE(exists(out));  // refused before anything is created
    }
    const Run no_value = run_tool({"--out", out, "--radius"});
    CHECK(no_value.status == kExitInputError);
    CHECK(no_value.err.find("--radius needs a value") != std::string::npos);
    const Run no_out = run_tool({"--simulated"});
    CHECK(no_out.status == kExitInputError);
    CHECK(no_out.err.find("--out is required") != std::string::npos);
    const Run help = run_tool({"--help"});
    CHECK(help.status == kExitOk);
    CHECK(help.out.find("--background-npy FILE") != std::string::npos);
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: an output directory that cannot be created exits 1") {
    TempDir dir("prior-tool");
    REQUIRE(write_bytes(dir / "file", {'x'}));
    const Run r = run_tool({"--simulated", "--out", dir / "file"});
    CHECK(r.status == kExitOutputError);
    CHECK(r.err.find("cannot create the output directory") != std::string::npos);
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: recorded .pcd frames with poses from the monitor config give the simulated cell's prior") {
    // The simulated empty cell as recorded point clouds: each depth image back
    // projected into the sensor frame, one folder per sensor of paper-cell.toml.
    TempDir dir("prior-tool");
    const std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const sim::SimulatedFrame frame = sim::render_frame(sensors, sim::reference_scene());
    for (int k = 0; k < 3; ++k) {  // the probabilistic method needs 3 (min_background_frames)
        for (std::size_t s = 0; s < sensors.size(); ++s) {
            const PinholeIntrinsics in = sensors[s].intrinsics();
            std::vector<PcdPoint> pts;
            for (std::int32_t v = 0; v < in.height; ++v) {
                for (std::int32_t u = 0; u < in.width; ++u) {
                    const float d = frame.depth[s][static_cast<std::size_t>(v * in.width + u)];
                    if (d > 0.0F) {
                        pts.push_back(PcdPoint{static_cast<float>((u - in.cx) / in.fx * d),
                                               static_cast<float>((v - in.cy) / in.fy * d), d});
                    }
                }
            }
            const std::string folder = dir / ("frames/" + sensors[s].name);
            std::filesystem::create_directories(folder);
            REQUIRE(write_pcd((folder + "/" + std::to_string(k) + ".pcd").c_str(), {pts.data(), pts.size()},
                              static_cast<std::uint32_t>(pts.size()), 1U, PcdViewpoint{}, PcdDataKind::kBinary)
                        .ok());
        }
    }
    const std::string config = std::string(CELLGUARD_SOURCE_DIR) + "/apps/monitor/config/paper-cell.toml";
    const Run r = run_tool({"--frames", dir / "frames", "--config", config, "--out", dir / "rec"});
    INFO(r.err);
    REQUIRE(r.status == kExitOk);
    CHECK(r.out.find("recorded frames (3;") != std::string::npos);
    const Run s = run_tool({"--simulated", "--background-frames", "3", "--out", dir / "sim"});
    REQUIRE(s.status == kExitOk);
    const std::vector<std::int16_t> rec = image_values(dir / "rec/prior.cgprior", paper_grid_geometry());
    const std::vector<std::int16_t> simp = image_values(dir / "sim/prior.cgprior", paper_grid_geometry());
    // Points vs depth pixels differ only by float rounding of the back projection.
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rec.size(); ++i) {
        differ += std::abs(static_cast<int>(rec[i]) - static_cast<int>(simp[i])) > 16 ? 1U : 0U;
    }
    CHECK(differ <= rec.size() / 200U);

    // A folder that names no sensor, and a cloud with a VIEWPOINT, are refused.
    std::filesystem::create_directories(dir / "frames/lidar-c");
    Run bad = run_tool({"--frames", dir / "frames", "--config", config, "--out", dir / "bad"});
    CHECK(bad.status == kExitInputError);
    CHECK(bad.err.find("folder 'lidar-c' names no sensor") != std::string::npos);
    std::filesystem::remove(dir / "frames/lidar-c");
    const PcdPoint p{0.0F, 0.0F, 1.0F};
    PcdViewpoint vp;
    vp.tx = 1.0;
    REQUIRE(write_pcd((dir / "vp.pcd").c_str(), {&p, 1}, 1U, 1U, vp, PcdDataKind::kAscii).ok());
    bad = run_tool({"--frame", "lidar-a=" + (dir / "vp.pcd"), "--config", config, "--method", "thresholded", "--out",
                    dir / "bad"});
    CHECK(bad.status == kExitInputError);
    CHECK(bad.err.find("vp.pcd: VIEWPOINT (1.000, 0.000, 0.000) is not the pose of sensor 'lidar-a'") !=
          std::string::npos);
    // The sensor's own pose as VIEWPOINT is accepted. (One frame each: the
    // thresholded method, which needs one, so that the frame's checks run.)
    const Eigen::Isometry3d pose = sensors[0].pose();
    const Eigen::Quaterniond q(pose.linear());
    vp = PcdViewpoint{
        pose.translation().x(), pose.translation().y(), pose.translation().z(), q.w(), q.x(), q.y(), q.z()};
    REQUIRE(write_pcd((dir / "vp.pcd").c_str(), {&p, 1}, 1U, 1U, vp, PcdDataKind::kAscii).ok());
    const Run good = run_tool(
        {"--frame", "lidar-a=" + (dir / "vp.pcd"), "--config", config, "--method", "thresholded", "--out", dir / "vp"});
    INFO(good.err);
    CHECK(good.status == kExitOk);
    // More points than the sensor's image has pixels: not a frame of this sensor.
    std::vector<PcdPoint> many(176U * 144U + 1U, PcdPoint{0.0F, 0.0F, 1.0F});
    REQUIRE(write_pcd((dir / "many.pcd").c_str(), {many.data(), many.size()}, static_cast<std::uint32_t>(many.size()),
                      1U, PcdViewpoint{}, PcdDataKind::kBinary)
                .ok());
    bad = run_tool({"--frame", "lidar-a=" + (dir / "many.pcd"), "--config", config, "--method", "thresholded", "--out",
                    dir / "bad"});
    CHECK(bad.status == kExitInputError);
    CHECK(bad.err.find("many.pcd: 25345 points, more than sensor 'lidar-a' delivers (176 x 144)") != std::string::npos);
    bad = run_tool({"--frame", "lidar-z=" + (dir / "vp.pcd"), "--config", config, "--out", dir / "bad"});
    CHECK(bad.status == kExitInputError);
    CHECK(bad.err.find("no sensor 'lidar-z'") != std::string::npos);
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: --config-frames replays the configuration's pcd_files like --frames") {
    TempDir dir("prior-tool");
    const std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const sim::SimulatedFrame frame = sim::render_frame(sensors, sim::reference_scene());
    for (std::size_t s = 0; s < sensors.size(); ++s) {
        const PinholeIntrinsics in = sensors[s].intrinsics();
        std::vector<PcdPoint> pts;
        for (std::int32_t v = 0; v < in.height; ++v) {
            for (std::int32_t u = 0; u < in.width; ++u) {
                const float d = frame.depth[s][static_cast<std::size_t>(v * in.width + u)];
                if (d > 0.0F) {
                    pts.push_back(PcdPoint{static_cast<float>((u - in.cx) / in.fx * d),
                                           static_cast<float>((v - in.cy) / in.fy * d), d});
                }
            }
        }
        std::filesystem::create_directories(dir / ("frames/" + sensors[s].name));
        REQUIRE(write_pcd((dir / ("frames/" + sensors[s].name + "/0.pcd")).c_str(), {pts.data(), pts.size()},
                          static_cast<std::uint32_t>(pts.size()), 1U, PcdViewpoint{}, PcdDataKind::kBinaryCompressed)
                    .ok());
    }
    // paper-cell.toml with pcd_files (relative to the config's folder) in every sensor table.
    const std::vector<std::uint8_t> toml = read_bytes(std::string(CELLGUARD_SOURCE_DIR) +
                                                      "/apps/monitor/config/paper-cell.toml");
    std::istringstream in(std::string(toml.begin(), toml.end()));
    std::string line, text, name;
    while (std::getline(in, line)) {
        if (line.rfind("background_match = ", 0) == 0) {
            line = "background_match = 0";  // recorded sensors have no view of the empty cell (SR-BKG-005)
        }
        text += line + "\n";
        if (line.rfind("name = \"", 0) == 0) {
            name = line.substr(8, line.find('"', 8) - 8);
        }
        if (line.rfind("max_range = ", 0) == 0) {
            text += "pcd_files = [\"frames/" + name + "/0.pcd\"]\n";
        }
    }
    text += "background_view_check = \"recorded sensors without a view of the empty cell\"\n";  // ends [opt_out]
    REQUIRE(write_bytes(dir / "cell.toml", std::vector<std::uint8_t>(text.begin(), text.end())));
    // One recorded frame is too few for the probabilistic method (3), enough for the thresholded one.
    const Run few = run_tool({"--config-frames", "--config", dir / "cell.toml", "--out", dir / "few"});
    CHECK(few.status == kExitInputError);
    CHECK(few.err.find("1 background frame(s) are too few for the probabilistic method") != std::string::npos);
    const Run a = run_tool(
        {"--config-frames", "--config", dir / "cell.toml", "--method", "thresholded", "--out", dir / "a"});
    INFO(a.err);
    REQUIRE(a.status == kExitOk);
    CHECK(a.out.find("recorded frames (1;") != std::string::npos);
    const Run b = run_tool(
        {"--frames", dir / "frames", "--config", dir / "cell.toml", "--method", "thresholded", "--out", dir / "b"});
    REQUIRE(b.status == kExitOk);
    CHECK(read_bytes(dir / "a/prior.cgprior") == read_bytes(dir / "b/prior.cgprior"));
    // The configuration without pcd_files has nothing to replay.
    const Run none = run_tool({"--config-frames", "--config",
                               std::string(CELLGUARD_SOURCE_DIR) + "/apps/monitor/config/paper-cell.toml", "--out",
                               dir / "c"});
    CHECK(none.status == kExitInputError);
    CHECK(none.err.find("have no pcd_files") != std::string::npos);
}

// verifies: SR-PRIOR-015, SR-SYS-011
TEST_CASE("prior tool: --config-frames replays depth_files through the camera path, as the simulated frames") {
    TempDir dir("prior-tool");
    const std::vector<sim::SensorSpec> sensors = sim::paper_sensors();
    const sim::SimulatedFrame frame = sim::render_frame(sensors, sim::reference_scene());
    const std::vector<std::uint8_t> toml = read_bytes(std::string(CELLGUARD_SOURCE_DIR) +
                                                      "/apps/monitor/config/paper-cell.toml");
    std::istringstream in(std::string(toml.begin(), toml.end()));
    std::string line, text, name;
    std::size_t s = 0U;
    while (std::getline(in, line)) {
        text += line + "\n";
        if (line.rfind("name = \"", 0) == 0) {
            name = line.substr(8, line.find('"', 8) - 8);
        }
        if (line.rfind("max_range = ", 0) == 0) {  // the end of a sensor table: its recording, 3 frames
            REQUIRE(s < sensors.size());
            REQUIRE(sensors[s].name == name);
            std::filesystem::create_directories(dir / ("rec/" + name));
            for (int k = 0; k < 3; ++k) {
                const std::vector<float>& d = frame.depth[s];
                REQUIRE(write_npy_depth_f32((dir / ("rec/" + name + "/" + std::to_string(k) + ".npy")).c_str(),
                                            {d.data(), d.size()}, sensors[s].width, sensors[s].height)
                            .ok());
            }
            text += "depth_files = \"rec/" + name + "\"\n";
            ++s;
        }
    }
    REQUIRE(s == sensors.size());
    REQUIRE(write_bytes(dir / "cell.toml", std::vector<std::uint8_t>(text.begin(), text.end())));
    const Run recorded = run_tool({"--config-frames", "--config", dir / "cell.toml", "--out", dir / "a"});
    INFO(recorded.err);
    REQUIRE(recorded.status == kExitOk);
    CHECK(recorded.out.find("recorded frames (3; files per sensor: lidar-a 3,") != std::string::npos);
    const Run simulated = run_tool(
        {"--simulated", "--background-frames", "3", "--config", dir / "cell.toml", "--out", dir / "b"});
    INFO(simulated.err);
    REQUIRE(simulated.status == kExitOk);
    CHECK(read_bytes(dir / "a/prior.cgprior") == read_bytes(dir / "b/prior.cgprior"));
    // One sensor's recording of another resolution: refused when the configuration loads, naming the file.
    const std::vector<float> small(100U, 1.0F);
    REQUIRE(write_npy_depth_f32((dir / "rec/lidar-a/9.npy").c_str(), {small.data(), small.size()}, 10, 10).ok());
    const Run bad = run_tool({"--config-frames", "--config", dir / "cell.toml", "--out", dir / "c"});
    CHECK(bad.status != kExitOk);
    CHECK(bad.err.find("rec/lidar-a/9.npy") != std::string::npos);
}

// verifies: SR-PRIOR-015
TEST_CASE("prior tool: parse_open_faces and method names round trip") {
    std::uint8_t faces = 0;
    CHECK(parse_open_faces("sides", faces));
    CHECK(faces == kPaperOpenFaces);
    CHECK(open_faces_list(faces) == "xmin,xmax,ymin,ymax");
    CHECK(parse_open_faces("zmin,xmax", faces));
    CHECK(faces == (kFaceMinZ | kFaceMaxX));
    CHECK(parse_open_faces("none", faces));
    CHECK(faces == 0U);
    CHECK(open_faces_list(0U) == "none");
    CHECK_FALSE(parse_open_faces("", faces));
    CHECK_FALSE(parse_open_faces("xmin,", faces));
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                PriorMethod::kThresholdedBaseline, PriorMethod::kProbabilisticBaseline}) {
        PriorMethod back = PriorMethod::kThresholded;
        CHECK(parse_method(method_name(m), back));
        CHECK(back == m);
    }
}

#endif  // __has_include prior_tool.hpp
