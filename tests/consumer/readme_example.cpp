// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// README's consumer example (tests/consumer/CMakeLists.txt links it with the
// libraries README's `target_link_libraries(my_controller ...)` line names):
// a controller that uses lib/ and the Linux port's clock, as a newcomer's
// first program does. Built, linked and run: exit status 0 when the clock
// advances and a grid is made.
#include <Eigen/Core>
#include <cstdint>
#include <cstdio>

#include "cellguard/grid/grid.hpp"
#include "cellguard/port/clock.hpp"

int main() {
    using namespace cellguard;
    const Result<GridGeometry> grid = GridGeometry::make(Eigen::Vector3d::Zero(), 0.05, GridDims{4, 4, 4});
    const std::uint64_t a = linux_port::monotonic_now_us();
    const std::uint64_t b = linux_port::monotonic_now_us();
    const bool ok = grid.ok() && b >= a && a > 0U;
    std::printf("%s: README's example: lib/ and the Linux port's clock, linked as README says\n", ok ? "ok  " : "FAIL");
    return ok ? 0 : 1;
}
