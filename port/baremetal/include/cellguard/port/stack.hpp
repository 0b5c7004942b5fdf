// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file stack.hpp
/// The bare-metal port's stack painting (hazard H-MEM-3): the stack is the
/// linker script's region [__stack_bottom, __stack_top) (one stack: the
/// processor's main stack). StackMonitor::start() paints it from
/// __stack_bottom up to kStackPaintMarginBytes below its own frame and hands
/// the painting (cellguard/base/stack_paint.hpp) to the controller, which
/// checks the lowest guard_bytes every cycle (ControllerConfig::stack): a
/// stack that grew into them is kInternalCheck. high_water_bytes() is the
/// deepest use below the painting point. The same header name in port/linux
/// paints a budget of a thread's stack. No heap.
#ifndef CELLGUARD_PORT_STACK_HPP
#define CELLGUARD_PORT_STACK_HPP

#include <cstddef>

#include "cellguard/base/result.hpp"
#include "cellguard/base/stack_paint.hpp"

namespace cellguard::baremetal {

/// The default guard band at the bottom of the stack.
constexpr std::size_t kDefaultStackGuardBytes = 1024U;
/// Bytes below start()'s frame that are left unpainted.
constexpr std::size_t kStackPaintMarginBytes = 256U;

/// See the file comment. Not copyable: the controller holds its address.
class StackMonitor {
public:
    StackMonitor() noexcept = default;
    StackMonitor(const StackMonitor&) = delete;
    StackMonitor& operator=(const StackMonitor&) = delete;
    StackMonitor(StackMonitor&&) = delete;
    StackMonitor& operator=(StackMonitor&&) = delete;
    ~StackMonitor() = default;

    /// Paints the stack below this call's frame, the lowest @p guard_bytes
    /// (> 0, a multiple of 4) the guard band. kInvalidArgument for a guard
    /// out of range, kStorageTooSmall when the unused stack is not larger
    /// than the guard (then nothing is painted and the check stays off).
    [[nodiscard]] Status start(std::size_t guard_bytes = kDefaultStackGuardBytes) noexcept;

    /// The painting the controller checks (no region before a good start()).
    [[nodiscard]] const StackPaint& paint() const noexcept { return paint_; }
    /// The deepest use of the painted stack so far, bytes (a scan; for summaries).
    [[nodiscard]] std::size_t high_water_bytes() const noexcept { return paint_.high_water_bytes(); }

private:
    StackPaint paint_{};
};

}  // namespace cellguard::baremetal

#endif  // CELLGUARD_PORT_STACK_HPP
