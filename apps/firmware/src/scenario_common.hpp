// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file scenario_common.hpp
/// What the zones-only run (scenario.cpp) and the robot-cell run
/// (robot_scenario.cpp) share: the digest, the digesting CAN sender, text
/// lines, and the canned sensors as controller input. Internal to apps/firmware.
#ifndef CELLGUARD_FIRMWARE_SCENARIO_COMMON_HPP
#define CELLGUARD_FIRMWARE_SCENARIO_COMMON_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/crc32.hpp"
#include "cellguard/can/can_sender.hpp"
#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/firmware/canned_frames.hpp"
#include "cellguard/firmware/scenario.hpp"
#include "cellguard/grid/evidence_grid.hpp"
#include "cellguard/safety/clock.hpp"

namespace cellguard::firmware::detail {

/// The firmware's grid storage (scenario.cpp, .bss, GridStorage::kVoxels
/// each, grid_config.hpp), which both runs use one after the other.
struct FirmwareStorage {
    std::int16_t* log_odds;        ///< the frame grid's log-odds
    std::uint8_t* observed;        ///< the frame grid's observed flags
    std::int16_t* fusion_scratch;  ///< fusion's per-sensor working memory
    std::uint32_t* zone_mask;      ///< the zone membership mask
};
/// The storage; a run uses the first voxel_count() elements of each.
[[nodiscard]] FirmwareStorage firmware_storage() noexcept;

/// Feeds values, little-endian, to the cycle's and the whole run's CRC.
class Digest {
public:
    void bytes(Span<const std::uint8_t> b) noexcept {
        cycle_.update(b);
        total_.update(b);
    }
    void u8(std::uint8_t v) noexcept { bytes(Span<const std::uint8_t>(&v, 1U)); }
    void u32(std::uint32_t v) noexcept {
        const std::uint8_t b[4] = {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8U),
                                   static_cast<std::uint8_t>(v >> 16U), static_cast<std::uint8_t>(v >> 24U)};
        bytes(Span<const std::uint8_t>(b, 4U));
    }
    void u64(std::uint64_t v) noexcept {
        u32(static_cast<std::uint32_t>(v));
        u32(static_cast<std::uint32_t>(v >> 32U));
    }
    void start_cycle() noexcept { cycle_.reset(); }
    [[nodiscard]] std::uint32_t cycle() const noexcept { return cycle_.value(); }
    [[nodiscard]] std::uint32_t total() const noexcept { return total_.value(); }

private:
    Crc32 cycle_;
    Crc32 total_;
};

/// Digests every frame (diagnostics timing masked) and forwards it.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class DigestingSender final : public CanSender {
public:
    DigestingSender(CanSender& inner, std::uint32_t diagnostics_id, Digest& digest) noexcept
        : inner_(&inner), diagnostics_id_(diagnostics_id), digest_(&digest) {}
    bool send(const CanFrame& frame) noexcept override {
        CanFrame m = frame;
        if (m.id == diagnostics_id_) {
            m.data[0] = 0U;                                            // E2E CRC (covers the timing)
            m.data[4] = 0U;                                            // CycleTime bits 32..39
            m.data[5] = 0U;                                            // CycleTime 40..42, MaxCycleTime 43..47
            m.data[6] = static_cast<std::uint8_t>(m.data[6] & 0xC0U);  // MaxCycleTime 48..53; keep the CRC page
        }
        digest_->u32(m.id);
        digest_->u8(m.dlc);
        digest_->bytes(Span<const std::uint8_t>(m.data, sizeof(m.data)));
        ++frames_;
        return inner_->send(frame);
    }
    [[nodiscard]] std::uint32_t frames() const noexcept { return frames_; }

private:
    CanSender* inner_;
    std::uint32_t diagnostics_id_;
    Digest* digest_;
    std::uint32_t frames_ = 0U;
};

/// The canned PLC's receiving side (protocol 0.2): every frame the
/// controller sends goes to the PLC's receiver at @p clock's time, then on
/// to @p inner. The PLC's link frames take their fields (the echo of the
/// controller's sequence) from that receiver (PlcReceiver::next_link).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class PlcTapSender final : public CanSender {
public:
    PlcTapSender(CanSender& inner, PlcReceiver& plc, MonotonicClock& clock) noexcept
        : inner_(&inner), plc_(&plc), clock_(&clock) {}
    bool send(const CanFrame& frame) noexcept override {
        const ReceiverStatus s = plc_->on_frame(frame, clock_->now_us());
        accepted_ += s.communication_valid && frame.id == plc_->config().link.peer.can_id ? 1U : 0U;
        return inner_->send(frame);
    }
    [[nodiscard]] std::uint16_t detail_faults() noexcept override { return inner_->detail_faults(); }
    /// Link frames after which the PLC's receiver was valid (a pair accepted with its link frame).
    [[nodiscard]] std::uint32_t accepted() const noexcept { return accepted_; }

private:
    CanSender* inner_;
    PlcReceiver* plc_;
    MonotonicClock* clock_;
    std::uint32_t accepted_ = 0U;
};

/// A text line built in place.
class Line {
public:
    Line& text(const char* s) noexcept {
        while (*s != '\0' && n_ + 1U < sizeof(buf_)) {
            buf_[n_++] = *s++;
        }
        buf_[n_] = '\0';
        return *this;
    }
    Line& hex(std::uint32_t v) noexcept {
        char b[11];
        format_hex32(v, b);
        return text(b);
    }
    Line& dec(std::uint64_t v) noexcept {
        char b[21];
        format_decimal(v, b);
        return text(b);
    }
    [[nodiscard]] const char* c_str() const noexcept { return buf_; }

private:
    char buf_[200] = {};
    std::size_t n_ = 0U;
};

inline void digest_grid(const EvidenceGrid& grid, Digest& d) noexcept {
    std::uint8_t chunk[256];
    std::size_t used = 0U;
    for (const std::int16_t v : grid.log_odds()) {
        const auto bits = static_cast<std::uint16_t>(v);
        chunk[used++] = static_cast<std::uint8_t>(bits);
        chunk[used++] = static_cast<std::uint8_t>(bits >> 8U);
        if (used == sizeof(chunk)) {
            d.bytes(Span<const std::uint8_t>(chunk, used));
            used = 0U;
        }
    }
    d.bytes(Span<const std::uint8_t>(chunk, used));
    d.bytes(Span<const std::uint8_t>(grid.observed().data(), grid.observed().size()));
}

inline void digest_report(const CycleReport& r, Digest& d) noexcept {
    d.u64(r.cycle);
    d.u32(r.fusion.rays_fused);
    d.u32(r.fusion.readings_in_grid);
    d.u32(r.fusion.skipped());
    d.u64(r.fusion.voxel_updates);
    d.u32(static_cast<std::uint32_t>(r.zones.count));
    for (std::size_t z = 0U; z < r.zones.count; ++z) {
        d.u8(static_cast<std::uint8_t>(r.zones.zones[z].state));
        d.u32(r.zones.zones[z].foreground);
        d.u32(r.zones.zones[z].unseen);
    }
    d.u32(r.detected_faults);
    d.u8(r.safety.stop_requested ? 1U : 0U);
    d.u8(r.safety.warning ? 1U : 0U);
    d.u8(r.safety.interlock_holding ? 1U : 0U);
    d.u32(r.safety.latched_faults);
    d.u32(r.safety.intruded_mask);
    d.u32(r.safety.unseen_mask);
    d.u32(r.safety.fault_zone_mask);
}

inline SensorReading canned_reading(const CannedFrames& frames, std::size_t sensor, std::size_t scene) noexcept {
    const CannedSensor& s = frames.sensor(sensor);
    SensorReading r;
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 4; ++col) {
            m(row, col) = s.pose[static_cast<std::size_t>(row * 4 + col)];
        }
    }
    r.pose.matrix() = m;
    r.kind = SensorDataKind::kDepthImage;
    r.depth = frames.depth(scene, sensor);
    r.intrinsics = PinholeIntrinsics{s.fx, s.fy, s.cx, s.cy, s.width, s.height};
    r.max_range = s.max_range;
    return r;
}

}  // namespace cellguard::firmware::detail

#endif  // CELLGUARD_FIRMWARE_SCENARIO_COMMON_HPP
