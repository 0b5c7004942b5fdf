// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file noise.hpp
/// Sensor noise models for the simulated workcell: a flash lidar (SR4000
/// class) and a stereo camera (TYZX G3 EVS class). They act on the ideal depth
/// images of render_depth (workcell.hpp), which stay the default everywhere:
/// the existing render_frame is ideal and unchanged.
///
/// Flash lidar, per pixel with a reading at range R (metres along the ray):
/// - mixed pixels: a pixel with a 4-neighbour whose depth differs by more
///   than mixed_pixel_edge_m sees both surfaces; with probability
///   mixed_pixel_probability its depth becomes w * own + (1 - w) * neighbour
///   (the neighbour of the largest jump, w uniform in [0, 1]): the "flying
///   pixels" between a foreground edge and what lies behind it;
/// - range noise: R += N(0, sigma), sigma = range_sigma_base_m +
///   range_sigma_per_m * R (about 1 cm at 2 m with the defaults);
/// - dropouts: with probability missing_probability (0 by default) a pixel
///   has no reading (tof_camera_noise: 1 %).
///
/// Stereo camera, per pixel with depth z (along the optical axis):
/// - missing pixels: at a depth edge (a 4-neighbour differing by more than
///   edge_missing_m) with probability edge_missing_probability (occlusion
///   and matching failures at boundaries), elsewhere with probability
///   missing_probability; a missing pixel reads 0 (no reading);
/// - depth noise through the disparity d = f b / z (f = the image's fx in
///   pixels, b = baseline_m): d += N(0, disparity_sigma_px), rounded to
///   disparity_quantum_px when that is > 0, z = f b / d. To first order
///   sigma_z = z^2 sigma_d / (f b): it grows with the square of depth.
///   A disparity at or below min_disparity_px gives no reading.
///
/// Determinism: every random number comes from a SplitMix64 generator
/// seeded from (seed, sensor index) and drawn in pixel order, with normals by
/// the Box-Muller transform: the same seed gives the same frame with any
/// compiler and standard library (no <random> distributions).
#ifndef CELLGUARD_HOST_SIM_NOISE_HPP
#define CELLGUARD_HOST_SIM_NOISE_HPP

#include <cstdint>
#include <vector>

#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::sim {

/// Which noise model a sensor uses.
enum class SensorKind : std::uint8_t {
    kIdeal = 0,       ///< exact depths (render_depth)
    kFlashLidar = 1,  ///< FlashLidarNoise
    kStereo = 2,      ///< StereoNoise
};

/// Static name of a sensor kind ("ideal", "flash_lidar", "stereo").
const char* to_string(SensorKind kind);

/// Parameters of the flash-lidar model; defaults are SR4000-like.
struct FlashLidarNoise {
    double range_sigma_base_m = 0.004;     ///< standard deviation of range noise at range 0, metres
    double range_sigma_per_m = 0.003;      ///< growth of that standard deviation per metre of range
    double mixed_pixel_edge_m = 0.05;      ///< depth jump to a 4-neighbour that makes a pixel an edge pixel, metres
    double mixed_pixel_probability = 0.5;  ///< chance that an edge pixel reads a mixture of both depths
    /// Dropouts: chance that a pixel has no reading (reads 0). 0 (the SR4000
    /// model's default): none, and no number is drawn for them, so the paper's
    /// frames are those of the model without this field.
    double missing_probability = 0.0;
};

/// Parameters of the stereo model; defaults are TYZX-G3-like.
struct StereoNoise {
    double baseline_m = 0.22;               ///< stereo baseline b, metres
    double disparity_sigma_px = 0.15;       ///< standard deviation of the disparity, pixels
    double disparity_quantum_px = 0.0625;   ///< sub-pixel step of the disparity (1/16 px); 0 = continuous
    double min_disparity_px = 1.0;          ///< disparities at or below this give no reading
    double missing_probability = 0.02;      ///< chance that a pixel off any depth edge has no reading
    double edge_missing_m = 0.05;           ///< depth jump to a 4-neighbour that makes a pixel an edge pixel, metres
    double edge_missing_probability = 0.6;  ///< chance that an edge pixel has no reading
};

/// A sensor's noise model: its kind and the parameters of every kind (only
/// those of `kind` are used).
struct NoiseModel {
    SensorKind kind = SensorKind::kIdeal;  ///< which model applies
    FlashLidarNoise lidar{};               ///< used when kind is kFlashLidar
    StereoNoise stereo{};                  ///< used when kind is kStereo
};

/// The paper's models for paper_sensors(), in the same order: two flash
/// lidars, two stereo cameras, default parameters.
std::vector<NoiseModel> paper_noise_models();

/// The seed of sensor @p sensor_index's generator in frame @p frame_seed
/// (a SplitMix64 mix of both), exposed for tests.
std::uint64_t sensor_seed(std::uint64_t frame_seed, std::size_t sensor_index);

/// A small deterministic generator (SplitMix64) with uniform and normal draws.
class Rng {
public:
    /// Starts the sequence of @p seed.
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    /// The next 64 random bits.
    std::uint64_t next_u64();
    /// Uniform in [0, 1), 53 bits.
    double uniform();
    /// Standard normal (Box-Muller, both values used).
    double normal();

private:
    std::uint64_t state_;
    double spare_ = 0.0;
    bool has_spare_ = false;
};

/// A time-of-flight camera as detection tests assume one (the flash-lidar
/// model): range noise of @p range_sigma_per_m per metre of range (0.01: 1 %,
/// 3 cm at 3 m) and none at range 0, flying pixels at depth edges of more than
/// 5 cm (each edge pixel with probability 0.5), 1 % dropouts.
NoiseModel tof_camera_noise(double range_sigma_per_m = 0.01);

/// apply_noise into caller storage: @p depth (exactly width * height values)
/// in place, @p ideal (as many) receives the ideal image the model reads
/// edges from. False, with nothing changed, when a size differs. Allocates
/// nothing; the same image as the vector form, bit for bit.
[[nodiscard]] bool apply_noise(const SensorSpec& sensor, const NoiseModel& model, Span<float> depth, Span<float> ideal,
                               Rng& rng) noexcept;

/// Applies @p model to the ideal depth image @p depth of @p sensor in place
/// (row-major, width * height values, 0 = no reading), drawing from @p rng.
void apply_noise(const SensorSpec& sensor, const NoiseModel& model, std::vector<float>& depth, Rng& rng);

/// Renders every sensor of @p sensors looking at @p scene, then applies
/// models[i] to sensor i with the generator sensor_seed(seed, i). A missing
/// model (models shorter than sensors) means ideal. The same (sensors,
/// models, scene, seed) give the same frame.
SimulatedFrame render_noisy_frame(const std::vector<SensorSpec>& sensors, const std::vector<NoiseModel>& models,
                                  const Scene& scene, std::uint64_t seed);

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_NOISE_HPP
