// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: PLC-side receiver: every injected fault gives the safe state with its reason; recovery; good path and counter wrap.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "cellguard/can/plc_receiver.hpp"
#include "contract_capture.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {

constexpr std::uint64_t kPeriodUs = 20000U;  // the sender's cycle
constexpr std::uint64_t kGapUs = 1000U;      // normal frame -> inverted copy

PlcReceiverConfig receiver_config() {
    PlcReceiverConfig c;
    c.srvt_us = 10000U;
    c.sct_us = 50000U;
    c.max_delta_counter = 1U;
    c.recovery_good_pairs = 2U;
    c.expected_zone_count = 4U;
    c.link.enabled = false;  // the protocol 0.1 checks; the session link's tests set up both sides
    return c;
}

SafetyMessage clear_message() {
    SafetyMessage m;
    m.protective_stop = false;
    m.zone_count = 4U;
    return m;
}

/// A sender and a PLC-side receiver on one simulated bus; time in microseconds.
struct Link {
    explicit Link(const PlcReceiverConfig& c = receiver_config()) : config(c), receiver(c) {}

    CanFrame next_frame(const SafetyMessage& m = clear_message()) {
        const CanFrame f = encode_safety_frame(m, counter, config.channel).value();
        counter = e2e_p01_next_counter(counter);
        return f;
    }
    ReceiverStatus deliver(const CanFrame& f, std::uint64_t at) {
        now = at;
        return receiver.on_frame(f, now);
    }
    /// One period later: the next frame and, kGapUs after it, its inverted copy.
    ReceiverStatus send_pair(const SafetyMessage& m = clear_message()) {
        const CanFrame f = next_frame(m);
        (void)deliver(f, now + kPeriodUs);
        return deliver(inverted_copy(f), now + kGapUs);
    }
    /// Sends pairs until the receiver is valid; returns how many it took.
    int bring_up() {
        int pairs = 0;
        while (!receiver.poll(now).communication_valid && pairs < 100) {
            (void)send_pair();
            ++pairs;
        }
        return pairs;
    }

    PlcReceiverConfig config;
    PlcReceiver receiver;
    std::uint8_t counter = 0U;
    std::uint64_t now = 1000000U;
};

void check_safe_state(const ReceiverStatus& s, ReceiverFault reason) {
    CHECK(s.stop_requested);
    CHECK_FALSE(s.communication_valid);
    CHECK(s.fault == reason);
    CHECK(s.message == safe_state_message(4U));
}

}  // namespace

// verifies: SR-CAN-007, SR-CAN-009
TEST_CASE("plc receiver: it starts in the safe state and needs a reference pair plus the recovery pairs") {
    Link link;
    check_safe_state(link.receiver.poll(link.now), ReceiverFault::kNoFrameYet);
    CHECK_FALSE(link.send_pair().communication_valid);  // reference pair: counter not yet checkable
    CHECK_FALSE(link.send_pair().communication_valid);  // good pair 1 of 2
    const ReceiverStatus s = link.send_pair();          // good pair 2 of 2
    CHECK(s.communication_valid);
    CHECK_FALSE(s.stop_requested);
    CHECK(s.fault == ReceiverFault::kNone);
    CHECK(s.message == clear_message());
    CHECK(s.fault_events == 0U);
}

// verifies: SR-CAN-007, SR-CAN-009
TEST_CASE(
    "plc receiver: on the good path it follows the frame's stop request and stays valid across the 14 -> 0 wrap") {
    Link link;
    CHECK(link.bring_up() == 3);
    SafetyMessage stop = clear_message();
    stop.protective_stop = true;
    stop.zone_intrusion = 0x4U;
    for (int i = 0; i < 40; ++i) {  // well past two wraps of the counter
        const bool want_stop = (i % 3) == 0;
        const ReceiverStatus s = link.send_pair(want_stop ? stop : clear_message());
        CHECK(s.communication_valid);
        CHECK(s.stop_requested == want_stop);
        CHECK(s.message == (want_stop ? stop : clear_message()));
        CHECK(link.receiver.poll(link.now + kPeriodUs - 1U).communication_valid);  // polled between pairs
    }
    CHECK(link.receiver.poll(link.now + kPeriodUs).fault_events == 0U);
}

// verifies: SR-CAN-007
TEST_CASE("plc receiver: a bad CRC gives the safe state with reason wrong CRC") {
    Link link;
    (void)link.bring_up();
    CanFrame f = link.next_frame();
    f.data[3] = static_cast<std::uint8_t>(f.data[3] ^ 0x10U);
    const ReceiverStatus s = link.deliver(f, link.now + kPeriodUs);
    check_safe_state(s, ReceiverFault::kWrongCrc);
    CHECK(s.fault_events == 1U);
    // Its copy then has no normal frame to pair with: a further fault, still safe.
    check_safe_state(link.deliver(inverted_copy(f), link.now + kGapUs), ReceiverFault::kUnexpectedInvertedCopy);
}

// verifies: SR-CAN-007
TEST_CASE("plc receiver: a frame with another data ID is rejected (implicit ID: CRC, NIBBLE: the explicit nibble)") {
    Link link;
    (void)link.bring_up();
    SafetyChannelConfig masquerade = link.config.channel;
    masquerade.safety_data_id = 0x0C52U;
    const CanFrame f = encode_safety_frame(clear_message(), link.counter, masquerade).value();
    check_safe_state(link.deliver(f, link.now + kPeriodUs), ReceiverFault::kWrongCrc);

    PlcReceiverConfig nc = receiver_config();
    nc.channel.data_id_mode = E2eP01DataIdMode::kNibble;
    Link nibble(nc);
    (void)nibble.bring_up();
    SafetyChannelConfig other = nc.channel;
    other.safety_data_id = 0x0B51U;
    const CanFrame g = encode_safety_frame(clear_message(), nibble.counter, other).value();
    check_safe_state(nibble.deliver(g, nibble.now + kPeriodUs), ReceiverFault::kWrongDataIdNibble);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: a repeated counter gives the safe state") {
    Link link;
    (void)link.bring_up();
    const CanFrame f = link.next_frame();
    (void)link.deliver(f, link.now + kPeriodUs);
    CHECK(link.deliver(inverted_copy(f), link.now + kGapUs).communication_valid);
    (void)link.deliver(f, link.now + kPeriodUs);  // the same pair again
    check_safe_state(link.deliver(inverted_copy(f), link.now + kGapUs), ReceiverFault::kRepeatedCounter);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: skipped counters within the bound are accepted, beyond it give the safe state") {
    PlcReceiverConfig c = receiver_config();
    c.max_delta_counter = 3U;
    Link link(c);
    (void)link.bring_up();
    (void)link.next_frame();  // two frames lost: delta 3
    (void)link.next_frame();
    CHECK(link.send_pair().communication_valid);
    for (int lost = 0; lost < 3; ++lost) {  // three frames lost: delta 4 > 3
        (void)link.next_frame();
    }
    check_safe_state(link.send_pair(), ReceiverFault::kCounterJump);

    Link strict;  // max_delta_counter 1: a single lost frame is a fault
    (void)strict.bring_up();
    (void)strict.next_frame();
    check_safe_state(strict.send_pair(), ReceiverFault::kCounterJump);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: a missing inverted copy is seen at the next frame or when the SRVT runs out") {
    Link link;
    (void)link.bring_up();
    (void)link.deliver(link.next_frame(), link.now + kPeriodUs);
    CHECK(link.receiver.poll(link.now + link.config.srvt_us).communication_valid);  // SRVT is inclusive
    check_safe_state(link.deliver(link.next_frame(), link.now + kPeriodUs), ReceiverFault::kInvertedCopyMissing);

    Link timed;
    (void)timed.bring_up();
    (void)timed.deliver(timed.next_frame(), timed.now + kPeriodUs);
    check_safe_state(timed.receiver.poll(timed.now + timed.config.srvt_us + 1U), ReceiverFault::kInvertedCopyMissing);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: an inverted copy that is not the exact inverse gives the safe state") {
    for (unsigned bit = 0U; bit < 64U; ++bit) {
        Link link;
        (void)link.bring_up();
        const CanFrame f = link.next_frame();
        CanFrame copy = inverted_copy(f);
        copy.data[bit / 8U] = static_cast<std::uint8_t>(copy.data[bit / 8U] ^ (1U << (bit % 8U)));
        (void)link.deliver(f, link.now + kPeriodUs);
        check_safe_state(link.deliver(copy, link.now + kGapUs), ReceiverFault::kInvertedCopyMismatch);
    }
    Link link;
    (void)link.bring_up();
    const CanFrame f = link.next_frame();
    CanFrame same = f;  // an uninverted repeat on the copy's ID
    same.id = inverted_can_id(link.config.channel);
    (void)link.deliver(f, link.now + kPeriodUs);
    check_safe_state(link.deliver(same, link.now + kGapUs), ReceiverFault::kInvertedCopyMismatch);
    Link short_copy;
    (void)short_copy.bring_up();
    const CanFrame g = short_copy.next_frame();
    CanFrame truncated = inverted_copy(g);
    truncated.dlc = 7U;
    (void)short_copy.deliver(g, short_copy.now + kPeriodUs);
    check_safe_state(short_copy.deliver(truncated, short_copy.now + kGapUs), ReceiverFault::kInvertedCopyMismatch);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: an inverted copy after the SRVT gives the safe state, one at the SRVT does not") {
    Link link;
    (void)link.bring_up();
    CanFrame f = link.next_frame();
    (void)link.deliver(f, link.now + kPeriodUs);
    CHECK(link.deliver(inverted_copy(f), link.now + link.config.srvt_us).communication_valid);
    f = link.next_frame();
    (void)link.deliver(f, link.now + kPeriodUs);
    check_safe_state(link.deliver(inverted_copy(f), link.now + link.config.srvt_us + 1U),
                     ReceiverFault::kInvertedCopyLate);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: a late frame and silence both expire the SCT") {
    Link late;
    (void)late.bring_up();
    const CanFrame f = late.next_frame();
    check_safe_state(late.deliver(f, late.now + late.config.sct_us + 1U), ReceiverFault::kSctExpired);

    Link silent;
    (void)silent.bring_up();
    CHECK(silent.receiver.poll(silent.now + silent.config.sct_us).communication_valid);
    check_safe_state(silent.receiver.poll(silent.now + silent.config.sct_us + 1U), ReceiverFault::kSctExpired);
    // Silence goes on: still safe, and counted once.
    const ReceiverStatus s = silent.receiver.poll(silent.now + 10U * silent.config.sct_us);
    check_safe_state(s, ReceiverFault::kSctExpired);
    CHECK(s.fault_events == 1U);

    // A pair whose copy completes it after the SCT is late too.
    Link slow;
    (void)slow.bring_up();
    const CanFrame g = slow.next_frame();
    (void)slow.deliver(g, slow.now + slow.config.sct_us - 500U);
    check_safe_state(slow.deliver(inverted_copy(g), slow.now + 1000U), ReceiverFault::kSctExpired);
}

// verifies: SR-CAN-008
TEST_CASE("plc receiver: a copy with no frame waiting, or time going backwards, gives the safe state") {
    Link link;
    (void)link.bring_up();
    const CanFrame f = link.next_frame();
    check_safe_state(link.deliver(inverted_copy(f), link.now + kPeriodUs), ReceiverFault::kUnexpectedInvertedCopy);

    Link clock;
    (void)clock.bring_up();
    check_safe_state(clock.receiver.poll(clock.now - 1U), ReceiverFault::kTimeWentBackwards);
    Link clock2;
    (void)clock2.bring_up();
    check_safe_state(clock2.deliver(clock2.next_frame(), clock2.now - 1U), ReceiverFault::kTimeWentBackwards);
}

// verifies: SR-CAN-007
TEST_CASE("plc receiver: wrong length, counter 15, malformed content and a different zone count give the safe state") {
    Link len;
    (void)len.bring_up();
    CanFrame f = len.next_frame();
    f.dlc = 6U;
    check_safe_state(len.deliver(f, len.now + kPeriodUs), ReceiverFault::kWrongLength);

    Link ctr;
    (void)ctr.bring_up();
    f = ctr.next_frame();
    set_signal(f, safety_layout::kCounter, 15U);
    f.data[0] = e2e_p01_crc(Span<const std::uint8_t>(f.data, 8U), 0U, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth,
                            15U);
    check_safe_state(ctr.deliver(f, ctr.now + kPeriodUs), ReceiverFault::kCounterOutOfRange);

    Link content;
    (void)content.bring_up();
    f = content.next_frame();
    set_signal(f, safety_layout::kZoneIntrusion, 0x0010U);  // zone 4 of zones 0..3
    f.data[0] = e2e_p01_crc(Span<const std::uint8_t>(f.data, 8U), 0U, kDefaultSafetyDataId, E2eP01DataIdMode::kBoth,
                            static_cast<std::uint8_t>(f.data[1] & 0x0FU));
    check_safe_state(content.deliver(f, content.now + kPeriodUs), ReceiverFault::kMalformedContent);

    Link zones;
    (void)zones.bring_up();
    SafetyMessage five = clear_message();
    five.zone_count = 5U;
    check_safe_state(zones.deliver(zones.next_frame(five), zones.now + kPeriodUs), ReceiverFault::kZoneCountMismatch);
}

// verifies: SR-CAN-009
TEST_CASE(
    "plc receiver: after a fault it recovers after a reference pair and N good pairs in a row, a fault restarting the count") {
    PlcReceiverConfig c = receiver_config();
    c.recovery_good_pairs = 3U;
    Link link(c);
    CHECK(link.bring_up() == 4);                         // 1 reference + 3 good pairs
    (void)link.receiver.poll(link.now + c.sct_us + 1U);  // silence: safe state
    link.now += c.sct_us + 1U;
    CHECK_FALSE(link.send_pair().communication_valid);  // new reference
    CHECK_FALSE(link.send_pair().communication_valid);  // 1
    CHECK_FALSE(link.send_pair().communication_valid);  // 2
    // A fault during recovery: the count starts over.
    CanFrame bad = link.next_frame();
    bad.data[5] = static_cast<std::uint8_t>(bad.data[5] ^ 1U);
    CHECK(link.deliver(bad, link.now + kPeriodUs).fault == ReceiverFault::kWrongCrc);
    int pairs = 0;
    ReceiverStatus s;
    do {
        s = link.send_pair();
        ++pairs;
    } while (!s.communication_valid && pairs < 20);
    CHECK(pairs == 4);
    CHECK(s.fault == ReceiverFault::kNone);
    CHECK(s.fault_events == 2U);
}

// verifies: SR-CAN-009
TEST_CASE("plc receiver: frames on other CAN IDs are ignored, diagnostics included") {
    Link link;
    (void)link.bring_up();
    const CanFrame diag = encode_diagnostics_frame(DiagnosticsMessage{}, 0U, link.config.channel).value();
    CHECK(link.deliver(diag, link.now + 100U).communication_valid);
    CanFrame other{0x7F0U, 3U, {1U, 2U, 3U, 0U, 0U, 0U, 0U, 0U}};
    CHECK(link.deliver(other, link.now + 100U).communication_valid);
    CHECK(link.send_pair().communication_valid);
    // ... but they still advance time: silence on the safety IDs expires the SCT.
    check_safe_state(link.deliver(other, link.now + link.config.sct_us + 1U), ReceiverFault::kSctExpired);
}

// verifies: SR-CAN-010, SR-GEN-003
TEST_CASE("plc receiver: a configuration is checked, and an invalid one cannot build a receiver") {
    CHECK(PlcReceiver::check_config(receiver_config()).ok());
    PlcReceiverConfig c = receiver_config();
    c.srvt_us = 0U;
    CHECK(PlcReceiver::check_config(c).error() == ErrorCode::kInvalidArgument);
    c = receiver_config();
    c.srvt_us = c.sct_us;
    CHECK_FALSE(PlcReceiver::check_config(c).ok());
    c = receiver_config();
    c.max_delta_counter = 0U;
    CHECK_FALSE(PlcReceiver::check_config(c).ok());
    c.max_delta_counter = 15U;
    CHECK_FALSE(PlcReceiver::check_config(c).ok());
    c = receiver_config();
    c.recovery_good_pairs = 0U;
    CHECK_FALSE(PlcReceiver::check_config(c).ok());
    c = receiver_config();
    c.expected_zone_count = 17U;
    CHECK_FALSE(PlcReceiver::check_config(c).ok());
    c = receiver_config();
    c.channel.diagnostics_can_id = c.channel.safety_can_id + 1U;
    CHECK_FALSE(PlcReceiver::check_config(c).ok());
    CHECK(test::violates_contract([&] {
        const PlcReceiver r(c);
        (void)r;
    }));
}

// verifies: SR-CAN-015, SR-GEN-003
TEST_CASE(
    "plc receiver: a link whose peer channel is invalid or shares a safety, copy, diagnostics or separation ID is "
    "refused") {
    PlcReceiverConfig c = receiver_config();
    c.link.enabled = true;
    REQUIRE(PlcReceiver::check_config(c).ok());
    const SafetyChannelConfig ch = c.channel;
    for (const std::uint32_t taken :
         {ch.safety_can_id, inverted_can_id(ch), ch.diagnostics_can_id, ch.separation_can_id, kCanMaxStandardId + 1U}) {
        CAPTURE(taken);
        PlcReceiverConfig d = c;
        d.link.peer.can_id = taken;
        CHECK(PlcReceiver::check_config(d).error() == ErrorCode::kInvalidArgument);
    }
    PlcReceiverConfig d = c;
    d.link.watchdog_us = 0U;  // the endpoint's own check
    CHECK(PlcReceiver::check_config(d).error() == ErrorCode::kInvalidArgument);
    const PlcReceiver rx(c);
    CHECK(rx.link().config().peer.can_id == c.link.peer.can_id);  // the const view of the endpoint
}

// verifies: SR-CAN-007
TEST_CASE("plc receiver: the safe-state message stops, warns, faults, reduces speed and marks every configured zone") {
    const SafetyMessage m = safe_state_message(16U);
    CHECK(m.protective_stop);
    CHECK(m.warning);
    CHECK(m.fault);
    CHECK(m.reduced_speed);
    CHECK(m.active_case == 0U);
    CHECK(m.zone_intrusion == 0xFFFFU);
    CHECK(m.zone_unseen == 0xFFFFU);
    CHECK(safe_state_message(0U).zone_intrusion == 0U);
    CHECK(test::violates_contract([] { (void)safe_state_message(17U); }));
    CHECK(std::string(to_string(ReceiverFault::kSctExpired)) == "safeguard cycle time expired");
    CHECK(std::string(to_string(static_cast<ReceiverFault>(99))) == "unknown receiver fault");
}

// verifies: SR-GEN-004
TEST_CASE(
    "plc receiver: every receiver fault has its own name, and a value outside the enumeration has the fallback name") {
    test::check_enum_names<ReceiverFault>(27U, "unknown receiver fault");
}

// verifies: SR-CMD-008
TEST_CASE(
    "plc receiver: the active case and the reduced speed bit pass through, with both stop and reduced, stop wins") {
    Link link;
    (void)link.bring_up();
    SafetyMessage reduced = clear_message();
    reduced.reduced_speed = true;
    reduced.active_case = 15U;
    ReceiverStatus s = link.send_pair(reduced);
    CHECK(s.communication_valid);
    CHECK_FALSE(s.stop_requested);
    CHECK(s.message.reduced_speed);
    CHECK(s.message.active_case == 15U);
    SafetyMessage both = reduced;
    both.protective_stop = true;  // a valid frame: stop wins
    s = link.send_pair(both);
    CHECK(s.communication_valid);
    CHECK(s.stop_requested);
    CHECK(s.message == both);
}

// verifies: SR-CAN-009
TEST_CASE("plc receiver: the largest recovery count, 255 good pairs, is reached and a long run then stays valid") {
    PlcReceiverConfig c = receiver_config();
    c.recovery_good_pairs = 255U;
    Link link(c);
    for (int k = 0; k < 255; ++k) {  // the reference pair and 254 good pairs
        CHECK_FALSE(link.send_pair().communication_valid);
    }
    CHECK(link.send_pair().communication_valid);  // the 255th good pair
    for (int k = 0; k < 20; ++k) {                // past the saturated count of good pairs
        const ReceiverStatus s = link.send_pair();
        CHECK(s.communication_valid);
        CHECK_FALSE(s.stop_requested);
    }
    CHECK(link.receiver.poll(link.now).fault_events == 0U);
}

// verifies: SR-CAN-016
TEST_CASE(
    "plc receiver: a frame that comes when the data in use is older than the watchdog time gives the safe state") {
    // Found by the fuzz target's age oracle: the age was checked at polls and
    // on link frames, so the status a safety frame or copy returned could be
    // valid for data older than the watchdog time until the next poll.
    PlcReceiverConfig c = receiver_config();
    c.link.enabled = true;
    c.link.watchdog_us = 20000U;
    PlcReceiver rx(c);
    LinkEndpoint controller(controller_link_config());
    std::uint64_t t = 1000000U;
    std::uint8_t counter = 0U;
    ReceiverStatus s;
    const auto pair = [&](std::uint64_t at) {
        const CanFrame f = encode_safety_frame(clear_message(), counter, c.channel).value();
        const CanFrame bound[1] = {f};
        const CanFrame link =
            encode_link_frame(controller.next(at), counter, c.link.peer, Span<const CanFrame>(bound)).value();
        counter = e2e_p01_next_counter(counter);
        static_cast<void>(rx.on_frame(f, at));
        static_cast<void>(rx.on_frame(inverted_copy(f), at + 1U));
        return rx.on_frame(link, at + 2U);
    };
    for (int k = 0; k < 4; ++k) {  // the PLC's link frame echoed, then a pair: the reference and two recovery pairs
        static_cast<void>(controller.on_peer(rx.next_link(t), t));
        s = pair(t);
        t += 5000U;
    }
    REQUIRE(s.communication_valid);
    // The PLC's link frames stop reaching the controller; 25 ms after the
    // last echoed one (> 20 ms) the next safety frame arrives, within the SCT.
    t += 20000U;
    const CanFrame f = encode_safety_frame(clear_message(), counter, c.channel).value();
    s = rx.on_frame(f, t);
    CHECK_FALSE(s.communication_valid);
    CHECK(s.stop_requested);
    CHECK(s.fault == ReceiverFault::kWatchdogExpired);
}

// verifies: SR-CAN-014
TEST_CASE("plc receiver: with the session link, a pair waits for its link frame up to the SRVT and no longer") {
    PlcReceiverConfig c = receiver_config();
    c.link.enabled = true;
    Link link(c);
    const std::uint8_t counter = link.counter;
    const CanFrame f = link.next_frame();
    const std::uint64_t sent = link.now + kPeriodUs;
    (void)link.deliver(f, sent);
    CHECK(link.deliver(inverted_copy(f), sent + kGapUs).fault_events == 0U);
    // Polled while the link frame is still due: no fault yet.
    const ReceiverStatus waiting = link.receiver.poll(sent + c.srvt_us);
    CHECK(waiting.fault == ReceiverFault::kNoFrameYet);
    CHECK(waiting.fault_events == 0U);
    SUBCASE("the next safety frame comes before the link frame") {
        const ReceiverStatus s = link.deliver(link.next_frame(), sent + c.srvt_us);
        check_safe_state(s, ReceiverFault::kLinkFrameMissing);
        CHECK(s.fault_events == 1U);
    }
    SUBCASE("the link frame comes after the SRVT, with no poll in between") {
        LinkEndpoint controller(controller_link_config());
        const CanFrame bound[1] = {f};
        const CanFrame late =
            encode_link_frame(controller.next(sent), counter, c.link.peer, Span<const CanFrame>(bound)).value();
        const ReceiverStatus s = link.deliver(late, sent + c.srvt_us + 1U);
        check_safe_state(s, ReceiverFault::kLinkFrameMissing);
        CHECK(s.fault_events == 1U);
    }
}
