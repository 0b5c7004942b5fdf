// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Start-up of a Cortex-M7 image: the vector table, the reset handler (FPU
// on, .data copied from flash, .bss zeroed, constructors run) and the
// default exception handler. Symbols come from the linker script
// (apps/firmware/mps2_an500.ld); the application's entry is
// cellguard_firmware_main(), its return value the semihosting exit status.
#include <cstdint>

#include "cellguard/port/clock.hpp"
#include "cellguard/port/semihosting.hpp"

extern "C" {
// NOLINTBEGIN(bugprone-reserved-identifier,cert-dcl37-c,cert-dcl51-cpp,readability-identifier-naming,cppcoreguidelines-avoid-non-const-global-variables): symbols defined by the linker script
extern std::uint32_t __stack_top;
extern std::uint32_t __data_start;
extern std::uint32_t __data_end;
extern const std::uint32_t __data_load;
extern std::uint32_t __bss_start;
extern std::uint32_t __bss_end;
extern void (*const __init_array_start[])();
extern void (*const __init_array_end[])();
// NOLINTEND(bugprone-reserved-identifier,cert-dcl37-c,cert-dcl51-cpp,readability-identifier-naming,cppcoreguidelines-avoid-non-const-global-variables)

/// The application: returns 0 on success.
int cellguard_firmware_main() noexcept;
[[noreturn]] void Reset_Handler() noexcept;
void Default_Handler() noexcept;
}

namespace {

using Handler = void (*)() noexcept;

/// The ARMv7-M vector table: initial stack pointer and the 15 system exceptions.
struct VectorTable {
    const void* initial_sp;
    Handler reset;
    Handler system[13];  // NMI .. PendSV (exceptions 2..14)
    Handler systick;
};

}  // namespace

extern "C" __attribute__((section(".isr_vector"), used)) const VectorTable g_vector_table = {
    &__stack_top,
    Reset_Handler,
    {Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler},
    SysTick_Handler,
};

extern "C" void Default_Handler() noexcept {
    cellguard::baremetal::semihosting_write("fault: unexpected exception\n");
    cellguard::baremetal::semihosting_exit(false);
}

extern "C" void Reset_Handler() noexcept {
    // CP10 and CP11 full access: the FPU, before any floating-point instruction.
    // NOLINTNEXTLINE(performance-no-int-to-ptr,cppcoreguidelines-pro-type-reinterpret-cast): a memory-mapped register
    volatile std::uint32_t& cpacr = *reinterpret_cast<volatile std::uint32_t*>(0xE000ED88U);
    cpacr = cpacr | (0xFU << 20U);
    // NOLINTNEXTLINE(hicpp-no-assembler): barriers so the FPU is on before the next instruction
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    const std::uint32_t* src = &__data_load;
    // cppcheck-suppress comparePointers ; the linker's region bounds: one region, not two objects
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): linker-defined region
    for (std::uint32_t* dst = &__data_start; dst < &__data_end; ++dst, ++src) {
        *dst = *src;
    }
    // cppcheck-suppress comparePointers ; the linker's region bounds: one region, not two objects
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): linker-defined region
    for (std::uint32_t* dst = &__bss_start; dst < &__bss_end; ++dst) {
        *dst = 0U;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): linker-defined table
    for (void (*const* f)() = __init_array_start; f < __init_array_end; ++f) {
        (*f)();
    }
    cellguard::baremetal::semihosting_exit(cellguard_firmware_main() == 0);
}
