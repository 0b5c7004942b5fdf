// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file scenario.hpp
/// The demo's scripted person: a 0.3 m x 0.3 m x 1.7 m box (the simulator's
/// stand-in for a person) who waits outside the cell, walks into the warning
/// zone, steps into the protective zone, walks out along the warning strip,
/// stands behind background box A, and leaves. Positions are given per cycle
/// so the monitor and the log check agree on when the person enters a zone.
#ifndef CELLGUARD_HOST_CELL_SCENARIO_HPP
#define CELLGUARD_HOST_CELL_SCENARIO_HPP

#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::cell {

/// Footprint edge of the person box, metres.
constexpr double kPersonWidth = 0.3;
/// Height of the person box, metres.
constexpr double kPersonHeight = 1.7;

/// Where the person stands in one cycle (floor position of the box centre).
struct PersonPosition {
    double x = 0.0;  ///< metres
    double y = 0.0;  ///< metres
};

/// The person's position in demo cycle @p cycle (0-based); after the last
/// waypoint the person stays outside the cell.
PersonPosition demo_person(int cycle);
/// The simulator box of the person at @p p.
sim::Box person_box(const PersonPosition& p);
/// True when the person's box at @p p overlaps @p zone (tested on a 1 cm lattice of the box).
bool person_overlaps(const ZoneConfig& zone, const PersonPosition& p);
/// A short label of where the person is along the path in @p cycle.
const char* demo_phase(int cycle);

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_SCENARIO_HPP
