// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file frame_signal.hpp
/// A count that the threads which publish camera frames raise and one thread
/// sleeps on (a Linux futex): the monitor's paced loop starts a cycle when
/// every live camera has a new frame instead of at a fixed phase of the
/// period, so a frame waits for the cycle only as long as the other cameras'
/// frames take to arrive (monitor_loop.hpp, run_cycles).
///
/// notify() is an atomic increment and a futex wake: it never blocks and never
/// allocates, so a camera's receive thread may call it after each publish.
/// wait_after() sleeps until the count is no longer a value the caller read,
/// or until a CLOCK_MONOTONIC deadline: a notify() between the caller's read
/// and its wait is never lost (the futex compares the count before it sleeps).
/// One thread waits; any number notify.
#ifndef CELLGUARD_PORT_FRAME_SIGNAL_HPP
#define CELLGUARD_PORT_FRAME_SIGNAL_HPP

#include <cstdint>

namespace cellguard::linux_port {

/// See the file comment.
class FrameSignal {
public:
    FrameSignal() = default;
    FrameSignal(const FrameSignal&) = delete;
    FrameSignal& operator=(const FrameSignal&) = delete;
    FrameSignal(FrameSignal&&) = delete;
    FrameSignal& operator=(FrameSignal&&) = delete;
    ~FrameSignal() = default;

    /// The count now: read it before looking for new frames, then pass it to wait_after().
    [[nodiscard]] std::uint32_t value() const noexcept;
    /// Raises the count (wrapping) and wakes the waiter. Any thread; never blocks.
    void notify() noexcept;
    /// Sleeps until the count differs from @p seen (true, also at once when it
    /// already does) or CLOCK_MONOTONIC reaches @p deadline_us (false; at once
    /// when it already has). A signal that interrupts the sleep ends it early:
    /// the caller looks again.
    [[nodiscard]] bool wait_after(std::uint32_t seen, std::uint64_t deadline_us) noexcept;

private:
    /// The futex word, accessed with the compiler's atomic builtins only (a
    /// plain 32-bit word, as the futex call takes it).
    alignas(4) std::uint32_t count_ = 0U;
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_FRAME_SIGNAL_HPP
