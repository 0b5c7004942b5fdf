// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// ARM semihosting calls (semihosting.hpp).
#include "cellguard/port/semihosting.hpp"

#include <cstdint>

namespace cellguard::baremetal {
namespace {

constexpr std::uint32_t kSysWrite0 = 0x04U;
constexpr std::uint32_t kSysExit = 0x18U;
constexpr std::uint32_t kApplicationExit = 0x20026U;      // ADP_Stopped_ApplicationExit
constexpr std::uint32_t kRunTimeErrorUnknown = 0x20023U;  // ADP_Stopped_RunTimeErrorUnknown

std::uint32_t semihosting_call(std::uint32_t operation, const void* argument) noexcept {
    // NOLINTBEGIN(hicpp-no-assembler): the semihosting trap is an instruction with arguments in r0 and r1
    register std::uint32_t r0 __asm__("r0") = operation;
    register const void* r1 __asm__("r1") = argument;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    // NOLINTEND(hicpp-no-assembler)
    return r0;
}

}  // namespace

void semihosting_write(const char* text) noexcept { static_cast<void>(semihosting_call(kSysWrite0, text)); }

void semihosting_exit(bool success) noexcept {
    // On 32-bit ARM the parameter is the reason itself, not a block.
    const std::uintptr_t reason = success ? kApplicationExit : kRunTimeErrorUnknown;
    // NOLINTNEXTLINE(performance-no-int-to-ptr): SYS_EXIT takes the reason in r1 on AArch32
    static_cast<void>(semihosting_call(kSysExit, reinterpret_cast<const void*>(reason)));
    for (;;) {
        __asm__ volatile("wfi");  // NOLINT(hicpp-no-assembler): wait for interrupt, nothing else to do
    }
}

}  // namespace cellguard::baremetal
