// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file paper_sensor_model.hpp
/// The paper's own sensor model (section IV), for the evaluation only: the
/// parametrized one-dimensional profile after Moravec, accumulated ray by
/// ray. Every valid reading is a ray from the sensor's origin; every voxel
/// the ray reaches gets the profile's log-odds added (saturating), so a
/// voxel's frame evidence is the sum over every ray of every sensor that
/// reaches it:
/// - the voxel holding the reading: the peak, P(occ) = 0.56;
/// - a voxel the ray leaves at least ramp_length (10 cm) before its reading:
///   the trough, P(occ) = 0.44 (the paper's "0.44 at the sensor origin";
///   the paper leaves the shape between origin and reading open: constant
///   here, as the paper's figure 3 draws it flat);
/// - within ramp_length before the reading: rising linearly to 0.5 at the
///   reading (so space just in front of a surface is not called free with
///   full weight, and no voxel other than the reading's is made occupied).
/// The profile's values are those of lib's SensorModelTable built with
/// p_miss = 0.44 and p_hit = 0.56 (paper_profile()); only the accumulation
/// differs from the product's model (one opinion per sensor, voxel and
/// frame; grid/sensor_model.hpp).
///
/// Why the monitor does not use it: summed over every ray, a voxel that a
/// surface only clips is crossed by many grazing rays and reads free; at
/// 640 x 480 a quarter of real Kinect frames' surface voxels were lost that
/// way (issue 24; safety manual 1.1). The product keeps every reading.
///
/// Readings are taken, placed and skipped by the product's one reading loop
/// (for_each_reading_ray, fusion.hpp): NaN, infinite, zero, behind the
/// sensor (z < 0), nearer than min_range or beyond max_range are skipped.
/// Host code: the evaluation's experiments and their tests.
#ifndef CELLGUARD_HOST_SIM_PAPER_SENSOR_MODEL_HPP
#define CELLGUARD_HOST_SIM_PAPER_SENSOR_MODEL_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_traversal.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/grid/sensor_model.hpp"

namespace cellguard::sim {

/// Which sensor model an experiment fuses its frames with.
enum class EvalSensorModel : std::uint8_t {
    kPaper = 0,    ///< the paper's per-ray profile, summed over rays (this file)
    kProduct = 1,  ///< the monitor's: one opinion per sensor, voxel and frame (fusion.hpp)
};

/// "paper" or "product".
[[nodiscard]] const char* model_name(EvalSensorModel model) noexcept;

/// The paper's profile parameters as lib's table takes them: trough 0.44,
/// peak 0.56, a 10 cm ramp (the clamps are not used by the per-ray sum).
[[nodiscard]] SensorModelParams paper_profile() noexcept;

/// Adds one ray's profile, from @p origin to @p reading (cell frame,
/// metres), to @p grid (saturating) and marks the voxels observed; returns
/// the number of voxels the ray reaches. Sets @p reading_in_grid when the
/// reading's voxel lies in the grid. Non-finite input adds nothing.
std::uint32_t add_ray_profile(EvidenceGrid& grid, const Eigen::Vector3d& origin, const Eigen::Vector3d& reading,
                              const SensorModelTable& profile, Rasterization rasterization,
                              bool* reading_in_grid) noexcept;

/// Adds every valid reading of every sensor of one frame to @p grid, ray by
/// ray (add_ray_profile), after checking every description
/// (validate_sensor_reading; on error the grid is untouched). The grid is
/// not cleared here. Counts as fuse_frame does.
[[nodiscard]] Result<FusionStats> fuse_frame_per_ray(EvidenceGrid& grid, Span<const SensorReading> sensors,
                                                     const SensorModelTable& profile,
                                                     Rasterization rasterization) noexcept;

/// Empty frames the probabilistic method needs with the paper's model
/// before a voxel that one ray per frame clears falls below t_E in G_B:
/// ceil(logit(t_E) / trough), at least 1.
[[nodiscard]] std::uint32_t paper_min_background_frames(double t_e, const SensorModelTable& profile) noexcept;

}  // namespace cellguard::sim

#endif  // CELLGUARD_HOST_SIM_PAPER_SENSOR_MODEL_HPP
