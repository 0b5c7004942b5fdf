// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Compiled against cellguard_can alone (tests/CMakeLists.txt): the CAN
// module, with the PLC receiver and the CAN sender interface, must build
// without the grid, the controller and Eigen. If the include path of the
// can module ever reaches them, this file stops compiling and the ctest
// layering_can_module_builds_without_the_grid fails.
#include "cellguard/can/can_sender.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/safety/clock.hpp"
#include "cellguard/safety/faults.hpp"

#if __has_include("cellguard/grid/grid.hpp") || __has_include("cellguard/safety/safety_controller.hpp") ||        \
                                                              __has_include("cellguard/prior/prior_image.hpp") || \
                                                                            __has_include(<Eigen/Core>)
#error "the can module sees the grid, the prior, the controller or Eigen"
#endif

/// Uses what it includes, so the probe is a real translation unit.
int cellguard_layering_probe_can() {
    const cellguard::SafetyMessage message = cellguard::safe_state_message(1U);
    return message.protective_stop ? 0 : 1;
}
