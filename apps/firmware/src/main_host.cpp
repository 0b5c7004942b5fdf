// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-firmware-digest: the firmware's canned run (scenario.hpp) on a
// Linux host (x86-64 natively, aarch64 under qemu-user): prints the same
// lines and digest as the Cortex-M7 image. With an argument 0x........ it
// exits 1 unless the digest equals it; --help, --version and usage errors as
// every program (cellguard/host/cli.hpp), a bad command line exits 2. Its one
// optional argument is parsed by hand, not with CLI11 (command_line.hpp):
// this is the host twin of the bare-metal image's main, built for every
// Linux target of tools/cross.sh, and CLI11 would bring exceptions, RTTI
// and the heap for that one argument.
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

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
    "usage: cellguard-firmware-digest [EXPECTED]\n"
    "\n"
    "Runs the firmware's canned scenario on this host and prints the same lines,\n"
    "CAN frames and digest as the Cortex-M7 image.\n"
    "\n"
    "arguments:\n"
    "  EXPECTED                    the digest to compare with: 0x and 1 to 8 hex\n"
    "                              digits, as in apps/firmware/expected_digest.txt\n"
    "\n"
    "options:\n"
    "  -h, --help                  print this help and exit\n"
    "  --version                   print the version and exit\n"
    "\n"
    "Exit status: 0 the run completed (and the digest matches EXPECTED), 1 the\n"
    "set-up failed or the digest differs, 2 bad command line.\n";

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

/// Reads the command line: the optional EXPECTED digest into @p expected_text
/// and @p expected, and -1 to run; else the exit status (0 after --help or
/// --version, 2 after a usage error).
int parse_args(int argc, char** argv, const char*& expected_text, unsigned long& expected) {
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
    if (argc > 2) {
        return cellguard::host::usage_error(kProgram, std::string("unknown argument '") + argv[2] + "'");
    }
    if (argc == 2 && !parse_digest(argv[1], expected)) {
        return cellguard::host::usage_error(
            kProgram, std::string("EXPECTED expects 0x and 1 to 8 hex digits, got '") + argv[1] + "'");
    }
    expected_text = argc == 2 ? argv[1] : nullptr;
    return -1;
}

}  // namespace

int main(int argc, char** argv) {
    const char* expected_text = nullptr;
    unsigned long expected = 0U;
    const int parse_status = parse_args(argc, argv, expected_text, expected);
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
    if (expected_text != nullptr) {
        if (expected != s.digest) {
            std::printf("digest 0x%08x differs from the expected %s\n", static_cast<unsigned>(s.digest), expected_text);
            return 1;
        }
        std::printf("digest matches the expected %s\n", expected_text);
    }
    return 0;
}
