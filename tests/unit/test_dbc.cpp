// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: certification/cellguard.dbc states every frame and signal exactly as the layout tables in safety_frame.hpp, separation_frame.hpp and command_frame.hpp; the frames file that tools/dbc_decode_check.py decodes with canmatrix.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "cellguard/can/command_frame.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/can/separation_frame.hpp"
#include "cellguard/can/session_link.hpp"

using namespace cellguard;

namespace {

struct DbcSignal {
    std::string name;
    std::string multiplex;  // "", "M" or "m<value>"
    unsigned start = 0U;
    unsigned length = 0U;
    unsigned byte_order = 0U;  // 1 = Intel, 0 = Motorola
    char sign = '?';
    double factor = 0.0;
    double offset = 0.0;
    double minimum = 0.0;
    double maximum = 0.0;
    std::string unit;
};

struct DbcMessage {
    std::uint32_t id = 0U;
    std::string name;
    unsigned dlc = 0U;
    std::string sender;
    std::vector<DbcSignal> signals;
};

struct Dbc {
    std::vector<DbcMessage> messages;
    unsigned sg_lines = 0U;  // SG_ lines seen, parsed or not
};

/// Reads the BO_ and SG_ lines of a DBC file.
Dbc parse_dbc(const std::string& path) {
    static const std::regex bo(R"(^BO_\s+(\d+)\s+(\w+)\s*:\s*(\d+)\s+(\w+)\s*$)");
    static const std::regex sg(
        R"(^\s+SG_\s+(\w+)\s*(M|m\d+)?\s*:\s*(\d+)\|(\d+)@([01])([+-])\s*\(([^,]+),([^)]+)\)\s*\[([^|]+)\|([^\]]+)\]\s*\"([^\"]*)\"\s*(.*)$)");
    Dbc dbc;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        std::smatch m;
        if (std::regex_match(line, m, bo)) {
            DbcMessage msg;
            msg.id = static_cast<std::uint32_t>(std::stoul(m[1]));
            msg.name = m[2];
            msg.dlc = static_cast<unsigned>(std::stoul(m[3]));
            msg.sender = m[4];
            dbc.messages.push_back(msg);
        } else if (line.find(" SG_ ") == 0U) {
            ++dbc.sg_lines;
            if (std::regex_match(line, m, sg) && !dbc.messages.empty()) {
                DbcSignal s;
                s.name = m[1];
                s.multiplex = m[2];
                s.start = static_cast<unsigned>(std::stoul(m[3]));
                s.length = static_cast<unsigned>(std::stoul(m[4]));
                s.byte_order = static_cast<unsigned>(std::stoul(m[5]));
                s.sign = m[6].str()[0];
                s.factor = std::stod(m[7]);
                s.offset = std::stod(m[8]);
                s.minimum = std::stod(m[9]);
                s.maximum = std::stod(m[10]);
                s.unit = m[11];
                dbc.messages.back().signals.push_back(s);
            }
        }
    }
    return dbc;
}

const Dbc& the_dbc() {
    static const Dbc dbc = parse_dbc(std::string(CELLGUARD_SOURCE_DIR) + "/certification/cellguard.dbc");
    return dbc;
}

const DbcMessage* find_message(std::uint32_t id) {
    for (const DbcMessage& m : the_dbc().messages) {
        if (m.id == id) {
            return &m;
        }
    }
    return nullptr;
}

std::string expected_multiplex(const SignalLayout& s) {
    switch (s.multiplex) {
        case Multiplex::kNone: return "";
        case Multiplex::kMultiplexor: return "M";
        case Multiplex::kMultiplexed: return "m" + std::to_string(s.multiplex_value);
    }
    return "?";
}

/// Checks that @p msg holds exactly the signals of @p table, each as the table states it.
/// @p inverted: the raw range of the inverted copy is the whole field.
template <std::size_t N>
void check_against_table(const DbcMessage& msg, const SignalLayout (&table)[N], bool inverted) {
    CHECK(msg.signals.size() == N);
    for (const SignalLayout& s : table) {
        CAPTURE(msg.name);
        CAPTURE(s.name);
        int found = 0;
        for (const DbcSignal& d : msg.signals) {
            if (d.name != s.name) {
                continue;
            }
            ++found;
            CHECK(d.start == s.start_bit);
            CHECK(d.length == s.length);
            CHECK(d.byte_order == static_cast<unsigned>(s.byte_order));
            CHECK(d.sign == (s.is_signed ? '-' : '+'));
            CHECK(d.factor == static_cast<double>(s.factor));
            CHECK(d.offset == 0.0);
            CHECK(d.unit == s.unit);
            CHECK(d.multiplex == expected_multiplex(s));
            // The inverted copy's raw range is the whole field; a signed field is two's complement.
            const int value_bits = static_cast<int>(s.length) - (s.is_signed ? 1 : 0);
            const double field_max = std::ldexp(1.0, value_bits) - 1.0;
            const double raw_max = inverted ? field_max : s.raw_max;
            const double raw_min = !s.is_signed ? 0.0 : (inverted ? -field_max - 1.0 : -static_cast<double>(s.raw_max));
            CHECK(d.minimum == raw_min * static_cast<double>(s.factor));
            CHECK(d.maximum == raw_max * static_cast<double>(s.factor));
            CHECK(d.start + d.length <= 8U * msg.dlc);
        }
        CHECK(found == 1);
    }
}

}  // namespace

// verifies: SR-CAN-002
TEST_CASE("dbc: the file parses, every SG_ line included, and holds the twelve frames on the default CAN IDs") {
    const Dbc& dbc = the_dbc();
    REQUIRE(dbc.messages.size() == 12U);
    unsigned parsed = 0U;
    for (const DbcMessage& m : dbc.messages) {
        parsed += static_cast<unsigned>(m.signals.size());
        CHECK(m.dlc == 8U);
        const bool command = (m.id >= kDefaultCommandBaseCanId && m.id < kDefaultCommandBaseCanId + 6U) ||
                             m.id == kDefaultPlcLinkChannel.can_id;
        CHECK(m.sender == (command ? "PLC" : "CELLGUARD"));
    }
    CHECK(parsed == dbc.sg_lines);
    REQUIRE(find_message(kDefaultSafetyCanId) != nullptr);
    REQUIRE(find_message(inverted_can_id(SafetyChannelConfig{})) != nullptr);
    REQUIRE(find_message(kDefaultDiagnosticsCanId) != nullptr);
    CHECK(find_message(kDefaultSafetyCanId)->name == "CellguardSafety");
    CHECK(find_message(kDefaultSafetyCanId + 1U)->name == "CellguardSafetyInverted");
    CHECK(find_message(kDefaultDiagnosticsCanId)->name == "CellguardDiagnostics");
    REQUIRE(find_message(kDefaultSeparationCanId) != nullptr);
    CHECK(find_message(kDefaultSeparationCanId)->name == "CellguardSeparation");
    const char* const command_names[] = {"PlcCommandA",         "PlcCommandAInverted", "PlcCommandB",
                                         "PlcCommandBInverted", "PlcCommandC",         "PlcCommandCInverted"};
    for (std::uint32_t i = 0U; i < 6U; ++i) {
        const DbcMessage* m = find_message(kDefaultCommandBaseCanId + i);
        REQUIRE(m != nullptr);
        CHECK(m->name == command_names[i]);
    }
}

// verifies: SR-CAN-013
TEST_CASE("dbc: both link frames (protocol 0.2) match the link layout table") {
    REQUIRE(find_message(kDefaultControllerLinkChannel.can_id) != nullptr);
    REQUIRE(find_message(kDefaultPlcLinkChannel.can_id) != nullptr);
    CHECK(find_message(kDefaultControllerLinkChannel.can_id)->name == "CellguardLink");
    CHECK(find_message(kDefaultPlcLinkChannel.can_id)->name == "PlcLink");
    check_against_table(*find_message(kDefaultControllerLinkChannel.can_id), link_layout::kSignals, false);
    check_against_table(*find_message(kDefaultPlcLinkChannel.can_id), link_layout::kSignals, false);
}

// verifies: SR-CAN-002
TEST_CASE("dbc: the safety frame's signals match the layout table in start bit, length, byte order and factor") {
    REQUIRE(find_message(kDefaultSafetyCanId) != nullptr);
    check_against_table(*find_message(kDefaultSafetyCanId), safety_layout::kSignals, false);
}

// verifies: SR-CAN-002
TEST_CASE("dbc: the inverted copy has the safety frame's signals at the same bits") {
    REQUIRE(find_message(kDefaultSafetyCanId + 1U) != nullptr);
    check_against_table(*find_message(kDefaultSafetyCanId + 1U), safety_layout::kSignals, true);
}

// verifies: SR-CAN-002
TEST_CASE("dbc: the diagnostics frame's signals, multiplexing included, match the layout table") {
    REQUIRE(find_message(kDefaultDiagnosticsCanId) != nullptr);
    check_against_table(*find_message(kDefaultDiagnosticsCanId), diagnostics_layout::kSignals, false);
}

// verifies: SR-CMD-009
TEST_CASE("dbc: the separation frame's signals match the layout table") {
    REQUIRE(find_message(kDefaultSeparationCanId) != nullptr);
    check_against_table(*find_message(kDefaultSeparationCanId), separation_layout::kSignals, false);
}

// verifies: SR-CMD-009
TEST_CASE("dbc: the three command parts and their inverted copies match the layout tables, joints signed") {
    const CommandChannelConfig c;
    REQUIRE(find_message(command_can_id(c, CommandPart::kA)) != nullptr);
    REQUIRE(find_message(command_can_id(c, CommandPart::kB)) != nullptr);
    REQUIRE(find_message(command_can_id(c, CommandPart::kC)) != nullptr);
    check_against_table(*find_message(command_can_id(c, CommandPart::kA)), command_layout::kPartASignals, false);
    check_against_table(*find_message(command_can_id(c, CommandPart::kB)), command_layout::kPartBSignals, false);
    check_against_table(*find_message(command_can_id(c, CommandPart::kC)), command_layout::kPartCSignals, false);
    REQUIRE(find_message(command_copy_can_id(c, CommandPart::kA)) != nullptr);
    REQUIRE(find_message(command_copy_can_id(c, CommandPart::kB)) != nullptr);
    REQUIRE(find_message(command_copy_can_id(c, CommandPart::kC)) != nullptr);
    check_against_table(*find_message(command_copy_can_id(c, CommandPart::kA)), command_layout::kPartASignals, true);
    check_against_table(*find_message(command_copy_can_id(c, CommandPart::kB)), command_layout::kPartBSignals, true);
    check_against_table(*find_message(command_copy_can_id(c, CommandPart::kC)), command_layout::kPartCSignals, true);
}

namespace {

/// One frame of the frames file and the raw values a DBC decoder must find in it.
struct ExpectedFrame {
    CanFrame frame;
    std::vector<std::pair<std::string, long long>> values;
};

/// The E2E header's expected values (kBoth mode: no nibble).
void add_header(ExpectedFrame& e, std::uint8_t counter) {
    e.values.emplace_back("E2E_Crc", e.frame.data[0]);
    e.values.emplace_back("E2E_Counter", counter);
    e.values.emplace_back("E2E_DataIdNibble", 0);
}

/// The inverted copy of @p e: every raw value complemented in its field (signed fields: ~x).
ExpectedFrame inverted(const ExpectedFrame& e, const std::vector<unsigned>& lengths) {
    ExpectedFrame c{inverted_copy(e.frame), {}};
    for (std::size_t i = 0U; i < e.values.size(); ++i) {
        const long long v = e.values[i].second;
        const bool is_signed = lengths[i] == 0U;  // 0 marks a signed 16-bit joint
        c.values.emplace_back(e.values[i].first, is_signed ? ~v : ((1LL << lengths[i]) - 1) ^ v);
    }
    return c;
}

std::vector<ExpectedFrame> expected_frames() {
    std::vector<ExpectedFrame> out;
    const SafetyChannelConfig ch;
    SafetyMessage m;
    m.protective_stop = false;
    m.warning = true;
    m.active_case = 11U;
    m.reduced_speed = true;
    m.zone_count = 12U;
    m.zone_intrusion = 0x0801U;
    m.zone_unseen = 0x0402U;
    ExpectedFrame safety{encode_safety_frame(m, 6U, ch).value(), {}};
    add_header(safety, 6U);
    safety.values.insert(safety.values.end(), {{"ProtectiveStop", 0},
                                               {"Warning", 1},
                                               {"Fault", 0},
                                               {"ActiveCase", 11},
                                               {"ReducedSpeed", 1},
                                               {"ZoneIntrusion", 0x0801},
                                               {"ZoneUnseen", 0x0402},
                                               {"ZoneCount", 12}});
    out.push_back(safety);
    out.push_back(inverted(safety, {8U, 4U, 4U, 1U, 1U, 1U, 4U, 1U, 16U, 16U, 8U}));
    for (const std::uint8_t page : {std::uint8_t{0U}, std::uint8_t{3U}}) {
        DiagnosticsMessage d;
        d.cycle_time = 1001U;
        d.max_cycle_time = 2047U;
        d.active_faults = 0x8021U;
        d.prior_crc_page = page;
        d.prior_crc_part = page == 0U ? 0x0DU : 0xCAU;
        ExpectedFrame diag{encode_diagnostics_frame(d, 14U, ch).value(), {}};
        add_header(diag, 14U);
        diag.values.insert(diag.values.end(),
                           {{"ActiveFaults", 0x8021},
                            {"CycleTime", 1001},
                            {"MaxCycleTime", 2047},
                            {"PriorCrcPage", page},
                            {page == 0U ? "PriorCrcBits0To7" : "PriorCrcBits24To31", page == 0U ? 0x0D : 0xCA}});
        out.push_back(diag);
    }
    SeparationMessage sep;
    sep.distance_mm = 65535U;
    sep.required_mm = 1450U;
    sep.active_case = 15U;
    sep.speed_request = SpeedRequest::kProtectiveStop;
    sep.command_valid = true;
    sep.command_counter = 9U;
    ExpectedFrame separation{encode_separation_frame(sep, 0U, ch).value(), {}};
    add_header(separation, 0U);
    separation.values.insert(separation.values.end(), {{"SeparationDistance", 65535},
                                                       {"RequiredDistance", 1450},
                                                       {"ActiveCase", 15},
                                                       {"SpeedRequest", 2},
                                                       {"CommandValid", 1},
                                                       {"CommandCounter", 9}});
    out.push_back(separation);

    RobotCommand cmd;
    cmd.monitoring_case = 14U;
    cmd.speed_class = 3U;
    cmd.joint_count = 7U;
    cmd.robot_id = 0xFEDCU;
    cmd.reset_request = true;
    const std::int16_t joints[] = {-32767, 32767, -1, 0, 15708, -15708, 1234};
    for (std::size_t j = 0U; j < 7U; ++j) {
        cmd.joint_raw[j] = joints[j];
    }
    const CommandFrames s = encode_command_sample(cmd, 12U, CommandChannelConfig{}).value();
    ExpectedFrame a{s.frame[0], {}};
    add_header(a, 12U);
    a.values.insert(a.values.end(), {{"MonitoringCase", 14},
                                     {"SpeedClass", 3},
                                     {"ResetRequest", 1},
                                     {"JointCount", 7},
                                     {"Joint0", joints[0]},
                                     {"Joint1", joints[1]}});
    ExpectedFrame b{s.frame[2], {}};
    add_header(b, 12U);
    b.values.insert(b.values.end(), {{"Joint2", joints[2]}, {"Joint3", joints[3]}, {"Joint4", joints[4]}});
    ExpectedFrame c{s.frame[4], {}};
    add_header(c, 12U);
    c.values.insert(c.values.end(), {{"Joint5", joints[5]}, {"Joint6", joints[6]}, {"RobotId", 0xFEDC}});
    for (const LinkChannel& link_channel : {kDefaultControllerLinkChannel, kDefaultPlcLinkChannel}) {
        LinkFields f;
        f.sequence = 54321U;
        f.echo = 65535U;
        f.session = 200U;
        f.echo_session = 17U;
        const CanFrame bound[1] = {s.frame[0]};
        ExpectedFrame link{encode_link_frame(f, 12U, link_channel, Span<const CanFrame>(bound)).value(), {}};
        add_header(link, 12U);
        link.values.insert(link.values.end(),
                           {{"Sequence", 54321}, {"EchoSequence", 65535}, {"Session", 200}, {"EchoSession", 17}});
        out.push_back(link);
    }
    out.push_back(a);
    out.push_back(inverted(a, {8U, 4U, 4U, 4U, 2U, 1U, 3U, 0U, 0U}));
    out.push_back(b);
    out.push_back(inverted(b, {8U, 4U, 4U, 0U, 0U, 0U}));
    out.push_back(c);
    out.push_back(inverted(c, {8U, 4U, 4U, 0U, 0U, 16U}));
    return out;
}

/// A candump -L line with the expected raw values after a '#' comment.
std::string frames_file_line(const ExpectedFrame& e, int index) {
    char head[64];
    (void)std::snprintf(head, sizeof head, "(1700000000.%06d) vcan0 %03X#", index * 1000,
                        static_cast<unsigned>(e.frame.id));
    std::string line = head;
    for (std::size_t k = 0U; k < e.frame.dlc; ++k) {
        char byte[3];
        (void)std::snprintf(byte, sizeof byte, "%02X", static_cast<unsigned>(e.frame.data[k]));
        line += byte;
    }
    line += " #";
    for (const auto& v : e.values) {
        line += " " + v.first + "=" + std::to_string(v.second);
    }
    return line;
}

}  // namespace

// verifies: SR-CMD-009
TEST_CASE("dbc: the frames file for the third-party decoder check covers every message of the DBC") {
    const std::vector<ExpectedFrame> frames = expected_frames();
    std::string text;
    int index = 0;
    for (const ExpectedFrame& e : frames) {
        CAPTURE(e.frame.id);
        const DbcMessage* m = find_message(e.frame.id);
        REQUIRE(m != nullptr);
        // every signal of the message (the active multiplexed one only) has an expected value
        std::size_t present = 0U;
        for (const DbcSignal& sig : m->signals) {
            present += (sig.multiplex.empty() || sig.multiplex == "M" ||
                        sig.multiplex == "m" + std::to_string(e.frame.data[6] >> 6U))
                           ? 1U
                           : 0U;
        }
        CHECK(e.values.size() == present);
        text += frames_file_line(e, index++) + "\n";
    }
    CHECK(frames.size() == 13U);  // the twelve messages, the diagnostics frame on two pages
    // tools/dbc_decode_check.py runs this test case with CELLGUARD_DBC_FRAMES_OUT set and decodes the file.
    if (const char* path = std::getenv("CELLGUARD_DBC_FRAMES_OUT"); path != nullptr) {
        std::ofstream out(path);
        out << text;
        CHECK(out.good());
    }
}
