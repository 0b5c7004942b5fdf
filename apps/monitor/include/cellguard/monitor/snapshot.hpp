// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file snapshot.hpp
/// A bounded snapshot of each protective stop, for the investigation after
/// it: when a cycle requests the stop after a cycle that did not (a stop
/// after a release), the SnapshotRecorder keeps
/// - the cycle's evidence grid (log-odds and observed flags),
/// - the last frames_around CAN frames before it (those of the stop cycle
///   included) and the next frames_around after it, sent and received,
/// and a writer thread of its own writes them into
/// `DIR/stop-YYYYmmddTHHMMSSZ-NNNN-cycle-K/`:
/// - `grid_log_odds.npy`, `grid_probability.npy`, `grid_observed.npy`
///   (write_grid_npy, numpy's format),
/// - `picture.png`: the configuration picture (picture.hpp) with the voxel
///   columns whose evidence reached the foreground threshold in that cycle
///   drawn over the top view in green,
/// - `can.log`: the frames in candump -L format (the ones before, then the
///   ones after), stamped with the start time of the cycle they belong to,
/// - `snapshot.txt`: cycle, time, zone states, faults, frame counts (before,
///   after, received).
/// The directory is written under a name starting with "." and renamed when
/// complete, so a directory named stop-* is always whole. After each one the
/// oldest stop-* directories beyond keep are removed.
///
/// The cycle's side (after_cycle, on_frame) copies only into storage
/// allocated at construction (one grid, the frame ring, the snapshot's
/// frames) and wakes the writer with sem_post: it never blocks and never
/// allocates. A stop that fires while a snapshot is still collecting its
/// later frames or being written is counted as skipped, not recorded. The
/// writer thread allocates (file names, PNG), outside the cycle's time path,
/// as a background thread (SCHED_OTHER, nice 10, also under --realtime).
#ifndef CELLGUARD_MONITOR_SNAPSHOT_HPP
#define CELLGUARD_MONITOR_SNAPSHOT_HPP

#include <semaphore.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/monitor/picture.hpp"
#include "cellguard/port/log_queue.hpp"

namespace cellguard::monitor {

/// Where and how much.
struct SnapshotSettings {
    std::string directory;                ///< where the snapshots go (must exist or be creatable)
    std::size_t keep = 10U;               ///< snapshots kept at most (1 or more)
    std::size_t frames_around = 64U;      ///< CAN frames kept before and after the stop (1 or more)
    std::string interface_name = "can0";  ///< the interface name in can.log
};

/// What the recorder did.
struct SnapshotCounts {
    std::uint64_t triggered = 0U;    ///< stops after a release seen
    std::uint64_t written = 0U;      ///< snapshots written whole
    std::uint64_t skipped = 0U;      ///< stops while a snapshot was in progress
    std::uint64_t failed = 0U;       ///< snapshots the writer could not write
    std::uint64_t removed = 0U;      ///< old snapshots removed (beyond keep)
    std::uint64_t max_copy_us = 0U;  ///< the longest copy in a stop cycle (grid and frames), microseconds
};

/// A CAN frame with the start time of its cycle.
struct TimedFrame {
    std::uint64_t time_us = 0U;                    ///< its cycle's start, microseconds
    CanFrame frame{0U, 0U, {}};                    ///< the frame
    TapDirection direction = TapDirection::kSent;  ///< sent or received
};

/// See the file comment.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class SnapshotRecorder final : public CycleObserver, public CanFrameTap {
public:
    /// Records the stops of the cycles whose grid is @p grid (the cell's
    /// frame grid; must outlive the recorder), drawn with @p picture (its
    /// zones and prior must outlive the recorder) and with the foreground
    /// threshold of @p cfg.
    SnapshotRecorder(SnapshotSettings settings, const cell::MonitorConfig& cfg, const EvidenceGrid& grid,
                     PictureInput picture);
    SnapshotRecorder(const SnapshotRecorder&) = delete;
    SnapshotRecorder& operator=(const SnapshotRecorder&) = delete;
    SnapshotRecorder(SnapshotRecorder&&) = delete;
    SnapshotRecorder& operator=(SnapshotRecorder&&) = delete;
    /// Finishes (finish()).
    ~SnapshotRecorder();

    /// Creates the directory if needed, checks that it can be written and
    /// starts the writer; false with @p error set otherwise.
    [[nodiscard]] bool start(std::string& error);
    /// Reports each snapshot written or failed on @p log (nullptr: none; must outlive the recorder).
    void set_log(linux_port::LogQueue* log) noexcept { log_ = log; }
    /// See the file comment.
    void after_cycle(const CycleView& cycle) noexcept override;
    /// See the file comment.
    void on_frame(const CanFrame& frame, TapDirection direction) noexcept override;
    /// Ends the recording: a snapshot still collecting its later frames is
    /// written with those it has; waits for the writer and joins it.
    void finish() noexcept;

    /// What was done so far (read after finish() for the final figures).
    [[nodiscard]] SnapshotCounts counts() const noexcept;
    /// The directories written, oldest first (after finish()).
    [[nodiscard]] const std::vector<std::string>& written_paths() const noexcept { return paths_; }

private:
    enum State : int { kIdle = 0, kCollecting = 1, kWriting = 2, kDone = 3 };
    void trigger(const CycleView& cycle) noexcept;
    void run() noexcept;
    bool write(std::string& error);
    bool write_frames(const std::string& path, std::string& error) const;
    bool write_text(const std::string& path, std::string& error) const;
    bool write_picture(const std::string& path, std::string& error) const;
    void prune() noexcept;

    SnapshotSettings settings_;
    const cell::MonitorConfig* cfg_;
    const EvidenceGrid* grid_;
    PictureInput picture_;
    // The cycle's side: the ring of the latest frames.
    std::vector<TimedFrame> ring_;
    std::size_t ring_next_ = 0U;
    std::size_t ring_count_ = 0U;
    std::size_t unstamped_ = 0U;  ///< frames tapped since the last cycle ended (stamped then)
    bool released_ = false;       ///< the last cycle did not request the stop
    // The snapshot being collected or written (owned by the writer in kWriting).
    std::atomic<int> state_{kIdle};
    std::vector<std::int16_t> log_odds_;
    std::vector<std::uint8_t> observed_;
    std::vector<TimedFrame> before_;
    std::size_t before_count_ = 0U;
    std::vector<TimedFrame> after_;
    std::size_t after_count_ = 0U;
    std::size_t after_unstamped_ = 0U;
    CycleReport report_{};
    int cycle_ = 0;
    std::uint64_t sequence_ = 0U;
    // Counts (atomics: the writer updates some, the main thread reads them).
    std::atomic<std::uint64_t> triggered_{0U};
    std::atomic<std::uint64_t> written_{0U};
    std::atomic<std::uint64_t> skipped_{0U};
    std::atomic<std::uint64_t> failed_{0U};
    std::atomic<std::uint64_t> removed_{0U};
    std::uint64_t max_copy_us_ = 0U;
    std::vector<std::string> paths_;
    linux_port::LogQueue* log_ = nullptr;
    sem_t wakeup_{};
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_SNAPSHOT_HPP
