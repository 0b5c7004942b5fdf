// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// import_urdf_text() and import_urdf_file() of urdf_import.hpp on liburdfdom.
// Internally a refusal is thrown (ImportFailure) and turned into the
// IoStatus at the two entry points.
#include "cellguard/host/io/urdf_import.hpp"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <set>
#include <utility>

#include "cellguard/host/io/mesh.hpp"
#include "cellguard/host/io/stroke_envelope.hpp"

namespace cellguard::host {

namespace {

constexpr double kTwoPi = 6.28318530717958647692;
/// Largest joint position the command's int16 carries (-32768 is reserved).
constexpr double kMaxRawJoint = 32767.0;

/// A refusal on its way to the entry point.
class ImportFailure final : public std::exception {
public:
    explicit ImportFailure(const IoStatus& status) : status_(status) {}
    [[nodiscard]] const char* what() const noexcept override { return status_.message(); }
    [[nodiscard]] const IoStatus& status() const noexcept { return status_; }

private:
    IoStatus status_;
};

// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style, checked by the format attribute
[[noreturn]] void fail(ErrorCode code, const char* format, ...) __attribute__((format(printf, 2, 3)));
// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style, checked by the format attribute
void fail(ErrorCode code, const char* format, ...) {
    char text[IoStatus::kMessageCapacity];
    std::va_list args;
    va_start(args, format);
    // The format is checked at each caller (format attribute); va_start is two lines up, which the analyzer
    // loses on some of the paths it inlines from the callers.
    // NOLINTNEXTLINE(clang-diagnostic-format-nonliteral,clang-analyzer-valist.Uninitialized): see above
    const int n = std::vsnprintf(text, sizeof(text), format, args);
    va_end(args);
    if (n < 0) {
        text[0] = '\0';
    }
    throw ImportFailure(IoStatus::failure(code, "%s", text));
}

std::string join(const std::vector<std::string>& items, const char* separator) {
    std::string out;
    for (const std::string& item : items) {
        out += (out.empty() ? "" : separator) + item;
    }
    return out;
}

// ---------------------------------------------------------------- parsing

/// Collects what liburdfdom logs at WARN and above while it lives; restores
/// the previous handler and level afterwards.
class ConsoleCapture final : public console_bridge::OutputHandler {
public:
    ConsoleCapture() : previous_level_(console_bridge::getLogLevel()) {
        console_bridge::useOutputHandler(this);
        console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
    }
    ~ConsoleCapture() override {
        console_bridge::setLogLevel(previous_level_);
        console_bridge::restorePreviousOutputHandler();
    }
    ConsoleCapture(const ConsoleCapture&) = delete;
    ConsoleCapture& operator=(const ConsoleCapture&) = delete;
    ConsoleCapture(ConsoleCapture&&) = delete;
    ConsoleCapture& operator=(ConsoleCapture&&) = delete;

    void log(const std::string& text, console_bridge::LogLevel level, const char* /*filename*/, int /*line*/) override {
        if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
            messages_.push_back(text);
        }
    }
    /// What was logged, in order.
    [[nodiscard]] const std::vector<std::string>& messages() const noexcept { return messages_; }

private:
    std::vector<std::string> messages_;
    console_bridge::LogLevel previous_level_;
};

urdf::ModelInterfaceSharedPtr parse_model(const std::string& text) {
    static std::mutex console_mutex;  // console_bridge's handler is global
    std::vector<std::string> logged;
    urdf::ModelInterfaceSharedPtr model;
    {
        const std::lock_guard<std::mutex> lock(console_mutex);
        ConsoleCapture capture;
        model = urdf::parseURDF(text);
        logged = capture.messages();
    }
    if (!model) {
        fail(ErrorCode::kMalformedInput, "liburdfdom: %s",
             logged.empty() ? "cannot read the robot" : join(logged, "; ").c_str());
    }
    if (!logged.empty()) {
        fail(ErrorCode::kMalformedInput, "liburdfdom: %s (refused: liburdfdom drops what it cannot read and goes on)",
             join(logged, "; ").c_str());
    }
    return model;
}

/// What liburdfdom accepts silently, checked on the XML: a link with two
/// parent joints, a movable joint without <axis>.
void check_xml(const std::string& text) {
    TiXmlDocument doc;
    doc.Parse(text.c_str());
    const TiXmlElement* robot = doc.FirstChildElement("robot");
    if (doc.Error() || robot == nullptr) {
        fail(ErrorCode::kMalformedInput, "not a URDF: %s", doc.Error() ? doc.ErrorDesc() : "no <robot>");
    }
    std::map<std::string, std::string> parent_joint;  // child link -> joint
    for (const TiXmlElement* j = robot->FirstChildElement("joint"); j != nullptr; j = j->NextSiblingElement("joint")) {
        const char* name = j->Attribute("name");
        const char* type = j->Attribute("type");
        const TiXmlElement* child = j->FirstChildElement("child");
        const char* child_link = child != nullptr ? child->Attribute("link") : nullptr;
        if (name == nullptr || type == nullptr || child_link == nullptr) {
            continue;  // liburdfdom refuses these
        }
        const auto [it, fresh] = parent_joint.emplace(child_link, name);
        if (!fresh) {
            fail(ErrorCode::kMalformedInput, "link '%s' has two parent joints, '%s' and '%s': not a tree", child_link,
                 it->second.c_str(), name);
        }
        const std::string t = type;
        if ((t == "revolute" || t == "continuous" || t == "prismatic") && j->FirstChildElement("axis") == nullptr) {
            fail(ErrorCode::kInvalidArgument, "joint '%s' (%s) has no <axis>: liburdfdom would take x; write it", name,
                 type);
        }
    }
}

// ---------------------------------------------------------------- tree

/// A link of the tree in depth-first order.
struct Node {
    urdf::LinkConstSharedPtr link;
    urdf::JointConstSharedPtr joint;  ///< nullptr for the root
    int parent = -1;                  ///< index in the node list
};

bool is_movable(const urdf::Joint& joint) {
    return joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS ||
           joint.type == urdf::Joint::PRISMATIC;
}

std::vector<Node> depth_first(const urdf::ModelInterface& model) {
    std::vector<Node> nodes;
    std::vector<Node> stack{Node{model.getRoot(), nullptr, -1}};
    while (!stack.empty()) {
        Node node = stack.back();
        stack.pop_back();
        const int index = static_cast<int>(nodes.size());
        nodes.push_back(node);
        const auto& children = node.link->child_joints;
        for (auto it = children.rbegin(); it != children.rend(); ++it) {  // first child on top
            stack.push_back(Node{model.getLink((*it)->child_link_name), *it, index});
        }
    }
    return nodes;
}

/// The nodes with @p keep set, parents renumbered (a kept node's parent must
/// be kept); @p index maps old indices to new ones (-1: not kept).
std::vector<Node> kept_nodes(const std::vector<Node>& nodes, const std::vector<bool>& keep, std::vector<int>& index) {
    std::vector<Node> out;
    index.assign(nodes.size(), -1);
    for (std::size_t i = 0U; i < nodes.size(); ++i) {
        if (keep[i]) {
            index[i] = static_cast<int>(out.size());
            Node n = nodes[i];
            n.parent = n.parent < 0 ? -1 : index[static_cast<std::size_t>(n.parent)];
            out.push_back(n);
        }
    }
    return out;
}

/// Drops fixed leaf frames without collision geometry (repeatedly: a chain of them).
std::vector<Node> drop_empty_frames(const std::vector<Node>& nodes, std::vector<std::string>& notes) {
    std::vector<bool> keep(nodes.size(), false);
    std::vector<bool> kept_child(nodes.size(), false);
    std::vector<std::string> dropped;
    for (std::size_t i = nodes.size(); i-- > 1U;) {
        keep[i] = kept_child[i] || !nodes[i].link->collision_array.empty() || is_movable(*nodes[i].joint);
        if (keep[i]) {
            kept_child[static_cast<std::size_t>(nodes[i].parent)] = true;
        } else {
            dropped.insert(dropped.begin(), nodes[i].link->name);
        }
    }
    keep[0] = true;
    if (!dropped.empty()) {
        notes.push_back("dropped frame link(s) without collision geometry on fixed joints: " + join(dropped, ", "));
    }
    std::vector<int> index;
    return kept_nodes(nodes, keep, index);
}

// ---------------------------------------------------------------- joints

void put_pose(const urdf::Pose& pose, const std::string& joint, RobotLink& link) {
    const urdf::Vector3& p = pose.position;
    const urdf::Rotation& r = pose.rotation;
    const double values[7] = {p.x, p.y, p.z, r.w, r.x, r.y, r.z};
    for (const double v : values) {
        if (!std::isfinite(v)) {
            fail(ErrorCode::kNonFiniteValue, "joint '%s': origin is not finite", joint.c_str());
        }
    }
    if (std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z) > kMaxRobotReach) {
        fail(ErrorCode::kInvalidArgument, "joint '%s': origin %.3f m from its parent, at most %.0f m", joint.c_str(),
             std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), kMaxRobotReach);
    }
    const Eigen::Quaterniond q = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized();
    link.origin_xyz[0] = p.x;
    link.origin_xyz[1] = p.y;
    link.origin_xyz[2] = p.z;
    link.origin_wxyz[0] = q.w();
    link.origin_wxyz[1] = q.x();
    link.origin_wxyz[2] = q.y();
    link.origin_wxyz[3] = q.z();
}

void put_axis(const urdf::Joint& joint, RobotLink& link, std::vector<std::string>& notes) {
    const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
    const char* name = joint.name.c_str();
    if (!axis.allFinite()) {
        fail(ErrorCode::kNonFiniteValue, "joint '%s': axis is not finite", name);
    }
    const double length = axis.norm();
    if (length == 0.0) {
        fail(ErrorCode::kInvalidArgument, "joint '%s': zero axis", name);
    }
    if (std::abs(length - 1.0) > kUrdfAxisTolerance) {
        fail(ErrorCode::kInvalidArgument, "joint '%s': axis (%g %g %g) has length %g, not 1 (tolerance %g)", name,
             axis.x(), axis.y(), axis.z(), length, kUrdfAxisTolerance);
    }
    if (std::abs(length - 1.0) > kUnitLengthTolerance) {
        notes.push_back("joint '" + joint.name + "': axis of length " + std::to_string(length) + " normalised");
    }
    const Eigen::Vector3d unit = axis / length;
    for (int k = 0; k < 3; ++k) {
        link.axis[k] = unit[k];
    }
}

void put_limits(const urdf::Joint& joint, RobotLink& link, std::vector<std::string>& notes) {
    const char* name = joint.name.c_str();
    const bool continuous = joint.type == urdf::Joint::CONTINUOUS;
    const double velocity = joint.limits ? joint.limits->velocity : 0.0;
    double lower = continuous ? -kTwoPi : (joint.limits ? joint.limits->lower : 0.0);
    double upper = continuous ? kTwoPi : (joint.limits ? joint.limits->upper : 0.0);
    if (!std::isfinite(lower) || !std::isfinite(upper) || !std::isfinite(velocity)) {
        fail(ErrorCode::kNonFiniteValue, "joint '%s': a limit is not finite", name);
    }
    if (!(velocity > 0.0) && !(joint.mimic && velocity == 0.0)) {  // a mimic without one: put_mimics
        fail(ErrorCode::kInvalidArgument, "joint '%s': velocity limit %g, must be > 0 (<limit velocity=...>)", name,
             velocity);
    }
    if (lower > upper) {
        fail(ErrorCode::kInvalidArgument, "joint '%s': lower limit %g above upper limit %g", name, lower, upper);
    }
    if (lower == upper) {
        fail(ErrorCode::kInvalidArgument, "joint '%s': no range (lower = upper = %g): <limit> without lower/upper?",
             name, lower);
    }
    const bool prismatic = joint.type == urdf::Joint::PRISMATIC;
    const double wire = kMaxRawJoint * (prismatic ? kPrismaticJointUnitM : kRevoluteJointUnitRad);
    if (lower < -wire || upper > wire) {
        fail(ErrorCode::kInvalidArgument, "joint '%s': limits %g .. %g outside the command's range +-%g %s", name,
             lower, upper, wire, prismatic ? "m" : "rad");
    }
    if (continuous) {
        notes.push_back("joint '" + joint.name + "': continuous, taken as revolute -2 pi .. 2 pi");
    }
    link.lower = lower;
    link.upper = upper;
    link.max_velocity = velocity;
}

JointType joint_type(const urdf::Joint& joint) {
    switch (joint.type) {
        case urdf::Joint::FIXED: return JointType::kFixed;
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS: return JointType::kRevolute;
        case urdf::Joint::PRISMATIC: return JointType::kPrismatic;
        case urdf::Joint::FLOATING:
            fail(ErrorCode::kUnsupportedType, "joint '%s' is floating: not supported", joint.name.c_str());
        case urdf::Joint::PLANAR:
            fail(ErrorCode::kUnsupportedType, "joint '%s' is planar: not supported", joint.name.c_str());
        default: fail(ErrorCode::kUnsupportedType, "joint '%s' has an unknown type", joint.name.c_str());
    }
}

void put_joint(const urdf::Joint& joint, RobotLink& link, std::vector<std::string>& notes) {
    link.joint = joint_type(joint);
    put_pose(joint.parent_to_joint_origin_transform, joint.name, link);
    if (link.joint != JointType::kFixed) {
        put_axis(joint, link, notes);
        put_limits(joint, link, notes);
    }
}

/// Whether node @p i's joint is an arm joint's mimic: movable, kept (not
/// folded, so its master is no stroke joint) and following its master.
bool is_arm_mimic(const std::vector<Node>& nodes, std::size_t i) {
    return is_movable(*nodes[i].joint) && nodes[i].joint->mimic != nullptr;
}

/// Command indices from the PLC's joint order; an arm joint's mimic is not
/// in it (put_mimics gives it its master's).
void put_command_order(const std::vector<Node>& nodes, const std::vector<std::string>& order, RobotModel& model) {
    std::vector<std::string> movable;
    for (std::size_t i = 1U; i < nodes.size(); ++i) {
        if (model.links[i].joint != JointType::kFixed && !is_arm_mimic(nodes, i)) {
            movable.push_back(nodes[i].joint->name);
        }
    }
    if (movable.size() > kMaxRobotJoints) {
        fail(ErrorCode::kCapacityExceeded,
             "%zu movable joints to send, at most %zu (name a gripper's fingers stroke "
             "joints): %s",
             movable.size(), kMaxRobotJoints, join(movable, ", ").c_str());
    }
    for (std::size_t k = 0U; k < order.size(); ++k) {
        const auto it = std::find_if(nodes.begin() + 1, nodes.end(),
                                     [&](const Node& n) { return n.joint->name == order[k]; });
        if (it == nodes.end()) {
            fail(ErrorCode::kInvalidArgument, "joint order: joint '%s' is not in the URDF", order[k].c_str());
        }
        const auto i = static_cast<std::size_t>(it - nodes.begin());
        RobotLink& link = model.links[i];
        if (link.joint == JointType::kFixed) {
            fail(ErrorCode::kInvalidArgument, "joint order: joint '%s' is fixed", order[k].c_str());
        }
        if (is_arm_mimic(nodes, i)) {
            fail(ErrorCode::kInvalidArgument,
                 "joint order: joint '%s' mimics '%s' and follows it: the PLC does not send it", order[k].c_str(),
                 it->joint->mimic->joint_name.c_str());
        }
        if (link.command_index != kNoCommandIndex) {
            fail(ErrorCode::kInvalidArgument, "joint order: joint '%s' named twice", order[k].c_str());
        }
        link.command_index = static_cast<std::uint8_t>(k);
    }
    for (std::size_t i = 1U; i < nodes.size(); ++i) {
        if (model.links[i].joint != JointType::kFixed && !is_arm_mimic(nodes, i) &&
            model.links[i].command_index == kNoCommandIndex) {
            fail(ErrorCode::kInvalidArgument,
                 "joint order: movable joint '%s' is missing (the PLC must send it; a gripper's finger joint is "
                 "named a stroke joint instead)",
                 nodes[i].joint->name.c_str());
        }
    }
    model.joint_count = static_cast<std::uint8_t>(order.size());
}

// ---------------------------------------------------------------- strokes

/// Which nodes the PLC does not move, and the stroke variable of each
/// stroke joint (see stroke_envelope.hpp).
struct StrokePlan {
    std::vector<bool> folded;         ///< node i is a stroke joint's child or below one
    std::vector<std::size_t> anchor;  ///< the nearest node at or above node i that is not folded
    std::vector<int> variable;        ///< stroke joints: their variable; -1 elsewhere
    std::vector<double> multiplier;   ///< stroke joints: position = multiplier * variable + offset
    std::vector<double> offset;       ///< see multiplier
    std::vector<StrokeRange> ranges;  ///< per variable: its joint's limits
};

int find_node(const std::vector<Node>& nodes, const std::string& joint) {
    for (std::size_t i = 1U; i < nodes.size(); ++i) {
        if (nodes[i].joint->name == joint) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

bool named(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

/// The stroke joints as named: each a movable joint of the URDF, once, not also sent by the PLC.
void check_stroke_names(const std::vector<Node>& nodes, const UrdfImportOptions& options) {
    for (std::size_t k = 0U; k < options.stroke_joints.size(); ++k) {
        const std::string& name = options.stroke_joints[k];
        const int i = find_node(nodes, name);
        if (i < 0 || !is_movable(*nodes[static_cast<std::size_t>(i)].joint)) {
            fail(ErrorCode::kInvalidArgument, "stroke joint '%s' is not a movable joint of the URDF", name.c_str());
        }
        if (named(options.joint_order, name)) {
            fail(ErrorCode::kInvalidArgument, "joint '%s' is named both in the PLC's order and a stroke joint",
                 name.c_str());
        }
        if (std::find(options.stroke_joints.begin(), options.stroke_joints.begin() + static_cast<long>(k), name) !=
            options.stroke_joints.begin() + static_cast<long>(k)) {
            fail(ErrorCode::kInvalidArgument, "stroke joint '%s' named twice", name.c_str());
        }
    }
}

/// The master of mimic joint @p i, which must be in the URDF and not a mimic itself.
std::size_t mimic_master(const std::vector<Node>& nodes, std::size_t i) {
    const urdf::Joint& joint = *nodes[i].joint;
    const int master = find_node(nodes, joint.mimic->joint_name);
    if (master < 0 || !is_movable(*nodes[static_cast<std::size_t>(master)].joint)) {
        fail(ErrorCode::kInvalidArgument, "joint '%s' mimics joint '%s', which is not a movable joint of the URDF",
             joint.name.c_str(), joint.mimic->joint_name.c_str());
    }
    if (nodes[static_cast<std::size_t>(master)].joint->mimic) {
        fail(ErrorCode::kUnsupportedType, "joint '%s' mimics joint '%s', itself a mimic joint: not supported",
             joint.name.c_str(), joint.mimic->joint_name.c_str());
    }
    return static_cast<std::size_t>(master);
}

/// A mimic's position over its master's range must stay within its own
/// limits: a wrong multiplier or offset in the file shows there.
void check_mimic_range(const urdf::Joint& joint, const StrokeRange& master, const StrokeRange& own) {
    const double m = joint.mimic->multiplier;
    const double o = joint.mimic->offset;
    if (!std::isfinite(m) || !std::isfinite(o)) {
        fail(ErrorCode::kNonFiniteValue, "joint '%s': mimic multiplier or offset is not finite", joint.name.c_str());
    }
    const double lo = std::min(m * master.lower + o, m * master.upper + o);
    const double hi = std::max(m * master.lower + o, m * master.upper + o);
    const double slack = 1e-6 * std::max(1.0, std::max(std::abs(own.lower), std::abs(own.upper)));
    if (lo < own.lower - slack || hi > own.upper + slack) {
        fail(ErrorCode::kInvalidArgument,
             "joint '%s' mimics joint '%s' (x %g + %g): its master's range gives %g .. %g, outside its own limits "
             "%g .. %g (a wrong multiplier or offset?)",
             joint.name.c_str(), joint.mimic->joint_name.c_str(), m, o, lo, hi, own.lower, own.upper);
    }
}

/// Whether stroke joint @p joint follows its master: a mimic not named a stroke joint itself.
bool follows_master(const urdf::Joint& joint, const UrdfImportOptions& options) {
    return joint.mimic && !named(options.stroke_joints, joint.name);
}

/// Stroke joint @p i's own limits, checked as any movable joint's.
StrokeRange stroke_limits(const urdf::Joint& joint, std::vector<std::string>& notes) {
    RobotLink scratch;
    scratch.joint = joint_type(joint);
    put_limits(joint, scratch, notes);
    return StrokeRange{scratch.lower, scratch.upper};
}

/// Gives node @p i (a stroke joint) its variable: a mimic of a stroke joint
/// follows its master's (which must have its own already); any other
/// stroke joint has its own.
void plan_stroke_joint(const std::vector<Node>& nodes, std::size_t i, const UrdfImportOptions& options,
                       StrokePlan& plan, std::vector<std::string>& notes) {
    const urdf::Joint& joint = *nodes[i].joint;
    if (!follows_master(joint, options)) {
        plan.variable[i] = static_cast<int>(plan.ranges.size());
        plan.ranges.push_back(stroke_limits(joint, notes));
        if (joint.mimic) {
            notes.push_back("joint '" + joint.name + "' mimics '" + joint.mimic->joint_name +
                            "' but is named a stroke joint: enclosed over its own limits");
        }
        return;
    }
    const std::size_t master = mimic_master(nodes, i);
    check_mimic_range(joint, plan.ranges[static_cast<std::size_t>(plan.variable[master])], stroke_limits(joint, notes));
    plan.variable[i] = plan.variable[master];
    plan.multiplier[i] = joint.mimic->multiplier;
    plan.offset[i] = joint.mimic->offset;
}

/// Whether node @p i's joint is a stroke joint: named, or a mimic of a named one.
bool is_stroke_joint(const std::vector<Node>& nodes, std::size_t i, const UrdfImportOptions& options) {
    const urdf::Joint& joint = *nodes[i].joint;
    if (!is_movable(joint)) {
        return false;
    }
    if (named(options.stroke_joints, joint.name)) {
        return true;
    }
    if (!joint.mimic) {
        return false;
    }
    const std::size_t master = mimic_master(nodes, i);
    return named(options.stroke_joints, nodes[master].joint->name);  // else an arm joint's mimic (put_mimics)
}

/// Each kept mimic joint follows its arm joint master: the master's command
/// index, the URDF's multiplier and offset, its master's range checked
/// against its own limits (the model check repeats that).
void put_mimics(const std::vector<Node>& nodes, RobotModel& model, std::vector<std::string>& notes) {
    for (std::size_t i = 1U; i < nodes.size(); ++i) {
        if (!is_arm_mimic(nodes, i)) {
            continue;
        }
        const urdf::Joint& joint = *nodes[i].joint;
        const RobotLink& master = model.links[mimic_master(nodes, i)];
        RobotLink& link = model.links[i];
        check_mimic_range(joint, StrokeRange{master.lower, master.upper}, StrokeRange{link.lower, link.upper});
        link.command_index = master.command_index;
        link.mimic = true;
        link.mimic_multiplier = joint.mimic->multiplier;
        link.mimic_offset = joint.mimic->offset;
        if (link.mimic_multiplier == 0.0) {
            fail(ErrorCode::kInvalidArgument, "joint '%s': mimic multiplier 0 (make it a fixed joint)",
                 joint.name.c_str());
        }
        if (!(link.max_velocity > 0.0)) {
            link.max_velocity = std::abs(link.mimic_multiplier) * master.max_velocity;
            notes.push_back("joint '" + joint.name + "': no velocity limit, its master's x |multiplier| taken");
        }
        notes.push_back("joint '" + joint.name + "' mimics '" + joint.mimic->joint_name +
                        "': not sent, placed at its position x " + std::to_string(link.mimic_multiplier) + " + " +
                        std::to_string(link.mimic_offset));
    }
}

StrokePlan plan_strokes(const std::vector<Node>& nodes, const UrdfImportOptions& options,
                        std::vector<std::string>& notes) {
    check_stroke_names(nodes, options);
    StrokePlan plan;
    plan.folded.assign(nodes.size(), false);
    plan.anchor.assign(nodes.size(), 0U);
    plan.variable.assign(nodes.size(), -1);
    plan.multiplier.assign(nodes.size(), 1.0);
    plan.offset.assign(nodes.size(), 0.0);
    std::vector<bool> stroke_joint(nodes.size(), false);
    for (std::size_t i = 1U; i < nodes.size(); ++i) {
        const bool stroke = is_stroke_joint(nodes, i, options);
        const auto parent = static_cast<std::size_t>(nodes[i].parent);
        plan.folded[i] = stroke || plan.folded[parent];
        plan.anchor[i] = plan.folded[i] ? plan.anchor[parent] : i;
        if (plan.folded[i] && named(options.joint_order, nodes[i].joint->name)) {
            fail(ErrorCode::kInvalidArgument, "joint order: joint '%s' hangs below a stroke joint: not sent by the PLC",
                 nodes[i].joint->name.c_str());
        }
        if (plan.folded[i] && is_movable(*nodes[i].joint) && !stroke) {
            fail(ErrorCode::kInvalidArgument,
                 "joint '%s' moves below a stroke joint: name it a stroke joint too (the PLC cannot send it)",
                 nodes[i].joint->name.c_str());
        }
        stroke_joint[i] = stroke;
    }
    for (const bool followers : {false, true}) {  // masters first, then the mimics that follow them
        for (std::size_t i = 1U; i < nodes.size(); ++i) {
            if (stroke_joint[i] && follows_master(*nodes[i].joint, options) == followers) {
                plan_stroke_joint(nodes, i, options, plan, notes);
            }
        }
    }
    return plan;
}

/// The chain from folded node @p i's anchor down to it.
std::vector<StrokeStep> stroke_chain(const std::vector<Node>& nodes, const StrokePlan& plan, std::size_t i,
                                     std::vector<std::string>& notes) {
    std::vector<std::size_t> path;
    for (std::size_t k = i; k != plan.anchor[i]; k = static_cast<std::size_t>(nodes[k].parent)) {
        path.insert(path.begin(), k);
    }
    std::vector<StrokeStep> chain;
    for (const std::size_t n : path) {
        const urdf::Joint& joint = *nodes[n].joint;
        RobotLink scratch;
        put_pose(joint.parent_to_joint_origin_transform, joint.name, scratch);
        StrokeStep step;
        step.origin = Eigen::Translation3d(scratch.origin_xyz[0], scratch.origin_xyz[1], scratch.origin_xyz[2]) *
                      Eigen::Quaterniond(scratch.origin_wxyz[0], scratch.origin_wxyz[1], scratch.origin_wxyz[2],
                                         scratch.origin_wxyz[3]);
        step.type = joint_type(joint);
        if (step.type != JointType::kFixed) {
            put_axis(joint, scratch, notes);
            step.axis = Eigen::Vector3d(scratch.axis[0], scratch.axis[1], scratch.axis[2]);
            step.variable = static_cast<std::size_t>(plan.variable[n]);
            step.multiplier = plan.multiplier[n];
            step.offset = plan.offset[n];
        }
        chain.push_back(step);
    }
    return chain;
}

/// Folded node @p i's capsule @p c as an envelope on its anchor.
Capsule fold_capsule(const std::vector<Node>& nodes, const StrokePlan& plan, std::size_t i, const Capsule& c,
                     UrdfImport& result) {
    const std::size_t anchor = plan.anchor[i];
    const std::vector<StrokeStep> chain = stroke_chain(nodes, plan, i, result.notes);
    StrokeEnvelope envelope;
    const IoStatus st = envelope_capsule(chain, plan.ranges, c, envelope);
    if (!st) {
        fail(st.error(), "link '%s': %s", nodes[i].link->name.c_str(), st.message());
    }
    result.folded.push_back(FoldedCapsule{nodes[i].link->name, nodes[anchor].link->name, c, envelope.capsule,
                                          envelope.between, envelope.poses});
    char text[256];
    static_cast<void>(std::snprintf(
        text, sizeof(text),
        "link '%s' folded into '%s' over its stroke: capsule radius %.4f -> %.4f m, volume %.3f -> %.3f L (%zu poses)",
        nodes[i].link->name.c_str(), nodes[anchor].link->name.c_str(), c.radius, envelope.capsule.radius,
        1e3 * capsule_volume(c), 1e3 * capsule_volume(envelope.capsule), envelope.poses));
    result.notes.emplace_back(text);
    return envelope.capsule;
}

// ---------------------------------------------------------------- geometry

/// A capsule of one link, and whether it came from a <sphere>.
struct LinkCapsule {
    Capsule capsule;
    bool sphere = false;
};

/// The file a mesh filename names (see the file comment of urdf_import.hpp).
std::string resolve_mesh(const std::string& filename, const UrdfImportOptions& options, const char* link) {
    const std::string scheme = "package://";
    if (filename.compare(0U, scheme.size(), scheme) == 0) {
        const std::size_t slash = filename.find('/', scheme.size());
        const std::string package = filename.substr(scheme.size(), slash - scheme.size());
        const auto it = options.packages.find(package);
        if (slash == std::string::npos || it == options.packages.end()) {
            fail(ErrorCode::kInvalidArgument, "link '%s': mesh '%s': package '%s' not given (--package %s=DIR)", link,
                 filename.c_str(), package.c_str(), package.c_str());
        }
        return (std::filesystem::path(it->second) / filename.substr(slash + 1U)).string();
    }
    if (filename.find("://") != std::string::npos || std::filesystem::path(filename).is_absolute()) {
        fail(ErrorCode::kInvalidArgument,
             "link '%s': mesh '%s': only package:// and paths relative to the URDF are resolved", link,
             filename.c_str());
    }
    if (options.base_directory.empty()) {
        fail(ErrorCode::kInvalidArgument, "link '%s': mesh '%s': a relative path needs the URDF's directory", link,
             filename.c_str());
    }
    return (std::filesystem::path(options.base_directory) / filename).string();
}

Capsule mesh_capsule(const urdf::Mesh& mesh, const UrdfImportOptions& options, const char* link) {
    const char* file = mesh.filename.c_str();
    const Eigen::Vector3d scale(mesh.scale.x, mesh.scale.y, mesh.scale.z);
    if (!scale.allFinite() || !(scale.minCoeff() > 0.0)) {
        fail(ErrorCode::kInvalidArgument, "link '%s': mesh '%s': scale (%g %g %g) must be finite and > 0", link, file,
             scale.x(), scale.y(), scale.z());
    }
    Mesh read;
    const IoStatus st = read_mesh_file(resolve_mesh(mesh.filename, options, link), read);
    if (!st) {
        fail(st.error(), "link '%s': mesh: %s", link, st.message());
    }
    Eigen::AlignedBox3d box;
    for (Eigen::Vector3d& v : read.vertices) {
        v = v.cwiseProduct(scale);
        box.extend(v);
    }
    const double extent = box.diagonal().norm();
    if (extent < kMinMeshExtent || extent > kMaxMeshExtent) {
        fail(ErrorCode::kInvalidArgument,
             "link '%s': mesh '%s': %.6g m across after its unit (%g m) and scale, implausible for a robot link "
             "(%g .. %g m): a mesh in the wrong unit?",
             link, file, extent, read.unit, kMinMeshExtent, kMaxMeshExtent);
    }
    Capsule c = bounding_capsule(read.vertices);
    for (const Eigen::Vector3d& v : read.vertices) {
        if (segment_distance(v, c.a, c.b) > c.radius) {
            fail(ErrorCode::kInvalidArgument, "link '%s': mesh '%s': bounding capsule misses a vertex", link, file);
        }
    }
    return c;
}

void check_size(double value, const char* what, const char* link) {
    if (!std::isfinite(value)) {
        fail(ErrorCode::kNonFiniteValue, "link '%s': %s is not finite", link, what);
    }
    if (!(value > 0.0)) {
        fail(ErrorCode::kInvalidArgument, "link '%s': %s %g, must be > 0", link, what, value);
    }
}

/// One collision geometry as a capsule in its own frame.
LinkCapsule shape_capsule(const urdf::Geometry& geometry, const UrdfImportOptions& options, const char* link) {
    switch (geometry.type) {
        case urdf::Geometry::SPHERE: {
            const double r = dynamic_cast<const urdf::Sphere&>(geometry).radius;
            check_size(r, "sphere radius", link);
            return {Capsule{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), r}, true};
        }
        case urdf::Geometry::CYLINDER: {
            const auto& c = dynamic_cast<const urdf::Cylinder&>(geometry);
            check_size(c.radius, "cylinder radius", link);
            check_size(c.length, "cylinder length", link);
            const Eigen::Vector3d half(0.0, 0.0, 0.5 * c.length);
            return {Capsule{-half, half, c.radius}, false};
        }
        case urdf::Geometry::BOX: {
            const urdf::Vector3& d = dynamic_cast<const urdf::Box&>(geometry).dim;
            const Eigen::Vector3d size(d.x, d.y, d.z);
            for (int k = 0; k < 3; ++k) {
                check_size(size[k], "box size", link);
            }
            Eigen::Index longest = 0;
            static_cast<void>(size.maxCoeff(&longest));
            Eigen::Vector3d half = Eigen::Vector3d::Zero();
            half[longest] = 0.5 * size[longest];
            const double across2 = size.squaredNorm() - size[longest] * size[longest];
            return {Capsule{-half, half, 0.5 * std::sqrt(across2)}, false};
        }
        case urdf::Geometry::MESH:
            return {mesh_capsule(dynamic_cast<const urdf::Mesh&>(geometry), options, link), false};
        default: fail(ErrorCode::kUnsupportedType, "link '%s': unknown geometry type", link);
    }
}

Capsule transformed(const Capsule& c, const urdf::Pose& pose, const char* link) {
    const urdf::Rotation& r = pose.rotation;
    const Eigen::Quaterniond q(r.w, r.x, r.y, r.z);
    const Eigen::Vector3d t(pose.position.x, pose.position.y, pose.position.z);
    if (!q.coeffs().allFinite() || !t.allFinite() || q.norm() == 0.0) {
        fail(ErrorCode::kNonFiniteValue, "link '%s': collision origin is not finite", link);
    }
    const Eigen::Quaterniond unit = q.normalized();
    return Capsule{unit * c.a + t, unit * c.b + t, c.radius};
}

/// Drops spheres that lie (within the tolerance) inside another capsule of
/// the link; that capsule's radius grows to contain each exactly.
std::vector<LinkCapsule> merge_spheres(std::vector<LinkCapsule> parts, double tolerance, int& merged) {
    std::vector<bool> gone(parts.size(), false);
    for (std::size_t s = 0U; s < parts.size(); ++s) {
        if (!parts[s].sphere) {
            continue;
        }
        for (std::size_t k = 0U; k < parts.size(); ++k) {
            Capsule& into = parts[k].capsule;
            const Capsule& sphere = parts[s].capsule;
            if (k == s || gone[k]) {
                continue;
            }
            const double need = segment_distance(sphere.a, into.a, into.b) + sphere.radius;
            if (need <= into.radius + tolerance) {
                into.radius = std::max(into.radius, need);
                gone[s] = true;
                ++merged;
                break;
            }
        }
    }
    std::vector<LinkCapsule> out;
    for (std::size_t i = 0U; i < parts.size(); ++i) {
        if (!gone[i]) {
            out.push_back(parts[i]);
        }
    }
    return out;
}

/// The link's capsules, in the link frame, merged.
std::vector<LinkCapsule> link_capsules(const urdf::Link& link, const UrdfImportOptions& options,
                                       std::vector<std::string>& notes) {
    std::vector<LinkCapsule> parts;
    const char* name = link.name.c_str();
    if (link.collision_array.empty() && !link.visual_array.empty()) {
        notes.push_back("link '" + link.name + "' has visual but no collision geometry: no capsule, not masked");
    }
    for (const urdf::CollisionSharedPtr& collision : link.collision_array) {
        if (!collision || !collision->geometry) {
            fail(ErrorCode::kMalformedInput, "link '%s': a <collision> without geometry", name);
        }
        LinkCapsule part = shape_capsule(*collision->geometry, options, name);
        part.capsule = transformed(part.capsule, collision->origin, name);
        parts.push_back(part);
    }
    int merged = 0;
    parts = merge_spheres(std::move(parts), options.merge_tolerance, merged);
    if (merged > 0) {
        notes.push_back("link '" + link.name + "': " + std::to_string(merged) + " sphere(s) merged into a capsule");
    }
    for (const LinkCapsule& p : parts) {
        const Capsule& c = p.capsule;
        if (c.radius > kMaxCapsuleRadius) {
            fail(ErrorCode::kInvalidArgument, "link '%s': capsule radius %.3f m, at most %.1f m", name, c.radius,
                 kMaxCapsuleRadius);
        }
        if (!(c.radius > 0.0)) {
            fail(ErrorCode::kInvalidArgument, "link '%s': degenerate geometry (capsule radius 0)", name);
        }
        if (c.a.norm() > kMaxRobotReach || c.b.norm() > kMaxRobotReach) {
            fail(ErrorCode::kInvalidArgument, "link '%s': geometry reaches beyond %.0f m of the link frame", name,
                 kMaxRobotReach);
        }
    }
    return parts;
}

/// Every node's capsules: a kept node's on its own link, a folded node's as
/// envelopes on its anchor (@p index maps nodes to model links).
void put_capsules(const std::vector<Node>& nodes, const StrokePlan& plan, const std::vector<int>& index,
                  const UrdfImportOptions& options, UrdfImport& result) {
    std::vector<std::pair<std::size_t, Capsule>> all;
    std::vector<std::string> per_link;
    for (std::size_t i = 0U; i < nodes.size(); ++i) {
        const std::vector<LinkCapsule> parts = link_capsules(*nodes[i].link, options, result.notes);
        for (const LinkCapsule& p : parts) {
            const Capsule c = plan.folded[i] ? fold_capsule(nodes, plan, i, p.capsule, result) : p.capsule;
            all.emplace_back(static_cast<std::size_t>(index[plan.anchor[i]]), c);
        }
        if (!parts.empty()) {
            per_link.push_back(nodes[i].link->name + " " + std::to_string(parts.size()));
        }
    }
    if (all.size() > kMaxRobotCapsules) {
        fail(ErrorCode::kCapacityExceeded, "%zu capsules after merging (%s), at most %zu", all.size(),
             join(per_link, ", ").c_str(), kMaxRobotCapsules);
    }
    if (all.empty()) {
        fail(ErrorCode::kInvalidArgument, "no link has collision geometry");
    }
    RobotModel& model = result.model;
    model.capsule_count = static_cast<std::uint8_t>(all.size());
    for (std::size_t k = 0U; k < all.size(); ++k) {
        RobotCapsule& out = model.capsules[k];
        out.link = static_cast<std::uint8_t>(all[k].first);
        for (int d = 0; d < 3; ++d) {
            out.a[d] = all[k].second.a[d];
            out.b[d] = all[k].second.b[d];
        }
        out.radius = all[k].second.radius;
    }
}

// ---------------------------------------------------------------- model

void put_name_and_base(const std::string& name, const UrdfImportOptions& options, UrdfImport& result) {
    RobotModel& model = result.model;
    const std::size_t n = std::min(name.size(), kRobotNameBytes - 1U);
    std::memcpy(model.name, name.data(), n);
    if (n < name.size()) {
        result.notes.push_back("robot name cut to " + std::to_string(n) + " bytes: " + name.substr(0U, n));
    }
    const Eigen::Quaterniond& q = options.base_rotation;
    if (!options.base_xyz.allFinite() || !q.coeffs().allFinite() || q.norm() == 0.0) {
        fail(ErrorCode::kInvalidArgument, "base pose: not finite (or a zero rotation)");
    }
    const Eigen::Quaterniond unit = q.normalized();
    const double wxyz[4] = {unit.w(), unit.x(), unit.y(), unit.z()};
    for (int k = 0; k < 3; ++k) {
        model.base_xyz[k] = options.base_xyz[k];
    }
    std::copy(wxyz, wxyz + 4, model.base_wxyz);
}

void import_model(const std::string& text, const UrdfImportOptions& options, UrdfImport& result) {
    const urdf::ModelInterfaceSharedPtr urdf = parse_model(text);
    check_xml(text);
    const std::vector<Node> all = drop_empty_frames(depth_first(*urdf), result.notes);
    const StrokePlan plan = plan_strokes(all, options, result.notes);
    std::vector<int> index;
    std::vector<bool> keep(all.size());
    std::transform(plan.folded.begin(), plan.folded.end(), keep.begin(), [](bool folded) { return !folded; });
    const std::vector<Node> nodes = kept_nodes(all, keep, index);
    if (nodes.size() > kMaxRobotLinks) {
        fail(ErrorCode::kCapacityExceeded, "%zu links, at most %zu", nodes.size(), kMaxRobotLinks);
    }
    if (options.joint_order.size() > kMaxRobotJoints) {
        fail(ErrorCode::kCapacityExceeded, "joint order: %zu joints, at most %zu", options.joint_order.size(),
             kMaxRobotJoints);
    }
    RobotModel& model = result.model;
    model.link_count = static_cast<std::uint8_t>(nodes.size());
    result.link_names.push_back(nodes[0].link->name);
    result.joint_names.emplace_back();
    for (std::size_t i = 1U; i < nodes.size(); ++i) {
        model.links[i].parent = static_cast<std::uint8_t>(nodes[i].parent);
        put_joint(*nodes[i].joint, model.links[i], result.notes);
        result.link_names.push_back(nodes[i].link->name);
        result.joint_names.push_back(nodes[i].joint->name);
    }
    put_command_order(nodes, options.joint_order, model);
    put_mimics(nodes, model, result.notes);
    put_capsules(all, plan, index, options, result);
    put_name_and_base(urdf->getName(), options, result);
    const RobotModelError error = check_robot_model(model);
    if (error.code != ErrorCode::kOk) {
        fail(error.code, "the imported model fails its check: %s (item %zu)", error.reason, error.index);
    }
}

}  // namespace

IoStatus import_urdf_text(const std::string& text, const UrdfImportOptions& options, UrdfImport& result) {
    result = UrdfImport{};
    try {
        if (text.size() > kUrdfMaxBytes) {
            fail(ErrorCode::kCapacityExceeded, "URDF of %zu bytes, at most %zu", text.size(), kUrdfMaxBytes);
        }
        import_model(text, options, result);
    } catch (const ImportFailure& failure) {
        result = UrdfImport{};
        return failure.status();
    } catch (const std::exception& e) {
        result = UrdfImport{};
        return IoStatus::failure(ErrorCode::kMalformedInput, "URDF: %s", e.what());
    }
    return {};
}

IoStatus import_urdf_file(const std::string& path, const UrdfImportOptions& options, UrdfImport& result) {
    result = UrdfImport{};
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open", path.c_str());
    }
    std::string text;
    text.resize(kUrdfMaxBytes + 1U);
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<std::size_t>(in.gcount()));
    if (in.bad()) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: read error", path.c_str());
    }
    UrdfImportOptions with_directory = options;
    with_directory.base_directory = std::filesystem::path(path).parent_path().string();
    if (with_directory.base_directory.empty()) {
        with_directory.base_directory = ".";
    }
    return import_urdf_text(text, with_directory, result).prefixed(path.c_str());
}

}  // namespace cellguard::host
