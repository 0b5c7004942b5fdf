// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The stop snapshot: the cycle's copy and the writer thread (snapshot.hpp).
#include "cellguard/monitor/snapshot.hpp"
#include "cellguard/port/clock.hpp"

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <utility>

#include "cellguard/host/io/candump_log.hpp"
#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/npy.hpp"
#include "cellguard/monitor/monitor_loop.hpp"

namespace cellguard::monitor {
namespace {

using linux_port::LogPriority;

std::string errno_text(const std::string& what) { return what + ": " + std::strerror(errno); }

// The names in @p dir (without "." and ".."); false when it cannot be read.
bool list_directory(const std::string& dir, std::vector<std::string>& names) {
    DIR* d = ::opendir(dir.c_str());
    if (d == nullptr) {
        return false;
    }
    while (const dirent* e = ::readdir(d)) {  // NOLINT(concurrency-mt-unsafe): one thread reads this directory stream
        if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0) {
            names.emplace_back(e->d_name);
        }
    }
    ::closedir(d);
    return true;
}

// Removes the files in @p dir (one level: a snapshot holds files only), then @p dir.
bool remove_snapshot_directory(const std::string& dir) {
    std::vector<std::string> names;
    if (!list_directory(dir, names)) {
        return false;
    }
    bool ok = true;
    for (const std::string& n : names) {
        std::string file = dir;
        file += '/';
        file += n;
        ok = ::unlink(file.c_str()) == 0 && ok;
    }
    return ::rmdir(dir.c_str()) == 0 && ok;
}

}  // namespace

SnapshotRecorder::SnapshotRecorder(SnapshotSettings settings, const cell::MonitorConfig& cfg, const EvidenceGrid& grid,
                                   PictureInput picture)
    : settings_(std::move(settings)), cfg_(&cfg), grid_(&grid), picture_(std::move(picture)) {
    settings_.keep = std::max<std::size_t>(settings_.keep, 1U);
    settings_.frames_around = std::max<std::size_t>(settings_.frames_around, 1U);
    ring_.resize(settings_.frames_around);
    before_.resize(settings_.frames_around);
    after_.resize(settings_.frames_around);
    log_odds_.resize(grid.voxel_count());
    observed_.resize(grid.voxel_count());
    static_cast<void>(sem_init(&wakeup_, 0, 0U));
}

SnapshotRecorder::~SnapshotRecorder() {
    finish();
    static_cast<void>(sem_destroy(&wakeup_));
}

bool SnapshotRecorder::start(std::string& error) {
    const std::string& dir = settings_.directory;
    if (::mkdir(dir.c_str(), 0750) != 0 && errno != EEXIST) {
        error = errno_text("snapshot directory " + dir);
        return false;
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0) {
        error = errno_text("snapshot directory " + dir + " cannot be written");
        return false;
    }
    try {
        thread_ = std::thread([this] { run(); });
    } catch (const std::exception& e) {
        error = std::string("snapshot writer thread: ") + e.what();
        return false;
    }
    return true;
}

void SnapshotRecorder::on_frame(const CanFrame& frame, TapDirection direction) noexcept {
    const std::size_t k = ring_.size();
    ring_[ring_next_] = TimedFrame{0U, frame, direction};
    ring_next_ = (ring_next_ + 1U) % k;
    ring_count_ = std::min(ring_count_ + 1U, k);
    unstamped_ = std::min(unstamped_ + 1U, k);
    if (state_.load(std::memory_order_relaxed) == kCollecting && after_count_ < after_.size()) {
        after_[after_count_++] = TimedFrame{0U, frame, direction};
        ++after_unstamped_;
    }
}

void SnapshotRecorder::after_cycle(const CycleView& cycle) noexcept {
    const CycleReport& r = *cycle.report;
    const std::size_t k = ring_.size();
    for (std::size_t i = 1U; i <= unstamped_; ++i) {
        ring_[(ring_next_ + k - i) % k].time_us = r.started_us;
    }
    unstamped_ = 0U;
    if (state_.load(std::memory_order_relaxed) == kCollecting) {
        for (std::size_t i = after_count_ - after_unstamped_; i < after_count_; ++i) {
            after_[i].time_us = r.started_us;
        }
        after_unstamped_ = 0U;
        if (after_count_ == after_.size()) {
            state_.store(kWriting, std::memory_order_release);  // the writer owns the snapshot now
            static_cast<void>(sem_post(&wakeup_));
        }
    }
    const bool stop = r.safety.stop_requested;
    if (stop && released_) {
        trigger(cycle);
    }
    released_ = !stop;
}

void SnapshotRecorder::trigger(const CycleView& cycle) noexcept {
    triggered_.fetch_add(1U, std::memory_order_relaxed);
    if (!thread_.joinable() || state_.load(std::memory_order_acquire) != kIdle) {
        skipped_.fetch_add(1U, std::memory_order_relaxed);  // the last one is still in progress (or no writer)
        return;
    }
    const std::uint64_t copy_start = linux_port::monotonic_now_us();
    const Span<std::int16_t> lo = grid_->log_odds();
    const Span<std::uint8_t> ob = grid_->observed();
    std::copy(lo.begin(), lo.end(), log_odds_.begin());
    std::copy(ob.begin(), ob.end(), observed_.begin());
    const std::size_t k = ring_.size();
    before_count_ = ring_count_;
    for (std::size_t i = 0U; i < ring_count_; ++i) {  // oldest first
        before_[i] = ring_[(ring_next_ + k - ring_count_ + i) % k];
    }
    report_ = *cycle.report;
    cycle_ = cycle.k;
    after_count_ = 0U;
    after_unstamped_ = 0U;
    state_.store(kCollecting, std::memory_order_release);
    max_copy_us_ = std::max(max_copy_us_, linux_port::monotonic_now_us() - copy_start);
}

void SnapshotRecorder::finish() noexcept {
    if (!thread_.joinable()) {
        return;
    }
    if (state_.load(std::memory_order_acquire) == kCollecting) {
        state_.store(kWriting, std::memory_order_release);  // written with the later frames it has
    }
    stopping_.store(true, std::memory_order_release);
    static_cast<void>(sem_post(&wakeup_));
    thread_.join();
}

SnapshotCounts SnapshotRecorder::counts() const noexcept {
    SnapshotCounts c;
    c.triggered = triggered_.load(std::memory_order_relaxed);
    c.written = written_.load(std::memory_order_relaxed);
    c.skipped = skipped_.load(std::memory_order_relaxed);
    c.failed = failed_.load(std::memory_order_relaxed);
    c.removed = removed_.load(std::memory_order_relaxed);
    c.max_copy_us = max_copy_us_;
    return c;
}

void SnapshotRecorder::run() noexcept {
    // Below the cycle and the log writer: on a 2-core machine its PNG and
    // files otherwise lengthen the cycles that run while it writes.
    static_cast<void>(linux_port::make_background_thread(10));
    for (;;) {
        static_cast<void>(sem_wait(&wakeup_));
        if (state_.load(std::memory_order_acquire) == kWriting) {
            std::string error;
            bool ok = false;
            try {
                ok = write(error);
            } catch (const std::exception& e) {
                error = e.what();
            }
            if (ok) {
                written_.fetch_add(1U, std::memory_order_relaxed);
                if (log_ != nullptr) {
                    log_->push(LogPriority::kNotice, "snapshot of the stop in cycle %d: %s", cycle_,
                               paths_.back().c_str());
                }
                prune();
            } else {
                failed_.fetch_add(1U, std::memory_order_relaxed);
                if (log_ != nullptr) {
                    log_->push(LogPriority::kError, "snapshot of the stop in cycle %d failed: %s", cycle_,
                               error.c_str());
                }
            }
            state_.store(kIdle, std::memory_order_release);
        }
        if (stopping_.load(std::memory_order_acquire) && state_.load(std::memory_order_acquire) != kWriting) {
            return;
        }
    }
}

bool SnapshotRecorder::write(std::string& error) {
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    if (gmtime_r(&now, &utc) == nullptr || std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc) == 0U) {
        static_cast<void>(std::snprintf(stamp, sizeof stamp, "unknown-time"));
    }
    char name[96];
    static_cast<void>(std::snprintf(name, sizeof name, "stop-%s-%04llu-cycle-%06d", stamp,
                                    static_cast<unsigned long long>(sequence_++ % 10000U), cycle_));
    const std::string final_path = settings_.directory + "/" + name;
    const std::string path = settings_.directory + "/." + name;
    if (::mkdir(path.c_str(), 0750) != 0) {
        error = errno_text("creating " + path);
        return false;
    }
    const Result<EvidenceGrid> copy = EvidenceGrid::make(grid_->geometry(), {log_odds_.data(), log_odds_.size()},
                                                         {observed_.data(), observed_.size()});
    bool ok = copy.ok();
    if (!ok) {
        error = "the grid copy does not fit the grid";
    } else if (const IoStatus st = write_grid_npy((path + "/grid").c_str(), copy.value()); !st.ok()) {
        error = std::string("grid: ") + st.message();
        ok = false;
    }
    ok = ok && write_frames(path + "/can.log", error) && write_picture(path + "/picture.png", error) &&
         write_text(path + "/snapshot.txt", error);
    if (ok && ::rename(path.c_str(), final_path.c_str()) != 0) {
        error = errno_text("renaming " + path);
        ok = false;
    }
    if (!ok) {
        static_cast<void>(remove_snapshot_directory(path));
        return false;
    }
    paths_.push_back(final_path);
    return true;
}

bool SnapshotRecorder::write_frames(const std::string& path, std::string& error) const {
    host::FilePtr file = host::open_file(path.c_str(), "w");
    std::FILE* f = file.get();
    if (f == nullptr) {
        error = errno_text(path);
        return false;
    }
    // Plain candump -L lines (canplayer reads them back): the frames before,
    // then after; snapshot.txt says how many of each.
    const auto put = [&](const TimedFrame* frames, std::size_t n) {
        for (std::size_t i = 0U; i < n; ++i) {
            char line[kCandumpLineCapacity];
            if (format_candump_line(line, sizeof line, frames[i].time_us, settings_.interface_name.c_str(),
                                    frames[i].frame) > 0U) {
                static_cast<void>(std::fprintf(f, "%s\n", line));
            }
        }
    };
    put(before_.data(), before_count_);
    put(after_.data(), after_count_);
    if (!host::close_file(file)) {
        error = errno_text("writing " + path);
        return false;
    }
    return true;
}

bool SnapshotRecorder::write_text(const std::string& path, std::string& error) const {
    host::FilePtr file = host::open_file(path.c_str(), "w");
    std::FILE* f = file.get();
    if (f == nullptr) {
        error = errno_text(path);
        return false;
    }
    char faults[256];
    static_cast<void>(std::fprintf(f, "cycle %d\nstarted_us %llu\nstop %d\nwarning %d\nfaults %s\n", cycle_,
                                   static_cast<unsigned long long>(report_.started_us),
                                   report_.safety.stop_requested ? 1 : 0, report_.safety.warning ? 1 : 0,
                                   format_fault_names(report_.safety.latched_faults, faults, sizeof faults)));
    for (std::size_t z = 0U; z < std::min(cfg_->zones.size(), kMaxZones); ++z) {
        static_cast<void>(std::fprintf(f, "zone %s %s foreground %u unseen %u\n", cfg_->zones[z].name.c_str(),
                                       to_string(report_.zones.zones[z].state),
                                       static_cast<unsigned>(report_.zones.zones[z].foreground),
                                       static_cast<unsigned>(report_.zones.zones[z].unseen)));
    }
    std::size_t received = 0U;
    for (std::size_t i = 0U; i < before_count_; ++i) {
        received += before_[i].direction == TapDirection::kReceived ? 1U : 0U;
    }
    for (std::size_t i = 0U; i < after_count_; ++i) {
        received += after_[i].direction == TapDirection::kReceived ? 1U : 0U;
    }
    static_cast<void>(std::fprintf(f,
                                   "can_frames_before %zu\ncan_frames_after %zu\ncan_frames_received %zu\n"
                                   "can_log_time the start of each frame's cycle\n",
                                   before_count_, after_count_, received));
    if (!host::close_file(file)) {
        error = errno_text("writing " + path);
        return false;
    }
    return true;
}

bool SnapshotRecorder::write_picture(const std::string& path, std::string& error) const {
    PictureInput in = picture_;
    in.title = "cellguard stop snapshot: cycle " + std::to_string(cycle_) +
               " (green: evidence at the foreground threshold)";
    PictureLayout layout;
    RgbImage image = render_config_picture(in, &layout);
    const GridDims d = grid_->geometry().dims();
    const int half = std::max(layout.voxel_px / 2, 1);
    for (int iy = 0; iy < d.ny; ++iy) {
        for (int ix = 0; ix < d.nx; ++ix) {
            bool hit = false;
            for (int iz = 0; iz < d.nz && !hit; ++iz) {
                const std::size_t v = static_cast<std::size_t>(ix) +
                                      static_cast<std::size_t>(d.nx) *
                                          (static_cast<std::size_t>(iy) +
                                           static_cast<std::size_t>(d.ny) * static_cast<std::size_t>(iz));
                hit = log_odds_[v] >= cfg_->foreground_threshold &&
                      (v >= in.prior.size() || in.prior[v] >= cfg_->accessible_min_prior);
            }
            if (!hit) {
                continue;
            }
            int px = 0;
            int py = 0;
            top_view_pixel(layout, grid_->geometry(), ix, iy, px, py);
            for (int y = std::max(py - half, 0); y < std::min(py + half, image.height); ++y) {
                for (int x = std::max(px - half, 0); x < std::min(px + half, image.width); ++x) {
                    const std::size_t o = image.offset(x, y);
                    image.rgb[o] = 0U;
                    image.rgb[o + 1U] = 170U;
                    image.rgb[o + 2U] = 0U;
                }
            }
        }
    }
    return write_png(path, image, error);
}

void SnapshotRecorder::prune() noexcept {
    try {
        std::vector<std::string> names;
        if (!list_directory(settings_.directory, names)) {
            return;
        }
        names.erase(
            std::remove_if(names.begin(), names.end(), [](const std::string& n) { return n.rfind("stop-", 0U) != 0U; }),
            names.end());
        std::sort(names.begin(), names.end());  // the UTC time stamp first: oldest first
        for (std::size_t i = 0U; i + settings_.keep < names.size(); ++i) {
            if (remove_snapshot_directory(settings_.directory + "/" + names[i])) {
                removed_.fetch_add(1U, std::memory_order_relaxed);
                paths_.erase(std::remove(paths_.begin(), paths_.end(), settings_.directory + "/" + names[i]),
                             paths_.end());
            }
        }
    } catch (...) {
        // out of memory: nothing removed this time; the next snapshot tries again
    }
}

}  // namespace cellguard::monitor
