// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-prior: the accessibility prior of an empty workcell, as a prior
// image, flash source and .npy files. The tool is run_prior_tool (prior_tool.hpp).
#include <unistd.h>

#include <iostream>
#include <string>
#include <vector>

#include "cellguard/prior_tool/prior_tool.hpp"

int main(int argc, char** argv) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        args.emplace_back(argv[i]);
    }
    return cellguard::prior_tool::run_prior_tool(args, std::cout, std::cerr, isatty(STDERR_FILENO) == 1);
}
