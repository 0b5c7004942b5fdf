// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The paper cell's commissioning as the controller and background-change
// tests build it: the paper sensors' render of the empty reference scene,
// G_B from 8 of those frames (fuse_background_frame, exact rasterization,
// the default sensor model) and the accessibility prior of G_B (default
// parameters). It is immutable and the same for every test, so it is built
// once per process (paper_cell_commissioning) and each test copies what it
// may change: a test that flips a prior bit flips its own copy.
#ifndef CELLGUARD_TESTS_PAPER_CELL_HPP
#define CELLGUARD_TESTS_PAPER_CELL_HPP

#include <cstdint>
#include <vector>

#include "cellguard/host/sim/workcell.hpp"

namespace cellguard::test {

/// The paper cell commissioned from its empty reference scene (see the file comment).
struct PaperCellCommissioning {
    /// sim::paper_sensors() rendering sim::reference_scene(): its readings point into its depth images.
    sim::SimulatedFrame empty;
    /// The accessibility prior of G_B, one value per voxel of paper_grid_geometry().
    std::vector<std::int16_t> prior;
    /// The frame grid and the fusion scratch as the 8 fusions left them (a
    /// test that used them as working storage for G_B hands them on so).
    std::vector<std::int16_t> frame_log_odds;
    std::vector<std::uint8_t> frame_observed;
    std::vector<std::int16_t> scratch;
};

/// The commissioning, built on the first call (REQUIRE on each step) and
/// shared, read-only, by every later call in the process.
const PaperCellCommissioning& paper_cell_commissioning();

/// The paper's sensors rendering the reference scene with a person-sized
/// foreground box (0.4 x 0.3 x 1.8 m, yaw 0.4) near the cell's centre.
sim::SimulatedFrame paper_person_frame();

}  // namespace cellguard::test

#endif  // CELLGUARD_TESTS_PAPER_CELL_HPP
