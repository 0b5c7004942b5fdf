// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file safety_frame.hpp
/// The CAN safety output: the safety frame (with its inverted copy) and the
/// diagnostics frame, their bit layout, encoder and decoder, and the channel
/// config of all output frames (the separation frame's codec is in
/// separation_frame.hpp).
///
/// Both frames are classic CAN, 8 data bytes, protected as in AUTOSAR E2E
/// Profile 1 (e2e_crc.hpp): CRC in byte 0 over the data ID and bytes 1..7,
/// counter 0..14 in bits 8..11, explicit data ID nibble in bits 12..15 (kNibble
/// mode; zero in the other modes). Each frame type has its own data ID.
///
/// As with CANopen Safety (EN 50325-5) SRDOs, every safety frame is followed
/// by its inverted copy: the next CAN ID (safety_can_id + 1), every data bit
/// inverted (CRC and counter included). The diagnostics frame has no copy.
///
/// The layout tables below are the one statement of byte order and bit
/// positions; certification/cellguard.dbc states the same and
/// tests/unit/test_dbc.cpp checks that the two agree. Safety frame: up to 16
/// zones (kMaxZonesInFrame), bit z of ZoneIntrusion / ZoneUnseen is zone z;
/// the monitoring case in force (ActiveCase, 0..15) and the speed request:
/// ProtectiveStop = 1 means stop, else ReducedSpeed = 1 means reduced speed,
/// else full speed. ProtectiveStop wins: a frame with both bits set is valid
/// and means stop.
/// Diagnostics frame: cycle times in units of 100 us (rounded up, saturating
/// at 2047 = "204.7 ms or more"); the 32-bit CRC of the prior image is split
/// over four multiplexed pages, page p carrying its bits 8p..8p+7.
#ifndef CELLGUARD_SAFETY_FRAME_HPP
#define CELLGUARD_SAFETY_FRAME_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/e2e_crc.hpp"
#include "cellguard/can/fault_code.hpp"

namespace cellguard {

/// Largest number of zones one safety frame carries.
constexpr std::uint8_t kMaxZonesInFrame = 16U;

/// Safety frame layout (Intel, unsigned). Every bit is used.
namespace safety_layout {
/// E2E Profile 1 CRC (byte 0).
inline constexpr SignalLayout kCrc{"E2E_Crc", 0U, 8U, ByteOrder::kIntel, 1U, "", 255U, Multiplex::kNone, 0U};
/// E2E Profile 1 counter, 0..14.
inline constexpr SignalLayout kCounter{"E2E_Counter", 8U, 4U, ByteOrder::kIntel, 1U, "", 14U, Multiplex::kNone, 0U};
/// Data ID bits 8..11 in kNibble mode, else 0.
inline constexpr SignalLayout kDataIdNibble{"E2E_DataIdNibble", 12U, 4U, ByteOrder::kIntel, 1U, "", 15U,
                                            Multiplex::kNone,   0U};
/// 1 = protective stop requested.
inline constexpr SignalLayout kProtectiveStop{"ProtectiveStop", 16U, 1U, ByteOrder::kIntel, 1U, "", 1U,
                                              Multiplex::kNone, 0U};
/// 1 = a warning zone is intruded or unseen.
inline constexpr SignalLayout kWarning{"Warning", 17U, 1U, ByteOrder::kIntel, 1U, "", 1U, Multiplex::kNone, 0U};
/// 1 = the controller has detected a fault (details in the diagnostics frame).
inline constexpr SignalLayout kFault{"Fault", 18U, 1U, ByteOrder::kIntel, 1U, "", 1U, Multiplex::kNone, 0U};
/// Monitoring case whose zones this frame reports, 0..15 (0 without cases).
inline constexpr SignalLayout kActiveCase{"ActiveCase", 19U, 4U, ByteOrder::kIntel, 1U, "", 15U, Multiplex::kNone, 0U};
/// 1 = reduced speed requested (meaningful when ProtectiveStop is 0; stop wins).
inline constexpr SignalLayout kReducedSpeed{"ReducedSpeed",   23U, 1U, ByteOrder::kIntel, 1U, "", 1U,
                                            Multiplex::kNone, 0U};
/// Bit z = zone z is intruded.
inline constexpr SignalLayout kZoneIntrusion{"ZoneIntrusion",  24U, 16U, ByteOrder::kIntel, 1U, "", 65535U,
                                             Multiplex::kNone, 0U};
/// Bit z = zone z cannot be seen (too many unobserved voxels).
inline constexpr SignalLayout kZoneUnseen{"ZoneUnseen",     40U, 16U, ByteOrder::kIntel, 1U, "", 65535U,
                                          Multiplex::kNone, 0U};
/// Number of configured zones, 0..16; zone bits at and above it are zero.
inline constexpr SignalLayout kZoneCount{"ZoneCount", 56U, 8U, ByteOrder::kIntel, 1U, "", 16U, Multiplex::kNone, 0U};
/// Every signal of the safety frame (and, with inverted raw values, of its copy).
inline constexpr SignalLayout kSignals[] = {kCrc,           kCounter,    kDataIdNibble, kProtectiveStop,
                                            kWarning,       kFault,      kActiveCase,   kReducedSpeed,
                                            kZoneIntrusion, kZoneUnseen, kZoneCount};
static_assert(layout_is_consistent(kSignals), "safety frame layout overlaps or overflows");
/// Reserved bits (must be zero): none since ActiveCase and ReducedSpeed took bits 19..23.
inline constexpr std::uint64_t kReservedBits = ~layout_used_bits(kSignals);
static_assert(kReservedBits == 0U, "the safety frame has no reserved bits");
}  // namespace safety_layout

/// Diagnostics frame layout (Intel, unsigned). All 64 bits are used.
namespace diagnostics_layout {
/// E2E Profile 1 CRC (byte 0).
inline constexpr SignalLayout kCrc{"E2E_Crc", 0U, 8U, ByteOrder::kIntel, 1U, "", 255U, Multiplex::kNone, 0U};
/// E2E Profile 1 counter, 0..14 (its own sequence, independent of the safety frame's).
inline constexpr SignalLayout kCounter{"E2E_Counter", 8U, 4U, ByteOrder::kIntel, 1U, "", 14U, Multiplex::kNone, 0U};
/// Data ID bits 8..11 in kNibble mode, else 0.
inline constexpr SignalLayout kDataIdNibble{"E2E_DataIdNibble", 12U, 4U, ByteOrder::kIntel, 1U, "", 15U,
                                            Multiplex::kNone,   0U};
/// Active fault codes, bit n = FaultCode n: 0..8 and 15 safety logic Faults, 9..14 CAN details.
inline constexpr SignalLayout kActiveFaults{"ActiveFaults",   16U, 16U, ByteOrder::kIntel, 1U, "", 65535U,
                                            Multiplex::kNone, 0U};
/// Duration of the last cycle, 100 us units, rounded up, saturating at 2047.
inline constexpr SignalLayout kCycleTime{"CycleTime",      32U, 11U, ByteOrder::kIntel, 100U, "us", 2047U,
                                         Multiplex::kNone, 0U};
/// Longest cycle since start-up, 100 us units, rounded up, saturating at 2047.
inline constexpr SignalLayout kMaxCycleTime{"MaxCycleTime",   43U, 11U, ByteOrder::kIntel, 100U, "us", 2047U,
                                            Multiplex::kNone, 0U};
/// Multiplexor: which byte of the prior image CRC-32 this frame carries, 0..3.
inline constexpr SignalLayout kPriorCrcPage{"PriorCrcPage",          54U, 2U, ByteOrder::kIntel, 1U, "", 3U,
                                            Multiplex::kMultiplexor, 0U};
/// Prior image CRC-32 bits 0..7 (page 0).
inline constexpr SignalLayout kPriorCrcBits0To7{"PriorCrcBits0To7",      56U, 8U, ByteOrder::kIntel, 1U, "", 255U,
                                                Multiplex::kMultiplexed, 0U};
/// Prior image CRC-32 bits 8..15 (page 1).
inline constexpr SignalLayout kPriorCrcBits8To15{"PriorCrcBits8To15",     56U, 8U, ByteOrder::kIntel, 1U, "", 255U,
                                                 Multiplex::kMultiplexed, 1U};
/// Prior image CRC-32 bits 16..23 (page 2).
inline constexpr SignalLayout kPriorCrcBits16To23{"PriorCrcBits16To23",    56U, 8U, ByteOrder::kIntel, 1U, "", 255U,
                                                  Multiplex::kMultiplexed, 2U};
/// Prior image CRC-32 bits 24..31 (page 3).
inline constexpr SignalLayout kPriorCrcBits24To31{"PriorCrcBits24To31",    56U, 8U, ByteOrder::kIntel, 1U, "", 255U,
                                                  Multiplex::kMultiplexed, 3U};
/// Every signal of the diagnostics frame.
inline constexpr SignalLayout kSignals[] = {
    kCrc,          kCounter,          kDataIdNibble,      kActiveFaults,       kCycleTime,         kMaxCycleTime,
    kPriorCrcPage, kPriorCrcBits0To7, kPriorCrcBits8To15, kPriorCrcBits16To23, kPriorCrcBits24To31};
static_assert(layout_is_consistent(kSignals), "diagnostics frame layout overlaps or overflows");
static_assert(~layout_used_bits(kSignals) == 0U, "the diagnostics frame has no reserved bits");
}  // namespace diagnostics_layout

/// Largest monitoring case number a safety frame carries.
constexpr std::uint8_t kMaxActiveCase = 15U;

/// Content of the safety frame. Defaults are the safe state: stop requested.
struct SafetyMessage {
    bool protective_stop = true;        ///< protective stop requested (wins over reduced_speed)
    bool warning = false;               ///< a warning zone is intruded or unseen
    bool fault = false;                 ///< the controller has detected a fault
    std::uint8_t active_case = 0U;      ///< monitoring case in force, 0..kMaxActiveCase
    bool reduced_speed = false;         ///< reduced speed requested (when no stop)
    std::uint16_t zone_intrusion = 0U;  ///< bit z: zone z intruded (z < zone_count)
    std::uint16_t zone_unseen = 0U;     ///< bit z: zone z cannot be seen (z < zone_count)
    std::uint8_t zone_count = 0U;       ///< configured zones, 0..kMaxZonesInFrame
    /// Field-wise equality.
    friend constexpr bool operator==(const SafetyMessage& a, const SafetyMessage& b) noexcept {
        return a.protective_stop == b.protective_stop && a.warning == b.warning && a.fault == b.fault &&
               a.active_case == b.active_case && a.reduced_speed == b.reduced_speed &&
               a.zone_intrusion == b.zone_intrusion && a.zone_unseen == b.zone_unseen && a.zone_count == b.zone_count;
    }
    /// Field-wise inequality.
    friend constexpr bool operator!=(const SafetyMessage& a, const SafetyMessage& b) noexcept { return !(a == b); }
};

/// Unit of the diagnostics frame's cycle times, in microseconds.
constexpr std::uint32_t kDiagnosticsTimeUnitUs = 100U;
/// Saturated cycle time value: 2047 means 204.7 ms or more.
constexpr std::uint16_t kDiagnosticsTimeSaturated = 2047U;

/// Content of the diagnostics frame (raw wire values).
struct DiagnosticsMessage {
    std::uint16_t cycle_time = 0U;      ///< last cycle, kDiagnosticsTimeUnitUs units, <= 2047
    std::uint16_t max_cycle_time = 0U;  ///< longest cycle, same units, <= 2047
    std::uint16_t active_faults = 0U;   ///< FaultCode bits, only kAssignedFaultBits
    std::uint8_t prior_crc_page = 0U;   ///< which byte of the prior CRC-32, 0..3
    std::uint8_t prior_crc_part = 0U;   ///< bits 8*page .. 8*page+7 of the prior CRC-32
    /// Field-wise equality.
    friend constexpr bool operator==(const DiagnosticsMessage& a, const DiagnosticsMessage& b) noexcept {
        return a.cycle_time == b.cycle_time && a.max_cycle_time == b.max_cycle_time &&
               a.active_faults == b.active_faults && a.prior_crc_page == b.prior_crc_page &&
               a.prior_crc_part == b.prior_crc_part;
    }
};

/// Microseconds to the diagnostics time unit: rounded up (never reports a
/// cycle shorter than it was), saturating at kDiagnosticsTimeSaturated.
[[nodiscard]] constexpr std::uint16_t diagnostics_time_saturating(std::uint64_t microseconds) noexcept {
    const std::uint64_t units = microseconds / kDiagnosticsTimeUnitUs +
                                ((microseconds % kDiagnosticsTimeUnitUs) != 0U ? 1U : 0U);
    return static_cast<std::uint16_t>(units > kDiagnosticsTimeSaturated ? kDiagnosticsTimeSaturated : units);
}

/// Byte @p page (0..3, a contract) of @p prior_crc: its bits 8*page .. 8*page+7.
[[nodiscard]] constexpr std::uint8_t prior_crc_part(std::uint32_t prior_crc, std::uint8_t page) noexcept {
    CG_ENFORCE(page < 4U, "the prior CRC has four pages");
    return static_cast<std::uint8_t>(prior_crc >> (8U * page));
}

/// Default CAN IDs (those in certification/cellguard.dbc): EN 50325-5's first
/// SRDO pair 0x101 / 0x102, diagnostics on 0x103, separation on 0x104.
constexpr std::uint32_t kDefaultSafetyCanId = 0x101U;
/// Default CAN ID of the diagnostics frame.
constexpr std::uint32_t kDefaultDiagnosticsCanId = 0x103U;
/// Default data ID of the safety frame.
constexpr std::uint16_t kDefaultSafetyDataId = 0x0C51U;
/// Default data ID of the diagnostics frame (distinguishable from the safety one in every mode).
constexpr std::uint16_t kDefaultDiagnosticsDataId = 0x0D52U;
/// Default CAN ID of the separation frame.
constexpr std::uint32_t kDefaultSeparationCanId = 0x104U;
/// Default data ID of the separation frame (distinguishable from the other two in every mode).
constexpr std::uint16_t kDefaultSeparationDataId = 0x0E53U;

/// Identifiers shared by the sender and the PLC-side receiver.
struct SafetyChannelConfig {
    std::uint32_t safety_can_id = kDefaultSafetyCanId;              ///< 11-bit; the inverted copy uses +1
    std::uint32_t diagnostics_can_id = kDefaultDiagnosticsCanId;    ///< 11-bit, differs from both safety IDs
    std::uint16_t safety_data_id = kDefaultSafetyDataId;            ///< E2E data ID of the safety frame
    std::uint16_t diagnostics_data_id = kDefaultDiagnosticsDataId;  ///< E2E data ID of the diagnostics frame
    E2eP01DataIdMode data_id_mode = E2eP01DataIdMode::kBoth;        ///< how the data IDs enter the CRC
    std::uint32_t separation_can_id = kDefaultSeparationCanId;      ///< 11-bit, differs from the other three
    std::uint16_t separation_data_id = kDefaultSeparationDataId;    ///< E2E data ID of the separation frame
};

/// Checks @p config: valid mode; 11-bit CAN IDs, safety_can_id + 1 included;
/// four distinct CAN IDs; data IDs valid for the mode and pairwise
/// distinguishable (e2e_p01_data_ids_distinguishable). kInvalidArgument if not.
[[nodiscard]] Status check_channel_config(const SafetyChannelConfig& config) noexcept;

/// CAN ID of the inverted copy of the safety frame.
[[nodiscard]] constexpr std::uint32_t inverted_can_id(const SafetyChannelConfig& config) noexcept {
    return config.safety_can_id + 1U;
}

/// Outcome of checking one received frame; checks run in this order.
enum class FrameCheck : std::uint8_t {
    kOk = 0,                 ///< every check passed
    kWrongCanId = 1,         ///< not the expected CAN ID
    kWrongLength = 2,        ///< DLC is not 8
    kWrongDataIdNibble = 3,  ///< kNibble mode: the explicit nibble is not the data ID's
    kWrongCrc = 4,           ///< CRC mismatch: corrupted data or a wrong (implicit) data ID
    kCounterOutOfRange = 5,  ///< counter is 15
    kMalformedContent = 6,   ///< reserved bits set, zone count > 16, zone bit beyond the count, unassigned fault
                             ///< bit, speed request 3
};
/// A short, static name for @p check (never nullptr).
[[nodiscard]] const char* to_string(FrameCheck check) noexcept;
/// The ErrorCode for a failed check: kCrcMismatch for kWrongCrc and
/// kWrongDataIdNibble, kTruncatedInput for kWrongLength, kMalformedInput otherwise.
[[nodiscard]] ErrorCode to_error_code(FrameCheck check) noexcept;

/// A decoded safety frame.
struct SafetyFrameContent {
    SafetyMessage message;      ///< the content
    std::uint8_t counter = 0U;  ///< its E2E counter, 0..14
};
/// A decoded diagnostics frame.
struct DiagnosticsFrameContent {
    DiagnosticsMessage message;  ///< the content
    std::uint8_t counter = 0U;   ///< its E2E counter, 0..14
};

/// The protected safety frame for @p message with counter @p counter.
/// kInvalidArgument when the config is invalid, the counter > 14, the zone
/// count > 16, a zone bit is set at or above the zone count, or the active case > 15.
[[nodiscard]] Result<CanFrame> encode_safety_frame(const SafetyMessage& message, std::uint8_t counter,
                                                   const SafetyChannelConfig& config) noexcept;
/// The inverted copy of @p frame: CAN ID + 1, same DLC, every data bit inverted.
[[nodiscard]] CanFrame inverted_copy(const CanFrame& frame) noexcept;
/// The protected diagnostics frame. kInvalidArgument when the config is
/// invalid, the counter > 14, a time > 2047, the page > 3, or an unassigned fault bit is set.
[[nodiscard]] Result<CanFrame> encode_diagnostics_frame(const DiagnosticsMessage& message, std::uint8_t counter,
                                                        const SafetyChannelConfig& config) noexcept;

/// Checks @p frame as a safety frame of @p config field by field and, on kOk,
/// writes its content to @p out (untouched otherwise). @p config must be valid (contract).
[[nodiscard]] FrameCheck check_safety_frame(const CanFrame& frame, const SafetyChannelConfig& config,
                                            SafetyFrameContent& out) noexcept;
/// Same as check_safety_frame, as a Result (error from to_error_code).
[[nodiscard]] Result<SafetyFrameContent> decode_safety_frame(const CanFrame& frame,
                                                             const SafetyChannelConfig& config) noexcept;
/// Checks @p frame as a diagnostics frame of @p config; on kOk writes @p out.
[[nodiscard]] FrameCheck check_diagnostics_frame(const CanFrame& frame, const SafetyChannelConfig& config,
                                                 DiagnosticsFrameContent& out) noexcept;
/// Same as check_diagnostics_frame, as a Result.
[[nodiscard]] Result<DiagnosticsFrameContent> decode_diagnostics_frame(const CanFrame& frame,
                                                                       const SafetyChannelConfig& config) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_FRAME_HPP
