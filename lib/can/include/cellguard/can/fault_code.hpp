// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file fault_code.hpp
/// The fault codes of the diagnostics frame's ActiveFaults bitmask and how
/// the safety logic's Fault bits map onto them (wire_fault_bits). Split from
/// safety_frame.hpp, which includes it.
#ifndef CELLGUARD_CAN_FAULT_CODE_HPP
#define CELLGUARD_CAN_FAULT_CODE_HPP

#include <cstdint>

#include "cellguard/safety/faults.hpp"

namespace cellguard {

/// Fault codes of the diagnostics frame's ActiveFaults bitmask: bit n is code n.
/// Codes 0..8 are the safety logic's Fault bits (safety_logic.hpp) unchanged;
/// codes 9..14 detail the CAN port's faults (all of which the safety logic
/// sees as Fault::kCanError); code 15 is the safety logic's Fault 9
/// (kCommandInvalid), added after the CAN details: wire_fault_bits maps.
enum class FaultCode : std::uint8_t {
    kSensorStale = 0,            ///< Fault::kSensorStale: a sensor frame older than its age limit
    kSensorMissing = 1,          ///< Fault::kSensorMissing: a configured sensor delivered no frame
    kFrameInconsistent = 2,      ///< Fault::kFrameInconsistent: a frame failed its checks
    kPriorCheckFailed = 3,       ///< Fault::kPriorCheckFailed: the prior's CRC or geometry check failed
    kCycleOverrun = 4,           ///< Fault::kCycleOverrun: a cycle exceeded its time budget
    kCanError = 5,               ///< Fault::kCanError: the CAN output failed (details in bits 9..14)
    kInternalCheck = 6,          ///< Fault::kInternalCheck: an internal consistency check failed
    kClockFault = 7,             ///< Fault::kClockFault: the monotonic clock did not advance
    kZoneEvaluation = 8,         ///< Fault::kZoneEvaluation: zone evaluation could not run
    kCanTxBufferFull = 9,        ///< CAN send queue full (ENOBUFS / EAGAIN) after the bounded retries
    kCanNetworkDown = 10,        ///< CAN interface down (ENETDOWN and similar)
    kCanBusOff = 11,             ///< CAN controller is bus-off
    kCanErrorPassive = 12,       ///< CAN controller is error-passive
    kCanControllerProblem = 13,  ///< CAN controller overflow, TX timeout or missing acknowledgement
    kCanSendFailed = 14,         ///< any other CAN send error
    kCommandInvalid = 15,        ///< Fault::kCommandInvalid: the PLC's command is missing, late, corrupt or unfit
};
static_assert(static_cast<unsigned>(FaultCode::kSensorStale) == static_cast<unsigned>(Fault::kSensorStale) &&
                  static_cast<unsigned>(FaultCode::kSensorMissing) == static_cast<unsigned>(Fault::kSensorMissing) &&
                  static_cast<unsigned>(FaultCode::kFrameInconsistent) ==
                      static_cast<unsigned>(Fault::kFrameInconsistent) &&
                  static_cast<unsigned>(FaultCode::kPriorCheckFailed) ==
                      static_cast<unsigned>(Fault::kPriorCheckFailed) &&
                  static_cast<unsigned>(FaultCode::kCycleOverrun) == static_cast<unsigned>(Fault::kCycleOverrun) &&
                  static_cast<unsigned>(FaultCode::kCanError) == static_cast<unsigned>(Fault::kCanError) &&
                  static_cast<unsigned>(FaultCode::kInternalCheck) == static_cast<unsigned>(Fault::kInternalCheck) &&
                  static_cast<unsigned>(FaultCode::kClockFault) == static_cast<unsigned>(Fault::kClockFault) &&
                  static_cast<unsigned>(FaultCode::kZoneEvaluation) == static_cast<unsigned>(Fault::kZoneEvaluation),
              "ActiveFaults bits 0..8 are the safety logic's Fault bits unchanged");
static_assert(kFaultCount == 10U, "a new safety logic Fault needs a FaultCode and a place in wire_fault_bits");
/// The bit of @p code in ActiveFaults.
[[nodiscard]] constexpr std::uint16_t fault_bit(FaultCode code) noexcept {
    return static_cast<std::uint16_t>(1U << static_cast<unsigned>(code));
}
/// ActiveFaults bits that are safety logic Fault bits (0..8 and 15).
constexpr std::uint16_t kSafetyLogicFaultBits = 0x81FFU;
/// ActiveFaults bits that detail CAN port faults (9..14).
constexpr std::uint16_t kCanDetailFaultBits = 0x7E00U;
/// Bits with an assigned FaultCode: all 16.
constexpr std::uint16_t kAssignedFaultBits = 0xFFFFU;
/// The ActiveFaults bits of a safety logic fault mask @p faults (Fault bits):
/// Faults 0..8 on bits 0..8, Fault::kCommandInvalid (9) on bit 15.
[[nodiscard]] constexpr std::uint16_t wire_fault_bits(std::uint32_t faults) noexcept {
    return static_cast<std::uint16_t>((faults & 0x1FFU) |
                                      (((faults >> static_cast<unsigned>(Fault::kCommandInvalid)) & 1U) << 15U));
}
static_assert(wire_fault_bits(kAllFaults) == kSafetyLogicFaultBits, "every safety logic Fault has its wire bit");
static_assert((kSafetyLogicFaultBits | kCanDetailFaultBits) == kAssignedFaultBits &&
                  (kSafetyLogicFaultBits & kCanDetailFaultBits) == 0U,
              "safety logic bits and CAN detail bits partition the assigned bits");

}  // namespace cellguard

#endif  // CELLGUARD_CAN_FAULT_CODE_HPP
