// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file monitor_loop.hpp
/// The monitor's cycle. A MonitorLoop takes the wiring (the configuration,
/// the cell built at start-up, one frame source per sensor, the CAN port and
/// the clock), builds the controller and the CAN safety output, and
/// allocates at construction everything a cycle needs: the sensor inputs and
/// the status-line buffer (the frame sources hold their own frame buffers).
/// run_cycle(k) then does one cycle without the heap:
///  1. each sensor's frame of cycle k, loaded once into its source's buffer
///     (a refused recorded frame is reported on the status output);
///  2. the clock starts the cycle at 1 s + k periods (cycle_clock.hpp); every
///     frame is stamped with that time, except a live camera's, which
///     carries its capture time (FrameStatus::stamp_us, CLOCK_MONOTONIC: the
///     monitor runs cameras paced only);
///  3. the controller runs and publishes through the CAN safety output,
///     which asks the CAN port for its detail faults (a SocketCAN
///     interface reads its error frames then; can_port.hpp); protocol 0.2:
///     with the link frame whose fields come from the command link's
///     controller endpoint (command_link.hpp), and the cycle's frames go to
///     the command link (a simulated PLC receives them). Without a command
///     link the controller's frames carry no echo and a PLC refuses them;
///  4. the run's counts are updated and the status line is formatted into the
///     fixed buffer and written to the status output.
/// run_cycles() runs a loop's cycles, as fast as possible or paced one per
/// period on CLOCK_MONOTONIC.
#ifndef CELLGUARD_MONITOR_MONITOR_LOOP_HPP
#define CELLGUARD_MONITOR_MONITOR_LOOP_HPP

#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "cellguard/can/safety_output.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/cycle_observer.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/robot_cell_demo.hpp"
#include "cellguard/port/frame_signal.hpp"
#include "cellguard/port/stack.hpp"
#include "cellguard/safety/safety_controller.hpp"

namespace cellguard::monitor {

/// The simulated time of cycle 0's start, microseconds.
constexpr std::uint64_t kSimStartUs = 1000000U;

/// What the cycles of a run came to.
struct MonitorStats {
    int cycles_run = 0;                 ///< cycles run
    int stop_cycles = 0;                ///< cycles with the stop requested
    int warning_cycles = 0;             ///< cycles with the warning on
    int first_stop_after_release = -1;  ///< the first cycle that stopped after one that did not (-1: none)
    int send_failures = 0;              ///< log or sender: cycles that did not send their frames (4, or 5 with a robot)
    int reduced_cycles = 0;             ///< cycles with reduced speed requested (and no stop)
    int command_invalid_cycles = 0;     ///< cycles that refused the PLC's command
    int can_fault_cycles = 0;           ///< cycles that ended with the CAN-error fault latched
    std::uint32_t faults_seen = 0U;     ///< every fault latched in some cycle
    std::uint64_t max_cycle_us = 0U;    ///< the longest cycle
    /// Per cycle (the first cfg.demo_cycles, room made at construction):
    /// the controller's cycle, its fusion stage, and loading the frames
    /// (rendering or reading them, before the cycle), microseconds.
    std::vector<std::uint64_t> cycle_us;
    std::vector<std::uint64_t> fuse_us;  ///< see cycle_us
    std::vector<std::uint64_t> load_us;  ///< see cycle_us
    /// Per cycle with a live camera: from the newest frame's capture time to
    /// the moment the cycle's CAN frames were sent (CLOCK_MONOTONIC),
    /// microseconds; latency_count of them (the first cfg.demo_cycles).
    std::vector<std::uint64_t> latency_us;
    std::size_t latency_count = 0U;  ///< see latency_us
    /// The same from the moment the newest frame's last packet arrived
    /// (FrameStatus::receive_us: the wait for the cycle and the cycle itself,
    /// without the camera's own delay); arrival_count of them.
    std::vector<std::uint64_t> arrival_us;
    std::size_t arrival_count = 0U;  ///< see arrival_us
    /// Per cycle (as cycle_us): the cycle thread's CPU time in the controller's
    /// cycle (CLOCK_THREAD_CPUTIME_ID: its work, without time it waited for a
    /// core; fusion workers' time not included), microseconds.
    std::vector<std::uint64_t> cpu_us;
    int cpu_over_budget = 0;  ///< cycles whose cycle-thread CPU time exceeded the budget
    bool released = false;    ///< some cycle did not request the stop
};

/// How run_cycles() ended.
struct RunResult {
    bool stopped_by_signal = false;      ///< the stop flag ended it early
    bool paced = false;                  ///< one cycle per period on the real clock
    std::uint64_t skipped_periods = 0U;  ///< paced: periods skipped after a cycle that ran past its period
    bool frame_started = false;          ///< paced by frames (run_cycles' @p frames)
    std::uint64_t frame_starts = 0U;     ///< paced by frames: cycles started when every source had a new frame
    std::uint64_t deadline_starts = 0U;  ///< paced by frames: cycles started at the deadline, some frame still old
};

/// Median, 99th percentile and maximum of some durations, microseconds.
struct DurationFigures {
    std::size_t count = 0U;     ///< durations
    std::uint64_t median = 0U;  ///< the middle one (the upper of the two middle ones)
    std::uint64_t p99 = 0U;     ///< the ceil(0.99 n)-th smallest
    std::uint64_t p999 = 0U;    ///< the ceil(0.999 n)-th smallest
    std::uint64_t max = 0U;     ///< the largest
};
/// The figures of the first @p n of @p us (fewer when it holds fewer).
DurationFigures duration_figures(const std::vector<std::uint64_t>& us, std::size_t n);

/// The painting of the cycle thread's stack (port/linux stack.hpp, hazard
/// H-MEM-3) that every MonitorLoop hands its controller: no region (never
/// failing) until the program starts it on the thread that runs the cycles.
linux_port::StackMonitor& cycle_stack() noexcept;

/// Writes the names of the faults in @p mask, comma-separated ("-" for none),
/// into @p out (capacity @p capacity, cut to fit); returns @p out.
const char* format_fault_names(std::uint32_t mask, char* out, std::size_t capacity) noexcept;

/// See the file comment. All references must outlive the loop.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class MonitorLoop final : private CycleOutput {
public:
    /// Binds the wiring: @p sources holds one source per configured sensor,
    /// in configuration order; @p status_out receives the status lines and
    /// refused-frame reports (nullptr: quiet). A cell with a robot or
    /// monitoring cases takes the PLC's command from @p commands each cycle
    /// (nullptr: none arrives, so the controller stops); @p hook (optional)
    /// is called around each cycle (the robot-cell demo's simulation).
    /// With footprint fusion ([fusion] method = "footprint") the sensors'
    /// passes run on @p runner (nullptr: one core, in order).
    MonitorLoop(const cell::MonitorConfig& cfg, MonitorCell& cell, const std::vector<cell::FrameSource*>& sources,
                CanPort& can, CycleClock& clock, std::FILE* status_out, CommandLink* commands = nullptr,
                CycleHook* hook = nullptr, TaskRunner* runner = nullptr);
    MonitorLoop(const MonitorLoop&) = delete;
    MonitorLoop& operator=(const MonitorLoop&) = delete;
    MonitorLoop(MonitorLoop&&) = delete;
    MonitorLoop& operator=(MonitorLoop&&) = delete;
    ~MonitorLoop() = default;

    /// kOk, or why the loop cannot run: the CAN output refused its
    /// configuration, or the sources do not match the sensors (kInvalidArgument).
    [[nodiscard]] Status status() const noexcept;
    /// Runs cycle @p k (from 0); see the file comment. Allocates nothing.
    const CycleReport& run_cycle(int k) noexcept;

    /// True when every source has a frame it has not given before
    /// (FrameSource::has_new_frame; false when the sources do not match).
    [[nodiscard]] bool frames_ready() const noexcept;
    /// The run's counts so far.
    [[nodiscard]] const MonitorStats& stats() const noexcept { return stats_; }
    /// The last cycle's status line (with its newline; "" before the first cycle).
    [[nodiscard]] const char* status_line() const noexcept { return line_.data(); }
    /// The controller.
    [[nodiscard]] const SafetyController& controller() const noexcept { return controller_; }
    /// Calls @p observer after each complete cycle (nullptr: none); cycle_observer.hpp.
    void set_observer(CycleObserver* observer) noexcept { observer_ = observer; }

    /// The run's summary lines (counts, faults, pacing, sources, CAN) to
    /// @p out; @p log_ok: CanPort::close() succeeded.
    void write_summary(std::FILE* out, const RunResult& run, bool log_ok) const noexcept;
    /// The exit status of the run (0 done, 1 the CAN log failed, 3 the CAN
    /// output failed in some cycle), after saying why on @p err.
    int exit_status(std::FILE* err, bool log_ok) const noexcept;

private:
    bool publish(const CycleReport& report) noexcept override;
    void load_frames(int k) noexcept;
    void write_timing(std::FILE* out) const noexcept;
    /// Counts cycle @p k's report @p r, whose controller cycle took @p cpu_us of the thread's CPU time.
    void count(int k, const CycleReport& r, std::uint64_t cpu_us) noexcept;
    void format_status(int k, const CycleReport& r) noexcept;
    CommandFault command_fault_ = CommandFault::kNoSampleYet;  ///< the last poll's receiver status
    void append(const char* format, ...) noexcept __attribute__((format(printf, 2, 3)));

    const cell::MonitorConfig* cfg_;
    std::vector<cell::FrameSource*> sources_;
    CanPort* can_;
    CycleClock* clock_;
    std::FILE* out_;
    bool sources_match_;
    CommandLink* commands_;            ///< the PLC's command (nullptr: none)
    CycleHook* hook_;                  ///< around each cycle (nullptr: none)
    bool robot_cell_;                  ///< the cell has a robot or cases: the status line shows them
    bool show_person_;                 ///< false: every sensor is recorded, no simulated person to show
    std::size_t zone_count_;           ///< zones on the status line
    std::vector<SensorInput> inputs_;  ///< one per sensor, made at construction
    std::vector<char> line_;           ///< the status line, sized at construction for the longest one
    std::size_t line_length_ = 0U;
    cell::FrameStatus frame_status_{};
    std::vector<std::uint64_t> stamps_;     ///< per sensor: the capture time its source gave (0: none)
    std::vector<std::uint64_t> receives_;   ///< per sensor: when its frame arrived (0: not known)
    std::vector<SensorReading> delivered_;  ///< per sensor: its frame as delivered, when a depth filter changed it
    std::uint64_t sent_us_ = 0U;            ///< CLOCK_MONOTONIC when the last cycle's CAN frames were sent
    std::uint64_t cycle_real_us_ = 0U;      ///< the last cycle's real duration (CycleClock::real_span_us)
    SafetyController controller_;
    LinkEndpoint own_link_;   ///< the controller's link endpoint when there is no command link (no echo)
    CanSafetyOutput output_;  ///< made after the controller: it sends the controller's prior CRC
    MonitorStats stats_{};
    CycleObserver* observer_ = nullptr;  ///< after each complete cycle (nullptr: none)
};

/// Runs cycles 0 .. @p cycles - 1 of @p loop; ends early when @p stop
/// becomes non-zero (checked before each cycle). @p paced: each cycle starts
/// at the next period of CLOCK_MONOTONIC (cfg.period_us apart); periods that
/// are already over when a cycle ends are skipped, not run back to back.
/// Paced with @p frames (the signal live cameras notify on each frame;
/// nullptr: by the period): a cycle starts as soon as every source has a new
/// frame (MonitorLoop::frames_ready), but not before half a period after the
/// previous start, and at the latest 1.125 periods after it (the cameras'
/// period jitters around the cycle's; a late or silent camera then gives its
/// previous frame, which the controller's frame-age check judges). Cycles
/// follow the cameras' rate, at most two per period and at least one per 1.125
/// periods; each frame waits for the cycle only until the last camera's frame arrives.
RunResult run_cycles(MonitorLoop& loop, int cycles, std::uint64_t period_us, bool paced,
                     const volatile std::sig_atomic_t& stop, linux_port::FrameSignal* frames = nullptr) noexcept;

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_MONITOR_LOOP_HPP
