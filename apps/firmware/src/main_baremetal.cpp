// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The Cortex-M7 image for qemu-system-arm -M mps2-an500: the canned runs
// (scenario.hpp, then robot_scenario.hpp, then the first run fused by
// footprint) with the SysTick clock and the semihosting CAN backend.
#include <cstdint>

#include "cellguard/base/crc32.hpp"
#include "cellguard/firmware/robot_scenario.hpp"
#include "cellguard/firmware/scenario.hpp"
#include "cellguard/port/can.hpp"
#include "cellguard/port/clock.hpp"
#include "cellguard/port/semihosting.hpp"

extern "C" {
// NOLINTNEXTLINE(bugprone-reserved-identifier,cert-dcl37-c,cert-dcl51-cpp,cppcoreguidelines-avoid-non-const-global-variables): defined by the linker script
extern std::uint32_t __stack_bottom;
}

namespace {

constexpr std::uint32_t kStackPaint = 0x5AFE57ACU;

/// Fills the unused stack below @p in_use (an address in the current frame) with kStackPaint.
void paint_stack(const volatile std::uint32_t* in_use) noexcept {
    // cppcheck-suppress comparePointers ; the stack region from the linker script
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): linker-defined region
    for (volatile std::uint32_t* p = &__stack_bottom; p + 64 < in_use; ++p) {
        *p = kStackPaint;
    }
}

/// Bytes of stack below @p in_use that were written since paint_stack.
std::uint32_t stack_used_below(const volatile std::uint32_t* in_use) noexcept {
    const volatile std::uint32_t* p = &__stack_bottom;
    // cppcheck-suppress comparePointers ; the stack region from the linker script
    while (p < in_use && *p == kStackPaint) {
        ++p;  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic): linker-defined region
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): address difference
    return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(in_use) -
                                      // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): address difference
                                      reinterpret_cast<std::uintptr_t>(p));
}

/// The MPS2 FPGA images run the processor at 25 MHz.
constexpr std::uint32_t kCpuHz = 25000000U;

class SemihostingText final : public cellguard::firmware::TextSink {
public:
    void write(const char* text) noexcept override { cellguard::baremetal::semihosting_write(text); }
};

/// Writes @p label and @p us in decimal.
void write_us(cellguard::firmware::TextSink& text, const char* label, std::uint64_t us) noexcept {
    char digits[21];
    cellguard::firmware::format_decimal(us, digits);
    text.write(label);
    text.write(digits);
}

/// One line of a run's cycle timing: its whole time (set-up and cycles), the
/// longest and the mean cycle and the longest fusion stage.
void write_run_timing(cellguard::firmware::TextSink& text, const char* run, std::uint64_t run_us,
                      const cellguard::firmware::ScenarioSummary& s) noexcept {
    write_us(text, run, run_us);
    write_us(text, " cycle max ", s.cycle_us_max);
    write_us(text, " mean ", s.cycles == 0U ? 0U : s.cycle_us_sum / s.cycles);
    write_us(text, " fusion max ", s.fuse_us_max);
    text.write("\n");
}

}  // namespace

extern "C" int cellguard_firmware_main() noexcept {
    volatile std::uint32_t frame_marker = 0U;  // this frame's address: the stack in use so far
    paint_stack(&frame_marker);
    SemihostingText text;
    text.write("cellguard firmware: mps2-an500 Cortex-M7, canned run\n");
    if (!cellguard::crc32_table_self_test()) {
        text.write("error: CRC-32 table in flash is corrupt\n");
        return 1;
    }
    cellguard::baremetal::SysTickClock clock(kCpuHz);
    clock.start();
    cellguard::baremetal::SemihostingCanSender can;
    const std::uint64_t start = clock.now_us();
    const cellguard::firmware::ScenarioSummary s = cellguard::firmware::run_scenario(clock, can, text);
    const std::uint64_t ray_end = clock.now_us();
    const cellguard::firmware::ScenarioSummary r = cellguard::firmware::run_robot_scenario(can, text);
    const std::uint64_t footprint_start = clock.now_us();
    const cellguard::firmware::ScenarioSummary f = cellguard::firmware::run_footprint_scenario(clock, can, text);
    const std::uint64_t end = clock.now_us();
    text.write("timing (SysTick, us; under qemu: see README):\n");
    write_run_timing(text, "zones-only run ", ray_end - start, s);
    write_run_timing(text, "footprint run ", end - footprint_start, f);
    const std::uint64_t elapsed = end - start;
    char us[21];
    cellguard::firmware::format_decimal(elapsed, us);
    text.write("run time (SysTick, us): ");
    text.write(us);
    char stack[21];
    cellguard::firmware::format_decimal(stack_used_below(&frame_marker), stack);
    text.write("\nstack used below main's frame (bytes): ");
    text.write(stack);
    text.write("\n");
    return s.setup_ok && s.cycles == cellguard::firmware::kScenarioCycles && r.setup_ok &&
                   r.cycles == cellguard::firmware::kRobotScenarioCycles && f.setup_ok &&
                   f.cycles == cellguard::firmware::kScenarioCycles
               ? 0
               : 1;
}
