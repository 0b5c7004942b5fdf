// cellguard-prior's command line: options, progress bar, report. See prior_tool.hpp.
#include <sys/stat.h>

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
#include <vector>

#include "cellguard/accessibility.hpp"
#include "cellguard/host/cli.hpp"
#include "cellguard/log_odds.hpp"
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
           " method: it needs at least " + std::to_string(need) + ", so that space seen free in every frame counts "
           "as empty (below t_E); record more frames of the empty cell, or give the same frame again for a static scene";
}

/// Voxels from which the progress bar is on by default (on a terminal).
constexpr std::size_t kLargeGridVoxels = std::size_t{1} << 20U;

constexpr const char* kUsage =
    "usage: cellguard-prior [INPUT] [GRID] [ANALYSIS] --out DIR\n"
    "\n"
    "Computes the accessibility prior of an empty workcell (Anderson-Sprecher,\n"
    "Simmons and Huber) from its background grid G_B and writes it into DIR as\n"
    "  prior.cgprior    the prior image (certification/prior-image-format.md),\n"
    "                   for the Linux monitor's [prior] file = ...\n"
    "  prior_flash.hpp  the same image as C++ source, to compile into a firmware\n"
    "  p_acc.npy        P(acc) per voxel, float32, shape (nz, ny, nx)\n"
    "  p_fore.npy       P(fore) = P(acc) / 2 per voxel, float32, shape (nz, ny, nx)\n"
    "then reads every file back and checks it (the image with the controller's\n"
    "loader) and prints the image's CRCs and geometry.\n"
    "\n"
    "INPUT, one of (default: --simulated):\n"
    "  --simulated             the simulated paper cell's empty background: its four\n"
    "                          sensors looking at the reference scene (a demo)\n"
    "  --background-npy FILE   a background grid, shape (nz, ny, nx): int16 log-odds\n"
    "                          ('<i2', 1/256 nat, as the npy exporter writes) or\n"
    "                          float32 probability ('<f4', in [0, 1])\n"
    "  --observed FILE         uint8 observed flags for --background-npy (default: the\n"
    "                          sibling *_observed.npy of a *_log_odds.npy if it exists,\n"
    "                          else voxels without evidence count as unobserved)\n"
    "  --frames DIR            recorded frames of the empty cell: DIR/<sensor>/*.pcd,\n"
    "                          one folder per sensor of --config, points in the sensor\n"
    "                          frame; frame k is the k-th file (by name) of each sensor\n"
    "  --frame SENSOR=FILE     one more recorded .pcd of SENSOR (repeatable)\n"
    "  --config-frames         the `pcd_files` of --config's sensors as recorded frames\n"
    "                          (as the monitor replays them; combines with --frames)\n"
    "\n"
    "GRID:\n"
    "  --config FILE           a monitor configuration (apps/monitor/config/*.toml):\n"
    "                          [grid] and, for --frames, the sensors' names and poses;\n"
    "                          --simulated takes [grid] and [prior] background_frames\n"
    "                          (its sensors stay the simulated paper cell's)\n"
    "  --origin X,Y,Z          grid minimum corner, metres   (default: --config's, or\n"
    "  --voxel-size S          voxel edge, metres             the paper grid: 34 x 30 x 30\n"
    "  --dims NX,NY,NZ         voxels per axis                of 0.05 m from (-0.85,-0.75,0))\n"
    "                          with --background-npy the shape gives the dims; --dims\n"
    "                          or --config then only check it\n"
    "  --background-frames N   frames --simulated accumulates (default: --config's, or 8)\n"
    "\n"
    "ANALYSIS (defaults: the paper's):\n"
    "  --method M              probabilistic | thresholded | thresholded-baseline |\n"
    "                          probabilistic-baseline            (default probabilistic)\n"
    "  --tb T                  thresholded: empty when P(occ) < T, 0 < T < 1 (0.51)\n"
    "  --te T                  probabilistic: P(occ) < T counts as 0, 0 < T < 1 (0.1)\n"
    "  --radius R              object radius r in voxels, 0..8 (2)\n"
    "  --open-faces F          faces open to the outside: sides | all | none | a comma\n"
    "                          list of xmin,xmax,ymin,ymax,zmin,zmax (sides)\n"
    "\n"
    "OUTPUT:\n"
    "  --out DIR               output directory, created if missing (required)\n"
    "  --namespace NS          namespace of prior_flash.hpp (cellguard_prior)\n"
    "  --config-header H       header prior_flash.hpp includes first, e.g. the one that\n"
    "                          defines CELLGUARD_GRID_NX/NY/NZ\n"
    "  --progress              progress bar on stderr (default: on a terminal, for\n"
    "  --no-progress             frames and grids of 2^20 voxels or more)\n"
    "  --help                  this text\n"
    "  --version               print the version and exit\n"
    "\n"
    "Exit status: 0 written and verified, 1 an output could not be written or\n"
    "failed verification, 2 bad command line or bad input.\n";

/// A refused command line or input: the message for the one error line.
struct Failure {
    int status = kExitInputError;
    std::string message;
};

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

bool parse_int(const std::string& text, long min, long max, long& value) {
    if (text.empty()) {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (errno != 0 || end != text.c_str() + text.size() || v < min || v > max) {
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

struct Options {
    InputKind input = InputKind::kSimulated;
    bool input_given = false;
    std::string npy;
    std::string observed;
    std::string frames_dir;
    std::vector<std::pair<std::string, std::string>> frame_files;
    bool config_frames = false;
    std::string config;
    bool has_origin = false;
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    bool has_voxel_size = false;
    double voxel_size = 0.0;
    bool has_dims = false;
    GridDims dims{};
    int background_frames = -1;
    AccessibilityParams params{};
    std::string out_dir;
    std::string name_space = "cellguard_prior";
    std::string config_header;
    ProgressMode progress = ProgressMode::kAuto;
    bool help = false;
    bool version = false;
};

/// Parses @p raw into @p o; false with @p f set on a bad command line.
/// "--name=value" is read as "--name" "value".
bool parse_args(const std::vector<std::string>& raw, Options& o, Failure& f) {
    std::vector<std::string> args;
    for (const std::string& a : raw) {
        const std::size_t eq = a.find('=');
        if (a.rfind("--", 0) == 0 && eq != std::string::npos) {
            args.push_back(a.substr(0U, eq));
            args.push_back(a.substr(eq + 1U));
        } else {
            args.push_back(a);
        }
    }
    auto fail = [&](const std::string& m) {
        f.status = kExitInputError;
        f.message = m;
        return false;
    };
    auto set_input = [&](InputKind kind, const char* name) {
        if (o.input_given && o.input != kind) {
            return fail(std::string(name) + " excludes the other input (--simulated, --background-npy, --frames/--frame/--config-frames)");
        }
        o.input_given = true;
        o.input = kind;
        return true;
    };
    for (std::size_t i = 0U; i < args.size(); ++i) {
        const std::string& a = args[i];
        std::string v;
        auto value = [&](const char* name) {
            if (i + 1U >= args.size() || !host::is_option_value(args[i + 1U].c_str())) {
                return fail(std::string(name) + " needs a value");
            }
            v = args[++i];
            return true;
        };
        if (a == "--help" || a == "-h") {
            o.help = true;
            return true;
        } else if (a == "--version") {
            o.version = true;
            return true;
        } else if (a == "--simulated") {
            if (!set_input(InputKind::kSimulated, "--simulated")) return false;
        } else if (a == "--background-npy") {
            if (!value("--background-npy") || !set_input(InputKind::kNpy, "--background-npy")) return false;
            o.npy = v;
        } else if (a == "--observed") {
            if (!value("--observed")) return false;
            o.observed = v;
        } else if (a == "--frames") {
            if (!value("--frames") || !set_input(InputKind::kFrames, "--frames")) return false;
            if (!o.frames_dir.empty()) return fail("--frames given twice");
            o.frames_dir = v;
        } else if (a == "--frame") {
            if (!value("--frame") || !set_input(InputKind::kFrames, "--frame")) return false;
            const std::size_t eq = v.find('=');
            if (eq == std::string::npos || eq == 0U || eq + 1U == v.size()) {
                return fail("--frame expects SENSOR=FILE.pcd, got '" + v + "'");
            }
            o.frame_files.emplace_back(v.substr(0U, eq), v.substr(eq + 1U));
        } else if (a == "--config-frames") {
            if (!set_input(InputKind::kFrames, "--config-frames")) return false;
            o.config_frames = true;
        } else if (a == "--config") {
            if (!value("--config")) return false;
            o.config = v;
        } else if (a == "--origin") {
            double t[3];
            if (!value("--origin")) return false;
            if (!parse_triple(v, t)) return fail("--origin expects X,Y,Z in metres (finite numbers), got '" + v + "'");
            o.has_origin = true;
            o.origin = Eigen::Vector3d(t[0], t[1], t[2]);
        } else if (a == "--voxel-size") {
            if (!value("--voxel-size")) return false;
            if (!parse_double(v, o.voxel_size) || !(o.voxel_size > 0.0)) {
                return fail("--voxel-size expects a positive length in metres, got '" + v + "'");
            }
            o.has_voxel_size = true;
        } else if (a == "--dims") {
            if (!value("--dims")) return false;
            long d[3] = {0, 0, 0};
            std::size_t start = 0U;
            bool ok = true;
            for (int k = 0; k < 3 && ok; ++k) {
                const std::size_t comma = k < 2 ? v.find(',', start) : v.size();
                ok = comma != std::string::npos && parse_int(v.substr(start, comma - start), 1, kMaxDimension, d[k]);
                start = comma + 1U;
            }
            if (!ok) {
                return fail("--dims expects NX,NY,NZ, each 1.." + std::to_string(kMaxDimension) + ", got '" + v + "'");
            }
            o.has_dims = true;
            o.dims = GridDims{static_cast<std::int32_t>(d[0]), static_cast<std::int32_t>(d[1]),
                              static_cast<std::int32_t>(d[2])};
        } else if (a == "--background-frames") {
            long n = 0;
            if (!value("--background-frames")) return false;
            if (!parse_int(v, 1, 100000, n)) return fail("--background-frames expects an integer 1..100000, got '" + v + "'");
            o.background_frames = static_cast<int>(n);
        } else if (a == "--method") {
            if (!value("--method")) return false;
            if (!parse_method(v, o.params.method)) {
                return fail("--method expects probabilistic, thresholded, thresholded-baseline or "
                            "probabilistic-baseline, got '" + v + "'");
            }
        } else if (a == "--tb" || a == "--te") {
            double t = 0.0;
            if (!value(a.c_str())) return false;
            if (!parse_double(v, t) || !(t > 0.0 && t < 1.0)) {
                return fail(a + " expects a probability strictly between 0 and 1, got '" + v + "'");
            }
            (a == "--tb" ? o.params.t_b : o.params.t_e) = t;
        } else if (a == "--radius") {
            long r = 0;
            if (!value("--radius")) return false;
            if (!parse_int(v, 0, kMaxAccessibilityAnalysisRadius, r)) {
                return fail("--radius expects an integer 0.." + std::to_string(kMaxAccessibilityAnalysisRadius) +
                            " (voxels), got '" + v + "'");
            }
            o.params.radius_voxels = static_cast<std::int32_t>(r);
        } else if (a == "--open-faces") {
            if (!value("--open-faces")) return false;
            if (!parse_open_faces(v, o.params.open_faces)) {
                return fail("--open-faces expects sides, all, none or a comma list of xmin,xmax,ymin,ymax,zmin,zmax, "
                            "got '" + v + "'");
            }
        } else if (a == "--out") {
            if (!value("--out")) return false;
            if (v.empty()) return fail("--out expects a directory, got ''");
            o.out_dir = v;
        } else if (a == "--namespace") {
            if (!value("--namespace")) return false;
            o.name_space = v;
        } else if (a == "--config-header") {
            if (!value("--config-header")) return false;
            o.config_header = v;
        } else if (a == "--progress") {
            o.progress = ProgressMode::kOn;
        } else if (a == "--no-progress") {
            o.progress = ProgressMode::kOff;
        } else {
            return fail("unknown argument '" + a + "'");
        }
    }
    if (o.out_dir.empty()) {
        return fail("--out DIR is required (where the prior image, flash source and .npy files go)");
    }
    if (!o.observed.empty() && o.input != InputKind::kNpy) {
        return fail("--observed goes with --background-npy");
    }
    if (o.input == InputKind::kFrames && o.config.empty()) {
        return fail("--frames/--frame/--config-frames need --config FILE (the sensors' names and poses)");
    }
    if (o.background_frames > 0 && o.input != InputKind::kSimulated) {
        return fail("--background-frames goes with --simulated");
    }
    return true;
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
        std::string line = "\r" + std::string(stage) + " [" + std::string(filled, '#') + std::string(kWidth - filled, '.') +
                           "] " + std::to_string(done) + "/" + std::to_string(total) + "   ";
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
                std::snprintf(buf, sizeof(buf), " ... %.1f s   ", s);
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
    std::snprintf(buf, sizeof(buf), "%.1f ms", seconds * 1e3);
    return buf;
}

std::string geometry_text(const GridGeometry& g) {
    const GridDims d = g.dims();
    char buf[200];
    std::snprintf(buf, sizeof(buf), "%d x %d x %d voxels of %g m from (%g, %g, %g)", d.nx, d.ny, d.nz, g.voxel_size(),
                  g.origin().x(), g.origin().y(), g.origin().z());
    return buf;
}

bool file_exists(const std::string& path) {
    struct stat st {};
    return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool err_is_tty) {
    auto error = [&](int status, const std::string& message) {
        err << kToolName << ": " << message << "\n" << std::flush;
        return status;
    };
    Options o;
    Failure f;
    if (!parse_args(args, o, f)) {
        return error(f.status, f.message + " (see --help)");
    }
    if (o.help) {
        out << kUsage;
        return kExitOk;
    }
    if (o.version) {
        out << kToolName << " " << host::kVersion << "\n";
        return kExitOk;
    }

    // --namespace and --config-header: checked by the source generator, on a one-voxel image.
    {
        PriorSourceOptions probe;
        probe.name_space = o.name_space.c_str();
        probe.config_header = o.config_header.empty() ? nullptr : o.config_header.c_str();
        const GridGeometry one = GridGeometry::make(Eigen::Vector3d::Zero(), 1.0, GridDims{1, 1, 1}).value();
        const std::int16_t zero = 0;
        std::vector<std::uint8_t> image;
        std::string text;
        if (!encode_prior_image(one, AccessibilityParams{}, {&zero, 1U}, image).ok()) {
            return error(kExitOutputError, "internal: encoding a one-voxel probe image failed");
        }
        const Result<PriorImageView> view = load_prior_image({image.data(), image.size()}, one);
        const IoStatus st = view.ok() ? prior_source_text(view.value(), probe, text) : IoStatus{};
        if (!view.ok() || !st.ok()) {
            return error(kExitInputError, "--namespace '" + o.name_space + "' or --config-header '" + o.config_header +
                                              "' refused by the source generator: " + (st.ok() ? "" : st.message()));
        }
    }

    // Grid and sensors.
    GridGeometry grid = paper_grid_geometry();
    std::vector<RecordedSensor> sensors;
    int config_frames = 8;
    if (!o.config.empty()) {
        const IoStatus st = sensors_from_config(o.config, o.config_frames, sensors, grid, config_frames);
        if (!st.ok()) {
            return error(kExitInputError, std::string("configuration: ") + st.message());
        }
    }
    if (o.input == InputKind::kNpy && o.config.empty() && !(o.has_origin && o.has_voxel_size)) {
        return error(kExitInputError,
                     "--background-npy needs the grid's placement: --origin X,Y,Z and --voxel-size S, or --config FILE");
    }
    const Eigen::Vector3d origin = o.has_origin ? o.origin : grid.origin();
    const double voxel_size = o.has_voxel_size ? o.voxel_size : grid.voxel_size();
    const GridDims dims = o.has_dims ? o.dims : grid.dims();
    if (o.input != InputKind::kNpy) {
        const Result<GridGeometry> g = GridGeometry::make(origin, voxel_size, dims);
        if (!g.ok()) {
            return error(kExitInputError, std::string("grid: ") + to_string(g.error()));
        }
        grid = g.value();
    }

    // The background.
    const auto t_start = std::chrono::steady_clock::now();
    BackgroundGrid background;
    std::string background_text;
    bool progress_on = o.progress == ProgressMode::kOn;
    if (o.input == InputKind::kNpy) {
        NpyPlacement placement;
        placement.origin = origin;
        placement.voxel_size = voxel_size;
        placement.check_dims = o.has_dims || !o.config.empty();
        placement.dims = dims;
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
            return error(kExitInputError, st.message());
        }
        grid = background.grid.geometry();
        background_text = o.npy + " (" + (info.float_input ? "float32 probability" : "int16 log-odds") + "), " +
                          "observed flags: " + info.observed_source + ", " + std::to_string(info.observed_voxels) +
                          " of " + std::to_string(grid.voxel_count()) + " observed";
    } else {
        if (o.progress == ProgressMode::kAuto) {
            progress_on = err_is_tty;
        }
        IoStatus st = background.allocate(grid);
        if (!st.ok()) {
            return error(kExitInputError, st.message());
        }
        Progress progress(err, progress_on);
        const ProgressFn report = [&](std::size_t done, std::size_t total) { progress.bar("fusing frames", done, total); };
        if (o.input == InputKind::kSimulated) {
            const int frames = o.background_frames > 0 ? o.background_frames : config_frames;
            if (const std::string why = too_few_frames(static_cast<std::size_t>(frames), o.params); !why.empty()) {
                return error(kExitInputError, why);
            }
            SimulatedFrameSource source(static_cast<std::size_t>(frames));
            st = accumulate_frames(source, background, report);
            background_text = "the simulated paper cell's empty background, " + std::to_string(source.sensor_count()) +
                              " sensors, " + std::to_string(frames) + " frames";
        } else {
            if (!o.frames_dir.empty()) {
                st = add_frames_dir(o.frames_dir, sensors);
                if (!st.ok()) {
                    return error(kExitInputError, st.message());
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
                    return error(kExitInputError,
                                 "--frame " + sf.first + "=" + sf.second + ": no sensor '" + sf.first + "' in " + o.config);
                }
            }
            std::string counts;
            for (const RecordedSensor& s : sensors) {
                counts += (counts.empty() ? "" : ", ") + s.name + " " + std::to_string(s.files.size());
            }
            PcdFrameSource source(sensors);
            if (source.frame_count() == 0U) {
                return error(kExitInputError, "no recorded frames: " + o.config + "'s sensors have no pcd_files");
            }
            if (const std::string why = too_few_frames(source.frame_count(), o.params); !why.empty()) {
                return error(kExitInputError, why);
            }
            st = accumulate_frames(source, background, report);
            background_text = "recorded frames (" + std::to_string(source.frame_count()) + "; files per sensor: " +
                              counts + ")";
        }
        if (!st.ok()) {
            return error(kExitInputError, st.message());
        }
    }
    if (o.progress == ProgressMode::kAuto) {
        progress_on = err_is_tty && grid.voxel_count() >= kLargeGridVoxels;
    }
    out << kToolName << ": background: " << background_text << "\n";
    out << kToolName << ": grid: " << geometry_text(grid) << "\n";

    // The output directory, before the analysis (which may be long).
    {
        std::error_code ec;
        std::filesystem::create_directories(o.out_dir, ec);
        if (ec || !std::filesystem::is_directory(o.out_dir, ec)) {
            return error(kExitOutputError, o.out_dir + ": cannot create the output directory" +
                                               (ec ? ": " + ec.message() : std::string(" (a file of that name exists)")));
        }
    }

    // The analysis.
    PriorResult result;
    {
        Progress progress(err, progress_on);
        progress.start_ticker(std::string("accessibility analysis (") + method_name(o.params.method) + ")");
        const IoStatus st = compute_prior(background.grid, o.params, result);
        progress.stop_ticker();
        if (!st.ok()) {
            return error(kExitOutputError, st.message());
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

    // The outputs.
    PriorSourceOptions source_options;
    source_options.name_space = o.name_space.c_str();
    source_options.config_header = o.config_header.empty() ? nullptr : o.config_header.c_str();
    WrittenOutputs written;
    const auto t_analysed = std::chrono::steady_clock::now();
    IoStatus st;
    {
        Progress progress(err, progress_on);
        st = write_prior_outputs(o.out_dir, grid, o.params, result, source_options, written,
                                 [&](std::size_t done, std::size_t total) { progress.bar("writing, verifying", done, total); });
    }
    const auto t_written = std::chrono::steady_clock::now();
    if (!st.ok()) {
        return error(kExitOutputError, st.message());
    }
    const PriorImageHeader& h = written.header;
    char crc[96];
    std::snprintf(crc, sizeof(crc), "payload CRC-32 0x%08X, header CRC-32 0x%08X", h.payload_crc, h.header_crc);
    out << kToolName << ": wrote " << written.image_path << " (" << written.image_bytes << " bytes), "
        << written.source_path << ", " << written.p_acc_path << ", " << written.p_fore_path << "\n";
    out << kToolName << ": verified: " << written.image_path << " loads with load_prior_image: format "
        << h.format_version << ", " << h.nx << " x " << h.ny << " x " << h.nz << " voxels of " << h.voxel_size()
        << " m from (" << h.origin().x() << ", " << h.origin().y() << ", " << h.origin().z() << "), " << crc
        << "; flash source and .npy files read back equal\n";
    char times[160];
    std::snprintf(times, sizeof(times), "time: background and set-up %.2f s, analysis %.1f ms, outputs written and verified %.2f s",
                  std::chrono::duration<double>(t_analysed - t_start).count() - result.seconds, result.seconds * 1e3,
                  std::chrono::duration<double>(t_written - t_analysed).count());
    out << kToolName << ": " << times << "\n";
    out << std::flush;
    return kExitOk;
}

}  // namespace

const char* usage_text() noexcept { return kUsage; }

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
