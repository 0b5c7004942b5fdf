// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the robot image format (byte layout, writer, loader), every corruption refused, a model from another
// robot gives another CRC and robot id.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/base/crc32.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "test_robot.hpp"

using namespace cellguard;
using cellguard::test::make_test_arm;
using cellguard::test::make_test_arm_with_mimic;
namespace layout = cellguard::robot_image_layout;

namespace {

std::vector<std::uint8_t> encode(const RobotModel& m) {
    std::vector<std::uint8_t> out(kRobotImageMaxBytes);
    const Result<std::size_t, RobotModelError> n = write_robot_image(m, Span<std::uint8_t>(out.data(), out.size()));
    REQUIRE(n.ok());
    out.resize(n.value());
    return out;
}

Span<const std::uint8_t> span_of(const std::vector<std::uint8_t>& v) { return {v.data(), v.size()}; }

ErrorCode why_refused(const std::vector<std::uint8_t>& img) {
    const Result<LoadedRobot, RobotModelError> r = load_robot_image(span_of(img));
    return r.ok() ? ErrorCode::kOk : r.error().code;
}

std::uint32_t stored_crc(const std::vector<std::uint8_t>& img) {
    const std::size_t at = img.size() - 4U;
    return static_cast<std::uint32_t>(img[at]) | (static_cast<std::uint32_t>(img[at + 1]) << 8U) |
           (static_cast<std::uint32_t>(img[at + 2]) << 16U) | (static_cast<std::uint32_t>(img[at + 3]) << 24U);
}

void reseal(std::vector<std::uint8_t>& img) {
    const std::uint32_t crc = crc32(Span<const std::uint8_t>(img.data(), img.size() - 4U));
    for (std::size_t i = 0; i < 4U; ++i)
        img[img.size() - 4U + i] = static_cast<std::uint8_t>(crc >> (8U * i));
}

void put_double(std::vector<std::uint8_t>& img, std::size_t at, double d) {
    std::uint64_t b = 0;
    std::memcpy(&b, &d, sizeof b);
    for (std::size_t i = 0; i < 8U; ++i)
        img.at(at + i) = static_cast<std::uint8_t>(b >> (8U * i));
}

// How many of @p img's single-bit errors and flipped bytes (9 per byte) the loader refuses.
std::size_t refused_changes(const std::vector<std::uint8_t>& img) {
    std::size_t refused = 0;
    for (std::size_t i = 0; i < img.size(); ++i) {
        for (unsigned bit = 0; bit < 8U; ++bit) {
            std::vector<std::uint8_t> bad = img;
            bad[i] = static_cast<std::uint8_t>(bad[i] ^ (1U << bit));
            refused += why_refused(bad) != ErrorCode::kOk ? 1U : 0U;
        }
        std::vector<std::uint8_t> bad = img;
        bad[i] = static_cast<std::uint8_t>(~bad[i]);
        refused += why_refused(bad) != ErrorCode::kOk ? 1U : 0U;
    }
    return refused;
}

// Every field of two models, used entries only.
void check_same(const RobotModel& a, const RobotModel& b) {
    CHECK(std::memcmp(a.name, b.name, sizeof a.name) == 0);
    REQUIRE(a.link_count == b.link_count);
    REQUIRE(a.capsule_count == b.capsule_count);
    CHECK(a.joint_count == b.joint_count);
    CHECK(std::memcmp(a.base_xyz, b.base_xyz, sizeof a.base_xyz) == 0);
    CHECK(std::memcmp(a.base_wxyz, b.base_wxyz, sizeof a.base_wxyz) == 0);
    for (std::size_t i = 0; i < a.link_count; ++i) {
        const RobotLink& x = a.links[i];
        const RobotLink& y = b.links[i];
        CHECK(x.parent == y.parent);
        CHECK(x.joint == y.joint);
        CHECK(x.command_index == y.command_index);
        CHECK(std::memcmp(x.origin_xyz, y.origin_xyz, sizeof x.origin_xyz) == 0);
        CHECK(std::memcmp(x.origin_wxyz, y.origin_wxyz, sizeof x.origin_wxyz) == 0);
        CHECK(std::memcmp(x.axis, y.axis, sizeof x.axis) == 0);
        CHECK(x.lower == y.lower);
        CHECK(x.upper == y.upper);
        CHECK(x.max_velocity == y.max_velocity);
        CHECK(x.mimic == y.mimic);
        CHECK(x.mimic_multiplier == y.mimic_multiplier);
        CHECK(x.mimic_offset == y.mimic_offset);
    }
    for (std::size_t i = 0; i < a.capsule_count; ++i) {
        CHECK(a.capsules[i].link == b.capsules[i].link);
        CHECK(std::memcmp(a.capsules[i].a, b.capsules[i].a, sizeof a.capsules[i].a) == 0);
        CHECK(std::memcmp(a.capsules[i].b, b.capsules[i].b, sizeof a.capsules[i].b) == 0);
        CHECK(a.capsules[i].radius == b.capsules[i].radius);
    }
}

// A model at full capacity: 16 links in a chain, 7 of them movable, 32 capsules.
RobotModel full_model() {
    RobotModel m;
    m.link_count = static_cast<std::uint8_t>(kMaxRobotLinks);
    m.joint_count = static_cast<std::uint8_t>(kMaxRobotJoints);
    m.capsule_count = static_cast<std::uint8_t>(kMaxRobotCapsules);
    for (std::size_t i = 1; i < kMaxRobotLinks; ++i) {
        RobotLink& l = m.links[i];
        l.parent = static_cast<std::uint8_t>(i - 1U);
        l.origin_xyz[2] = 0.1;
        if (i <= kMaxRobotJoints) {
            l.joint = (i % 2U == 0U) ? JointType::kPrismatic : JointType::kRevolute;
            l.command_index = static_cast<std::uint8_t>(i - 1U);
            l.lower = -1.0;
            l.upper = 1.0;
            l.max_velocity = 1.0;
        }
    }
    for (std::size_t c = 0; c < kMaxRobotCapsules; ++c) {
        m.capsules[c].link = static_cast<std::uint8_t>(c % kMaxRobotLinks);
        m.capsules[c].b[2] = 0.1;
        m.capsules[c].radius = 0.02 + 0.001 * static_cast<double>(c);
    }
    return m;
}

}  // namespace

// verifies: SR-ROB-004
TEST_CASE("a robot image round-trips every field and carries its CRC") {
    const RobotModel arm = make_test_arm(0.3, -0.2, 0.01);
    const std::vector<std::uint8_t> img = encode(arm);
    CHECK(img.size() == robot_image_size(7U, 7U));
    CHECK(img.size() == 112U + 7U * 108U + 7U * 60U);
    CHECK(std::memcmp(img.data(), "CGROBOT1", 8) == 0);
    CHECK(img[layout::kVersion] == 1U);
    CHECK(img[layout::kVersion + 1] == 0U);
    CHECK(img[layout::kLinkCount] == 7U);
    CHECK(img[layout::kJointCount] == 6U);
    CHECK(img[layout::kCapsuleCount] == 7U);
    CHECK(img[layout::kImageSize] == (img.size() & 0xFFU));
    CHECK(img[layout::kImageSize + 1] == (img.size() >> 8U));
    CHECK(std::memcmp(img.data() + layout::kName, "cellguard_test_arm", 18) == 0);
    // base x = 0.3 = 0x3FD3333333333333, little-endian.
    const std::uint8_t x_bits[8] = {0x33, 0x33, 0x33, 0x33, 0x33, 0x33, 0xD3, 0x3F};
    CHECK(std::memcmp(img.data() + layout::kBaseXyz, x_bits, 8) == 0);
    CHECK(stored_crc(img) == crc32(Span<const std::uint8_t>(img.data(), img.size() - 4U)));

    Result<LoadedRobot, RobotModelError> r = load_robot_image(span_of(img));
    {
        const cellguard::test::AllocationScope scope;
        r = load_robot_image(span_of(img));
        CHECK(scope.allocations() == 0U);
    }
    REQUIRE(r.ok());
    CHECK(r.value().crc == stored_crc(img));
    check_same(arm, r.value().model);
    CHECK(encode(r.value().model) == img);
}

// verifies: SR-ROB-004
TEST_CASE("a robot image at full capacity fits kRobotImageMaxBytes and round-trips") {
    const RobotModel m = full_model();
    REQUIRE(is_no_error(check_robot_model(m)));
    const std::vector<std::uint8_t> img = encode(m);
    CHECK(img.size() == robot_image_size(kMaxRobotLinks, kMaxRobotCapsules));
    CHECK(img.size() <= kRobotImageMaxBytes);
    const Result<LoadedRobot, RobotModelError> r = load_robot_image(span_of(img));
    REQUIRE(r.ok());
    check_same(m, r.value().model);
}

// verifies: SR-ROB-004
TEST_CASE("the writer refuses a bad model and storage that is too small") {
    RobotModel bad = make_test_arm();
    bad.capsules[3].radius = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::uint8_t> out(kRobotImageMaxBytes, 0xAAU);
    Result<std::size_t, RobotModelError> w = write_robot_image(bad, Span<std::uint8_t>(out.data(), out.size()));
    REQUIRE(!w.ok());
    CHECK(w.error().code == ErrorCode::kNonFiniteValue);
    CHECK(w.error().index == 3U);
    const RobotModel arm = make_test_arm();
    const std::size_t need = robot_image_size(7U, 7U);
    w = write_robot_image(arm, Span<std::uint8_t>(out.data(), need - 1U));
    REQUIRE(!w.ok());
    CHECK(w.error().code == ErrorCode::kStorageTooSmall);
    w = write_robot_image(arm, Span<std::uint8_t>(out.data(), need));
    CHECK(w.ok());
}

// verifies: SR-ROB-005
TEST_CASE("every single-bit error and every flipped byte of a robot image is refused") {
    const std::vector<std::uint8_t> img = encode(make_test_arm());
    REQUIRE(why_refused(img) == ErrorCode::kOk);
    CHECK(refused_changes(img) == img.size() * 9U);
}

// verifies: SR-ROB-005
TEST_CASE("a truncated or extended robot image is refused") {
    const std::vector<std::uint8_t> img = encode(make_test_arm());
    for (std::size_t n = 0; n < img.size(); ++n) {
        const std::vector<std::uint8_t> cut(img.begin(), img.begin() + static_cast<std::ptrdiff_t>(n));
        INFO("length " << n);
        CHECK(why_refused(cut) == ErrorCode::kTruncatedInput);
    }
    std::vector<std::uint8_t> longer = img;
    longer.push_back(0U);
    CHECK(why_refused(longer) == ErrorCode::kMalformedInput);
}

// verifies: SR-ROB-005
TEST_CASE("a robot image with the wrong magic, version, counts, size field or reserved bytes is refused") {
    const std::vector<std::uint8_t> img = encode(make_test_arm());
    std::vector<std::uint8_t> bad = img;
    bad[7] = '2';  // "CGROBOT2"
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kBadMagic);
    bad = img;
    bad[layout::kVersion] = 3U;
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kUnsupportedVersion);
    bad = img;
    bad[layout::kVersion] = 2U;  // version 2's link records are longer: the size field disagrees
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    for (const std::uint8_t links : {0, 17, 255}) {
        bad = img;
        bad[layout::kLinkCount] = links;
        reseal(bad);
        CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    }
    for (const std::uint8_t caps : {0, 33}) {
        bad = img;
        bad[layout::kCapsuleCount] = caps;
        reseal(bad);
        CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    }
    bad = img;
    bad[layout::kLinkCount] = 6U;  // counts that disagree with the size field
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    bad = img;
    bad[layout::kImageSize + 2] = 1U;
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    for (const std::size_t at : {layout::kReserved, layout::kReserved + 2U, kRobotImageHeaderBytes + 3U,
                                 kRobotImageHeaderBytes + 7U * kRobotImageLinkBytes + 1U}) {
        bad = img;
        bad[at] = 1U;
        reseal(bad);
        INFO("offset " << at);
        CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    }
}

// verifies: SR-ROB-005
TEST_CASE("a robot image with a correct CRC over an impossible robot is refused by the model check") {
    const std::vector<std::uint8_t> img = encode(make_test_arm());
    std::vector<std::uint8_t> bad = img;
    // Capsule 2's radius (capsule records start after the links; the radius is the record's last double).
    const std::size_t capsule2 = kRobotImageHeaderBytes + 7U * kRobotImageLinkBytes + 2U * kRobotImageCapsuleBytes;
    put_double(bad, capsule2 + 52U, std::numeric_limits<double>::quiet_NaN());
    reseal(bad);
    Result<LoadedRobot, RobotModelError> r = load_robot_image(span_of(bad));
    REQUIRE(!r.ok());
    CHECK(r.error().code == ErrorCode::kNonFiniteValue);
    CHECK(r.error().index == 2U);
    bad = img;
    bad[kRobotImageHeaderBytes + 4U * kRobotImageLinkBytes] = 4U;  // link 4 its own parent
    reseal(bad);
    r = load_robot_image(span_of(bad));
    REQUIRE(!r.ok());
    CHECK(r.error().code == ErrorCode::kInvalidArgument);
    CHECK(r.error().index == 4U);
    bad = img;
    bad[layout::kJointCount] = 5U;
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kInvalidArgument);
    bad = img;
    bad[kRobotImageHeaderBytes + 2U * kRobotImageLinkBytes + 1U] = 7U;  // unknown joint type
    reseal(bad);
    CHECK(why_refused(bad) == ErrorCode::kInvalidArgument);
}

// verifies: SR-ROB-006
TEST_CASE("a model from another robot gives another image CRC and robot id") {
    const std::vector<std::uint8_t> img = encode(make_test_arm());
    RobotModel other = make_test_arm();
    other.links[3].origin_xyz[2] += 0.001;  // forearm 1 mm longer
    const std::vector<std::uint8_t> other_img = encode(other);
    CHECK(stored_crc(img) != stored_crc(other_img));
    CHECK(robot_id(stored_crc(img)) != robot_id(stored_crc(other_img)));
    RobotModel moved = make_test_arm(0.001, 0.0, 0.0);  // same arm, base 1 mm away
    CHECK(robot_id(stored_crc(encode(moved))) != robot_id(stored_crc(img)));
    CHECK(robot_id(0x89ABCDEFU) == 0xCDEFU);
}

// verifies: SR-ROB-004
TEST_CASE("the writer's bytes equal an image made independently from the format page") {
    // tests/fuzz/corpus/fuzz_robot_image/test_arm (after its mode byte) was made with Python's struct and
    // zlib.crc32 from certification/robot-image-format.md: 1,288 bytes, CRC-32 0xE811646A.
    const std::vector<std::uint8_t> img = encode(make_test_arm());
    CHECK(img.size() == 1288U);
    CHECK(stored_crc(img) == 0xE811646AU);
    CHECK(robot_id(stored_crc(img)) == 0x646AU);
}

// verifies: SR-ROB-007
TEST_CASE("a model with a mimic joint is written as format version 2 and round-trips, one without stays version 1") {
    const RobotModel bar = make_test_arm_with_mimic(-0.5, 0.25);
    CHECK(robot_image_version(bar) == kRobotImageMimicFormatVersion);
    CHECK(robot_image_version(make_test_arm()) == kRobotImageFormatVersion);
    const std::vector<std::uint8_t> img = encode(bar);
    CHECK(img.size() == robot_image_size(8U, 8U, kRobotImageMimicFormatVersion));
    CHECK(img.size() == 112U + 8U * 124U + 8U * 60U);
    CHECK(img[layout::kVersion] == 2U);
    CHECK(img[layout::kJointCount] == 6U);
    const std::size_t bar_record = kRobotImageHeaderBytes + 7U * kRobotImageMimicLinkBytes;
    CHECK(img[bar_record + 2U] == 1U);  // the master's command index
    CHECK(img[bar_record + 3U] == 1U);  // the mimic flag
    Result<LoadedRobot, RobotModelError> r = load_robot_image(span_of(img));
    {
        const cellguard::test::AllocationScope scope;
        r = load_robot_image(span_of(img));
        CHECK(scope.allocations() == 0U);
    }
    REQUIRE(r.ok());
    check_same(bar, r.value().model);
    CHECK(encode(r.value().model) == img);
    // The plain arm's bytes are unchanged by mimic support: the same size and CRC as before it.
    CHECK(encode(make_test_arm()).size() == 1288U);
    CHECK(stored_crc(encode(make_test_arm())) == 0xE811646AU);
}

// verifies: SR-ROB-007
TEST_CASE("a version 2 robot image: every changed byte, reserved flag bits and a model without a mimic are refused") {
    const std::vector<std::uint8_t> img = encode(make_test_arm_with_mimic(-0.5, 0.25));
    REQUIRE(why_refused(img) == ErrorCode::kOk);
    CHECK(refused_changes(img) == img.size() * 9U);
    const std::size_t bar_record = kRobotImageHeaderBytes + 7U * kRobotImageMimicLinkBytes;
    for (const std::uint8_t flags : {0x02, 0x81, 0xFF}) {
        std::vector<std::uint8_t> bad = img;
        bad[bar_record + 3U] = flags;
        reseal(bad);
        INFO("flags " << int{flags});
        CHECK(why_refused(bad) == ErrorCode::kMalformedInput);
    }
    // The bar made a fixed link (no index, no flag, multiplier 1, offset 0): a valid model, but version 2 is
    // only for a model with a mimic (each model has exactly one image).
    std::vector<std::uint8_t> plain = img;
    plain[bar_record + 1U] = 0U;
    plain[bar_record + 2U] = kNoCommandIndex;
    plain[bar_record + 3U] = 0U;
    put_double(plain, bar_record + 108U, 1.0);
    put_double(plain, bar_record + 116U, 0.0);
    reseal(plain);
    const Result<LoadedRobot, RobotModelError> r = load_robot_image(span_of(plain));
    REQUIRE(!r.ok());
    CHECK(r.error().code == ErrorCode::kMalformedInput);
    CHECK(std::string(r.error().reason).find("without a mimic") != std::string::npos);
    // A mimic whose ratio was changed in the file, CRC resealed: the model check refuses it.
    std::vector<std::uint8_t> ratio = img;
    put_double(ratio, bar_record + 108U, -0.6);
    reseal(ratio);
    CHECK(why_refused(ratio) == ErrorCode::kInvalidArgument);
}

// verifies: SR-ROB-007
TEST_CASE("the writer's version 2 bytes equal an image made independently from the format page") {
    // tests/fuzz/corpus/fuzz_robot_image/palletizer_bar (after its mode byte) was made with Python's struct and
    // zlib.crc32 from certification/robot-image-format.md by tools/robot_image_v2_seed.py: 1,584 bytes, CRC-32 0xCBDB99F2.
    const std::vector<std::uint8_t> img = encode(make_test_arm_with_mimic(-0.5, 0.25));
    CHECK(img.size() == 1584U);
    CHECK(stored_crc(img) == 0xCBDB99F2U);
}
