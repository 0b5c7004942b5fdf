// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The frame signal (frame_signal.hpp): a futex word.
#include "cellguard/port/frame_signal.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <climits>
#include <ctime>

#include "cellguard/port/clock.hpp"

namespace cellguard::linux_port {

std::uint32_t FrameSignal::value() const noexcept { return __atomic_load_n(&count_, __ATOMIC_ACQUIRE); }

void FrameSignal::notify() noexcept {
    static_cast<void>(__atomic_add_fetch(&count_, 1U, __ATOMIC_RELEASE));
    // Wakes the one waiter, if it sleeps (a private futex: this process only).
    static_cast<void>(syscall(SYS_futex, &count_, FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0));
}

bool FrameSignal::wait_after(std::uint32_t seen, std::uint64_t deadline_us) noexcept {
    for (;;) {
        if (value() != seen) {
            return true;
        }
        const std::uint64_t now = monotonic_now_us();
        if (now == 0U || now >= deadline_us) {
            return false;  // also when the clock cannot be read: never sleep without a deadline
        }
        timespec until{};
        until.tv_sec = static_cast<time_t>(deadline_us / 1000000U);
        until.tv_nsec = static_cast<long>((deadline_us % 1000000U) * 1000U);
        // FUTEX_WAIT_BITSET takes an absolute CLOCK_MONOTONIC time; it returns at once when the
        // word is no longer seen (EAGAIN), at the deadline (ETIMEDOUT) or on a wake or signal.
        static_cast<void>(
            syscall(SYS_futex, &count_, FUTEX_WAIT_BITSET_PRIVATE, seen, &until, nullptr, FUTEX_BITSET_MATCH_ANY));
    }
}

}  // namespace cellguard::linux_port
