// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: SocketCAN port without a CAN kernel: errno and error-frame classification, fault recovery, frame conversion, clean open errors.
#include <doctest/doctest.h>

#include <linux/can.h>
#include <linux/can/error.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cellguard/port/can.hpp"

using namespace cellguard;
using namespace cellguard::linux_port;

namespace {

can_frame error_frame(std::uint32_t error_class, std::uint8_t controller = 0U) {
    can_frame f{};
    f.can_id = CAN_ERR_FLAG | error_class;
    f.len = CAN_ERR_DLC;
    f.data[1] = controller;
    return f;
}

constexpr std::uint16_t bit(FaultCode c) { return fault_bit(c); }

}  // namespace

// verifies: SR-CAN-011
TEST_CASE("socketcan: a full queue is retried, a down interface and other errors are not") {
    CHECK(classify_send_errno(ENOBUFS) == SendErrnoClass::kRetry);
    CHECK(classify_send_errno(EAGAIN) == SendErrnoClass::kRetry);
    CHECK(classify_send_errno(ENETDOWN) == SendErrnoClass::kNetworkDown);
    CHECK(classify_send_errno(ENODEV) == SendErrnoClass::kNetworkDown);
    CHECK(classify_send_errno(ENXIO) == SendErrnoClass::kNetworkDown);
    CHECK(classify_send_errno(EINVAL) == SendErrnoClass::kFailed);
    CHECK(classify_send_errno(EMSGSIZE) == SendErrnoClass::kFailed);
    CHECK(classify_send_errno(0) == SendErrnoClass::kFailed);
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: error frames map to bus-off, error-passive and controller-problem faults") {
    CHECK(classify_error_frame(error_frame(CAN_ERR_BUSOFF)).raised_faults == bit(FaultCode::kCanBusOff));
    CHECK(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE)).raised_faults ==
          bit(FaultCode::kCanErrorPassive));
    CHECK(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_PASSIVE)).raised_faults ==
          bit(FaultCode::kCanErrorPassive));
    CHECK(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_OVERFLOW)).raised_faults ==
          bit(FaultCode::kCanControllerProblem));
    CHECK(classify_error_frame(error_frame(CAN_ERR_TX_TIMEOUT)).raised_faults == bit(FaultCode::kCanControllerProblem));
    CHECK(classify_error_frame(error_frame(CAN_ERR_ACK)).raised_faults == bit(FaultCode::kCanControllerProblem));
    CHECK(classify_error_frame(error_frame(CAN_ERR_TRX)).raised_faults == bit(FaultCode::kCanControllerProblem));
    const ErrorFrameReport warn = classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_WARNING));
    CHECK(warn.warning);
    CHECK(warn.raised_faults == 0U);  // the warning level is reported, not a fault
    CHECK(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE)).back_to_error_active);
    CHECK(classify_error_frame(error_frame(CAN_ERR_RESTARTED)).restarted);
    const ErrorFrameReport both = classify_error_frame(
        error_frame(CAN_ERR_BUSOFF | CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE));
    CHECK(both.raised_faults == (bit(FaultCode::kCanBusOff) | bit(FaultCode::kCanErrorPassive)));
    can_frame data{};
    data.can_id = CAN_ERR_BUSOFF;  // no CAN_ERR_FLAG: a data frame with ID 0x40, not an error
    CHECK(classify_error_frame(data).raised_faults == 0U);
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: bus-off clears only after a restart and then an accepted send") {
    CanFaultMonitor m;
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_BUSOFF)));
    CHECK(m.active_faults() == bit(FaultCode::kCanBusOff));
    m.on_send(SocketCanError::kOk);  // accepted, but the controller has not restarted
    CHECK(m.active_faults() == bit(FaultCode::kCanBusOff));
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_RESTARTED)));
    CHECK(m.active_faults() == bit(FaultCode::kCanBusOff));
    m.on_send(SocketCanError::kOk);
    CHECK(m.active_faults() == 0U);
    // A second bus-off forgets the earlier restart.
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_BUSOFF)));
    m.on_send(SocketCanError::kOk);
    CHECK(m.active_faults() == bit(FaultCode::kCanBusOff));
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: error-passive clears when the controller is error-active again or restarts") {
    CanFaultMonitor m;
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_PASSIVE)));
    m.on_send(SocketCanError::kOk);
    CHECK(m.active_faults() == bit(FaultCode::kCanErrorPassive));  // sends do not clear it
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE)));
    CHECK(m.active_faults() == 0U);
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE)));
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_RESTARTED)));
    CHECK(m.active_faults() == 0U);
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: send faults and controller problems clear with the next accepted send") {
    CanFaultMonitor m;
    m.on_send(SocketCanError::kTxBufferFull);
    m.on_send(SocketCanError::kNetworkDown);
    m.on_send(SocketCanError::kSendFailed);
    m.on_error_frame(classify_error_frame(error_frame(CAN_ERR_ACK)));
    CHECK(m.active_faults() == (bit(FaultCode::kCanTxBufferFull) | bit(FaultCode::kCanNetworkDown) |
                                bit(FaultCode::kCanSendFailed) | bit(FaultCode::kCanControllerProblem)));
    m.on_send(SocketCanError::kOk);
    CHECK(m.active_faults() == 0U);
    m.on_send(SocketCanError::kNotOpen);
    CHECK(m.active_faults() == bit(FaultCode::kCanSendFailed));
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: only standard-ID data frames up to 8 bytes pass between kernel and cellguard frames") {
    CanFrame out{};
    can_frame k{};
    k.can_id = 0x101U;
    k.len = 8U;
    for (std::uint8_t i = 0U; i < 8U; ++i) {
        k.data[i] = static_cast<std::uint8_t>(i + 1U);
    }
    REQUIRE(classify_kernel_frame(k, out) == KernelFrameKind::kData);
    CHECK(out.id == 0x101U);
    CHECK(out.dlc == 8U);
    CHECK(out.data[7] == 8U);
    can_frame eff = k;
    eff.can_id = 0x101U | CAN_EFF_FLAG;  // would alias the safety ID
    CHECK(classify_kernel_frame(eff, out) == KernelFrameKind::kIgnored);
    can_frame rtr = k;
    rtr.can_id = 0x101U | CAN_RTR_FLAG;
    CHECK(classify_kernel_frame(rtr, out) == KernelFrameKind::kIgnored);
    can_frame big = k;
    big.len = 9U;
    CHECK(classify_kernel_frame(big, out) == KernelFrameKind::kIgnored);
    CHECK(classify_kernel_frame(error_frame(CAN_ERR_BUSOFF), out) == KernelFrameKind::kError);

    const CanFrame f{0x102U, 3U, {9U, 8U, 7U, 0U, 0U, 0U, 0U, 0U}};
    can_frame back{};
    REQUIRE(to_kernel_frame(f, back).ok());
    CHECK(back.can_id == 0x102U);
    CHECK(back.len == 3U);
    CHECK(back.data[2] == 7U);
    CHECK(to_kernel_frame(CanFrame{0x800U, 8U, {}}, back).error == SocketCanError::kInvalidFrame);
    CHECK(to_kernel_frame(CanFrame{0x100U, 9U, {}}, back).error == SocketCanError::kInvalidFrame);
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: opening a missing interface, or with a bad name, is a clear error, not a crash") {
    SocketCan can;
    const SocketCanStatus missing = can.open("cgnosuchcan0");
    CHECK(missing.error == SocketCanError::kNoSuchInterface);
    CHECK_FALSE(can.is_open());
    CHECK(std::string(to_string(missing.error)) == "no such network interface");
    CHECK(can.open("").error == SocketCanError::kInvalidInterfaceName);
    CHECK(can.open(nullptr).error == SocketCanError::kInvalidInterfaceName);
    CHECK(can.open("an-interface-name-too-long").error == SocketCanError::kInvalidInterfaceName);
    // "lo" exists but is no CAN interface: without CAN support socket() fails, with it bind() does.
    const SocketCanStatus lo = can.open("lo");
    CHECK((lo.error == SocketCanError::kCanNotSupported || lo.error == SocketCanError::kNotACanInterface));
    CHECK(lo.sys_errno != 0);
    CHECK_FALSE(can.is_open());
}

// verifies: SR-CAN-011
TEST_CASE("socketcan: a closed socket refuses to send and receive, and the refusal is a send fault") {
    SocketCan can;
    const CanFrame f{0x101U, 8U, {}};
    CHECK(can.transmit(f).error == SocketCanError::kNotOpen);
    CHECK(can.active_faults() == fault_bit(FaultCode::kCanSendFailed));
    CanFrame out{};
    CHECK(can.receive(out) == SocketCan::ReceiveOutcome::kFailed);
    CHECK(can.last_receive_errno() == EBADF);
    SocketCan moved(std::move(can));
    CHECK_FALSE(moved.is_open());
    CHECK(std::string(to_string(static_cast<SocketCanError>(250))) == "unknown SocketCAN error");
}

// verifies: SR-CAN-011, SR-CAN-005
TEST_CASE("socketcan: as a CanSender it reports a refused send as false and its own fault as a detail fault") {
    SocketCan can;
    CanSender& sender = can;
    CHECK(sender.detail_faults() == 0U);  // closed, nothing sent yet: no fault, and no socket read
    CHECK_FALSE(sender.send(CanFrame{0x101U, 8U, {}}));
    CHECK(sender.detail_faults() == fault_bit(FaultCode::kCanSendFailed));
    CHECK((sender.detail_faults() & ~kCanDetailFaultBits) == 0U);
}

// verifies: SR-CAN-011
TEST_CASE(
    "socketcan: every fault the port raises is an ActiveFaults CAN detail bit (9..14), never a safety logic bit") {
    CanFaultMonitor m;
    m.on_send(SocketCanError::kTxBufferFull);
    m.on_send(SocketCanError::kNetworkDown);
    m.on_send(SocketCanError::kSendFailed);
    m.on_error_frame(
        classify_error_frame(error_frame(CAN_ERR_BUSOFF | CAN_ERR_CRTL | CAN_ERR_ACK, CAN_ERR_CRTL_TX_PASSIVE)));
    CHECK(m.active_faults() == kCanDetailFaultBits);
    CHECK((m.active_faults() & kSafetyLogicFaultBits) == 0U);
    CHECK(bit(FaultCode::kCanTxBufferFull) == 0x0200U);
    CHECK(bit(FaultCode::kCanSendFailed) == 0x4000U);
}

// verifies: SR-CMD-020
TEST_CASE("socketcan: a received frame's arrival is its kernel stamp on the monotonic clock, else the earliest bound") {
    // The frame arrived 3 ms before the read on the real-time clock; the read happened at 50 ms monotonic.
    ReceiveStamp stamp{true, 1'000'000'000'000LL, 1'000'003'000'000LL};
    bool from_kernel = false;
    CHECK(arrival_monotonic_us(stamp, 50'000U, 40'000U, &from_kernel) == 47'000U);
    CHECK(from_kernel);
    // Older than the last time the socket was seen empty: impossible, the real-time clock stepped; the bound.
    CHECK(arrival_monotonic_us(stamp, 50'000U, 48'000U, &from_kernel) == 48'000U);
    CHECK_FALSE(from_kernel);
    // Stamped after the read (the real-time clock stepped back): the bound, not the read time.
    ReceiveStamp future{true, 1'000'003'000'001LL, 1'000'003'000'000LL};
    CHECK(arrival_monotonic_us(future, 50'000U, 40'000U, &from_kernel) == 40'000U);
    CHECK_FALSE(from_kernel);
    // No kernel stamp: the bound.
    CHECK(arrival_monotonic_us(ReceiveStamp{}, 50'000U, 40'000U, &from_kernel) == 40'000U);
    CHECK_FALSE(from_kernel);
    // An age larger than the whole monotonic time does not wrap around.
    ReceiveStamp ancient{true, 1'000'000'000LL, 1'000'000'000'000LL};
    CHECK(arrival_monotonic_us(ancient, 50'000U, 0U, &from_kernel) == 0U);
    CHECK_FALSE(from_kernel);
    // A bound after the read (a caller's error) never moves the arrival past the read.
    CHECK(arrival_monotonic_us(ReceiveStamp{}, 50'000U, 60'000U) == 50'000U);
    // Arrival exactly at the bound and exactly at the read are accepted from the kernel.
    ReceiveStamp at_read{true, 5'000'000LL, 5'000'000LL};
    CHECK(arrival_monotonic_us(at_read, 50'000U, 40'000U, &from_kernel) == 50'000U);
    CHECK(from_kernel);
    ReceiveStamp at_bound{true, 5'000'000LL, 15'000'000LL};
    CHECK(arrival_monotonic_us(at_bound, 50'000U, 40'000U, &from_kernel) == 40'000U);
    CHECK(from_kernel);
}

// verifies: SR-CMD-020
TEST_CASE("socketcan: a closed socket's stamped receive fails and leaves no stamp") {
    SocketCan closed;
    CanFrame f{};
    ReceiveStamp stamp{true, 1, 2};
    CHECK(closed.receive(f, stamp) == SocketCan::ReceiveOutcome::kFailed);
    CHECK_FALSE(stamp.kernel);
}

// verifies: SR-CMD-020
TEST_CASE("socketcan: the read's two clocks are paired at one moment, the tightest of three tries") {
    // A monotonic clock whose first pair of readings straddles a 7 ms preemption, the second does not.
    std::vector<std::uint64_t> readings = {1000U, 8000U, 8010U, 8020U};
    std::size_t next = 0U;
    auto mono = [&]() { return readings[std::min(next++, readings.size() - 1U)]; };
    cellguard::linux_port::ReceiveStamp stamp;
    std::uint64_t gap = 0U;
    const std::uint64_t mid = cellguard::linux_port::pair_with_realtime(stamp, mono, 50U, &gap);
    CHECK(mid == 8015U);  // the second try's middle, not 4500 (the preempted pair's)
    CHECK(gap == 10U);
    CHECK(next == 4U);  // the tight pair ended the tries
    CHECK(stamp.read_realtime_ns > 0);
    // Every try preempted: the tightest pair is taken, after three tries.
    readings = {0U, 900U, 1000U, 1300U, 2000U, 2500U, 3000U};
    next = 0U;
    const std::uint64_t worst = cellguard::linux_port::pair_with_realtime(stamp, mono, 50U, &gap);
    CHECK(gap == 300U);
    CHECK(worst == 1150U);
    CHECK(next == 6U);
}
