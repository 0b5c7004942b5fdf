// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the PLC-side command sender: six frames per sample in the order A, A', B, B', C, C', one counter per sample advancing by one and wrapping, a command that is not well formed refused without advancing, and so is a linked sample whose link fields or channel are invalid.
#include <doctest/doctest.h>

#include <cstdint>

#include "alloc_counter.hpp"
#include "cellguard/can/command_receiver.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

RobotCommand seven_axis(std::int16_t base) {
    RobotCommand c;
    c.monitoring_case = 15U;
    c.speed_class = 3U;
    c.joint_count = 7U;
    c.robot_id = 0xA5A5U;
    for (std::size_t j = 0U; j < kMaxCommandJoints; ++j) {
        c.joint_raw[j] = static_cast<std::int16_t>(base + static_cast<std::int16_t>(j));
    }
    return c;
}

bool same(const CanFrame& a, const CanFrame& b) {
    bool equal = a.id == b.id && a.dlc == b.dlc;
    for (std::size_t k = 0U; k < 8U; ++k) {
        equal = equal && a.data[k] == b.data[k];
    }
    return equal;
}

}  // namespace

// verifies: SR-CMD-007
TEST_CASE("plc command sender: six frames in the order A, A', B, B', C, C', all with the sample's counter") {
    PlcCommandSender sender{CommandChannelConfig{}};
    CHECK(sender.counter() == 0U);
    const CommandFrames s = sender.next_sample(seven_axis(100)).value();
    const std::uint32_t ids[] = {0x0C1U, 0x0C2U, 0x0C3U, 0x0C4U, 0x0C5U, 0x0C6U};
    for (std::size_t i = 0U; i < kCommandFramesPerSample; ++i) {
        CAPTURE(i);
        CHECK(s.frame[i].id == ids[i]);
        CHECK(s.frame[i].dlc == 8U);
        const std::uint32_t counter = get_signal(s.frame[i], command_layout::kCounter);
        CHECK(counter == (i % 2U == 0U ? 0U : 15U));  // a copy carries the counter inverted
    }
    for (std::size_t p = 0U; p < kCommandParts; ++p) {
        CHECK(same(
            s.frame[2U * p],
            encode_command_part(seven_axis(100), static_cast<CommandPart>(p), 0U, CommandChannelConfig{}).value()));
        CHECK(same(s.frame[2U * p + 1U], inverted_copy(s.frame[2U * p])));
    }
    CHECK(sender.counter() == 1U);
}

// verifies: SR-CMD-007
TEST_CASE("plc command sender: the counter advances once per sample and wraps 14 -> 0, the receiver accepts each") {
    CommandReceiverConfig rc;
    rc.max_delta_counter = 1U;  // no sample may be lost
    rc.link.enabled = false;    // the protocol 0.1 checks; the session link's tests set up both sides
    CommandReceiver receiver(rc);
    PlcCommandSender sender(rc.channel);
    std::uint64_t now = 5000000U;
    std::size_t allocations = 0U;  // of the sender and the receiver only (doctest's own bookkeeping may allocate)
    for (int k = 0; k < 32; ++k) {
        CAPTURE(k);
        CHECK(sender.counter() == static_cast<std::uint8_t>(k % 15));
        const RobotCommand command = seven_axis(static_cast<std::int16_t>(k * 10));
        const test::AllocationScope scope;
        const Result<CommandFrames> s = sender.next_sample(command);
        for (std::size_t i = 0U; s.ok() && i < kCommandFramesPerSample; ++i) {
            now += 250U;
            (void)receiver.on_frame(s.value().frame[i], now);
        }
        const CommandPoll p = receiver.poll(now);
        allocations += scope.allocations();
        REQUIRE(s.ok());
        CHECK(p.status.valid == (k >= 2));
        if (k >= 2) {
            CHECK(p.input.command == seven_axis(static_cast<std::int16_t>(k * 10)));
            CHECK(p.input.counter == static_cast<std::uint8_t>(k % 15));
        }
        now += 40000U;
    }
    CHECK(allocations == 0U);
    CHECK(receiver.status().fault_events == 0U);
}

// verifies: SR-CMD-007
TEST_CASE("plc command sender: a command that is not well formed is refused and the counter stays") {
    PlcCommandSender sender{CommandChannelConfig{}};
    (void)sender.next_sample(seven_axis(0));
    RobotCommand bad = seven_axis(0);
    bad.joint_raw[4] = kJointRawInvalid;
    CHECK(sender.next_sample(bad).error() == ErrorCode::kInvalidArgument);
    bad = seven_axis(0);
    bad.joint_count = 3U;  // joints 3..6 are set
    CHECK(sender.next_sample(bad).error() == ErrorCode::kInvalidArgument);
    bad = seven_axis(0);
    bad.monitoring_case = 16U;
    CHECK_FALSE(sender.next_sample(bad).ok());
    CHECK(sender.counter() == 1U);
    CommandChannelConfig invalid;
    invalid.base_can_id = 0x800U;
    CHECK(PlcCommandSender::check_config(invalid).error() == ErrorCode::kInvalidArgument);
    CHECK(test::violates_contract([&] { const PlcCommandSender s(invalid); }));
}

// verifies: SR-CMD-007
TEST_CASE(
    "plc command sender: a linked sample with a bad command, link fields or link channel is refused, the counter stays") {
    PlcCommandSender sender{CommandChannelConfig{}};
    LinkFields link;
    link.sequence = 1U;
    link.session = 7U;
    const LinkedCommandFrames first = sender.next_sample(seven_axis(0), link, kDefaultPlcLinkChannel).value();
    CHECK(first.link.id == kDefaultPlcLinkChannel.can_id);
    CHECK(sender.counter() == 1U);

    RobotCommand bad = seven_axis(0);
    bad.joint_raw[2] = kJointRawInvalid;  // the command itself does not encode
    CHECK(sender.next_sample(bad, link, kDefaultPlcLinkChannel).error() == ErrorCode::kInvalidArgument);
    LinkFields no_sequence = link;
    no_sequence.sequence = 0U;  // the link frame does not encode: sequence 0 is never sent
    CHECK(sender.next_sample(seven_axis(0), no_sequence, kDefaultPlcLinkChannel).error() ==
          ErrorCode::kInvalidArgument);
    LinkFields no_session = link;
    no_session.session = 0U;
    CHECK(sender.next_sample(seven_axis(0), no_session, kDefaultPlcLinkChannel).error() == ErrorCode::kInvalidArgument);
    LinkChannel wide = kDefaultPlcLinkChannel;
    wide.can_id = 0x800U;  // not an 11-bit ID
    CHECK(sender.next_sample(seven_axis(0), link, wide).error() == ErrorCode::kInvalidArgument);
    CHECK(sender.counter() == 1U);  // no refused sample advanced it

    link.sequence = 2U;
    const LinkedCommandFrames second = sender.next_sample(seven_axis(0), link, kDefaultPlcLinkChannel).value();
    CHECK(get_signal(second.sample.frame[0], command_layout::kCounter) == 1U);
    CHECK(sender.counter() == 2U);
}
