// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the PLC's command message: layout of the three parts, encoding of one sample into six frames, the check of each part, the channel config rules.
#include <doctest/doctest.h>

#include <cstdint>

#include "cellguard/can/command_frame.hpp"
#include "cellguard/can/separation_frame.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

constexpr E2eP01DataIdMode kAllModes[] = {E2eP01DataIdMode::kBoth, E2eP01DataIdMode::kAlt, E2eP01DataIdMode::kLow,
                                          E2eP01DataIdMode::kNibble};

CommandChannelConfig channel(E2eP01DataIdMode mode = E2eP01DataIdMode::kBoth) {
    CommandChannelConfig c;
    c.data_id_mode = mode;
    return c;
}

RobotCommand six_axis() {
    RobotCommand c;
    c.monitoring_case = 5U;
    c.speed_class = 2U;
    c.joint_count = 6U;
    c.robot_id = 0xBEEFU;
    const std::int16_t joints[] = {15708, -15708, 32767, -32767, 1, -1};
    for (std::size_t j = 0U; j < 6U; ++j) {
        c.joint_raw[j] = joints[j];
    }
    return c;
}

/// Recomputes the CRC of @p f after a test changed its content on purpose.
void reprotect(CanFrame& f, std::uint16_t data_id, E2eP01DataIdMode mode = E2eP01DataIdMode::kBoth) {
    const auto counter = static_cast<std::uint8_t>(get_signal(f, command_layout::kCounter));
    f.data[0] = e2e_p01_crc(Span<const std::uint8_t>(f.data, 8U), 0U, data_id, mode, counter);
}

FrameCheck check(const CanFrame& f, CommandPart part, const CommandChannelConfig& c = channel()) {
    CommandPartContent out;
    return check_command_part(f, part, c, out);
}

}  // namespace

// verifies: SR-CMD-001
TEST_CASE("command frame: the encoder puts every field of the three parts at the bit the layout tables name") {
    const CommandFrames s = encode_command_sample(six_axis(), 7U, channel()).value();
    const CanFrame& a = s.frame[0];
    const CanFrame& b = s.frame[2];
    const CanFrame& c = s.frame[4];
    CHECK(a.id == 0x0C1U);
    CHECK(s.frame[1].id == 0x0C2U);
    CHECK(b.id == 0x0C3U);
    CHECK(s.frame[3].id == 0x0C4U);
    CHECK(c.id == 0x0C5U);
    CHECK(s.frame[5].id == 0x0C6U);
    for (const CanFrame& f : s.frame) {
        CHECK(f.dlc == 8U);
        CHECK((f.data[1] & 0x0FU) == ((f.id % 2U == 1U) ? 7U : 8U));  // copies carry the counter inverted
    }
    CHECK(a.data[2] == 0x25);  // case 5 (bits 16..19), speed class 2 (bits 20..21)
    CHECK(a.data[3] == 0x06);  // joint count 6 (bits 24..26)
    CHECK(a.data[4] == 0x5C);  // joint 0 = 15708 = 0x3D5C, little-endian
    CHECK(a.data[5] == 0x3D);
    CHECK(a.data[6] == 0xA4);  // joint 1 = -15708 = 0xC2A4
    CHECK(a.data[7] == 0xC2);
    CHECK(b.data[2] == 0xFF);  // joint 2 = 32767
    CHECK(b.data[3] == 0x7F);
    CHECK(b.data[4] == 0x01);  // joint 3 = -32767 = 0x8001
    CHECK(b.data[5] == 0x80);
    CHECK(b.data[6] == 0x01);  // joint 4 = 1
    CHECK(b.data[7] == 0x00);
    CHECK(c.data[2] == 0xFF);  // joint 5 = -1
    CHECK(c.data[3] == 0xFF);
    CHECK(c.data[4] == 0x00);  // joint 6 unused
    CHECK(c.data[5] == 0x00);
    CHECK(c.data[6] == 0xEF);  // robot ID 0xBEEF
    CHECK(c.data[7] == 0xBE);
    CHECK(a.data[0] ==
          e2e_p01_crc(Span<const std::uint8_t>(a.data, 8U), 0U, kDefaultCommandDataIdA, E2eP01DataIdMode::kBoth, 7U));
    for (std::size_t p = 0U; p < kCommandParts; ++p) {
        const CanFrame& part = s.frame[2U * p];
        const CanFrame& copy = s.frame[2U * p + 1U];
        for (std::size_t k = 0U; k < 8U; ++k) {
            CHECK(copy.data[k] == static_cast<std::uint8_t>(~part.data[k]));
        }
    }
    const CanFrame n = encode_command_part(six_axis(), CommandPart::kB, 3U, channel(E2eP01DataIdMode::kNibble)).value();
    CHECK(n.data[1] == 0x83);  // data ID 0x0862: nibble 8 in bits 12..15
}

// verifies: SR-CMD-001, SR-CMD-010
TEST_CASE("command frame: ResetRequest is part A's bit 22, and a pressed reset decodes back as pressed") {
    RobotCommand pressed = six_axis();
    pressed.reset_request = true;
    const CommandFrames s = encode_command_sample(pressed, 3U, channel()).value();
    const CommandFrames r = encode_command_sample(six_axis(), 3U, channel()).value();
    CHECK(s.frame[0].data[2] == 0x65);          // case 5, speed class 2 and bit 22 (0x40)
    CHECK(r.frame[0].data[2] == 0x25);          // released: bit 22 clear
    CHECK((s.frame[1].data[2] & 0x40U) == 0U);  // the copy carries it inverted
    CHECK(get_signal(s.frame[0], command_layout::kResetRequest) == 1U);
    for (std::size_t k = 3U; k < 8U; ++k) {
        CHECK(s.frame[0].data[k] == r.frame[0].data[k]);  // nothing else of part A moved
    }
    CHECK(s.frame[2].data[2] == r.frame[2].data[2]);  // parts B and C unchanged (their CRCs too)
    CHECK(s.frame[4].data[0] == r.frame[4].data[0]);
    RobotCommand out;
    for (std::size_t p = 0U; p < kCommandParts; ++p) {
        const Result<CommandPartContent> c = decode_command_part(s.frame[2U * p], static_cast<CommandPart>(p),
                                                                 channel());
        REQUIRE(c.ok());
        merge_command_part(c.value(), out);
    }
    CHECK(out.reset_request);
    CHECK(out == pressed);
    CHECK(out != six_axis());  // equality sees the reset request
    CHECK((command_layout::kPartAReservedBits & (std::uint64_t{1} << 22U)) == 0U);
}

// verifies: SR-CMD-001, SR-CMD-002
TEST_CASE("command frame: every counter and every mode decodes back to the sample, part by part") {
    for (const E2eP01DataIdMode mode : kAllModes) {
        for (std::uint8_t counter = 0U; counter <= kE2eP01CounterMax; ++counter) {
            CAPTURE(counter);
            RobotCommand cmd = six_axis();
            cmd.joint_count = 7U;
            cmd.joint_raw[6] = static_cast<std::int16_t>(-1000 * counter);
            cmd.monitoring_case = counter;
            const CommandFrames s = encode_command_sample(cmd, counter, channel(mode)).value();
            RobotCommand back;
            for (std::size_t p = 0U; p < kCommandParts; ++p) {
                const Result<CommandPartContent> r = decode_command_part(s.frame[2U * p], static_cast<CommandPart>(p),
                                                                         channel(mode));
                REQUIRE(r.ok());
                CHECK(r.value().counter == counter);
                merge_command_part(r.value(), back);
            }
            CHECK(back == cmd);
        }
    }
}

// verifies: SR-CMD-003
TEST_CASE("command frame: each part is checked for ID, length, CRC, data ID, counter, reserved bits and joint values") {
    const CommandChannelConfig c = channel();
    const CommandFrames s = encode_command_sample(six_axis(), 4U, c).value();
    for (std::size_t p = 0U; p < kCommandParts; ++p) {
        const auto part = static_cast<CommandPart>(p);
        CAPTURE(p);
        CHECK(check(s.frame[2U * p], part) == FrameCheck::kOk);
        CHECK(check(s.frame[2U * p + 1U], part) == FrameCheck::kWrongCanId);  // a copy is no part
        CHECK(check(s.frame[(2U * p + 2U) % 6U], part) == FrameCheck::kWrongCanId);
        CanFrame f = s.frame[2U * p];
        f.dlc = 7U;
        CHECK(check(f, part) == FrameCheck::kWrongLength);
        for (unsigned bit = 0U; bit < 64U; ++bit) {  // every single flipped bit
            f = s.frame[2U * p];
            f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] ^ (1U << (bit % 8U)));
            CHECK(check(f, part) != FrameCheck::kOk);
        }
        f = s.frame[2U * p];  // the same content under another part's data ID
        reprotect(f, c.data_id[(p + 1U) % 3U]);
        CHECK(check(f, part) == FrameCheck::kWrongCrc);
        f = s.frame[2U * p];
        set_signal(f, command_layout::kCounter, 15U);
        reprotect(f, c.data_id[p]);
        CHECK(check(f, part) == FrameCheck::kCounterOutOfRange);
        f = s.frame[2U * p];  // a joint at the reserved raw value
        set_signed_signal(f, command_layout::kJoints[p == 0U ? 0U : (p == 1U ? 3U : 5U)], kJointRawInvalid);
        reprotect(f, c.data_id[p]);
        CHECK(check(f, part) == FrameCheck::kMalformedContent);
        f = s.frame[2U * p];  // the nibble is reserved outside NIBBLE mode
        set_signal(f, command_layout::kDataIdNibble, 3U);
        reprotect(f, c.data_id[p]);
        CHECK(check(f, part) == FrameCheck::kMalformedContent);
    }
    for (const unsigned bit : {23U, 27U, 28U, 29U, 30U, 31U}) {  // part A's reserved bits (22 is ResetRequest)
        CanFrame f = s.frame[0];
        f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] | (1U << (bit % 8U)));
        reprotect(f, c.data_id[0]);
        CHECK(check(f, CommandPart::kA) == FrameCheck::kMalformedContent);
    }
    const CommandFrames n = encode_command_sample(six_axis(), 4U, channel(E2eP01DataIdMode::kNibble)).value();
    CommandChannelConfig other = channel(E2eP01DataIdMode::kNibble);
    other.data_id[1] = 0x0A62U;  // another high nibble
    CHECK(check(n.frame[2], CommandPart::kB, other) == FrameCheck::kWrongDataIdNibble);
    CHECK(decode_command_part(n.frame[2], CommandPart::kB, other).error() == ErrorCode::kCrcMismatch);
    CommandPartContent untouched;
    untouched.counter = 99U;
    CHECK(check_command_part(n.frame[2], CommandPart::kB, other, untouched) == FrameCheck::kWrongDataIdNibble);
    CHECK(untouched.counter == 99U);
}

// verifies: SR-CMD-001
TEST_CASE("command frame: the encoder refuses a bad counter, case, speed class, joint count and joint values") {
    CHECK(encode_command_sample(six_axis(), 15U, channel()).error() == ErrorCode::kInvalidArgument);
    RobotCommand c = six_axis();
    c.monitoring_case = 16U;
    CHECK_FALSE(command_well_formed(c));
    CHECK(encode_command_sample(c, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    c = six_axis();
    c.speed_class = 4U;
    CHECK_FALSE(command_well_formed(c));
    c = six_axis();
    c.joint_count = 8U;
    CHECK_FALSE(command_well_formed(c));
    c = six_axis();
    c.joint_raw[2] = kJointRawInvalid;
    CHECK_FALSE(command_well_formed(c));
    c = six_axis();
    c.joint_raw[6] = 5;  // beyond the joint count
    CHECK_FALSE(command_well_formed(c));
    CHECK(encode_command_part(c, CommandPart::kA, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    CHECK(command_well_formed(RobotCommand{}));  // no joints at all
    CHECK(encode_command_part(six_axis(), static_cast<CommandPart>(3), 0U, channel()).error() ==
          ErrorCode::kInvalidArgument);
    CommandChannelConfig bad;
    bad.base_can_id = 0x7FBU;  // C' would need 0x800
    CHECK(encode_command_sample(six_axis(), 0U, bad).error() == ErrorCode::kInvalidArgument);
    CommandPartContent out;
    CHECK(test::violates_contract([&] { (void)check_command_part(CanFrame{}, CommandPart::kA, bad, out); }));
}

// verifies: SR-CMD-002
TEST_CASE("command frame: the channel config needs 11-bit IDs and data IDs distinguishable from each other") {
    for (const E2eP01DataIdMode mode : kAllModes) {
        CHECK(check_command_channel_config(channel(mode)).ok());
    }
    CommandChannelConfig c;
    c.base_can_id = 0x7FAU;  // C' on 0x7FF: the last one that fits
    CHECK(check_command_channel_config(c).ok());
    c.base_can_id = 0x7FBU;
    CHECK(check_command_channel_config(c).error() == ErrorCode::kInvalidArgument);
    c = channel(E2eP01DataIdMode::kLow);
    c.data_id[2] = 0x0A61U;  // the low byte of part A's
    CHECK_FALSE(check_command_channel_config(c).ok());
    c = channel(E2eP01DataIdMode::kNibble);
    c.data_id[0] = 0x1761U;  // 13 bits
    CHECK_FALSE(check_command_channel_config(c).ok());
    c = CommandChannelConfig{};
    c.data_id[0] = 0x0000U;
    c.data_id[1] = 0x1D01U;  // same CRC for all data in BOTH mode
    CHECK_FALSE(check_command_channel_config(c).ok());
    c = CommandChannelConfig{};
    c.data_id_mode = static_cast<E2eP01DataIdMode>(9);
    CHECK_FALSE(check_command_channel_config(c).ok());
}

// verifies: SR-CMD-002
TEST_CASE("command frame: the default IDs and data IDs share a bus with the output's in every data ID mode") {
    for (const E2eP01DataIdMode out_mode : kAllModes) {
        for (const E2eP01DataIdMode cmd_mode : kAllModes) {
            SafetyChannelConfig out;
            out.data_id_mode = out_mode;
            CHECK(check_channels_compatible(out, channel(cmd_mode)).ok());
        }
    }
    SafetyChannelConfig out;
    CommandChannelConfig cmd;
    cmd.base_can_id = 0x0FFU;  // C' on 0x104, the separation frame's ID
    CHECK(check_channels_compatible(out, cmd).error() == ErrorCode::kInvalidArgument);
    cmd.base_can_id = 0x0FEU;  // ends at 0x103, the diagnostics frame
    CHECK_FALSE(check_channels_compatible(out, cmd).ok());
    cmd.base_can_id = 0x0F8U;  // ends at 0x0FD
    CHECK(check_channels_compatible(out, cmd).ok());
    cmd = CommandChannelConfig{};
    cmd.data_id[1] = kDefaultSafetyDataId;
    CHECK_FALSE(check_channels_compatible(out, cmd).ok());
    cmd = CommandChannelConfig{};
    cmd.data_id_mode = E2eP01DataIdMode::kLow;
    cmd.data_id[2] = 0x0A53U;  // the separation frame's low byte
    CHECK_FALSE(check_channels_compatible(out, cmd).ok());
    out.separation_can_id = 0x7FFU;
    cmd = CommandChannelConfig{};
    cmd.base_can_id = 0x800U;
    CHECK_FALSE(check_channels_compatible(out, cmd).ok());
}

// verifies: SR-CMD-001
TEST_CASE("command frame: signed signals are two's complement, sign-extended on read, range-checked in the table") {
    CanFrame f{0x0C1U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    for (const std::int32_t v : {-32768, -32767, -1, 0, 1, 32767}) {
        set_signed_signal(f, command_layout::kJoint3, v);
        CHECK(get_signed_signal(f, command_layout::kJoint3) == v);
        CHECK(get_signal(f, command_layout::kJoint3) == (static_cast<std::uint32_t>(v) & 0xFFFFU));
    }
    CHECK(f.data[2] == 0U);  // neighbours untouched
    CHECK(f.data[6] == 0U);
    const SignalLayout three_bits{"S", 8U, 3U, ByteOrder::kIntel, 1U, "", 3U, Multiplex::kNone, 0U, true};
    set_signed_signal(f, three_bits, -4);
    CHECK(f.data[1] == 0x04U);
    CHECK(get_signed_signal(f, three_bits) == -4);
    CHECK(test::violates_contract([&] { set_signed_signal(f, three_bits, 4); }));
    CHECK(test::violates_contract([&] { set_signed_signal(f, three_bits, -5); }));
    const SignalLayout too_wide[] = {{"S", 0U, 3U, ByteOrder::kIntel, 1U, "", 4U, Multiplex::kNone, 0U, true}};
    CHECK_FALSE(layout_is_consistent(too_wide));
    const SignalLayout one_bit[] = {{"S", 0U, 1U, ByteOrder::kIntel, 1U, "", 0U, Multiplex::kNone, 0U, true}};
    CHECK_FALSE(layout_is_consistent(one_bit));
    const SignalLayout ok[] = {{"S", 0U, 3U, ByteOrder::kIntel, 1U, "", 3U, Multiplex::kNone, 0U, true}};
    CHECK(layout_is_consistent(ok));
}

// verifies: SR-CMD-002
TEST_CASE(
    "command frame: channels are incompatible with an invalid output channel or a data ID confusable in the output's mode") {
    SafetyChannelConfig out;
    CommandChannelConfig cmd;
    out.safety_can_id = kCanMaxStandardId;  // the inverted copy would need 0x800
    CHECK(check_channels_compatible(out, cmd).error() == ErrorCode::kInvalidArgument);
    out = SafetyChannelConfig{};
    cmd.base_can_id = 0x200U;  // every output ID (0x101..0x104) lies below the command's IDs
    CHECK(check_channels_compatible(out, cmd).ok());
    // Part A's data ID shares only its low byte with the safety frame's: distinguishable in the
    // command's BOTH mode, not in the output's LOW mode.
    cmd = CommandChannelConfig{};
    cmd.data_id[0] = static_cast<std::uint16_t>(0x1100U | (kDefaultSafetyDataId & 0xFFU));
    REQUIRE(check_command_channel_config(cmd).ok());
    CHECK(check_channels_compatible(out, cmd).ok());
    out.data_id_mode = E2eP01DataIdMode::kLow;
    CHECK(check_channels_compatible(out, cmd).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-CMD-001
TEST_CASE("command frame: a sample whose command is not well formed encodes to no frames but an error") {
    RobotCommand c = six_axis();
    c.monitoring_case = kMaxMonitoringCases;
    const Result<CommandFrames> r = encode_command_sample(c, 0U, channel());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error() == ErrorCode::kInvalidArgument);
    CHECK(encode_command_sample(six_axis(), 15U, channel()).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-CMD-003, SR-GEN-003
TEST_CASE("command frame: checking a part that is not A, B or C, or under an invalid config, is a contract violation") {
    const CanFrame f = encode_command_part(six_axis(), CommandPart::kA, 0U, channel()).value();
    CHECK(test::violates_contract([&] { (void)check(f, static_cast<CommandPart>(3)); }));
    CommandChannelConfig bad = channel();
    bad.base_can_id = 0x800U;
    CHECK(test::violates_contract([&] { (void)check(f, CommandPart::kA, bad); }));
    CHECK_FALSE(test::violates_contract([&] { (void)check(f, CommandPart::kA); }));
}
