// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/robot/robot_image.hpp"

#include <cstring>

#include "cellguard/base/crc32.hpp"

namespace cellguard {

namespace layout = robot_image_layout;

namespace {

static_assert(layout::kBaseWxyz + std::size_t{32U} == kRobotImageHeaderBytes, "the base rotation ends the header");
static_assert(layout::kName + kRobotNameBytes == layout::kBaseXyz, "the name precedes the base position");
static_assert(4U + 13U * 8U == kRobotImageLinkBytes, "a link record: 4 bytes, then 13 binary64");
static_assert(kRobotImageLinkBytes + std::size_t{16U} == kRobotImageMimicLinkBytes, "version 2 adds two binary64");
static_assert(4U + 7U * 8U == kRobotImageCapsuleBytes, "a capsule record: 4 bytes, then 7 binary64");
static_assert(sizeof(double) == 8U, "binary64 doubles");

RobotModelError fail(ErrorCode code, const char* reason) noexcept {
    RobotModelError e;
    e.code = code;
    e.reason = reason;
    return e;
}

/// Writes little-endian integers and binary64 doubles at a moving offset.
class Writer {
public:
    explicit Writer(Span<std::uint8_t> out) noexcept : out_(out) {}
    void u(std::uint64_t value, std::size_t bytes) noexcept {
        for (std::size_t i = 0U; i < bytes; ++i) {
            out_.at(at_ + i) = static_cast<std::uint8_t>((value >> (8U * i)) & 0xFFU);
        }
        at_ += bytes;
    }
    void d(const double* v, std::size_t n) noexcept {
        for (std::size_t i = 0U; i < n; ++i) {
            std::uint64_t bits = 0U;
            std::memcpy(&bits, &v[i], sizeof bits);
            u(bits, 8U);
        }
    }
    [[nodiscard]] std::size_t offset() const noexcept { return at_; }

private:
    Span<std::uint8_t> out_;
    std::size_t at_ = 0U;
};

/// Reads what Writer writes; the caller has checked the size.
class Reader {
public:
    explicit Reader(Span<const std::uint8_t> in, std::size_t at) noexcept : in_(in), at_(at) {}
    std::uint64_t u(std::size_t bytes) noexcept {
        std::uint64_t v = 0U;
        for (std::size_t i = 0U; i < bytes; ++i) {
            v |= static_cast<std::uint64_t>(in_.at(at_ + i)) << (8U * i);
        }
        at_ += bytes;
        return v;
    }
    std::uint8_t u8() noexcept { return static_cast<std::uint8_t>(u(1U)); }
    void d(double* v, std::size_t n) noexcept {
        for (std::size_t i = 0U; i < n; ++i) {
            const std::uint64_t bits = u(8U);
            std::memcpy(&v[i], &bits, sizeof bits);
        }
    }

private:
    Span<const std::uint8_t> in_;
    std::size_t at_;
};

/// Version 2's flags byte (version 1: reserved, 0): bit 0 marks a mimic joint.
constexpr std::uint8_t kMimicFlag = 0x01U;

void write_link(Writer& w, const RobotLink& l, std::uint16_t version) noexcept {
    w.u(l.parent, 1U);
    w.u(static_cast<std::uint8_t>(l.joint), 1U);
    w.u(l.command_index, 1U);
    w.u(l.mimic ? kMimicFlag : 0U, 1U);  // version 1: reserved (a model with a mimic is written as version 2)
    w.d(l.origin_xyz, 3U);
    w.d(l.origin_wxyz, 4U);
    w.d(l.axis, 3U);
    const double limits[3] = {l.lower, l.upper, l.max_velocity};
    w.d(limits, 3U);
    if (version == kRobotImageMimicFormatVersion) {
        const double mimic[2] = {l.mimic_multiplier, l.mimic_offset};
        w.d(mimic, 2U);
    }
}

/// Reads a link record; false when a reserved bit is set (version 1: any
/// bit of the fourth byte; version 2: any but the mimic flag).
bool read_link(Reader& r, RobotLink& l, std::uint16_t version) noexcept {
    l.parent = r.u8();
    l.joint = static_cast<JointType>(r.u8());  // an unknown type is refused by check_robot_model
    l.command_index = r.u8();
    const std::uint8_t flags = r.u8();
    const std::uint8_t allowed = version == kRobotImageMimicFormatVersion ? kMimicFlag : 0U;
    l.mimic = (flags & kMimicFlag) != 0U;
    r.d(l.origin_xyz, 3U);
    r.d(l.origin_wxyz, 4U);
    r.d(l.axis, 3U);
    double limits[3] = {};
    r.d(limits, 3U);
    l.lower = limits[0];
    l.upper = limits[1];
    l.max_velocity = limits[2];
    if (version == kRobotImageMimicFormatVersion) {
        double mimic[2] = {};
        r.d(mimic, 2U);
        l.mimic_multiplier = mimic[0];
        l.mimic_offset = mimic[1];
    }
    return (flags & static_cast<std::uint8_t>(~allowed)) == 0U;
}

void write_capsule(Writer& w, const RobotCapsule& c) noexcept {
    w.u(c.link, 1U);
    w.u(0U, 3U);  // reserved
    w.d(c.a, 3U);
    w.d(c.b, 3U);
    w.d(&c.radius, 1U);
}

/// Reads a capsule record; false when its reserved bytes are not 0.
bool read_capsule(Reader& r, RobotCapsule& c) noexcept {
    c.link = r.u8();
    const bool reserved_zero = r.u(3U) == 0U;
    r.d(c.a, 3U);
    r.d(c.b, 3U);
    r.d(&c.radius, 1U);
    return reserved_zero;
}

/// The header's counts and size against the input; kOk when they agree.
RobotModelError check_frame(Span<const std::uint8_t> bytes, std::size_t& size, std::uint16_t& version) noexcept {
    if (bytes.size() < sizeof kRobotImageMagic) {
        return fail(ErrorCode::kTruncatedInput, "robot image shorter than its magic");
    }
    for (std::size_t i = 0U; i < sizeof kRobotImageMagic; ++i) {
        if (bytes[layout::kMagic + i] != kRobotImageMagic[i]) {
            return fail(ErrorCode::kBadMagic, "robot image magic is not CGROBOT1");
        }
    }
    if (bytes.size() < kRobotImageHeaderBytes) {
        return fail(ErrorCode::kTruncatedInput, "robot image shorter than its header");
    }
    Reader r(bytes, layout::kVersion);
    version = static_cast<std::uint16_t>(r.u(2U));
    if (version != kRobotImageFormatVersion && version != kRobotImageMimicFormatVersion) {
        return fail(ErrorCode::kUnsupportedVersion, "robot image format version not supported");
    }
    const std::uint8_t links = r.u8();
    r.u8();  // joint count: check_robot_model checks it
    const std::uint8_t capsules = r.u8();
    if (links == 0U || links > kMaxRobotLinks || capsules == 0U || capsules > kMaxRobotCapsules) {
        return fail(ErrorCode::kMalformedInput, "robot image link or capsule count outside 1..capacity");
    }
    size = robot_image_size(links, capsules, version);
    Reader sized(bytes, layout::kImageSize);
    if (sized.u(4U) != size) {
        return fail(ErrorCode::kMalformedInput, "robot image size field disagrees with its counts");
    }
    if (bytes.size() < size) {
        return fail(ErrorCode::kTruncatedInput, "robot image shorter than its size field");
    }
    if (bytes.size() > size) {
        return fail(ErrorCode::kMalformedInput, "robot image has bytes after its CRC");
    }
    Reader crc(bytes, size - 4U);
    if (crc32(bytes.subspan(0U, size - 4U)) != crc.u(4U)) {
        return fail(ErrorCode::kCrcMismatch, "robot image CRC mismatch");
    }
    return RobotModelError{};
}

}  // namespace

std::uint16_t robot_image_version(const RobotModel& model) noexcept {
    return has_mimic_joint(model) ? kRobotImageMimicFormatVersion : kRobotImageFormatVersion;
}

Result<std::size_t, RobotModelError> write_robot_image(const RobotModel& model, Span<std::uint8_t> out) noexcept {
    const RobotModelError e = check_robot_model(model);
    if (!is_no_error(e)) {
        return e;
    }
    const std::uint16_t version = robot_image_version(model);
    const std::size_t size = robot_image_size(model.link_count, model.capsule_count, version);
    if (out.size() < size) {
        return fail(ErrorCode::kStorageTooSmall, "robot image storage too small");
    }
    Writer w(out.subspan(0U, size));
    for (const std::uint8_t m : kRobotImageMagic) {
        w.u(m, 1U);
    }
    w.u(version, 2U);
    w.u(model.link_count, 1U);
    w.u(model.joint_count, 1U);
    w.u(model.capsule_count, 1U);
    w.u(0U, 3U);  // reserved
    w.u(size, 4U);
    for (const char c : model.name) {
        w.u(static_cast<std::uint8_t>(c), 1U);
    }
    w.d(model.base_xyz, 3U);
    w.d(model.base_wxyz, 4U);
    for (std::size_t i = 0U; i < model.link_count; ++i) {
        write_link(w, model.links[i], version);
    }
    for (std::size_t i = 0U; i < model.capsule_count; ++i) {
        write_capsule(w, model.capsules[i]);
    }
    CG_ENFORCE(w.offset() == size - 4U, "robot image layout and size disagree");
    w.u(crc32(Span<const std::uint8_t>(out.data(), size - 4U)), 4U);
    return size;
}

Result<LoadedRobot, RobotModelError> load_robot_image(Span<const std::uint8_t> bytes) noexcept {
    std::size_t size = 0U;
    std::uint16_t version = 0U;
    const RobotModelError frame = check_frame(bytes, size, version);
    if (!is_no_error(frame)) {
        return frame;
    }
    LoadedRobot out;
    RobotModel& m = out.model;
    Reader r(bytes, layout::kLinkCount);
    m.link_count = r.u8();
    m.joint_count = r.u8();
    m.capsule_count = r.u8();
    bool reserved_zero = r.u(3U) == 0U;
    r.u(4U);  // size, checked
    for (char& c : m.name) {
        c = static_cast<char>(r.u8());
    }
    r.d(m.base_xyz, 3U);
    r.d(m.base_wxyz, 4U);
    for (std::size_t i = 0U; i < m.link_count; ++i) {
        reserved_zero = read_link(r, m.links[i], version) && reserved_zero;
    }
    for (std::size_t i = 0U; i < m.capsule_count; ++i) {
        reserved_zero = read_capsule(r, m.capsules[i]) && reserved_zero;
    }
    if (!reserved_zero) {
        return fail(ErrorCode::kMalformedInput, "robot image reserved byte is not 0");
    }
    if (version != robot_image_version(m)) {
        return fail(ErrorCode::kMalformedInput, "robot image version 2 without a mimic joint");
    }
    out.crc = static_cast<std::uint32_t>(r.u(4U));
    const RobotModelError e = check_robot_model(m);
    if (!is_no_error(e)) {
        return e;
    }
    return out;
}

}  // namespace cellguard
