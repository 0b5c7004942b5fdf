// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file faults.hpp
/// The fault codes of the safety logic: what each detected fault is, its bit
/// in a fault mask, and which faults only a re-initialisation clears. A
/// small interface header: the CAN layer and the PLC receiver use it without
/// compiling the grid or the controller.
#ifndef CELLGUARD_SAFETY_FAULTS_HPP
#define CELLGUARD_SAFETY_FAULTS_HPP

#include <cstdint>

namespace cellguard {

/// Fault codes: bit positions in a fault mask. Values appear on CAN and in
/// the certification pack: append only.
enum class Fault : std::uint8_t {
    kSensorStale = 0,        ///< a sensor frame older than its age limit
    kSensorMissing = 1,      ///< a configured sensor delivered no frame
    kFrameInconsistent = 2,  ///< a frame failed its checks (description, size)
    kPriorCheckFailed = 3,   ///< the prior's CRC or geometry check failed (non-recoverable)
    kCycleOverrun = 4,       ///< a cycle exceeded its time budget
    kCanError = 5,           ///< the CAN output failed (bus-off, error-passive, send failure)
    kInternalCheck = 6,      ///< an internal consistency check failed (non-recoverable)
    kClockFault = 7,         ///< the monotonic clock did not advance (non-recoverable)
    kZoneEvaluation = 8,     ///< zone evaluation could not run
    kCommandInvalid = 9,     ///< the PLC's command is missing, late, corrupt or does not fit the cell
};

/// Number of defined faults.
constexpr std::uint8_t kFaultCount = 10U;

/// The mask bit of @p fault.
constexpr std::uint32_t fault_bit(Fault fault) noexcept { return 1U << static_cast<std::uint32_t>(fault); }

/// Faults that only a re-initialisation clears.
constexpr std::uint32_t kNonRecoverableFaults = fault_bit(Fault::kPriorCheckFailed) | fault_bit(Fault::kInternalCheck) |
                                                fault_bit(Fault::kClockFault);
/// All defined fault bits.
constexpr std::uint32_t kAllFaults = (1U << kFaultCount) - 1U;

/// Static name of a fault.
[[nodiscard]] const char* to_string(Fault fault) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_FAULTS_HPP
