// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/sim/noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cellguard::sim {

namespace {
constexpr double kTwoPi = 6.28318530717958647692;

std::uint64_t splitmix64(std::uint64_t& state) {
    state += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state;
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
}

// The 4-neighbour of pixel (u, v) whose depth differs most from the pixel's,
// among neighbours with a reading; returns that depth and the jump.
struct EdgeNeighbour {
    float depth = 0.0F;
    double jump = 0.0;
};

EdgeNeighbour largest_jump(Span<const float> depth, std::int32_t w, std::int32_t h, std::int32_t u, std::int32_t v) {
    const float own = depth[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)];
    EdgeNeighbour best;
    const std::int32_t du[4] = {-1, 1, 0, 0};
    const std::int32_t dv[4] = {0, 0, -1, 1};
    for (int k = 0; k < 4; ++k) {
        const std::int32_t nu = u + du[k];
        const std::int32_t nv = v + dv[k];
        if (nu < 0 || nv < 0 || nu >= w || nv >= h) {
            continue;
        }
        const float d =
            depth[static_cast<std::size_t>(nv) * static_cast<std::size_t>(w) + static_cast<std::size_t>(nu)];
        if (!(d > 0.0F)) {
            continue;
        }
        const double jump = std::fabs(static_cast<double>(d) - static_cast<double>(own));
        if (jump > best.jump) {
            best.jump = jump;
            best.depth = d;
        }
    }
    return best;
}

void apply_lidar(const SensorSpec& sensor, const FlashLidarNoise& p, Span<const float> ideal, Span<float> depth,
                 Rng& rng) {
    const PinholeIntrinsics k = sensor.intrinsics();
    const bool dropouts = p.missing_probability > 0.0;  // else no number is drawn for them (the paper's figures)
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) +
                                  static_cast<std::size_t>(u);
            // Draw the same count of numbers for every pixel, so that a change in one
            // pixel's state does not shift the noise of all later pixels.
            const double mix_draw = rng.uniform();
            const double weight = rng.uniform();
            const double n = rng.normal();
            const double drop_draw = dropouts ? rng.uniform() : 1.0;
            const auto z = static_cast<double>(ideal[i]);
            if (!(z > 0.0)) {
                continue;
            }
            if (drop_draw < p.missing_probability) {
                depth[i] = 0.0F;
                continue;
            }
            double z_new = z;
            const EdgeNeighbour e = largest_jump(ideal, k.width, k.height, u, v);
            if (e.jump > p.mixed_pixel_edge_m && mix_draw < p.mixed_pixel_probability) {
                z_new = weight * z + (1.0 - weight) * static_cast<double>(e.depth);
            }
            // Range along the ray and depth along the axis differ by a per-pixel factor.
            const double x = (u - k.cx) / k.fx;
            const double y = (v - k.cy) / k.fy;
            const double ray_scale = std::sqrt(1.0 + x * x + y * y);
            const double range = z_new * ray_scale;
            const double sigma = p.range_sigma_base_m + p.range_sigma_per_m * range;
            const double noisy_range = range + sigma * n;
            depth[i] = noisy_range > 0.0 ? static_cast<float>(noisy_range / ray_scale) : 0.0F;
        }
    }
}

void apply_stereo(const SensorSpec& sensor, const StereoNoise& p, Span<const float> ideal, Span<float> depth,
                  Rng& rng) {
    const PinholeIntrinsics k = sensor.intrinsics();
    const double fb = k.fx * p.baseline_m;
    for (std::int32_t v = 0; v < k.height; ++v) {
        for (std::int32_t u = 0; u < k.width; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) +
                                  static_cast<std::size_t>(u);
            const double miss_draw = rng.uniform();
            const double n = rng.normal();
            const auto z = static_cast<double>(ideal[i]);
            if (!(z > 0.0)) {
                continue;
            }
            const EdgeNeighbour e = largest_jump(ideal, k.width, k.height, u, v);
            const double p_miss = e.jump > p.edge_missing_m ? p.edge_missing_probability : p.missing_probability;
            if (miss_draw < p_miss) {
                depth[i] = 0.0F;
                continue;
            }
            double d = fb / z + p.disparity_sigma_px * n;
            if (p.disparity_quantum_px > 0.0) {
                d = std::round(d / p.disparity_quantum_px) * p.disparity_quantum_px;
            }
            depth[i] = d > p.min_disparity_px ? static_cast<float>(fb / d) : 0.0F;
        }
    }
}
}  // namespace

const char* to_string(SensorKind kind) {
    switch (kind) {
        case SensorKind::kIdeal: return "ideal";
        case SensorKind::kFlashLidar: return "flash_lidar";
        case SensorKind::kStereo: return "stereo";
    }
    return "unknown";
}

std::vector<NoiseModel> paper_noise_models() {
    std::vector<NoiseModel> m(4);
    m[0].kind = SensorKind::kFlashLidar;
    m[1].kind = SensorKind::kFlashLidar;
    m[2].kind = SensorKind::kStereo;
    m[3].kind = SensorKind::kStereo;
    return m;
}

std::uint64_t sensor_seed(std::uint64_t frame_seed, std::size_t sensor_index) {
    std::uint64_t s = frame_seed ^ (0xD1B54A32D192ED03ULL * (static_cast<std::uint64_t>(sensor_index) + 1U));
    return splitmix64(s);
}

std::uint64_t Rng::next_u64() { return splitmix64(state_); }

double Rng::uniform() { return static_cast<double>(next_u64() >> 11U) * (1.0 / 9007199254740992.0); }

double Rng::normal() {
    if (has_spare_) {
        has_spare_ = false;
        return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
    const double u2 = uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return radius * std::cos(kTwoPi * u2);
}

NoiseModel tof_camera_noise(double range_sigma_per_m) {
    NoiseModel m;
    m.kind = SensorKind::kFlashLidar;
    m.lidar.range_sigma_base_m = 0.0;
    m.lidar.range_sigma_per_m = range_sigma_per_m;
    m.lidar.mixed_pixel_edge_m = 0.05;
    m.lidar.mixed_pixel_probability = 0.5;
    m.lidar.missing_probability = 0.01;
    return m;
}

bool apply_noise(const SensorSpec& sensor, const NoiseModel& model, Span<float> depth, Span<float> ideal,
                 Rng& rng) noexcept {
    const PinholeIntrinsics k = sensor.intrinsics();
    const auto pixels = static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height);
    if (depth.size() != pixels || ideal.size() != pixels) {
        return false;
    }
    std::copy(depth.begin(), depth.end(), ideal.begin());  // edges are found on the ideal image
    const Span<const float> clean(ideal.data(), ideal.size());
    switch (model.kind) {
        case SensorKind::kIdeal: break;
        case SensorKind::kFlashLidar: apply_lidar(sensor, model.lidar, clean, depth, rng); break;
        case SensorKind::kStereo: apply_stereo(sensor, model.stereo, clean, depth, rng); break;
    }
    return true;
}

void apply_noise(const SensorSpec& sensor, const NoiseModel& model, std::vector<float>& depth, Rng& rng) {
    if (model.kind == SensorKind::kIdeal) {
        return;
    }
    std::vector<float> ideal(depth.size());
    static_cast<void>(apply_noise(sensor, model, {depth.data(), depth.size()}, {ideal.data(), ideal.size()}, rng));
}

SimulatedFrame render_noisy_frame(const std::vector<SensorSpec>& sensors, const std::vector<NoiseModel>& models,
                                  const Scene& scene, std::uint64_t seed) {
    SimulatedFrame f;
    f.depth.resize(sensors.size());
    const PreparedScene prepared(scene);
    for (std::size_t i = 0; i < sensors.size(); ++i) {
        render_depth(sensors[i], prepared, f.depth[i]);
        if (i < models.size()) {
            Rng rng(sensor_seed(seed, i));
            apply_noise(sensors[i], models[i], f.depth[i], rng);
        }
    }
    add_readings(sensors, f);
    return f;
}

}  // namespace cellguard::sim
