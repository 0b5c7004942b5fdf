// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/command_check.hpp"

namespace cellguard {

const char* to_string(CommandRefusal r) noexcept {
    switch (r) {
        case CommandRefusal::kNone: return "none";
        case CommandRefusal::kJointCountMismatch: return "joint count mismatch";
        case CommandRefusal::kInvalidRaw: return "invalid raw joint value";
        case CommandRefusal::kOutsideLimits: return "joint outside its limits";
        case CommandRefusal::kRobotIdMismatch: return "robot id mismatch";
        case CommandRefusal::kMissing: return "command missing";
        case CommandRefusal::kStale: return "command stale";
        case CommandRefusal::kUnknownCase: return "unknown monitoring case";
        case CommandRefusal::kUnknownSpeedClass: return "unknown speed class";
    }
    return "unknown refusal";
}

Result<CheckedCommand, CommandRefusal> check_command(const CommandInput& input, std::uint64_t now_us,
                                                     const CommandLimits& limits) noexcept {
    if (!input.valid) {
        return CommandRefusal::kMissing;
    }
    if (input.received_us > now_us || now_us - input.received_us > limits.max_age_us) {
        return CommandRefusal::kStale;
    }
    const RobotCommand& c = input.command;
    if (limits.cases == nullptr || !limits.cases->contains(c.monitoring_case)) {
        return CommandRefusal::kUnknownCase;
    }
    CheckedCommand out;
    out.monitoring_case = c.monitoring_case;
    out.speed_class = c.speed_class;
    if (limits.robot == nullptr) {
        if (c.joint_count != 0U) {
            return CommandRefusal::kJointCountMismatch;
        }
        return out;
    }
    if (c.speed_class >= limits.speed_classes || c.speed_class >= kSpeedClasses) {
        return CommandRefusal::kUnknownSpeedClass;
    }
    const Result<JointPositions, JointCheck> q = joint_positions(*limits.robot, limits.image_crc, c);
    if (!q.ok()) {
        return static_cast<CommandRefusal>(static_cast<std::uint8_t>(q.error()));
    }
    out.joints = q.value();
    return out;
}

}  // namespace cellguard
