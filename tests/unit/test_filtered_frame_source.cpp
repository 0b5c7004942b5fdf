// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The depth filter in the monitor's camera path (apps/host
// cell/filtered_frame_source.hpp): float and uint16 images are filtered
// against the sensor's view and given on as float images with the frame as
// delivered beside them; point sets pass; a wrong size is refused.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cellguard/host/cell/filtered_frame_source.hpp"

using namespace cellguard;
using namespace cellguard::cell;

namespace {

constexpr std::int32_t kW = 6;
constexpr std::int32_t kH = 4;
constexpr std::size_t kN = static_cast<std::size_t>(kW * kH);

/// A source that gives one prepared reading (float, uint16 or points), or refuses.
class StubSource final : public FrameSource {
public:
    SensorReading reading{};
    bool refuse = false;
    bool fresh = true;
    int summaries = 0;
    bool load_frame(std::uint64_t /*cycle*/, SensorReading& out, FrameStatus& status) noexcept override {
        if (refuse) {
            refuse_reading(out);
            status.ok = false;
            return false;
        }
        out = reading;
        status.ok = true;
        return true;
    }
    [[nodiscard]] bool has_new_frame() const noexcept override { return fresh; }
    void write_summary(std::FILE* /*out*/) const noexcept override { ++const_cast<StubSource*>(this)->summaries; }
};

PinholeIntrinsics intrinsics(std::int32_t w, std::int32_t h) {
    return PinholeIntrinsics{100.0, 100.0, w / 2.0, h / 2.0, w, h};
}

DepthConditioning tolerance_and_edges() {
    DepthConditioning c;
    c.background_tolerance_per_m = 0.05;  // 15 cm at 3 m
    c.edge_jump_min_m = 0.05;
    return c;
}

}  // namespace

// verifies: SR-CAM-011
TEST_CASE("filtered frame source: a float image is filtered against the view, the delivered frame kept beside it") {
    const std::vector<float> view(kN, 3.0F);
    std::vector<float> raw(kN, 3.0F);
    raw[0] = 3.04F;  // range noise: under the edge jump (5 cm), within the tolerance: onto the view
    raw[10] = 2.5F;  // an object: stays, and its 4 neighbours are its edge
    auto stub = std::make_unique<StubSource>();
    stub->reading.kind = SensorDataKind::kDepthImage;
    stub->reading.depth = {raw.data(), raw.size()};
    stub->reading.intrinsics = intrinsics(kW, kH);
    StubSource* inner = stub.get();
    FilteredFrameSource f(std::move(stub), {view.data(), view.size()}, kW, kH, tolerance_and_edges(), "cam");
    SensorReading r;
    FrameStatus st;
    REQUIRE(f.load_frame(0U, r, st));
    CHECK(st.filtered);
    CHECK(st.delivered.depth.data() == raw.data());  // the frame as delivered: the inner source's
    CHECK(r.kind == SensorDataKind::kDepthImage);
    REQUIRE(r.depth.size() == kN);
    CHECK(r.depth.data() != raw.data());
    CHECK(r.depth[0] == 3.0F);
    CHECK(r.depth[10] == 0.0F);  // dropped: every 4-neighbour is 0.5 m deeper
    CHECK(r.depth[4] == 0.0F);   // (4, 0) is above it: an edge pixel
    CHECK(r.depth[23] == 3.0F);
    CHECK(raw[0] == 3.04F);  // the delivered frame is not changed
    CHECK(f.counts().dropped == 5U);
    CHECK(f.frames() == 1U);
    // The inner source's freshness and summary go through.
    CHECK(f.has_new_frame());
    inner->fresh = false;
    CHECK_FALSE(f.has_new_frame());
    f.write_summary(nullptr);
    CHECK(inner->summaries == 1);
    // The filter's counts under the sensor's name.
    std::FILE* out = std::tmpfile();
    REQUIRE(out != nullptr);
    f.write_summary(out);
    std::rewind(out);
    char line[256] = {};
    CHECK(std::fgets(line, sizeof line, out) != nullptr);
    static_cast<void>(std::fclose(out));
    CHECK(std::string(line).find("depth filter (cam): 1 frames, 5 readings dropped at edges") == 0U);
}

// verifies: SR-CAM-011
TEST_CASE("filtered frame source: a uint16 image reads as the fusion reads it, raw 0 as no reading") {
    const std::vector<float> view(kN, 2.0F);
    std::vector<std::uint16_t> raw(kN, 2000U);
    raw[3] = 0U;     // no reading
    raw[7] = 2040U;  // 4 cm deeper: within 5 % of 2 m
    auto stub = std::make_unique<StubSource>();
    stub->reading.kind = SensorDataKind::kDepthImageU16;
    stub->reading.depth_u16 = {raw.data(), raw.size()};
    stub->reading.depth_scale = 0.001F;
    stub->reading.intrinsics = intrinsics(kW, kH);
    DepthConditioning c;
    c.background_tolerance_per_m = 0.05;
    FilteredFrameSource f(std::move(stub), {view.data(), view.size()}, kW, kH, c, "cam");
    SensorReading r;
    FrameStatus st;
    REQUIRE(f.load_frame(1U, r, st));
    CHECK(st.filtered);
    CHECK(st.delivered.kind == SensorDataKind::kDepthImageU16);
    CHECK(r.kind == SensorDataKind::kDepthImage);
    CHECK(r.depth_u16.empty());
    CHECK(std::isnan(r.depth[3]));
    CHECK(r.depth[7] == 2.0F);
    CHECK(r.depth[0] == depth_value(st.delivered, 0U));
    CHECK(f.counts().snapped == kN - 1U);
}

// verifies: SR-CAM-011
TEST_CASE("filtered frame source: a point set passes, a refusal passes, an image of another size is refused") {
    const std::vector<float> view(kN, 3.0F);
    auto stub = std::make_unique<StubSource>();
    const std::vector<Eigen::Vector3f> points(3, Eigen::Vector3f(0.0F, 0.0F, 1.0F));
    stub->reading.kind = SensorDataKind::kPointSet;
    stub->reading.points = {points.data(), points.size()};
    StubSource* inner = stub.get();
    FilteredFrameSource f(std::move(stub), {view.data(), view.size()}, kW, kH, tolerance_and_edges(), "cam");
    SensorReading r;
    FrameStatus st;
    REQUIRE(f.load_frame(0U, r, st));
    CHECK_FALSE(st.filtered);
    CHECK(r.points.data() == points.data());
    inner->refuse = true;
    CHECK_FALSE(f.load_frame(1U, r, st));
    CHECK_FALSE(std::isfinite(r.pose.translation().x()));
    inner->refuse = false;
    std::vector<float> wide(static_cast<std::size_t>((kW + 1) * kH), 3.0F);
    inner->reading = SensorReading{};
    inner->reading.kind = SensorDataKind::kDepthImage;
    inner->reading.depth = {wide.data(), wide.size()};
    inner->reading.intrinsics = intrinsics(kW + 1, kH);
    FrameStatus wrong;
    CHECK_FALSE(f.load_frame(2U, r, wrong));
    CHECK_FALSE(wrong.ok);
    CHECK_FALSE(wrong.filtered);
    CHECK_FALSE(std::isfinite(r.pose.translation().x()));
    CHECK(std::string(wrong.reason).find("depth filter: a 7x4 image, the sensor's view is 6x4") == 0U);
    CHECK(f.frames() == 0U);
}
