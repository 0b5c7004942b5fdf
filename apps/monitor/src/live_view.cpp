// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The browser view's side of the cycle (live_view.hpp).
#include "cellguard/monitor/live_view.hpp"

#include <algorithm>
#include <cstring>

#include "cellguard/grid/log_odds.hpp"
#include "cellguard/port/clock.hpp"

namespace cellguard::monitor {

void SnapshotChannel::begin() noexcept {
    const std::uint64_t s = sequence_.load(std::memory_order_relaxed);
    sequence_.store(s + 1U, std::memory_order_relaxed);   // odd: a write in progress
    std::atomic_thread_fence(std::memory_order_release);  // the odd sequence is seen before any new word
}

void SnapshotChannel::end() noexcept {
    const std::uint64_t s = sequence_.load(std::memory_order_relaxed);
    sequence_.store(s + 1U, std::memory_order_release);  // even: the words before it are visible with it
}

void SnapshotChannel::publish(const LiveSnapshot& s) noexcept {
    begin();
    const auto* bytes = reinterpret_cast<const unsigned char*>(&s);  // trivially copyable (static_assert)
    for (std::size_t i = 0U; i < kWords; ++i) {
        std::uint64_t w = 0U;
        const std::size_t off = i * 8U;
        std::memcpy(&w, bytes + off, std::min<std::size_t>(8U, sizeof(LiveSnapshot) - off));
        words_[i].store(w, std::memory_order_relaxed);
    }
    end();
}

bool SnapshotChannel::read(LiveSnapshot& out, int attempts) const noexcept {
    auto* bytes = reinterpret_cast<unsigned char*>(&out);
    for (int a = 0; a < attempts; ++a) {
        const std::uint64_t before = sequence_.load(std::memory_order_acquire);
        if ((before & 1U) == 0U) {
            for (std::size_t i = 0U; i < kWords; ++i) {
                const std::uint64_t w = words_[i].load(std::memory_order_relaxed);
                const std::size_t off = i * 8U;
                std::memcpy(bytes + off, &w, std::min<std::size_t>(8U, sizeof(LiveSnapshot) - off));
            }
            std::atomic_thread_fence(std::memory_order_acquire);  // the words are read before the check
            if (sequence_.load(std::memory_order_relaxed) == before) {
                return true;
            }
        }
        retries_.fetch_add(1U, std::memory_order_relaxed);
    }
    return false;
}

LiveView::LiveView(const cell::MonitorConfig& cfg, const EvidenceGrid& grid, const std::int16_t* prior,
                   std::size_t prior_size, const CompiledZones& zones)
    : grid_(&grid),
      prior_(prior),
      prior_size_(prior_size),
      zones_(&zones),
      foreground_threshold_(cfg.foreground_threshold),
      accessible_min_prior_(cfg.accessible_min_prior),
      staging_(std::make_unique<LiveSnapshot>()),
      channel_(std::make_unique<SnapshotChannel>()) {}

void LiveView::scan(std::uint32_t active) noexcept {
    LiveSnapshot& s = *staging_;
    const std::size_t n = std::min(grid_->voxel_count(), prior_size_);
    const std::int16_t* lo = grid_->log_odds().data();
    const std::uint8_t* observed = grid_->observed().data();
    const std::uint32_t* mask = zones_->membership().data();
    const std::size_t mask_size = zones_->membership().size();
    std::uint32_t fg = 0U;
    std::uint32_t unseen = 0U;
    // The robot's voxels are neither foreground nor unseen (zone_evaluation.cpp), in cycles that placed it.
    const std::uint8_t* robot = s.capsule_count > 0U && robot_mask_size_ >= n ? robot_mask_ : nullptr;
    for (std::size_t i = 0U; i < n; ++i) {
        if (robot != nullptr && robot[i] != 0U) {
            continue;
        }
        // As the zone evaluation decides (zone_evaluation.cpp): foreground when frame + prior reach t_f;
        // unseen when no sensor observed an accessible voxel (unknown space is never taken for empty).
        if (add_saturating(lo[i], prior_[i]) >= foreground_threshold_) {
            if (fg < kLiveMaxForeground) {
                s.foreground[fg] = static_cast<std::uint32_t>(i);
            }
            ++fg;
        } else if (i < mask_size && observed[i] == 0U && (mask[i] & active) != 0U && prior_[i] != kNeverForeground &&
                   prior_[i] >= accessible_min_prior_) {
            if (unseen < kLiveMaxUnseen) {
                s.unseen[unseen] = static_cast<std::uint32_t>(i);
            }
            ++unseen;
        }
    }
    s.foreground_total = fg;
    s.foreground_count = std::min<std::uint32_t>(fg, kLiveMaxForeground);
    s.unseen_total = unseen;
    s.unseen_count = std::min<std::uint32_t>(unseen, kLiveMaxUnseen);
}

void LiveView::copy_robot(const CycleReport& r) noexcept {
    LiveSnapshot& s = *staging_;
    s.capsule_count = 0U;
    if (controller_ == nullptr || !r.robot.configured || !r.robot.command_valid || r.robot.robot_voxels == 0U) {
        return;  // no pose placed in this cycle
    }
    const RobotPose& pose = controller_->robot_pose();
    const std::size_t n = std::min<std::size_t>(pose.count, kMaxRobotCapsules);
    for (std::size_t c = 0U; c < n; ++c) {
        const PlacedCapsule& p = pose.capsules[c];
        LiveCapsule& l = s.capsules[c];
        for (std::size_t i = 0U; i < 3U; ++i) {
            l.a[i] = static_cast<float>(p.a[i]);
            l.b[i] = static_cast<float>(p.b[i]);
        }
        l.radius = static_cast<float>(p.radius);
    }
    s.capsule_count = static_cast<std::uint32_t>(n);
}

void LiveView::after_cycle(const CycleView& cycle) noexcept {
    const std::uint64_t start = linux_port::monotonic_now_us();
    const CycleReport& r = *cycle.report;
    LiveSnapshot& s = *staging_;
    s.valid = 1U;
    s.k = cycle.k;
    s.cycle = r.cycle;
    s.started_us = r.started_us;
    s.cycle_us = cycle.cycle_us;
    s.stop = r.safety.stop_requested ? 1U : 0U;
    s.warning = r.safety.warning ? 1U : 0U;
    s.reduced_speed = r.safety.reduced_speed ? 1U : 0U;
    s.separation_stop = r.safety.separation_stop ? 1U : 0U;
    s.robot = r.robot.configured ? 1U : 0U;
    s.active_case = r.robot.active_case;
    s.distance_mm = r.robot.distance_mm;
    s.required_mm = r.robot.required_mm;
    s.latched_faults = r.safety.latched_faults;
    s.intruded_mask = r.safety.intruded_mask;
    s.unseen_mask = r.safety.unseen_mask;
    s.fault_zone_mask = r.safety.fault_zone_mask;
    s.active_mask = r.zones.active_mask;
    s.zone_count = static_cast<std::uint32_t>(std::min<std::size_t>(r.zones.count, kMaxZones));
    for (std::size_t z = 0U; z < s.zone_count; ++z) {
        const ZoneReport& zr = r.zones.zones[z];
        s.zones[z] = LiveZone{static_cast<std::uint8_t>(zr.state),
                              static_cast<std::uint8_t>((r.zones.active_mask >> z) & 1U), zr.foreground, zr.unseen,
                              zr.robot};
    }
    copy_robot(r);
    const std::uint64_t demand = channel_->last_demand_us();
    s.voxels = demand != 0U && start - std::min(start, demand) < kLiveDemandWindowUs ? 1U : 0U;
    if (s.voxels != 0U) {
        scan(r.zones.active_mask);
    } else {
        s.foreground_total = 0U;
        s.foreground_count = 0U;
        s.unseen_total = 0U;
        s.unseen_count = 0U;
    }
    const std::uint64_t now = linux_port::monotonic_now_us();
    s.published_us = now;
    channel_->publish(s);
    const std::uint64_t us = linux_port::monotonic_now_us() - start;
    if (us > max_us_.load(std::memory_order_relaxed)) {
        max_us_.store(us, std::memory_order_relaxed);
    }
}

}  // namespace cellguard::monitor
