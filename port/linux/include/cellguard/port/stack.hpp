// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file stack.hpp
/// The Linux port's stack painting (hazard H-MEM-3): the cycle thread paints
/// a bounded budget of its own stack below the frame that starts it and hands
/// the painting (cellguard/base/stack_paint.hpp) to the controller, which
/// checks its guard band every cycle (ControllerConfig::stack): a cycle whose
/// stack reached within guard_bytes of the budget's end is kInternalCheck.
/// The same header name in port/baremetal paints from the linker's symbols.
///
/// StackMonitor::start() asks the thread's stack bounds
/// (pthread_getattr_np) and refuses a budget the stack cannot hold, leaving
/// kStackPaintMarginBytes unpainted below its own frame (for the painting
/// loop's frame and the x86-64 red zone). Only the thread that called
/// start() is covered; the worker pool's threads are not. Signal handlers
/// that run on this stack count as its use. No heap; allocates nothing.
#ifndef CELLGUARD_PORT_STACK_HPP
#define CELLGUARD_PORT_STACK_HPP

#include <cstddef>

#include "cellguard/base/result.hpp"
#include "cellguard/base/stack_paint.hpp"

namespace cellguard::linux_port {

/// The default stack budget of the cycle below the frame that paints it.
constexpr std::size_t kDefaultStackBudgetBytes = std::size_t{512U} * 1024U;
/// The default guard band at the budget's end.
constexpr std::size_t kDefaultStackGuardBytes = 4096U;
/// Bytes below start()'s frame that are left unpainted.
constexpr std::size_t kStackPaintMarginBytes = 1024U;

/// See the file comment. Not copyable: the controller holds its address.
class StackMonitor {
public:
    StackMonitor() noexcept = default;
    StackMonitor(const StackMonitor&) = delete;
    StackMonitor& operator=(const StackMonitor&) = delete;
    StackMonitor(StackMonitor&&) = delete;
    StackMonitor& operator=(StackMonitor&&) = delete;
    ~StackMonitor() = default;

    /// Paints @p budget_bytes (a multiple of 4, > guard_bytes) of the
    /// calling thread's stack below this call's frame, the lowest
    /// @p guard_bytes (> 0, a multiple of 4) the guard band. kInvalidArgument
    /// for sizes out of range, kStorageTooSmall when the thread's stack does
    /// not reach that far (then nothing is painted and the check stays off).
    [[nodiscard]] Status start(std::size_t budget_bytes = kDefaultStackBudgetBytes,
                               std::size_t guard_bytes = kDefaultStackGuardBytes) noexcept;

    /// The painting the controller checks (no region before a good start()).
    [[nodiscard]] const StackPaint& paint() const noexcept { return paint_; }
    /// True once start() has painted.
    [[nodiscard]] bool started() const noexcept { return paint_.region_bytes() != 0U; }
    /// The deepest use of the budget so far, bytes (a scan; for summaries).
    [[nodiscard]] std::size_t high_water_bytes() const noexcept { return paint_.high_water_bytes(); }

private:
    StackPaint paint_{};
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_STACK_HPP
