// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The host's gnuplot helper (apps/host io/gnuplot.hpp): shell quoting, and a
// plot drawn into a folder whose name holds a quote (a user's --out).
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "cellguard/host/io/gnuplot.hpp"
#include "temp_dir.hpp"

using namespace cellguard;

// verifies: SR-EVAL-005
TEST_CASE("gnuplot: a quoted word keeps quotes, spaces and shell characters as text") {
    CHECK(host::shell_quoted("plain") == "'plain'");
    CHECK(host::shell_quoted("it's here") == "'it'\\''s here'");
    CHECK(host::shell_quoted("") == "''");
    CHECK(host::shell_quoted("$(x); `y` \"z\"") == "'$(x); `y` \"z\"'");
}

// verifies: SR-EVAL-005
TEST_CASE("gnuplot: a script in a folder whose name holds a quote is written, and drawn when gnuplot is installed") {
    const test::TempDir tmp("gnuplot");
    const std::string dir = tmp / "it's a folder";
    REQUIRE(std::filesystem::create_directory(dir));
    const std::string png = dir + "/plot.png";
    std::string quoted_png;  // for gnuplot's single-quoted string: ' doubled
    for (const char c : png) {
        quoted_png += c;
        if (c == '\'') {
            quoted_png += '\'';
        }
    }
    const std::string script = "set terminal pngcairo size 64,48\nset output '" + quoted_png + "'\nplot x\n";
    std::FILE* err = std::tmpfile();
    REQUIRE(err != nullptr);
    CHECK(host::write_and_run_gnuplot(dir + "/plot.gp", script, "test", err));
    CHECK(std::filesystem::exists(dir + "/plot.gp"));
    if (host::have_gnuplot()) {
        CHECK(std::filesystem::exists(png));
        CHECK(std::ftell(err) == 0);  // no "gnuplot failed" note
    } else {
        MESSAGE("gnuplot not installed: the plot is not drawn");
    }
    static_cast<void>(std::fclose(err));
}
