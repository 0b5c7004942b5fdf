// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: certification/cellguard.dbc states every frame and signal exactly as the layout tables in safety_frame.hpp.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "cellguard/can/safety_frame.hpp"

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
            CHECK(d.sign == '+');
            CHECK(d.factor == static_cast<double>(s.factor));
            CHECK(d.offset == 0.0);
            CHECK(d.unit == s.unit);
            CHECK(d.multiplex == expected_multiplex(s));
            CHECK(d.minimum == 0.0);
            const double raw_max = inverted ? std::ldexp(1.0, static_cast<int>(s.length)) - 1.0 : s.raw_max;
            CHECK(d.maximum == raw_max * static_cast<double>(s.factor));
            CHECK(d.start + d.length <= 8U * msg.dlc);
        }
        CHECK(found == 1);
    }
}

}  // namespace

// verifies: SR-CAN-002
TEST_CASE("dbc: the file parses, every SG_ line included, and holds the three frames on the default CAN IDs") {
    const Dbc& dbc = the_dbc();
    REQUIRE(dbc.messages.size() == 3U);
    unsigned parsed = 0U;
    for (const DbcMessage& m : dbc.messages) {
        parsed += static_cast<unsigned>(m.signals.size());
        CHECK(m.dlc == 8U);
        CHECK(m.sender == "CELLGUARD");
    }
    CHECK(parsed == dbc.sg_lines);
    REQUIRE(find_message(kDefaultSafetyCanId) != nullptr);
    REQUIRE(find_message(inverted_can_id(SafetyChannelConfig{})) != nullptr);
    REQUIRE(find_message(kDefaultDiagnosticsCanId) != nullptr);
    CHECK(find_message(kDefaultSafetyCanId)->name == "CellguardSafety");
    CHECK(find_message(kDefaultSafetyCanId + 1U)->name == "CellguardSafetyInverted");
    CHECK(find_message(kDefaultDiagnosticsCanId)->name == "CellguardDiagnostics");
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
