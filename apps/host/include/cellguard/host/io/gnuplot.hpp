// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file gnuplot.hpp
/// Plots of the host programs (cellguard-eval's precision-recall curves,
/// cellguard-detection's detection rates): each writes a gnuplot script
/// beside its CSV and runs gnuplot on it when it is installed. gnuplot is
/// optional: without it the script and the CSV stay, and the program says so.
#ifndef CELLGUARD_HOST_IO_GNUPLOT_HPP
#define CELLGUARD_HOST_IO_GNUPLOT_HPP

#include <cstdio>
#include <string>

namespace cellguard::host {

/// True when a `gnuplot` program is on the PATH.
[[nodiscard]] bool have_gnuplot();

/// @p text as one single-quoted word for the POSIX shell: each ' written as
/// '\'' (so a path with a quote in it stays one argument and runs nothing).
[[nodiscard]] std::string shell_quoted(const std::string& text);

/// Writes @p script to @p script_path and, when gnuplot is installed, runs
/// it. False, with the reason on @p err (the calling program's name first),
/// when the script cannot be written; true otherwise, with a note on @p err
/// when gnuplot is not installed or fails (no plot; the script stays).
[[nodiscard]] bool write_and_run_gnuplot(const std::string& script_path, const std::string& script, const char* program,
                                         std::FILE* err);

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_GNUPLOT_HPP
