// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor's cycle without the heap (monitor_loop.hpp).
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/port/clock.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstring>
#include <ctime>

#include "cellguard/host/cell/scenario.hpp"

namespace cellguard::monitor {
namespace {

// The CAN safety output's configuration for @p cfg, with the controller's prior CRC.
SafetyOutputConfig output_config(const cell::MonitorConfig& cfg, const MonitorCell& cell, std::uint32_t prior_crc) {
    SafetyOutputConfig oc;
    oc.channel = cfg.can.channel;
    oc.zone_count = static_cast<std::uint8_t>(cell.zones.size());
    oc.prior_crc = prior_crc;
    return oc;  // session link on (protocol 0.2): the link endpoint is the command link's
}

// The controller's configuration with the cell's robot and fusion sides.
ControllerConfig robot_controller_config(const cell::MonitorConfig& cfg, MonitorCell& cell, TaskRunner* runner) {
    ControllerConfig cc = controller_config(cfg);
    cc.stack = &cycle_stack().paint();
    attach_robot(cc, cfg, cell);
    attach_fusion(cc, cfg, cell, runner);
    return cc;
}

// Room for the longest status line of @p cfg: the fixed text and numbers,
// every zone's name with the longest state, every fault's name.
std::size_t status_line_capacity(const cell::MonitorConfig& cfg) {
    std::size_t longest_state = 0U;
    for (const ZoneState s : {ZoneState::kClear, ZoneState::kIntruded, ZoneState::kUnseen, ZoneState::kFault}) {
        longest_state = std::max(longest_state, std::strlen(to_string(s)));
    }
    // "t=... cycle ... " with the 63-character scene text (79 with a cycle
    // hook's), stop and warning, cycle time, and the robot's case, request and distances.
    std::size_t n = 336U;
    for (const cell::ZoneSettings& z : cfg.zones) {
        n += z.name.size() + 2U + longest_state;
    }
    for (std::uint8_t f = 0U; f < kFaultCount; ++f) {
        n += std::strlen(to_string(static_cast<Fault>(f))) + 1U;
    }
    return n;
}

// Sleeps until @p next, then moves it one period on, past every period that
// is already over (counted in @p skipped).
void wait_for_period(timespec& next, std::uint64_t period_us, std::uint64_t& skipped) noexcept {
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
    const auto advance = [&next, period_us] {
        next.tv_nsec += static_cast<long>((period_us % 1000000U) * 1000U);
        next.tv_sec += static_cast<time_t>(period_us / 1000000U) + next.tv_nsec / 1000000000L;
        next.tv_nsec %= 1000000000L;
    };
    advance();
    // After a cycle that ran past its period the next start is already
    // over: skip the periods that are over instead of running their cycles
    // back to back (a burst).
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    while (next.tv_sec < now.tv_sec || (next.tv_sec == now.tv_sec && next.tv_nsec <= now.tv_nsec)) {
        advance();
        ++skipped;
    }
}

// "summary: latency from the newest camera frame's @p from to its CAN frames ..." for
// the first @p count of @p us; nothing when there are none (no live camera). Allocates (after the run).
void write_latency(std::FILE* out, const char* from, const std::vector<std::uint64_t>& us, std::size_t count) {
    if (count == 0U) {
        return;
    }
    const DurationFigures f = duration_figures(us, count);
    const auto ms = [](std::uint64_t v) { return static_cast<double>(v) / 1000.0; };
    static_cast<void>(std::fprintf(out,
                                   "summary: latency from the newest camera frame's %s to its CAN frames over %zu "
                                   "cycles: median %.2f ms, p99 %.2f ms, p99.9 %.2f ms, max %.2f ms\n",
                                   from, f.count, ms(f.median), ms(f.p99), ms(f.p999), ms(f.max)));
}

// Paced by frames (run_cycles): sleeps until half a period after @p last_start_us
// (0: the first cycle, no wait), then until every source of @p loop has a new
// frame or 1.125 periods after @p last_start_us have passed; counts which came first.
void wait_for_frames(const MonitorLoop& loop, linux_port::FrameSignal& frames, std::uint64_t last_start_us,
                     std::uint64_t period_us, RunResult& result) noexcept {
    if (last_start_us != 0U) {
        const std::uint64_t earliest = last_start_us + period_us / 2U;
        timespec until{};
        until.tv_sec = static_cast<time_t>(earliest / 1000000U);
        until.tv_nsec = static_cast<long>((earliest % 1000000U) * 1000U);
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr);
    }
    // An eighth of a period beyond it: the cameras' own period jitters around the cycle's, and a
    // deadline at exactly one period started every other cycle just before the last frame arrived.
    const std::uint64_t deadline = last_start_us + period_us + period_us / 8U;
    for (;;) {
        const std::uint32_t seen = frames.value();  // before looking: a frame published meanwhile changes it
        if (loop.frames_ready()) {
            ++result.frame_starts;
            return;
        }
        if (!frames.wait_after(seen, deadline)) {
            ++result.deadline_starts;
            return;
        }
    }
}

}  // namespace

linux_port::StackMonitor& cycle_stack() noexcept {
    static linux_port::StackMonitor stack;
    return stack;
}

DurationFigures duration_figures(const std::vector<std::uint64_t>& us, std::size_t n) {
    std::vector<std::uint64_t> sorted(us.begin(), us.begin() + static_cast<std::ptrdiff_t>(std::min(n, us.size())));
    std::sort(sorted.begin(), sorted.end());
    DurationFigures f;
    f.count = sorted.size();
    if (f.count == 0U) {
        return f;
    }
    f.median = sorted[f.count / 2U];
    f.p99 = sorted[(f.count * 99U + 99U) / 100U - 1U];
    f.p999 = sorted[(f.count * 999U + 999U) / 1000U - 1U];
    f.max = sorted.back();
    return f;
}

const char* format_fault_names(std::uint32_t mask, char* out, std::size_t capacity) noexcept {
    if (capacity == 0U) {
        return out;
    }
    out[0] = '\0';
    if (mask == 0U) {
        static_cast<void>(std::snprintf(out, capacity, "-"));
        return out;
    }
    std::size_t length = 0U;
    for (std::uint8_t f = 0U; f < kFaultCount; ++f) {
        if ((mask & fault_bit(static_cast<Fault>(f))) != 0U && length + 1U < capacity) {
            const int n = std::snprintf(out + length, capacity - length, "%s%s", length == 0U ? "" : ",",
                                        to_string(static_cast<Fault>(f)));
            length = std::min(length + static_cast<std::size_t>(n > 0 ? n : 0), capacity - 1U);
        }
    }
    return out;
}

MonitorLoop::MonitorLoop(const cell::MonitorConfig& cfg, MonitorCell& cell,
                         const std::vector<cell::FrameSource*>& sources, CanPort& can, CycleClock& clock,
                         std::FILE* status_out, CommandLink* commands, CycleHook* hook, TaskRunner* runner)
    : cfg_(&cfg),
      sources_(sources),
      can_(&can),
      clock_(&clock),
      out_(status_out),
      sources_match_(sources.size() == cfg.sensors.size() && cell.specs.size() == cfg.sensors.size() &&
                     cell.tables.size() == cfg.sensors.size() && cell.backgrounds.size() == cfg.sensors.size() &&
                     std::find(sources.begin(), sources.end(), nullptr) == sources.end()),
      commands_(commands),
      hook_(hook),
      robot_cell_(cell.has_cases || !cell.robot_image.empty()),
      // The scripted person is in the simulated sensors' frames only: not in recorded or live camera frames.
      show_person_(std::any_of(cfg.sensors.begin(), cfg.sensors.end(),
                               [](const cell::SensorSettings& s) {
                                   return s.pcd_files.empty() && s.recording.files.empty() && !s.camera.enabled;
                               })),
      zone_count_(std::min({cell.zones.size(), cfg.zones.size(), kMaxZones})),
      inputs_(cfg.sensors.size()),
      line_(status_line_capacity(cfg), '\0'),
      stamps_(cfg.sensors.size(), 0U),
      receives_(cfg.sensors.size(), 0U),
      delivered_(cfg.sensors.size()),
      controller_(robot_controller_config(cfg, cell, runner), cell.frame_grid,
                  {cell.fusion_scratch.data(), cell.fusion_scratch.size()}, {cell.prior.data(), cell.prior.size()},
                  cell.zones, cell.model, clock, this),
      own_link_(controller_link_config()),
      output_(output_config(cfg, cell, controller_.prior_crc()), can,
              commands != nullptr ? &commands->controller_link() : &own_link_) {
    for (std::size_t s = 0U; s < inputs_.size() && sources_match_; ++s) {
        const bool simulated = cfg.sensors[s].pcd_files.empty();
        inputs_[s].present = true;
        // Footprint fusion needs no ray table (none was built).
        inputs_[s].table = simulated && cfg.fusion.method == FusionMethod::kRay ? &cell.tables[s].table() : nullptr;
        // A recorded sensor's view is per direction bin (MonitorCell::attach_backgrounds).
        inputs_[s].background = cfg.background_match > 0.0F ? &cell.backgrounds[s] : nullptr;
    }
    const std::size_t recorded = static_cast<std::size_t>(std::max(cfg.demo_cycles, 0));
    stats_.cycle_us.assign(recorded, 0U);
    stats_.fuse_us.assign(recorded, 0U);
    stats_.load_us.assign(recorded, 0U);
    stats_.latency_us.assign(recorded, 0U);
    stats_.arrival_us.assign(recorded, 0U);
    stats_.cpu_us.assign(recorded, 0U);
}

bool MonitorLoop::frames_ready() const noexcept {
    return sources_match_ &&
           std::all_of(sources_.begin(), sources_.end(), [](const cell::FrameSource* s) { return s->has_new_frame(); });
}

Status MonitorLoop::status() const noexcept {
    if (!sources_match_) {
        return Status{ErrorCode::kInvalidArgument};
    }
    return output_.status();
}

bool MonitorLoop::publish(const CycleReport& report) noexcept {
    const bool sent = output_.publish(report);
    sent_us_ = linux_port::monotonic_now_us();
    if (commands_ != nullptr) {
        commands_->on_sent(output_.last_frames(), clock_->now_us());  // a simulated PLC receives them
    }
    return sent;
}

void MonitorLoop::load_frames(int k) noexcept {
    if (!sources_match_) {
        return;  // no input is present: the controller reports every sensor missing
    }
    for (std::size_t s = 0U; s < inputs_.size(); ++s) {
        frame_status_ = cell::FrameStatus{};  // nothing of the previous sensor's frame carries over
        const bool ok = sources_[s]->load_frame(static_cast<std::uint64_t>(k), inputs_[s].reading, frame_status_);
        delivered_[s] = frame_status_.delivered;
        inputs_[s].delivered = frame_status_.filtered ? &delivered_[s] : nullptr;  // the frozen check's frame
        stamps_[s] = frame_status_.has_stamp ? frame_status_.stamp_us : 0U;
        receives_[s] = frame_status_.has_stamp ? frame_status_.receive_us : 0U;
        if (!ok && out_ != nullptr) {
            static_cast<void>(std::fprintf(out_, "input: cycle %d sensor '%s': frame %s refused: %s\n", k,
                                           cfg_->sensors[s].name.c_str(), frame_status_.file, frame_status_.reason));
        }
    }
}

const CycleReport& MonitorLoop::run_cycle(int k) noexcept {
    if (hook_ != nullptr) {
        hook_->before_cycle(k, static_cast<double>(static_cast<std::uint64_t>(k) * cfg_->period_us) * 1e-6);
    }
    const std::uint64_t load_start = linux_port::monotonic_now_us();
    load_frames(k);
    const std::uint64_t load_us = linux_port::monotonic_now_us() - load_start;
    if (k >= 0 && static_cast<std::size_t>(k) < stats_.load_us.size()) {
        stats_.load_us[static_cast<std::size_t>(k)] = load_us;
    }
    clock_->start_cycle(kSimStartUs + static_cast<std::uint64_t>(k) * cfg_->period_us);
    std::uint64_t newest = 0U;   // the newest live camera frame's capture time (0: none)
    std::uint64_t arrival = 0U;  // the last arrival of a live camera frame (0: none)
    for (std::size_t s = 0U; s < inputs_.size(); ++s) {
        inputs_[s].captured_us = stamps_[s] != 0U ? stamps_[s] : clock_->base();
        newest = std::max(newest, stamps_[s]);
        arrival = std::max(arrival, receives_[s]);
    }
    const CommandPoll command = commands_ != nullptr ? commands_->poll(clock_->base()) : CommandPoll{};
    command_fault_ = command.status.fault;
    if (commands_ != nullptr) {
        controller_.report_faults(commands_->clock_rate().faults());  // the clock's rate against the PLC's
    }
    const std::size_t sent_before = can_->frames_sent();
    sent_us_ = 0U;
    const std::uint64_t cpu_start = linux_port::thread_cpu_now_us();
    const CycleReport& r = controller_.run_cycle({inputs_.data(), inputs_.size()}, false, command.input);
    const std::uint64_t cpu_end = linux_port::thread_cpu_now_us();
    count(k, r, cpu_end > cpu_start ? cpu_end - cpu_start : 0U);
    if (newest != 0U && sent_us_ != 0U && stats_.latency_count < stats_.latency_us.size()) {
        stats_.latency_us[stats_.latency_count++] = sent_us_ > newest ? sent_us_ - newest : 0U;
    }
    if (arrival != 0U && sent_us_ != 0U && stats_.arrival_count < stats_.arrival_us.size()) {
        stats_.arrival_us[stats_.arrival_count++] = sent_us_ > arrival ? sent_us_ - arrival : 0U;
    }
    const std::size_t frames_per_cycle = (r.robot.configured ? 4U : 3U) + (output_.last_frames().has_link ? 1U : 0U);
    if (can_->kind() != CanPort::Kind::kInterface && can_->frames_sent() - sent_before != frames_per_cycle) {
        ++stats_.send_failures;
    }
    if (hook_ != nullptr) {
        hook_->after_cycle(r);
    }
    if (observer_ != nullptr) {
        observer_->after_cycle(CycleView{k, &r, cycle_real_us_, linux_port::monotonic_now_us()});
    }
    format_status(k, r);
    if (out_ != nullptr) {
        static_cast<void>(std::fputs(line_.data(), out_));
        static_cast<void>(std::fflush(out_));
    }
    return r;
}

void MonitorLoop::count(int k, const CycleReport& r, std::uint64_t cpu_us) noexcept {
    // The figures are real time: unpaced, the controller's clock is simulated (cycle_clock.hpp).
    const CycleTiming& timing = controller_.monitor().last();
    const std::uint64_t begin = r.started_us;
    cycle_real_us_ = clock_->real_span_us(begin, begin + timing.total_us);
    const std::uint64_t fuse_us = clock_->real_span_us(
        begin, begin + timing.stage_us[static_cast<std::size_t>(CycleStage::kFuse)]);
    stats_.max_cycle_us = std::max(stats_.max_cycle_us, cycle_real_us_);
    if (k >= 0 && static_cast<std::size_t>(k) < stats_.cycle_us.size()) {
        stats_.cycle_us[static_cast<std::size_t>(k)] = cycle_real_us_;
        stats_.fuse_us[static_cast<std::size_t>(k)] = fuse_us;
        stats_.cpu_us[static_cast<std::size_t>(k)] = cpu_us;
    }
    stats_.cpu_over_budget += cpu_us > cfg_->budget_us ? 1 : 0;
    ++stats_.cycles_run;
    stats_.faults_seen |= r.safety.latched_faults;
    if ((r.safety.latched_faults & fault_bit(Fault::kCanError)) != 0U) {
        ++stats_.can_fault_cycles;
    }
    if (r.safety.stop_requested) {
        ++stats_.stop_cycles;
        if (stats_.released && stats_.first_stop_after_release < 0) {
            stats_.first_stop_after_release = k;
        }
    } else {
        stats_.released = true;
    }
    if (r.safety.warning) {
        ++stats_.warning_cycles;
    }
    if (!r.safety.stop_requested && r.robot.speed_request == SpeedRequest::kReduced) {
        ++stats_.reduced_cycles;
    }
    if ((r.safety.latched_faults & fault_bit(Fault::kCommandInvalid)) != 0U && !r.robot.command_valid) {
        ++stats_.command_invalid_cycles;
    }
}

// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
void MonitorLoop::append(const char* format, ...) noexcept {
    if (line_length_ + 1U >= line_.size()) {
        return;
    }
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(line_.data() + line_length_, line_.size() - line_length_, format, args);
    va_end(args);
    line_length_ = std::min(line_length_ + static_cast<std::size_t>(n > 0 ? n : 0), line_.size() - 1U);
}

void MonitorLoop::format_status(int k, const CycleReport& r) noexcept {
    line_length_ = 0U;
    line_[0] = '\0';
    // The scripted person exists only for simulated sensors: with recorded or live frames alone, say so instead.
    char scene_text[64];
    if (show_person_) {
        const cell::PersonPosition person = cell::demo_person(k);
        static_cast<void>(std::snprintf(scene_text, sizeof scene_text, "person (%5.2f,%5.2f) %-17s", person.x, person.y,
                                        cell::demo_phase(k)));
    } else if (std::any_of(cfg_->sensors.begin(), cfg_->sensors.end(),
                           [](const cell::SensorSettings& s) { return s.camera.enabled; })) {
        static_cast<void>(std::snprintf(scene_text, sizeof scene_text, "live cameras %-21s", ""));
    } else {
        static_cast<void>(std::snprintf(scene_text, sizeof scene_text, "recorded frames %-18s", ""));
    }
    char hook_text[sizeof scene_text + 16];
    if (hook_ != nullptr) {
        hook_->describe(scene_text, hook_text, sizeof hook_text);
    }
    append("t=%7.3fs cycle %3d %s|", static_cast<double>(clock_->base() - kSimStartUs) / 1e6, k,
           hook_ != nullptr ? hook_text : scene_text);
    // As the CAN frame and the browser view show them: with a fault latched its Fault bit makes every
    // zone FAULT (a zone's own CLEAR would hide why the stop holds).
    for (std::size_t z = 0U; z < zone_count_; ++z) {
        append(" %s:%s", cfg_->zones[z].name.c_str(),
               r.safety.latched_faults != 0U ? to_string(ZoneState::kFault) : to_string(r.zones.zones[z].state));
    }
    if (robot_cell_) {
        char distance[16] = "-";
        if (r.robot.distance_mm != 65535U) {
            static_cast<void>(std::snprintf(distance, sizeof distance, "%.2f m", r.robot.distance_mm / 1000.0));
        }
        append(" | case %u %-7s d %-7s S_p %.2f m", r.robot.active_case, to_string(r.robot.speed_request), distance,
               r.robot.required_mm / 1000.0);
        if (!r.robot.command_valid && r.robot.command_check != 0U) {
            append(" cmd refused: %s (link: %s)", to_string(static_cast<CommandRefusal>(r.robot.command_check)),
                   to_string(command_fault_));
        }
    }
    char faults[256];
    append(" | %-4s %-4s | faults %s | cycle %.2f ms\n", r.safety.stop_requested ? "STOP" : "run",
           r.safety.warning ? "WARN" : "-", format_fault_names(r.safety.latched_faults, faults, sizeof faults),
           static_cast<double>(cycle_real_us_) / 1000.0);
}

void MonitorLoop::write_summary(std::FILE* out, const RunResult& run, bool log_ok) const noexcept {
    static_cast<void>(std::fprintf(out, "\nsummary: %d cycles%s, stop requested in %d, warning in %d",
                                   stats_.cycles_run, run.stopped_by_signal ? " (stopped by signal)" : "",
                                   stats_.stop_cycles, stats_.warning_cycles));
    if (stats_.first_stop_after_release >= 0) {
        static_cast<void>(std::fprintf(out, ", first stop after release in cycle %d", stats_.first_stop_after_release));
    }
    char faults[256];
    static_cast<void>(std::fprintf(
        out, "\nsummary: faults latched during the run: %s; longest cycle %.2f ms (budget %.1f ms), overruns %llu\n",
        format_fault_names(stats_.faults_seen, faults, sizeof faults),
        static_cast<double>(stats_.max_cycle_us) / 1000.0, static_cast<double>(cfg_->budget_us) / 1000.0,
        static_cast<unsigned long long>(controller_.monitor().overruns())));
    write_timing(out);
    if (run.frame_started) {  // implies paced (run_cycles)
        static_cast<void>(std::fprintf(out,
                                       "summary: paced by the cameras' frames: %llu cycles started when every "
                                       "camera had a new frame, %llu at the period's deadline\n",
                                       static_cast<unsigned long long>(run.frame_starts),
                                       static_cast<unsigned long long>(run.deadline_starts)));
    } else if (run.paced) {
        static_cast<void>(std::fprintf(out,
                                       "summary: paced: %llu periods skipped after cycles that ran past their period\n",
                                       static_cast<unsigned long long>(run.skipped_periods)));
    } else {
        static_cast<void>(std::fprintf(out,
                                       "summary: unpaced: the decisions, the budget check and the CAN log ran "
                                       "on simulated time; the cycle times above are real (--paced: real time)\n"));
    }
    for (const cell::FrameSource* s : sources_) {
        if (s != nullptr) {
            s->write_summary(out);
        }
    }
    if (commands_ != nullptr && commands_->clock_rate().enabled()) {
        const ClockRateCounts& c = commands_->clock_rate().counts();
        static_cast<void>(std::fprintf(
            out,
            "summary: clock rate against the PLC's samples: %u samples, %u windows, %u restarts, last %+.3f %%, "
            "largest |deviation| %.3f %% (tolerance %.3f %%)%s\n",
            c.samples, c.windows, c.restarts, c.last_deviation_ppm / 1e4, c.max_abs_deviation_ppm / 1e4,
            commands_->clock_rate().config().tolerance_ppm / 1e4,
            commands_->clock_rate().faulted() ? ": CLOCK FAULT" : ""));
    }
    if (commands_ != nullptr) {
        const StandaloneLinkCounts& alone = commands_->standalone_link();
        if (alone.accepted + alone.refused != 0U) {
            static_cast<void>(std::fprintf(out,
                                           "summary: the PLC's link frames sent alone: %u accepted, %u refused%s%s\n",
                                           alone.accepted, alone.refused, alone.refused != 0U ? ", the last: " : "",
                                           alone.refused != 0U ? to_string(alone.last) : ""));
        }
    } else {
        static_cast<void>(
            std::fprintf(out, "summary: no PLC link: the link frames carry no echo, a PLC refuses them\n"));
    }
    can_->write_summary(out, log_ok);
}

void MonitorLoop::write_timing(std::FILE* out) const noexcept {
    const std::size_t n = static_cast<std::size_t>(std::max(stats_.cycles_run, 0));
    const char* const method = cfg_->fusion.method == FusionMethod::kFootprint ? "footprint" : "ray";
    const auto ms = [](std::uint64_t us) { return static_cast<double>(us) / 1000.0; };
    try {  // the summary's sorting copies allocate; after the run
        const DurationFigures cycle = duration_figures(stats_.cycle_us, n);
        const DurationFigures fuse = duration_figures(stats_.fuse_us, n);
        const DurationFigures load = duration_figures(stats_.load_us, n);
        const DurationFigures cpu = duration_figures(stats_.cpu_us, n);
        static_cast<void>(
            std::fprintf(out,
                         "summary: cycle times over %zu cycles: median %.2f ms, p99 %.2f ms, max %.2f ms; "
                         "fusion stage (%s): median %.2f ms, p99 %.2f ms, max %.2f ms\n",
                         cycle.count, ms(cycle.median), ms(cycle.p99), ms(cycle.max), method, ms(fuse.median),
                         ms(fuse.p99), ms(fuse.max)));
        static_cast<void>(std::fprintf(out,
                                       "summary: the cycle thread's CPU time per cycle: median %.2f ms, p99 %.2f ms, "
                                       "max %.2f ms; over the budget in %d cycles (the wall clock's overruns also "
                                       "count time the thread waited for a core)\n",
                                       ms(cpu.median), ms(cpu.p99), ms(cpu.max), stats_.cpu_over_budget));
        static_cast<void>(std::fprintf(out,
                                       "summary: loading the frames (before each cycle, not in its time): median "
                                       "%.2f ms, p99 %.2f ms, max %.2f ms\n",
                                       ms(load.median), ms(load.p99), ms(load.max)));
        write_latency(out, "capture", stats_.latency_us, stats_.latency_count);
        write_latency(out, "arrival", stats_.arrival_us, stats_.arrival_count);
    } catch (...) {
        static_cast<void>(std::fprintf(out, "summary: cycle time figures: out of memory\n"));
    }
}

int MonitorLoop::exit_status(std::FILE* err, bool log_ok) const noexcept {
    if (!log_ok || stats_.send_failures != 0) {
        static_cast<void>(std::fprintf(err, "cellguard-monitor: writing the CAN log failed\n"));
        return 1;
    }
    if (stats_.can_fault_cycles != 0) {
        // A supervisor (systemd, the commissioning script) must not read
        // this run as clean: the safe state held, but frames were lost.
        static_cast<void>(
            std::fprintf(err, "cellguard-monitor: the CAN output failed: CAN-error fault latched in %d of %d cycles\n",
                         stats_.can_fault_cycles, stats_.cycles_run));
        return 3;
    }
    return 0;
}

RunResult run_cycles(MonitorLoop& loop, int cycles, std::uint64_t period_us, bool paced,
                     const volatile std::sig_atomic_t& stop, linux_port::FrameSignal* frames) noexcept {
    RunResult result;
    result.paced = paced;
    result.frame_started = paced && frames != nullptr;
    timespec next{};
    clock_gettime(CLOCK_MONOTONIC, &next);
    std::uint64_t last_start_us = 0U;
    for (int k = 0; k < cycles && stop == 0; ++k) {
        if (result.frame_started) {
            wait_for_frames(loop, *frames, last_start_us, period_us, result);
            last_start_us = linux_port::monotonic_now_us();
        } else if (paced) {
            wait_for_period(next, period_us, result.skipped_periods);
        }
        (void)loop.run_cycle(k);
    }
    result.stopped_by_signal = stop != 0;
    return result;
}

}  // namespace cellguard::monitor
