// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-prior: the background of an empty cell -> the accessibility prior
// as an image file, flash source and .npy files. See prior_tool.hpp.
#include "cellguard/prior_tool/prior_tool.hpp"

#include <sys/stat.h>
#include <sys/types.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/depth_input.hpp"
#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/npy.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/prior/prior_image.hpp"

namespace cellguard::prior_tool {

namespace {

/// "(x, y, z)" of linear index @p i in @p dims.
std::string voxel_name(std::size_t i, GridDims dims) {
    const auto nx = static_cast<std::size_t>(dims.nx);
    const auto ny = static_cast<std::size_t>(dims.ny);
    return "(x " + std::to_string(i % nx) + ", y " + std::to_string((i / nx) % ny) + ", z " +
           std::to_string(i / (nx * ny)) + ")";
}

std::string join_path(const std::string& dir, const char* name) {
    if (dir.empty() || dir.back() == '/') {
        return dir + name;
    }
    return dir + "/" + name;
}

/// Reads the .npy preamble and header of @p path (at most the largest header
/// the reader accepts) and parses it.
IoStatus read_npy_file_header(const std::string& path, NpyHeader& header, std::uint64_t& file_size) {
    const host::FilePtr f = host::open_file(path.c_str(), "rb");
    if (!f) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open: %s", path.c_str(),
                                 std::strerror(errno));
    }
    struct stat st {};
    if (fstat(fileno(f.get()), &st) != 0 || !S_ISREG(st.st_mode)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: not a regular file", path.c_str());
    }
    file_size = static_cast<std::uint64_t>(st.st_size);
    std::vector<std::uint8_t> head(kNpyPreambleV2 + kNpyMaxHeaderBytes);
    const std::size_t n = std::fread(head.data(), 1U, head.size(), f.get());
    const bool read_error = std::ferror(f.get()) != 0;
    if (read_error) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot read", path.c_str());
    }
    return parse_npy_header(head.data(), n, header).prefixed(path.c_str());
}

std::string shape_text(const NpyHeader& h) {
    std::string s = "(";
    for (std::size_t d = 0U; d < h.ndim; ++d) {
        s += (d == 0U ? "" : ", ") + std::to_string(h.shape[d]);
    }
    return s + (h.ndim == 1U ? ",)" : ")");
}

}  // namespace

const char* method_name(PriorMethod method) noexcept { return sim::method_name(method); }

bool parse_method(const std::string& text, PriorMethod& method) noexcept {
    for (const PriorMethod m : {PriorMethod::kThresholded, PriorMethod::kProbabilistic,
                                PriorMethod::kThresholdedBaseline, PriorMethod::kProbabilisticBaseline}) {
        if (text == method_name(m)) {
            method = m;
            return true;
        }
    }
    return false;
}

namespace {
constexpr const char* kFaceNames[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
}  // namespace

bool parse_open_faces(const std::string& text, std::uint8_t& faces) {
    if (text == "sides") {
        faces = kPaperOpenFaces;
        return true;
    }
    if (text == "all") {
        faces = kAllFaces;
        return true;
    }
    if (text == "none") {
        faces = 0U;
        return true;
    }
    unsigned bits = 0U;
    std::size_t start = 0U;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        bool known = false;
        for (unsigned b = 0U; b < 6U; ++b) {
            if (item == kFaceNames[b]) {
                if ((bits & (1U << b)) != 0U) {
                    return false;  // named twice
                }
                bits |= 1U << b;
                known = true;
            }
        }
        if (!known) {
            return false;
        }
        start = comma + 1U;
    }
    faces = static_cast<std::uint8_t>(bits);
    return true;
}

std::string open_faces_list(std::uint8_t faces) {
    std::string s;
    for (unsigned b = 0U; b < 6U; ++b) {
        if ((static_cast<unsigned>(faces) & (1U << b)) != 0U) {
            s += (s.empty() ? "" : ",");
            s += kFaceNames[b];
        }
    }
    return s.empty() ? "none" : s;
}

IoStatus BackgroundGrid::allocate(const GridGeometry& geometry) {
    if (geometry.voxel_count() == 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "background: empty grid");
    }
    log_odds.assign(geometry.voxel_count(), kLogOddsUnknown);
    observed.assign(geometry.voxel_count(), 0U);
    const Result<EvidenceGrid> g = EvidenceGrid::make(geometry, {log_odds.data(), log_odds.size()},
                                                      {observed.data(), observed.size()});
    if (!g.ok()) {
        return IoStatus::failure(g.error(), "background: %s", to_string(g.error()));
    }
    grid = g.value();
    return IoStatus{};
}

namespace {

/// The background file's dtype and shape (int16 or float32, (nz, ny, nx)) as a grid's @p dims, checked against
/// @p placement when it fixes them.
IoStatus check_background_shape(const std::string& path, const NpyHeader& h, const NpyPlacement& placement,
                                GridDims& dims) {
    if (h.dtype == NpyDtype::kUInt8) {
        return IoStatus::failure(ErrorCode::kUnsupportedType,
                                 "%s: dtype is uint8 ('|u1', observed flags?); a background grid is int16 log-odds "
                                 "('<i2') or float32 probability ('<f4')",
                                 path.c_str());
    }
    if (h.ndim != 3U) {
        return IoStatus::failure(ErrorCode::kGeometryMismatch,
                                 "%s: shape %s has %zu dimensions; a grid has 3, (nz, ny, nx)", path.c_str(),
                                 shape_text(h).c_str(), h.ndim);
    }
    for (std::size_t d = 0U; d < 3U; ++d) {
        if (h.shape[d] < 1U || h.shape[d] > static_cast<std::uint64_t>(kMaxDimension)) {
            return IoStatus::failure(ErrorCode::kGeometryMismatch, "%s: shape %s: every extent must be 1..%d",
                                     path.c_str(), shape_text(h).c_str(), kMaxDimension);
        }
    }
    dims = GridDims{static_cast<std::int32_t>(h.shape[2]), static_cast<std::int32_t>(h.shape[1]),
                    static_cast<std::int32_t>(h.shape[0])};
    if (placement.check_dims && !(dims == placement.dims)) {
        return IoStatus::failure(ErrorCode::kGeometryMismatch,
                                 "%s: shape %s is a %d x %d x %d grid, expected %d x %d x %d (nx x ny x nz)",
                                 path.c_str(), shape_text(h).c_str(), dims.nx, dims.ny, dims.nz, placement.dims.nx,
                                 placement.dims.ny, placement.dims.nz);
    }
    return IoStatus{};
}

/// int16 log-odds as they are; the prior's "never foreground" sentinel is refused.
IoStatus read_log_odds_background(const std::string& path, GridDims dims, BackgroundGrid& bg) {
    const std::size_t n = bg.log_odds.size();
    const IoStatus st = read_npy_int16(path.c_str(), dims, {bg.log_odds.data(), n});
    if (!st.ok()) {
        return st;
    }
    for (std::size_t i = 0U; i < n; ++i) {
        if (bg.log_odds[i] == kNeverForeground) {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "%s: voxel %s holds -32768, the prior's \"never foreground\" sentinel; "
                                     "a background grid never does (is this a prior?)",
                                     path.c_str(), voxel_name(i, dims).c_str());
        }
    }
    return IoStatus{};
}

/// float32 probabilities in [0, 1], converted to log-odds (0 to the lowest log-odds).
IoStatus read_probability_background(const std::string& path, GridDims dims, BackgroundGrid& bg) {
    const std::size_t n = bg.log_odds.size();
    std::vector<float> p(n);
    const IoStatus st = read_npy_float32(path.c_str(), dims, {p.data(), n});
    if (!st.ok()) {
        return st;
    }
    for (std::size_t i = 0U; i < n; ++i) {
        const float v = p[i];
        if (!std::isfinite(v)) {
            return IoStatus::failure(ErrorCode::kNonFiniteValue, "%s: voxel %s is %s; probabilities must be finite",
                                     path.c_str(), voxel_name(i, dims).c_str(), std::isnan(v) ? "NaN" : "infinite");
        }
        if (v < 0.0F || v > 1.0F) {
            return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: voxel %s is %g, not a probability in [0, 1]",
                                     path.c_str(), voxel_name(i, dims).c_str(), static_cast<double>(v));
        }
        bg.log_odds[i] = v == 0.0F ? kLogOddsMin : log_odds_from_probability(static_cast<double>(v));
    }
    return IoStatus{};
}

/// The observed flags (0 or 1) from their own file.
IoStatus read_observed_flags(const std::string& observed_path, GridDims dims, BackgroundGrid& bg) {
    const std::size_t n = bg.observed.size();
    const IoStatus st = read_npy_uint8(observed_path.c_str(), dims, {bg.observed.data(), n});
    if (!st.ok()) {
        return st;
    }
    for (std::size_t i = 0U; i < n; ++i) {
        if (bg.observed[i] > 1U) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "%s: voxel %s is %u; observed flags are 0 or 1",
                                     observed_path.c_str(), voxel_name(i, dims).c_str(),
                                     static_cast<unsigned>(bg.observed[i]));
        }
    }
    return IoStatus{};
}

}  // namespace

IoStatus load_background_npy(const std::string& path, const std::string& observed_path, const NpyPlacement& placement,
                             BackgroundGrid& out, NpyBackgroundInfo& info) {
    out = BackgroundGrid{};
    info = NpyBackgroundInfo{};
    NpyHeader h;
    std::uint64_t file_size = 0U;
    IoStatus st = read_npy_file_header(path, h, file_size);
    if (!st.ok()) {
        return st;
    }
    GridDims dims;
    st = check_background_shape(path, h, placement, dims);
    if (!st.ok()) {
        return st;
    }
    const Result<GridGeometry> geometry = GridGeometry::make(placement.origin, placement.voxel_size, dims);
    if (!geometry.ok()) {
        return IoStatus::failure(geometry.error(), "%s: a %d x %d x %d grid with voxel size %g: %s", path.c_str(),
                                 dims.nx, dims.ny, dims.nz, placement.voxel_size, to_string(geometry.error()));
    }
    st = check_npy_layout(h, h.dtype, dims, file_size);  // the file's size, before allocating for it
    if (!st.ok()) {
        return st.prefixed(path.c_str());
    }
    BackgroundGrid bg;
    st = bg.allocate(geometry.value());
    if (!st.ok()) {
        return st.prefixed(path.c_str());
    }
    const std::size_t n = bg.log_odds.size();
    if (h.dtype == NpyDtype::kInt16) {
        st = read_log_odds_background(path, dims, bg);
    } else {
        info.float_input = true;
        st = read_probability_background(path, dims, bg);
    }
    if (!st.ok()) {
        return st;
    }
    if (!observed_path.empty()) {
        st = read_observed_flags(observed_path, dims, bg);
        if (!st.ok()) {
            return st;
        }
        info.observed_source = observed_path;
    } else {
        for (std::size_t i = 0U; i < n; ++i) {
            bg.observed[i] = bg.log_odds[i] != kLogOddsUnknown ? 1U : 0U;
        }
        info.observed_source = "derived: voxels without evidence (log-odds 0) count as unobserved";
    }
    info.observed_voxels = bg.grid.observed_count();
    out = std::move(bg);
    return IoStatus{};
}

SimulatedFrameSource::SimulatedFrameSource(std::size_t frames)
    : rendered_(sim::render_frame(sim::paper_sensors(), sim::reference_scene())), frames_(frames) {}

IoStatus SimulatedFrameSource::frame(std::size_t k, std::vector<SensorReading>& readings) {
    if (k >= frames_) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "simulated frame %zu of %zu", k, frames_);
    }
    readings = rendered_.readings;
    return IoStatus{};
}

RecordedFrameSource::RecordedFrameSource(const std::vector<RecordedSensor>& sensors) {
    for (const RecordedSensor& s : sensors) {
        if (!s.recording.files.empty()) {
            cell::CameraReadingParams p;
            p.pose = s.pose;
            p.intrinsics = s.intrinsics;
            p.depth_scale_m = static_cast<float>(s.recording.depth_scale_m);
            p.depth_offset_m = static_cast<float>(s.recording.depth_offset_m);
            p.max_range = s.max_range;
            file_counts_.push_back(s.recording.files.size());
            sources_.push_back(
                std::make_unique<cell::DepthFileFrameSource>(s.name, s.recording.files, p, s.recording.raw));
        } else if (!s.files.empty()) {
            file_counts_.push_back(s.files.size());
            sources_.push_back(
                std::make_unique<cell::PcdFrameSource>(s.name, s.files, s.pose, s.width, s.height, s.max_range));
        } else {
            continue;
        }
        frames_ = std::max(frames_, file_counts_.back());
        names_.push_back(s.name);
    }
}

IoStatus RecordedFrameSource::frame(std::size_t k, std::vector<SensorReading>& readings) {
    readings.clear();
    for (std::size_t s = 0U; s < sources_.size(); ++s) {
        if (k >= file_counts_[s]) {
            continue;
        }
        SensorReading r;
        cell::FrameStatus status;
        if (!sources_[s]->load_frame(k, r, status)) {
            // The readers' messages start with the path already.
            const std::string file = status.file;
            const std::string reason = status.reason;
            const bool named = reason.rfind(file, 0) == 0;
            return IoStatus::failure(ErrorCode::kMalformedInput, "%s%s%s (sensor '%s')", named ? "" : file.c_str(),
                                     named ? "" : ": ", reason.c_str(), names_[s].c_str());
        }
        readings.push_back(r);
    }
    return IoStatus{};
}

IoStatus sensors_from_config(const std::string& config_path, bool with_pcd_files, std::vector<RecordedSensor>& sensors,
                             GridGeometry& grid, int& background_frames) {
    const cell::ConfigLoad load = cell::load_monitor_config(config_path);
    if (!load.ok) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "%s", load.error.c_str());
    }
    const cell::MonitorConfig& cfg = load.config;
    const Result<GridGeometry> g = GridGeometry::make(cfg.grid.origin, cfg.grid.voxel_size,
                                                      GridDims{cfg.grid.dims[0], cfg.grid.dims[1], cfg.grid.dims[2]});
    if (!g.ok()) {
        return IoStatus::failure(g.error(), "%s: [grid]: %s", config_path.c_str(), to_string(g.error()));
    }
    grid = g.value();
    background_frames = cfg.prior.background_frames;
    sensors.clear();
    for (const cell::SensorSettings& s : cfg.sensors) {
        RecordedSensor r;
        r.name = s.name;
        r.max_range = static_cast<float>(s.max_range);
        r.width = s.width;
        r.height = s.height;
        r.hfov_deg = s.hfov_deg;
        r.vfov_deg = s.vfov_deg;
        r.intrinsics = cell::sensor_intrinsics(s);
        if (with_pcd_files) {
            r.files = s.pcd_files;
            r.recording = s.recording;
        }
        if (s.has_target) {
            const Eigen::Vector3d axis = s.target - s.position;
            if (axis.norm() <= 0.0 || std::abs(axis.normalized().z()) > 0.999) {
                return IoStatus::failure(ErrorCode::kInvalidArgument,
                                         "%s:%d: sensor '%s': a target straight above or below the sensor leaves "
                                         "its x axis undefined; give `rotation`",
                                         config_path.c_str(), s.line, s.name.c_str());
            }
        }
        r.pose = cell::sensor_pose(s);
        sensors.push_back(std::move(r));
    }
    return IoStatus{};
}

IoStatus add_frames_dir(const std::string& dir, std::vector<RecordedSensor>& sensors) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: not a readable directory%s%s", dir.c_str(),
                                 ec ? ": " : "", ec ? ec.message().c_str() : "");
    }
    std::size_t added = 0U;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const fs::directory_entry& entry = *it;
        std::error_code ec2;
        if (!entry.is_directory(ec2)) {
            continue;  // loose files (notes, calibration) are not frames
        }
        const std::string name = entry.path().filename().string();
        auto sensor = std::find_if(sensors.begin(), sensors.end(),
                                   [&](const RecordedSensor& s) { return s.name == name; });
        if (sensor == sensors.end()) {
            std::string known;
            for (const RecordedSensor& s : sensors) {
                known += (known.empty() ? "" : ", ") + s.name;
            }
            return IoStatus::failure(ErrorCode::kInvalidArgument,
                                     "%s: folder '%s' names no sensor of the configuration (sensors: %s)", dir.c_str(),
                                     name.c_str(), known.c_str());
        }
        std::vector<std::string> files;
        for (fs::directory_iterator f(entry.path(), ec2), fend; !ec2 && f != fend; f.increment(ec2)) {
            std::error_code ec3;
            if (f->is_regular_file(ec3) && f->path().extension() == ".pcd") {
                files.push_back(f->path().string());
            }
        }
        if (ec2) {
            return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot list: %s", entry.path().c_str(),
                                     ec2.message().c_str());
        }
        std::sort(files.begin(), files.end());
        added += files.size();
        sensor->files.insert(sensor->files.end(), files.begin(), files.end());
    }
    if (ec) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot list: %s", dir.c_str(), ec.message().c_str());
    }
    if (added == 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument,
                                 "%s: no .pcd files (expected one folder per sensor, named as in the configuration)",
                                 dir.c_str());
    }
    return IoStatus{};
}

IoStatus accumulate_frames(FrameSource& frames, BackgroundGrid& background, const ProgressFn& progress) {
    const GridGeometry& g = background.grid.geometry();
    if (g.voxel_count() == 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "background: no grid");
    }
    background.grid.clear();
    BackgroundGrid frame;
    IoStatus st = frame.allocate(g);
    if (!st.ok()) {
        return st;
    }
    const SensorModelTable model;
    std::vector<SensorReading> readings;
    std::vector<std::int16_t> scratch(g.voxel_count());
    const std::size_t total = frames.frame_count();
    for (std::size_t k = 0U; k < total; ++k) {
        st = frames.frame(k, readings);
        if (!st.ok()) {
            return st;
        }
        const Result<FusionStats> fused = fuse_background_frame(
            background.grid, frame.grid, {readings.data(), readings.size()}, model, {scratch.data(), scratch.size()});
        if (!fused.ok()) {
            return IoStatus::failure(fused.error(), "frame %zu: fusing it into the background failed: %s", k,
                                     to_string(fused.error()));
        }
        if (progress) {
            progress(k + 1U, total);
        }
    }
    return IoStatus{};
}

IoStatus compute_prior(const EvidenceGrid& background, const AccessibilityParams& params, PriorResult& result) {
    const Status valid = validate_accessibility_params(params);
    if (!valid.ok()) {
        return IoStatus::failure(valid.error(), "analysis: parameters out of range: %s", to_string(valid.error()));
    }
    const std::size_t n = background.voxel_count();
    const AccessibilityScratchSize size = accessibility_scratch_size(background.geometry().dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    result.prior.assign(n, 0);
    result.p_acc.assign(n, 0.0F);
    const auto start = std::chrono::steady_clock::now();
    const Status st = compute_accessibility_prior(
        background, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
        {result.prior.data(), n}, {result.p_acc.data(), n});
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!st.ok()) {
        return IoStatus::failure(st.error(), "analysis: compute_accessibility_prior failed: %s", to_string(st.error()));
    }
    result.p_fore.resize(n);
    for (std::size_t i = 0U; i < n; ++i) {
        result.p_fore[i] = result.p_acc[i] * 0.5F;  // exact: halving a float only lowers its exponent (or is 0)
    }
    return IoStatus{};
}

namespace {

IoStatus read_text_file(const std::string& path, std::string& text) {
    const host::FilePtr f = host::open_file(path.c_str(), "rb");
    if (!f) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open for reading back: %s", path.c_str(),
                                 std::strerror(errno));
    }
    text.clear();
    char buf[65536];
    std::size_t n = 0U;
    while ((n = std::fread(buf, 1U, sizeof(buf), f.get())) > 0U) {
        text.append(buf, n);
    }
    const bool failed = std::ferror(f.get()) != 0;
    if (failed) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot read back", path.c_str());
    }
    return IoStatus{};
}

IoStatus verify_npy(const std::string& path, GridDims dims, const std::vector<float>& expected) {
    std::vector<float> back(expected.size());
    const IoStatus st = read_npy_float32(path.c_str(), dims, {back.data(), back.size()});
    if (!st.ok()) {
        return st;
    }
    if (std::memcmp(back.data(), expected.data(), expected.size() * sizeof(float)) != 0) {
        return IoStatus::failure(ErrorCode::kCrcMismatch, "%s: read back differs from what was written", path.c_str());
    }
    return IoStatus{};
}

}  // namespace

namespace {

/// Counts the steps of write_prior_outputs for its progress callback.
class OutputSteps {
public:
    static constexpr std::size_t kSteps = 8U;  // four files written, four read back
    explicit OutputSteps(const ProgressFn& progress) : progress_(&progress) {}
    void done() {
        if (*progress_) {
            (*progress_)(++steps_, kSteps);
        }
    }

private:
    const ProgressFn* progress_;
    std::size_t steps_ = 0U;
};

/// @p dir and its parents, created when missing.
IoStatus make_output_dir(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir, ec)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot create the output directory%s%s", dir.c_str(),
                                 ec ? ": " : " (a file of that name exists)", ec ? ec.message().c_str() : "");
    }
    return IoStatus{};
}

/// The four files written; @p image is the encoded image, for the verification.
IoStatus write_output_files(const GridGeometry& geometry, const AccessibilityParams& params, const PriorResult& result,
                            const PriorSourceOptions& source_options, const WrittenOutputs& written,
                            std::vector<std::uint8_t>& image, OutputSteps& steps) {
    // The image: encoded, checked by the loader, written atomically.
    IoStatus st = encode_prior_image(geometry, params, {result.prior.data(), result.prior.size()}, image);
    if (!st.ok()) {
        return st;
    }
    const Result<PriorImageView, PriorImageError> view = load_prior_image({image.data(), image.size()}, geometry);
    if (!view.ok()) {
        return IoStatus::failure(to_error_code(view.error()), "the encoded image fails its own check: %s",
                                 to_string(view.error()));
    }
    st = write_prior_image_file(written.image_path.c_str(), view.value());
    if (!st.ok()) {
        return st;
    }
    steps.done();
    st = write_prior_source_file(written.source_path.c_str(), view.value(), source_options);
    if (!st.ok()) {
        return st;
    }
    steps.done();
    const GridDims dims = geometry.dims();
    st = write_npy_float32(written.p_acc_path.c_str(), {result.p_acc.data(), result.p_acc.size()}, dims);
    if (!st.ok()) {
        return st;
    }
    steps.done();
    st = write_npy_float32(written.p_fore_path.c_str(), {result.p_fore.data(), result.p_fore.size()}, dims);
    if (!st.ok()) {
        return st;
    }
    steps.done();
    return IoStatus{};
}

/// Everything read back from disk and compared with what was written.
IoStatus verify_output_files(const GridGeometry& geometry, const PriorResult& result,
                             const PriorSourceOptions& source_options, const std::vector<std::uint8_t>& image,
                             WrittenOutputs& written, OutputSteps& steps) {
    std::vector<std::uint8_t> bytes;
    PriorImageView back;
    PriorImageError reason = PriorImageError::kNone;
    IoStatus st = read_prior_image_file(written.image_path.c_str(), geometry, bytes, back, &reason);
    if (!st.ok()) {
        return st;  // names the file
    }
    if (bytes != image) {
        return IoStatus::failure(ErrorCode::kCrcMismatch, "%s: read back differs from the encoded image",
                                 written.image_path.c_str());
    }
    steps.done();
    written.image_bytes = bytes.size();
    written.header = back.header();
    std::string expected_text;
    std::string text;
    st = prior_source_text(back, source_options, expected_text);
    if (!st.ok()) {
        return st;
    }
    st = read_text_file(written.source_path, text);
    if (!st.ok()) {
        return st;
    }
    if (text != expected_text) {
        return IoStatus::failure(ErrorCode::kCrcMismatch, "%s: read back differs from the generated source",
                                 written.source_path.c_str());
    }
    steps.done();
    const GridDims dims = geometry.dims();
    st = verify_npy(written.p_acc_path, dims, result.p_acc);
    if (!st.ok()) {
        return st;
    }
    steps.done();
    st = verify_npy(written.p_fore_path, dims, result.p_fore);
    if (st.ok()) {
        steps.done();
    }
    return st;
}

}  // namespace

IoStatus write_prior_outputs(const std::string& dir, const GridGeometry& geometry, const AccessibilityParams& params,
                             const PriorResult& result, const PriorSourceOptions& source_options,
                             WrittenOutputs& written, const ProgressFn& progress) {
    written = WrittenOutputs{};
    OutputSteps steps(progress);
    IoStatus st = make_output_dir(dir);
    if (!st.ok()) {
        return st;
    }
    written.image_path = join_path(dir, kPriorImageName);
    written.source_path = join_path(dir, kPriorSourceName);
    written.p_acc_path = join_path(dir, kPAccName);
    written.p_fore_path = join_path(dir, kPForeName);
    std::vector<std::uint8_t> image;
    st = write_output_files(geometry, params, result, source_options, written, image, steps);
    if (!st.ok()) {
        return st;
    }
    return verify_output_files(geometry, result, source_options, image, written, steps);
}

}  // namespace cellguard::prior_tool
