// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/gnuplot.hpp"

#include <cstdlib>
#include <fstream>

namespace cellguard::host {

bool have_gnuplot() {
    // NOLINTNEXTLINE(cert-env33-c): a fixed command string that asks the shell whether gnuplot is installed
    return std::system("command -v gnuplot > /dev/null 2>&1") == 0;
}

std::string shell_quoted(const std::string& text) {
    std::string out = "'";
    for (const char c : text) {
        if (c == '\'') {
            out += "'\\''";  // close the quote, an escaped quote, open again
        } else {
            out += c;
        }
    }
    out += '\'';
    return out;
}

bool write_and_run_gnuplot(const std::string& script_path, const std::string& script, const char* program,
                           std::FILE* err) {
    std::ofstream f(script_path, std::ios::binary);
    f << script;
    f.close();
    if (!f) {
        static_cast<void>(std::fprintf(err, "%s: cannot write %s\n", program, script_path.c_str()));
        return false;
    }
    if (!have_gnuplot()) {
        static_cast<void>(
            std::fprintf(err, "%s: gnuplot is not installed: %s written, not drawn\n", program, script_path.c_str()));
        return true;
    }
    const std::string cmd = "gnuplot " + shell_quoted(script_path);
    // NOLINTNEXTLINE(cert-env33-c): gnuplot on the script just written; the command is the program's own, for the user who runs it
    if (std::system(cmd.c_str()) != 0) {
        static_cast<void>(std::fprintf(err, "%s: gnuplot failed on %s\n", program, script_path.c_str()));
    }
    return true;
}

}  // namespace cellguard::host
