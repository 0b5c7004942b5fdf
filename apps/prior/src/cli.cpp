// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-prior's command line: options, progress bar, report. See prior_tool.hpp.
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/host/cli.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/background_files.hpp"
#include "cellguard/prior/accessibility.hpp"
#include "cellguard/prior_tool/prior_tool.hpp"

namespace cellguard::prior_tool {

namespace {

constexpr const char* kToolName = "cellguard-prior";

/// Why @p frames background frames are too few for @p params' method with the
/// default sensor model (min_background_frames), or "" when they suffice.
std::string too_few_frames(std::size_t frames, const AccessibilityParams& params) {
    const std::uint32_t need = min_background_frames(params, SensorModelTable{});
    if (frames >= need) {
        return "";
    }
    return std::to_string(frames) + " background frame(s) are too few for the " + method_name(params.method) +
           " method: it needs at least " + std::to_string(need) +
           ", so that space seen free in every frame counts "
           "as empty (below t_E); record more frames of the empty cell, or give the same frame again for a static scene";
}

/// Voxels from which the progress bar is on by default (on a terminal).
constexpr std::size_t kLargeGridVoxels = std::size_t{1} << 20U;

constexpr const char* kDescription =
    "Computes the accessibility prior of an empty workcell (Anderson-Sprecher,\n"
    "Simmons and Huber) from its background grid G_B and writes it into DIR as\n"
    "  prior.cgprior    the prior image (certification/prior-image-format.md),\n"
    "                   for the Linux monitor's [prior] file = ...\n"
    "  prior_flash.hpp  the same image as C++ source, to compile into a firmware\n"
    "  p_acc.npy        P(acc) per voxel, float32, shape (nz, ny, nx)\n"
    "  p_fore.npy       P(fore) = P(acc) / 2 per voxel, float32, shape (nz, ny, nx)\n"
    "then reads every file back and checks it (the image with the controller's\n"
    "loader) and prints the image's CRCs and geometry.";

constexpr const char* kFooter =
    "Exit status: 0 written and verified, 1 an output could not be written or\n"
    "failed verification, 2 bad command line or bad input.";

bool parse_double(const std::string& text, double& value) {
    if (text.empty()) {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(v)) {
        return false;
    }
    value = v;
    return true;
}

bool parse_triple(const std::string& text, double out[3]) {
    std::size_t start = 0U;
    for (int i = 0; i < 3; ++i) {
        const std::size_t comma = i < 2 ? text.find(',', start) : text.size();
        if (comma == std::string::npos) {
            return false;
        }
        if (!parse_double(text.substr(start, comma - start), out[i])) {
            return false;
        }
        start = comma + 1U;
    }
    return true;
}

enum class InputKind { kSimulated, kNpy, kFrames };
enum class ProgressMode { kAuto, kOn, kOff };

struct Options {  // fields ordered by alignment (no padding between them)
    std::string npy;
    std::string observed;
    std::string frames_dir;
    std::vector<std::pair<std::string, std::string>> frame_files;
    std::string config;
    std::string out_dir;
    std::string name_space = "cellguard_prior";
    std::string config_header;
    std::string background_file;
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    double voxel_size = 0.0;
    AccessibilityParams params{};
    GridDims dims{};
    int background_frames = -1;
    InputKind input = InputKind::kSimulated;
    ProgressMode progress = ProgressMode::kAuto;
    bool config_frames = false;
    bool has_origin = false;
    bool has_voxel_size = false;
    bool has_dims = false;
};

/// The INPUT options' --background-npy, and those of recorded frames (the GRID options refer to them).
struct InputOptions {
    host::OptionRef npy;
    std::vector<host::OptionRef> recorded;
};

/// INPUT: --simulated, --background-npy (with --observed), or recorded frames (--frames, --frame, --config-frames).
InputOptions add_input_options(host::CommandLine& cli, Options& o, bool& simulated) {
    using host::reject;
    cli.group("INPUT, one of (default: --simulated)");
    host::OptionRef simulated_opt = cli.flag("--simulated", simulated,
                                             "the simulated paper cell's empty background: its four\n"
                                             "sensors looking at the reference scene (a demo)");
    host::OptionRef npy = cli.text("--background-npy", o.npy, "FILE",
                                   "a background grid, shape (nz, ny, nx): int16 log-odds\n"
                                   "('<i2', 1/256 nat, as the npy exporter writes) or\n"
                                   "float32 probability ('<f4', in [0, 1])");
    cli.text("--observed", o.observed, "FILE",
             "uint8 observed flags for --background-npy (default: the\n"
             "sibling *_observed.npy of a *_log_odds.npy if it exists,\n"
             "else voxels without evidence count as unobserved)")
        .needs(npy);
    host::OptionRef frames = cli.value("--frames", "DIR",
                                       "recorded frames of the empty cell: DIR/<sensor>/*.pcd,\n"
                                       "one folder per sensor of --config, points in the sensor\n"
                                       "frame; frame k is the k-th file (by name) of each sensor",
                                       [&o](const std::string& v) {
                                           if (!o.frames_dir.empty()) {
                                               reject("--frames given twice");
                                           }
                                           o.frames_dir = v;
                                       });
    host::OptionRef frame = cli.value("--frame", "SENSOR=FILE", "one more recorded .pcd of SENSOR (repeatable)",
                                      [&o](const std::string& v) {
                                          const std::size_t eq = v.find('=');
                                          if (eq == std::string::npos || eq == 0U || eq + 1U == v.size()) {
                                              reject("--frame expects SENSOR=FILE.pcd, got '" + v + "'");
                                          }
                                          o.frame_files.emplace_back(v.substr(0U, eq), v.substr(eq + 1U));
                                      });
    host::OptionRef config_frames = cli.flag(
        "--config-frames", o.config_frames,
        "the `pcd_files` and `depth_files` of --config's sensors as recorded frames\n"
        "(as the monitor replays them; combines with --frames)");
    InputOptions options{npy, {frames, frame, config_frames}};
    for (const host::OptionRef r : options.recorded) {
        simulated_opt.excludes(r);
        npy.excludes(r);
    }
    simulated_opt.excludes(npy);
    return options;
}

/// GRID: --config, --origin, --voxel-size, --dims, --background-frames.
void add_grid_options(host::CommandLine& cli, Options& o, const InputOptions& input) {
    using host::reject;
    cli.group("GRID");
    host::OptionRef config = cli.text("--config", o.config, "FILE",
                                      "a monitor configuration (apps/monitor/config/*.toml):\n"
                                      "[grid] and, for --frames, the sensors' names and poses;\n"
                                      "--simulated takes [grid] and [prior] background_frames\n"
                                      "(its sensors stay the simulated paper cell's)");
    for (const host::OptionRef r : input.recorded) {
        r.needs(config);
    }
    cli.value("--origin", "X,Y,Z", "grid minimum corner, metres", [&o](const std::string& v) {
        double t[3];
        if (!parse_triple(v, t)) {
            reject("--origin expects X,Y,Z in metres (finite numbers), got '" + v + "'");
        }
        o.has_origin = true;
        o.origin = Eigen::Vector3d(t[0], t[1], t[2]);
    });
    cli.value("--voxel-size", "S", "voxel edge, metres", [&o](const std::string& v) {
        if (!parse_double(v, o.voxel_size) || !(o.voxel_size > 0.0)) {
            reject("--voxel-size expects a positive length in metres, got '" + v + "'");
        }
        o.has_voxel_size = true;
    });
    cli.value("--dims", "NX,NY,NZ",
              "voxels per axis; with --background-npy the shape gives\n"
              "the dims, --dims or --config then only check it\n"
              "(default of all three: --config's, or the paper grid,\n"
              "34 x 30 x 30 of 0.05 m from (-0.85,-0.75,0))",
              [&o](const std::string& v) {
                  long d[3] = {0, 0, 0};
                  std::size_t start = 0U;
                  bool ok = true;
                  for (int k = 0; k < 3 && ok; ++k) {
                      const std::size_t comma = k < 2 ? v.find(',', start) : v.size();
                      ok = comma != std::string::npos &&
                           host::parse_integer(v.substr(start, comma - start), 1, kMaxDimension, d[k]);
                      start = comma + 1U;
                  }
                  if (!ok) {
                      reject("--dims expects NX,NY,NZ, each 1.." + std::to_string(kMaxDimension) + ", got '" + v + "'");
                  }
                  o.has_dims = true;
                  o.dims = GridDims{static_cast<std::int32_t>(d[0]), static_cast<std::int32_t>(d[1]),
                                    static_cast<std::int32_t>(d[2])};
              });
    host::OptionRef background_frames = cli.integer("--background-frames", o.background_frames, 1, 100000, "N",
                                                    "frames --simulated accumulates (default: --config's, or 8)");
    background_frames.excludes(input.npy);
    for (const host::OptionRef r : input.recorded) {
        background_frames.excludes(r);
    }
}

/// ANALYSIS: --method, --tb, --te, --radius, --open-faces.
void add_analysis_options(host::CommandLine& cli, Options& o) {
    using host::reject;
    cli.group("ANALYSIS (defaults: the paper's)");
    cli.value("--method", "M",
              "probabilistic | thresholded | thresholded-baseline |\n"
              "probabilistic-baseline            (default probabilistic)",
              [&o](const std::string& v) {
                  if (!parse_method(v, o.params.method)) {
                      reject(
                          "--method expects probabilistic, thresholded, thresholded-baseline or "
                          "probabilistic-baseline, got '" +
                          v + "'");
                  }
              });
    auto probability = [](const char* name, double& target) {
        return [name, &target](const std::string& v) {
            double t = 0.0;
            if (!parse_double(v, t) || !(t > 0.0 && t < 1.0)) {
                reject(std::string(name) + " expects a probability strictly between 0 and 1, got '" + v + "'");
            }
            target = t;
        };
    };
    cli.value("--tb", "T", "thresholded: empty when P(occ) < T, 0 < T < 1 (0.51)", probability("--tb", o.params.t_b));
    cli.value("--te", "T", "probabilistic: P(occ) < T counts as 0, 0 < T < 1 (0.1)", probability("--te", o.params.t_e));
    cli.integer("--radius", o.params.radius_voxels, 0, kMaxAccessibilityAnalysisRadius, "R",
                "object radius r in voxels, 0.." + std::to_string(kMaxAccessibilityAnalysisRadius) + " (2)");
    cli.value("--open-faces", "F",
              "faces open to the outside: sides | all | none | a comma\n"
              "list of xmin,xmax,ymin,ymax,zmin,zmax (sides)",
              [&o](const std::string& v) {
                  if (!parse_open_faces(v, o.params.open_faces)) {
                      reject(
                          "--open-faces expects sides, all, none or a comma list of xmin,xmax,ymin,ymax,zmin,zmax, "
                          "got '" +
                          v + "'");
                  }
              });
}

/// OUTPUT: --out, --namespace, --config-header, --progress; returns the --progress option.
host::OptionRef add_output_options(host::CommandLine& cli, Options& o, bool& progress) {
    using host::reject;
    cli.group("OUTPUT");
    cli.value("--out", "DIR", "output directory, created if missing (required)",
              [&o](const std::string& v) {
                  if (v.empty()) {
                      reject("--out expects a directory, got ''");
                  }
                  o.out_dir = v;
              })
        .required();
    cli.text("--namespace", o.name_space, "NS", "namespace of prior_flash.hpp (cellguard_prior)");
    cli.text("--config-header", o.config_header, "H",
             "header prior_flash.hpp includes first, e.g. the one that\n"
             "defines CELLGUARD_GRID_NX/NY/NZ");
    cli.value("--write-background", "FILE",
              "also write every sensor's view of the empty cell (the per-\n"
              "pixel median of the same frames; for recorded .pcd frames\n"
              "the nearest and farthest range per direction bin) to FILE,\n"
              "bound to the prior by its CRC (the monitor's\n"
              "prior.background_file); not with --background-npy",
              [&o](const std::string& v) {
                  if (v.empty()) {
                      reject("--write-background expects a file, got ''");
                  }
                  o.background_file = v;
              });
    host::OptionRef progress_opt = cli.flag("--progress,!--no-progress", progress,
                                            "progress bar on stderr, or none (default: on a\n"
                                            "terminal, for frames and grids of 2^20 voxels or more)");
    return progress_opt;
}

/// Reads @p args into @p o: -1 to run, else the exit status (kExitOk after
/// --help or --version on @p out, kExitInputError after a usage error on @p err).
int parse_args(const std::vector<std::string>& args, Options& o, std::ostream& out, std::ostream& err) {
    static_assert(kExitInputError == host::kExitUsage, "a bad command line is a bad input");
    host::CommandLine cli(kToolName, "cellguard-prior [INPUT] [GRID] [ANALYSIS] --out DIR", kDescription, kFooter);
    bool simulated = false;
    const InputOptions input = add_input_options(cli, o, simulated);
    add_grid_options(cli, o, input);
    add_analysis_options(cli, o);
    bool progress = false;
    host::OptionRef progress_opt = add_output_options(cli, o, progress);

    const int status = cli.parse(args, out, err);
    if (!o.npy.empty()) {
        o.input = InputKind::kNpy;
    } else if (!o.frames_dir.empty() || !o.frame_files.empty() || o.config_frames) {
        o.input = InputKind::kFrames;
    }
    if (progress_opt.count() > 0U) {
        o.progress = progress ? ProgressMode::kOn : ProgressMode::kOff;
    }
    return status;
}

/// The progress bar on stderr: a bar for counted work, an elapsed-time
/// ticker (from a thread) for one long call that cannot report progress.
class Progress {
public:
    Progress(std::ostream& err, bool on) : err_(err), on_(on) {}
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    Progress(Progress&&) = delete;
    Progress& operator=(Progress&&) = delete;
    ~Progress() { stop_ticker(); }

    void bar(const char* stage, std::size_t done, std::size_t total) {
        if (!on_ || total == 0U) {
            return;
        }
        constexpr std::size_t kWidth = 30U;
        const std::size_t filled = done * kWidth / total;
        std::string line = "\r" + std::string(stage) + " [" + std::string(filled, '#') +
                           std::string(kWidth - filled, '.') + "] " + std::to_string(done) + "/" +
                           std::to_string(total) + "   ";
        err_ << line << (done == total ? "\n" : "") << std::flush;
    }

    void start_ticker(const std::string& stage) {
        if (!on_) {
            return;
        }
        stop_ = false;
        const auto start = std::chrono::steady_clock::now();
        thread_ = std::thread([this, stage, start] {
            std::unique_lock<std::mutex> lock(mutex_);
            do {
                const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                char buf[64];
                static_cast<void>(std::snprintf(buf, sizeof(buf), " ... %.1f s   ", s));
                err_ << "\r" << stage << buf << std::flush;
            } while (!cv_.wait_for(lock, std::chrono::milliseconds(200), [this] { return stop_; }));
            err_ << "\r" << stage << " ... done" << std::string(12, ' ') << "\n" << std::flush;
        });
    }

    void stop_ticker() {
        if (!thread_.joinable()) {
            return;
        }
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }

private:
    std::ostream& err_;
    bool on_;
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
};

std::string milliseconds_text(double seconds) {
    char buf[64];
    static_cast<void>(std::snprintf(buf, sizeof(buf), "%.1f ms", seconds * 1e3));
    return buf;
}

std::string geometry_text(const GridGeometry& g) {
    const GridDims d = g.dims();
    char buf[200];
    static_cast<void>(std::snprintf(buf, sizeof(buf), "%d x %d x %d voxels of %g m from (%g, %g, %g)", d.nx, d.ny, d.nz,
                                    g.voxel_size(), g.origin().x(), g.origin().y(), g.origin().z()));
    return buf;
}

bool file_exists(const std::string& path) {
    struct stat st {};
    return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/// A step of run that failed: the exit status and the message for stderr; none when @c failed is false.
struct RunFailure {
    bool failed = false;
    int status = kExitOk;
    std::string message;
};

RunFailure run_failure(int status, std::string message) { return RunFailure{true, status, std::move(message)}; }

/// The failure @p st reports (its message copied).
RunFailure io_failure(int status, const IoStatus& st) {
    RunFailure f{true, status, {}};
    f.message = st.message();
    return f;
}

/// --namespace and --config-header: checked by the source generator, on a one-voxel image.
RunFailure check_source_options(const Options& o) {
    PriorSourceOptions probe;
    probe.name_space = o.name_space.c_str();
    probe.config_header = o.config_header.empty() ? nullptr : o.config_header.c_str();
    const GridGeometry one = GridGeometry::make(Eigen::Vector3d::Zero(), 1.0, GridDims{1, 1, 1}).value();
    const std::int16_t zero = 0;
    std::vector<std::uint8_t> image;
    std::string text;
    if (!encode_prior_image(one, AccessibilityParams{}, {&zero, 1U}, image).ok()) {
        return run_failure(kExitOutputError, "internal: encoding a one-voxel probe image failed");
    }
    const Result<PriorImageView, PriorImageError> view = load_prior_image({image.data(), image.size()}, one);
    const IoStatus st = view.ok() ? prior_source_text(view.value(), probe, text) : IoStatus{};
    if (!view.ok() || !st.ok()) {
        return run_failure(kExitInputError, "--namespace '" + o.name_space + "' or --config-header '" +
                                                o.config_header +
                                                "' refused by the source generator: " + (st.ok() ? "" : st.message()));
    }
    return {};
}

/// The grid's placement the options ask for: each of origin, voxel size, dims given, else --config's, else the
/// paper grid's.
struct GridChoice {
    GridGeometry grid =
        paper_grid_geometry();            ///< --config's or the paper grid; the chosen one unless --background-npy
    std::vector<RecordedSensor> sensors;  ///< --config's sensors (for recorded frames)
    int config_frames = 8;                ///< --config's [prior] background_frames
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    double voxel_size = 0.0;
    GridDims dims{};
};

/// Grid and sensors: --config, then --origin, --voxel-size, --dims over it.
RunFailure choose_grid(const Options& o, GridChoice& c) {
    if (!o.config.empty()) {
        const IoStatus st = sensors_from_config(o.config, o.config_frames, c.sensors, c.grid, c.config_frames);
        if (!st.ok()) {
            return run_failure(kExitInputError, std::string("configuration: ") + st.message());
        }
    }
    if (o.input == InputKind::kNpy && o.config.empty() && !(o.has_origin && o.has_voxel_size)) {
        return run_failure(kExitInputError,
                           "--background-npy needs the grid's placement: --origin X,Y,Z and "
                           "--voxel-size S, or --config FILE");
    }
    c.origin = o.has_origin ? o.origin : c.grid.origin();
    c.voxel_size = o.has_voxel_size ? o.voxel_size : c.grid.voxel_size();
    c.dims = o.has_dims ? o.dims : c.grid.dims();
    if (o.input != InputKind::kNpy) {
        const Result<GridGeometry> g = GridGeometry::make(c.origin, c.voxel_size, c.dims);
        if (!g.ok()) {
            return run_failure(kExitInputError, std::string("grid: ") + to_string(g.error()));
        }
        c.grid = g.value();
    }
    return {};
}

/// --background-npy (and its observed flags: --observed, else a *_observed.npy sibling of a *_log_odds.npy); the
/// grid is the file's.
RunFailure load_npy_input(const Options& o, GridChoice& c, BackgroundGrid& background, std::string& text) {
    NpyPlacement placement;
    placement.origin = c.origin;
    placement.voxel_size = c.voxel_size;
    placement.check_dims = o.has_dims || !o.config.empty();
    placement.dims = c.dims;
    std::string observed = o.observed;
    const std::string suffix = "_log_odds.npy";
    if (observed.empty() && o.npy.size() > suffix.size() &&
        o.npy.compare(o.npy.size() - suffix.size(), suffix.size(), suffix) == 0) {
        const std::string sibling = o.npy.substr(0U, o.npy.size() - suffix.size()) + "_observed.npy";
        if (file_exists(sibling)) {
            observed = sibling;
        }
    }
    NpyBackgroundInfo info;
    const IoStatus st = load_background_npy(o.npy, observed, placement, background, info);
    if (!st.ok()) {
        return io_failure(kExitInputError, st);
    }
    c.grid = background.grid.geometry();
    text = o.npy + " (" + (info.float_input ? "float32 probability" : "int16 log-odds") + "), " +
           "observed flags: " + info.observed_source + ", " + std::to_string(info.observed_voxels) + " of " +
           std::to_string(c.grid.voxel_count()) + " observed";
    return {};
}

/// The recorded frames' source: --frames DIR's folders and each --frame added to --config's sensors.
RunFailure add_recorded_files(const Options& o, std::vector<RecordedSensor>& sensors) {
    if (!o.frames_dir.empty()) {
        const IoStatus st = add_frames_dir(o.frames_dir, sensors);
        if (!st.ok()) {
            return io_failure(kExitInputError, st);
        }
    }
    for (const auto& sf : o.frame_files) {
        bool found = false;
        for (RecordedSensor& s : sensors) {
            if (s.name == sf.first) {
                s.files.push_back(sf.second);
                found = true;
            }
        }
        if (!found) {
            return run_failure(kExitInputError, "--frame " + sf.first + "=" + sf.second + ": no sensor '" + sf.first +
                                                    "' in " + o.config);
        }
    }
    return {};
}

/// Recorded frames fused into @p background.
RunFailure fuse_recorded_frames(const Options& o, std::vector<RecordedSensor>& sensors, BackgroundGrid& background,
                                const ProgressFn& report, std::string& text) {
    RunFailure f = add_recorded_files(o, sensors);
    if (f.failed) {
        return f;
    }
    std::string counts;
    for (const RecordedSensor& s : sensors) {
        counts += (counts.empty() ? "" : ", ") + s.name + " " +
                  std::to_string(s.recording.files.empty() ? s.files.size() : s.recording.files.size());
    }
    RecordedFrameSource source(sensors);
    if (source.frame_count() == 0U) {
        return run_failure(kExitInputError,
                           "no recorded frames: " + o.config + "'s sensors have no pcd_files or depth_files");
    }
    if (const std::string why = too_few_frames(source.frame_count(), o.params); !why.empty()) {
        return run_failure(kExitInputError, why);
    }
    const IoStatus st = accumulate_frames(source, background, report);
    text = "recorded frames (" + std::to_string(source.frame_count()) + "; files per sensor: " + counts + ")";
    if (!st.ok()) {
        return io_failure(kExitInputError, st);
    }
    return {};
}

/// The simulated paper cell's or the recorded frames, fused into @p background on the chosen grid.
RunFailure fuse_input_frames(const Options& o, GridChoice& c, bool progress_on, std::ostream& err,
                             BackgroundGrid& background, std::string& text) {
    IoStatus st = background.allocate(c.grid);
    if (!st.ok()) {
        return io_failure(kExitInputError, st);
    }
    Progress progress(err, progress_on);
    const ProgressFn report = [&](std::size_t done, std::size_t total) { progress.bar("fusing frames", done, total); };
    if (o.input != InputKind::kSimulated) {
        return fuse_recorded_frames(o, c.sensors, background, report, text);
    }
    const int frames = o.background_frames > 0 ? o.background_frames : c.config_frames;
    if (const std::string why = too_few_frames(static_cast<std::size_t>(frames), o.params); !why.empty()) {
        return run_failure(kExitInputError, why);
    }
    SimulatedFrameSource source(static_cast<std::size_t>(frames));
    st = accumulate_frames(source, background, report);
    text = "the simulated paper cell's empty background, " + std::to_string(source.sensor_count()) + " sensors, " +
           std::to_string(frames) + " frames";
    if (!st.ok()) {
        return io_failure(kExitInputError, st);
    }
    return {};
}

/// The output directory, made before the analysis (which may be long).
RunFailure make_out_dir(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir, ec)) {
        return run_failure(kExitOutputError,
                           dir + ": cannot create the output directory" +
                               (ec ? ": " + ec.message() : std::string(" (a file of that name exists)")));
    }
    return {};
}

/// The accessibility analysis, with a ticker, and its summary line on @p out.
RunFailure analyse(const Options& o, const BackgroundGrid& background, bool progress_on, std::ostream& out,
                   std::ostream& err, PriorResult& result) {
    {
        Progress progress(err, progress_on);
        progress.start_ticker(std::string("accessibility analysis (") + method_name(o.params.method) + ")");
        const IoStatus st = compute_prior(background.grid, o.params, result);
        progress.stop_ticker();
        if (!st.ok()) {
            return io_failure(kExitOutputError, st);
        }
    }
    std::size_t never = 0U;
    std::size_t half = 0U;
    for (const std::int16_t v : result.prior) {
        never += v == kNeverForeground ? 1U : 0U;
        half += v == 0 ? 1U : 0U;
    }
    out << kToolName << ": prior: " << method_name(o.params.method) << ", t_B " << o.params.t_b << ", t_E "
        << o.params.t_e << ", r " << o.params.radius_voxels << ", open faces " << open_faces_list(o.params.open_faces)
        << ": " << milliseconds_text(result.seconds) << "; never foreground " << never << " voxels, P(fore) = 0.5 "
        << half << " voxels\n";
    return {};
}

/// Writes @p records to o.background_file for the prior with payload CRC
/// @p prior_crc (read back and checked); @p size gets the file's size and
/// @p crc_text the CRC as "0x%08X" for the report.
RunFailure write_view_records(const Options& o, const std::vector<BackgroundViewRecord>& records,
                              std::uint32_t prior_crc, std::size_t frames, std::size_t& size, std::string& crc_text) {
    std::vector<std::uint8_t> bytes;
    const IoStatus st = write_background_image_file(o.background_file.c_str(),
                                                    Span<const BackgroundViewRecord>(records.data(), records.size()),
                                                    prior_crc, static_cast<std::uint32_t>(frames), bytes);
    if (!st.ok()) {
        return io_failure(kExitOutputError, st);
    }
    size = bytes.size();
    char crc[32];
    static_cast<void>(std::snprintf(crc, sizeof(crc), "0x%08X", prior_crc));
    crc_text = crc;
    return {};
}

/// The simulated sensors' views of the empty cell, from the same @p frames
/// frames as the prior, written to o.background_file and checked.
RunFailure write_background_views(const Options& o, int frames, std::uint32_t prior_crc, std::ostream& out) {
    SimulatedFrameSource source(static_cast<std::size_t>(frames));
    const std::vector<sim::SensorSpec> specs = sim::paper_sensors();
    std::vector<BackgroundViewBuilder> builders;
    builders.reserve(specs.size());
    for (const sim::SensorSpec& s : specs) {
        builders.emplace_back(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height));
    }
    std::vector<SensorReading> readings;
    std::vector<BackgroundViewRecord> records(specs.size());
    for (std::size_t k = 0U; k < source.frame_count(); ++k) {
        const IoStatus st = source.frame(k, readings);
        if (!st.ok()) {
            return io_failure(kExitInputError, st);
        }
        for (std::size_t s = 0U; s < specs.size() && s < readings.size(); ++s) {
            if (!builders[s].add(readings[s])) {
                return run_failure(kExitInputError, "--write-background: sensor '" + specs[s].name +
                                                        "' does not deliver a depth image of its size");
            }
            records[s].identity = background_identity(specs[s].name, readings[s]);
        }
    }
    std::vector<std::vector<float>> views;
    for (std::size_t s = 0U; s < specs.size(); ++s) {
        views.push_back(builders[s].median());
        records[s].depth = Span<const float>(views[s].data(), views[s].size());
    }
    std::size_t size = 0U;
    std::string crc;
    if (RunFailure f = write_view_records(o, records, prior_crc, static_cast<std::size_t>(frames), size, crc);
        f.failed) {
        return f;
    }
    out << kToolName << ": wrote " << o.background_file << " (" << size << " bytes): " << specs.size()
        << " sensors' views of the empty cell, median of " << frames << " frames, for the prior with payload CRC-32 "
        << crc << "; read back and checked\n";
    return {};
}

/// The recorded sensors' direction-grid views (SR-BKG-009), from the same
/// .pcd frames as the prior, written to o.background_file and checked.
/// Every configured sensor needs recorded frames (the file holds a view of
/// each, in the configuration's order).
RunFailure write_recorded_background_views(const Options& o, const std::vector<RecordedSensor>& sensors,
                                           std::uint32_t prior_crc, std::ostream& out) {
    std::vector<std::vector<float>> views;
    std::vector<BackgroundViewRecord> records(sensors.size());
    std::size_t frames = 0U;
    std::size_t outside = 0U;
    for (const RecordedSensor& s : sensors) {
        if (s.files.empty()) {
            return run_failure(kExitInputError, "--write-background: sensor '" + s.name +
                                                    "' has no recorded frames, so no view of the empty cell");
        }
        const DirectionGrid grid = recorded_view_grid(s.hfov_deg, s.vfov_deg, s.width, s.height);
        records[views.size()].identity = point_view_identity(s.name, s.pose, grid);
        PointViewBuilder builder(grid);
        cell::PcdFrameSource source(s.name, s.files, s.pose, s.width, s.height, s.max_range);
        for (std::size_t k = 0U; k < s.files.size(); ++k) {
            SensorReading r;
            const cell::PcdFrameCheck c = source.load(k, r);
            if (!c.ok) {
                return run_failure(kExitInputError, "--write-background: " + c.file + ": " + c.reason);
            }
            if (!builder.add(r)) {
                return run_failure(kExitInputError, "--write-background: sensor '" + s.name +
                                                        "': its direction grid is refused (field of view or bins)");
            }
        }
        frames = std::max(frames, s.files.size());
        outside += builder.outside();
        views.push_back(builder.values());
    }
    for (std::size_t s = 0U; s < sensors.size(); ++s) {
        records[s].depth = Span<const float>(views[s].data(), views[s].size());
    }
    std::size_t size = 0U;
    std::string crc;
    if (RunFailure f = write_view_records(o, records, prior_crc, static_cast<std::size_t>(frames), size, crc);
        f.failed) {
        return f;
    }
    out << kToolName << ": wrote " << o.background_file << " (" << size << " bytes): " << sensors.size()
        << " recorded sensors' direction-grid views of the empty cell, farthest and nearest range per bin of " << frames
        << " frames (" << outside << " points outside the grids), for the prior with payload CRC-32 " << crc
        << "; read back and checked\n";
    return {};
}

/// --write-background's views, for the prior just written (nothing without the option).
RunFailure write_background_if_asked(const Options& o, const GridChoice& c, const WrittenOutputs& written,
                                     std::ostream& out) {
    if (o.background_file.empty()) {
        return {};
    }
    if (o.input != InputKind::kSimulated) {
        return write_recorded_background_views(o, c.sensors, written.header.payload_crc, out);
    }
    const int frames = o.background_frames > 0 ? o.background_frames : c.config_frames;
    return write_background_views(o, frames, written.header.payload_crc, out);
}

/// What was written and verified, on @p out.
void report_outputs(const WrittenOutputs& written, std::ostream& out) {
    const PriorImageHeader& h = written.header;
    char crc[96];
    static_cast<void>(
        std::snprintf(crc, sizeof(crc), "payload CRC-32 0x%08X, header CRC-32 0x%08X", h.payload_crc, h.header_crc));
    out << kToolName << ": wrote " << written.image_path << " (" << written.image_bytes << " bytes), "
        << written.source_path << ", " << written.p_acc_path << ", " << written.p_fore_path << "\n";
    out << kToolName << ": verified: " << written.image_path << " loads with load_prior_image: format "
        << h.format_version << ", " << h.nx << " x " << h.ny << " x " << h.nz << " voxels of " << h.voxel_size()
        << " m from (" << h.origin().x() << ", " << h.origin().y() << ", " << h.origin().z() << "), " << crc
        << "; flash source and .npy files read back equal\n";
}

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool err_is_tty) {
    const auto error = [&err](const RunFailure& f) {
        err << kToolName << ": " << f.message << "\n" << std::flush;
        return f.status;
    };
    Options o;
    if (const int status = parse_args(args, o, out, err); status >= 0) {
        return status;
    }
    if (const RunFailure f = check_source_options(o); f.failed) {
        return error(f);
    }
    if (!o.background_file.empty() && o.input == InputKind::kNpy) {
        return error(run_failure(kExitInputError,
                                 "--write-background: only with --simulated or recorded frames; a .npy grid has "
                                 "no sensors, so it gives no view"));
    }
    GridChoice c;
    if (const RunFailure f = choose_grid(o, c); f.failed) {
        return error(f);
    }

    // The background.
    const auto t_start = std::chrono::steady_clock::now();
    BackgroundGrid background;
    std::string background_text;
    bool progress_on = o.progress == ProgressMode::kOn;
    if (o.progress == ProgressMode::kAuto && o.input != InputKind::kNpy) {
        progress_on = err_is_tty;
    }
    if (const RunFailure f = o.input == InputKind::kNpy
                                 ? load_npy_input(o, c, background, background_text)
                                 : fuse_input_frames(o, c, progress_on, err, background, background_text);
        f.failed) {
        return error(f);
    }
    if (o.progress == ProgressMode::kAuto) {
        progress_on = err_is_tty && c.grid.voxel_count() >= kLargeGridVoxels;
    }
    out << kToolName << ": background: " << background_text << "\n";
    out << kToolName << ": grid: " << geometry_text(c.grid) << "\n";
    if (const RunFailure f = make_out_dir(o.out_dir); f.failed) {
        return error(f);
    }
    PriorResult result;
    if (const RunFailure f = analyse(o, background, progress_on, out, err, result); f.failed) {
        return error(f);
    }

    // The outputs.
    PriorSourceOptions source_options;
    source_options.name_space = o.name_space.c_str();
    source_options.config_header = o.config_header.empty() ? nullptr : o.config_header.c_str();
    WrittenOutputs written;
    const auto t_analysed = std::chrono::steady_clock::now();
    IoStatus st;
    {
        Progress progress(err, progress_on);
        st = write_prior_outputs(
            o.out_dir, c.grid, o.params, result, source_options, written,
            [&](std::size_t done, std::size_t total) { progress.bar("writing, verifying", done, total); });
    }
    const auto t_written = std::chrono::steady_clock::now();
    if (!st.ok()) {
        return error(io_failure(kExitOutputError, st));
    }
    report_outputs(written, out);
    if (const RunFailure f = write_background_if_asked(o, c, written, out); f.failed) {
        return error(f);
    }
    char times[160];
    static_cast<void>(
        std::snprintf(times, sizeof(times),
                      "time: background and set-up %.2f s, analysis %.1f ms, outputs written and verified %.2f s",
                      std::chrono::duration<double>(t_analysed - t_start).count() - result.seconds,
                      result.seconds * 1e3, std::chrono::duration<double>(t_written - t_analysed).count()));
    out << kToolName << ": " << times << "\n";
    out << std::flush;
    return kExitOk;
}

}  // namespace

int run_prior_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                   bool err_is_tty) noexcept {
    try {
        return run(args, out, err, err_is_tty);
    } catch (const std::bad_alloc&) {
        try {
            err << kToolName << ": out of memory\n" << std::flush;
        } catch (...) {  // NOLINT(bugprone-empty-catch): nothing left to report with
        }
        return kExitOutputError;
    } catch (const std::exception& e) {
        try {
            err << kToolName << ": " << e.what() << "\n" << std::flush;
        } catch (...) {  // NOLINT(bugprone-empty-catch): nothing left to report with
        }
        return kExitOutputError;
    }
}

}  // namespace cellguard::prior_tool
