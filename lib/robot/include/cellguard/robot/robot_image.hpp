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

/// A loaded robot image: the model and the image's CRC-32.
struct LoadedRobot {
    RobotModel model{};       ///< the checked model
    std::uint32_t crc = 0U;   ///< the CRC-32 stored in (and verified over) the image
};

/// The 16-bit robot identity the PLC's command carries: the low 16 bits of
/// the robot image's CRC-32. A PLC commissioned for another robot image
/// sends another value; the controller refuses its commands.
[[nodiscard]] constexpr std::uint16_t robot_id(std::uint32_t image_crc) noexcept {
    return static_cast<std::uint16_t>(image_crc & 0xFFFFU);
}

/// Writes @p model (checked first with check_robot_model) as an image into
/// @p out; returns the number of bytes written. Errors: the model's own, or
/// kStorageTooSmall when @p out is shorter than the image.
[[nodiscard]] Result<std::size_t, RobotModelError> write_robot_image(const RobotModel& model,
                                                                     Span<std::uint8_t> out) noexcept;

/// Reads and checks an image. Errors: kTruncatedInput, kBadMagic,
/// kUnsupportedVersion, kMalformedInput (size or counts disagree),
/// kCrcMismatch, then check_robot_model's.
[[nodiscard]] Result<LoadedRobot, RobotModelError> load_robot_image(Span<const std::uint8_t> bytes) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ROBOT_IMAGE_HPP
