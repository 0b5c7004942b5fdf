// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file detection.hpp
/// Detection capability, measured (ISO 13855's d, IEC 61496's test pieces):
/// test pieces (test_piece.hpp: cylinders with flat ends, spheres) placed at
/// seeded random poses inside one zone of a monitor configuration, rendered
/// over the simulated cameras' view of the empty cell with the cameras'
/// noise, and fed to the monitor's own cycle (MonitorCell, MonitorLoop: the
/// configuration's fusion, prior, zones and thresholds, a simulated PLC
/// selecting the first monitoring case).
///
/// Per pose: the piece appears in cycle j and stays for `cycles` cycles; the
/// pose counts as detected when the zone is INTRUDED (its state in the
/// zone evaluation, before any fault overrides the outputs) in one of them.
/// Per method, size and placement: the poses detected and the one-sided 95 %
/// Clopper-Pearson lower bound of the detection probability. Beside them,
/// the empty cell with the same noise: the cycles in which the zone was
/// INTRUDED with nothing in it (false stops of a protective zone).
///
/// Seeds: pose i of a (size, placement) row is drawn from the generator
/// sim::sensor_seed(seed, row) in order; frame noise of cycle c of sensor s
/// from sim::sensor_seed(seed * 1000003 + c, s) (shards: see
/// DetectionSettings::jobs). The same settings give the same table.
#ifndef CELLGUARD_MONITOR_DETECTION_HPP
#define CELLGUARD_MONITOR_DETECTION_HPP

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/depth_conditioning.hpp"
#include "cellguard/host/sim/noise.hpp"
#include "cellguard/host/sim/test_piece.hpp"
#include "cellguard/prior/accessibility_params.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::monitor {

/// The zone's min_foreground_voxels values every run reports (1 to this), beside
/// the configured one: the zone's foreground count in a cycle does not depend
/// on it (zone_evaluation.hpp: INTRUDED when the count reaches it), so one run
/// gives the detection rates and false stops of each (the trade-off of issue 35).
inline constexpr std::size_t kMinVoxelsColumns = 4U;

/// Most threads (DetectionSettings::jobs) a run uses.
inline constexpr int kMaxDetectionJobs = 64;

/// Where a piece lies in its zone.
enum class Placement : std::uint8_t {
    kFree = 0,    ///< anywhere inside, at any orientation, not touching the floor or a box
    kFloor = 1,   ///< lying on the floor (a cylinder's axis horizontal), at any yaw
    kBoxTop = 2,  ///< lying on a background box's top face (1 mm above it), at any yaw
};

/// Static name of a placement ("free", "floor", "box top").
const char* to_string(Placement placement) noexcept;

/// A test piece's shape and size.
struct PieceSize {
    sim::PieceShape shape = sim::PieceShape::kCylinder;  ///< cylinder or sphere
    double diameter = 0.0;                               ///< metres
    double length = 0.0;                                 ///< cylinder: metres (0 for a sphere)
};

/// The experiment's settings.
struct DetectionSettings {
    std::string zone = "protective";  ///< the zone the pieces are placed in (by name)
    /// The pieces: by default cylinders of 20, 30, 40, 55, 70, 100, 150 and
    /// 200 mm diameter, 300 mm long, and spheres of the same diameters.
    std::vector<PieceSize> sizes = default_sizes();
    /// The placements tried (a size that fits nowhere in one has a row without poses).
    std::vector<Placement> placements{Placement::kFree, Placement::kFloor, Placement::kBoxTop};
    std::vector<PriorMethod> methods{PriorMethod::kProbabilistic, PriorMethod::kThresholded};  ///< the priors
    int poses = 1000;        ///< poses per method, size and placement
    int cycles = 2;          ///< k: cycles the piece stays (detected in any of them)
    int empty_cycles = 200;  ///< empty-cell cycles per method (false INTRUDED counted)
    int warmup_cycles = 10;  ///< cycles before the first counted one (the PLC's first command)
    /// The cameras' noise (sim::tof_camera_noise: 1 % of range, flying
    /// pixels, dropouts); kind kIdeal: noise-free frames.
    sim::NoiseModel noise = sim::tof_camera_noise();
    /// The cameras' own filters on each noisy frame (depth_conditioning.hpp;
    /// the background tolerance against the empty cell's noise-free image). Off by default.
    cell::DepthConditioning conditioning{};
    std::uint64_t seed = 1U;  ///< the seed of poses and noise
    /// Threads (1..kMaxDetectionJobs), each a shard with a cell of its own:
    /// pose p of a row in shard p mod jobs, the empty cycles split evenly,
    /// shard j's frame noise of its cycle c drawn as for cycle c + j * 2^40.
    /// The same poses at every jobs; the same jobs and seed give the same table.
    int jobs = 1;
    /// The default pieces (see sizes).
    static std::vector<PieceSize> default_sizes();
};

/// One row of the result: a method, a size and a placement.
struct DetectionRow {
    PriorMethod method = PriorMethod::kProbabilistic;  ///< the prior's method
    PieceSize size{};                                  ///< the piece
    Placement placement = Placement::kFree;            ///< where it lay
    int poses = 0;                                     ///< poses tried
    int detected = 0;                                  ///< poses with the zone INTRUDED within k cycles
    double lower_bound = 0.0;                          ///< one-sided 95 % Clopper-Pearson lower bound
    /// [n - 1]: poses in which the zone held at least n foreground voxels in
    /// one of the k cycles (detected had its min_foreground_voxels been n).
    std::array<int, kMinVoxelsColumns> detected_with{};
    /// Poses detected at min_foreground_voxels @p n (1..kMinVoxelsColumns; 0: as configured).
    [[nodiscard]] int detected_at(std::size_t n) const noexcept {
        return n == 0U || n > kMinVoxelsColumns ? detected : detected_with[n - 1U];
    }
};

/// One method's empty cell.
struct EmptyCellRow {
    PriorMethod method = PriorMethod::kProbabilistic;  ///< the prior's method
    int cycles = 0;                                    ///< empty-cell cycles run
    int intruded = 0;                                  ///< of them with the zone INTRUDED (false stops)
    std::uint32_t max_foreground = 0U;                 ///< the zone's most foreground voxels in one cycle
    std::uint64_t foreground_sum = 0U;                 ///< the zone's foreground voxels summed over the cycles
    int unseen = 0;  ///< cycles with more unseen voxels than the zone allows (a stop at every n unless INTRUDED)
    /// [n - 1]: cycles that would have stopped had the zone's
    /// min_foreground_voxels been n (at least n foreground voxels, or UNSEEN).
    std::array<int, kMinVoxelsColumns> stops_with{};
};

/// The experiment's result.
struct DetectionResult {
    std::string error;                ///< why it could not run (empty: it ran)
    std::vector<DetectionRow> rows;   ///< per method, size and placement, in the settings' order
    std::vector<EmptyCellRow> empty;  ///< per method
    std::uint64_t cycles_run = 0U;    ///< every cycle of the run
    /// The smallest diameter of @p shape detected in every pose of every
    /// placement it was tried in (rows without poses left out) with @p
    /// method, every larger one of that shape too; 0: none. @p min_voxels:
    /// as had the zone's min_foreground_voxels been that (0: as configured).
    [[nodiscard]] double smallest_always_detected(PriorMethod method, sim::PieceShape shape,
                                                  std::size_t min_voxels = 0U) const noexcept;
};

/// One-sided lower confidence bound (Clopper-Pearson) at @p confidence on a
/// probability of which @p successes of @p trials happened: the p at which
/// P(X >= successes) = 1 - confidence (0 for no success). Trials 1..10^6.
[[nodiscard]] double clopper_pearson_lower(int successes, int trials, double confidence = 0.95) noexcept;

/// One-sided upper confidence bound (Clopper-Pearson) at @p confidence:
/// 1 - clopper_pearson_lower(trials - events, trials) (1 for no trial).
[[nodiscard]] double clopper_pearson_upper(int events, int trials, double confidence = 0.95) noexcept;

/// A seeded random pose of @p size in @p zone with @p placement (see
/// Placement), clear of @p boxes: false when 10,000 draws found none (the
/// piece does not fit).
[[nodiscard]] bool random_pose(const ZoneConfig& zone, const PieceSize& size, Placement placement,
                               const std::vector<sim::Box>& boxes, sim::Rng& rng, sim::TestPiece& out);

/// Runs the experiment on the monitor configuration @p cfg (its sensors must
/// all be simulated); progress lines to @p progress (nullptr: quiet).
DetectionResult run_detection(const cell::MonitorConfig& cfg, const DetectionSettings& settings, std::FILE* progress);

/// Writes @p result as a Markdown table (and the empty cell's rows, and the
/// trade-off over min_foreground_voxels 1..kMinVoxelsColumns: false stops per
/// hour at @p cycle_hz against d) to @p out.
void write_detection_table(std::FILE* out, const DetectionSettings& settings, const DetectionResult& result,
                           double cycle_hz);

/// Writes @p result's rows as CSV to @p out: a header, then per row
/// cell,prior,shape,diameter_mm,length_mm,placement,detected,poses,rate,lower_bound,
/// detected_min1..detected_min4 (@p cell names the configuration in the first column).
void write_detection_csv(std::FILE* out, const std::string& cell, const DetectionResult& result);

/// A gnuplot script that draws the detection rate of @p result against the
/// diameter, one line per prior, shape and placement (the data in the
/// script), into @p png_path.
[[nodiscard]] std::string detection_plot_script(const std::string& png_path, const std::string& title,
                                                const DetectionResult& result);

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_DETECTION_HPP
