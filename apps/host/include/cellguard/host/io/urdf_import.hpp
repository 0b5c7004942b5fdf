// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file urdf_import.hpp
/// Commissioning a robot from its URDF (liburdfdom, Debian liburdfdom-dev):
/// the kinematic tree, the joint limits and the collision geometry as
/// capsules, in a RobotModel (cellguard/robot/robot_model.hpp) that
/// cellguard-robot writes as the robot image. Host side only (heap,
/// exceptions inside, none escape).
///
/// Links: parent before child, depth first from the root, children in
/// joint-name order (liburdfdom's maps). A link joined by a fixed joint that
/// has no collision geometry and no children (a tool frame such as tool0)
/// carries nothing the controller needs: it is dropped, repeatedly, and the
/// notes say so. At most kMaxRobotLinks links remain.
///
/// Joints: revolute and prismatic; continuous joints become revolute with
/// limits -2 pi .. +2 pi (kinematics are periodic: the PLC sends the
/// position wrapped into that range, which the command's +-6.5534 rad
/// carries), and the notes say so. Refused, naming the joint: floating and
/// planar joints, a mimic of a mimic or of a joint the URDF lacks, a movable
/// joint without <axis>, a zero axis,
/// an axis whose length differs from 1 by more than kUrdfAxisTolerance
/// (within it, the axis is normalised and the notes say so: URDFs write
/// "0.7071 0 0.7071"), lower > upper, velocity <= 0 (a continuous joint
/// needs <limit velocity=...>), limits outside what the command's int16
/// carries (robot_command.hpp), non-finite numbers. Command order: the PLC's
/// joint names (UrdfImportOptions::joint_order), matched by name: each must
/// name a movable joint, once; every movable joint must be named; at most
/// kMaxRobotJoints. A zero pose outside the limits is allowed (real arms).
///
/// Mimic joints of sent joints (a palletizer's parallelogram): a mimic whose
/// master the PLC sends is not in the joint order (refused when named there)
/// and becomes a mimic link (robot_model.hpp) with its master's command
/// index and the URDF's multiplier and offset; its master's range must map
/// inside its own limits ("a wrong multiplier or offset?"), and a multiplier
/// of 0 is refused. A mimic without a velocity limit (0 or no <limit>) gets
/// its master's x |multiplier|. The notes list each mimic.
///
/// Grippers: UrdfImportOptions::stroke_joints names the joints the PLC does
/// not send (a gripper's fingers). A mimic joint of a stroke joint is one
/// too and follows it (position = multiplier x master + offset); its
/// master's range must map inside its own limits, or the file is refused
/// as a wrong multiplier or offset. A stroke joint named itself is enclosed
/// over its own limits (also a mimic: the notes say so). Every link below a
/// stroke joint is folded into the nearest link above that is not (the
/// anchor): it leaves the model, and each of its capsules becomes, on the
/// anchor, a capsule that encloses it over every position of the stroke
/// joints that move it (stroke_envelope.hpp; at most kMaxStrokeVariables
/// per capsule). Refused: a stroke joint that is not a movable joint of the
/// URDF, named twice or also in the PLC's order; a joint in the PLC's order
/// below a stroke joint; a movable joint below a stroke joint that is not
/// named a stroke joint. FoldedCapsule records each fold; the notes give
/// the radius and volume before and after.
///
/// Structure: liburdfdom's own refusals (two roots, no root, a joint to a
/// missing link) and, checked on the XML, a link with two parent joints.
/// Any error or warning liburdfdom logs through console_bridge refuses the
/// file, with the logged text: liburdfdom drops a bad <collision> (an
/// unknown shape such as <capsule>, a missing <geometry>, a one-number
/// scale, NaN in a size) and every later one of the link, and would still
/// return a model. While parsing, import_urdf_* installs its own
/// console_bridge output handler (global state: one import at a time).
///
/// Geometry (each <collision>, its origin applied): sphere -> a sphere
/// (capsule with both ends equal); cylinder -> the capsule along its axis
/// with its radius and length (contains it); box -> the capsule along its
/// longest edge, as long as the box, radius half the diagonal of the cross
/// section (contains it); a mesh (STL, COLLADA .dae or OBJ, read by
/// mesh.hpp in a child process, the file's unit and the URDF's scale
/// applied) -> bounding_capsule() of its vertices, checked to contain each;
/// a mesh whose extent lies outside kMinMeshExtent .. kMaxMeshExtent is
/// refused as one in the wrong unit; any other suffix -> refused, naming
/// the link and the file.
/// Sizes and scales must be finite and > 0. A link with <visual> but no
/// <collision> gets no capsule (the notes say so: its voxels stay
/// foreground, which stops the robot rather than hide anyone). Mesh files: `package://NAME/REST`
/// resolves to packages[NAME]/REST; a relative path resolves against the
/// URDF's directory (base_directory); absolute paths and other schemes
/// (file://, http://) are refused, so that the files a robot image comes
/// from are exactly the ones the command line names.
///
/// The URDF way to write a capsule (a cylinder and a sphere on each end) is
/// merged: a sphere is dropped when it lies within merge_tolerance of
/// inside another capsule of its link, whose radius then grows to contain
/// it exactly (by at most merge_tolerance). At most kMaxRobotCapsules
/// capsules remain. Every capsule: radius <= kMaxCapsuleRadius, ends within
/// kMaxRobotReach of the link frame. The result passes check_robot_model().
#ifndef CELLGUARD_HOST_IO_URDF_IMPORT_HPP
#define CELLGUARD_HOST_IO_URDF_IMPORT_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "cellguard/host/io/io_status.hpp"
#include "cellguard/robot/robot_model.hpp"

namespace cellguard::host {

/// Default merge tolerance of a URDF capsule's parts, metres: descriptions
/// that write pi/2 as 1.57 miss by a fraction of a millimetre.
constexpr double kUrdfMergeTolerance = 0.001;
/// Largest |length - 1| of a joint axis that is normalised; beyond it the
/// axis is refused (a typo such as "0 0 2" or "1 1 0").
constexpr double kUrdfAxisTolerance = 1e-3;
/// Smallest extent (bounding-box diagonal) of a link's mesh, metres, after
/// its unit and scale: below it, a mesh in metres scaled as millimetres.
constexpr double kMinMeshExtent = 0.002;
/// Largest extent of a link's mesh, metres: beyond it, millimetres read as metres.
constexpr double kMaxMeshExtent = 4.0;
/// Largest URDF text, bytes.
constexpr std::size_t kUrdfMaxBytes = std::size_t{4} << 20U;

/// What the import needs beside the URDF.
struct UrdfImportOptions {
    /// The PLC's joint order: command position k is the joint named joint_order[k].
    std::vector<std::string> joint_order;
    /// The root link's position in the cell's world frame, metres.
    Eigen::Vector3d base_xyz = Eigen::Vector3d::Zero();
    /// The root link's rotation in the world frame (normalised on use).
    Eigen::Quaterniond base_rotation = Eigen::Quaterniond::Identity();
    /// package:// resolution: package name -> directory.
    std::map<std::string, std::string> packages;
    /// Directory of relative mesh paths; import_urdf_file() sets the URDF's own.
    std::string base_directory;
    /// See the file comment; 0 merges only spheres fully inside.
    double merge_tolerance = kUrdfMergeTolerance;
    /// Stroke joints: movable joints the PLC does not send (a gripper's
    /// fingers). Each, every mimic joint of it and every link below it are
    /// folded into the link above (the anchor), whose capsules then enclose
    /// theirs over the whole stroke (stroke_envelope.hpp).
    std::vector<std::string> stroke_joints;
};

/// A capsule in some frame: the points within radius of the segment a-b.
struct Capsule {
    Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< first end
    Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< second end (= a: a sphere)
    double radius = 0.0;                          ///< metres
};

/// A capsule of a link folded into its anchor: what it became.
struct FoldedCapsule {
    std::string link;        ///< URDF name of the folded link
    std::string anchor;      ///< URDF name of the link that carries the envelope
    Capsule original{};      ///< the capsule in the folded link's frame
    Capsule envelope{};      ///< in the anchor's frame, enclosing the original over the stroke
    double between = 0.0;    ///< the envelope's margin for movement between sampled poses, metres
    std::size_t poses = 0U;  ///< sampled poses
};

/// The imported robot and what the import did.
struct UrdfImport {
    RobotModel model{};                    ///< checked with check_robot_model()
    std::vector<std::string> link_names;   ///< URDF name of model link i
    std::vector<std::string> joint_names;  ///< URDF name of the joint above link i ("" for the root)
    std::vector<std::string> notes;        ///< merges, normalised axes, dropped frames, continuous joints, folds
    std::vector<FoldedCapsule> folded;     ///< capsules of links below stroke joints, as enveloped
};

/// Imports the URDF @p text. Errors (the message names the link, joint or
/// file): kMalformedInput (liburdfdom's refusals and logged errors, broken
/// trees), kUnsupportedType (geometry, joint types), kInvalidArgument
/// (axes, limits, sizes, joint order, paths), kCapacityExceeded (links,
/// joints, capsules, sizes), kNonFiniteValue; a mesh file's own errors.
IoStatus import_urdf_text(const std::string& text, const UrdfImportOptions& options, UrdfImport& result);

/// Reads the URDF at @p path (at most kUrdfMaxBytes) and imports it with
/// relative mesh paths resolved against its directory. The message of an
/// error starts with @p path.
IoStatus import_urdf_file(const std::string& path, const UrdfImportOptions& options, UrdfImport& result);

/// A capsule that contains every point of @p points (not empty): of the
/// capsules along the principal axis and along each coordinate axis, each
/// with its axis line through the centre of the points' bounding rectangle
/// across it and the shortest segment that then contains them, the one of
/// least volume; its radius is then raised to the largest distance of any
/// point from its segment, so that containment holds as computed.
Capsule bounding_capsule(const std::vector<Eigen::Vector3d>& points);

/// Volume of @p c, cubic metres: a cylinder and a sphere.
[[nodiscard]] double capsule_volume(const Capsule& c) noexcept;

/// Distance of @p p from the segment @p a - @p b.
double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_URDF_IMPORT_HPP
