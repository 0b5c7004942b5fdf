// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/port/stack.hpp"

#include <cstdint>

extern "C" {
// NOLINTNEXTLINE(bugprone-reserved-identifier,cert-dcl37-c,cert-dcl51-cpp,cppcoreguidelines-avoid-non-const-global-variables): defined by the linker script
extern std::uint32_t __stack_bottom;
}

namespace cellguard::baremetal {

// noinline: this frame is the top the painting is measured from.
__attribute__((noinline)) Status StackMonitor::start(std::size_t guard_bytes) noexcept {
    constexpr std::size_t kWord = sizeof(std::uint32_t);
    if (guard_bytes == 0U || guard_bytes % kWord != 0U) {
        return ErrorCode::kInvalidArgument;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): addresses to compare
    const auto bottom = reinterpret_cast<std::uintptr_t>(&__stack_bottom);
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the frame's address
    const auto frame = reinterpret_cast<std::uintptr_t>(__builtin_frame_address(0));
    const std::uintptr_t top = (frame - kStackPaintMarginBytes) & ~static_cast<std::uintptr_t>(kWord - 1U);
    if (top <= bottom || top - bottom <= guard_bytes) {
        return ErrorCode::kStorageTooSmall;
    }
    paint_ = StackPaint(Span<std::uint32_t>(&__stack_bottom, (top - bottom) / kWord), guard_bytes / kWord);
    paint_.paint();
    return ErrorCode::kOk;
}

}  // namespace cellguard::baremetal
