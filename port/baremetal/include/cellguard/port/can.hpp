// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file can.hpp
/// A CAN backend for bring-up without a bus: every frame is printed through
/// semihosting as "can 0x101 [8] xx xx xx xx xx xx xx xx" (the format of
/// the host's cellguard-firmware-digest). Sending always succeeds.
#ifndef CELLGUARD_PORT_CAN_HPP
#define CELLGUARD_PORT_CAN_HPP

#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/can_sender.hpp"

namespace cellguard::baremetal {

/// CanSender printing frames via semihosting.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class SemihostingCanSender final : public CanSender {
public:
    /// Prints @p frame (at most 8 data bytes); returns true.
    bool send(const CanFrame& frame) noexcept override;
};

/// Formats @p frame as one line (with newline) into @p out: the text that send() prints.
void format_can_frame(const CanFrame& frame, char (&out)[48]) noexcept;

}  // namespace cellguard::baremetal

#endif  // CELLGUARD_PORT_CAN_HPP
