// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file grid_config.hpp
/// The grid the firmware is compiled for: the paper's 34 x 30 x 30 voxels
/// at 5 cm (paper_grid_geometry, grid.hpp): the size of the static grid
/// storage. The prior image's grid is checked against paper_grid_geometry
/// at start-up (load_prior_image).
#ifndef CELLGUARD_FIRMWARE_GRID_CONFIG_HPP
#define CELLGUARD_FIRMWARE_GRID_CONFIG_HPP

/// Voxels along x.
#define CELLGUARD_GRID_NX 34
/// Voxels along y.
#define CELLGUARD_GRID_NY 30
/// Voxels along z.
#define CELLGUARD_GRID_NZ 30

#endif  // CELLGUARD_FIRMWARE_GRID_CONFIG_HPP
