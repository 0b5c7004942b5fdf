// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_image.hpp
/// The robot image: a RobotModel as bytes, CRC-protected, written at
/// commissioning (cellguard-robot, from a URDF) next to the prior image and
/// placed in the firmware's flash. The byte layout is stated in
/// certification/robot-image-format.md: little-endian, numbers as IEEE-754
/// binary64, a magic, a version, the counts, the model, and a CRC-32 over
/// everything before it. Loading checks the magic, version, size, CRC and
/// then the model itself (check_robot_model): a corrupt image, one from
/// another robot (see robot_id) or one that describes an impossible robot is
/// refused with the reason, never half-loaded.
#ifndef CELLGUARD_ROBOT_IMAGE_HPP
#define CELLGUARD_ROBOT_IMAGE_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/robot/robot_model.hpp"

namespace cellguard {

/// Storage that holds any robot image (a model at full capacity; robot_image.cpp
/// checks the exact size against it).
constexpr std::size_t kRobotImageMaxBytes = 4096U;

/// The image's first eight bytes, ASCII "CGROBOT1".
constexpr std::uint8_t kRobotImageMagic[8] = {0x43U, 0x47U, 0x52U, 0x4FU, 0x42U, 0x4FU, 0x54U, 0x31U};
/// The format version of a model without mimic joints: written for every
/// such model, so its bytes, CRC and robot id are those of every earlier build.
constexpr std::uint16_t kRobotImageFormatVersion = 1U;
/// The format version of a model with a mimic joint: each link record adds
/// the mimic flag, multiplier and offset. This build reads both versions.
constexpr std::uint16_t kRobotImageMimicFormatVersion = 2U;
/// Bytes of the image's header (magic .. base rotation).
constexpr std::size_t kRobotImageHeaderBytes = 108U;
/// Bytes of one link record (version 1).
constexpr std::size_t kRobotImageLinkBytes = 108U;
/// Bytes of one link record (version 2: version 1's and two binary64).
constexpr std::size_t kRobotImageMimicLinkBytes = 124U;
/// Bytes of one capsule record.
constexpr std::size_t kRobotImageCapsuleBytes = 60U;

/// Byte offsets of the header's fields (certification/robot-image-format.md).
namespace robot_image_layout {
constexpr std::size_t kMagic = 0U;          ///< 8 bytes "CGROBOT1"
constexpr std::size_t kVersion = 8U;        ///< u16 format version
constexpr std::size_t kLinkCount = 10U;     ///< u8
constexpr std::size_t kJointCount = 11U;    ///< u8
constexpr std::size_t kCapsuleCount = 12U;  ///< u8
constexpr std::size_t kReserved = 13U;      ///< 3 bytes, 0
constexpr std::size_t kImageSize = 16U;     ///< u32 size of the whole image, CRC included
constexpr std::size_t kName = 20U;          ///< 32 bytes, the name as the model holds it
constexpr std::size_t kBaseXyz = 52U;       ///< 3 binary64
constexpr std::size_t kBaseWxyz = 76U;      ///< 4 binary64
}  // namespace robot_image_layout

/// Size in bytes of the image of a model with @p links links and @p capsules
/// capsules in format @p version (1 or 2): header, link records, capsule
/// records and the 4-byte CRC.
[[nodiscard]] constexpr std::size_t robot_image_size(std::size_t links, std::size_t capsules,
                                                     std::uint16_t version = kRobotImageFormatVersion) noexcept {
    const std::size_t link_bytes = version == kRobotImageMimicFormatVersion ? kRobotImageMimicLinkBytes
                                                                            : kRobotImageLinkBytes;
    return kRobotImageHeaderBytes + links * link_bytes + capsules * kRobotImageCapsuleBytes + 4U;
}

static_assert(robot_image_size(kMaxRobotLinks, kMaxRobotCapsules, kRobotImageMimicFormatVersion) <= kRobotImageMaxBytes,
              "the largest robot image fits kRobotImageMaxBytes");

/// The format version @p model is written in: 2 when it has a mimic joint, else 1.
[[nodiscard]] std::uint16_t robot_image_version(const RobotModel& model) noexcept;

/// A loaded robot image: the model and the image's CRC-32.
struct LoadedRobot {
    RobotModel model{};      ///< the checked model
    std::uint32_t crc = 0U;  ///< the CRC-32 stored in (and verified over) the image
};

/// The 16-bit robot identity the PLC's command carries: the low 16 bits of
/// the robot image's CRC-32. A PLC commissioned for another robot image
/// sends another value; the controller refuses its commands.
[[nodiscard]] constexpr std::uint16_t robot_id(std::uint32_t image_crc) noexcept {
    return static_cast<std::uint16_t>(image_crc & 0xFFFFU);
}

/// Writes @p model (checked first with check_robot_model) as an image in
/// format robot_image_version(model) into
/// @p out; returns the number of bytes written. Errors: the model's own, or
/// kStorageTooSmall when @p out is shorter than the image.
[[nodiscard]] Result<std::size_t, RobotModelError> write_robot_image(const RobotModel& model,
                                                                     Span<std::uint8_t> out) noexcept;

/// Reads and checks an image of either version. Errors: kTruncatedInput,
/// kBadMagic, kUnsupportedVersion, kMalformedInput (size or counts disagree,
/// a reserved bit set, a version 2 image without a mimic joint: each model
/// has one image), kCrcMismatch, then check_robot_model's.
[[nodiscard]] Result<LoadedRobot, RobotModelError> load_robot_image(Span<const std::uint8_t> bytes) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ROBOT_IMAGE_HPP
