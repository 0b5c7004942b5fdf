// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file frame_protection.hpp
/// Private to lib/can: the E2E Profile 1 header every cellguard frame shares
/// (CRC byte 0, counter bits 8..11, data ID nibble bits 12..15, the bits of
/// safety_layout::kCrc, kCounter and kDataIdNibble), written and checked
/// once for the output frames and the PLC's command parts.
#ifndef CELLGUARD_CAN_FRAME_PROTECTION_HPP
#define CELLGUARD_CAN_FRAME_PROTECTION_HPP

#include <cstdint>

#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/e2e_crc.hpp"
#include "cellguard/can/safety_frame.hpp"

namespace cellguard::detail {

/// Writes counter, data ID nibble (kNibble mode, else 0) and CRC into @p frame.
void protect_frame(CanFrame& frame, std::uint8_t counter, std::uint16_t data_id, E2eP01DataIdMode mode) noexcept;

/// The E2E part of a frame check, in this order: CAN ID, length, data ID
/// nibble (kNibble mode), CRC, counter range, nibble bits zero outside kNibble mode.
[[nodiscard]] FrameCheck check_frame_protection(const CanFrame& frame, std::uint32_t can_id, std::uint16_t data_id,
                                                E2eP01DataIdMode mode) noexcept;

/// A CAN frame with 8 zero data bytes and identifier @p id.
[[nodiscard]] constexpr CanFrame empty_frame(std::uint32_t id) noexcept {
    return {id, kCanMaxDataLength, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
}

}  // namespace cellguard::detail

#endif  // CELLGUARD_CAN_FRAME_PROTECTION_HPP
