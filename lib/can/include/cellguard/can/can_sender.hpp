/// @file can_sender.hpp
/// Where CAN frames go: the interface a port's CAN driver implements (a
/// SocketCAN socket, a log file, a test). A small interface header: a port
/// adapter compiles it with the frame type only.
#ifndef CELLGUARD_CAN_CAN_SENDER_HPP
#define CELLGUARD_CAN_CAN_SENDER_HPP

#include "cellguard/can/can_frame.hpp"

namespace cellguard {

/// Where CAN frames go (a SocketCAN socket, a log file, a test).
class CanSender {
public:
    /// Sends @p frame; false when it could not be sent.
    virtual bool send(const CanFrame& frame) noexcept = 0;

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
