// cellguard-firmware-digest: the firmware's canned run (scenario.hpp) on a
// Linux host (x86-64 natively, aarch64 under qemu-user): prints the same
// lines and digest as the Cortex-M7 image. With an argument 0x........ it
// exits 1 unless the digest equals it.
#include <cstdio>
#include <cstdlib>

#include "cellguard/firmware/scenario.hpp"

namespace {

/// A deterministic clock: one microsecond per reading.
class CountingClock final : public cellguard::MonotonicClock {
public:
    std::uint64_t now_us() noexcept override { return t_ += 1U; }

private:
    std::uint64_t t_ = 1000000U;
};

class StdoutText final : public cellguard::firmware::TextSink {
public:
    void write(const char* text) noexcept override { std::fputs(text, stdout); }
};

/// Prints frames like the board's semihosting CAN backend.
class PrintingCan final : public cellguard::CanSender {
public:
    bool send(const cellguard::CanFrame& frame) noexcept override {
        std::printf("can 0x%03x [%u]", static_cast<unsigned>(frame.id), static_cast<unsigned>(frame.dlc));
        for (unsigned i = 0U; i < frame.dlc && i < 8U; ++i) std::printf(" %02x", static_cast<unsigned>(frame.data[i]));
        std::printf("\n");
        return true;
    }
};

}  // namespace

int main(int argc, char** argv) {
    CountingClock clock;
    StdoutText text;
    PrintingCan can;
    const cellguard::firmware::ScenarioSummary s = cellguard::firmware::run_scenario(clock, can, text);
    if (!s.setup_ok || s.cycles != cellguard::firmware::kScenarioCycles) return 1;
    if (argc > 1) {
        const unsigned long expected = std::strtoul(argv[1], nullptr, 16);
        if (expected != s.digest) {
            std::printf("digest 0x%08x differs from the expected %s\n", static_cast<unsigned>(s.digest), argv[1]);
            return 1;
        }
        std::printf("digest matches the expected %s\n", argv[1]);
    }
    return 0;
}
