// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file clock.hpp
/// The MonotonicClock of a Cortex-M: SysTick on the processor clock,
/// interrupting every millisecond; now_us() adds the microseconds elapsed in
/// the current millisecond from the counter. Monotonic by construction: a
/// reading is never smaller than the previous one (the short window between
/// the counter's reload and the tick interrupt cannot make time go back).
#ifndef CELLGUARD_PORT_CLOCK_HPP
#define CELLGUARD_PORT_CLOCK_HPP

#include <cstdint>

#include "cellguard/safety/clock.hpp"

namespace cellguard::baremetal {

/// SysTick as the controller's clock. One instance per core.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class SysTickClock final : public MonotonicClock {
public:
    /// A clock for a processor running at @p cpu_hz (>= 1 MHz, a multiple of 1 kHz: contract).
    explicit SysTickClock(std::uint32_t cpu_hz) noexcept;

    /// Programs SysTick (reload for 1 ms, processor clock, interrupt on) and starts it.
    void start() noexcept;

    /// Microseconds since start().
    std::uint64_t now_us() noexcept override;

private:
    std::uint32_t reload_;
    std::uint64_t last_us_ = 0U;
};

}  // namespace cellguard::baremetal

/// The SysTick exception handler (in the vector table): counts milliseconds.
extern "C" void SysTick_Handler() noexcept;

#endif  // CELLGUARD_PORT_CLOCK_HPP
