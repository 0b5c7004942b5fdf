// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file can_sender.hpp
/// Where CAN frames go: the interface a port's CAN driver implements (a
/// SocketCAN socket, a log file, a test), with the driver's own detail
/// faults for the diagnostics frame. A small interface header: a port
/// adapter compiles it with the frame type only.
#ifndef CELLGUARD_CAN_CAN_SENDER_HPP
#define CELLGUARD_CAN_CAN_SENDER_HPP

#include <cstdint>

#include "cellguard/can/can_frame.hpp"

namespace cellguard {

/// Where CAN frames go (a SocketCAN socket, a log file, a test).
class CanSender {
public:
    /// Sends @p frame; false when it could not be sent.
    virtual bool send(const CanFrame& frame) noexcept = 0;
    /// The driver's CAN detail faults now: FaultCode bits 9..14
    /// (kCanDetailFaultBits, safety_frame.hpp), e.g. bus-off or error
    /// passive. Asked once per cycle, before the cycle's frames are sent
    /// (CanSafetyOutput::publish); a driver may take in here what its
    /// transport reported since (error frames). Bits outside 9..14 are
    /// ignored. 0 for a sender without such details (the default).
    [[nodiscard]] virtual std::uint16_t detail_faults() noexcept { return 0U; }

protected:
    CanSender() = default;
    ~CanSender() = default;
    CanSender(const CanSender&) = default;
    CanSender& operator=(const CanSender&) = default;
    CanSender(CanSender&&) = default;
    CanSender& operator=(CanSender&&) = default;
};

}  // namespace cellguard

#endif  // CELLGUARD_CAN_CAN_SENDER_HPP
