// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file embedded_data.hpp
/// The firmware's generated data as embedded by embedded_data.S (.incbin of
/// apps/firmware/generated/prior.cgprior and frames.bin into .rodata, flash
/// on the MCU): symbols with their sizes. Nothing here is checked: run_scenario
/// checks the prior with load_prior_image and the frames with
/// CannedFrames::parse before it uses them.
#ifndef CELLGUARD_FIRMWARE_EMBEDDED_DATA_HPP
#define CELLGUARD_FIRMWARE_EMBEDDED_DATA_HPP

#include <cstdint>

extern "C" {
// NOLINTBEGIN(bugprone-dynamic-static-initializers): declarations of symbols defined in embedded_data.S, no initialiser at all (false positive in clang-tidy 14)
/// The prior image (prior_image.hpp's format), byte for byte as the host tools write it.
extern const std::uint8_t cellguard_firmware_prior_image[];
/// Bytes in cellguard_firmware_prior_image.
extern const std::uint32_t cellguard_firmware_prior_image_size;
/// The image's payload, the same bytes from offset 88 on, as int16 values (in
/// place, no copy; little-endian targets only, 2-byte aligned).
extern const std::int16_t cellguard_firmware_prior_values[];
/// The canned frames (canned_frames.hpp's format).
extern const std::uint8_t cellguard_firmware_frames[];
/// The same bytes as binary32 values, for the depth images in place.
extern const float cellguard_firmware_frames_f32[];
/// Bytes in cellguard_firmware_frames.
extern const std::uint32_t cellguard_firmware_frames_size;
/// The robot image (robot_image.hpp's format) of the robot-cell run.
extern const std::uint8_t cellguard_firmware_robot_image[];
/// Bytes in cellguard_firmware_robot_image.
extern const std::uint32_t cellguard_firmware_robot_image_size;
/// The robot cell's prior image.
extern const std::uint8_t cellguard_firmware_robot_prior_image[];
/// Bytes in cellguard_firmware_robot_prior_image.
extern const std::uint32_t cellguard_firmware_robot_prior_image_size;
/// Its payload as int16 values, in place (as cellguard_firmware_prior_values).
extern const std::int16_t cellguard_firmware_robot_prior_values[];
/// The robot cell's canned frames (canned_frames.hpp's format).
extern const std::uint8_t cellguard_firmware_robot_frames[];
/// The same bytes as binary32 values.
extern const float cellguard_firmware_robot_frames_f32[];
/// Bytes in cellguard_firmware_robot_frames.
extern const std::uint32_t cellguard_firmware_robot_frames_size;
// NOLINTEND(bugprone-dynamic-static-initializers)
}

#endif  // CELLGUARD_FIRMWARE_EMBEDDED_DATA_HPP
