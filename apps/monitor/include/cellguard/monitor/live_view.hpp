// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file live_view.hpp
/// The browser view's side of the cycle (issue 20; the server is
/// web_server.hpp). It is not a safety function and reads only.
///
/// LiveView is a CycleObserver: after each cycle, on the cycle's thread, it
/// copies what the page shows (cycle, zone states, faults, stop, warning,
/// separation and the robot's capsules as the controller placed them, the foreground voxels and the unseen voxels of active zones,
/// each up to a fixed cap with a "truncated" flag; the voxels only while a
/// reader asked for them in the last kLiveDemandWindowUs) into a LiveSnapshot it
/// owns and publishes that through a SnapshotChannel. It allocates nothing
/// after construction, takes no lock and never waits.
///
/// SnapshotChannel is a seqlock over one fixed LiveSnapshot, held as
/// relaxed atomic 64-bit words (no data race in the C++ memory model): the
/// one writer makes the sequence odd, stores the words, makes it even; a
/// reader copies the words and keeps the copy only when the sequence was
/// even and unchanged around it, retrying at most a given number of times
/// (the server answers 503 then). The writer never waits for readers.
#ifndef CELLGUARD_MONITOR_LIVE_VIEW_HPP
#define CELLGUARD_MONITOR_LIVE_VIEW_HPP

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard::monitor {

/// Foreground voxel indices a snapshot holds at most.
constexpr std::size_t kLiveMaxForeground = 4096U;
/// Unseen voxel indices (of active zones) a snapshot holds at most.
constexpr std::size_t kLiveMaxUnseen = 4096U;
/// The voxel scan runs only while a reader asked within this window
/// (SnapshotChannel::note_demand): with nobody watching, the view costs the
/// cycle thread a copy of a few hundred bytes, not a pass over the grid.
constexpr std::uint64_t kLiveDemandWindowUs = 2000000U;

/// One zone in a snapshot.
struct LiveZone {
    std::uint8_t state = 0U;        ///< ZoneState as a number (the controller's, before the fault override)
    std::uint8_t active = 0U;       ///< 1: evaluated this cycle (in the active monitoring case)
    std::uint32_t foreground = 0U;  ///< foreground voxels in the zone
    std::uint32_t unseen = 0U;      ///< unseen accessible voxels in the zone
    std::uint32_t robot = 0U;       ///< voxels of the zone that were the robot's
};

/// One robot capsule in a snapshot (world frame, metres).
struct LiveCapsule {
    float a[3] = {0.0F, 0.0F, 0.0F};  ///< first end
    float b[3] = {0.0F, 0.0F, 0.0F};  ///< second end
    float radius = 0.0F;              ///< radius
};

/// What the page shows of one cycle. Trivially copyable, fixed size.
struct LiveSnapshot {
    std::uint64_t valid = 0U;                           ///< 1 once a cycle was published
    std::uint64_t voxels = 0U;                          ///< 1: the voxel lists below were scanned this cycle
    std::int64_t k = -1;                                ///< the cycle's index from 0 (the k-th safety frame on CAN)
    std::uint64_t cycle = 0U;                           ///< the controller's cycle number, from 1
    std::uint64_t started_us = 0U;                      ///< the cycle's start on the controller's clock
    std::uint64_t published_us = 0U;                    ///< CLOCK_MONOTONIC when published
    std::uint64_t cycle_us = 0U;                        ///< the controller's time for the cycle
    std::uint8_t stop = 1U;                             ///< protective stop requested
    std::uint8_t warning = 0U;                          ///< warning on
    std::uint8_t reduced_speed = 0U;                    ///< reduced speed requested
    std::uint8_t separation_stop = 0U;                  ///< speed and separation monitoring requests the stop
    std::uint8_t robot = 0U;                            ///< a robot is configured
    std::uint8_t active_case = 0U;                      ///< monitoring case evaluated
    std::uint16_t distance_mm = 65535U;                 ///< separation distance (65535: nothing in range)
    std::uint16_t required_mm = 0U;                     ///< protective separation distance S_p
    std::uint32_t latched_faults = 0U;                  ///< fault bits latched
    std::uint32_t intruded_mask = 0U;                   ///< as on CAN: active zones INTRUDED
    std::uint32_t unseen_mask = 0U;                     ///< as on CAN: active zones UNSEEN
    std::uint32_t fault_zone_mask = 0U;                 ///< active zones in FAULT
    std::uint32_t active_mask = 0U;                     ///< zones evaluated
    std::uint32_t zone_count = 0U;                      ///< zones
    LiveZone zones[kMaxZones] = {};                     ///< per zone, configuration order
    std::uint32_t capsule_count = 0U;                   ///< robot capsules held (0: no robot, or no pose this cycle)
    LiveCapsule capsules[kMaxRobotCapsules] = {};       ///< the controller's placed capsules of this cycle
    std::uint32_t foreground_total = 0U;                ///< foreground voxels in the grid (all, not only those held)
    std::uint32_t foreground_count = 0U;                ///< indices held in foreground[]
    std::uint32_t unseen_total = 0U;                    ///< unseen voxels of active zones
    std::uint32_t unseen_count = 0U;                    ///< indices held in unseen[]
    std::uint32_t foreground[kLiveMaxForeground] = {};  ///< voxel indices
    std::uint32_t unseen[kLiveMaxUnseen] = {};          ///< voxel indices
};
static_assert(std::is_trivially_copyable<LiveSnapshot>::value, "the seqlock copies it as words");

/// See the file comment. One writer thread; any number of readers.
class SnapshotChannel {
public:
    /// Words of the payload.
    static constexpr std::size_t kWords = (sizeof(LiveSnapshot) + 7U) / 8U;
    /// An empty channel (valid == 0 in what readers see).
    SnapshotChannel() noexcept = default;
    /// Publishes @p s (the one writer). Never waits.
    void publish(const LiveSnapshot& s) noexcept;
    /// Copies the latest snapshot into @p out; false when every one of
    /// @p attempts (1 or more) saw a write in progress or a torn copy.
    [[nodiscard]] bool read(LiveSnapshot& out, int attempts) const noexcept;
    /// Torn or busy attempts readers saw (and retried) so far.
    [[nodiscard]] std::uint64_t retries() const noexcept { return retries_.load(std::memory_order_relaxed); }
    /// A reader says it wants the voxel lists (CLOCK_MONOTONIC @p now_us); any thread.
    void note_demand(std::uint64_t now_us) const noexcept { demand_us_.store(now_us, std::memory_order_relaxed); }
    /// The last note_demand() time (0: never).
    [[nodiscard]] std::uint64_t last_demand_us() const noexcept { return demand_us_.load(std::memory_order_relaxed); }
    /// Test hooks: a write left half done (odd sequence) and its end.
    void begin_write_for_test() noexcept { begin(); }
    /// See begin_write_for_test().
    void end_write_for_test() noexcept { end(); }

private:
    void begin() noexcept;
    void end() noexcept;
    std::atomic<std::uint64_t> sequence_{0U};
    std::atomic<std::uint64_t> words_[kWords]{};
    mutable std::atomic<std::uint64_t> retries_{0U};
    mutable std::atomic<std::uint64_t> demand_us_{0U};
};

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class LiveView final : public CycleObserver {
public:
    /// Watches the cycles of a cell whose evidence grid is @p grid, prior
    /// @p prior and zones @p zones (all must outlive the view), with the
    /// thresholds of @p cfg. Allocates its snapshot and channel here.
    LiveView(const cell::MonitorConfig& cfg, const EvidenceGrid& grid, const std::int16_t* prior,
             std::size_t prior_size, const CompiledZones& zones);
    /// See the file comment.
    void after_cycle(const CycleView& cycle) noexcept override;
    /// Shows the robot capsules @p controller placed in each cycle (nullptr: none; must outlive the view).
    void set_controller(const SafetyController* controller) noexcept { controller_ = controller; }
    /// Leaves out of the foreground the voxels of @p mask (one byte per voxel, nonzero: the robot's; the
    /// controller's robot mask, must outlive the view) in cycles that placed the robot, as the zone
    /// evaluation does (nullptr: none).
    void set_robot_mask(const std::uint8_t* mask, std::size_t size) noexcept {
        robot_mask_ = mask;
        robot_mask_size_ = size;
    }
    /// Where the server reads.
    [[nodiscard]] const SnapshotChannel& channel() const noexcept { return *channel_; }
    /// The longest after_cycle so far, microseconds (cycle thread's figure).
    [[nodiscard]] std::uint64_t max_us() const noexcept { return max_us_.load(std::memory_order_relaxed); }

private:
    void scan(std::uint32_t active) noexcept;
    void copy_robot(const CycleReport& r) noexcept;
    const EvidenceGrid* grid_;
    const std::int16_t* prior_;
    std::size_t prior_size_;
    const CompiledZones* zones_;
    const SafetyController* controller_ = nullptr;
    const std::uint8_t* robot_mask_ = nullptr;
    std::size_t robot_mask_size_ = 0U;
    std::int16_t foreground_threshold_;
    std::int16_t accessible_min_prior_;
    std::unique_ptr<LiveSnapshot> staging_;
    std::unique_ptr<SnapshotChannel> channel_;
    std::atomic<std::uint64_t> max_us_{0U};
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_LIVE_VIEW_HPP
