/// @file cli.hpp
/// What every host program's command line does alike (apps/; issue 15):
/// `--version` prints "<program> <version>" to stdout and exits 0, `--help`
/// prints the usage to stdout and exits 0, and a usage error prints a message
/// naming the option to stderr and exits 2. An option that takes a value
/// never takes the next option as its value: `--out --help` is "--out needs
/// a value", not an output folder named "--help".
///
/// Header-only and standard C++ only, so that the firmware's host digest
/// program can use it on every Linux target. The programs on CLI11
/// (command_line.hpp) share version_text() and usage_error_line().
#ifndef CELLGUARD_HOST_CLI_HPP
#define CELLGUARD_HOST_CLI_HPP

#include <cstdio>
#include <cstring>
#include <string>

#include "cellguard/host/version.hpp"

namespace cellguard::host {

/// Exit status of a usage error (bad command line), in every program.
constexpr int kExitUsage = 2;

/// The --version answer: "<program> <version>" (no newline).
inline std::string version_text(const std::string& program) { return program + " " + kVersion; }

/// The line a usage error prints to stderr: "<program>: <message> (see --help)"
/// and a newline (command_line.hpp, the programs on CLI11).
inline std::string usage_error_line(const std::string& program, const std::string& message) {
    return program + ": " + message + " (see --help)\n";
}

/// Prints "<program> <version>" and a newline to stdout (the --version answer).
inline void print_version(const char* program) noexcept { std::printf("%s %s\n", program, kVersion); }

/// True when @p arg can be an option's value: it exists and does not start
/// with "--" (that is the next option). Single-dash text such as "-0.5" is a value.
inline bool is_option_value(const char* arg) noexcept {
    return arg != nullptr && std::strncmp(arg, "--", 2U) != 0;
}

/// The value of the option at argv[@p i]: argv[i + 1] when there is one and
/// is_option_value() holds, with @p i advanced to it; nullptr otherwise (the
/// caller reports needs_value()).
inline const char* take_value(int argc, char** argv, int& i) noexcept {
    if (i + 1 >= argc || !is_option_value(argv[i + 1])) {
        return nullptr;
    }
    ++i;
    return argv[i];
}

/// Prints "<program>: <message>" and "Try '<program> --help'." to stderr and
/// returns kExitUsage.
inline int usage_error(const char* program, const char* message) noexcept {
    std::fprintf(stderr, "%s: %s\nTry '%s --help'.\n", program, message, program);
    return kExitUsage;
}

/// usage_error() with @p quoted appended in quotes: "<program>: <message> '<quoted>'".
inline int usage_error(const char* program, const char* message, const char* quoted) noexcept {
    std::fprintf(stderr, "%s: %s '%s'\nTry '%s --help'.\n", program, message, quoted, program);
    return kExitUsage;
}

/// usage_error() for an option given without its value: "<option> needs a value".
inline int needs_value(const char* program, const char* option) noexcept {
    std::fprintf(stderr, "%s: %s needs a value\nTry '%s --help'.\n", program, option, program);
    return kExitUsage;
}

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_CLI_HPP
