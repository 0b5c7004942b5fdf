// cellguard-monitor-check-log: checks a candump log written by
// `cellguard-monitor --demo` as the robot's PLC would receive it: the PLC-side
// receiver gets every frame at its time stamp and is polled on the log's clock
// up to the end of the run; every frame decodes, every inverted copy matches,
// the receiver never enters the safe state once recovered, and the stop
// request appears in the cycle in which the scripted person enters the
// protective zone (and not in the cycle before). The checks themselves are
// check_demo_log (demo_log_check.hpp).
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "cellguard/host/cli.hpp"
#include "cellguard/monitor/config.hpp"
#include "cellguard/monitor/demo_log_check.hpp"

using namespace cellguard;
using namespace cellguard::monitor;

namespace {

constexpr const char* kProgram = "cellguard-monitor-check-log";

constexpr const char* kUsage =
    "usage: cellguard-monitor-check-log LOG CYCLES\n"
    "\n"
    "Checks the candump log LOG of `cellguard-monitor --demo --cycles CYCLES` as the\n"
    "robot's PLC would receive it: each frame goes to the PLC-side receiver at its time\n"
    "stamp, and the receiver is polled every 1 ms of log time up to the end of the run\n"
    "(the first frame's time plus CYCLES periods), with SRVT half a period and SCT three\n"
    "periods. Fails on a malformed line, a counter out of sequence, a mismatching copy,\n"
    "any receiver fault (frames that stop early, a frame late past the SRVT, a pair\n"
    "split by more than the SRVT), a wrong line count, or a stop request that is not\n"
    "in the cycle in which the scripted person enters the protective zone.\n"
    "\n"
    "  --help     this text\n"
    "  --version  print the version and exit\n"
    "\n"
    "Exit status: 0 the log passes, 1 it fails (one FAIL line each on stderr),\n"
    "2 bad command line or unreadable log.\n";

static_assert(kDemoLogMaxCycles == 1000000, "the usage error below states the limit");

/// CYCLES as an integer 1..kDemoLogMaxCycles; false for anything else.
bool parse_cycles(const char* text, int& cycles) {
    char* end = nullptr;
    errno = 0;
    const long n = std::strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || n < 1 || n > kDemoLogMaxCycles) {
        return false;
    }
    cycles = static_cast<int>(n);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::fputs(kUsage, stdout);
            return 0;
        }
        if (std::strcmp(argv[i], "--version") == 0) {
            host::print_version(kProgram);
            return 0;
        }
        if (std::strncmp(argv[i], "--", 2U) == 0) {
            return host::usage_error(kProgram, "unknown option", argv[i]);
        }
    }
    if (argc != 3) {
        return host::usage_error(kProgram, "expects two arguments, LOG and CYCLES");
    }
    int cycles = 0;
    if (!parse_cycles(argv[2], cycles)) {
        return host::usage_error(kProgram, "CYCLES expects an integer 1..1000000, got", argv[2]);
    }
    const DemoLogCheck r = check_demo_log_file(argv[1], cycles, demo_config());
    for (const std::string& f : r.failures) {
        std::fprintf(stderr, "%s: %s\n", r.input_ok ? "FAIL" : kProgram, f.c_str());
    }
    if (!r.input_ok) {
        return host::kExitUsage;
    }
    std::printf("%s\n", r.summary.c_str());
    return r.passed() ? 0 : 1;
}
