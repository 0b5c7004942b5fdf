// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/grid/ray_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "cellguard/base/contract.hpp"
#include "cellguard/base/crc32.hpp"
#include "cellguard/grid/log_odds.hpp"
#include "placement.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
    if (!is_depth_image(sensor.kind)) {
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

float compact_exit_step(const GridGeometry& grid, const SensorReading& sensor) noexcept {
    if (!validate_sensor_reading(sensor).ok()) {
        return 0.0F;
    }
    // The farthest point of the box from the origin is one of its corners.
    const Eigen::Vector3d origin = sensor.pose.translation();
    const Eigen::Vector3d& lo = grid.origin();
    const Eigen::Vector3d hi = grid.max_corner();
    double farthest = 0.0;
    for (unsigned corner = 0U; corner < 8U; ++corner) {
        const Eigen::Vector3d c((corner & 1U) != 0U ? hi.x() : lo.x(), (corner & 2U) != 0U ? hi.y() : lo.y(),
                                (corner & 4U) != 0U ? hi.z() : lo.z());
        farthest = std::max(farthest, (c - origin).norm());
    }
    const double reach = std::min(farthest, static_cast<double>(sensor.max_range)) * 1.0001;
    int exponent = 0;
    (void)std::frexp(reach / 65535.0, &exponent);  // reach / 65535 < 2^exponent
    return static_cast<float>(std::ldexp(1.0, exponent));
}

bool ray_table_is_compact(const GridGeometry& grid, const SensorReading& sensor) noexcept {
    const float step = compact_exit_step(grid, sensor);
    return grid.voxel_count() <= kCompactRayTableVoxels && step > 0.0F &&
           static_cast<double>(step) <= grid.voxel_size() / kCompactStepsPerVoxelEdge;
}

namespace {

/// A table's entries, one array per field: pass 2 reads only the voxels,
/// the search only the keys, so each reads half the bytes of a record.
/// Compact: 16-bit voxels and exit steps; wide: 32-bit voxels and float
/// exit distances.
struct CompactEntries {
    const std::uint16_t* voxel;
    const std::uint16_t* exit_steps;
};
struct WideEntries {
    const std::uint32_t* voxel;
    const float* exit;
};

/// The exit distance of entry @p k as fuse() compares it (@p step is a
/// compact table's exit step; a wide table stores the distance itself).
/// Exact in float for a compact table: a 16-bit count times a power of two.
inline float exit_of(const CompactEntries& e, std::size_t k, float step) noexcept {
    return static_cast<float>(e.exit_steps[k]) * step;
}
inline float exit_of(const WideEntries& e, std::size_t k, float /*step*/) noexcept { return e.exit[k]; }

/// Search keys: an entry's ray has left it at distance x exactly when
/// its key <= key_limit(x). For a compact table the key is the exit steps
/// and the limit floor(x x steps_per_metre) (-1 below 0, at most 65535):
/// steps x step <= x exactly when steps <= x x steps_per_metre, and both
/// products are exact because the step is a power of two, so comparing
/// integers keeps the floating point out of the search. For a wide table
/// both are the distances themselves.
inline const std::uint16_t* keys(const CompactEntries& e) noexcept { return e.exit_steps; }
inline const float* keys(const WideEntries& e) noexcept { return e.exit; }
inline const std::uint16_t* voxels(const CompactEntries& e) noexcept { return e.voxel; }
inline const std::uint32_t* voxels(const WideEntries& e) noexcept { return e.voxel; }
inline std::int32_t key_limit(const CompactEntries& /*kind*/, float x, float steps_per_metre) noexcept {
    constexpr std::int32_t kMaxSteps = 65535;
    const float steps = x * steps_per_metre;
    return !(steps >= 0.0F)                         ? -1
           : steps >= static_cast<float>(kMaxSteps) ? kMaxSteps
                                                    : static_cast<std::int32_t>(steps);
}
inline float key_limit(const WideEntries& /*kind*/, float x, float /*steps_per_metre*/) noexcept { return x; }

/// True when @p storage holds the per-pixel arrays of @p pixels pixels and
/// the per-voxel arrays of @p grid.
bool storage_fits(const GridGeometry& grid, std::size_t pixels, const RayTableStorage& storage) noexcept {
    return storage.pixel_begin.size() >= pixels + 1U && storage.pixel_enter.size() >= pixels &&
           storage.pixel_exit.size() >= pixels && storage.pixel_norm.size() >= pixels &&
           storage.pixel_walked.size() >= pixels && storage.full_hits.size() >= grid.voxel_count() &&
           storage.crossed_voxels.size() >= grid.voxel_count() && storage.hit_count.size() >= grid.voxel_count() &&
           storage.sensor_opinion.size() >= grid.voxel_count();
}

/// How a table stores its entries: compact or wide, how many fit, the
/// exit step of a compact table.
struct EntryFormat {
    bool compact = false;
    std::size_t capacity = 0U;
    float exit_step = 0.0F;
};

/// Walks the ray of @p pixel from @p origin and appends its entries from
/// entry @p n on (entries beyond the capacity are counted, not written);
/// sets the pixel's begin, norm, enter and exit distances. Returns the entry
/// count after the pixel.
std::size_t add_pixel_entries(const GridGeometry& grid, const RayTableStorage& storage, const EntryFormat& format,
                              Rasterization rasterization, const Eigen::Vector3d& origin, std::size_t pixel,
                              const PixelRay& ray, std::size_t n) noexcept {
    constexpr float kNone = std::numeric_limits<float>::infinity();
    storage.pixel_begin[pixel] = static_cast<std::uint32_t>(n);
    storage.pixel_norm[pixel] = static_cast<float>(ray.norm);
    storage.pixel_enter[pixel] = kNone;
    storage.pixel_exit[pixel] = kNone;
    double enter = -1.0;
    float last_exit = -kNone;
    (void)traverse(rasterization, grid, origin, ray.far_point, [&](const TraversedVoxel& t) {
        if (enter < 0.0) {
            enter = t.t_enter;
            storage.pixel_enter[pixel] = static_cast<float>(t.t_enter);
        }
        if (n < format.capacity) {
            if (format.compact) {
                const double steps = std::round(t.t_exit / static_cast<double>(format.exit_step));
                storage.compact_voxels[n] = static_cast<std::uint16_t>(t.index);
                storage.compact_exit_steps[n] = static_cast<std::uint16_t>(steps < 0.0       ? 0.0
                                                                           : steps > 65535.0 ? 65535.0
                                                                                             : steps);
            } else {
                storage.wide_voxels[n] = static_cast<std::uint32_t>(t.index);
                storage.wide_exits[n] = static_cast<float>(t.t_exit);
            }
        }
        ++n;
    });
    // The exit distances as fuse() compares them: they must not
    // decrease (it searches them), and the last is the ray's exit.
    const std::size_t first = storage.pixel_begin[pixel];
    for (std::size_t k = first; k < n && k < format.capacity; ++k) {
        const float e = format.compact ? static_cast<float>(storage.compact_exit_steps[k]) * format.exit_step
                                       : storage.wide_exits[k];
        CG_ENFORCE(e >= last_exit, "ray table exit distances must not decrease");
        last_exit = e;
    }
    if (n > first && n <= format.capacity) {
        storage.pixel_exit[pixel] = last_exit;
    }
    return n;
}

/// How many of the table's @p n entries cross each voxel (full_hits; a ray
/// crosses a voxel at most once, so a count is at most the pixel count) and
/// the voxels some ray crosses, ascending (crossed_voxels: fuse() sets and
/// sums only these). Returns how many voxels are crossed.
std::size_t count_crossings(const GridGeometry& grid, const RayTableStorage& storage, bool compact,
                            std::size_t n) noexcept {
    for (std::size_t v = 0U; v < grid.voxel_count(); ++v) {
        storage.full_hits[v] = 0U;
    }
    for (std::size_t k = 0U; k < n; ++k) {
        ++storage.full_hits[compact ? storage.compact_voxels[k] : storage.wide_voxels[k]];
    }
    std::size_t crossed = 0U;
    for (std::size_t v = 0U; v < grid.voxel_count(); ++v) {
        if (storage.full_hits[v] != 0U) {
            storage.crossed_voxels[crossed] = static_cast<std::uint32_t>(v);
            ++crossed;
        }
    }
    return crossed;
}

}  // namespace

Result<RayTable> RayTable::build(const GridGeometry& grid, const SensorReading& sensor, RayTableStorage storage,
                                 Rasterization rasterization) noexcept {
    const Status ok = check_depth_sensor(sensor);
    if (!ok.ok()) {
        return ok.error();
    }
    const std::size_t pixels = static_cast<std::size_t>(sensor.intrinsics.width) *
                               static_cast<std::size_t>(sensor.intrinsics.height);
    if (!storage_fits(grid, pixels, storage)) {
        return ErrorCode::kStorageTooSmall;
    }
    EntryFormat format;
    format.compact = ray_table_is_compact(grid, sensor);
    format.capacity = format.compact ? std::min(storage.compact_voxels.size(), storage.compact_exit_steps.size())
                                     : std::min(storage.wide_voxels.size(), storage.wide_exits.size());
    // Exit distances of a compact table, in steps of a power of two metres.
    format.exit_step = format.compact ? compact_exit_step(grid, sensor) : 0.0F;
    const bool compact = format.compact;
    const float exit_step = format.exit_step;
    const Eigen::Vector3d origin = sensor.pose.translation();
    std::size_t n = 0U;
    std::size_t pixel = 0U;
    for (std::int32_t v = 0; v < sensor.intrinsics.height; ++v) {
        for (std::int32_t u = 0; u < sensor.intrinsics.width; ++u, ++pixel) {
            const PixelRay ray = pixel_ray(sensor, u, v);
            n = add_pixel_entries(grid, storage, format, rasterization, origin, pixel, ray, n);
            if (n > std::numeric_limits<std::uint32_t>::max()) {  // the next pixel_begin and the total are uint32
                return ErrorCode::kCapacityExceeded;
            }
        }
    }
    if (n > format.capacity) {
        return ErrorCode::kStorageTooSmall;
    }
    storage.pixel_begin[pixels] = static_cast<std::uint32_t>(n);
    const std::size_t crossed = count_crossings(grid, storage, compact, n);
    RayTable table;
    table.geometry_ = grid;
    table.crossed_count_ = crossed;
    table.storage_ = storage;
    table.pixels_ = pixels;
    table.step_count_ = n;
    table.min_range_ = sensor.min_range;
    table.max_range_ = sensor.max_range;
    table.exit_step_ = exit_step;
    table.steps_per_metre_ = compact ? 1.0F / exit_step : 0.0F;
    table.compact_ = compact;
    table.placement_ = ReadingPlacement{grid, sensor.intrinsics, 1.0 / sensor.intrinsics.fx, 1.0 / sensor.intrinsics.fy,
                                        sensor.pose};
    table.header_words_ = table.check_header();
    std::uint32_t crc = kCrc32Init;
    for (const SignatureRegion& region : table.signature_regions()) {
        crc = crc32_update(crc, region);
    }
    table.storage_crc_ = crc32_finish(crc);
    return table;
}

namespace {

std::uint32_t bits_of(float value) noexcept {
    std::uint32_t bits = 0U;
    std::memcpy(&bits, &value, sizeof(bits));
    return bits;
}

/// Low and high word of @p value's bits.
std::array<std::uint32_t, 2> bits_of(double value) noexcept {
    std::uint64_t bits = 0U;
    std::memcpy(&bits, &value, sizeof(bits));
    return {static_cast<std::uint32_t>(bits), static_cast<std::uint32_t>(bits >> 32U)};
}

}  // namespace

RayTable::CheckHeader RayTable::check_header() const noexcept {
    const std::array<std::uint32_t, 2> size = bits_of(geometry_.voxel_size());
    const std::array<std::uint32_t, 2> ox = bits_of(geometry_.origin().x());
    const std::array<std::uint32_t, 2> oy = bits_of(geometry_.origin().y());
    const std::array<std::uint32_t, 2> oz = bits_of(geometry_.origin().z());
    CheckHeader words{static_cast<std::uint32_t>(pixels_),
                      static_cast<std::uint32_t>(step_count_),
                      static_cast<std::uint32_t>(crossed_count_),
                      bits_of(min_range_),
                      bits_of(max_range_),
                      bits_of(exit_step_),
                      bits_of(steps_per_metre_),
                      compact_ ? 1U : 0U,
                      static_cast<std::uint32_t>(geometry_.dims().nx),
                      static_cast<std::uint32_t>(geometry_.dims().ny),
                      static_cast<std::uint32_t>(geometry_.dims().nz),
                      size[0],
                      size[1],
                      ox[0],
                      ox[1],
                      oy[0],
                      oy[1],
                      oz[0],
                      oz[1]};
    // The reading placement (ray_table.hpp): what fuse() reads near a face.
    std::size_t n = 19U;
    const auto put = [&words, &n](double value) noexcept {
        const std::array<std::uint32_t, 2> b = bits_of(value);
        words[n++] = b[0];
        words[n++] = b[1];
    };
    const ReadingPlacement& p = placement_;
    for (const double value :
         {p.intrinsics.fx, p.intrinsics.fy, p.intrinsics.cx, p.intrinsics.cy, p.inv_fx, p.inv_fy}) {
        put(value);
    }
    words[n++] = static_cast<std::uint32_t>(p.intrinsics.width);
    words[n++] = static_cast<std::uint32_t>(p.intrinsics.height);
    for (Eigen::Index row = 0; row < 3; ++row) {
        for (Eigen::Index col = 0; col < 4; ++col) {
            put(p.pose.matrix()(row, col));
        }
    }
    return words;
}

RayTableSignatureRegions RayTable::signature_regions() const noexcept {
    if (pixels_ == 0U) {
        return RayTableSignatureRegions{};
    }
    const std::size_t voxels = geometry_.voxel_count();
    return RayTableSignatureRegions{
        as_bytes(Span<const std::uint32_t>(header_words_.data(), header_words_.size())),
        compact_ ? as_bytes(storage_.compact_voxels.subspan(0U, step_count_))
                 : as_bytes(storage_.wide_voxels.subspan(0U, step_count_)),
        compact_ ? as_bytes(storage_.compact_exit_steps.subspan(0U, step_count_))
                 : as_bytes(storage_.wide_exits.subspan(0U, step_count_)),
        as_bytes(storage_.pixel_begin.subspan(0U, pixels_ + 1U)),
        as_bytes(storage_.pixel_enter.subspan(0U, pixels_)),
        as_bytes(storage_.pixel_exit.subspan(0U, pixels_)),
        as_bytes(storage_.pixel_norm.subspan(0U, pixels_)),
        as_bytes(storage_.full_hits.subspan(0U, voxels)),
        as_bytes(storage_.crossed_voxels.subspan(0U, crossed_count_)),
    };
}

std::size_t RayTable::checked_bytes() const noexcept {
    std::size_t total = 0U;
    for (const SignatureRegion& region : signature_regions()) {
        total += region.size();
    }
    return total;
}

bool RayTable::limits_intact() const noexcept { return pixels_ == 0U || check_header() == header_words_; }

std::uint32_t RayTable::entry_voxel(std::size_t entry) const noexcept {
    CG_ENFORCE(entry < step_count_, "ray table entry out of range");
    return compact_ ? storage_.compact_voxels[entry] : storage_.wide_voxels[entry];
}

float RayTable::entry_exit(std::size_t pixel, std::size_t entry) const noexcept {
    CG_ENFORCE(pixel < pixels_ && entry >= storage_.pixel_begin[pixel] && entry < storage_.pixel_begin[pixel + 1U],
               "ray table entry is not the pixel's");
    return compact_ ? static_cast<float>(storage_.compact_exit_steps[entry]) * exit_step_ : storage_.wide_exits[entry];
}

namespace {

/// Adds @p delta (modulo 2^32: 0xFFFFFFFF subtracts one) to the hit count
/// of the voxel of every entry in [@p run_begin, @p run_end).
template <typename Voxel>
void add_to_hits(const Voxel* voxels, std::uint32_t run_begin, std::uint32_t run_end, std::uint32_t delta,
                 Span<std::uint32_t> hits) noexcept {
    if (run_begin == run_end) {
        return;
    }
    std::uint32_t k = run_begin;
    // Four entries per step: the loop's own instructions were a third of it.
    for (; k + 4U <= run_end; k += 4U) {
        hits[voxels[k]] += delta;
        hits[voxels[k + 1U]] += delta;
        hits[voxels[k + 2U]] += delta;
        hits[voxels[k + 3U]] += delta;
    }
    // The last 0 to 3 entries without a loop: run lengths vary from pixel to
    // pixel, and a loop's exit mispredicts. A lane past the run adds 0 to the
    // run's last voxel (indices stay inside the run).
    const std::uint32_t last = run_end - 1U;
    const std::uint32_t left = run_end - k;
    hits[voxels[std::min(k, last)]] += delta & (0U - static_cast<std::uint32_t>(left > 0U));
    hits[voxels[std::min(k + 1U, last)]] += delta & (0U - static_cast<std::uint32_t>(left > 1U));
    hits[voxels[std::min(k + 2U, last)]] += delta & (0U - static_cast<std::uint32_t>(left > 2U));
}

/// add_to_hits for the pixels' segments: [begin[i], walked[i]) when
/// @p walked_part, else [walked[i], begin[i + 1]). Segments that continue
/// one another are added as one run.
template <typename Voxel>
void count_segments(const Voxel* voxels, const std::uint32_t* begin, const std::uint32_t* walked, std::size_t pixels,
                    bool walked_part, std::uint32_t delta, Span<std::uint32_t> hits) noexcept {
    std::uint32_t run_begin = 0U;
    std::uint32_t run_end = 0U;
    for (std::size_t i = 0U; i < pixels; ++i) {
        const std::uint32_t b = walked_part ? begin[i] : walked[i];
        const std::uint32_t e = walked_part ? walked[i] : begin[i + 1U];
        if (b == e) {
            continue;
        }
        if (b != run_end) {
            add_to_hits(voxels, run_begin, run_end, delta, hits);
            run_begin = b;
        }
        run_end = e;
    }
    add_to_hits(voxels, run_begin, run_end, delta, hits);
}

/// Pixels whose binary searches pass 1 runs together (see find_free_ends).
constexpr std::size_t kSearchBatch = 16U;

/// One pixel's search in pass 1: its entries [base, base + n) (n >= 1) are
/// searched for the first whose key exceeds free_limit; base is the result.
template <typename Limit>
struct SearchSlot {
    std::uint32_t pixel;
    std::uint32_t base;
    std::uint32_t n;
    Limit free_limit;   ///< key_limit(range - ramp): the constant part ends here
    Limit range_limit;  ///< key_limit(range): the ramp ends here
    float range;        ///< the reading, metres from the sensor origin
};

/// The end of each slot's constant part: the first of its entries whose key
/// exceeds free_limit (base + n if none); keys do not decrease along a
/// pixel's entries. Branch-free binary searches, a step of every slot at a
/// time: one search is a chain of dependent loads, and the slots' chains
/// overlap. A branching search mispredicts about half its steps when
/// readings vary from pixel to pixel (bench_cycle --readings random).
template <typename Key, typename Limit>
void find_free_ends(const Key* keys, std::size_t /*key_count*/, Span<SearchSlot<Limit>> slots) noexcept {
    std::uint32_t widest = 0U;
    for (const SearchSlot<Limit>& slot : slots) {
        widest = slot.n > widest ? slot.n : widest;
    }
    // Each step takes n to n - n / 2 (the kept half holds the answer); a
    // slot at n = 1 probes keys[base] and stays put, so all run in step.
    while (widest > 1U) {
        for (SearchSlot<Limit>& slot : slots) {
            const std::uint32_t half = slot.n / 2U;
            slot.base += half & (0U - static_cast<std::uint32_t>(keys[slot.base + half] <= slot.free_limit));
            slot.n -= half;
        }
        widest -= widest / 2U;
    }
    for (SearchSlot<Limit>& slot : slots) {
        slot.base += static_cast<std::uint32_t>(keys[slot.base] <= slot.free_limit);
    }
}

#if defined(__SSE2__)
/// Entries a compact pixel's window search compares at once.
constexpr std::uint32_t kKeyWindow = 32U;

/// find_free_ends for a compact table on x86-64: each pixel compares a
/// window of kKeyWindow keys with its limit at once (four 8-lane compares)
/// and takes the first key above it, or, when there is none and the pixel
/// goes on, the next window: no chain of dependent loads. Windows must lie
/// inside the key array; a pixel whose window would not takes the binary
/// search. Same result: keys do not decrease along a pixel.
void find_free_ends(const std::uint16_t* keys, std::size_t key_count, Span<SearchSlot<std::int32_t>> slots) noexcept {
    const __m128i bias = _mm_set1_epi16(static_cast<std::int16_t>(-32768));
    for (SearchSlot<std::int32_t>& slot : slots) {
        if (slot.free_limit < 0) {
            continue;  // every key is above it: the constant part is empty
        }
        // Unsigned 16-bit compare as signed: flip the top bit of both sides.
        const __m128i limit = _mm_set1_epi16(static_cast<std::int16_t>(slot.free_limit - 32768));
        while (key_count - slot.base >= kKeyWindow) {
            const std::uint16_t* window = keys + slot.base;
            const auto above = [&](std::size_t q) noexcept {
                // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): unaligned SIMD load of the keys
                const __m128i k = _mm_loadu_si128(reinterpret_cast<const __m128i*>(window + 8U * q));
                return _mm_cmpgt_epi16(_mm_xor_si128(k, bias), limit);
            };
            const auto low = static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(above(0U), above(1U))));
            const auto high = static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(above(2U), above(3U))));
            auto mask = static_cast<std::uint64_t>(low | (high << 16U));
            if (slot.n <= kKeyWindow) {
                mask |= std::uint64_t{1} << slot.n;  // none above: the pixel's end
            }
            if (mask != 0U) {
                slot.base += static_cast<std::uint32_t>(__builtin_ctzll(mask));
                slot.n = 0U;  // found
                break;
            }
            slot.base += kKeyWindow;
            slot.n -= kKeyWindow;
        }
        if (slot.n != 0U) {
            find_free_ends<std::uint16_t, std::int32_t>(keys, key_count, Span<SearchSlot<std::int32_t>>(&slot, 1U));
        }
    }
}
#endif

/// The depth image fuse() reads in place: a kDepthImageU16 reading through
/// depth_value (raw 0: NaN) when @p u16 is set, else the floats as stored
/// (depth_value's rule for a kDepthImage).
struct ImageDepth {
    const float* floats;
    const SensorReading* u16;
    float operator[](std::size_t i) const noexcept { return u16 != nullptr ? depth_value(*u16, i) : floats[i]; }
};

/// One kind of ImageDepth, for the per-pixel pass: the test of the kind
/// taken out of its loop (measured: a test per pixel there cost 9 % more
/// instructions per frame on float images at maximum range).
struct FloatDepth {
    const float* floats;
    float operator[](std::size_t i) const noexcept { return floats[i]; }
};
struct U16Depth {
    const SensorReading* u16;
    float operator[](std::size_t i) const noexcept { return depth_value(*u16, i); }
};

/// What fuse() passes to fuse_entries: the table's arrays and limits.
struct FuseView {
    const std::uint32_t* begin;
    const float* enter;
    const float* exit;
    const float* norm;
    const std::uint32_t* full_hits;
    const std::uint32_t* crossed;
    std::size_t crossed_count;
    std::uint32_t* walked;
    std::uint32_t* hits;
    std::int16_t* opinion;
    std::size_t pixels;
    std::size_t steps;
    std::size_t voxels;
    float min_range;
    float max_range;
    float exit_step;
    float steps_per_metre;
    const ReadingPlacement* placement;  ///< fuse_sensor's rule for readings near a face
};

/// Entries on either side of the table's own entry that settle_reading
/// searches: a reading on an edge or a corner lies on the faces of up to
/// three entries of zero or rounding length.
constexpr std::uint32_t kSettleReach = 3U;

/// The entry within kSettleReach of @p k among a pixel's entries [first,
/// end) whose voxel is @p voxel, nearest to k first; @p k when none is (not
/// reached in the tests).
template <typename Entries>
std::uint32_t entry_of_voxel(const Entries& entries, std::uint32_t first, std::uint32_t end, std::uint32_t k,
                             std::size_t voxel) noexcept {
    for (std::uint32_t r = 0U; r <= kSettleReach; ++r) {
        if (k + r < end && voxels(entries)[k + r] == voxel) {
            return k + r;
        }
        if (r <= k && k - r >= first && k - r < end && voxels(entries)[k - r] == voxel) {
            return k - r;
        }
    }
    return k;
}

/// Where fuse_sensor puts the reading of @p pixel at depth @p d: the entry of
/// its voxel (GridGeometry's half-open rule on depth_pixel_point and
/// reading_in_cell, fusion.hpp), @p end when that point lies outside the
/// grid, or @p k, the table's own entry, when the two are not neighbours.
template <typename Entries>
std::uint32_t settle_reading(const Entries& entries, const FuseView& t, std::size_t pixel, float d, std::uint32_t first,
                             std::uint32_t end, std::uint32_t k) noexcept {
    const ReadingPlacement& p = *t.placement;
    const auto width = static_cast<std::size_t>(p.intrinsics.width);
    const auto u = static_cast<std::int32_t>(pixel % width);
    const auto v = static_cast<std::int32_t>(pixel / width);
    const Eigen::Vector3d point = detail::cell_point(p.pose,
                                                     detail::pixel_point(p.intrinsics, p.inv_fx, p.inv_fy, u, v, d));
    const VoxelCoord c = p.grid.world_to_voxel_unchecked(point);
    if (!p.grid.contains(c)) {
        return end;
    }
    return entry_of_voxel(entries, first, end, k, p.grid.index_of(c));
}

/// True when @p range lies within a compact table's rounding (two exit
/// steps) or 0.1 mm of the face where entry @p k - 1 ends or @p k ends:
/// there fuse_sensor's float point and the table's exit distances may put the
/// reading in different voxels.
template <typename Entries>
bool near_a_face(const Entries& entries, const FuseView& t, float range, std::uint32_t first, std::uint32_t end,
                 std::uint32_t k) noexcept {
    const float eps = t.exit_step > 0.0F ? 2.0F * t.exit_step : 1e-4F;
    const bool near_before = k > first && std::fabs(range - exit_of(entries, k - 1U, t.exit_step)) <= eps;
    const bool near_after = k < end && std::fabs(exit_of(entries, k, t.exit_step) - range) <= eps;
    return near_before || near_after;
}

/// Pass 1a for pixels [@p batch_begin, @p batch_end): sets each pixel's walk
/// end to begin[i], counts the skipped readings in @p s, settles the pixels
/// whose reading lies a ramp or more beyond the grid (every entry constant),
/// and puts the others into @p batch for the search. Returns how many.
template <typename Entries, typename Limit, typename Depth>
std::size_t classify_batch(const Entries& entries, const FuseView& t, Depth depth, float ramp, std::size_t batch_begin,
                           std::size_t batch_end, std::array<SearchSlot<Limit>, kSearchBatch>& batch,
                           FusionStats& s) noexcept {
    std::size_t searched = 0U;
    for (std::size_t i = batch_begin; i < batch_end; ++i) {
        t.walked[i] = t.begin[i];
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
        const float range = d * t.norm[i];
        if (range < t.min_range || range > t.max_range) {
            ++s.skipped_out_of_range;
            continue;
        }
        ++s.rays_fused;
        if (range < t.enter[i]) {
            continue;  // the ray misses the grid (enter = +inf), or the reading lies before it
        }
        // The ray enters the grid, so it has at least one entry.
        const std::uint32_t first = t.begin[i];
        const std::uint32_t end = t.begin[i + 1U];
        // The constant part of the profile: the voxels left at least one
        // ramp before the reading, entries [first, free_end).
        const float free_until = range - ramp;
        if (free_until >= t.exit[i]) {
            // The reading lies at least one ramp beyond where the ray
            // leaves the grid: every entry gets the constant, no ramp, no peak.
            t.walked[i] = end;
            s.voxel_updates += static_cast<std::uint64_t>(end - first);
            continue;
        }
        batch[searched] = SearchSlot<Limit>{static_cast<std::uint32_t>(i),
                                            first,
                                            end - first,
                                            key_limit(entries, free_until, t.steps_per_metre),
                                            key_limit(entries, range, t.steps_per_metre),
                                            range};
        ++searched;
    }
    return searched;
}

/// Pass 1b for the searched pixels of @p batch: the ramp, voxels left
/// before the reading; then the voxel holding the reading, if it lies inside
/// the grid. A walked voxel's opinion is the constant unless a ray's ramp or
/// reading lies in it: then it is the largest of their opinions (the weakest
/// free, or the hit), as fuse_sensor keeps it.
template <typename Entries, typename Limit>
void take_ramps(const Entries& entries, const FuseView& t, ImageDepth depth, const SensorModelTable& model,
                const std::array<SearchSlot<Limit>, kSearchBatch>& batch, std::size_t searched,
                FusionStats& s) noexcept {
    const std::int16_t peak = model.reading_evidence();
    for (std::size_t j = 0U; j < searched; ++j) {
        const SearchSlot<Limit>& slot = batch[j];
        const std::uint32_t first = t.begin[slot.pixel];
        const std::uint32_t end = t.begin[slot.pixel + 1U];
        // The table's own entry of the reading: the first whose exit
        // lies beyond it (end: beyond the grid). Near a face,
        // fuse_sensor's rule decides instead (at most kSettleReach
        // entries away, or out of the grid).
        std::uint32_t own = slot.base;
        while (own < end && keys(entries)[own] <= slot.range_limit) {
            ++own;
        }
        const std::uint32_t hit = near_a_face(entries, t, slot.range, first, end, own)
                                      ? settle_reading(entries, t, slot.pixel, depth[slot.pixel], first, end, own)
                                      : own;
        // The entries before the reading's are crossed: the ramp (the
        // constant before slot.base is set already). A reading outside
        // the grid leaves every entry to the box crossed.
        const std::uint32_t crossed_end = hit < end ? hit : end;
        std::uint32_t k = slot.base;
        for (; k < crossed_end; ++k) {
            const float exit = exit_of(entries, k, t.exit_step);
            const std::int16_t e = model.free_evidence(static_cast<double>(slot.range - exit));
            std::int16_t& o = t.opinion[voxels(entries)[k]];
            o = e > o ? e : o;
        }
        if (hit < end) {
            t.opinion[voxels(entries)[hit]] = peak;  // above every free opinion
            k = hit + 1U;
            ++s.readings_in_grid;
        }
        t.walked[slot.pixel] = k;
        s.voxel_updates += static_cast<std::uint64_t>(k - first);
    }
}

/// Pass 2: the hits per crossed voxel. Counts the walked entries, or, when
/// more than half of the table was walked (@p voxel_updates), starts from
/// the table's full counts and takes off the entries not walked: at most
/// half the table either way.
template <typename Entries>
void count_hits(const Entries& entries, const FuseView& t, std::uint64_t voxel_updates) noexcept {
    if (2U * voxel_updates <= static_cast<std::uint64_t>(t.steps)) {
        for (std::size_t j = 0U; j < t.crossed_count; ++j) {
            t.hits[t.crossed[j]] = 0U;
        }
        count_segments(voxels(entries), t.begin, t.walked, t.pixels, true, 1U, Span<std::uint32_t>(t.hits, t.voxels));
    } else {
        for (std::size_t j = 0U; j < t.crossed_count; ++j) {
            t.hits[t.crossed[j]] = t.full_hits[t.crossed[j]];
        }
        count_segments(voxels(entries), t.begin, t.walked, t.pixels, false, std::numeric_limits<std::uint32_t>::max(),
                       Span<std::uint32_t>(t.hits, t.voxels));
    }
}

/// RayTable::fuse for one entry kind (the checks are done by the caller).
template <typename Entries>
FusionStats fuse_entries(const Entries& entries, const FuseView& t, EvidenceGrid& grid, ImageDepth depth,
                         const SensorModelTable& model) noexcept {
    std::int16_t* const lo = grid.log_odds().data();
    std::uint8_t* const obs = grid.observed().data();
    const std::int16_t constant = model.constant_free_evidence();
    const auto ramp = static_cast<float>(model.ramp_length());
    for (std::size_t j = 0U; j < t.crossed_count; ++j) {
        t.opinion[t.crossed[j]] = constant;
    }
    // Pass 1, per pixel: where its walk ends (walked[i]; begin[i] when it
    // walks nothing), and the opinions of its ramp and hit voxels;
    // kSearchBatch pixels at a time: classify them, search them together,
    // then take their ramps.
    using Limit = decltype(key_limit(entries, 0.0F, 0.0F));
    std::array<SearchSlot<Limit>, kSearchBatch> batch{};
    FusionStats s;
    for (std::size_t batch_begin = 0U; batch_begin < t.pixels; batch_begin += kSearchBatch) {
        const std::size_t batch_end = std::min(t.pixels, batch_begin + kSearchBatch);
        const std::size_t searched = depth.u16 != nullptr ? classify_batch(entries, t, U16Depth{depth.u16}, ramp,
                                                                           batch_begin, batch_end, batch, s)
                                                          : classify_batch(entries, t, FloatDepth{depth.floats}, ramp,
                                                                           batch_begin, batch_end, batch, s);
        find_free_ends(keys(entries), t.steps, Span<SearchSlot<Limit>>(batch.data(), searched));
        take_ramps(entries, t, depth, model, batch, searched, s);
    }
    count_hits(entries, t, s.voxel_updates);
    // Pass 3: each voxel a walk reached gets the sensor's one opinion, pooled.
    for (std::size_t j = 0U; j < t.crossed_count; ++j) {
        const std::uint32_t v = t.crossed[j];
        if (t.hits[v] != 0U) {
            lo[v] = model.pool(lo[v], t.opinion[v]);
            obs[v] = 1U;
        }
    }
    return s;
}

}  // namespace

Result<FusionStats> RayTable::fuse(EvidenceGrid& grid, Span<const float> depth,
                                   const SensorModelTable& model) const noexcept {
    return fuse_image(grid, nullptr, depth, model);
}

Result<FusionStats> RayTable::fuse(EvidenceGrid& grid, const SensorReading& reading,
                                   const SensorModelTable& model) const noexcept {
    const Status valid = validate_sensor_reading(reading);
    if (!valid.ok()) {
        return valid.error();
    }
    if (!is_depth_image(reading.kind)) {
        return ErrorCode::kInvalidArgument;
    }
    if (reading.kind == SensorDataKind::kDepthImageU16) {
        return fuse_image(grid, &reading, {}, model);
    }
    return fuse_image(grid, nullptr, reading.depth, model);
}

Result<FusionStats> RayTable::fuse_image(EvidenceGrid& grid, const SensorReading* u16, Span<const float> depth,
                                         const SensorModelTable& model) const noexcept {
    if (pixels_ == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    if (!(grid.geometry() == geometry_)) {
        return ErrorCode::kGeometryMismatch;
    }
    if ((u16 != nullptr ? u16->depth_u16.size() : depth.size()) != pixels_) {
        return ErrorCode::kMalformedInput;
    }
    const std::size_t voxel_count = geometry_.voxel_count();
    CG_ENFORCE((compact_ ? std::min(storage_.compact_voxels.size(), storage_.compact_exit_steps.size())
                         : std::min(storage_.wide_voxels.size(), storage_.wide_exits.size())) >= step_count_ &&
                   pixels_ <= storage_.pixel_walked.size() && voxel_count <= storage_.full_hits.size() &&
                   crossed_count_ <= storage_.crossed_voxels.size() && voxel_count <= storage_.hit_count.size() &&
                   voxel_count <= storage_.sensor_opinion.size(),
               "ray table storage changed size");
    const FuseView view{storage_.pixel_begin.data(),
                        storage_.pixel_enter.data(),
                        storage_.pixel_exit.data(),
                        storage_.pixel_norm.data(),
                        storage_.full_hits.data(),
                        storage_.crossed_voxels.data(),
                        crossed_count_,
                        storage_.pixel_walked.data(),
                        storage_.hit_count.data(),
                        storage_.sensor_opinion.data(),
                        pixels_,
                        step_count_,
                        voxel_count,
                        min_range_,
                        max_range_,
                        exit_step_,
                        steps_per_metre_,
                        &placement_};
    const ImageDepth d{depth.data(), u16};
    return compact_ ? fuse_entries(CompactEntries{storage_.compact_voxels.data(), storage_.compact_exit_steps.data()},
                                   view, grid, d, model)
                    : fuse_entries(WideEntries{storage_.wide_voxels.data(), storage_.wide_exits.data()}, view, grid, d,
                                   model);
}

}  // namespace cellguard
