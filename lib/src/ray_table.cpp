#include "cellguard/ray_table.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "cellguard/contract.hpp"
#include "cellguard/log_odds.hpp"

namespace cellguard {

namespace {

// The far point of pixel (u, v)'s ray at max_range, and the ray's norm factor.
struct PixelRay {
    Eigen::Vector3d far_point;
    double norm;
};

PixelRay pixel_ray(const SensorReading& s, std::int32_t u, std::int32_t v) noexcept {
    const PinholeIntrinsics& k = s.intrinsics;
    const Eigen::Vector3d dir((static_cast<double>(u) - k.cx) / k.fx, (static_cast<double>(v) - k.cy) / k.fy, 1.0);
    const double norm = dir.norm();
    const Eigen::Vector3d far_cam = dir * (static_cast<double>(s.max_range) / norm);
    return PixelRay{s.pose * far_cam, norm};
}

Status check_depth_sensor(const SensorReading& sensor) noexcept {
    const Status valid = validate_sensor_reading(sensor);
    if (!valid.ok()) {
        return valid;
    }
    if (sensor.kind != SensorDataKind::kDepthImage) {
        return ErrorCode::kInvalidArgument;
    }
    return Status{};
}

}  // namespace

Result<std::size_t> count_ray_steps(const GridGeometry& grid, const SensorReading& sensor,
                                    Rasterization rasterization) noexcept {
    const Status ok = check_depth_sensor(sensor);
    if (!ok.ok()) {
        return ok.error();
    }
    std::size_t total = 0U;
    const Eigen::Vector3d origin = sensor.pose.translation();
    for (std::int32_t v = 0; v < sensor.intrinsics.height; ++v) {
        for (std::int32_t u = 0; u < sensor.intrinsics.width; ++u) {
            total += traverse(rasterization, grid, origin, pixel_ray(sensor, u, v).far_point,
                                   [](const TraversedVoxel& /*voxel*/) {});
        }
    }
    return total;
}

Result<RayTable> RayTable::build(const GridGeometry& grid, const SensorReading& sensor, RayTableStorage storage,
                                 Rasterization rasterization) noexcept {
    const Status ok = check_depth_sensor(sensor);
    if (!ok.ok()) {
        return ok.error();
    }
    const std::size_t pixels =
        static_cast<std::size_t>(sensor.intrinsics.width) * static_cast<std::size_t>(sensor.intrinsics.height);
    if (storage.pixel_begin.size() < pixels + 1U || storage.pixel_enter.size() < pixels ||
        storage.pixel_exit.size() < pixels || storage.pixel_norm.size() < pixels ||
        storage.pixel_walked.size() < pixels || storage.full_hits.size() < grid.voxel_count() ||
        storage.hit_count.size() < grid.voxel_count() || storage.hit_correction.size() < grid.voxel_count()) {
        return ErrorCode::kStorageTooSmall;
    }
    const std::size_t capacity =
        storage.voxels.size() < storage.t_exit.size() ? storage.voxels.size() : storage.t_exit.size();
    const Eigen::Vector3d origin = sensor.pose.translation();
    constexpr float kNone = std::numeric_limits<float>::infinity();
    std::size_t n = 0U;
    std::size_t pixel = 0U;
    for (std::int32_t v = 0; v < sensor.intrinsics.height; ++v) {
        for (std::int32_t u = 0; u < sensor.intrinsics.width; ++u, ++pixel) {
            const PixelRay ray = pixel_ray(sensor, u, v);
            if (n > std::numeric_limits<std::uint32_t>::max()) {
                return ErrorCode::kCapacityExceeded;
            }
            storage.pixel_begin[pixel] = static_cast<std::uint32_t>(n);
            storage.pixel_norm[pixel] = static_cast<float>(ray.norm);
            storage.pixel_enter[pixel] = kNone;
            storage.pixel_exit[pixel] = kNone;
            float last_exit = -kNone;
            (void)traverse(rasterization, grid, origin, ray.far_point, [&](const TraversedVoxel& t) {
                const auto t_exit = static_cast<float>(t.t_exit);
                // fuse() searches a pixel's exit distances: they must not decrease.
                CG_ENFORCE(t_exit >= last_exit, "ray traversal exit distances must not decrease");
                if (last_exit == -kNone) {
                    storage.pixel_enter[pixel] = static_cast<float>(t.t_enter);
                }
                last_exit = t_exit;
                if (n < capacity) {
                    storage.voxels[n] = static_cast<std::uint32_t>(t.index);
                    storage.t_exit[n] = t_exit;
                }
                ++n;
            });
            if (last_exit != -kNone) {
                storage.pixel_exit[pixel] = last_exit;
            }
        }
    }
    if (n > std::numeric_limits<std::uint32_t>::max()) {
        return ErrorCode::kCapacityExceeded;
    }
    if (n > capacity) {
        return ErrorCode::kStorageTooSmall;
    }
    storage.pixel_begin[pixels] = static_cast<std::uint32_t>(n);
    // How many of the table's rays cross each voxel (a ray crosses a voxel
    // at most once, so a count is at most the pixel count).
    for (std::size_t v = 0U; v < grid.voxel_count(); ++v) {
        storage.full_hits[v] = 0U;
    }
    for (std::size_t k = 0U; k < n; ++k) {
        ++storage.full_hits[storage.voxels[k]];
    }
    RayTable table;
    table.geometry_ = grid;
    table.storage_ = storage;
    table.pixels_ = pixels;
    table.step_count_ = n;
    table.min_range_ = sensor.min_range;
    table.max_range_ = sensor.max_range;
    return table;
}

namespace {

/// Adds @p delta (modulo 2^32: 0xFFFFFFFF subtracts one) to the hit count
/// of every table entry in the pixels' segments: [begin[i], walked[i]) when
/// @p walked_part, else [walked[i], begin[i + 1]). Segments that continue
/// one another are walked as one run.
void count_segments(const std::uint32_t* voxels, const std::uint32_t* begin, const std::uint32_t* walked,
                    std::size_t pixels, bool walked_part, std::uint32_t delta, std::uint32_t* hits) noexcept {
    std::uint32_t run_begin = 0U;
    std::uint32_t run_end = 0U;
    const auto count_run = [&]() noexcept {
        for (std::uint32_t k = run_begin; k < run_end; ++k) {
            hits[voxels[k]] += delta;
        }
    };
    for (std::size_t i = 0U; i < pixels; ++i) {
        const std::uint32_t b = walked_part ? begin[i] : walked[i];
        const std::uint32_t e = walked_part ? walked[i] : begin[i + 1U];
        if (b == e) {
            continue;
        }
        if (b != run_end) {
            count_run();
            run_begin = b;
        }
        run_end = e;
    }
    count_run();
}

/// A hint to load @p address into the cache ahead of its use (no effect on
/// results; compilers without the builtin get nothing).
inline void prefetch(const void* address) noexcept {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(address);
#else
    (void)address;
#endif
}

/// How many pixels ahead fuse() asks for a pixel's last exit distances.
constexpr std::size_t kPrefetchPixels = 16U;

/// The end of a pixel's constant part: the first of the entries [first, end)
/// whose exit distance exceeds @p free_until (end if none). The entries'
/// exit distances do not decrease.
std::uint32_t find_free_end(const float* t_exit, std::uint32_t first, std::uint32_t end, float free_until) noexcept {
    // Branch-free binary search (the loop's trip count depends only on the
    // pixel's entry count): the first entry whose exit exceeds free_until.
    const float* base = t_exit + first;
    std::uint32_t n = end - first;
    if (n == 0U) {
        return first;
    }
    while (n > 1U) {
        const std::uint32_t half = n / 2U;
        base = base[half - 1U] <= free_until ? base + half : base;
        n -= half;
    }
    return static_cast<std::uint32_t>(base - t_exit) + (*base <= free_until ? 1U : 0U);
}

/// @p value plus @p hits times @p constant plus @p correction, summed
/// exactly in 64 bits (|hits x constant| < 2^47) and saturated once.
std::int16_t add_frame_sum_saturating(std::int16_t value, std::uint32_t hits, std::int16_t constant,
                                      std::int32_t correction) noexcept {
    const std::int64_t sum = static_cast<std::int64_t>(value) +
                             static_cast<std::int64_t>(hits) * static_cast<std::int64_t>(constant) +
                             static_cast<std::int64_t>(correction);
    return static_cast<std::int16_t>(sum < kLogOddsMin ? kLogOddsMin : sum > kLogOddsMax ? kLogOddsMax : sum);
}

}  // namespace

Result<FusionStats> RayTable::fuse(EvidenceGrid& grid, Span<const float> depth,
                                   const SensorModelTable& model) const noexcept {
    if (pixels_ == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (!(grid.geometry() == geometry_)) {
        return ErrorCode::kGeometryMismatch;
    }
    if (depth.size() != pixels_) {
        return ErrorCode::kMalformedInput;
    }
    const std::size_t voxel_count = geometry_.voxel_count();
    CG_ENFORCE(step_count_ <= storage_.voxels.size() && step_count_ <= storage_.t_exit.size() &&
                   pixels_ <= storage_.pixel_walked.size() && voxel_count <= storage_.full_hits.size() &&
                   voxel_count <= storage_.hit_count.size() && voxel_count <= storage_.hit_correction.size(),
               "ray table storage changed size");
    const std::int16_t constant = model.constant_free_evidence();
    const std::int16_t peak = model.reading_evidence();
    // A ramp or peak voxel's correction (evidence minus the constant) lies in
    // [0, peak - constant]; the corrections of one frame sum exactly in 32
    // bits when every pixel's could land in one voxel.
    const auto max_correction = static_cast<std::uint64_t>(static_cast<std::int32_t>(peak) - constant);
    constexpr auto kCorrectionLimit = static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
    if (static_cast<std::uint64_t>(pixels_) * max_correction > kCorrectionLimit) {
        return ErrorCode::kInvalidArgument;
    }
    std::int16_t* const lo = grid.log_odds().data();
    std::uint8_t* const obs = grid.observed().data();
    const std::uint32_t* const voxels = storage_.voxels.data();
    const float* const t_exit = storage_.t_exit.data();
    const std::uint32_t* const begin = storage_.pixel_begin.data();
    std::uint32_t* const hits = storage_.hit_count.data();
    std::int32_t* const correction = storage_.hit_correction.data();
    std::uint32_t* const walked = storage_.pixel_walked.data();
    for (std::size_t v = 0U; v < voxel_count; ++v) {
        correction[v] = 0;
    }
    const auto ramp = static_cast<float>(model.ramp_length());
    const auto prefetch_reading = [&](std::size_t j, float d) noexcept {
        const float enter = storage_.pixel_enter[j];
        const float exit = storage_.pixel_exit[j];
        const float range = d * storage_.pixel_norm[j];  // NaN and negative depths fail both compares
        if (range >= enter && range < exit + ramp) {
            const float fraction = (range - ramp - enter) / (exit - enter);
            const auto span = static_cast<float>(begin[j + 1U] - begin[j]);
            const std::uint32_t k =
                begin[j] + static_cast<std::uint32_t>(fraction > 0.0F && fraction < 1.0F ? fraction * span : 0.0F);
            prefetch(t_exit + k);
            prefetch(voxels + k);
        }
    };
    // Pass 1, per pixel: where its walk ends (walked[i]; begin[i] when it
    // walks nothing), and the ramp and peak corrections.
    FusionStats s;
    for (std::size_t i = 0U; i < pixels_; ++i) {
        // A reading inside the grid reads the entries around its position on
        // the ray: a cache miss per pixel unless asked for ahead. The hint
        // uses the same proportional estimate as find_free_end.
        if (i + kPrefetchPixels < pixels_) {
            prefetch_reading(i + kPrefetchPixels, depth[i + kPrefetchPixels]);
        }
        walked[i] = begin[i];
        const float d = depth[i];
        if (std::isnan(d)) {
            ++s.skipped_nan;
            continue;
        }
        if (std::isinf(d)) {
            ++s.skipped_infinite;
            continue;
        }
        if (d == 0.0F) {
            ++s.skipped_zero;
            continue;
        }
        if (d < 0.0F) {
            ++s.skipped_behind;
            continue;
        }
        const float range = d * storage_.pixel_norm[i];
        if (range < min_range_ || range > max_range_) {
            ++s.skipped_out_of_range;
            continue;
        }
        ++s.rays_fused;
        if (range < storage_.pixel_enter[i]) {
            continue;  // the ray misses the grid (enter = +inf), or the reading lies before it
        }
        const std::uint32_t first = begin[i];
        const std::uint32_t end = begin[i + 1U];
        // The constant part of the profile: the voxels left at least one ramp
        // before the reading, entries [first, free_end).
        const float free_until = range - ramp;
        std::uint32_t free_end = end;
        if (free_until < storage_.pixel_exit[i]) {
            free_end = find_free_end(t_exit, first, end, free_until);
        }
        // The ramp: voxels left before the reading; then the voxel holding
        // the reading, if it lies inside the grid. Every walked voxel is
        // counted as if it got the constant (pass 2); a ramp or peak voxel's
        // correction (its evidence minus the constant) is summed here.
        std::uint32_t k = free_end;
        for (; k < end && t_exit[k] <= range; ++k) {
            const std::int16_t e = model.free_evidence(static_cast<double>(range - t_exit[k]));
            correction[voxels[k]] += static_cast<std::int32_t>(e) - constant;
        }
        if (k < end) {
            correction[voxels[k]] += static_cast<std::int32_t>(peak) - constant;
            ++k;
            ++s.readings_in_grid;
        }
        walked[i] = k;
        s.voxel_updates += static_cast<std::uint64_t>(k - first);
    }
    // Pass 2: the hits per voxel. Count the walked entries, or, when more
    // than half of the table was walked, start from the table's full counts
    // and take off the entries not walked: at most half the table either way.
    if (2U * s.voxel_updates <= static_cast<std::uint64_t>(step_count_)) {
        for (std::size_t v = 0U; v < voxel_count; ++v) {
            hits[v] = 0U;
        }
        count_segments(voxels, begin, walked, pixels_, true, 1U, hits);
    } else {
        const std::uint32_t* const full = storage_.full_hits.data();
        for (std::size_t v = 0U; v < voxel_count; ++v) {
            hits[v] = full[v];
        }
        count_segments(voxels, begin, walked, pixels_, false, std::numeric_limits<std::uint32_t>::max(), hits);
    }
    // Each crossed voxel's exact sum, added with one saturation.
    for (std::size_t v = 0U; v < voxel_count; ++v) {
        if (hits[v] != 0U) {
            lo[v] = add_frame_sum_saturating(lo[v], hits[v], constant, correction[v]);
            obs[v] = 1U;
        }
    }
    return s;
}

}  // namespace cellguard
