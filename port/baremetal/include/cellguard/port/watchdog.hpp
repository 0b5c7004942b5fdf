// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file watchdog.hpp
/// The Cortex-M board's watchdog: the Arm CMSDK APB watchdog (Cortex-M System
/// Design Kit, DDI0479C) of the MPS2 AN500 image (and qemu-system-arm -M
/// mps2-an500) at 0x40008000, clocked by the 25 MHz system clock. Its 32-bit
/// counter counts down from WDOGLOAD; at zero it raises its interrupt (on
/// the MPS2: the NMI) and reloads; at zero again with the interrupt still
/// pending it asserts its reset output (RESEN) and the board resets. feed()
/// clears the interrupt, which also reloads the counter. Registers are
/// locked (WDOGLOCK) except inside start(), feed() and stop().
///
/// So after start(load), a firmware that stops feeding gets the NMI after
/// load ticks and the reset after 2 x load ticks. The same class name as
/// port/linux's watchdog (the Linux watchdog device); the calls differ with
/// the platform.
#ifndef CELLGUARD_PORT_WATCHDOG_HPP
#define CELLGUARD_PORT_WATCHDOG_HPP

#include <cstdint>

namespace cellguard::baremetal {

/// Base address of the CMSDK APB watchdog on the MPS2 (AN500).
constexpr std::uintptr_t kCmsdkWatchdogBase = 0x40008000U;

/// See the file comment. Stateless: every call reads or writes the registers.
class Watchdog {
public:
    /// Loads @p load_ticks (>= 1; the clock's ticks to the interrupt, the
    /// reset follows after as many again) and enables the counter, its
    /// interrupt and its reset; locks the registers.
    static void start(std::uint32_t load_ticks) noexcept;
    /// Clears the interrupt and so reloads the counter (the feed).
    static void feed() noexcept;
    /// Disables the counter, its interrupt and its reset (the orderly end).
    static void stop() noexcept;
    /// The counter now (WDOGVALUE).
    [[nodiscard]] static std::uint32_t value() noexcept;
    /// The raw interrupt status (WDOGRIS): the first expiry happened.
    [[nodiscard]] static bool interrupt_pending() noexcept;
};

}  // namespace cellguard::baremetal

#endif  // CELLGUARD_PORT_WATCHDOG_HPP
