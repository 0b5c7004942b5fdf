// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the CAN safety output: each cycle's safety frame, inverted copy, diagnostics frame and (with a robot) separation frame decode, the case and speed request reach the safety frame, the PLC receiver accepts a run of cycles across the counter wrap, the stop bit follows the report, fault bits and CRC pages are carried, too many zones are refused, a failing send is reported.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_output.hpp"
#include "cellguard/can/separation_frame.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

/// Records every frame; fails the send with index fail_at (counting from 0),
/// if set; reports the detail faults `details` and counts the queries.
class RecordingSender final : public CanSender {
public:
    bool send(const CanFrame& frame) noexcept override {
        const bool ok = static_cast<int>(frames.size()) != fail_at;
        frames.push_back(frame);
        return ok;
    }
    std::uint16_t detail_faults() noexcept override {
        ++detail_queries;
        return details;
    }
    std::vector<CanFrame> frames;
    int fail_at = -1;
    std::uint16_t details = 0U;
    int detail_queries = 0;
};

/// A sender with only send(): the interface's default detail faults.
class PlainSender final : public CanSender {
public:
    bool send(const CanFrame& frame) noexcept override {
        frames.push_back(frame);
        return true;
    }
    std::vector<CanFrame> frames;
};

SafetyOutputConfig output_config(std::uint8_t zones = 2U) {
    SafetyOutputConfig c;
    c.zone_count = zones;
    c.prior_crc = 0xCAFEF00DU;
    c.session_link = false;  // the protocol 0.1 checks; the session link's tests set up both sides
    return c;
}

CycleReport report_with(bool stop, std::uint32_t intruded, std::uint32_t latched) {
    CycleReport r;
    r.safety.stop_requested = stop;
    r.safety.warning = (intruded & 2U) != 0U;
    r.safety.intruded_mask = intruded;
    r.safety.latched_faults = latched;
    r.timing.total_us = 1234U;
    r.worst.total_us = 4567U;
    return r;
}

}  // namespace

// verifies: SR-CAN-006
TEST_CASE(
    "safety output: one cycle sends the safety frame, its inverted copy and the diagnostics frame, in that order") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    REQUIRE(out.status().ok());
    REQUIRE(out.publish(report_with(true, 1U, 0U)));
    REQUIRE(sender.frames.size() == 3U);
    const SafetyFrameContent s = decode_safety_frame(sender.frames[0], SafetyChannelConfig{}).value();
    CHECK(s.counter == 0U);
    CHECK(s.message.protective_stop);
    CHECK(s.message.zone_intrusion == 1U);
    CHECK(s.message.zone_count == 2U);
    CHECK_FALSE(s.message.fault);
    CHECK(sender.frames[1].id == kDefaultSafetyCanId + 1U);
    for (std::size_t k = 0U; k < 8U; ++k) {
        CHECK(sender.frames[1].data[k] == static_cast<std::uint8_t>(~sender.frames[0].data[k]));
    }
    const DiagnosticsFrameContent d = decode_diagnostics_frame(sender.frames[2], SafetyChannelConfig{}).value();
    CHECK(d.counter == 0U);
    CHECK(d.message.cycle_time == 13U);  // 1234 us, rounded up to 100 us units
    CHECK(d.message.max_cycle_time == 46U);
    CHECK(d.message.prior_crc_page == 0U);
    CHECK(d.message.prior_crc_part == 0x0DU);
}

// verifies: SR-CAN-006, SR-CAN-009
TEST_CASE(
    "safety output: the PLC receiver accepts a run of cycles across the counter wrap and the stop bit follows the report") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    PlcReceiverConfig rc;
    rc.expected_zone_count = 2U;
    rc.link.enabled = false;  // the protocol 0.1 checks; the session link's tests set up both sides
    PlcReceiver plc(rc);
    std::uint64_t now = 1000000U;
    std::uint32_t prior_crc = 0U;
    for (int cycle = 0; cycle < 40; ++cycle) {  // 40 cycles: the counters wrap twice
        const bool stop = (cycle / 7) % 2 == 1;
        const std::size_t first = sender.frames.size();
        REQUIRE(out.publish(report_with(stop, stop ? 1U : 0U, 0U)));
        REQUIRE(sender.frames.size() == first + 3U);
        now += 20000U;
        (void)plc.on_frame(sender.frames[first], now);
        const ReceiverStatus st = plc.on_frame(sender.frames[first + 1U], now + 500U);
        (void)plc.on_frame(sender.frames[first + 2U], now + 600U);  // other ID: ignored by the receiver
        const SafetyFrameContent s = decode_safety_frame(sender.frames[first], SafetyChannelConfig{}).value();
        CHECK(s.counter == cycle % 15);
        CHECK(s.message.protective_stop == stop);
        const DiagnosticsFrameContent d =
            decode_diagnostics_frame(sender.frames[first + 2U], SafetyChannelConfig{}).value();
        CHECK(d.counter == cycle % 15);
        CHECK(d.message.prior_crc_page == cycle % 4);
        prior_crc |= static_cast<std::uint32_t>(d.message.prior_crc_part) << (8U * d.message.prior_crc_page);
        if (cycle >= 3) {  // after the reference pair and two recovery pairs
            CHECK(st.communication_valid);
            CHECK(st.fault == ReceiverFault::kNone);
            CHECK(st.stop_requested == stop);
        }
    }
    CHECK(prior_crc == 0xCAFEF00DU);                  // the four pages give the whole CRC
    CHECK(plc.poll(now + 1000U).fault_events == 0U);  // no fault detected in the whole run
}

// verifies: SR-CAN-005
TEST_CASE("safety output: latched faults go to ActiveFaults bits 0..8 and the CAN details to bits 9..14") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    // The sender's own details; bits outside 9..14 are not sent.
    sender.details = static_cast<std::uint16_t>(fault_bit(FaultCode::kCanBusOff) | 0x8001U);
    REQUIRE(out.publish(report_with(true, 0U, fault_bit(Fault::kSensorStale) | fault_bit(Fault::kCanError))));
    CHECK(sender.detail_queries == 1);  // once per cycle
    const DiagnosticsFrameContent d = decode_diagnostics_frame(sender.frames[2], SafetyChannelConfig{}).value();
    CHECK(d.message.active_faults ==
          (fault_bit(FaultCode::kSensorStale) | fault_bit(FaultCode::kCanError) | fault_bit(FaultCode::kCanBusOff)));
    const SafetyFrameContent s = decode_safety_frame(sender.frames[0], SafetyChannelConfig{}).value();
    CHECK(s.message.fault);
    CHECK(s.message.protective_stop);
    // The next cycle carries what the sender reports then: the bus-off has cleared.
    sender.details = 0U;
    REQUIRE(out.publish(report_with(false, 0U, 0U)));
    CHECK(sender.detail_queries == 2);
    CHECK(decode_diagnostics_frame(sender.frames[5], SafetyChannelConfig{}).value().message.active_faults == 0U);
}

// verifies: SR-CAN-005
TEST_CASE("safety output: a sender without detail faults leaves bits 9..14 clear") {
    PlainSender sender;
    CanSafetyOutput out(output_config(), sender);
    REQUIRE(out.publish(report_with(false, 0U, fault_bit(Fault::kCanError))));
    const DiagnosticsFrameContent d = decode_diagnostics_frame(sender.frames[2], SafetyChannelConfig{}).value();
    CHECK(d.message.active_faults == fault_bit(FaultCode::kCanError));
}

// verifies: SR-CAN-006
TEST_CASE("safety output: zone bits above the zone count are not sent") {
    const SafetyMessage m = safety_message(report_with(false, 0xFFFFFFFFU, 0U).safety, 3U);
    CHECK(m.zone_intrusion == 0x7U);
    CHECK(m.zone_count == 3U);
    CHECK(safety_message(report_with(false, 0xFFFFFFFFU, 0U).safety, 16U).zone_intrusion == 0xFFFFU);
}

// verifies: SR-CAN-006
TEST_CASE("safety output: more than 16 zones or a bad channel config is refused and every publish fails") {
    RecordingSender sender;
    CHECK(check_safety_output_config(output_config(16U)).ok());
    CanSafetyOutput too_many(output_config(17U), sender);
    CHECK(too_many.status().error() == ErrorCode::kCapacityExceeded);
    CHECK_FALSE(too_many.publish(report_with(false, 0U, 0U)));
    CHECK(sender.frames.empty());
    SafetyOutputConfig bad = output_config();
    bad.channel.diagnostics_can_id = bad.channel.safety_can_id + 1U;  // collides with the inverted copy
    CanSafetyOutput clash(bad, sender);
    CHECK(clash.status().error() == ErrorCode::kInvalidArgument);
    CHECK_FALSE(clash.publish(report_with(false, 0U, 0U)));
    CHECK(sender.frames.empty());
}

// verifies: SR-CAN-006
TEST_CASE("safety output: a failing send makes publish return false and the counters still advance") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    sender.fail_at = 1;  // the inverted copy of the first cycle
    CHECK_FALSE(out.publish(report_with(false, 0U, 0U)));
    CHECK(sender.frames.size() == 2U);  // stopped after the failed send
    CHECK(out.encoder().safety_counter() == 1U);
    CHECK(out.publish(report_with(false, 0U, 0U)));
    CHECK(decode_safety_frame(sender.frames[2], SafetyChannelConfig{}).value().counter == 1U);
    sender.fail_at = 7;  // the diagnostics frame of the third cycle
    CHECK_FALSE(out.publish(report_with(false, 0U, 0U)));
}

namespace {

CycleReport robot_report(SpeedRequest request, std::uint8_t active_case, std::uint8_t command_counter) {
    CycleReport r = report_with(request == SpeedRequest::kProtectiveStop, 0U, 0U);
    r.robot.configured = true;
    r.robot.active_case = active_case;
    r.robot.command_valid = true;
    r.robot.command_counter = command_counter;
    r.robot.speed_request = request;
    r.robot.distance_mm = 812U;
    r.robot.required_mm = 640U;
    return r;
}

}  // namespace

// verifies: SR-CMD-008
TEST_CASE("safety output: with a robot, the separation frame follows the diagnostics frame every cycle") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    PlcReceiverConfig rc;
    rc.expected_zone_count = 2U;
    rc.link.enabled = false;  // the protocol 0.1 checks; the session link's tests set up both sides
    PlcReceiver plc(rc);
    std::uint64_t now = 1000000U;
    const SpeedRequest requests[] = {SpeedRequest::kFull, SpeedRequest::kReduced, SpeedRequest::kProtectiveStop};
    for (int cycle = 0; cycle < 20; ++cycle) {
        const SpeedRequest request = requests[(cycle / 4) % 3];
        const auto active_case = static_cast<std::uint8_t>(cycle % 16);
        const std::size_t first = sender.frames.size();
        REQUIRE(out.publish(robot_report(request, active_case, static_cast<std::uint8_t>((cycle + 3) % 15))));
        REQUIRE(sender.frames.size() == first + 4U);
        CHECK(out.last_frames().has_separation);
        const SeparationFrameContent sep =
            decode_separation_frame(sender.frames[first + 3U], SafetyChannelConfig{}).value();
        CHECK(sep.counter == cycle % 15);
        CHECK(sep.message.distance_mm == 812U);
        CHECK(sep.message.required_mm == 640U);
        CHECK(sep.message.active_case == active_case);
        CHECK(sep.message.speed_request == request);
        CHECK(sep.message.command_valid);
        CHECK(sep.message.command_counter == (cycle + 3) % 15);
        now += 20000U;
        (void)plc.on_frame(sender.frames[first], now);
        const ReceiverStatus st = plc.on_frame(sender.frames[first + 1U], now + 500U);
        (void)plc.on_frame(sender.frames[first + 3U], now + 700U);  // other ID: ignored by the receiver
        if (cycle >= 3) {
            CHECK(st.communication_valid);
            CHECK(st.stop_requested == (request == SpeedRequest::kProtectiveStop));
            CHECK(st.message.reduced_speed == (request == SpeedRequest::kReduced));
            CHECK(st.message.active_case == active_case);
        }
    }
    CHECK(out.encoder().separation_counter() == 20U % 15U);
}

// verifies: SR-CMD-008
TEST_CASE("safety output: without a robot, three frames as before: case 0, no reduced speed, no separation frame") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    REQUIRE(out.publish(report_with(false, 0U, 0U)));  // RobotReport's defaults: not configured, case 0, full
    CHECK(sender.frames.size() == 3U);
    CHECK_FALSE(out.last_frames().has_separation);
    const SafetyMessage m = decode_safety_frame(sender.frames[0], SafetyChannelConfig{}).value().message;
    CHECK(m.active_case == 0U);
    CHECK_FALSE(m.reduced_speed);
    CHECK(out.encoder().separation_counter() == 0U);
}

// verifies: SR-CMD-008
TEST_CASE("safety output: the robot's speed request sets the stop and reduced bits, stop wins, a send failure shows") {
    const SafetyOutputs clear = report_with(false, 0U, 0U).safety;
    RobotReport robot;
    robot.configured = true;
    robot.active_case = 12U;
    robot.speed_request = SpeedRequest::kReduced;
    SafetyMessage m = safety_message(clear, robot, 2U);
    CHECK_FALSE(m.protective_stop);
    CHECK(m.reduced_speed);
    CHECK(m.active_case == 12U);
    robot.speed_request = SpeedRequest::kProtectiveStop;
    m = safety_message(clear, robot, 2U);
    CHECK(m.protective_stop);  // even if the safety outputs did not ask for it
    CHECK_FALSE(m.reduced_speed);
    robot.speed_request = SpeedRequest::kFull;
    CHECK_FALSE(safety_message(clear, robot, 2U).protective_stop);
    robot.speed_request = static_cast<SpeedRequest>(7);  // unknown: sent as a stop in the separation frame
    CHECK(separation_message(robot).speed_request == SpeedRequest::kProtectiveStop);
    robot.active_case = 16U;
    CHECK(test::violates_contract([&] { (void)safety_message(clear, robot, 2U); }));

    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    sender.fail_at = 3;  // the separation frame of the first cycle
    CHECK_FALSE(out.publish(robot_report(SpeedRequest::kFull, 0U, 0U)));
    CHECK(sender.frames.size() == 4U);
    CHECK(out.encoder().separation_counter() == 1U);
}

// verifies: SR-CAN-006
TEST_CASE("safety output: more than 16 zones, case 16, counter 15 or an unchecked config are contract violations") {
    const SafetyOutputs clear = report_with(false, 0U, 0U).safety;
    CHECK_FALSE(test::violates_contract([&] { (void)safety_message(clear, 16U); }));
    CHECK(test::violates_contract([&] { (void)safety_message(clear, 17U); }));
    RobotReport robot;
    robot.active_case = 15U;
    robot.command_counter = 14U;
    CHECK_FALSE(test::violates_contract([&] { (void)separation_message(robot); }));
    robot.active_case = 16U;
    CHECK(test::violates_contract([&] { (void)separation_message(robot); }));
    robot.active_case = 15U;
    robot.command_counter = 15U;
    CHECK(test::violates_contract([&] { (void)separation_message(robot); }));
    CHECK_FALSE(test::violates_contract([&] { const CycleFrameEncoder ok_encoder(output_config(16U)); }));
    CHECK(test::violates_contract([&] { const CycleFrameEncoder too_many(output_config(17U)); }));
}

// verifies: SR-CAN-001
TEST_CASE(
    "safety output: a failing send of the safety frame stops the cycle before its copy and the diagnostics frame") {
    RecordingSender sender;
    CanSafetyOutput out(output_config(), sender);
    REQUIRE(out.status().ok());
    sender.fail_at = 0;  // the first frame of the first cycle
    CHECK_FALSE(out.publish(report_with(false, 0U, 0U)));
    REQUIRE(sender.frames.size() == 1U);
    CHECK(sender.frames[0].id == kDefaultSafetyCanId);
    CHECK(out.encoder().safety_counter() == 1U);
}

// verifies: SR-CAN-006, SR-CAN-014
TEST_CASE("safety output: with the session link, a failing send of the link frame stops the cycle before diagnostics") {
    RecordingSender sender;
    SafetyOutputConfig c = output_config();
    c.session_link = true;
    LinkEndpoint link(controller_link_config());
    CanSafetyOutput out(c, sender, &link);
    REQUIRE(out.status().ok());
    sender.fail_at = 2;  // safety frame, inverted copy, then the link frame
    CHECK_FALSE(out.publish(report_with(false, 0U, 0U)));
    REQUIRE(sender.frames.size() == 3U);  // no diagnostics frame after the failed send
    CHECK(sender.frames[2].id == link.config().own.can_id);
    CHECK(link.sequence() == 1U);  // the link frame was made: its sequence is used
    CHECK(out.publish(report_with(false, 0U, 0U)));
    CHECK(sender.frames.size() == 7U);  // the next cycle: all four
}
