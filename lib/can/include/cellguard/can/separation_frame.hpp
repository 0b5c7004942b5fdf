// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file separation_frame.hpp
/// The separation frame: speed and separation monitoring's result for the
/// PLC, once per cycle after the diagnostics frame (safety_output.hpp), sent
/// only in a cell with a robot configured.
///
/// Classic CAN, 8 data bytes, default CAN ID 0x104 (SafetyChannelConfig::
/// separation_can_id), protected as the other output frames by AUTOSAR E2E
/// Profile 1 with its own data ID and its own counter; no inverted copy. Like
/// the diagnostics frame it is informational: the stop and the reduced speed
/// the PLC acts on are the safety frame's ProtectiveStop and ReducedSpeed
/// bits (with its copy). This frame tells the PLC and the commissioning
/// engineer why: the measured separation distance, the protective separation
/// distance S_p it was compared with, the speed request, the monitoring case
/// and which command (its E2E counter) the cycle used.
///
/// The layout table below is the one statement of the bit positions;
/// certification/cellguard.dbc states the same (tests/unit/test_dbc.cpp).
#ifndef CELLGUARD_CAN_SEPARATION_FRAME_HPP
#define CELLGUARD_CAN_SEPARATION_FRAME_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Separation frame layout (Intel, unsigned). Bits 55 and 60..63 are reserved and zero.
namespace separation_layout {
/// E2E Profile 1 CRC (byte 0).
inline constexpr SignalLayout kCrc{"E2E_Crc", 0U, 8U, ByteOrder::kIntel, 1U, "", 255U, Multiplex::kNone, 0U};
/// E2E Profile 1 counter, 0..14 (its own sequence).
inline constexpr SignalLayout kCounter{"E2E_Counter", 8U, 4U, ByteOrder::kIntel, 1U, "", 14U, Multiplex::kNone, 0U};
/// Data ID bits 8..11 in kNibble mode, else 0.
inline constexpr SignalLayout kDataIdNibble{"E2E_DataIdNibble", 12U, 4U, ByteOrder::kIntel, 1U, "", 15U,
                                            Multiplex::kNone,   0U};
/// Smallest distance between the robot's capsules and a person (or an unseen
/// voxel in a monitored zone), mm; 65535 = nothing within range.
inline constexpr SignalLayout kSeparationDistance{"SeparationDistance", 16U, 16U, ByteOrder::kIntel, 1U, "mm", 65535U,
                                                  Multiplex::kNone,     0U};
/// Protective separation distance S_p of the robot's current speed class, mm.
inline constexpr SignalLayout kRequiredDistance{"RequiredDistance", 32U, 16U, ByteOrder::kIntel, 1U, "mm", 65535U,
                                                Multiplex::kNone,   0U};
/// Monitoring case in force, 0..15 (the safety frame's ActiveCase).
inline constexpr SignalLayout kActiveCase{"ActiveCase", 48U, 4U, ByteOrder::kIntel, 1U, "", 15U, Multiplex::kNone, 0U};
/// Speed request: 0 full, 1 reduced, 2 protective stop (SpeedRequest).
inline constexpr SignalLayout kSpeedRequest{"SpeedRequest",   52U, 2U, ByteOrder::kIntel, 1U, "", 2U,
                                            Multiplex::kNone, 0U};
/// 1 = the cycle used a good, timely command that fits the cell.
inline constexpr SignalLayout kCommandValid{"CommandValid",   54U, 1U, ByteOrder::kIntel, 1U, "", 1U,
                                            Multiplex::kNone, 0U};
/// E2E counter of the command the cycle used, 0..14 (0 when none).
inline constexpr SignalLayout kCommandCounter{"CommandCounter", 56U, 4U, ByteOrder::kIntel, 1U, "", 14U,
                                              Multiplex::kNone, 0U};
/// Every signal of the separation frame.
inline constexpr SignalLayout kSignals[] = {
    kCrc,        kCounter,      kDataIdNibble, kSeparationDistance, kRequiredDistance,
    kActiveCase, kSpeedRequest, kCommandValid, kCommandCounter};
static_assert(layout_is_consistent(kSignals), "separation frame layout overlaps or overflows");
/// Reserved bits (must be zero).
inline constexpr std::uint64_t kReservedBits = ~layout_used_bits(kSignals);
static_assert(kReservedBits == 0xF080'0000'0000'0000ULL, "bits 55 and 60..63 are the only reserved bits");
}  // namespace separation_layout

/// SeparationDistance value for "nothing within range".
constexpr std::uint16_t kSeparationDistanceFar = 65535U;

/// Content of the separation frame. Defaults: stop requested, nothing in range.
struct SeparationMessage {
    std::uint16_t distance_mm = kSeparationDistanceFar;          ///< separation distance, mm
    std::uint16_t required_mm = 0U;                              ///< S_p of the current speed class, mm
    std::uint8_t active_case = 0U;                               ///< monitoring case in force, 0..15
    SpeedRequest speed_request = SpeedRequest::kProtectiveStop;  ///< the request of this cycle
    bool command_valid = false;                                  ///< the cycle used a good command
    std::uint8_t command_counter = 0U;                           ///< that command's E2E counter, 0..14
    /// Field-wise equality.
    friend constexpr bool operator==(const SeparationMessage& a, const SeparationMessage& b) noexcept {
        return a.distance_mm == b.distance_mm && a.required_mm == b.required_mm && a.active_case == b.active_case &&
               a.speed_request == b.speed_request && a.command_valid == b.command_valid &&
               a.command_counter == b.command_counter;
    }
};

/// A decoded separation frame.
struct SeparationFrameContent {
    SeparationMessage message;  ///< the content
    std::uint8_t counter = 0U;  ///< its E2E counter, 0..14
};

/// The protected separation frame for @p message with counter @p counter.
/// kInvalidArgument when the config is invalid, the counter > 14, the case
/// > 15, the speed request is not one of the three, or the command counter > 14.
[[nodiscard]] Result<CanFrame> encode_separation_frame(const SeparationMessage& message, std::uint8_t counter,
                                                       const SafetyChannelConfig& config) noexcept;

/// Checks @p frame as a separation frame of @p config (CAN ID, DLC, data ID,
/// CRC, counter range, reserved bits, speed request 0..2, command counter
/// 0..14); on kOk writes @p out (untouched otherwise). @p config must be valid (contract).
[[nodiscard]] FrameCheck check_separation_frame(const CanFrame& frame, const SafetyChannelConfig& config,
                                                SeparationFrameContent& out) noexcept;

/// Same as check_separation_frame, as a Result (error from to_error_code).
[[nodiscard]] Result<SeparationFrameContent> decode_separation_frame(const CanFrame& frame,
                                                                     const SafetyChannelConfig& config) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_CAN_SEPARATION_FRAME_HPP
