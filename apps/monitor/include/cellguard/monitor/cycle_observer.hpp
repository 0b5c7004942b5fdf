// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file cycle_observer.hpp
/// What watches the monitor's cycles from outside the safety function: the
/// journal's event log and the service notification (daemon_observers.hpp),
/// the stop snapshot (snapshot.hpp). MonitorLoop calls its one observer after
/// each complete cycle (the controller ran and published its CAN frames),
/// on the cycle's thread: an observer must not block, must not allocate and
/// must return quickly; what takes time goes to a thread of its own.
/// ObserverList hands one cycle to several observers.
///
/// CanFrameTap sees every CAN frame the monitor's CAN port sent or took
/// from its receive queue (can_port.hpp), on the thread that sent it.
#ifndef CELLGUARD_MONITOR_CYCLE_OBSERVER_HPP
#define CELLGUARD_MONITOR_CYCLE_OBSERVER_HPP

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/can/can_frame.hpp"
#include "cellguard/safety/cycle_output.hpp"

namespace cellguard::monitor {

/// One complete cycle as an observer sees it.
struct CycleView {
    int k = 0;                            ///< the cycle's index, from 0
    const CycleReport* report = nullptr;  ///< what the cycle produced (never nullptr in a call)
    std::uint64_t cycle_us = 0U;          ///< the controller's time for this cycle, microseconds
    std::uint64_t now_us = 0U;            ///< CLOCK_MONOTONIC when the observer is called, microseconds
};

/// See the file comment.
class CycleObserver {
public:
    /// Called after each complete cycle; see the file comment.
    virtual void after_cycle(const CycleView& cycle) noexcept = 0;

protected:
    CycleObserver() = default;
    ~CycleObserver() = default;
    CycleObserver(const CycleObserver&) = default;
    CycleObserver& operator=(const CycleObserver&) = default;
    CycleObserver(CycleObserver&&) = default;
    CycleObserver& operator=(CycleObserver&&) = default;
};

/// Whether a tapped frame was sent or received.
enum class TapDirection : std::uint8_t {
    kSent = 0,      ///< sent by the monitor (or the simulated PLC through its port)
    kReceived = 1,  ///< taken from the receive queue (the PLC's frames on an interface)
};

/// See the file comment.
class CanFrameTap {
public:
    /// Called for each frame; must not block or allocate.
    virtual void on_frame(const CanFrame& frame, TapDirection direction) noexcept = 0;

protected:
    CanFrameTap() = default;
    ~CanFrameTap() = default;
    CanFrameTap(const CanFrameTap&) = default;
    CanFrameTap& operator=(const CanFrameTap&) = default;
    CanFrameTap(CanFrameTap&&) = default;
    CanFrameTap& operator=(CanFrameTap&&) = default;
};

/// Most observers an ObserverList holds.
constexpr std::size_t kMaxObservers = 6U;  // watchdog feed, event log, service status, snapshots, and room

/// Several observers behind one, called in the order added.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): never deleted through the base
class ObserverList final : public CycleObserver {
public:
    /// Adds @p observer (nullptr is ignored); false when the list is full.
    bool add(CycleObserver* observer) noexcept {
        if (observer == nullptr) {
            return true;
        }
        if (count_ == observers_.size()) {
            return false;
        }
        observers_[count_++] = observer;
        return true;
    }
    /// Observers held.
    [[nodiscard]] std::size_t size() const noexcept { return count_; }
    /// Calls every observer with @p cycle.
    void after_cycle(const CycleView& cycle) noexcept override {
        for (std::size_t i = 0U; i < count_; ++i) {
            observers_[i]->after_cycle(cycle);
        }
    }

private:
    std::array<CycleObserver*, kMaxObservers> observers_{};
    std::size_t count_ = 0U;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_CYCLE_OBSERVER_HPP
