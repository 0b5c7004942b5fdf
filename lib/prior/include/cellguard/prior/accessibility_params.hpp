// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file accessibility_params.hpp
/// The parameters of the accessibility analysis (the paper's sections II-IV),
/// shared by the analysis itself (accessibility.hpp) and the prior image that
/// records how a prior was made (prior_image.hpp).
#ifndef CELLGUARD_ACCESSIBILITY_PARAMS_HPP
#define CELLGUARD_ACCESSIBILITY_PARAMS_HPP

#include <cstdint>

namespace cellguard {

/// How the accessibility prior P(fore) was computed. The numeric values are
/// stored in prior images: append only, never renumber.
enum class PriorMethod : std::uint8_t {
    kThresholded = 1,            ///< eqs. 1-7: erosion, components from A_0, dilation; P(fore) in {0, 0.5}
    kProbabilistic = 2,          ///< eqs. 8-21: min-cost paths; P(fore) = P(acc) / 2
    kThresholdedBaseline = 3,    ///< section IV baseline: E in place of A in eq. 7
    kProbabilisticBaseline = 4,  ///< section IV baseline: 1 - P(occ; G_B) in place of P(acc)
};

/// One bit per face of the grid box; a set bit marks the face as open
/// (part of A_0, the known-accessible set, and free space beyond it).
enum GridFace : std::uint8_t {
    kFaceMinX = 1U << 0U,  ///< the face at x = 0
    kFaceMaxX = 1U << 1U,  ///< the face at x = nx - 1
    kFaceMinY = 1U << 2U,  ///< the face at y = 0
    kFaceMaxY = 1U << 3U,  ///< the face at y = ny - 1
    kFaceMinZ = 1U << 4U,  ///< the floor, z = 0
    kFaceMaxZ = 1U << 5U,  ///< the ceiling, z = nz - 1
};

/// The paper's A_0: the four side faces open, floor and ceiling closed.
constexpr std::uint8_t kPaperOpenFaces = static_cast<std::uint8_t>(
    static_cast<unsigned>(kFaceMinX) | static_cast<unsigned>(kFaceMaxX) | static_cast<unsigned>(kFaceMinY) |
    static_cast<unsigned>(kFaceMaxY));
/// Mask of all six face bits; other bits are invalid.
constexpr std::uint8_t kAllFaces = 0x3FU;

/// Largest radius r, in voxels, that the analysis accepts and a prior image may record.
constexpr std::int32_t kMaxAccessibilityRadius = 8;

/// Parameters of the accessibility analysis; defaults are the paper's.
struct AccessibilityParams {
    PriorMethod method = PriorMethod::kProbabilistic;  ///< which method computes the prior
    double t_b = 0.51;                                 ///< thresholded: a voxel is empty when P(occ; G_B) < t_B (eq. 1)
    double t_e = 0.1;                ///< probabilistic: P(occ) below t_E, and unobserved voxels, count as 0 (eq. 13)
    std::int32_t radius_voxels = 2;  ///< r of the L1-ball object R, in voxels (paper: 10 cm = 2 voxels)
    std::uint8_t open_faces = kPaperOpenFaces;  ///< GridFace bits of the faces in A_0
};

}  // namespace cellguard

#endif  // CELLGUARD_ACCESSIBILITY_PARAMS_HPP
