// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "paper_cell.hpp"

#include <doctest/doctest.h>

#include "cellguard/grid/fusion.hpp"
#include "cellguard/prior/accessibility.hpp"

namespace cellguard::test {

namespace {

PaperCellCommissioning commission() {
    const GridGeometry g = paper_grid_geometry();
    PaperCellCommissioning c;
    c.empty = sim::render_frame(sim::paper_sensors(), sim::reference_scene());
    c.prior.resize(g.voxel_count());
    c.frame_log_odds.resize(g.voxel_count());
    c.frame_observed.resize(g.voxel_count());
    c.scratch.resize(g.voxel_count());
    EvidenceGrid frame = EvidenceGrid::make(g, {c.frame_log_odds.data(), c.frame_log_odds.size()},
                                            {c.frame_observed.data(), c.frame_observed.size()})
                             .value();
    std::vector<std::int16_t> bg_lo(g.voxel_count());
    std::vector<std::uint8_t> bg_ob(g.voxel_count());
    EvidenceGrid bg = EvidenceGrid::make(g, {bg_lo.data(), bg_lo.size()}, {bg_ob.data(), bg_ob.size()}).value();
    bg.clear();
    const SensorModelTable model;
    for (int i = 0; i < 8; ++i) {
        REQUIRE(fuse_background_frame(bg, frame, {c.empty.readings.data(), c.empty.readings.size()}, model,
                                      {c.scratch.data(), c.scratch.size()})
                    .ok());
    }
    AccessibilityParams params;
    const AccessibilityScratchSize size = accessibility_scratch_size(g.dims(), params);
    std::vector<std::uint32_t> words(size.words);
    std::vector<std::uint8_t> bytes(size.bytes);
    REQUIRE(compute_accessibility_prior(
                bg, params, AccessibilityScratch{{words.data(), words.size()}, {bytes.data(), bytes.size()}},
                {c.prior.data(), c.prior.size()}, {})
                .ok());
    return c;
}

}  // namespace

const PaperCellCommissioning& paper_cell_commissioning() {
    static const PaperCellCommissioning c = commission();
    return c;
}

sim::SimulatedFrame paper_person_frame() {
    sim::Scene scene = sim::reference_scene();
    sim::Box box;
    box.center = Eigen::Vector3d(0.3, -0.2, 0.9);
    box.size = Eigen::Vector3d(0.4, 0.3, 1.8);
    box.yaw = 0.4;
    box.background = false;
    scene.boxes.push_back(box);
    return sim::render_frame(sim::paper_sensors(), scene);
}

}  // namespace cellguard::test
