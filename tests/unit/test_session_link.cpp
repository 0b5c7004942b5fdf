// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: protocol 0.2's session link: the link frame codec and its binding to a sample, the endpoint's
// session, sequence, echo and round-trip watchdog, and both directions end to end (controller output and PLC
// receiver; PLC command sender and controller command receiver) against IEC 61784-3's communication errors:
// corruption, unintended repetition, incorrect sequence, loss, unacceptable delay, insertion, masquerade and
// addressing, including a latency ramp and whole-sample replays 15 and 30 samples old and across a restart.
#include <doctest/doctest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "cellguard/can/command_receiver.hpp"
#include "cellguard/can/e2e_crc.hpp"
#include "cellguard/can/plc_command_sender.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_output.hpp"
#include "cellguard/can/session_link.hpp"
#include "enum_names.hpp"

using namespace cellguard;

namespace {

constexpr std::uint64_t kMs = 1000U;
constexpr std::uint64_t kTickUs = 10U * kMs;       // simulation step
constexpr std::uint64_t kWatchdogUs = 250U * kMs;  // both sides' link.watchdog_us
constexpr int kControllerTicks = 10;               // controller period 100 ms
constexpr int kPlcTicks = 5;                       // PLC period 50 ms

LinkFields fields(std::uint16_t seq, std::uint16_t echo, std::uint8_t session = 7U, std::uint8_t echo_session = 9U) {
    LinkFields f;
    f.sequence = seq;
    f.echo = echo;
    f.session = session;
    f.echo_session = echo_session;
    return f;
}

RobotCommand command() {
    RobotCommand c;
    c.monitoring_case = 2U;
    c.joint_count = 2U;
    c.joint_raw[0] = 100;
    c.joint_raw[1] = -100;
    return c;
}

/// A batch of frames one side sent at one time.
struct Batch {
    std::vector<CanFrame> frames;
    std::uint64_t created_us = 0U;  // when the sample's data was made (the sender's cycle)
};

/// Frames on the way, with their arrival time.
struct InFlight {
    CanFrame frame;
    std::uint64_t arrival_us;
    std::uint64_t created_us;
    bool last_of_batch;
};

/// Both sides of a cell on one simulated bus: the controller's command receiver (its link
/// endpoint) and CAN output; the PLC's receiver (its endpoint) and command sender.
struct Cell {
    using Mutator = std::function<void(int sample, Batch& batch, const std::vector<Batch>& history)>;
    using Delay = std::function<std::uint64_t(int sample)>;

    explicit Cell(std::uint8_t controller_session = 1U, std::uint8_t plc_session = 1U, bool link = true) {
        cr_config.link.session = controller_session;
        cr_config.link.watchdog_us = kWatchdogUs;
        cr_config.link.enabled = link;
        pr_config.link.session = plc_session;
        pr_config.link.watchdog_us = kWatchdogUs;
        pr_config.link.enabled = link;
        pr_config.sct_us = 150U * kMs;
        pr_config.max_delta_counter = 1U;
        out_config.session_link = link;
        restart_controller(controller_session);
        restart_plc(plc_session);
    }
    void restart_controller(std::uint8_t session) {
        cr_config.link.session = session;
        ctrl.emplace_back(cr_config);
        encoder.emplace_back(out_config);
    }
    void restart_plc(std::uint8_t session) {
        pr_config.link.session = session;
        plc.emplace_back(pr_config);
        sender.emplace_back(cr_config.channel);
    }
    CommandReceiver& c() { return ctrl.back(); }
    PlcReceiver& p() { return plc.back(); }

    /// Runs @p ticks steps of 10 ms.
    void run(int ticks) {
        for (int k = 0; k < ticks; ++k, ++tick) {
            now = 1000000U + static_cast<std::uint64_t>(tick) * kTickUs;
            deliver();
            if (tick % kControllerTicks == 0) {
                controller_cycle();
            }
            if (tick % kPlcTicks == 2) {
                plc_cycle();
            }
        }
    }

    void deliver() {
        // In arrival order; frames of equal arrival keep their sending order.
        for (;;) {
            std::size_t best = flight.size();
            for (std::size_t i = 0; i < flight.size(); ++i) {
                if (flight[i].arrival_us <= now &&
                    (best == flight.size() || flight[i].arrival_us < flight[best].arrival_us)) {
                    best = i;
                }
            }
            if (best == flight.size()) {
                return;
            }
            const InFlight f = flight[best];
            flight.erase(flight.begin() + static_cast<std::ptrdiff_t>(best));
            const bool to_controller = f.frame.id < 0x100U;
            if (to_controller) {
                (void)c().on_frame(f.frame, f.arrival_us);
            } else {
                (void)p().on_frame(f.frame, f.arrival_us);
                if (f.last_of_batch) {
                    newest_output_created = f.created_us;
                }
            }
        }
    }

    void send(Batch batch, std::uint64_t delay_us) {
        std::uint64_t t = now + 500U + delay_us;
        for (std::size_t i = 0; i < batch.frames.size(); ++i, t += 200U) {
            flight.push_back({batch.frames[i], t, batch.created_us, i + 1U == batch.frames.size()});
        }
    }

    void controller_cycle() {
        const CommandPoll cp = c().poll(now);
        controller_valid.push_back(cp.status.valid);
        controller_faults.push_back(cp.status.fault);
        if (cp.status.valid) {
            CHECK(now - newest_command_created_accepted(cp) <= kWatchdogUs);
        }
        CycleReport report;
        report.started_us = now;
        report.safety.stop_requested = false;
        const CycleFrames f = encoder.back().encode(report, 0U, out_config.session_link ? &c().link() : nullptr);
        Batch b;
        b.created_us = now;
        b.frames = {f.safety, f.inverted};
        if (f.has_link) {
            b.frames.push_back(f.link);
        }
        const int n = static_cast<int>(output_history.size());
        output_history.push_back(b);
        if (output_mutator) {
            output_mutator(n, b, output_history);
        }
        send(b, output_delay ? output_delay(n) : 0U);
    }

    std::uint64_t newest_command_created_accepted(const CommandPoll& cp) const {
        // The accepted sample's creation: its send time in the PLC's history (received_us minus its delay).
        for (auto it = command_history.rbegin(); it != command_history.rend(); ++it) {
            if (it->arrival_us <= cp.input.received_us) {
                return it->created_us;
            }
        }
        return 0U;
    }

    void plc_cycle() {
        const ReceiverStatus s = p().poll(now);
        plc_valid.push_back(s.communication_valid);
        plc_faults.push_back(s.fault);
        if (s.communication_valid) {
            CHECK(now - newest_output_created <= kWatchdogUs);  // the data the PLC acts on is never older
        }
        Batch b;
        b.created_us = now;
        if (pr_config.link.enabled) {
            const Result<LinkedCommandFrames> r = sender.back().next_sample(command(), p().next_link(now),
                                                                            p().config().link.own);
            REQUIRE(r.ok());
            b.frames.assign(r.value().sample.frame, r.value().sample.frame + kCommandFramesPerSample);
            b.frames.push_back(r.value().link);
        } else {
            const Result<CommandFrames> r = sender.back().next_sample(command());
            REQUIRE(r.ok());
            b.frames.assign(r.value().frame, r.value().frame + kCommandFramesPerSample);
        }
        const int n = static_cast<int>(input_history.size());
        input_history.push_back(b);
        if (input_mutator) {
            input_mutator(n, b, input_history);
        }
        const std::uint64_t delay = input_delay ? input_delay(n) : 0U;
        command_history.push_back({b.created_us, now + 500U + delay + 200U * (b.frames.size() - 1U)});
        send(b, delay);
    }

    /// Index of the first poll at or after poll @p from that was not valid, or -1.
    static int first_invalid(const std::vector<bool>& valid, int from) {
        for (int i = from; i < static_cast<int>(valid.size()); ++i) {
            if (!valid[static_cast<std::size_t>(i)]) {
                return i;
            }
        }
        return -1;
    }

    struct Sent {
        std::uint64_t created_us;
        std::uint64_t arrival_us;
    };

    CommandReceiverConfig cr_config;
    PlcReceiverConfig pr_config;
    SafetyOutputConfig out_config;
    std::vector<CommandReceiver> ctrl;
    std::vector<CycleFrameEncoder> encoder;
    std::vector<PlcReceiver> plc;
    std::vector<PlcCommandSender> sender;
    std::vector<InFlight> flight;
    std::vector<Batch> output_history;
    std::vector<Batch> input_history;
    std::vector<Sent> command_history;
    Mutator output_mutator;
    Mutator input_mutator;
    Delay output_delay;
    Delay input_delay;
    std::vector<bool> controller_valid;
    std::vector<CommandFault> controller_faults;
    std::vector<bool> plc_valid;
    std::vector<ReceiverFault> plc_faults;
    std::uint64_t newest_output_created = 0U;
    std::uint64_t now = 1000000U;
    int tick = 0;
};

/// A cell brought up: both sides valid.
Cell& bring_up(Cell& cell) {
    cell.run(100);  // 1 s: 10 controller cycles, 20 PLC cycles
    REQUIRE(cell.c().poll(cell.now).status.valid);
    REQUIRE(cell.p().poll(cell.now).communication_valid);
    return cell;
}

}  // namespace

namespace {

constexpr int kFirst = 10;  // the first output sample after bring_up (10 controller cycles, 20 PLC cycles)
constexpr int kFirstCommand = 20;

/// Invalid polls of the side that receives the mutated direction, after bring-up.
struct Outcome {
    int invalid_polls = 0;
    int first_invalid = -1;  // poll index
};

Outcome count(const std::vector<bool>& valid, int from) {
    Outcome o;
    for (int i = from; i < static_cast<int>(valid.size()); ++i) {
        if (!valid[static_cast<std::size_t>(i)]) {
            ++o.invalid_polls;
            if (o.first_invalid < 0) {
                o.first_invalid = i;
            }
        }
    }
    return o;
}

/// Brings a cell up, mutates the output direction from sample kFirst on, runs 1 s more.
Outcome output_mutant(const Cell::Mutator& mutator, const Cell::Delay& delay = {}, bool link = true, int ticks = 100) {
    Cell cell(1U, 1U, link);
    bring_up(cell);
    cell.output_mutator = mutator;
    cell.output_delay = delay;
    cell.run(ticks);
    return count(cell.plc_valid, 20);
}

/// The same for the command direction (PLC samples from kFirstCommand on), seen by the controller.
Outcome command_mutant(const Cell::Mutator& mutator, const Cell::Delay& delay = {}, bool link = true, int ticks = 100) {
    Cell cell(1U, 1U, link);
    bring_up(cell);
    cell.input_mutator = mutator;
    cell.input_delay = delay;
    cell.run(ticks);
    return count(cell.controller_valid, 10);
}

/// Mutator applied once, at sample @p at.
Cell::Mutator once(int at, std::function<void(Batch&, const std::vector<Batch>&)> f) {
    return [at, f](int n, Batch& b, const std::vector<Batch>& h) {
        if (n == at) {
            f(b, h);
        }
    };
}

void flip(Batch& b, std::size_t frame, std::size_t byte, std::uint8_t mask) {
    b.frames[frame].data[byte] = static_cast<std::uint8_t>(b.frames[frame].data[byte] ^ mask);
}

/// A ramp: @p step_ms more latency per sample from sample @p from on.
Cell::Delay ramp(int from, std::uint64_t step_ms) {
    return [from, step_ms](int n) { return n < from ? 0U : static_cast<std::uint64_t>(n - from + 1) * step_ms * kMs; };
}

/// The frames a second controller (session 99) sends as its first sample.
Batch foreign_output_sample() {
    SafetyOutputConfig oc;
    CommandReceiverConfig rc;
    rc.link.session = 99U;
    CommandReceiver other(rc);
    CycleFrameEncoder enc(oc);
    CycleReport report;
    report.safety.stop_requested = false;
    const CycleFrames f = enc.encode(report, 0U, &other.link());
    Batch b;
    b.frames = {f.safety, f.inverted, f.link};
    return b;
}

/// The frames a second PLC (session 99) sends as its first sample.
Batch foreign_command_sample() {
    PlcReceiverConfig pc;
    pc.link.session = 99U;
    PlcReceiver other(pc);
    PlcCommandSender s(CommandChannelConfig{});
    const Result<LinkedCommandFrames> r = s.next_sample(command(), other.next_link(0U), pc.link.own);
    Batch b;
    b.frames.assign(r.value().sample.frame, r.value().sample.frame + kCommandFramesPerSample);
    b.frames.push_back(r.value().link);
    return b;
}

}  // namespace

// verifies: SR-CAN-013
TEST_CASE("session link: sequence ring, link frame round trip, binding to its sample, refusals") {
    CHECK(link_next_sequence(1U) == 2U);
    CHECK(link_next_sequence(kLinkSequenceMax) == 1U);
    CHECK(link_sequence_delta(1U, kLinkSequenceMax) == 1U);
    CHECK(link_sequence_delta(5U, 5U) == 0U);
    CHECK(link_sequence_delta(5U, 20U) == 65520U);  // 15 back: a jump of nearly the whole ring

    const LinkChannel ch = kDefaultControllerLinkChannel;
    CanFrame bound[1] = {{0x101U, 8U, {1, 2, 3, 4, 5, 6, 7, 8}}};
    for (const E2eP01DataIdMode mode :
         {E2eP01DataIdMode::kBoth, E2eP01DataIdMode::kAlt, E2eP01DataIdMode::kLow, E2eP01DataIdMode::kNibble}) {
        LinkChannel m = ch;
        m.data_id_mode = mode;
        const Result<CanFrame> f = encode_link_frame(fields(40000U, 12U), 9U, m, Span<const CanFrame>(bound));
        REQUIRE(f.ok());
        LinkFields out;
        REQUIRE(check_link_frame(f.value(), m, Span<const CanFrame>(bound), 9U, out) == LinkFrameCheck::kOk);
        CHECK(out.sequence == 40000U);
        CHECK(out.echo == 12U);
        CHECK(out.session == 7U);
        CHECK(out.echo_session == 9U);
        CHECK(check_link_frame(f.value(), m, Span<const CanFrame>(bound), 10U, out) ==
              LinkFrameCheck::kCounterMismatch);
        // Every single-bit corruption of the link frame, and of the bound frame, fails.
        for (std::size_t bit = 0; bit < 64U; ++bit) {
            CanFrame bad = f.value();
            bad.data[bit / 8U] = static_cast<std::uint8_t>(bad.data[bit / 8U] ^ (1U << (bit % 8U)));
            CHECK(check_link_frame(bad, m, Span<const CanFrame>(bound), 9U, out) != LinkFrameCheck::kOk);
            CanFrame other[1] = {bound[0]};
            other[0].data[bit / 8U] = static_cast<std::uint8_t>(other[0].data[bit / 8U] ^ (1U << (bit % 8U)));
            CHECK(check_link_frame(f.value(), m, Span<const CanFrame>(other), 9U, out) == LinkFrameCheck::kWrongCrc);
        }
    }
    LinkFields out;
    const Result<CanFrame> good = encode_link_frame(fields(3U, 1U), 0U, ch, Span<const CanFrame>(bound));
    REQUIRE(good.ok());
    CanFrame wrong_id = good.value();
    wrong_id.id = 0x106U;
    CHECK(check_link_frame(wrong_id, ch, Span<const CanFrame>(bound), 0U, out) == LinkFrameCheck::kWrongCanId);
    CanFrame short_frame = good.value();
    short_frame.dlc = 7U;
    CHECK(check_link_frame(short_frame, ch, Span<const CanFrame>(bound), 0U, out) == LinkFrameCheck::kWrongLength);
    LinkChannel other_id = ch;
    other_id.data_id = 0x0F55U;
    CHECK(check_link_frame(good.value(), other_id, Span<const CanFrame>(bound), 0U, out) == LinkFrameCheck::kWrongCrc);
    CHECK_FALSE(encode_link_frame(fields(0U, 1U), 0U, ch, Span<const CanFrame>(bound)).ok());
    CHECK_FALSE(encode_link_frame(fields(1U, 1U, 0U), 0U, ch, Span<const CanFrame>(bound)).ok());
    CHECK_FALSE(encode_link_frame(fields(1U, 1U), 15U, ch, Span<const CanFrame>(bound)).ok());
    CHECK(std::string(to_string(LinkFrameCheck::kWrongCrc)).find("CRC") != std::string::npos);
}

// verifies: SR-CAN-013
TEST_CASE("session link: the endpoint's session, sequence, echo and watchdog checks") {
    LinkConfig config = controller_link_config();
    config.session = 9U;
    config.watchdog_us = 100U * kMs;
    REQUIRE(LinkEndpoint::check_config(config).ok());
    LinkEndpoint e(config);
    CHECK(e.age_check(0U) == LinkFault::kNoEchoYet);
    const LinkFields first = e.next(1000U);  // sequence 1 at 1 ms
    CHECK(first.sequence == 1U);
    CHECK(first.echo == 0U);
    CHECK(e.on_peer(fields(100U, 0U, 7U, 0U), 2000U) == LinkFault::kNoEchoYet);  // the peer has not heard us
    CHECK(e.next(3000U).echo == 100U);                                           // now we echo it
    CHECK(e.on_peer(fields(101U, 1U), 50U * kMs) == LinkFault::kNone);           // round trip 49 ms
    CHECK(e.data_origin_us() == 1000U);
    CHECK(e.age_check(101U * kMs) == LinkFault::kNone);
    CHECK(e.age_check(101U * kMs + 1U) == LinkFault::kWatchdogExpired);  // 100 ms + 1 us after 1 ms
    CHECK(e.on_peer(fields(101U, 2U), 60U * kMs) == LinkFault::kRepeatedSequence);
    CHECK(e.on_peer(fields(102U, 2U), 60U * kMs) == LinkFault::kNone);
    CHECK(e.on_peer(fields(105U, 2U), 61U * kMs) == LinkFault::kSequenceJump);  // two lost, bound 2
    CHECK(e.on_peer(fields(106U, 2U, 7U, 8U), 62U * kMs) == LinkFault::kWrongEchoSession);
    CHECK(e.on_peer(fields(107U, 40U), 63U * kMs) == LinkFault::kEchoUnknown);   // never sent
    CHECK(e.on_peer(fields(108U, 1U), 64U * kMs) == LinkFault::kEchoBackwards);  // older than echo 2
    CHECK(e.on_peer(fields(109U, 2U), 200U * kMs) == LinkFault::kWatchdogExpired);
    CHECK(e.on_peer(fields(110U, 2U, 8U), 64U * kMs) == LinkFault::kSessionChanged);
    CHECK(e.on_peer(fields(111U, 2U, 8U), 64U * kMs) == LinkFault::kNone);  // the new session is the reference
    // Configuration refusals.
    LinkConfig bad = config;
    bad.session = 0U;
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    bad = config;
    bad.watchdog_us = 0U;
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    bad = config;
    bad.peer = bad.own;
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    bad = config;
    bad.max_sequence_step = 0U;
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    test::check_enum_names<LinkFault>(9U, "unknown link fault");
    test::check_enum_names<LinkFrameCheck>(7U, "unknown link frame check");
}

// verifies: SR-CAN-014
TEST_CASE("session link: each refusal of the channel, the configuration, the frame content and the endpoint alone") {
    // Channels: an ID beyond 11 bits, a data ID beyond 12 bits in kNibble mode.
    LinkChannel wide = kDefaultControllerLinkChannel;
    wide.can_id = 0x800U;
    CHECK_FALSE(check_link_channel(wide).ok());
    CHECK_FALSE(encode_link_frame(fields(1U, 1U), 0U, wide, {}).ok());
    LinkChannel nibble = kDefaultControllerLinkChannel;
    nibble.data_id_mode = E2eP01DataIdMode::kNibble;
    nibble.data_id = 0x1000U;
    CHECK_FALSE(check_link_channel(nibble).ok());
    LinkChannel unknown_mode = kDefaultControllerLinkChannel;
    unknown_mode.data_id_mode = static_cast<E2eP01DataIdMode>(4);  // a corrupted or hand-edited configuration
    CHECK_FALSE(check_link_channel(unknown_mode).ok());
    CHECK_FALSE(encode_link_frame(fields(1U, 1U), 0U, unknown_mode, {}).ok());
    // Configurations: either channel invalid, a step bound above the history.
    LinkConfig bad = controller_link_config();
    bad.own = wide;
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    bad = controller_link_config();
    bad.peer = nibble;
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    bad = controller_link_config();
    bad.max_sequence_step = static_cast<std::uint16_t>(kLinkHistory + 1U);
    CHECK_FALSE(LinkEndpoint::check_config(bad).ok());
    // Content with a valid CRC but sequence 0, session 0 or nibble bits outside kNibble mode: malformed.
    const LinkChannel ch = kDefaultControllerLinkChannel;
    const auto crafted = [&ch](std::uint16_t sequence, std::uint8_t session, std::uint8_t nibble_bits) {
        CanFrame f{ch.can_id, 8U, {}};
        f.data[1] = static_cast<std::uint8_t>(nibble_bits << 4U);  // counter 0
        f.data[2] = static_cast<std::uint8_t>(sequence & 0xFFU);
        f.data[3] = static_cast<std::uint8_t>(sequence >> 8U);
        f.data[4] = 1U;  // echo 1
        f.data[6] = session;
        f.data[7] = 9U;
        f.data[0] = e2e_p01_crc({f.data, kCanMaxDataLength}, 0U, ch.data_id, ch.data_id_mode, 0U);
        return f;
    };
    LinkFields out;
    CHECK(check_link_frame(crafted(1U, 7U, 0U), ch, {}, 0U, out) == LinkFrameCheck::kOk);
    CHECK(check_link_frame(crafted(0U, 7U, 0U), ch, {}, 0U, out) == LinkFrameCheck::kMalformedContent);
    CHECK(check_link_frame(crafted(1U, 0U, 0U), ch, {}, 0U, out) == LinkFrameCheck::kMalformedContent);
    CHECK(check_link_frame(crafted(1U, 7U, 3U), ch, {}, 0U, out) == LinkFrameCheck::kMalformedContent);

    // The endpoint: fields with sequence 0, an echo session without an echo, an echo from before its own send,
    // a standalone frame that fails its check, an age check before the echo's send time.
    LinkConfig config = controller_link_config();
    config.peer = ch;
    config.own = kDefaultPlcLinkChannel;
    config.session = 9U;
    LinkEndpoint e(config);
    CHECK(e.on_peer(fields(0U, 1U), 1U * kMs) == LinkFault::kSequenceJump);
    const LinkFields mine = e.next(10U * kMs);
    CHECK(e.on_peer(fields(1U, 0U, 7U, 9U), 11U * kMs) == LinkFault::kNoEchoYet);
    CHECK(e.on_peer(fields(2U, mine.sequence), 9U * kMs) == LinkFault::kWatchdogExpired);  // before the send
    CHECK(e.on_standalone_frame(crafted(0U, 7U, 0U), 12U * kMs) == LinkFault::kSequenceJump);
    CHECK(e.on_peer(fields(3U, mine.sequence), 13U * kMs) == LinkFault::kNone);
    CHECK(e.age_check(13U * kMs) == LinkFault::kNone);
    CHECK(e.age_check(9U * kMs) == LinkFault::kWatchdogExpired);  // a clock before the data's origin
    // An echo whose slot was reused by a later sequence: unknown.
    for (std::size_t k = 0U; k < kLinkHistory; ++k) {
        static_cast<void>(e.next(14U * kMs));
    }
    CHECK(e.on_peer(fields(4U, mine.sequence), 15U * kMs) == LinkFault::kEchoUnknown);
}

// verifies: SR-CAN-013, SR-CAN-015
TEST_CASE(
    "session link: the own sequence wraps from 65,535 to 1, and a clock that steps back leaves no reference "
    "fresh") {
    LinkConfig config = controller_link_config();
    config.session = 9U;
    config.watchdog_us = 100U * kMs;
    LinkEndpoint e(config);
    std::uint16_t last = 0U;
    for (std::uint32_t k = 0U; k < kLinkSequenceMax; ++k) {
        last = e.next(1U * kMs).sequence;
    }
    CHECK(last == kLinkSequenceMax);
    const LinkFields wrapped = e.next(2U * kMs);
    CHECK(wrapped.sequence == 1U);                                    // 0 is never sent
    CHECK(e.on_peer(fields(10U, 1U), 3U * kMs) == LinkFault::kNone);  // the echo of the wrapped sequence
    // A frame stamped before the reference (a clock stepped back): the reference is not fresh, so the older
    // frame may move it; its echo is then checked against its own send time.
    CHECK(e.on_peer(fields(9U, 1U), 2U * kMs + 500U) == LinkFault::kSequenceJump);
    CHECK(e.on_peer(fields(10U, 1U), 2U * kMs + 600U) == LinkFault::kNone);
}

// verifies: SR-CAN-015
TEST_CASE("session link: a replay cannot take the reference back across a fault, by sequence or by session") {
    LinkConfig config = controller_link_config();
    config.session = 9U;
    config.watchdog_us = 100U * kMs;
    LinkEndpoint e(config);
    static_cast<void>(e.next(1U * kMs));  // sequences 1 and 2, sent at 1 and 2 ms
    static_cast<void>(e.next(2U * kMs));
    CHECK(e.on_peer(fields(10U, 1U), 10U * kMs) == LinkFault::kNone);
    CHECK(e.on_peer(fields(13U, 2U), 20U * kMs) == LinkFault::kSequenceJump);  // 11 and 12 lost: reference 13
    // 11 and 12 replayed, younger than the watchdog time: refused, the reference stays 13. (Before, 11 became
    // the reference and 12 passed: a replay accepted right after a fault.)
    CHECK(e.on_peer(fields(11U, 2U), 21U * kMs) == LinkFault::kRepeatedSequence);
    CHECK(e.on_peer(fields(12U, 2U), 22U * kMs) == LinkFault::kRepeatedSequence);
    CHECK(e.on_peer(fields(14U, 2U), 23U * kMs) == LinkFault::kNone);  // the genuine next frame
    // The ring's halves: 32,767 ahead is a loss (a jump forward), 32,768 ahead is behind.
    CHECK(kLinkSequenceBehind == 32768U);
    CHECK(e.on_peer(fields(static_cast<std::uint16_t>(14U + 32768U), 2U), 24U * kMs) == LinkFault::kRepeatedSequence);
    CHECK(e.on_peer(fields(static_cast<std::uint16_t>(14U + 32767U), 2U), 25U * kMs) == LinkFault::kSequenceJump);
    // A reference older than the watchdog time may move back (a long silence must not lock the link out); a
    // frame from before it echoes a sequence sent more than the watchdog time ago and is refused by that.
    CHECK(e.on_peer(fields(15U, 2U), 126U * kMs) == LinkFault::kSequenceJump);
    CHECK(e.on_peer(fields(16U, 2U), 127U * kMs) == LinkFault::kWatchdogExpired);

    // By session: the other side restarts (7 -> 8); frames of session 7 replayed after that are refused
    // and 8 stays the reference.
    LinkEndpoint s(config);
    static_cast<void>(s.next(1U * kMs));
    CHECK(s.on_peer(fields(50U, 1U, 7U), 10U * kMs) == LinkFault::kNone);
    CHECK(s.on_peer(fields(1U, 1U, 8U), 20U * kMs) == LinkFault::kSessionChanged);
    CHECK(s.on_peer(fields(51U, 1U, 7U), 30U * kMs) == LinkFault::kSessionChanged);
    CHECK(s.on_peer(fields(52U, 1U, 7U), 40U * kMs) == LinkFault::kSessionChanged);  // before: accepted
    CHECK(s.on_peer(fields(2U, 1U, 8U), 50U * kMs) == LinkFault::kNone);
    // Once the reference is older than the watchdog time the session just left may come back (a restart
    // whose session value repeats): taken as the reference, then accepted on a fresh echo.
    const LinkFields mine = s.next(150U * kMs);
    CHECK(s.on_peer(fields(1U, mine.sequence, 7U), 151U * kMs) == LinkFault::kSessionChanged);
    CHECK(s.on_peer(fields(2U, mine.sequence, 7U), 152U * kMs) == LinkFault::kNone);
}

// verifies: SR-CAN-008
TEST_CASE("session link: an inverted copy after the SCT reports the safe state, not the pair before it") {
    // With the link on, a copy completes no pair (its link frame does), so the status the copy returns
    // needs the SCT check of its own (a fuzz input found it valid 1.8 ms past the SCT before 2026-12-05).
    Cell cell;
    bring_up(cell);
    PlcReceiver& plc = cell.p();
    REQUIRE(plc.poll(cell.now).communication_valid);
    std::uint64_t expiry = cell.now;  // the first time a poll finds the pair in use too old, on a copy
    for (PlcReceiver probe = plc; probe.poll(expiry).communication_valid; probe = plc) {
        expiry += 100U;
    }
    PlcReceiver probe = plc;
    REQUIRE(probe.poll(expiry).fault == ReceiverFault::kSctExpired);
    const CanFrame normal = cell.output_history.back().frames[0];
    CHECK(plc.on_frame(normal, expiry - 1000U).communication_valid);  // still within the SCT
    const ReceiverStatus s = plc.on_frame(inverted_copy(normal), expiry);
    CHECK_FALSE(s.communication_valid);
    CHECK(s.fault == ReceiverFault::kSctExpired);
}

// verifies: SR-CAN-013
TEST_CASE(
    "session link: both sides come up through the handshake and stay valid, and an output without an endpoint is refused") {
    Cell cell;
    bring_up(cell);
    cell.run(200);
    CHECK(count(cell.plc_valid, 20).invalid_polls == 0);
    CHECK(count(cell.controller_valid, 10).invalid_polls == 0);
    CHECK(cell.p().link().sequence() > 0U);
    SafetyOutputConfig oc;  // session_link on by default
    struct NullSender final : CanSender {
        bool send(const CanFrame&) noexcept override { return true; }
    } sender;
    const CanSafetyOutput refused(oc, sender);
    CHECK_FALSE(refused.status().ok());
    CommandReceiverConfig rc;
    CommandReceiver rx(rc);
    const CanSafetyOutput accepted(oc, sender, &rx.link());
    CHECK(accepted.status().ok());
}

// The IEC 61784-3 communication errors, each with its mutants, in both directions. Output direction:
// frames 0 safety, 1 copy, 2 link; command direction: 0..5 A A' B B' C C', 6 link.

// verifies: SR-CAN-004, SR-CAN-014
TEST_CASE(
    "iec 61784-3 corruption: a flipped bit in a protected frame or in the link frame is detected, both directions") {
    CHECK(output_mutant(once(kFirst, [](Batch& b, const std::vector<Batch>&) {
              flip(b, 0U, 3U, 0x10U);
          })).invalid_polls > 0);
    CHECK(output_mutant(once(kFirst, [](Batch& b, const std::vector<Batch>&) {
              flip(b, 2U, 4U, 0x01U);
          })).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, [](Batch& b, const std::vector<Batch>&) {
              flip(b, 2U, 5U, 0x80U);
          })).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, [](Batch& b, const std::vector<Batch>&) {
              flip(b, 6U, 2U, 0x01U);
          })).invalid_polls > 0);
}

// verifies: SR-CAN-014, SR-CAN-015
TEST_CASE("iec 61784-3 unintended repetition: a repeated sample and whole-sample replays 15 and 30 samples old") {
    const auto twice = [](Batch& b, const std::vector<Batch>&) {
        const std::vector<CanFrame> f = b.frames;
        b.frames.insert(b.frames.end(), f.begin(), f.end());
    };
    const auto replay = [](int age) {
        return [age](Batch& b, const std::vector<Batch>& h) {
            b.frames = h[h.size() - 1U - static_cast<std::size_t>(age)].frames;
        };
    };
    CHECK(output_mutant(once(kFirst + 30, twice), {}, true, 400).invalid_polls > 0);
    for (const int age : {15, 30}) {
        CAPTURE(age);
        // The replayed sample carries the expected 4-bit counter: protocol 0.1 accepts it, 0.2 does not.
        CHECK(output_mutant(once(kFirst + 30, replay(age)), {}, false, 400).invalid_polls == 0);
        const Outcome out = output_mutant(once(kFirst + 30, replay(age)), {}, true, 400);
        CHECK(out.invalid_polls > 0);
        CHECK(command_mutant(once(kFirstCommand + 60, replay(age)), {}, false, 400).invalid_polls == 0);
        CHECK(command_mutant(once(kFirstCommand + 60, replay(age)), {}, true, 400).invalid_polls > 0);
    }
    CHECK(command_mutant(once(kFirstCommand + 60, twice), {}, true, 400).invalid_polls > 0);
}

// verifies: SR-CAN-014, SR-CAN-015
TEST_CASE("iec 61784-3 replay across a restart: frames of the previous session are refused on either side") {
    // The controller restarts with a new session; a sample of its previous session is then replayed.
    Cell cell;
    bring_up(cell);
    const std::vector<Batch> before = cell.output_history;
    cell.restart_controller(2U);
    cell.run(100);
    REQUIRE(cell.p().poll(cell.now).communication_valid);  // the PLC follows the restart through recovery
    const std::size_t polls = cell.plc_valid.size();
    cell.output_mutator = once(static_cast<int>(cell.output_history.size()),
                               [&before](Batch& b, const std::vector<Batch>&) { b.frames = before.back().frames; });
    cell.run(30);
    CHECK(count(cell.plc_valid, static_cast<int>(polls)).invalid_polls > 0);

    // The PLC restarts; the controller's frames from before its restart are replayed in place of the new ones:
    // they echo the PLC's previous session, so the new PLC never becomes valid on them.
    Cell plc_restart;
    bring_up(plc_restart);
    const std::vector<Batch> old = plc_restart.output_history;
    plc_restart.restart_plc(2U);
    const std::size_t start = plc_restart.plc_valid.size();
    plc_restart.output_mutator = [&old](int n, Batch& b, const std::vector<Batch>&) {
        b.frames = old[static_cast<std::size_t>(n) % old.size()].frames;
    };
    plc_restart.run(100);
    CHECK(count(plc_restart.plc_valid, static_cast<int>(start)).invalid_polls ==
          static_cast<int>(plc_restart.plc_valid.size() - start));
    // And the command direction: the PLC restarts, a sample of its previous session is replayed.
    Cell cmd;
    bring_up(cmd);
    const std::vector<Batch> cmd_before = cmd.input_history;
    cmd.restart_plc(2U);
    cmd.run(100);
    REQUIRE(cmd.c().poll(cmd.now).status.valid);
    const std::size_t cpolls = cmd.controller_valid.size();
    cmd.input_mutator = once(
        static_cast<int>(cmd.input_history.size()),
        [&cmd_before](Batch& b, const std::vector<Batch>&) { b.frames = cmd_before.back().frames; });
    cmd.run(30);
    CHECK(count(cmd.controller_valid, static_cast<int>(cpolls)).invalid_polls > 0);
}

// verifies: SR-CAN-008, SR-CAN-014
TEST_CASE("iec 61784-3 incorrect sequence: frames of a sample out of order, and an older sample, are detected") {
    const auto link_first = [](std::size_t link, std::size_t before) {
        return [link, before](Batch& b, const std::vector<Batch>&) { std::swap(b.frames[link], b.frames[before]); };
    };
    const auto older = [](Batch& b, const std::vector<Batch>& h) { b.frames = h[h.size() - 3U].frames; };
    CHECK(output_mutant(once(kFirst, link_first(2U, 1U))).invalid_polls > 0);
    CHECK(output_mutant(once(kFirst, older)).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, link_first(6U, 5U))).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, older)).invalid_polls > 0);
}

// verifies: SR-CAN-008, SR-CAN-014
TEST_CASE("iec 61784-3 loss: a lost link frame and lost samples are detected") {
    const auto drop_link = [](Batch& b, const std::vector<Batch>&) { b.frames.pop_back(); };
    const auto drop_from = [](int from, int n) {
        return [from, n](int k, Batch& b, const std::vector<Batch>&) {
            if (k >= from && k < from + n) {
                b.frames.clear();
            }
        };
    };
    CHECK(output_mutant(once(kFirst, drop_link)).invalid_polls > 0);
    CHECK(output_mutant(drop_from(kFirst, 3)).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, drop_link)).invalid_polls > 0);
    CHECK(command_mutant(drop_from(kFirstCommand, 4)).invalid_polls > 0);
}

// verifies: SR-CAN-014, SR-CAN-016
TEST_CASE("iec 61784-3 unacceptable delay: latency ramps of 10, 30 and 90 ms per sample and a constant 1.5 s") {
    // Cell's polls CHECK on every valid poll that the data in use is at most the watchdog time old.
    for (const std::uint64_t step : {10U, 30U, 90U}) {
        CAPTURE(step);
        const Outcome out = output_mutant({}, ramp(kFirst, step), true, 300);
        CHECK(out.invalid_polls > 0);
        const Outcome cmd = command_mutant({}, ramp(kFirstCommand, step), true, 300);
        CHECK(cmd.invalid_polls > 0);
    }
    // Constant 1.5 s from a sample on: after the detection, never valid again.
    const auto constant = [](int from) { return [from](int n) { return n < from ? 0U : 1500U * kMs; }; };
    Cell cell;
    bring_up(cell);
    cell.output_delay = constant(kFirst);
    cell.run(600);
    const Outcome out = count(cell.plc_valid, 20);
    CHECK(out.first_invalid >= 0);
    CHECK(out.invalid_polls == static_cast<int>(cell.plc_valid.size()) - out.first_invalid);
    Cell cmd;
    bring_up(cmd);
    cmd.input_delay = constant(kFirstCommand);
    cmd.run(600);
    const Outcome c = count(cmd.controller_valid, 10);
    CHECK(c.first_invalid >= 0);
    CHECK(c.invalid_polls == static_cast<int>(cmd.controller_valid.size()) - c.first_invalid);
}

// verifies: SR-CAN-014
TEST_CASE("iec 61784-3 insertion: a sample of another sender inserted after a genuine one is detected") {
    const Batch out_foreign = foreign_output_sample();
    const Batch cmd_foreign = foreign_command_sample();
    CHECK(output_mutant(once(kFirst, [&out_foreign](Batch& b, const std::vector<Batch>&) {
              b.frames.insert(b.frames.end(), out_foreign.frames.begin(), out_foreign.frames.end());
          })).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, [&cmd_foreign](Batch& b, const std::vector<Batch>&) {
              b.frames.insert(b.frames.end(), cmd_foreign.frames.begin(), cmd_foreign.frames.end());
          })).invalid_polls > 0);
}

// verifies: SR-CAN-004, SR-CAN-014
TEST_CASE("iec 61784-3 masquerade: the other direction's link frame on a link ID is detected") {
    const Batch cmd_sample = foreign_command_sample();
    const Batch out_sample = foreign_output_sample();
    CHECK(output_mutant(once(kFirst, [&cmd_sample](Batch& b, const std::vector<Batch>&) {
              const std::uint32_t id = b.frames[2].id;
              b.frames[2] = cmd_sample.frames[6];
              b.frames[2].id = id;
          })).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, [&out_sample](Batch& b, const std::vector<Batch>&) {
              const std::uint32_t id = b.frames[6].id;
              b.frames[6] = out_sample.frames[2];
              b.frames[6].id = id;
          })).invalid_polls > 0);
}

// verifies: SR-CAN-004, SR-CAN-014
TEST_CASE("iec 61784-3 addressing: a link frame for another channel (another data ID) is detected") {
    const auto readdress = [](std::size_t index, std::size_t first_bound, std::size_t stride, std::size_t n) {
        return [=](Batch& b, const std::vector<Batch>&) {
            LinkChannel other;
            other.can_id = b.frames[index].id;
            other.data_id = 0x0B65U;  // another cell's link data ID
            std::vector<CanFrame> bound;
            for (std::size_t k = 0; k < n; ++k) {
                bound.push_back(b.frames[first_bound + k * stride]);
            }
            LinkFields f;
            f.sequence = static_cast<std::uint16_t>(get_signal(b.frames[index], link_layout::kSequence));
            f.echo = static_cast<std::uint16_t>(get_signal(b.frames[index], link_layout::kEcho));
            f.session = static_cast<std::uint8_t>(get_signal(b.frames[index], link_layout::kSession));
            f.echo_session = static_cast<std::uint8_t>(get_signal(b.frames[index], link_layout::kEchoSession));
            const auto counter = static_cast<std::uint8_t>(get_signal(b.frames[index], link_layout::kCounter));
            b.frames[index] = encode_link_frame(f, counter, other, Span<const CanFrame>(bound.data(), n)).value();
        };
    };
    CHECK(output_mutant(once(kFirst, readdress(2U, 0U, 1U, 1U))).invalid_polls > 0);
    CHECK(command_mutant(once(kFirstCommand, readdress(6U, 0U, 2U, 3U))).invalid_polls > 0);
}

// verifies: SR-CAN-013
TEST_CASE(
    "session link: an echo of a sequence sent 32 or more frames ago is unknown, also across the sequence's wrap") {
    // The send history has kLinkHistory (32) slots, slot = sequence % 32. The sequence runs 1..65535 and
    // skips 0, so at the wrap 65535 -> 1 slot 0 is not written: it still holds 65504, sent 32 frames before
    // sequence 1. That slot's sequence matches an echo of 65504, and only the distance refuses it.
    LinkConfig config = controller_link_config();
    config.session = 9U;
    REQUIRE(LinkEndpoint::check_config(config).ok());
    LinkEndpoint e(config);
    std::uint64_t now = 0U;
    while (e.sequence() != kLinkSequenceMax) {
        (void)e.next(++now);  // one frame a microsecond, all within the watchdog time
    }
    {
        LinkEndpoint before_wrap = e;  // 65504 was sent 31 frames before 65535: still known
        CHECK(before_wrap.on_peer(fields(1U, 65504U), now) == LinkFault::kNone);
    }
    CHECK(e.next(++now).sequence == 1U);
    {
        LinkEndpoint stale = e;
        CHECK(stale.on_peer(fields(1U, 65504U), now) == LinkFault::kEchoUnknown);  // 32 frames before 1
    }
    {
        LinkEndpoint overwritten = e;  // 65505's slot (1) now holds sequence 1
        CHECK(overwritten.on_peer(fields(1U, 65505U), now) == LinkFault::kEchoUnknown);
    }
    {
        LinkEndpoint oldest = e;
        CHECK(oldest.on_peer(fields(1U, 65506U), now) == LinkFault::kNone);  // 30 frames before 1
    }
    CHECK(e.on_peer(fields(1U, 1U), now) == LinkFault::kNone);  // the frame just sent
}
