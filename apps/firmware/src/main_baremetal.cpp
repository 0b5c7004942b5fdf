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
#include "cellguard/port/stack.hpp"

namespace {

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
    // The stack below this frame painted; every controller checks its guard band each cycle.
    cellguard::baremetal::StackMonitor stack;  // in this frame: above the painting, alive for every run
    const bool stack_painted = stack.start().ok();
    cellguard::firmware::set_stack_check(stack_painted ? &stack.paint() : nullptr);
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
    write_us(text,
             "\nstack used below main's frame (bytes, high-water mark of the painting): ", stack.high_water_bytes());
    write_us(text, " of ", stack.paint().region_bytes());
    text.write(stack_painted && stack.paint().guard_intact() ? ", guard band intact\n" : ", guard band NOT intact\n");
    return stack_painted && s.setup_ok && s.cycles == cellguard::firmware::kScenarioCycles && r.setup_ok &&
                   r.cycles == cellguard::firmware::kRobotScenarioCycles && f.setup_ok &&
                   f.cycles == cellguard::firmware::kScenarioCycles
               ? 0
               : 1;
}
