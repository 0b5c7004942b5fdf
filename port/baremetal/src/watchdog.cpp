// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The CMSDK APB watchdog of the MPS2 (watchdog.hpp).
#include "cellguard/port/watchdog.hpp"

#include <cstdint>

namespace cellguard::baremetal {
namespace {

constexpr std::uintptr_t kLoad = 0x000U;     // WDOGLOAD
constexpr std::uintptr_t kValue = 0x004U;    // WDOGVALUE (read only)
constexpr std::uintptr_t kControl = 0x008U;  // WDOGCONTROL: bit 0 INTEN (counter and interrupt), bit 1 RESEN
constexpr std::uintptr_t kIntClr = 0x00CU;   // WDOGINTCLR (write only): clears the interrupt, reloads
constexpr std::uintptr_t kRis = 0x010U;      // WDOGRIS: raw interrupt status
constexpr std::uintptr_t kLock = 0xC00U;     // WDOGLOCK: 0x1ACCE551 unlocks, anything else locks
constexpr std::uint32_t kUnlock = 0x1ACCE551U;
constexpr std::uint32_t kIntEn = 1U;
constexpr std::uint32_t kResEn = 2U;

volatile std::uint32_t& reg(std::uintptr_t offset) noexcept {
    // NOLINTNEXTLINE(performance-no-int-to-ptr,cppcoreguidelines-pro-type-reinterpret-cast): a memory-mapped register
    return *reinterpret_cast<volatile std::uint32_t*>(kCmsdkWatchdogBase + offset);
}

}  // namespace

void Watchdog::start(std::uint32_t load_ticks) noexcept {
    reg(kLock) = kUnlock;
    reg(kLoad) = load_ticks == 0U ? 1U : load_ticks;
    reg(kIntClr) = 1U;
    reg(kControl) = kIntEn | kResEn;
    reg(kLock) = 0U;
}

void Watchdog::feed() noexcept {
    reg(kLock) = kUnlock;
    reg(kIntClr) = 1U;
    reg(kLock) = 0U;
}

void Watchdog::stop() noexcept {
    reg(kLock) = kUnlock;
    reg(kControl) = 0U;
    reg(kLock) = 0U;
}

std::uint32_t Watchdog::value() noexcept { return reg(kValue); }

bool Watchdog::interrupt_pending() noexcept { return (reg(kRis) & 1U) != 0U; }

}  // namespace cellguard::baremetal
