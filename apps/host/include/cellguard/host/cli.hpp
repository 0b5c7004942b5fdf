// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file cli.hpp
/// What every host program's command line does alike (apps/; issues 15 and
/// 16): `--version` prints "<program> <version>" to stdout and exits 0,
/// `--help` prints the usage to stdout and exits 0, and a usage error prints
/// one line naming the option, "<program>: <message> (see --help)", to stderr
/// and exits 2. An option that takes a value never takes the next option as
/// its value: `--out --help` is "--out needs a value", not an output folder
/// named "--help".
///
/// The programs parse with CLI11 through command_line.hpp. This header holds
/// the few pieces that need no CLI11, for command_line.cpp and for
/// cellguard-firmware-digest, which parses its one optional argument by hand
/// (it is also built for the cross targets). Standard C++ only.
#ifndef CELLGUARD_HOST_CLI_HPP
#define CELLGUARD_HOST_CLI_HPP

#include <cstdio>
#include <string>

#include "cellguard/host/version.hpp"

namespace cellguard::host {

/// Exit status of a usage error (bad command line), in every program.
constexpr int kExitUsage = 2;

/// The --version answer: "<program> <version>" (no newline).
inline std::string version_text(const std::string& program) { return program + " " + kVersion; }

/// Prints version_text(@p program) and a newline to stdout.
inline void print_version(const char* program) { std::printf("%s\n", version_text(program).c_str()); }

/// The line a usage error prints to stderr: "<program>: <message> (see --help)"
/// and a newline.
inline std::string usage_error_line(const std::string& program, const std::string& message) {
    return program + ": " + message + " (see --help)\n";
}

/// Prints usage_error_line(@p program, @p message) to stderr; returns kExitUsage.
inline int usage_error(const char* program, const std::string& message) {
    static_cast<void>(std::fputs(usage_error_line(program, message).c_str(), stderr));
    return kExitUsage;
}

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_CLI_HPP
