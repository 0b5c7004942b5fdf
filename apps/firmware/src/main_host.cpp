// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-firmware-digest: the firmware's canned runs (scenario.hpp, then
// robot_scenario.hpp, then the first run fused by footprint) on a Linux host
// (x86-64 natively, aarch64 under qemu-user): prints the same lines and
// digests as the Cortex-M7 image. With an argument 0x........ it exits 1
// unless the first run's digest equals it, with a second one likewise for the
// robot-cell run's, with a third for the footprint run's; --help, --version
// and usage errors as every program (cellguard/host/cli.hpp), a bad command
// line exits 2. Its optional arguments are parsed by hand, not with CLI11 (command_line.hpp):
// this is the host twin of the bare-metal image's main, built for every
// Linux target of tools/cross.sh, and CLI11 would bring exceptions, RTTI
// and the heap for those two arguments.
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "cellguard/firmware/robot_scenario.hpp"
#include "cellguard/firmware/scenario.hpp"
#include "cellguard/host/cli.hpp"

namespace {

/// A deterministic clock: one microsecond per reading.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class CountingClock final : public cellguard::MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t_ += 1U; }

private:
    std::uint64_t t_ = 1000000U;
};

// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class StdoutText final : public cellguard::firmware::TextSink {
public:
    void write(const char* text) noexcept override { static_cast<void>(std::fputs(text, stdout)); }
};

/// Prints frames like the board's semihosting CAN backend.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class PrintingCan final : public cellguard::CanSender {
public:
    bool send(const cellguard::CanFrame& frame) noexcept override {
        static_cast<void>(
            std::printf("can 0x%03x [%u]", static_cast<unsigned>(frame.id), static_cast<unsigned>(frame.dlc)));
        for (unsigned i = 0U; i < frame.dlc && i < 8U; ++i) {
            static_cast<void>(std::printf(" %02x", static_cast<unsigned>(frame.data[i])));
        }
        static_cast<void>(std::printf("\n"));
        return true;
    }
};

constexpr const char* kProgram = "cellguard-firmware-digest";

constexpr const char* kUsage =
    "usage: cellguard-firmware-digest [EXPECTED [ROBOT_EXPECTED [FOOTPRINT_EXPECTED]]]\n"
    "\n"
    "Runs the firmware's canned scenarios (the zones-only run, the robot cell,\n"
    "then the zones-only run fused by footprint fusion) on this host and prints\n"
    "the same lines, CAN frames and digests as the Cortex-M7 image.\n"
    "\n"
    "arguments:\n"
    "  EXPECTED                    the first run's digest: 0x and 1 to 8 hex\n"
    "                              digits, as in apps/firmware/expected_digest.txt\n"
    "  ROBOT_EXPECTED              the robot-cell run's digest, as in\n"
    "                              apps/firmware/expected_robot_digest.txt\n"
    "  FOOTPRINT_EXPECTED          the footprint run's digest, as in\n"
    "                              apps/firmware/expected_footprint_digest.txt\n"
    "\n"
    "options:\n"
    "  -h, --help                  print this help and exit\n"
    "  --version                   print the version and exit\n"
    "\n"
    "Exit status: 0 the three runs completed (and the digests match), 1 a set-up\n"
    "failed or a digest differs, 2 bad command line.\n";

/// @p text as a digest, "0x" and 1 to 8 hex digits; false for anything else.
bool parse_digest(const char* text, unsigned long& value) {
    const std::size_t n = std::strlen(text);
    if (n < 3U || n > 10U || text[0] != '0' || (text[1] != 'x' && text[1] != 'X') ||
        std::strspn(text + 2, "0123456789abcdefABCDEF") != n - 2U) {
        return false;
    }
    value = std::strtoul(text + 2, nullptr, 16);
    return true;
}

/// An expected digest from the command line.
struct Expected {
    const char* text = nullptr;  ///< as given; nullptr: not given
    unsigned long value = 0U;    ///< its value
};

/// Reads the command line: the optional EXPECTED, ROBOT_EXPECTED and FOOTPRINT_EXPECTED digests
/// into @p expected, and -1 to run; else the exit status (0 after --help or
/// --version, 2 after a usage error).
int parse_args(int argc, char** argv, Expected (&expected)[3]) {
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        if (std::strcmp(a, "--help") == 0 || std::strcmp(a, "-h") == 0) {
            static_cast<void>(std::fputs(kUsage, stdout));
            return 0;
        }
        if (std::strcmp(a, "--version") == 0) {
            cellguard::host::print_version(kProgram);
            return 0;
        }
        if (a[0] == '-') {
            return cellguard::host::usage_error(kProgram, std::string("unknown argument '") + a + "'");
        }
    }
    if (argc > 4) {
        return cellguard::host::usage_error(kProgram, std::string("unknown argument '") + argv[4] + "'");
    }
    constexpr const char* kNames[3] = {"EXPECTED", "ROBOT_EXPECTED", "FOOTPRINT_EXPECTED"};
    for (int i = 1; i < argc; ++i) {
        Expected& e = expected[i - 1];
        if (!parse_digest(argv[i], e.value)) {
            return cellguard::host::usage_error(
                kProgram, std::string(kNames[i - 1]) + " expects 0x and 1 to 8 hex digits, got '" + argv[i] + "'");
        }
        e.text = argv[i];
    }
    return -1;
}

/// False (said on stdout) when @p e is given and differs from @p digest.
bool matches(const Expected& e, std::uint32_t digest) {
    if (e.text == nullptr) {
        return true;
    }
    if (e.value != digest) {
        std::printf("digest 0x%08x differs from the expected %s\n", static_cast<unsigned>(digest), e.text);
        return false;
    }
    std::printf("digest matches the expected %s\n", e.text);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    Expected expected[3];
    const int parse_status = parse_args(argc, argv, expected);
    if (parse_status >= 0) {
        return parse_status;
    }
    CountingClock clock;
    StdoutText text;
    PrintingCan can;
    const cellguard::firmware::ScenarioSummary s = cellguard::firmware::run_scenario(clock, can, text);
    if (!s.setup_ok || s.cycles != cellguard::firmware::kScenarioCycles) {
        return 1;
    }
    const cellguard::firmware::ScenarioSummary r = cellguard::firmware::run_robot_scenario(can, text);
    if (!r.setup_ok || r.cycles != cellguard::firmware::kRobotScenarioCycles) {
        return 1;
    }
    const cellguard::firmware::ScenarioSummary f = cellguard::firmware::run_footprint_scenario(clock, can, text);
    if (!f.setup_ok || f.cycles != cellguard::firmware::kScenarioCycles) {
        return 1;
    }
    const bool first = matches(expected[0], s.digest);
    const bool robot = matches(expected[1], r.digest);
    const bool footprint = matches(expected[2], f.digest);
    return first && robot && footprint ? 0 : 1;
}
