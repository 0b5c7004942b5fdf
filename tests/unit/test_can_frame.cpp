// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: Intel signal placement in a CAN frame, layout table consistency checks.
#include <doctest/doctest.h>

#include <cstdint>

#include "cellguard/can/can_frame.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

constexpr SignalLayout make(const char* name, std::uint8_t start, std::uint8_t length, Multiplex mux = Multiplex::kNone,
                            std::uint8_t mux_value = 0U) {
    return SignalLayout{name,
                        start,
                        length,
                        ByteOrder::kIntel,
                        1U,
                        "",
                        static_cast<std::uint32_t>((std::uint64_t{1} << length) - 1U),
                        mux,
                        mux_value};
}

constexpr SignalLayout kGood[] = {make("a", 0U, 8U), make("b", 8U, 4U), make("sel", 12U, 2U, Multiplex::kMultiplexor),
                                  make("m0", 16U, 8U, Multiplex::kMultiplexed, 0U),
                                  make("m1", 16U, 8U, Multiplex::kMultiplexed, 1U)};
constexpr SignalLayout kOverlap[] = {make("a", 0U, 8U), make("b", 7U, 4U)};
constexpr SignalLayout kOutside[] = {make("a", 60U, 8U)};
constexpr SignalLayout kMotorola[] = {
    SignalLayout{"a", 0U, 8U, ByteOrder::kMotorola, 1U, "", 255U, Multiplex::kNone, 0U}};
constexpr SignalLayout kRawMaxTooWide[] = {
    SignalLayout{"a", 0U, 4U, ByteOrder::kIntel, 1U, "", 16U, Multiplex::kNone, 0U}};

}  // namespace

// verifies: SR-CAN-002
TEST_CASE("can frame: layout checks accept multiplexed signals sharing bits and reject overlaps and overflows") {
    static_assert(layout_is_consistent(kGood), "multiplexed signals of different pages may share bits");
    static_assert(!layout_is_consistent(kOverlap), "bit 7 used twice");
    static_assert(!layout_is_consistent(kOutside), "signal past bit 63");
    static_assert(!layout_is_consistent(kMotorola), "only Intel signals");
    static_assert(!layout_is_consistent(kRawMaxTooWide), "raw_max must fit in the length");
    CHECK(layout_used_bits(kGood) == 0x0000'0000'00FF'3FFFULL);
    CHECK(signal_mask(make("x", 12U, 4U)) == 0xF000U);
}

// verifies: SR-CAN-002
TEST_CASE("can frame: the layout check run on tables made at run time rejects each bad field") {
    // The same check as the static_asserts, evaluated at run time on tables that differ
    // from a good one in one field each: every clause of layout_is_consistent refuses.
    const auto one = [](SignalLayout s) {
        const SignalLayout table[] = {s};
        return layout_is_consistent(table);
    };
    const SignalLayout good = make("a", 8U, 8U);
    CHECK(one(good));
    SignalLayout s = good;
    s.byte_order = ByteOrder::kMotorola;
    CHECK_FALSE(one(s));
    s = good;
    s.length = 0U;
    CHECK_FALSE(one(s));
    s = good;
    s.length = 33U;
    CHECK_FALSE(one(s));
    s = good;
    s.start_bit = 57U;  // 57 + 8 > 64
    CHECK_FALSE(one(s));
    s = good;
    s.factor = 0U;
    CHECK_FALSE(one(s));
    s = good;
    s.raw_max = 256U;  // does not fit in 8 bits
    CHECK_FALSE(one(s));
    s = make("w", 0U, 32U);
    s.raw_max = 0xFFFFFFFFU;  // a 32-bit signal: any raw_max fits
    CHECK(one(s));
    s = good;
    s.is_signed = true;
    s.raw_max = 127U;
    CHECK(one(s));
    s.raw_max = 128U;  // does not fit in 7 bits plus sign
    CHECK_FALSE(one(s));
    s = make("b", 8U, 1U);
    s.is_signed = true;
    s.raw_max = 0U;  // a signed signal needs 2 bits at least
    CHECK_FALSE(one(s));
    const SignalLayout same_page[] = {make("m0", 16U, 8U, Multiplex::kMultiplexed, 1U),
                                      make("m1", 20U, 8U, Multiplex::kMultiplexed, 1U)};
    CHECK_FALSE(layout_is_consistent(same_page));  // same selector value: they coexist and overlap
    const SignalLayout other_page[] = {make("m0", 16U, 8U, Multiplex::kMultiplexed, 1U),
                                       make("m1", 20U, 8U, Multiplex::kMultiplexed, 2U)};
    CHECK(layout_is_consistent(other_page));
    const SignalLayout mux_and_plain[] = {make("m0", 16U, 8U, Multiplex::kMultiplexed, 1U), make("p", 20U, 8U)};
    CHECK_FALSE(layout_is_consistent(mux_and_plain));
}

// verifies: SR-CAN-002
TEST_CASE("can frame: an Intel signal's start bit is its least significant bit, byte 0 first") {
    CanFrame f{0x100U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    set_signal(f, make("word", 24U, 16U), 0xBEEFU);
    CHECK(f.data[3] == 0xEF);
    CHECK(f.data[4] == 0xBE);
    set_signal(f, make("nibble", 12U, 4U), 0xAU);
    CHECK(f.data[1] == 0xA0);
    set_signal(f, make("bit", 18U, 1U), 1U);
    CHECK(f.data[2] == 0x04);
    set_signal(f, make("odd", 43U, 11U), 0x7FFU);  // bits 43..53: byte 5 bits 3..7, byte 6 bits 0..5
    CHECK(f.data[5] == 0xF8);
    CHECK(f.data[6] == 0x3F);
    CHECK(get_signal(f, make("word", 24U, 16U)) == 0xBEEFU);
    CHECK(get_signal(f, make("odd", 43U, 11U)) == 0x7FFU);
    CHECK(frame_bits(f) == 0x003F'F8BE'EF04'A000ULL);
}

// verifies: SR-CAN-002
TEST_CASE("can frame: writing a signal leaves every other bit as it was") {
    CanFrame f{0x100U, 8U, {0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU}};
    set_signal(f, make("mid", 20U, 9U), 0U);
    CHECK(frame_bits(f) == ~(std::uint64_t{0x1FF} << 20U));
}

// verifies: SR-CAN-002, SR-GEN-003
TEST_CASE("can frame: a value wider than its signal, or a Motorola signal, is a contract violation") {
    CanFrame f{0x100U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    CHECK(test::violates_contract([&] { set_signal(f, make("n", 8U, 4U), 16U); }));
    CHECK(test::violates_contract([&] { (void)get_signal(f, kMotorola[0]); }));
    CHECK_FALSE(test::violates_contract([&] { set_signal(f, make("n", 8U, 4U), 15U); }));
}

// verifies: SR-CAN-002
TEST_CASE("can frame: the run-time layout check compares plain signals pairwise and pages only with pages") {
    const SignalLayout plain_overlap[] = {make("a", 0U, 8U), make("b", 4U, 8U)};
    CHECK_FALSE(layout_is_consistent(plain_overlap));
    const SignalLayout plain_disjoint[] = {make("a", 0U, 8U), make("b", 8U, 8U)};
    CHECK(layout_is_consistent(plain_disjoint));
    const SignalLayout plain_then_mux[] = {make("p", 20U, 8U), make("m0", 16U, 8U, Multiplex::kMultiplexed, 1U)};
    CHECK_FALSE(layout_is_consistent(plain_then_mux));
    const SignalLayout pages_disjoint[] = {make("m0", 0U, 8U, Multiplex::kMultiplexed, 1U),
                                           make("m1", 8U, 8U, Multiplex::kMultiplexed, 1U)};
    CHECK(layout_is_consistent(pages_disjoint));
    CHECK(signals_coexist(make("a", 0U, 8U), make("b", 0U, 8U)));
    CHECK(signals_coexist(make("a", 0U, 8U), make("m", 0U, 8U, Multiplex::kMultiplexed, 3U)));
    CHECK(signals_coexist(make("m", 0U, 8U, Multiplex::kMultiplexed, 3U), make("a", 0U, 8U)));
    CHECK(signals_coexist(make("m", 0U, 8U, Multiplex::kMultiplexed, 3U),
                          make("n", 0U, 8U, Multiplex::kMultiplexed, 3U)));
    CHECK_FALSE(signals_coexist(make("m", 0U, 8U, Multiplex::kMultiplexed, 3U),
                                make("n", 0U, 8U, Multiplex::kMultiplexed, 4U)));
}

// verifies: SR-CAN-002
TEST_CASE("can frame: a 32-bit signal takes any raw value, and a signed signal round-trips its extremes") {
    CanFrame f{0x100U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    const SignalLayout wide = make("w", 32U, 32U);
    set_signal(f, wide, 0xFFFFFFFFU);
    CHECK(get_signal(f, wide) == 0xFFFFFFFFU);
    CHECK(frame_bits(f) == 0xFFFF'FFFF'0000'0000ULL);
    SignalLayout s = make("s", 0U, 12U);
    s.is_signed = true;
    set_signed_signal(f, s, -2048);
    CHECK(get_signed_signal(f, s) == -2048);
    set_signed_signal(f, s, 2047);
    CHECK(get_signed_signal(f, s) == 2047);
    CHECK(get_signal(f, wide) == 0xFFFFFFFFU);  // untouched
}

// verifies: SR-CAN-002, SR-GEN-003
TEST_CASE(
    "can frame: reading or writing a signal of 0 or 33 bits or past bit 63, or a 1-bit signed one, is a contract violation") {
    CanFrame f{0x100U, 8U, {0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U}};
    SignalLayout zero = make("z", 8U, 8U);
    zero.length = 0U;
    SignalLayout wide = make("w", 0U, 8U);
    wide.length = 33U;
    const SignalLayout past = make("p", 60U, 8U);
    std::uint32_t got = 7U;
    CHECK(test::violates_contract([&] { got = get_signal(f, zero); }));
    CHECK(test::violates_contract([&] { got = get_signal(f, wide); }));
    CHECK(test::violates_contract([&] { got = get_signal(f, past); }));
    CHECK(got == 7U);
    CHECK(test::violates_contract([&] { set_signal(f, kMotorola[0], 1U); }));
    CHECK(test::violates_contract([&] { set_signal(f, zero, 0U); }));
    CHECK(test::violates_contract([&] { set_signal(f, wide, 0U); }));
    CHECK(test::violates_contract([&] { set_signal(f, past, 0U); }));
    const SignalLayout one_bit = make("b", 0U, 1U);
    CHECK(test::violates_contract([&] { set_signed_signal(f, one_bit, 0); }));
    CHECK(test::violates_contract([&] { set_signed_signal(f, wide, 0); }));
    CHECK(test::violates_contract([&] { set_signed_signal(f, make("s", 0U, 8U), 128); }));
    CHECK(frame_bits(f) == 0U);  // nothing was written
}
