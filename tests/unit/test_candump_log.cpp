// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the candump log (candump -L format): exact line text, round trip through the parser, bad lines and bad frames refused, the writer as a CanSender; and the Linux monotonic clock advances.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cellguard/host/io/candump_log.hpp"
#include "cellguard/port/clock.hpp"

using namespace cellguard;
using namespace cellguard::linux_port;

namespace {

class StepClock final : public MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t += 250U; }
    std::uint64_t t = 1700000000000000U;
};

std::string line_of(std::uint64_t t, const char* iface, const CanFrame& f) {
    char buf[kCandumpLineCapacity];
    const std::size_t n = format_candump_line(buf, sizeof(buf), t, iface, f);
    return std::string(buf, n);
}

}  // namespace

// verifies: SR-CAN-012
TEST_CASE("candump log: a frame is written as candump -L writes it") {
    const CanFrame f{0x101U, 8U, {0x00U, 0x11U, 0x22U, 0x33U, 0x44U, 0x55U, 0x66U, 0x77U}};
    CHECK(line_of(1700000000123456U, "vcan0", f) == "(1700000000.123456) vcan0 101#0011223344556677");
    const CanFrame g{0x7U, 2U, {0xABU, 0x0CU}};
    CHECK(line_of(5U, "can1", g) == "(0.000005) can1 007#AB0C");
    const CanFrame empty{0x7FFU, 0U, {}};
    CHECK(line_of(1000000U, "vcan0", empty) == "(1.000000) vcan0 7FF#");
}

// verifies: SR-CAN-012
TEST_CASE("candump log: frames that candump -L cannot show as standard frames, and bad names, are refused") {
    char buf[kCandumpLineCapacity];
    CHECK(format_candump_line(buf, sizeof(buf), 0U, "vcan0", CanFrame{0x800U, 8U, {}}) == 0U);
    CHECK(format_candump_line(buf, sizeof(buf), 0U, "vcan0", CanFrame{0x100U, 9U, {}}) == 0U);
    CHECK(format_candump_line(buf, sizeof(buf), 0U, "", CanFrame{0x100U, 1U, {}}) == 0U);
    CHECK(format_candump_line(buf, sizeof(buf), 0U, "an interface", CanFrame{0x100U, 1U, {}}) == 0U);
    CHECK(format_candump_line(buf, sizeof(buf), 0U, "sixteen-chars-xx", CanFrame{0x100U, 1U, {}}) == 0U);
    CHECK(format_candump_line(buf, 10U, 0U, "vcan0", CanFrame{0x100U, 8U, {}}) == 0U);  // does not fit
}

// verifies: SR-CAN-012
TEST_CASE("candump log: a written line parses back to the same frame, time and interface") {
    const CanFrame f{0x103U, 8U, {1U, 2U, 3U, 4U, 5U, 6U, 7U, 0xFEU}};
    const std::string line = line_of(42000017U, "vcan0", f) + "\n";
    CandumpRecord r;
    REQUIRE(parse_candump_line(line.c_str(), r).ok());
    CHECK(r.timestamp_us == 42000017U);
    CHECK(std::string(r.interface_name) == "vcan0");
    CHECK(r.frame.id == 0x103U);
    CHECK(r.frame.dlc == 8U);
    CHECK(r.frame.data[7] == 0xFEU);
    REQUIRE(parse_candump_line("(1.000000) vcan0 7ff#", r).ok());  // lower case and DLC 0 too
    CHECK(r.frame.id == 0x7FFU);
    CHECK(r.frame.dlc == 0U);
}

// verifies: SR-CAN-012
TEST_CASE("candump log: malformed lines are refused with a message, never read past the end") {
    const char* bad[] = {"",
                         "1.000000) vcan0 101#00",
                         "(1.00000) vcan0 101#00",
                         "(.000000) vcan0 101#00",
                         "(1.000000)vcan0 101#00",
                         "(1.000000) vcan0 1010#00",
                         "(1.000000) vcan0 101#0",
                         "(1.000000) vcan0 101#001122334455667788",
                         "(1.000000) vcan0 101#00 extra",
                         "(1.000000) vcan0",
                         "(1.000000) vcan0 10",
                         "(1.000000) a-very-long-interface 101#00"};
    for (const char* line : bad) {
        CAPTURE(line);
        CandumpRecord r;
        r.frame.id = 0x55U;
        const IoStatus s = parse_candump_line(line, r);
        CHECK(s.error() == ErrorCode::kMalformedInput);
        CHECK(std::string(s.message()).find("candump line") == 0U);
        CHECK(r.frame.id == 0x55U);  // untouched
    }
    CandumpRecord r;
    CHECK_FALSE(parse_candump_line(nullptr, r).ok());
}

// verifies: SR-CAN-012
TEST_CASE("candump log: the writer is a CanSender that appends one timestamped line per frame") {
    const std::string path = (std::filesystem::temp_directory_path() / "cellguard-candump-test.log").string();
    StepClock clock;
    CandumpLogWriter w;
    CanSender& sender = w;
    CHECK_FALSE(sender.send(CanFrame{0x101U, 8U, {}}));  // not open
    REQUIRE(w.open(path.c_str(), "vcan0", clock).ok());
    CHECK(sender.send(CanFrame{0x101U, 8U, {0xAAU}}));
    CHECK(sender.send(CanFrame{0x102U, 1U, {0x55U}}));
    CHECK_FALSE(sender.send(CanFrame{0x900U, 1U, {}}));  // not a standard ID: refused, nothing written
    CHECK(w.lines() == 2U);
    CHECK(w.close());
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);)
        lines.push_back(l);
    REQUIRE(lines.size() == 2U);
    CHECK(lines[0] == "(1700000000.000250) vcan0 101#AA00000000000000");
    CHECK(lines[1] == "(1700000000.000500) vcan0 102#55");
    std::remove(path.c_str());
    CandumpLogWriter bad;
    CHECK(bad.open(path.c_str(), "bad name", clock).error() == ErrorCode::kInvalidArgument);
    const IoStatus s = bad.open("/nonexistent-dir/x.log", "vcan0", clock);
    CHECK(s.error() == ErrorCode::kInvalidArgument);
    CHECK(std::string(s.message()).find("/nonexistent-dir/x.log") == 0U);
}

// Issue 32: a monitor refused after opening its log (an --http address it cannot bind, a missing prior)
// had already truncated the previous run's log to 0 bytes.
// verifies: SR-CAN-012
TEST_CASE("candump log: opening keeps an earlier log until the first frame, which replaces it") {
    const std::string path = (std::filesystem::temp_directory_path() / "cellguard-candump-keep-test.log").string();
    {
        std::ofstream old(path);
        old << "(1.000000) vcan0 101#00\n";
    }
    const auto text = [&path] {
        std::ifstream in(path);
        std::ostringstream all;
        all << in.rdbuf();
        return all.str();
    };
    StepClock clock;
    {
        CandumpLogWriter w;
        REQUIRE(w.open(path.c_str(), "vcan0", clock).ok());
        CHECK(w.close());  // refused before the first cycle: nothing sent
    }
    CHECK(text() == "(1.000000) vcan0 101#00\n");
    CandumpLogWriter w;
    REQUIRE(w.open(path.c_str(), "vcan0", clock).ok());
    CHECK(w.send(CanFrame{0x102U, 1U, {0x55U}}));
    CHECK(w.send(CanFrame{0x101U, 1U, {0xAAU}}));
    CHECK(w.close());
    CHECK(text() == "(1700000000.000250) vcan0 102#55\n(1700000000.000500) vcan0 101#AA\n");
    std::remove(path.c_str());
}

// verifies: SR-SYS-003
TEST_CASE("monotonic clock: CLOCK_MONOTONIC in microseconds never goes backwards") {
    LinuxMonotonicClock clock;
    const std::uint64_t a = clock.now_us();
    const std::uint64_t b = clock.now_us();
    CHECK(a > 0U);
    CHECK(b >= a);
}
