// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file test_piece.hpp
/// Test pieces for detection capability (ISO 13855, IEC 61496 test pieces):
/// a solid cylinder with flat ends (a rod of a diameter and a length) or a
/// sphere, at any position and orientation in the cell, and their exact ray
/// intersection for rendering them into the simulator's depth images
/// (detection.hpp renders them over a sensor's view of the empty cell).
#ifndef CELLGUARD_HOST_SIM_TEST_PIECE_HPP
#define CELLGUARD_HOST_SIM_TEST_PIECE_HPP

#include <Eigen/Core>
#include <cstdint>

namespace cellguard::sim {

/// The shape of a test piece.
enum class PieceShape : std::uint8_t {
    kCylinder = 0,  ///< a solid cylinder with flat ends
    kSphere = 1,    ///< a solid sphere
};

/// Static name of a shape ("cylinder", "sphere").
const char* to_string(PieceShape shape) noexcept;

/// A test piece in the cell frame.
struct TestPiece {
    PieceShape shape = PieceShape::kCylinder;          ///< which solid
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< its centre, metres
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< cylinder: unit vector along its axis
    double diameter = 0.0;                             ///< metres
    double length = 0.0;                               ///< cylinder: from end face to end face, metres
    /// Radius of the smallest sphere about the centre that holds the piece.
    [[nodiscard]] double bounding_radius() const noexcept;
    /// Lowest z of any point of the piece (its height above the floor when positive).
    [[nodiscard]] double lowest_z() const noexcept;
};

/// Distance along the ray origin + t dir (dir unit) to where it first meets
/// the piece's surface, 0 when the origin lies inside, +infinity when it
/// misses it (or meets it only behind the origin).
[[nodiscard]] double intersect_piece(const TestPiece& piece, const Eigen::Vector3d& origin,
                                     const Eigen::Vector3d& dir) noexcept;

/// True when @p p lies inside or on the piece.
[[nodiscard]] bool piece_contains(const TestPiece& piece, const Eigen::Vector3d& p) noexcept;

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_TEST_PIECE_HPP
