// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/port/stack.hpp"

#include <pthread.h>

#include <cstdint>

namespace cellguard::linux_port {

namespace {

/// The lowest usable address of the calling thread's stack (0: unknown).
std::uintptr_t stack_floor() noexcept {
    pthread_attr_t attr;
    if (pthread_getattr_np(pthread_self(), &attr) != 0) {
        return 0U;
    }
    void* base = nullptr;
    std::size_t size = 0U;
    std::size_t guard = 0U;
    const bool ok = pthread_attr_getstack(&attr, &base, &size) == 0 && pthread_attr_getguardsize(&attr, &guard) == 0;
    static_cast<void>(pthread_attr_destroy(&attr));
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): an address to compare
    return ok ? reinterpret_cast<std::uintptr_t>(base) + guard : 0U;
}

}  // namespace

// noinline: this frame is the top the budget is measured from.
__attribute__((noinline)) Status StackMonitor::start(std::size_t budget_bytes, std::size_t guard_bytes) noexcept {
    constexpr std::size_t kWord = sizeof(std::uint32_t);
    if (guard_bytes == 0U || guard_bytes % kWord != 0U || budget_bytes % kWord != 0U || budget_bytes <= guard_bytes) {
        return ErrorCode::kInvalidArgument;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the frame's address
    const auto frame = reinterpret_cast<std::uintptr_t>(__builtin_frame_address(0));
    const std::uintptr_t top = (frame - kStackPaintMarginBytes) & ~static_cast<std::uintptr_t>(kWord - 1U);
    const std::uintptr_t floor = stack_floor();
    if (floor == 0U || top < floor || top - floor < budget_bytes) {
        return ErrorCode::kStorageTooSmall;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast,performance-no-int-to-ptr): the stack below this frame
    auto* const low = reinterpret_cast<std::uint32_t*>(top - budget_bytes);
    paint_ = StackPaint(Span<std::uint32_t>(low, budget_bytes / kWord), guard_bytes / kWord);
    paint_.paint();
    return ErrorCode::kOk;
}

}  // namespace cellguard::linux_port
