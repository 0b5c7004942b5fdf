// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_tool.hpp
/// cellguard-robot, the commissioning tool that turns a robot's URDF into
/// the robot image (cellguard/robot/robot_image.hpp) the controllers load:
///
///   cellguard-robot --urdf FILE --joints a,b,c,... --base x,y,z[,yaw_deg]
///                   --out robot.cgrobot [--package name=dir]...
///
/// It imports the URDF (cellguard/host/io/urdf_import.hpp: --joints is the
/// PLC's joint order, --base the root link's pose in the cell, --package
/// resolves package:// mesh paths), writes the image, reads it back with the
/// controller's loader, and prints a summary: the links, the movable joints
/// with their limits and command positions, the capsules with radius and
/// length, what the import changed, and the image's CRC-32 with the 16-bit
/// robot id the PLC must send.
///
/// Exit status: kExitOk (0) written and verified; kExitOutputError (1) the
/// image could not be written or failed its read-back; kExitInputError (2)
/// a bad command line or a refused URDF (one line on stderr naming the
/// link, joint or file).
#ifndef CELLGUARD_ROBOT_TOOL_ROBOT_TOOL_HPP
#define CELLGUARD_ROBOT_TOOL_ROBOT_TOOL_HPP

#include <ostream>
#include <string>
#include <vector>

namespace cellguard::robot_tool {

/// Exit status: image written and verified.
constexpr int kExitOk = 0;
/// Exit status: the image could not be written or failed verification.
constexpr int kExitOutputError = 1;
/// Exit status: bad command line or bad input (URDF, mesh).
constexpr int kExitInputError = 2;

/// Runs cellguard-robot with @p args (without the program name): summary to
/// @p out, errors to @p err; returns the exit status.
int run_robot_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace cellguard::robot_tool

#endif  // CELLGUARD_ROBOT_TOOL_ROBOT_TOOL_HPP
