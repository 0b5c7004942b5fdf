// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// cellguard-robot's command line, image writing and summary. See robot_tool.hpp.
#include "cellguard/robot_tool/robot_tool.hpp"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iomanip>
#include <map>
#include <sstream>
#include <vector>

#include "cellguard/host/cli.hpp"
#include "cellguard/host/command_line.hpp"
#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/urdf_import.hpp"
#include "cellguard/robot/robot_image.hpp"

namespace cellguard::robot_tool {

namespace {

constexpr const char* kToolName = "cellguard-robot";
constexpr double kPi = 3.14159265358979323846;

constexpr const char* kDescription =
    "Imports a robot's URDF (liburdfdom) and writes the robot image the\n"
    "controllers load: the kinematic tree, the movable joints in the PLC's\n"
    "order with their limits, and each link's collision geometry as capsules\n"
    "(spheres, cylinders, boxes, STL, COLLADA and OBJ meshes); a gripper's\n"
    "finger links folded into the link they hang from, enclosed over their\n"
    "whole stroke (--stroke-joints). Reads the\n"
    "image back with the controller's loader and prints a summary with the\n"
    "image's CRC-32 and the robot id (its low 16 bits) the PLC must send.\n"
    "Mesh paths: package://NAME/... through --package NAME=DIR, relative paths\n"
    "against the URDF's folder; nothing else.";

constexpr const char* kFooter =
    "Exit status: 0 written and verified, 1 the image could not be written or\n"
    "failed verification, 2 bad command line or a refused URDF.";

struct Options {
    std::string urdf;
    std::string out;
    std::vector<std::string> joints;
    std::vector<std::string> strokes;
    std::map<std::string, std::string> packages;
    double base[4] = {0.0, 0.0, 0.0, 0.0};
};

bool parse_double(const std::string& text, double& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtod(text.c_str(), &end);
    return !text.empty() && errno == 0 && end == text.c_str() + text.size() && std::isfinite(value);
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0U;
    while (true) {
        const std::size_t at = text.find(separator, start);
        parts.push_back(text.substr(start, at - start));
        if (at == std::string::npos) {
            return parts;
        }
        start = at + 1U;
    }
}

/// The joint names of option @p option's value @p v: comma-separated, none empty.
std::vector<std::string> joint_names(const std::string& option, const std::string& v) {
    std::vector<std::string> names = split(v, ',');
    for (const std::string& name : names) {
        if (name.empty()) {
            std::string message = option;
            message.append(" expects joint names separated by commas, got '").append(v).append("'");
            host::reject(message);
        }
    }
    return names;
}

void take_joints(const std::string& v, Options& o) {
    o.joints = joint_names("--joints", v);
    if (o.joints.size() > kMaxRobotJoints) {
        host::reject("--joints expects at most " + std::to_string(kMaxRobotJoints) + " joints, got '" + v + "'");
    }
}

void take_strokes(const std::string& v, Options& o) { o.strokes = joint_names("--stroke-joints", v); }

void take_base(const std::string& v, Options& o) {
    const std::vector<std::string> parts = split(v, ',');
    bool ok = parts.size() == 3U || parts.size() == 4U;
    for (std::size_t k = 0U; ok && k < parts.size(); ++k) {
        ok = parse_double(parts[k], o.base[k]);
    }
    if (!ok || std::abs(o.base[0]) > 1000.0 || std::abs(o.base[1]) > 1000.0 || std::abs(o.base[2]) > 1000.0) {
        host::reject("--base expects X,Y,Z[,YAW_DEG] in metres and degrees (finite numbers), got '" + v + "'");
    }
}

void take_package(const std::string& v, Options& o) {
    const std::size_t eq = v.find('=');
    if (eq == std::string::npos || eq == 0U || eq + 1U == v.size()) {
        host::reject("--package expects NAME=DIR, got '" + v + "'");
    }
    if (!o.packages.emplace(v.substr(0U, eq), v.substr(eq + 1U)).second) {
        host::reject("--package expects each NAME once, got '" + v + "' again");
    }
}

int parse_args(const std::vector<std::string>& args, Options& o, std::ostream& out, std::ostream& err) {
    static_assert(kExitInputError == host::kExitUsage, "a bad command line is a bad input");
    host::CommandLine cli(kToolName, "cellguard-robot --urdf FILE --joints A,B,... --base X,Y,Z[,YAW] --out FILE",
                          kDescription, kFooter);
    cli.text("--urdf", o.urdf, "FILE", "the robot's URDF (required)").required();
    cli.value("--joints", "A,B,...", "the PLC's joint order: every movable joint, once (required)",
              [&o](const std::string& v) { take_joints(v, o); })
        .required();
    cli.value("--stroke-joints", "A,B,...",
              "joints the PLC does not send (a gripper's fingers): their\n"
              "links, and their mimic joints', are enclosed over the\n"
              "whole stroke by capsules on the link they hang from",
              [&o](const std::string& v) { take_strokes(v, o); });
    cli.value("--base", "X,Y,Z[,YAW]",
              "the root link's position in the cell, metres, and its\n"
              "rotation about the cell's z axis, degrees (required)",
              [&o](const std::string& v) { take_base(v, o); })
        .required();
    cli.text("--out", o.out, "FILE", "the robot image to write, e.g. robot.cgrobot (required)").required();
    cli.value("--package", "NAME=DIR", "resolve package://NAME/... in DIR (repeatable)",
              [&o](const std::string& v) { take_package(v, o); });
    return cli.parse(args, out, err);
}

const char* joint_word(JointType type) {
    switch (type) {
        case JointType::kRevolute: return "revolute";
        case JointType::kPrismatic: return "prismatic";
        default: return "fixed";
    }
}

void print_links(const host::UrdfImport& r, std::ostream& out) {
    const RobotModel& m = r.model;
    out << "links: " << int{m.link_count} << ", movable joints: " << int{m.joint_count} << "\n";
    for (std::size_t i = 0U; i < m.link_count; ++i) {
        const RobotLink& l = m.links[i];
        out << "  " << std::setw(2) << i << " " << r.link_names[i];
        if (i == 0U) {
            out << " (root)\n";
            continue;
        }
        out << " <- " << r.link_names[l.parent] << " by " << r.joint_names[i] << " (" << joint_word(l.joint);
        if (l.joint != JointType::kFixed) {
            const char* unit = l.joint == JointType::kRevolute ? "rad" : "m";
            out << ", axis " << l.axis[0] << " " << l.axis[1] << " " << l.axis[2] << ", " << l.lower << " .. "
                << l.upper << " " << unit << ", " << l.max_velocity << " " << unit << "/s, ";
            if (l.mimic) {
                out << "mimic: " << l.mimic_multiplier << " x command position " << int{l.command_index} << " + "
                    << l.mimic_offset;
            } else {
                out << "command position " << int{l.command_index};
            }
        }
        out << ")\n";
    }
}

void print_capsules(const host::UrdfImport& r, std::ostream& out) {
    const RobotModel& m = r.model;
    out << "capsules: " << int{m.capsule_count} << "\n";
    for (std::size_t k = 0U; k < m.capsule_count; ++k) {
        const RobotCapsule& c = m.capsules[k];
        const double dx = c.b[0] - c.a[0];
        const double dy = c.b[1] - c.a[1];
        const double dz = c.b[2] - c.a[2];
        out << "  " << std::setw(2) << k << " " << r.link_names[c.link] << ": radius " << c.radius << " m, length "
            << std::sqrt(dx * dx + dy * dy + dz * dz) << " m\n";
    }
    for (const std::string& note : r.notes) {
        out << "note: " << note << "\n";
    }
}

/// Writes the image of @p model to @p path and loads it back; the CRC, or an error line on @p err.
bool write_image(const RobotModel& model, const std::string& path, std::uint32_t& crc, std::ostream& err) {
    std::vector<std::uint8_t> bytes(kRobotImageMaxBytes);
    const auto written = write_robot_image(model, Span<std::uint8_t>(bytes.data(), bytes.size()));
    if (!written.ok()) {
        err << kToolName << ": the robot image: " << written.error().reason << "\n";
        return false;
    }
    bytes.resize(written.value());
    const auto loaded = load_robot_image(Span<const std::uint8_t>(bytes.data(), bytes.size()));
    if (!loaded.ok()) {
        err << kToolName << ": the written image does not load: " << loaded.error().reason << "\n";
        return false;
    }
    host::FilePtr file = host::open_file(path.c_str(), "wb");
    const bool ok = file && std::fwrite(bytes.data(), 1U, bytes.size(), file.get()) == bytes.size();
    if (!host::close_file(file) || !ok) {
        err << kToolName << ": " << path << ": cannot write: " << std::strerror(errno) << "\n";
        return false;
    }
    crc = loaded.value().crc;
    return true;
}

int run(const Options& o, std::ostream& out, std::ostream& err) {
    host::UrdfImportOptions options;
    options.joint_order = o.joints;
    options.stroke_joints = o.strokes;
    options.packages = o.packages;
    options.base_xyz = Eigen::Vector3d(o.base[0], o.base[1], o.base[2]);
    options.base_rotation = Eigen::AngleAxisd(o.base[3] * kPi / 180.0, Eigen::Vector3d::UnitZ());
    host::UrdfImport imported;
    const IoStatus st = host::import_urdf_file(o.urdf, options, imported);
    if (!st) {
        err << kToolName << ": " << st.message() << "\n";
        return kExitInputError;
    }
    std::uint32_t crc = 0U;
    if (!write_image(imported.model, o.out, crc, err)) {
        return kExitOutputError;
    }
    out << "robot " << imported.model.name << " from " << o.urdf << "\n";
    print_links(imported, out);
    print_capsules(imported, out);
    char id[64];
    static_cast<void>(std::snprintf(id, sizeof(id), "CRC-32 0x%08X, robot id 0x%04X (%u)", static_cast<unsigned>(crc),
                                    static_cast<unsigned>(robot_id(crc)), static_cast<unsigned>(robot_id(crc))));
    out << "image: " << o.out << ", " << id << "\n";
    return kExitOk;
}

}  // namespace

int run_robot_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    try {
        Options o;
        const int status = parse_args(args, o, out, err);
        if (status >= 0) {
            return status;
        }
        return run(o, out, err);
    } catch (const std::exception& e) {
        err << kToolName << ": " << e.what() << "\n";
        return kExitOutputError;
    }
}

}  // namespace cellguard::robot_tool
