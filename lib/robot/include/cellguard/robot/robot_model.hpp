// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file robot_model.hpp
/// The robot as the controller knows it: a kinematic tree of links joined by
/// fixed, revolute or prismatic joints, and the capsules (spheres when both
/// ends coincide) that bound each link's collision geometry. Fixed capacity,
/// plain data: the robot image (robot_image.hpp) stores exactly this, and
/// commissioning (apps/host, from a URDF) produces it.
///
/// Conventions (those of URDF): link 0 is the root; link i > 0 hangs from
/// links[i].parent < i through its joint, whose origin (translation, then
/// rotation as a unit quaternion w, x, y, z) places the child frame in the
/// parent frame at joint position 0, and whose unit axis is in the child
/// frame. A revolute joint at position q rotates the child by q radians
/// about the axis; a prismatic joint translates it by q metres along the
/// axis. The root link sits at base_translation / base_rotation in the
/// cell's world frame. Movable joints take their position from the PLC's
/// command: command_index k reads RobotCommand::joint_raw[k]. A mimic joint
/// (a parallelogram linkage's passive joint, URDF <mimic>) is not sent: it
/// reads its master's position q (the joint that owns command_index) and
/// stands at mimic_multiplier * q + mimic_offset.
#ifndef CELLGUARD_ROBOT_MODEL_HPP
#define CELLGUARD_ROBOT_MODEL_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/safety/robot_command.hpp"

namespace cellguard {

/// Most links of one robot, the root included.
constexpr std::size_t kMaxRobotLinks = 16U;
/// Most capsules of one robot (all links together).
constexpr std::size_t kMaxRobotCapsules = 32U;
/// Most movable joints: one command carries this many positions.
constexpr std::size_t kMaxRobotJoints = kMaxCommandJoints;
/// Longest robot name, bytes, terminating zero included.
constexpr std::size_t kRobotNameBytes = 32U;
/// A movable joint's command_index for fixed joints and the root.
constexpr std::uint8_t kNoCommandIndex = 0xFFU;
/// Largest capsule radius accepted, metres (a link thicker than this is not an arm).
constexpr double kMaxCapsuleRadius = 1.0;
/// Largest distance of any capsule end or joint origin from its frame, metres.
constexpr double kMaxRobotReach = 10.0;
/// Largest |limit| of a revolute joint, radians (16 turns; the command carries
/// +-6.5534 rad, and the kinematics' sine and cosine are exact far beyond).
constexpr double kMaxRevoluteLimit = 100.0;
/// Slack of a mimic's mapped range against its own limits, relative to the
/// larger of 1 and its largest |limit| (URDFs print limits to a few digits).
constexpr double kMimicRangeTolerance = 1e-6;
/// Tolerance of a joint axis' or a quaternion's unit length (|len - 1| <= this).
constexpr double kUnitLengthTolerance = 1e-6;

/// How a link moves against its parent.
enum class JointType : std::uint8_t {
    kFixed = 0,      ///< rigidly attached (and the root's type)
    kRevolute = 1,   ///< rotation about the axis, limits in radians
    kPrismatic = 2,  ///< translation along the axis, limits in metres
};

/// One link and the joint that attaches it to its parent.
struct RobotLink {
    std::uint8_t parent = 0U;                      ///< parent link index (< own index; the root's is 0)
    JointType joint = JointType::kFixed;           ///< joint type (kFixed for the root)
    std::uint8_t command_index = kNoCommandIndex;  ///< movable joints: index into RobotCommand::joint_raw
    double origin_xyz[3] = {0.0, 0.0, 0.0};        ///< joint origin translation in the parent frame, metres
    double origin_wxyz[4] = {1.0, 0.0, 0.0, 0.0};  ///< joint origin rotation, unit quaternion w, x, y, z
    double axis[3] = {1.0, 0.0, 0.0};              ///< movable joints: unit axis in the child frame
    double lower = 0.0;                            ///< movable joints: lowest position (rad or m)
    double upper = 0.0;                            ///< movable joints: highest position (rad or m), >= lower
    double max_velocity = 0.0;                     ///< movable joints: largest speed (rad/s or m/s), > 0
    bool mimic = false;             ///< movable joints: follows the joint that owns command_index (not sent)
    double mimic_multiplier = 1.0;  ///< mimic joints: position = multiplier * master + offset (non-zero); else 1
    double mimic_offset = 0.0;      ///< mimic joints: see mimic_multiplier (rad or m); else 0
};

/// A capsule: all points within radius of the segment a-b, in its link's frame.
struct RobotCapsule {
    std::uint8_t link = 0U;         ///< link the capsule belongs to
    double a[3] = {0.0, 0.0, 0.0};  ///< first end, metres, link frame
    double b[3] = {0.0, 0.0, 0.0};  ///< second end (equal to a: a sphere)
    double radius = 0.0;            ///< metres, 0 < radius <= kMaxCapsuleRadius
};

/// A robot: links in parent-before-child order, and its capsules.
struct RobotModel {
    char name[kRobotNameBytes] = {};                ///< zero-terminated name (the URDF robot name)
    std::uint8_t link_count = 0U;                   ///< links used, 1..kMaxRobotLinks
    std::uint8_t joint_count = 0U;                  ///< movable joints (= command positions), 0..kMaxRobotJoints
    std::uint8_t capsule_count = 0U;                ///< capsules used, 1..kMaxRobotCapsules
    RobotLink links[kMaxRobotLinks] = {};           ///< links[0] is the root
    RobotCapsule capsules[kMaxRobotCapsules] = {};  ///< capsules of all links
    double base_xyz[3] = {0.0, 0.0, 0.0};           ///< root link position in the cell's world frame, metres
    double base_wxyz[4] = {1.0, 0.0, 0.0, 0.0};     ///< root link rotation in the world frame, unit quaternion
};

/// Why a robot model (or its image) was refused, with the item's position.
struct RobotModelError {
    ErrorCode code = ErrorCode::kOk;  ///< kInvalidArgument, kCapacityExceeded, kNonFiniteValue, ...
    std::size_t index = 0U;           ///< the offending link or capsule (0 for the whole model)
    const char* reason = "";          ///< static text: what is wrong
};

/// True when @p e means "no error": what Result<T, RobotModelError> checks.
constexpr bool is_no_error(const RobotModelError& e) noexcept { return e.code == ErrorCode::kOk; }

/// Checks @p model: counts within capacity (1..16 links, 1..32 capsules,
/// joint_count 0..7); the name zero-terminated; every number finite; parents
/// before children; the root fixed, parent 0, no command index and the
/// identity origin (base_xyz / base_wxyz place it); known joint types; unit
/// quaternions and unit axes of movable joints (within
/// kUnitLengthTolerance); movable joints' command indices exactly
/// 0..joint_count-1, each once (mimic joints excepted: theirs names their
/// master, which must not be a mimic); a mimic's multiplier non-zero and its
/// master's whole range mapped inside its own limits (within
/// kMimicRangeTolerance); a link that is not a mimic with multiplier 1 and
/// offset 0; lower <= upper, both within
/// +-kMaxRevoluteLimit (revolute) or +-kMaxRobotReach (prismatic);
/// max_velocity > 0; fixed
/// joints without a command index; capsules on existing links with
/// 0 < radius <= kMaxCapsuleRadius; every translation and capsule end within
/// kMaxRobotReach (the base position too). Only the used entries (below the
/// counts) are read. The first failure is returned; code kOk when none:
/// kCapacityExceeded for counts above capacity, kNonFiniteValue for NaN or
/// infinity, kInvalidArgument for everything else (index = the link or
/// capsule; 0 for the counts, the name and the base).
[[nodiscard]] RobotModelError check_robot_model(const RobotModel& model) noexcept;

/// The link whose joint owns command index @p k (movable, not a mimic), or
/// nullptr when no link does. One per index in a checked model.
[[nodiscard]] const RobotLink* commanded_link(const RobotModel& model, std::size_t k) noexcept;

/// Whether @p model has a mimic joint (its image then needs format version 2).
[[nodiscard]] bool has_mimic_joint(const RobotModel& model) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_ROBOT_MODEL_HPP
