// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/faults.hpp"

namespace cellguard {

const char* to_string(Fault fault) noexcept {
    switch (fault) {
        case Fault::kSensorStale: return "sensor stale";
        case Fault::kSensorMissing: return "sensor missing";
        case Fault::kFrameInconsistent: return "frame inconsistent";
        case Fault::kPriorCheckFailed: return "prior check failed";
        case Fault::kCycleOverrun: return "cycle overrun";
        case Fault::kCanError: return "CAN error";
        case Fault::kInternalCheck: return "internal check failed";
        case Fault::kClockFault: return "clock fault";
        case Fault::kZoneEvaluation: return "zone evaluation failed";
        case Fault::kCommandInvalid: return "command invalid";
    }
    return "unknown fault";
}

}  // namespace cellguard
