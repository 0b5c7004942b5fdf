// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

const char* to_string(SpeedRequest request) noexcept {
    switch (request) {
        case SpeedRequest::kFull: return "FULL";
        case SpeedRequest::kReduced: return "REDUCED";
        case SpeedRequest::kProtectiveStop: return "STOP";
    }
    return "INVALID";
}

}  // namespace cellguard
