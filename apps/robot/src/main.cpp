// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-robot: a robot's URDF as the robot image. The tool is
// run_robot_tool (robot_tool.hpp).
#include <iostream>
#include <string>
#include <vector>

#include "cellguard/robot_tool/robot_tool.hpp"

int main(int argc, char** argv) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        args.emplace_back(argv[i]);
    }
    return cellguard::robot_tool::run_robot_tool(args, std::cout, std::cerr);
}
