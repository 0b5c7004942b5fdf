// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: uint16 depth images (kDepthImageU16) as a camera delivers
// them, with any size, scale, offset, ranges and pose. No crash, no read
// outside the image (ASan: the raw values are copied into a heap buffer of
// exactly their size); fuse_sensor refuses exactly what
// validate_sensor_reading refuses; every pixel is fused or counted as
// skipped; and the u16 image gives the same counts and the same grid as the
// float image of its depth_value()s, in both rasterizations and through a
// ray table of the sensor.
//
// Input: width - 1 and height - 1 (a byte each, mod 16), depth_scale,
// depth_offset, min_range, max_range (4 little-endian float bytes each), a
// rotation (a quaternion from 4 signed bytes, 0 0 0 0: the identity) and a
// translation (3 signed bytes, centimetres around the grid), then the raw
// values (2 bytes each; missing ones are 0; a 1-in-256 chance of a value
// count that does not fit the size comes from the first byte's high bits).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_table.hpp"

using namespace cellguard;

namespace {

void require(bool condition) {
    if (!condition) {
        std::abort();
    }
}

/// The fuzz bytes, read front to back; zeros once they run out.
struct Bytes {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t at = 0U;
    std::uint8_t byte() { return at < size ? data[at++] : std::uint8_t{0}; }
    float f32() {
        std::uint32_t bits = 0U;
        for (unsigned i = 0U; i < 4U; ++i) {
            bits |= static_cast<std::uint32_t>(byte()) << (8U * i);
        }
        float f = 0.0F;
        std::memcpy(&f, &bits, sizeof f);
        return f;
    }
};

GridGeometry small_grid() { return GridGeometry::make(Eigen::Vector3d::Zero(), 0.1, GridDims{8, 8, 8}).value(); }

struct OwnedGrid {
    std::vector<std::int16_t> lo, scratch;
    std::vector<std::uint8_t> ob;
    EvidenceGrid grid;
    explicit OwnedGrid(const GridGeometry& g) : lo(g.voxel_count()), scratch(g.voxel_count()), ob(g.voxel_count()) {
        grid = EvidenceGrid::make(g, {lo.data(), lo.size()}, {ob.data(), ob.size()}).value();
        grid.clear();
    }
    bool same_as(const OwnedGrid& o) const { return lo == o.lo && ob == o.ob; }
};

bool same_stats(const FusionStats& a, const FusionStats& b) {
    return a.rays_fused == b.rays_fused && a.readings_in_grid == b.readings_in_grid && a.skipped_nan == b.skipped_nan &&
           a.skipped_infinite == b.skipped_infinite && a.skipped_zero == b.skipped_zero &&
           a.skipped_behind == b.skipped_behind && a.skipped_out_of_range == b.skipped_out_of_range &&
           a.voxel_updates == b.voxel_updates;
}

/// A ray table of @p sensor in @p g fuses @p u16 as the float twin @p f.
void check_table(const GridGeometry& g, const SensorReading& u16, const SensorReading& f) {
    const Result<std::size_t> steps = count_ray_steps(g, u16);
    require(steps.ok());
    const std::size_t n = steps.value();
    const std::size_t px = u16.depth_u16.size();
    const std::size_t voxels = g.voxel_count();
    const bool compact = ray_table_is_compact(g, u16);
    std::vector<std::uint16_t> cv(compact ? n : 0U), cs(compact ? n : 0U);
    std::vector<std::uint32_t> wv(compact ? 0U : n), begin(px + 1U), full(voxels), crossed(voxels), walked(px),
        hits(voxels);
    std::vector<float> we(compact ? 0U : n), enter(px), exit(px), norm(px);
    std::vector<std::int16_t> opinion(voxels);
    const RayTableStorage st{
        {cv.data(), cv.size()},           {cs.data(), cs.size()},         {wv.data(), wv.size()},
        {we.data(), we.size()},           {begin.data(), begin.size()},   {enter.data(), enter.size()},
        {exit.data(), exit.size()},       {norm.data(), norm.size()},     {full.data(), full.size()},
        {crossed.data(), crossed.size()}, {walked.data(), walked.size()}, {hits.data(), hits.size()},
        {opinion.data(), opinion.size()}};
    const Result<RayTable> table = RayTable::build(g, u16, st);
    require(table.ok());
    OwnedGrid a(g);
    OwnedGrid b(g);
    const SensorModelTable model;
    const Result<FusionStats> su = table.value().fuse(a.grid, u16, model);
    const Result<FusionStats> sf = table.value().fuse(b.grid, f.depth, model);
    require(su.ok() && sf.ok());
    require(same_stats(su.value(), sf.value()) && a.same_as(b));
    require(su.value().rays_fused + su.value().skipped() == px);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Bytes in{data, size};
    const std::uint8_t first = in.byte();
    const std::int32_t width = 1 + (first & 15);
    const std::int32_t height = 1 + (in.byte() & 15);
    const bool misfit = (first >> 4U) == 15U && size % 16U == 0U;
    SensorReading r;
    r.kind = SensorDataKind::kDepthImageU16;
    r.depth_scale = in.f32();
    r.depth_offset = in.f32();
    r.min_range = in.f32();
    r.max_range = in.f32();
    const auto s8 = [&in] { return static_cast<double>(static_cast<std::int8_t>(in.byte())); };
    const double qw = s8();
    const double qx = s8();
    const double qy = s8();
    const double qz = s8();
    Eigen::Quaterniond q(qw, qx, qy, qz);
    q = q.norm() > 0.0 ? q.normalized() : Eigen::Quaterniond::Identity();
    r.pose.linear() = q.toRotationMatrix();
    r.pose.translation() = Eigen::Vector3d(0.4 + s8() / 100.0, 0.4 + s8() / 100.0, 0.4 + s8() / 100.0);
    r.intrinsics = PinholeIntrinsics{8.0, 8.0, (width - 1) / 2.0, (height - 1) / 2.0, width, height};
    const std::size_t px = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) + (misfit ? 1U : 0U);
    std::vector<std::uint16_t> raw(px);  // exactly px values on the heap, for ASan
    for (std::uint16_t& v : raw) {
        v = static_cast<std::uint16_t>(in.byte() | (in.byte() << 8U));
    }
    r.depth_u16 = Span<const std::uint16_t>(raw.data(), raw.size());

    const GridGeometry g = small_grid();
    const Status valid = validate_sensor_reading(r);
    OwnedGrid a(g);
    const Result<FusionStats> su = fuse_sensor(a.grid, r, SensorModelTable{}, {a.scratch.data(), a.scratch.size()});
    require(su.ok() == valid.ok());
    if (!valid.ok()) {
        require(su.error() == valid.error());
        return 0;
    }
    require(!misfit);  // a value count that does not fit the size is refused
    require(su.value().rays_fused + su.value().skipped() == px);
    // The float twin: depth_value of every pixel, fused the same way.
    std::vector<float> depth(px);
    std::size_t raw_zeros = 0U;
    for (std::size_t i = 0U; i < px; ++i) {
        depth[i] = depth_value(r, i);
        raw_zeros += raw[i] == 0U ? 1U : 0U;
    }
    require(su.value().skipped_nan >= raw_zeros);  // raw 0: no reading, counted as NaN
    SensorReading f = r;
    f.kind = SensorDataKind::kDepthImage;
    f.depth = Span<const float>(depth.data(), depth.size());
    for (const Rasterization ras : {Rasterization::kExact, Rasterization::kBresenham3d}) {
        OwnedGrid x(g);
        OwnedGrid y(g);
        const Result<FusionStats> xu = fuse_sensor(x.grid, r, SensorModelTable{}, {x.scratch.data(), x.scratch.size()},
                                                   ras);
        const Result<FusionStats> yf = fuse_sensor(y.grid, f, SensorModelTable{}, {y.scratch.data(), y.scratch.size()},
                                                   ras);
        require(xu.ok() && yf.ok());
        require(same_stats(xu.value(), yf.value()) && x.same_as(y));
    }
    check_table(g, r, f);
    return 0;
}
