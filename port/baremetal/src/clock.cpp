// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// SysTick as the monotonic clock (systick_clock.hpp).
#include "cellguard/port/clock.hpp"

#include "cellguard/base/contract.hpp"

namespace {

// Milliseconds counted by SysTick_Handler (64 bits: no wrap in practice;
// read twice around the counter to detect a tick in between).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): shared with the tick interrupt
volatile std::uint64_t g_milliseconds = 0U;

constexpr std::uintptr_t kSystCsr = 0xE000E010U;  // control and status
constexpr std::uintptr_t kSystRvr = 0xE000E014U;  // reload value
constexpr std::uintptr_t kSystCvr = 0xE000E018U;  // current value

volatile std::uint32_t& reg(std::uintptr_t address) noexcept {
    // NOLINTNEXTLINE(performance-no-int-to-ptr,cppcoreguidelines-pro-type-reinterpret-cast): a memory-mapped register
    return *reinterpret_cast<volatile std::uint32_t*>(address);
}

}  // namespace

extern "C" void SysTick_Handler() noexcept { g_milliseconds = g_milliseconds + 1U; }

namespace cellguard::baremetal {

SysTickClock::SysTickClock(std::uint32_t cpu_hz) noexcept : reload_(cpu_hz / 1000U - 1U) {
    CG_ENFORCE(cpu_hz >= 1000000U && cpu_hz % 1000U == 0U, "SysTick needs a processor clock of whole kHz, >= 1 MHz");
}

void SysTickClock::start() noexcept {  // NOLINT(readability-make-member-function-const): programs the hardware timer
    reg(kSystCsr) = 0U;
    reg(kSystRvr) = reload_;
    reg(kSystCvr) = 0U;
    reg(kSystCsr) = 0x7U;  // ENABLE | TICKINT | CLKSOURCE = processor clock
}

std::uint64_t SysTickClock::now_us() noexcept {
    std::uint64_t ms = 0U;
    std::uint32_t counter = 0U;
    for (;;) {
        ms = g_milliseconds;
        counter = reg(kSystCvr);
        if (g_milliseconds == ms) {
            break;
        }
    }
    const auto ticks_in_ms = static_cast<std::uint64_t>(reload_ - counter);
    const std::uint64_t now = ms * 1000U + ticks_in_ms * 1000U / (static_cast<std::uint64_t>(reload_) + 1U);
    if (now > last_us_) {
        last_us_ = now;
    }
    return last_us_;
}

}  // namespace cellguard::baremetal
