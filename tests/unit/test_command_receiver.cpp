// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the controller's command receiver: missing, late, repeated, reordered, corrupted or inconsistent command frames give an invalid command with a reason; recovery; the good path across the counter wrap; no heap.
#include <doctest/doctest.h>

#include <cstdint>

#include "alloc_counter.hpp"
#include "cellguard/can/command_receiver.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "contract_capture.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {

constexpr std::uint64_t kPeriodUs = 50000U;  // the PLC's send period
constexpr std::uint64_t kGapUs = 300U;       // between two frames of a sample

CommandReceiverConfig receiver_config() {
    CommandReceiverConfig c;  // the defaults: SRVT 10 ms, window 20 ms, SCT 120 ms, delta 2, recovery 2
    c.link.enabled = false;   // the protocol 0.1 checks; the session link's tests set up both sides
    return c;
}

RobotCommand command(std::int16_t j0 = 1000) {
    RobotCommand c;
    c.monitoring_case = 3U;
    c.speed_class = 1U;
    c.joint_count = 6U;
    c.robot_id = 0x1234U;
    c.joint_raw[0] = j0;
    c.joint_raw[1] = -2000;
    c.joint_raw[5] = 31415;
    return c;
}

/// A PLC-side sender and the controller's receiver on one simulated bus.
struct Link {
    explicit Link(const CommandReceiverConfig& c = receiver_config()) : config(c), sender(c.channel), receiver(c) {}

    CommandFrames next(const RobotCommand& cmd = command()) { return sender.next_sample(cmd).value(); }
    CommandStatus deliver(const CanFrame& f, std::uint64_t at) {
        now = at;
        return receiver.on_frame(f, now);
    }
    /// Delivers frames [from, to) of @p s, the first at @p first_at, the others kGapUs apart.
    CommandStatus deliver_frames(const CommandFrames& s, std::size_t from, std::size_t to, std::uint64_t first_at) {
        CommandStatus st = receiver.status();
        for (std::size_t i = from; i < to; ++i) {
            st = deliver(s.frame[i], i == from ? first_at : now + kGapUs);
        }
        return st;
    }
    /// One period later, the six frames of the next sample.
    CommandStatus send_sample(const RobotCommand& cmd = command()) {
        return deliver_frames(next(cmd), 0U, 6U, now + kPeriodUs);
    }
    int bring_up() {
        int samples = 0;
        while (!receiver.poll(now).status.valid && samples < 100) {
            (void)send_sample();
            ++samples;
        }
        return samples;
    }
    CommandPoll poll_at(std::uint64_t at) {
        now = at;
        return receiver.poll(now);
    }

    CommandReceiverConfig config;
    PlcCommandSender sender;
    CommandReceiver receiver;
    std::uint64_t now = 1000000U;
};

void check_invalid(const CommandStatus& s, CommandFault reason) {
    CHECK_FALSE(s.valid);
    CHECK(s.fault == reason);
}

void check_invalid(Link& link, CommandFault reason) {
    const CommandPoll p = link.receiver.poll(link.now);
    check_invalid(p.status, reason);
    CHECK_FALSE(p.input.valid);
    CHECK(p.input.command == RobotCommand{});
}

}  // namespace

// verifies: SR-CMD-006
TEST_CASE("command receiver: it starts invalid and needs a reference sample plus the recovery samples") {
    Link link;
    check_invalid(link, CommandFault::kNoSampleYet);
    check_invalid(link.send_sample(), CommandFault::kNoSampleYet);  // the reference
    check_invalid(link.send_sample(), CommandFault::kNoSampleYet);  // recovery 1 of 2
    const CommandStatus s = link.send_sample(command(-77));         // recovery 2 of 2
    CHECK(s.valid);
    CHECK(s.fault == CommandFault::kNone);
    CHECK(s.good_samples == 3U);
    const CommandPoll p = link.receiver.poll(link.now);
    CHECK(p.input.valid);
    CHECK(p.input.command == command(-77));
    CHECK(p.input.counter == 2U);
    CHECK(p.input.received_us == link.now);
    CHECK(p.status.fault_events == 0U);
}

// verifies: SR-CMD-006
TEST_CASE("command receiver: forty samples across two counter wraps stay valid and carry each command") {
    Link link;
    REQUIRE(link.bring_up() == 3);
    for (int k = 0; k < 40; ++k) {
        const auto j0 = static_cast<std::int16_t>(k * 100 - 2000);
        CHECK(link.send_sample(command(j0)).valid);
        // polled at the controller's cycle start, somewhere before the next sample
        const CommandPoll p = link.poll_at(link.now + kPeriodUs - 1U);
        CHECK(p.status.valid);
        CHECK(p.input.command.joint_raw[0] == j0);
    }
    CHECK(link.receiver.status().fault_events == 0U);
}

// verifies: SR-CMD-004
TEST_CASE("command receiver: a missing part makes the command invalid") {
    SUBCASE("part B missing: C follows A's copy") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver_frames(s, 0U, 2U, link.now + kPeriodUs);
        check_invalid(link.deliver(s.frame[4], link.now + kGapUs), CommandFault::kPartOutOfOrder);
    }
    SUBCASE("part C missing: the next sample's A comes") {
        Link link;
        (void)link.bring_up();
        (void)link.deliver_frames(link.next(), 0U, 4U, link.now + kPeriodUs);
        CHECK(link.receiver.status().valid);  // the last good sample is still recent
        check_invalid(link.deliver(link.next().frame[0], link.now + kPeriodUs), CommandFault::kSampleIncomplete);
    }
    SUBCASE("part C missing: nothing comes, the poll finds the sample incomplete after the window") {
        Link link;
        (void)link.bring_up();
        (void)link.deliver_frames(link.next(), 0U, 4U, link.now + kPeriodUs);
        const std::uint64_t start = link.now - 3U * kGapUs;
        CHECK(link.poll_at(start + link.config.sample_window_us).status.valid);  // the window is inclusive
        (void)link.poll_at(start + link.config.sample_window_us + 1U);
        check_invalid(link, CommandFault::kSampleIncomplete);
    }
}

// verifies: SR-CMD-004, SR-CMD-005
TEST_CASE("command receiver: a late part, a late sample and silence make the command invalid") {
    SUBCASE("a part after the sample window") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver_frames(s, 0U, 4U, link.now + kPeriodUs);
        const std::uint64_t start = link.now - 3U * kGapUs;
        check_invalid(link.deliver(s.frame[4], start + link.config.sample_window_us + 1U),
                      CommandFault::kSampleIncomplete);
    }
    SUBCASE("silence: valid up to the SCT, invalid after it") {
        Link link;
        (void)link.bring_up();
        const std::uint64_t last = link.now;
        CHECK(link.poll_at(last + link.config.sct_us).status.valid);
        const CommandPoll p = link.poll_at(last + link.config.sct_us + 1U);
        check_invalid(p.status, CommandFault::kSctExpired);
        CHECK_FALSE(p.input.valid);
    }
    SUBCASE("a sample that completes after the SCT, with no poll in between") {
        Link link;
        (void)link.bring_up();
        const std::uint64_t last = link.now;
        check_invalid(link.deliver_frames(link.next(), 0U, 6U, last + link.config.sct_us - 4U * kGapUs),
                      CommandFault::kSctExpired);
        check_invalid(link.send_sample(), CommandFault::kSctExpired);  // recovery: the late one was the reference
        CHECK(link.send_sample().valid);
    }
    SUBCASE("frames on other CAN IDs let time pass") {
        Link link;
        (void)link.bring_up();
        const CanFrame foreign{0x101U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
        CHECK(link.deliver(foreign, link.now + link.config.sct_us).valid);
        check_invalid(link.deliver(foreign, link.now + 1U), CommandFault::kSctExpired);
    }
}

// verifies: SR-CMD-004
TEST_CASE("command receiver: an inverted copy in time for its part but after the sample window is incomplete") {
    Link link;
    (void)link.bring_up();
    const CommandFrames s = link.next();
    const std::uint64_t start = link.now + kPeriodUs;
    (void)link.deliver_frames(s, 0U, 4U, start);
    // The last part just inside the window, its copy just outside it (well within the SRVT of the part).
    CHECK(link.deliver(s.frame[4], start + link.config.sample_window_us - 10U).fault == CommandFault::kNone);
    REQUIRE(link.config.srvt_us > 20U);
    check_invalid(link.deliver(s.frame[5], start + link.config.sample_window_us + 1U), CommandFault::kSampleIncomplete);
}

// verifies: SR-CMD-005
TEST_CASE("command receiver: a repeated sample or a repeated part makes the command invalid") {
    SUBCASE("the same six frames again") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        CHECK(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs).valid);
        check_invalid(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs), CommandFault::kRepeatedCounter);
    }
    SUBCASE("part A twice") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver_frames(s, 0U, 2U, link.now + kPeriodUs);
        check_invalid(link.deliver(s.frame[0], link.now + kGapUs), CommandFault::kSampleIncomplete);
    }
    SUBCASE("part B twice") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver_frames(s, 0U, 4U, link.now + kPeriodUs);
        check_invalid(link.deliver(s.frame[2], link.now + kGapUs), CommandFault::kPartOutOfOrder);
    }
    SUBCASE("a copy twice") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver_frames(s, 0U, 2U, link.now + kPeriodUs);
        check_invalid(link.deliver(s.frame[1], link.now + kGapUs), CommandFault::kUnexpectedInvertedCopy);
    }
}

// verifies: SR-CMD-004
TEST_CASE("command receiver: reordered parts and copies make the command invalid") {
    const struct {
        std::size_t order[6];
        std::size_t fails_at;  // index into order
        CommandFault reason;
    } cases[] = {
        {{2U, 3U, 0U, 1U, 4U, 5U}, 0U, CommandFault::kPartOutOfOrder},          // B first
        {{1U, 0U, 2U, 3U, 4U, 5U}, 0U, CommandFault::kUnexpectedInvertedCopy},  // A' before A
        {{0U, 2U, 1U, 3U, 4U, 5U}, 1U, CommandFault::kInvertedCopyMissing},     // B before A'
        {{0U, 1U, 4U, 5U, 2U, 3U}, 2U, CommandFault::kPartOutOfOrder},          // C before B
        {{0U, 1U, 2U, 5U, 3U, 4U}, 3U, CommandFault::kUnexpectedInvertedCopy},  // C' for B'
        {{0U, 1U, 2U, 3U, 5U, 4U}, 4U, CommandFault::kUnexpectedInvertedCopy},  // C' before C
    };
    for (const auto& c : cases) {
        CAPTURE(c.fails_at);
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        link.now += kPeriodUs;
        for (std::size_t i = 0U; i < 6U; ++i) {
            const CommandStatus st = link.deliver(s.frame[c.order[i]], link.now + kGapUs);
            CHECK(st.valid == (i < c.fails_at));
            if (i == c.fails_at) {
                CHECK(st.fault == c.reason);
            }
        }
        CHECK_FALSE(link.receiver.poll(link.now).status.valid);  // the rest of the sample does not make it good
    }
}

// verifies: SR-CMD-003, SR-CMD-004
TEST_CASE("command receiver: a corrupted byte in any of the six frames makes the command invalid") {
    for (std::size_t frame = 0U; frame < 6U; ++frame) {
        for (std::size_t byte = 0U; byte < 8U; ++byte) {
            CAPTURE(frame);
            CAPTURE(byte);
            Link link;
            (void)link.bring_up();
            CommandFrames s = link.next();
            s.frame[frame].data[byte] = static_cast<std::uint8_t>(s.frame[frame].data[byte] ^ 0x10U);
            (void)link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs);
            CHECK(link.receiver.status().fault_events == 1U);
            // A part fails its CRC; a copy is no longer the inverse of its part.
            const bool part = frame % 2U == 0U;
            check_invalid(link, part ? CommandFault::kWrongCrc : CommandFault::kInvertedCopyMismatch);
        }
    }
}

// verifies: SR-CMD-004
TEST_CASE("command receiver: an inverted copy that mismatches, is missing or is late makes the command invalid") {
    SUBCASE("another DLC") {
        Link link;
        (void)link.bring_up();
        CommandFrames s = link.next();
        s.frame[3].dlc = 7U;
        check_invalid(link.deliver_frames(s, 0U, 4U, link.now + kPeriodUs), CommandFault::kInvertedCopyMismatch);
    }
    SUBCASE("the part itself instead of its inverse, on the copy's ID") {
        Link link;
        (void)link.bring_up();
        CommandFrames s = link.next();
        s.frame[5] = s.frame[4];
        s.frame[5].id += 1U;
        check_invalid(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs), CommandFault::kInvertedCopyMismatch);
    }
    SUBCASE("missing: the poll after the SRVT") {
        Link link;
        (void)link.bring_up();
        (void)link.deliver_frames(link.next(), 0U, 3U, link.now + kPeriodUs);
        const std::uint64_t part_b = link.now;
        CHECK(link.poll_at(part_b + link.config.srvt_us).status.valid);  // inclusive
        (void)link.poll_at(part_b + link.config.srvt_us + 1U);
        check_invalid(link, CommandFault::kInvertedCopyMissing);
    }
    SUBCASE("late: after the SRVT, within the sample window") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver(s.frame[0], link.now + kPeriodUs);
        check_invalid(link.deliver(s.frame[1], link.now + link.config.srvt_us + 1U), CommandFault::kInvertedCopyLate);
    }
    SUBCASE("at the SRVT: accepted") {
        Link link;
        (void)link.bring_up();
        const CommandFrames s = link.next();
        (void)link.deliver(s.frame[0], link.now + kPeriodUs);
        CHECK(link.deliver(s.frame[1], link.now + link.config.srvt_us).valid);
        CHECK(link.deliver_frames(s, 2U, 6U, link.now + kGapUs).valid);
    }
}

// verifies: SR-CMD-004
TEST_CASE("command receiver: parts with different counters do not form a sample") {
    Link link;
    (void)link.bring_up();
    const CommandFrames first = link.next();
    const CommandFrames second = link.next();
    (void)link.deliver_frames(first, 0U, 2U, link.now + kPeriodUs);
    check_invalid(link.deliver_frames(second, 2U, 6U, link.now + kGapUs), CommandFault::kCounterMismatch);
    Link c_only;
    (void)c_only.bring_up();
    const CommandFrames a = c_only.next();
    const CommandFrames b = c_only.next();
    (void)c_only.deliver_frames(a, 0U, 4U, c_only.now + kPeriodUs);
    check_invalid(c_only.deliver(b.frame[4], c_only.now + kGapUs), CommandFault::kCounterMismatch);
}

// verifies: SR-CMD-003
TEST_CASE("command receiver: a wrong data ID makes the command invalid (implicit: CRC, NIBBLE: the nibble)") {
    Link link;
    (void)link.bring_up();
    CommandChannelConfig other = link.config.channel;
    other.data_id[1] = 0x0B62U;
    PlcCommandSender stranger(other);
    for (int k = 0; k < 3; ++k) {  // bring the stranger's counter to the link's
        (void)stranger.next_sample(command());
    }
    check_invalid(link.deliver_frames(stranger.next_sample(command()).value(), 0U, 6U, link.now + kPeriodUs),
                  CommandFault::kWrongCrc);

    CommandReceiverConfig nc = receiver_config();
    nc.channel.data_id_mode = E2eP01DataIdMode::kNibble;
    Link nibble(nc);
    (void)nibble.bring_up();
    other.data_id_mode = E2eP01DataIdMode::kNibble;
    PlcCommandSender nibble_stranger(other);
    check_invalid(nibble.deliver_frames(nibble_stranger.next_sample(command()).value(), 0U, 6U, nibble.now + kPeriodUs),
                  CommandFault::kWrongDataIdNibble);
}

// verifies: SR-CMD-005
TEST_CASE("command receiver: skipped samples within the bound are accepted, a jump beyond it is not") {
    Link link;  // max_delta_counter 2
    (void)link.bring_up();
    (void)link.next();  // one sample lost: delta 2
    CHECK(link.send_sample().valid);
    (void)link.next();
    (void)link.next();  // two lost: delta 3
    check_invalid(link.send_sample(), CommandFault::kCounterJump);
}

// verifies: SR-CMD-003
TEST_CASE("command receiver: a sample with a joint set beyond its joint count is malformed") {
    Link link;
    (void)link.bring_up();
    RobotCommand a = command();
    a.joint_count = 2U;
    a.joint_raw[5] = 0;
    const std::uint8_t counter = link.sender.counter();
    const CommandFrames short_a = encode_command_sample(a, counter, link.config.channel).value();
    CommandFrames s = link.next();  // joint 5 set, count 6
    s.frame[0] = short_a.frame[0];
    s.frame[1] = short_a.frame[1];
    check_invalid(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs), CommandFault::kMalformedContent);
}

// verifies: SR-CMD-005
TEST_CASE("command receiver: time going backwards makes the command invalid, on a poll and on a frame") {
    Link link;
    (void)link.bring_up();
    check_invalid(link.poll_at(link.now - 1U).status, CommandFault::kTimeWentBackwards);
    Link frames;
    (void)frames.bring_up();
    const CommandFrames s = frames.next();
    (void)frames.deliver_frames(s, 0U, 3U, frames.now + kPeriodUs);
    check_invalid(frames.deliver(s.frame[3], frames.now - 1U), CommandFault::kTimeWentBackwards);
    check_invalid(frames.deliver(s.frame[4], frames.now + kGapUs), CommandFault::kTimeWentBackwards);  // dropped
    CHECK(frames.receiver.status().fault_events == 1U);
}

// verifies: SR-CMD-006
TEST_CASE("command receiver: after a fault it recovers with a reference and two good samples, a fault restarts that") {
    Link link;
    (void)link.bring_up();
    (void)link.next();
    (void)link.next();
    check_invalid(link.send_sample(), CommandFault::kCounterJump);
    check_invalid(link.send_sample(), CommandFault::kCounterJump);  // the new reference
    check_invalid(link.send_sample(), CommandFault::kCounterJump);  // recovery 1
    CommandFrames s = link.next();
    s.frame[2].data[4] = static_cast<std::uint8_t>(s.frame[2].data[4] ^ 0x01U);
    check_invalid(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs), CommandFault::kWrongCrc);
    check_invalid(link.send_sample(), CommandFault::kWrongCrc);  // reference again
    check_invalid(link.send_sample(), CommandFault::kWrongCrc);
    CHECK(link.send_sample().valid);
    CHECK(link.receiver.status().fault_events == 2U);
}

// verifies: SR-CMD-006
TEST_CASE("command receiver: frames and polls allocate nothing") {
    Link link;
    const CommandFrames s = link.next();
    const test::AllocationScope scope;
    for (int k = 0; k < 20; ++k) {
        (void)link.send_sample();
        (void)link.poll_at(link.now + 1000U);
    }
    (void)link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs);  // a repeat: a fault
    CHECK(scope.allocations() == 0U);
}

// verifies: SR-CMD-006
TEST_CASE("command receiver: a configuration is checked, and an invalid one cannot build a receiver") {
    CHECK(CommandReceiver::check_config(receiver_config()).ok());
    CommandReceiverConfig c = receiver_config();
    c.srvt_us = 0U;
    CHECK(CommandReceiver::check_config(c).error() == ErrorCode::kInvalidArgument);
    c = receiver_config();
    c.srvt_us = c.sample_window_us + 1U;
    CHECK_FALSE(CommandReceiver::check_config(c).ok());
    c = receiver_config();
    c.sct_us = c.sample_window_us;
    CHECK_FALSE(CommandReceiver::check_config(c).ok());
    c = receiver_config();
    c.max_delta_counter = 0U;
    CHECK_FALSE(CommandReceiver::check_config(c).ok());
    c.max_delta_counter = 15U;
    CHECK_FALSE(CommandReceiver::check_config(c).ok());
    c = receiver_config();
    c.recovery_good_samples = 0U;
    CHECK_FALSE(CommandReceiver::check_config(c).ok());
    c = receiver_config();
    c.channel.base_can_id = 0x7FCU;
    CHECK_FALSE(CommandReceiver::check_config(c).ok());
    CHECK(test::violates_contract([&] { const CommandReceiver r(c); }));
    test::check_enum_names<CommandFault>(29U, "unknown command fault");
}

// verifies: SR-CAN-015, SR-CMD-006
TEST_CASE("command receiver: a link whose peer channel is invalid or lies among the command's frame IDs is refused") {
    CommandReceiverConfig c = receiver_config();
    c.link.enabled = true;
    REQUIRE(CommandReceiver::check_config(c).ok());
    const std::uint32_t base = c.channel.base_can_id;
    const auto frames = static_cast<std::uint32_t>(kCommandFramesPerSample);
    for (const std::uint32_t taken : {base, base + frames - 1U, std::uint32_t{kCanMaxStandardId + 1U}}) {
        CAPTURE(taken);
        CommandReceiverConfig d = c;
        d.link.peer.can_id = taken;
        CHECK(CommandReceiver::check_config(d).error() == ErrorCode::kInvalidArgument);
    }
    for (const std::uint32_t free_id : {base - 1U, base + frames}) {  // just outside the frames
        CAPTURE(free_id);
        CommandReceiverConfig d = c;
        d.link.peer.can_id = free_id;
        CHECK(CommandReceiver::check_config(d).ok() == (free_id != c.link.own.can_id));
    }
}

// verifies: SR-CMD-003, SR-CMD-004
TEST_CASE("command receiver: a part or copy of another length makes the command invalid") {
    for (std::size_t frame = 0U; frame < 6U; ++frame) {
        for (const std::uint8_t dlc : {std::uint8_t{7U}, std::uint8_t{0U}}) {
            CAPTURE(frame);
            CAPTURE(dlc);
            Link link;
            REQUIRE(link.bring_up() == 3);
            CommandFrames s = link.next();
            s.frame[frame].dlc = dlc;
            (void)link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs);
            CHECK(link.receiver.status().fault_events == 1U);
            const bool part = frame % 2U == 0U;
            check_invalid(link, part ? CommandFault::kWrongLength : CommandFault::kInvertedCopyMismatch);
        }
    }
}

// verifies: SR-CMD-003
TEST_CASE("command receiver: a part with counter 15 or with data ID nibble bits set outside NIBBLE mode is refused") {
    SUBCASE("counter 15, CRC correct") {
        Link link;
        (void)link.bring_up();
        CommandFrames s = link.next();
        set_signal(s.frame[0], command_layout::kCounter, 15U);
        s.frame[0].data[0] = e2e_p01_crc(Span<const std::uint8_t>(s.frame[0].data, 8U), 0U,
                                         link.config.channel.data_id[0], link.config.channel.data_id_mode, 15U);
        s.frame[1] = inverted_copy(s.frame[0]);
        check_invalid(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs), CommandFault::kCounterOutOfRange);
    }
    SUBCASE("nibble bits in BOTH mode, CRC correct") {
        Link link;
        (void)link.bring_up();
        CommandFrames s = link.next();
        set_signal(s.frame[2], command_layout::kDataIdNibble, 0x8U);
        const auto counter = static_cast<std::uint8_t>(get_signal(s.frame[2], command_layout::kCounter));
        s.frame[2].data[0] = e2e_p01_crc(Span<const std::uint8_t>(s.frame[2].data, 8U), 0U,
                                         link.config.channel.data_id[1], link.config.channel.data_id_mode, counter);
        s.frame[3] = inverted_copy(s.frame[2]);
        check_invalid(link.deliver_frames(s, 0U, 6U, link.now + kPeriodUs), CommandFault::kMalformedContent);
    }
}

// verifies: SR-CMD-003
TEST_CASE(
    "command receiver: a frame with a CAN ID below the command's base ID is not the receiver's and changes nothing") {
    Link link;
    REQUIRE(link.bring_up() == 3);
    const CanFrame below{link.config.channel.base_can_id - 1U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    const CommandStatus s = link.deliver(below, link.now + 100U);
    CHECK(s.valid);
    CHECK(s.fault == CommandFault::kNone);
    CHECK(s.fault_events == 0U);
    CHECK(link.send_sample().valid);
}

// verifies: SR-CMD-006
TEST_CASE(
    "command receiver: the largest recovery count, 255 good samples, is reached and a long run then stays valid") {
    CommandReceiverConfig c = receiver_config();
    c.recovery_good_samples = 255U;
    Link link(c);
    for (int k = 0; k < 255; ++k) {  // the reference and 254 good samples
        CHECK_FALSE(link.send_sample().valid);
    }
    CHECK(link.send_sample().valid);  // the 255th good sample
    for (int k = 0; k < 20; ++k) {    // past the saturated count of good samples
        CHECK(link.send_sample().valid);
    }
    const CommandStatus s = link.receiver.status();
    CHECK(s.good_samples == 276U);
    CHECK(s.fault_events == 0U);
}

namespace {

/// The receiver's defaults with the session link on, its watchdog time below the SCT (120 ms).
CommandReceiverConfig linked_config() {
    CommandReceiverConfig c;
    c.link.watchdog_us = 60000U;
    return c;
}

/// A PLC with the session link and the controller's receiver; the controller's link
/// fields reach the PLC when it makes a sample.
struct LinkedPlc {
    explicit LinkedPlc(const CommandReceiverConfig& c)
        : config(c), sender(c.channel), endpoint(plc_link_config()), receiver(c) {}

    /// The seven frames of the next sample, made at @p at, after the controller's link fields reached the PLC.
    LinkedCommandFrames next(std::uint64_t at) {
        (void)endpoint.on_peer(receiver.link().next(at), at);
        return sender.next_sample(command(), endpoint.next(at), endpoint.config().own).value();
    }
    /// Delivers frames [0, count) of @p s, kGapUs apart from @p at (the link frame is index 6).
    CommandStatus deliver(const LinkedCommandFrames& s, std::size_t count, std::uint64_t at) {
        CommandStatus st = receiver.status();
        for (std::size_t i = 0U; i < count; ++i) {
            st = receiver.on_frame(i < kCommandFramesPerSample ? s.sample.frame[i] : s.link, at + i * kGapUs);
        }
        return st;
    }

    CommandReceiverConfig config;
    PlcCommandSender sender;
    LinkEndpoint endpoint;
    CommandReceiver receiver;
};

}  // namespace

// verifies: SR-CAN-016
TEST_CASE("command receiver: with the session link, a poll after the watchdog time ends a valid command") {
    LinkedPlc plc(linked_config());
    std::uint64_t t = 1000000U;
    CommandStatus s;
    for (int k = 0; k < 3; ++k) {  // the reference and the two recovery samples
        t += kPeriodUs;
        s = plc.deliver(plc.next(t), 7U, t);
    }
    REQUIRE(s.valid);
    // The sample's link frame echoes the controller's sequence sent at t: its data is that old.
    CHECK(plc.receiver.poll(t + plc.config.link.watchdog_us).status.valid);
    const CommandPoll p = plc.receiver.poll(t + plc.config.link.watchdog_us + 1U);
    REQUIRE(t + plc.config.link.watchdog_us + 1U < t + 6U * kGapUs + plc.config.sct_us);  // within the SCT
    check_invalid(p.status, CommandFault::kWatchdogExpired);
    CHECK_FALSE(p.input.valid);
}

// verifies: SR-CAN-014
TEST_CASE("command receiver: with the session link, a link frame after the sample window is missing") {
    LinkedPlc plc(linked_config());
    const std::uint64_t t = 1000000U;
    const LinkedCommandFrames s = plc.next(t);
    const std::uint64_t window_end = t + plc.config.sample_window_us;
    SUBCASE("the link frame arrives late, with no poll in between") {
        CHECK(plc.deliver(s, 6U, t).fault_events == 0U);
        check_invalid(plc.receiver.on_frame(s.link, window_end + 1U), CommandFault::kLinkFrameMissing);
    }
    SUBCASE("a poll after the window finds the link frame missing") {
        (void)plc.deliver(s, 6U, t);
        CHECK(plc.receiver.poll(window_end).status.fault_events == 0U);
        check_invalid(plc.receiver.poll(window_end + 1U).status, CommandFault::kLinkFrameMissing);
    }
    SUBCASE("a poll after the window finds part B missing") {
        (void)plc.deliver(s, 2U, t);
        check_invalid(plc.receiver.poll(window_end + 1U).status, CommandFault::kSampleIncomplete);
    }
    CHECK(plc.receiver.status().fault_events == 1U);
}
