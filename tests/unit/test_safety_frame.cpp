// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: safety, diagnostics and separation frame encoding, inverted copy, field-by-field decoding, channel config rules.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "cellguard/can/safety_frame.hpp"
#include "cellguard/can/separation_frame.hpp"
#include "contract_capture.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {

constexpr E2eP01DataIdMode kAllModes[] = {E2eP01DataIdMode::kBoth, E2eP01DataIdMode::kAlt, E2eP01DataIdMode::kLow,
                                          E2eP01DataIdMode::kNibble};

SafetyChannelConfig channel(E2eP01DataIdMode mode = E2eP01DataIdMode::kBoth) {
    SafetyChannelConfig c;
    c.data_id_mode = mode;
    return c;
}

SafetyMessage sample_message() {
    SafetyMessage m;
    m.protective_stop = true;
    m.warning = false;
    m.fault = true;
    m.zone_intrusion = 0x0201U;
    m.zone_unseen = 0x0402U;
    m.zone_count = 11U;
    return m;
}

/// Recomputes the CRC of @p f after a test changed its content on purpose.
void reprotect(CanFrame& f, std::uint16_t data_id, E2eP01DataIdMode mode) {
    const auto counter = static_cast<std::uint8_t>(get_signal(f, safety_layout::kCounter));
    f.data[0] = e2e_p01_crc(Span<const std::uint8_t>(f.data, 8U), 0U, data_id, mode, counter);
}

FrameCheck check(const CanFrame& f, const SafetyChannelConfig& c) {
    SafetyFrameContent out;
    return check_safety_frame(f, c, out);
}

}  // namespace

// verifies: SR-CAN-002
TEST_CASE("safety frame: the encoder puts every field at the bit the layout table names") {
    const CanFrame f = encode_safety_frame(sample_message(), 9U, channel()).value();
    CHECK(f.id == 0x101U);
    CHECK(f.dlc == 8U);
    CHECK(f.data[1] == 0x09);  // counter 9, no nibble outside NIBBLE mode
    CHECK(f.data[2] == 0x05);  // stop (bit 16) and fault (bit 18)
    CHECK(f.data[3] == 0x01);  // ZoneIntrusion 0x0201, little-endian
    CHECK(f.data[4] == 0x02);
    CHECK(f.data[5] == 0x02);  // ZoneUnseen 0x0402
    CHECK(f.data[6] == 0x04);
    CHECK(f.data[7] == 11U);  // ZoneCount
    CHECK(f.data[0] ==
          e2e_p01_crc(Span<const std::uint8_t>(f.data, 8U), 0U, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth, 9U));
    const CanFrame n = encode_safety_frame(sample_message(), 9U, channel(E2eP01DataIdMode::kNibble)).value();
    CHECK(n.data[1] == 0xC9);  // data ID 0x0C51: nibble 0xC in bits 12..15
}

// verifies: SR-CAN-001, SR-CAN-002
TEST_CASE("safety frame: every counter and every data ID mode decodes back to what was encoded") {
    for (const E2eP01DataIdMode mode : kAllModes) {
        for (std::uint8_t counter = 0U; counter <= kE2eP01CounterMax; ++counter) {
            const CanFrame f = encode_safety_frame(sample_message(), counter, channel(mode)).value();
            const SafetyFrameContent c = decode_safety_frame(f, channel(mode)).value();
            CHECK(c.counter == counter);
            CHECK(c.message == sample_message());
        }
    }
    SafetyMessage all;
    all.protective_stop = false;
    all.warning = true;
    all.zone_count = 16U;
    all.zone_intrusion = 0xFFFFU;
    all.zone_unseen = 0x8001U;
    CHECK(decode_safety_frame(encode_safety_frame(all, 0U, channel()).value(), channel()).value().message == all);
}

// verifies: SR-CAN-003
TEST_CASE("safety frame: the inverted copy is on the next CAN ID with every data bit inverted") {
    const CanFrame f = encode_safety_frame(sample_message(), 3U, channel()).value();
    const CanFrame inv = inverted_copy(f);
    CHECK(inv.id == 0x102U);
    CHECK(inv.id == inverted_can_id(channel()));
    CHECK(inv.dlc == 8U);
    for (std::size_t k = 0U; k < 8U; ++k) {
        CHECK((f.data[k] ^ inv.data[k]) == 0xFF);
    }
    CHECK(check(inv, channel()) == FrameCheck::kWrongCanId);  // a copy is not a safety frame
    CHECK(inverted_copy(inv).data[5] == f.data[5]);
}

// verifies: SR-CAN-003
TEST_CASE("safety frame: with the default data IDs, inverted data never passes the check on the frame's own ID") {
    for (const E2eP01DataIdMode mode : kAllModes) {
        for (std::uint8_t counter = 0U; counter <= kE2eP01CounterMax; ++counter) {
            CanFrame inv = inverted_copy(encode_safety_frame(sample_message(), counter, channel(mode)).value());
            inv.id = kDefaultSafetyCanId;
            CHECK(check(inv, channel(mode)) != FrameCheck::kOk);
        }
    }
}

// verifies: SR-CAN-004
TEST_CASE("safety frame: every single flipped bit is caught by the CRC") {
    for (const E2eP01DataIdMode mode : kAllModes) {
        const CanFrame good = encode_safety_frame(sample_message(), 6U, channel(mode)).value();
        for (unsigned bit = 0U; bit < 64U; ++bit) {
            CanFrame f = good;
            f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] ^ (1U << (bit % 8U)));
            const FrameCheck r = check(f, channel(mode));
            if (mode == E2eP01DataIdMode::kNibble && bit >= 12U && bit < 16U) {
                CHECK(r == FrameCheck::kWrongDataIdNibble);
            } else {
                CHECK(r == FrameCheck::kWrongCrc);
            }
        }
    }
}

// verifies: SR-CAN-004
TEST_CASE("safety frame: a frame protected with another data ID is rejected") {
    SafetyChannelConfig other = channel();
    other.safety_data_id = 0x0C52U;
    const CanFrame f = encode_safety_frame(sample_message(), 4U, other).value();
    CHECK(check(f, channel()) == FrameCheck::kWrongCrc);
    CHECK(decode_safety_frame(f, channel()).error() == ErrorCode::kCrcMismatch);
    // NIBBLE mode: a different high nibble is seen explicitly, a different low byte by the CRC.
    SafetyChannelConfig nib_other = channel(E2eP01DataIdMode::kNibble);
    nib_other.safety_data_id = 0x0B51U;
    CHECK(check(encode_safety_frame(sample_message(), 4U, nib_other).value(), channel(E2eP01DataIdMode::kNibble)) ==
          FrameCheck::kWrongDataIdNibble);
    nib_other.safety_data_id = 0x0C50U;
    CHECK(check(encode_safety_frame(sample_message(), 4U, nib_other).value(), channel(E2eP01DataIdMode::kNibble)) ==
          FrameCheck::kWrongCrc);
}

// verifies: SR-CAN-004
TEST_CASE("safety frame: the decoder checks the CAN ID, the length, the counter range and every content field") {
    const SafetyChannelConfig c = channel();
    const CanFrame good = encode_safety_frame(sample_message(), 2U, c).value();
    CHECK(check(good, c) == FrameCheck::kOk);

    CanFrame f = good;
    f.id = 0x100U;
    CHECK(check(f, c) == FrameCheck::kWrongCanId);
    f = good;
    f.dlc = 7U;
    CHECK(check(f, c) == FrameCheck::kWrongLength);
    CHECK(decode_safety_frame(f, c).error() == ErrorCode::kTruncatedInput);
    f.dlc = 15U;
    CHECK(check(f, c) == FrameCheck::kWrongLength);

    f = good;  // counter 15 with a correct CRC: a sender error
    set_signal(f, safety_layout::kCounter, 15U);
    reprotect(f, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth);
    CHECK(check(f, c) == FrameCheck::kCounterOutOfRange);

    for (unsigned bit = 19U; bit <= 23U; ++bit) {  // once reserved, now ActiveCase and ReducedSpeed: accepted
        f = good;
        f.data[2] = static_cast<std::uint8_t>(f.data[2] | (1U << (bit - 16U)));
        reprotect(f, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth);
        CHECK(check(f, c) == FrameCheck::kOk);
    }
    CHECK(safety_layout::kReservedBits == 0U);
    f = good;  // the nibble is reserved outside NIBBLE mode
    set_signal(f, safety_layout::kDataIdNibble, 0xCU);
    reprotect(f, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth);
    CHECK(check(f, c) == FrameCheck::kMalformedContent);
    f = good;  // more zones than a frame carries
    set_signal(f, safety_layout::kZoneCount, 17U);
    reprotect(f, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth);
    CHECK(check(f, c) == FrameCheck::kMalformedContent);
    f = good;  // an intrusion bit at the zone count (zones 0..10 exist)
    set_signal(f, safety_layout::kZoneIntrusion, 0x0801U);
    reprotect(f, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth);
    CHECK(check(f, c) == FrameCheck::kMalformedContent);
    f = good;  // an unseen bit above the zone count
    set_signal(f, safety_layout::kZoneUnseen, 0x8000U);
    reprotect(f, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth);
    CHECK(check(f, c) == FrameCheck::kMalformedContent);
    CHECK(decode_safety_frame(f, c).error() == ErrorCode::kMalformedInput);

    SafetyFrameContent untouched;
    untouched.counter = 99U;
    CHECK(check_safety_frame(f, c, untouched) == FrameCheck::kMalformedContent);
    CHECK(untouched.counter == 99U);  // a rejected frame writes nothing
}

// verifies: SR-CAN-002
TEST_CASE("safety frame: the encoder refuses a counter above 14, more than 16 zones and zone bits beyond the count") {
    CHECK(encode_safety_frame(sample_message(), 15U, channel()).error() == ErrorCode::kInvalidArgument);
    SafetyMessage m = sample_message();
    m.zone_count = 17U;
    CHECK(encode_safety_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = sample_message();
    m.zone_intrusion = 0x0800U;  // zone 11 with 11 zones (0..10)
    CHECK(encode_safety_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = sample_message();
    m.zone_unseen = 0x1000U;
    CHECK(encode_safety_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    SafetyChannelConfig bad = channel();
    bad.safety_can_id = 0x7FFU;
    CHECK(encode_safety_frame(sample_message(), 0U, bad).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-CAN-010
TEST_CASE("safety frame: a channel config needs 11-bit IDs, four distinct CAN IDs and distinguishable data IDs") {
    CHECK(check_channel_config(SafetyChannelConfig{}).ok());
    for (const E2eP01DataIdMode mode : kAllModes) {
        CHECK(check_channel_config(channel(mode)).ok());  // the defaults work in every mode
    }
    SafetyChannelConfig c;
    c.safety_can_id = 0x7FFU;  // its copy would need ID 0x800
    CHECK(check_channel_config(c).error() == ErrorCode::kInvalidArgument);
    c = SafetyChannelConfig{};
    c.diagnostics_can_id = 0x800U;
    CHECK_FALSE(check_channel_config(c).ok());
    c = SafetyChannelConfig{};
    c.diagnostics_can_id = c.safety_can_id + 1U;
    CHECK_FALSE(check_channel_config(c).ok());
    c = SafetyChannelConfig{};
    c.diagnostics_can_id = c.safety_can_id;
    CHECK_FALSE(check_channel_config(c).ok());
    c = SafetyChannelConfig{};
    c.safety_data_id = 0x0000U;
    c.diagnostics_data_id = 0x1D01U;  // same CRC for all data in BOTH mode (bytes 01 1D)
    CHECK_FALSE(check_channel_config(c).ok());
    c = channel(E2eP01DataIdMode::kNibble);
    c.safety_data_id = 0x1C51U;  // 13 bits
    CHECK_FALSE(check_channel_config(c).ok());
    c = channel(E2eP01DataIdMode::kLow);
    c.diagnostics_data_id = 0x0D51U;  // same low byte as the safety data ID
    CHECK_FALSE(check_channel_config(c).ok());
    for (const std::uint32_t id : {0x101U, 0x102U, 0x103U, 0x800U}) {  // the separation frame's ID
        c = SafetyChannelConfig{};
        c.separation_can_id = id;
        CHECK_FALSE(check_channel_config(c).ok());
    }
    c = SafetyChannelConfig{};
    c.separation_data_id = kDefaultSafetyDataId;
    CHECK_FALSE(check_channel_config(c).ok());
    c = channel(E2eP01DataIdMode::kAlt);
    c.separation_data_id = 0x0D99U;  // the diagnostics data ID's high byte: odd counters collide
    CHECK_FALSE(check_channel_config(c).ok());
    c = SafetyChannelConfig{};
    c.data_id_mode = static_cast<E2eP01DataIdMode>(7);
    CHECK_FALSE(check_channel_config(c).ok());
    SafetyFrameContent out;
    const CanFrame f{0x101U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    CHECK(test::violates_contract([&] { (void)check_safety_frame(f, c, out); }));
}

// verifies: SR-CAN-005
TEST_CASE("safety frame: the diagnostics frame round-trips every prior CRC page and carries its own data ID") {
    const std::uint32_t prior_crc = 0xDEADBEEFU;
    for (const E2eP01DataIdMode mode : kAllModes) {
        for (std::uint8_t page = 0U; page < 4U; ++page) {
            DiagnosticsMessage m;
            m.cycle_time = diagnostics_time_saturating(33350U);
            m.max_cycle_time = kDiagnosticsTimeSaturated;
            m.active_faults = static_cast<std::uint16_t>(fault_bit(FaultCode::kCanBusOff) |
                                                         fault_bit(FaultCode::kCanSendFailed));
            m.prior_crc_page = page;
            m.prior_crc_part = prior_crc_part(prior_crc, page);
            const CanFrame f = encode_diagnostics_frame(m, page, channel(mode)).value();
            CHECK(f.id == kDefaultDiagnosticsCanId);
            CHECK(get_signal(f, diagnostics_layout::kPriorCrcPage) == page);
            CHECK(f.data[7] == ((prior_crc >> (8U * page)) & 0xFFU));
            const DiagnosticsFrameContent c = decode_diagnostics_frame(f, channel(mode)).value();
            CHECK(c.message == m);
            CHECK(c.counter == page);
            // A diagnostics frame never passes as a safety frame, even on the safety CAN ID.
            CanFrame moved = f;
            moved.id = kDefaultSafetyCanId;
            CHECK(check(moved, channel(mode)) != FrameCheck::kOk);
        }
    }
    const CanFrame f = encode_diagnostics_frame(DiagnosticsMessage{}, 0U, channel()).value();
    CHECK(get_signal(f, diagnostics_layout::kCycleTime) == 0U);
    CanFrame g = f;
    g.data[3] = 0x80U;  // fault bit 15: FaultCode::kCommandInvalid
    reprotect(g, kDefaultDiagnosticsDataId, E2eP01DataIdMode::kBoth);
    DiagnosticsFrameContent out;
    REQUIRE(check_diagnostics_frame(g, channel(), out) == FrameCheck::kOk);
    CHECK(out.message.active_faults == fault_bit(FaultCode::kCommandInvalid));
    g = f;
    g.data[6] = static_cast<std::uint8_t>(g.data[6] ^ 0x01U);
    CHECK(check_diagnostics_frame(g, channel(), out) == FrameCheck::kWrongCrc);
    CHECK(decode_diagnostics_frame(g, channel()).error() == ErrorCode::kCrcMismatch);
}

// verifies: SR-CAN-005
TEST_CASE("safety frame: cycle times are sent in 100 us units, rounded up and saturating at 2047") {
    CHECK(diagnostics_time_saturating(0U) == 0U);
    CHECK(diagnostics_time_saturating(1U) == 1U);
    CHECK(diagnostics_time_saturating(100U) == 1U);
    CHECK(diagnostics_time_saturating(101U) == 2U);
    CHECK(diagnostics_time_saturating(204700U) == 2047U);
    CHECK(diagnostics_time_saturating(204701U) == 2047U);
    CHECK(diagnostics_time_saturating(UINT64_MAX) == 2047U);
    DiagnosticsMessage m;
    m.cycle_time = 2048U;
    CHECK(encode_diagnostics_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = DiagnosticsMessage{};
    m.prior_crc_page = 4U;
    CHECK(encode_diagnostics_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = DiagnosticsMessage{};
    m.active_faults = kAssignedFaultBits;  // every assigned bit at once is valid
    CHECK(encode_diagnostics_frame(m, 0U, channel()).ok());
    CHECK(encode_diagnostics_frame(DiagnosticsMessage{}, 15U, channel()).error() == ErrorCode::kInvalidArgument);
    CHECK(prior_crc_part(0x11223344U, 0U) == 0x44U);
    CHECK(prior_crc_part(0x11223344U, 3U) == 0x11U);
    CHECK(test::violates_contract([] { (void)prior_crc_part(0U, 4U); }));
}

// verifies: SR-CAN-005
TEST_CASE(
    "safety frame: fault codes 0..8 and 15 are the safety logic's Fault bits, 9..14 the CAN details, and every check has a name and an error code") {
    for (std::uint8_t f = 0U; f < 9U; ++f) {
        CHECK(fault_bit(static_cast<FaultCode>(f)) == fault_bit(static_cast<Fault>(f)));
    }
    CHECK(fault_bit(FaultCode::kSensorStale) == 0x0001U);
    CHECK(fault_bit(FaultCode::kZoneEvaluation) == 0x0100U);
    CHECK(fault_bit(FaultCode::kCanTxBufferFull) == 0x0200U);
    CHECK(fault_bit(FaultCode::kCanSendFailed) == 0x4000U);
    CHECK(fault_bit(FaultCode::kCommandInvalid) == 0x8000U);
    CHECK(wire_fault_bits(fault_bit(Fault::kCommandInvalid)) == 0x8000U);
    CHECK(wire_fault_bits(fault_bit(Fault::kZoneEvaluation)) == 0x0100U);
    CHECK(wire_fault_bits(0xFFFFFC00U) == 0U);  // bits beyond the Faults are dropped
    CHECK(kSafetyLogicFaultBits == 0x81FFU);
    CHECK(kCanDetailFaultBits == 0x7E00U);
    CHECK((kSafetyLogicFaultBits | kCanDetailFaultBits) == kAssignedFaultBits);
    CHECK(std::string(to_string(FrameCheck::kWrongCrc)) == "wrong CRC");
    CHECK(std::string(to_string(static_cast<FrameCheck>(200))) == "unknown frame check");
    CHECK(to_error_code(FrameCheck::kOk) == ErrorCode::kOk);
    CHECK(to_error_code(FrameCheck::kWrongDataIdNibble) == ErrorCode::kCrcMismatch);
    CHECK(to_error_code(FrameCheck::kCounterOutOfRange) == ErrorCode::kMalformedInput);
    CHECK(to_error_code(FrameCheck::kWrongCanId) == ErrorCode::kMalformedInput);
    const SafetyMessage defaults;
    CHECK(defaults.protective_stop);  // a default message is the safe state
}

// verifies: SR-GEN-004
TEST_CASE(
    "safety frame: every frame check result has its own name, and a value outside the enumeration has the fallback name") {
    test::check_enum_names<FrameCheck>(7U, "unknown frame check");
}

// verifies: SR-CMD-008
TEST_CASE("safety frame: ActiveCase takes bits 19..22 and ReducedSpeed bit 23, every case round-trips, stop wins") {
    SafetyMessage m = sample_message();
    m.active_case = 9U;
    m.reduced_speed = true;
    const CanFrame f = encode_safety_frame(m, 1U, channel()).value();
    CHECK(f.data[2] == (0x05 | (9 << 3) | 0x80));  // stop, fault, case 9 in bits 19..22, reduced in bit 23
    CHECK(get_signal(f, safety_layout::kActiveCase) == 9U);
    CHECK(get_signal(f, safety_layout::kReducedSpeed) == 1U);
    CHECK(decode_safety_frame(f, channel()).value().message == m);  // stop and reduced together: valid
    for (std::uint8_t k = 0U; k <= kMaxActiveCase; ++k) {
        m.active_case = k;
        m.reduced_speed = (k % 2U) == 0U;
        CHECK(decode_safety_frame(encode_safety_frame(m, k % 15U, channel()).value(), channel()).value().message == m);
    }
    m.active_case = 16U;
    CHECK(encode_safety_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    CHECK(SafetyMessage{}.active_case == 0U);
    CHECK_FALSE(SafetyMessage{}.reduced_speed);
}

namespace {

SeparationMessage separation_sample() {
    SeparationMessage m;
    m.distance_mm = 1234U;
    m.required_mm = 0xABCDU;
    m.active_case = 7U;
    m.speed_request = SpeedRequest::kReduced;
    m.command_valid = true;
    m.command_counter = 13U;
    return m;
}

FrameCheck check_separation(const CanFrame& f, const SafetyChannelConfig& c) {
    SeparationFrameContent out;
    return check_separation_frame(f, c, out);
}

}  // namespace

// verifies: SR-CMD-008
TEST_CASE("separation frame: the encoder puts every field at its bit, and every counter and mode round-trips") {
    const CanFrame f = encode_separation_frame(separation_sample(), 4U, channel()).value();
    CHECK(f.id == 0x104U);
    CHECK(f.dlc == 8U);
    CHECK(f.data[1] == 0x04);
    CHECK(f.data[2] == 0xD2);  // distance 1234 = 0x04D2
    CHECK(f.data[3] == 0x04);
    CHECK(f.data[4] == 0xCD);  // required 0xABCD
    CHECK(f.data[5] == 0xAB);
    CHECK(f.data[6] == (7 | (1 << 4) | (1 << 6)));  // case 7, request 1 (bits 52..53), valid (bit 54)
    CHECK(f.data[7] == 13);                         // command counter
    CHECK(f.data[0] ==
          e2e_p01_crc(Span<const std::uint8_t>(f.data, 8U), 0U, kDefaultSeparationDataId, E2eP01DataIdMode::kBoth, 4U));
    for (const E2eP01DataIdMode mode : kAllModes) {
        for (std::uint8_t counter = 0U; counter <= kE2eP01CounterMax; ++counter) {
            SeparationMessage m = separation_sample();
            m.speed_request = static_cast<SpeedRequest>(counter % 3U);
            m.distance_mm = counter == 0U ? kSeparationDistanceFar : static_cast<std::uint16_t>(counter * 100U);
            const SeparationFrameContent c = decode_separation_frame(
                                                 encode_separation_frame(m, counter, channel(mode)).value(),
                                                 channel(mode))
                                                 .value();
            CHECK(c.counter == counter);
            CHECK(c.message == m);
        }
    }
}

// verifies: SR-CMD-008
TEST_CASE("separation frame: the decoder checks ID, length, CRC, its own data ID, reserved bits and ranges") {
    const SafetyChannelConfig c = channel();
    const CanFrame good = encode_separation_frame(separation_sample(), 2U, c).value();
    CHECK(check_separation(good, c) == FrameCheck::kOk);
    CanFrame f = good;
    f.id = kDefaultDiagnosticsCanId;
    CHECK(check_separation(f, c) == FrameCheck::kWrongCanId);
    f = good;
    f.dlc = 4U;
    CHECK(check_separation(f, c) == FrameCheck::kWrongLength);
    for (unsigned bit = 0U; bit < 64U; ++bit) {
        f = good;
        f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] ^ (1U << (bit % 8U)));
        CHECK(check_separation(f, c) == FrameCheck::kWrongCrc);
    }
    f = good;  // the diagnostics frame's data ID
    reprotect(f, kDefaultDiagnosticsDataId, E2eP01DataIdMode::kBoth);
    CHECK(check_separation(f, c) == FrameCheck::kWrongCrc);
    for (const unsigned bit : {55U, 60U, 61U, 62U, 63U}) {
        f = good;
        f.data[bit / 8U] = static_cast<std::uint8_t>(f.data[bit / 8U] | (1U << (bit % 8U)));
        reprotect(f, kDefaultSeparationDataId, E2eP01DataIdMode::kBoth);
        CHECK(check_separation(f, c) == FrameCheck::kMalformedContent);
    }
    f = good;
    set_signal(f, separation_layout::kSpeedRequest, 3U);
    reprotect(f, kDefaultSeparationDataId, E2eP01DataIdMode::kBoth);
    CHECK(check_separation(f, c) == FrameCheck::kMalformedContent);
    f = good;
    set_signal(f, separation_layout::kCommandCounter, 15U);
    reprotect(f, kDefaultSeparationDataId, E2eP01DataIdMode::kBoth);
    CHECK(decode_separation_frame(f, c).error() == ErrorCode::kMalformedInput);

    SeparationMessage m = separation_sample();
    CHECK(encode_separation_frame(m, 15U, c).error() == ErrorCode::kInvalidArgument);
    m.active_case = 16U;
    CHECK_FALSE(encode_separation_frame(m, 0U, c).ok());
    m = separation_sample();
    m.speed_request = static_cast<SpeedRequest>(3);
    CHECK_FALSE(encode_separation_frame(m, 0U, c).ok());
    m = separation_sample();
    m.command_counter = 15U;
    CHECK_FALSE(encode_separation_frame(m, 0U, c).ok());
    CHECK(SeparationMessage{}.speed_request == SpeedRequest::kProtectiveStop);
}

namespace {
/// True when @p m equals itself and differs from each of @p changed (copies of it with one field changed).
template <typename M, std::size_t N>
bool each_field_compared(const M& m, const M (&changed)[N]) {
    bool ok = m == m;
    for (const M& c : changed) {
        ok = ok && !(m == c) && !(c == m);
    }
    return ok;
}
}  // namespace

// verifies: SR-CAN-004
TEST_CASE("safety frame: the messages' equality compares every field") {
    const SafetyMessage s;
    SafetyMessage sc[8] = {s, s, s, s, s, s, s, s};
    sc[0].protective_stop = false;
    sc[1].warning = true;
    sc[2].fault = true;
    sc[3].active_case = 1U;
    sc[4].reduced_speed = true;
    sc[5].zone_intrusion = 1U;
    sc[6].zone_unseen = 1U;
    sc[7].zone_count = 1U;
    CHECK(each_field_compared(s, sc));
    CHECK_FALSE(s != s);
    CHECK(s != sc[7]);
    const DiagnosticsMessage d;
    DiagnosticsMessage dc[5] = {d, d, d, d, d};
    dc[0].cycle_time = 1U;
    dc[1].max_cycle_time = 1U;
    dc[2].active_faults = 1U;
    dc[3].prior_crc_page = 1U;
    dc[4].prior_crc_part = 1U;
    CHECK(each_field_compared(d, dc));
    const SeparationMessage p;
    SeparationMessage pc[6] = {p, p, p, p, p, p};
    pc[0].distance_mm = 1U;
    pc[1].required_mm = 1U;
    pc[2].active_case = 1U;
    pc[3].speed_request = SpeedRequest::kFull;
    pc[4].command_valid = true;
    pc[5].command_counter = 1U;
    CHECK(each_field_compared(p, pc));
}

// verifies: SR-CAN-004, SR-GEN-003
TEST_CASE("safety frame: checking a diagnostics frame under an invalid channel configuration is a contract violation") {
    SafetyChannelConfig c;
    c.data_id_mode = static_cast<E2eP01DataIdMode>(7);
    DiagnosticsFrameContent out;
    const CanFrame f{0x102U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    CHECK(test::violates_contract([&] { (void)check_diagnostics_frame(f, c, out); }));
    CHECK_FALSE(test::violates_contract([&] { (void)check_diagnostics_frame(f, SafetyChannelConfig{}, out); }));
}

// verifies: SR-CAN-005
TEST_CASE(
    "safety frame: the diagnostics encoder refuses a bad config, counter 15, a cycle time above 2047 and page 4") {
    const DiagnosticsMessage good;
    REQUIRE(encode_diagnostics_frame(good, 14U, channel()).ok());
    SafetyChannelConfig bad = channel();
    bad.diagnostics_can_id = 0x800U;
    CHECK(encode_diagnostics_frame(good, 0U, bad).error() == ErrorCode::kInvalidArgument);
    CHECK(encode_diagnostics_frame(good, 15U, channel()).error() == ErrorCode::kInvalidArgument);
    DiagnosticsMessage m = good;
    m.cycle_time = kDiagnosticsTimeSaturated + 1U;
    CHECK(encode_diagnostics_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = good;
    m.max_cycle_time = kDiagnosticsTimeSaturated + 1U;
    CHECK(encode_diagnostics_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = good;
    m.prior_crc_page = 4U;
    CHECK(encode_diagnostics_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-CMD-008
TEST_CASE("separation frame: the encoder refuses a bad config, counter 15, case 16, request 3 and command counter 15") {
    const SeparationMessage good = separation_sample();
    REQUIRE(encode_separation_frame(good, 14U, channel()).ok());
    SafetyChannelConfig bad = channel();
    bad.separation_can_id = bad.diagnostics_can_id;
    CHECK(encode_separation_frame(good, 0U, bad).error() == ErrorCode::kInvalidArgument);
    CHECK(encode_separation_frame(good, 15U, channel()).error() == ErrorCode::kInvalidArgument);
    SeparationMessage m = good;
    m.active_case = kMaxActiveCase + 1U;
    CHECK(encode_separation_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = good;
    m.speed_request = static_cast<SpeedRequest>(3);
    CHECK(encode_separation_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
    m = good;
    m.command_counter = 15U;
    CHECK(encode_separation_frame(m, 0U, channel()).error() == ErrorCode::kInvalidArgument);
}

// verifies: SR-CMD-008, SR-GEN-003
TEST_CASE("separation frame: checking a frame under an invalid channel configuration is a contract violation") {
    SafetyChannelConfig c;
    c.separation_can_id = c.safety_can_id;
    SeparationFrameContent out;
    const CanFrame f = encode_separation_frame(separation_sample(), 0U, channel()).value();
    CHECK(test::violates_contract([&] { (void)check_separation_frame(f, c, out); }));
    CHECK_FALSE(test::violates_contract([&] { (void)check_separation_frame(f, channel(), out); }));
    CHECK(out.message == separation_sample());
}

// verifies: SR-CAN-010
TEST_CASE("safety frame: in NIBBLE mode a channel config with a data ID above 12 bits is refused") {
    SafetyChannelConfig c = channel(E2eP01DataIdMode::kNibble);
    REQUIRE(check_channel_config(c).ok());
    c.diagnostics_data_id = 0x1D52U;
    CHECK(check_channel_config(c).error() == ErrorCode::kInvalidArgument);
    c.data_id_mode = E2eP01DataIdMode::kBoth;
    CHECK(check_channel_config(c).ok());
}

// verifies: SR-CAN-004
TEST_CASE("safety frame: each frame check maps to its error code, and a value outside the enumeration is malformed") {
    CHECK(to_error_code(FrameCheck::kOk) == ErrorCode::kOk);
    CHECK(to_error_code(FrameCheck::kWrongCanId) == ErrorCode::kMalformedInput);
    CHECK(to_error_code(FrameCheck::kWrongLength) == ErrorCode::kTruncatedInput);
    CHECK(to_error_code(FrameCheck::kWrongDataIdNibble) == ErrorCode::kCrcMismatch);
    CHECK(to_error_code(FrameCheck::kWrongCrc) == ErrorCode::kCrcMismatch);
    CHECK(to_error_code(FrameCheck::kCounterOutOfRange) == ErrorCode::kMalformedInput);
    CHECK(to_error_code(FrameCheck::kMalformedContent) == ErrorCode::kMalformedInput);
    CHECK(to_error_code(static_cast<FrameCheck>(42)) == ErrorCode::kMalformedInput);
}

// verifies: SR-CAN-005, SR-GEN-003
TEST_CASE("safety frame: the prior CRC has four pages, byte by byte, and a fifth page is a contract violation") {
    CHECK(prior_crc_part(0xDEADBEEFU, 0U) == 0xEFU);
    CHECK(prior_crc_part(0xDEADBEEFU, 3U) == 0xDEU);
    std::uint8_t part = 0U;
    CHECK(test::violates_contract([&] { part = prior_crc_part(0xDEADBEEFU, 4U); }));
    CHECK(part == 0U);
}
