// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file prior_tool.hpp
/// cellguard-prior, the commissioning tool that turns the background of an
/// empty workcell into the accessibility prior (the paper's sections II-IV)
/// and writes it in every form the controllers take: the prior image file
/// (certification/prior-image-format.md), generated C++ source for flash,
/// and float32 .npy files of P(acc) and P(fore) for inspection.
///
/// The command line is run_prior_tool(); main() only forwards to it, so the
/// unit tests drive the whole tool in-process. The steps are public for the
/// tests and for other host tools:
/// - the background G_B: from a .npy grid (load_background_npy), from
///   recorded .pcd frames with sensor poses from the monitor's TOML
///   configuration (RecordedFrameSource), or from the simulated empty paper cell
///   (SimulatedFrameSource), fused and accumulated as the monitor and the
///   firmware generator do (accumulate_frames);
/// - the analysis (compute_prior: lib's compute_accessibility_prior);
/// - the outputs, written and then verified by reading them back
///   (write_prior_outputs).
///
/// Every error is an IoStatus whose message names the file or option and
/// what is wrong. Host code: uses the heap and the standard library; the
/// steps may throw std::bad_alloc, run_prior_tool catches it.
#ifndef CELLGUARD_PRIOR_TOOL_PRIOR_TOOL_HPP
#define CELLGUARD_PRIOR_TOOL_PRIOR_TOOL_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/grid.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/grid/sensor_model.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/pcd_input.hpp"
#include "cellguard/host/io/io_status.hpp"
#include "cellguard/host/io/prior_files.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/prior/accessibility_params.hpp"

namespace cellguard::prior_tool {

/// Exit status: outputs written and verified.
constexpr int kExitOk = 0;
/// Exit status: an output could not be written or failed verification.
constexpr int kExitOutputError = 1;
/// Exit status: bad command line or bad input (file missing, unreadable or wrong).
constexpr int kExitInputError = 2;

/// File names written into the output directory.
constexpr const char* kPriorImageName = "prior.cgprior";
/// The generated flash source.
constexpr const char* kPriorSourceName = "prior_flash.hpp";
/// P(acc) per voxel, float32, shape (nz, ny, nx).
constexpr const char* kPAccName = "p_acc.npy";
/// P(fore) = P(acc) / 2 per voxel, float32, shape (nz, ny, nx).
constexpr const char* kPForeName = "p_fore.npy";

/// Runs the tool with @p args (without the program name). Normal output goes
/// to @p out, errors (one line each, "cellguard-prior: ...") and the progress
/// bar to @p err. @p err_is_tty switches the progress bar on by default.
/// Returns the exit status (kExitOk, kExitOutputError, kExitInputError);
/// never exits the process and never throws.
int run_prior_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                   bool err_is_tty) noexcept;

/// Method name on the command line: "thresholded", "probabilistic",
/// "thresholded-baseline", "probabilistic-baseline".
const char* method_name(PriorMethod method) noexcept;
/// Parses a method name (see method_name); false for anything else.
bool parse_method(const std::string& text, PriorMethod& method) noexcept;
/// Parses open faces: "sides" (the paper's A_0), "all", "none", or a comma
/// list of xmin, xmax, ymin, ymax, zmin, zmax; false for anything else.
bool parse_open_faces(const std::string& text, std::uint8_t& faces);
/// The open faces as a comma list ("none" when there are none).
std::string open_faces_list(std::uint8_t faces);

/// A background grid G_B with its own storage. Not copyable (the grid
/// refers to the vectors' storage); moving keeps it valid.
struct BackgroundGrid {
    std::vector<std::int16_t> log_odds;  ///< one per voxel
    std::vector<std::uint8_t> observed;  ///< one per voxel, 0 or 1
    EvidenceGrid grid;                   ///< over the two vectors

    BackgroundGrid() = default;
    BackgroundGrid(const BackgroundGrid&) = delete;
    BackgroundGrid& operator=(const BackgroundGrid&) = delete;
    BackgroundGrid(BackgroundGrid&&) noexcept = default;
    BackgroundGrid& operator=(BackgroundGrid&&) noexcept = default;
    ~BackgroundGrid() = default;

    /// Allocates storage for @p geometry and binds the grid to it, cleared
    /// (log-odds 0, unobserved). Errors: kInvalidArgument (empty geometry),
    /// kCapacityExceeded (allocation failed).
    IoStatus allocate(const GridGeometry& geometry);
};

/// Where a .npy grid sits in the world: the shape gives the voxel counts.
struct NpyPlacement {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< minimum corner, metres
    double voxel_size = 0.0;                           ///< edge, metres
    bool check_dims = false;                           ///< compare the shape with `dims`
    GridDims dims{};                                   ///< expected (nx, ny, nz) when check_dims
};

/// What load_background_npy found.
struct NpyBackgroundInfo {
    bool float_input = false;         ///< float32 probability (else int16 log-odds)
    std::string observed_source;      ///< file the observed flags came from, or how they were derived
    std::size_t observed_voxels = 0;  ///< voxels flagged observed
};

/// Reads a background grid from @p path: a 3-D .npy of shape (nz, ny, nx),
/// int16 log-odds ('<i2', as the npy exporter writes; the sentinel -32768 is
/// refused) or float32 probability ('<f4', every value finite and in
/// [0, 1]; 0 becomes the smallest finite log-odds, never the sentinel). The
/// observed flags come from @p observed_path (a uint8 .npy of the same
/// shape, values 0 or 1) when it is not empty; otherwise a voxel counts as
/// unobserved exactly when it holds no evidence (log-odds 0, probability
/// 0.5). Treating such voxels as unobserved can only raise P(acc) (eq. 13's
/// f = 0 instead of 0.5; the thresholded method reads both as P(occ) = 0.5),
/// the safe direction. On error @p out is left empty. Errors name the file:
/// kTruncatedInput, kMalformedInput, kUnsupportedType (dtype), kGeometryMismatch
/// (not 3-D, or the shape differs from placement.dims), kNonFiniteValue,
/// kInvalidArgument (unreadable, or a value out of range), kCapacityExceeded.
IoStatus load_background_npy(const std::string& path, const std::string& observed_path, const NpyPlacement& placement,
                             BackgroundGrid& out, NpyBackgroundInfo& info);

/// Background frames to fuse: frame k is a set of sensor readings.
class FrameSource {
public:
    FrameSource() = default;
    FrameSource(const FrameSource&) = delete;
    FrameSource& operator=(const FrameSource&) = delete;
    FrameSource(FrameSource&&) = delete;
    FrameSource& operator=(FrameSource&&) = delete;
    virtual ~FrameSource() = default;
    /// Number of frames.
    [[nodiscard]] virtual std::size_t frame_count() const = 0;
    /// The readings of frame @p k (< frame_count()), valid until the next call.
    virtual IoStatus frame(std::size_t k, std::vector<SensorReading>& readings) = 0;
};

/// The simulated paper cell (apps/simulator): the paper's four sensors
/// looking at the reference scene without a person, rendered once and
/// returned @p frames times (the simulator is noise-free).
class SimulatedFrameSource final : public FrameSource {
public:
    /// Renders the empty reference scene for @p frames frames.
    explicit SimulatedFrameSource(std::size_t frames);
    [[nodiscard]] std::size_t frame_count() const override { return frames_; }
    IoStatus frame(std::size_t k, std::vector<SensorReading>& readings) override;
    /// Number of simulated sensors.
    [[nodiscard]] std::size_t sensor_count() const { return rendered_.readings.size(); }

private:
    sim::SimulatedFrame rendered_;
    std::size_t frames_;
};

/// One recording sensor: its pose in the cell, its image size and its
/// recorded .pcd files (points in the sensor frame: x right, y down, z along
/// the optical axis).
struct RecordedSensor {
    std::string name;                                        ///< as in the configuration
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> cell
    int width = 0;                                           ///< image columns (capacity: width x height points)
    int height = 0;                                          ///< image rows
    float max_range = 10.0F;                                 ///< readings beyond are not fused
    double hfov_deg = 0.0;                                   ///< horizontal field of view (its view's direction grid)
    double vfov_deg = 0.0;                                   ///< vertical field of view
    std::vector<std::string> files;                          ///< its frames, in order (.pcd point sets)
    PinholeIntrinsics intrinsics{};                          ///< the cell's model of its camera (depth images)
    cell::DepthRecordingSettings recording;                  ///< its recorded depth images (`depth_files`), in order
};

/// Recorded frames: frame k holds the k-th file of every sensor that has
/// one, .pcd point sets (`pcd_files`, --frames, --frame) or depth images
/// (`depth_files`). Each file is read and checked by the monitor's reader
/// (apps/host pcd_input.hpp: decodes, at most width x height points, an
/// organised cloud of the sensor's resolution, a VIEWPOINT without
/// translation or equal to the configured pose; depth_input.hpp: the .npy
/// format, dtype and the sensor's (height, width)); a file that fails is an
/// error naming it, never a frame left out silently.
class RecordedFrameSource final : public FrameSource {
public:
    /// Frames of @p sensors (each with at least one file, else it is left out).
    explicit RecordedFrameSource(const std::vector<RecordedSensor>& sensors);
    [[nodiscard]] std::size_t frame_count() const override { return frames_; }
    IoStatus frame(std::size_t k, std::vector<SensorReading>& readings) override;

private:
    std::vector<std::unique_ptr<cell::FrameSource>> sources_;
    std::vector<std::string> names_;
    std::vector<std::size_t> file_counts_;
    std::size_t frames_ = 0U;
};

/// The sensors of a monitor configuration file (apps/monitor/config/*.toml)
/// with their poses (`target`: the simulator's convention, x horizontal;
/// `rotation`: as given) and, when @p with_pcd_files, their `pcd_files` as
/// recorded frames; also its grid and [prior] background_frames. Errors: the
/// loader's message (file, line, key), or a `target` straight above or below
/// the sensor (no horizontal axis; give `rotation`).
IoStatus sensors_from_config(const std::string& config_path, bool with_pcd_files, std::vector<RecordedSensor>& sensors,
                             GridGeometry& grid, int& background_frames);

/// Adds the recordings in @p dir: one subfolder per sensor, named as in the
/// configuration, holding that sensor's .pcd files (taken in name order).
/// Errors: the folder cannot be read, a subfolder names no configured
/// sensor, or no .pcd file at all.
IoStatus add_frames_dir(const std::string& dir, std::vector<RecordedSensor>& sensors);

/// Called with (frames done, frames in total).
using ProgressFn = std::function<void(std::size_t, std::size_t)>;

/// Fuses every frame of @p frames into a fresh frame grid and accumulates it
/// into @p background (cleared first; BackgroundClamp's defaults), as the
/// monitor and the firmware generator build their simulated background.
/// Errors: the source's, or fusion's (naming the frame).
IoStatus accumulate_frames(FrameSource& frames, BackgroundGrid& background, const ProgressFn& progress);

/// The computed prior and what to inspect.
struct PriorResult {
    std::vector<std::int16_t> prior;  ///< int16 log-odds of P(fore), kNeverForeground where 0
    std::vector<float> p_acc;         ///< P(acc) (baselines: what they use in its place)
    std::vector<float> p_fore;        ///< P(acc) / 2
    double seconds = 0.0;             ///< wall time of compute_accessibility_prior
};

/// Runs compute_accessibility_prior on @p background with @p params.
/// Errors: kInvalidArgument (params), kCapacityExceeded (allocation), lib's errors.
IoStatus compute_prior(const EvidenceGrid& background, const AccessibilityParams& params, PriorResult& result);

/// What write_prior_outputs wrote and read back.
struct WrittenOutputs {
    std::string image_path;        ///< the prior image
    std::string source_path;       ///< the flash source
    std::string p_acc_path;        ///< P(acc) .npy
    std::string p_fore_path;       ///< P(fore) .npy
    std::size_t image_bytes = 0U;  ///< size of the image
    PriorImageHeader header{};     ///< the header as re-read by the loader
};

/// Writes the four outputs into @p dir (created with its parents when
/// missing), then verifies each: the image file re-read with
/// read_prior_image_file against @p geometry and compared byte for byte
/// with the encoded image, the source file compared with prior_source_text
/// of the re-read image, the .npy files re-read and compared bit for bit.
/// @p progress, when set, is called after each of the eight steps.
/// Errors: kInvalidArgument (a write failed, with the OS message),
/// kCrcMismatch (a file read back differs), the loader's errors.
IoStatus write_prior_outputs(const std::string& dir, const GridGeometry& geometry, const AccessibilityParams& params,
                             const PriorResult& result, const PriorSourceOptions& source_options,
                             WrittenOutputs& written, const ProgressFn& progress = {});

}  // namespace cellguard::prior_tool

#endif  // CELLGUARD_PRIOR_TOOL_PRIOR_TOOL_HPP
