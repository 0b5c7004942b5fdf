// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Compiled against cellguard_port_linux alone (tests/CMakeLists.txt): the
// Linux port's clock and CAN adapter must build without the grid, the
// controller and Eigen (they implement small interfaces: clock.hpp,
// can_sender.hpp). Fails to compile, and so fails the ctest
// layering_port_builds_without_the_grid, if the port's include path reaches them.
#include "cellguard/port/can.hpp"
#include "cellguard/port/clock.hpp"

#if __has_include("cellguard/grid/grid.hpp") || __has_include("cellguard/safety/safety_controller.hpp") ||        \
                                                              __has_include("cellguard/prior/prior_image.hpp") || \
                                                                            __has_include(<Eigen/Core>)
#error "the Linux port sees the grid, the prior, the controller or Eigen"
#endif

/// Uses what it includes, so the probe is a real translation unit.
int cellguard_layering_probe_port() {
    cellguard::linux_port::LinuxMonotonicClock clock;
    return clock.now_us() > 0U ? 0 : 1;
}
