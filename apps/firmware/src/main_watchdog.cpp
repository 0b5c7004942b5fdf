// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The watchdog test image for qemu-system-arm -M mps2-an500 (not the product
// image): the zones-only canned run (scenario.hpp) with the board's CMSDK
// watchdog (port/baremetal watchdog.hpp) fed after each complete, checked
// cycle, and a hang injected in cycle kHangCycle of the first boot: the CAN
// driver's send of that cycle's first frame never returns (H-TIM-2's "a
// hang in a driver"). The watchdog's first expiry is the NMI (an early
// warning, printed), its second resets the board. A record in .noinit RAM
// (not zeroed at start-up) tells the second boot why it runs; it then checks
// that its first safety frame is a fresh start (E2E counter 0: the PLC's
// receiver, in its safe state after the silence, sees a new sequence and
// holds the stop through its recovery) and that the frame requests the
// stop itself, then exits through semihosting. The image configures a
// restart delay (kRestartDelayUs; the canned run's is 0), so every start,
// the one after a watchdog's reset included, begins in the safe state: the
// controller's start-up stop holds until the protective zones have been
// CLEAR that long (SR-LOGIC-001), whatever the PLC's receiver does.
//
// A cycle is complete and checked when its diagnostics frame (the cycle's
// last frame) has been sent and decodes, and it names no non-recoverable
// fault (kPriorCheckFailed, kInternalCheck, kClockFault), as the monitor's
// feed decision (apps/monitor watchdog_feed.hpp) has it.
#include <cstdint>

#include "cellguard/can/fault_code.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/firmware/scenario.hpp"
#include "cellguard/port/can.hpp"
#include "cellguard/port/clock.hpp"
#include "cellguard/port/semihosting.hpp"
#include "cellguard/port/watchdog.hpp"

namespace {

using cellguard::baremetal::semihosting_exit;
using cellguard::baremetal::semihosting_write;
using cellguard::baremetal::Watchdog;

constexpr std::uint32_t kCpuHz = 25000000U;
/// Ticks to the NMI (and again to the reset): 10 s of the 25 MHz clock, well
/// above a canned cycle under qemu (about 0.2 to 1 s on the build machines).
constexpr std::uint32_t kWatchdogTicks = 10U * kCpuHz;
/// The cycle (from 0) whose first CAN frame never returns on the first boot.
constexpr std::uint32_t kHangCycle = 3U;
constexpr std::uint32_t kArmedMagic = 0xA5D06001U;  ///< the first boot armed the watchdog and runs
/// The restart delay of this image's controller: any start requests the stop until it has passed.
constexpr std::uint64_t kRestartDelayUs = 500000U;

/// Survives the reset (the .noinit section of mps2_an500.ld).
struct ResetRecord {
    std::uint32_t magic;
    std::uint32_t cycles_fed;  ///< cycles fed before the reset
};
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): must survive a reset, in .noinit
__attribute__((section(".noinit"))) volatile ResetRecord g_record;

void write_number(const char* label, std::uint32_t n) noexcept {
    char digits[21];
    cellguard::firmware::format_decimal(n, digits);
    semihosting_write(label);
    semihosting_write(digits);
}

/// The NMI: the watchdog's first expiry. Warns and returns; the interrupt
/// stays pending, so the next expiry resets the board.
extern "C" void watchdog_test_nmi() noexcept { semihosting_write("watchdog: first expiry (NMI): the reset follows\n"); }

/// The vector table in RAM, as in flash but with watchdog_test_nmi as the NMI
/// (VTOR needs 128-byte alignment for the 16 system entries).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables,cppcoreguidelines-avoid-c-arrays,hicpp-avoid-c-arrays,modernize-avoid-c-arrays): the hardware's table
alignas(128) std::uint32_t g_ram_vectors[32];

void install_nmi_handler() noexcept {
    // NOLINTNEXTLINE(performance-no-int-to-ptr,cppcoreguidelines-pro-type-reinterpret-cast): the SCB's VTOR
    volatile std::uint32_t& vtor = *reinterpret_cast<volatile std::uint32_t*>(0xE000ED08U);
    // NOLINTNEXTLINE(performance-no-int-to-ptr,cppcoreguidelines-pro-type-reinterpret-cast): the current table
    const auto* flash = reinterpret_cast<const volatile std::uint32_t*>(vtor);
    for (std::uint32_t i = 0U; i < 16U; ++i) {
        g_ram_vectors[i] = flash[i];  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic): the table
    }
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): a handler's address in the table
    g_ram_vectors[2] = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(&watchdog_test_nmi));
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the table's address
    vtor = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(&g_ram_vectors[0]));
    // NOLINTNEXTLINE(hicpp-no-assembler): the new table is in use before the next instruction
    __asm__ volatile("dsb\n\tisb" ::: "memory");
}

/// The CAN backend between the scenario and the semihosting sender: feeds
/// the watchdog after each complete, checked cycle; hangs in cycle
/// kHangCycle on the first boot; on the second boot checks the first safety
/// frame and ends the test.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class WatchdogCan final : public cellguard::CanSender {
public:
    WatchdogCan(cellguard::CanSender& next, bool second_boot) noexcept : next_(&next), second_boot_(second_boot) {}

    bool send(const cellguard::CanFrame& frame) noexcept override {
        const cellguard::SafetyChannelConfig channel{};
        if (!second_boot_ && cycle_ == kHangCycle && frame.id == channel.safety_can_id) {
            write_number("watchdog test: cycle ", cycle_);
            semihosting_write(" hangs in the CAN driver (injected)\n");
            for (;;) {
                // NOLINTNEXTLINE(hicpp-no-assembler): the hang: wait for interrupts, forever
                __asm__ volatile("wfi");
            }
        }
        if (second_boot_ && frame.id == channel.safety_can_id && cycle_ == 0U) {
            check_first_frame_after_reset(frame, channel);
        }
        const bool sent = next_->send(frame);
        if (frame.id == channel.diagnostics_can_id) {
            end_of_cycle(frame, channel);
        }
        return sent;
    }

private:
    void end_of_cycle(const cellguard::CanFrame& frame, const cellguard::SafetyChannelConfig& channel) noexcept {
        const auto diagnostics = cellguard::decode_diagnostics_frame(frame, channel);
        constexpr std::uint32_t kStopFaults = (1U << static_cast<unsigned>(cellguard::FaultCode::kPriorCheckFailed)) |
                                              (1U << static_cast<unsigned>(cellguard::FaultCode::kInternalCheck)) |
                                              (1U << static_cast<unsigned>(cellguard::FaultCode::kClockFault));
        if (diagnostics.ok() && (diagnostics.value().message.active_faults & kStopFaults) == 0U) {
            Watchdog::feed();
            g_record.cycles_fed = g_record.cycles_fed + 1U;
        }
        ++cycle_;
    }

    static void check_first_frame_after_reset(const cellguard::CanFrame& frame,
                                              const cellguard::SafetyChannelConfig& channel) noexcept {
        const auto safety = cellguard::decode_safety_frame(frame, channel);
        // A fresh start: the sender's E2E counter begins again at 0, so the PLC's
        // receiver, after the silence of the hang (its SCT: the safe state), sees
        // a new sequence and holds the stop through its recovery.
        const bool fresh = safety.ok() && safety.value().counter == 0U;
        // The safe state after the reset: the controller's own start-up stop (the restart delay).
        const bool stop = safety.ok() && safety.value().message.protective_stop;
        semihosting_write(fresh ? "watchdog test: the first safety frame after the reset is a fresh start (counter 0)"
                                : "watchdog test: the first safety frame after the reset is NOT a fresh start");
        semihosting_write(stop ? ", stop requested\n" : ", stop NOT requested\n");
        Watchdog::stop();
        g_record.magic = 0U;
        const bool passed = fresh && stop;
        semihosting_write(passed ? "watchdog test: passed\n" : "watchdog test: FAILED\n");
        semihosting_exit(passed);
    }

    cellguard::CanSender* next_;
    bool second_boot_;
    std::uint32_t cycle_ = 0U;
};

// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class SemihostingText final : public cellguard::firmware::TextSink {
public:
    void write(const char* text) noexcept override { semihosting_write(text); }
};

}  // namespace

extern "C" int cellguard_firmware_main() noexcept {
    const bool second_boot = g_record.magic == kArmedMagic;
    install_nmi_handler();
    if (second_boot) {
        write_number("watchdog test: second boot, after a reset by the watchdog; cycles fed before it: ",
                     g_record.cycles_fed);
        semihosting_write("\n");
    } else {
        semihosting_write("watchdog test: first boot, watchdog armed (NMI after 10 s, reset after 20 s)\n");
        g_record.cycles_fed = 0U;
        g_record.magic = kArmedMagic;
    }
    cellguard::firmware::set_restart_delay(kRestartDelayUs);
    Watchdog::start(kWatchdogTicks);
    cellguard::baremetal::SysTickClock clock(kCpuHz);
    clock.start();
    cellguard::baremetal::SemihostingCanSender semihosting_can;
    WatchdogCan can(semihosting_can, second_boot);
    SemihostingText text;
    static_cast<void>(cellguard::firmware::run_scenario(clock, can, text));
    // Not reached on either boot: the first hangs, the second exits at its first frame.
    Watchdog::stop();
    semihosting_write("watchdog test: FAILED: the run ended without the hang or the check\n");
    return 1;
}
