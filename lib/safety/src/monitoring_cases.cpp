// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/safety/monitoring_cases.hpp"

#include <array>

#include "cellguard/base/crc32.hpp"

namespace cellguard {

MonitoringCases MonitoringCases::all_zones(const CompiledZones& zones) noexcept {
    MonitoringCases c;
    c.count_ = 1U;
    c.zone_count_ = zones.size();
    c.masks_[0] = all_zone_bits(zones.size());
    return c;
}

Result<MonitoringCases, CaseError> MonitoringCases::make(const CompiledZones& zones,
                                                         Span<const std::uint32_t> zone_masks) noexcept {
    if (zone_masks.empty()) {
        return all_zones(zones);
    }
    if (zone_masks.size() > kMaxMonitoringCases) {
        return CaseError{ErrorCode::kCapacityExceeded, 0U, "more monitoring cases than kMaxMonitoringCases (16)"};
    }
    const std::uint32_t known = all_zone_bits(zones.size());
    for (std::size_t k = 0U; k < zone_masks.size(); ++k) {
        if (zone_masks[k] == 0U) {
            return CaseError{ErrorCode::kInvalidArgument, k, "monitoring case names no zone"};
        }
        if ((zone_masks[k] & ~known) != 0U) {
            return CaseError{ErrorCode::kInvalidArgument, k,
                             "monitoring case names a zone beyond the configured zones"};
        }
    }
    MonitoringCases c;
    c.count_ = zone_masks.size();
    c.zone_count_ = zones.size();
    for (std::size_t k = 0U; k < zone_masks.size(); ++k) {
        c.masks_[k] = zone_masks[k];
    }
    return c;
}

bool MonitoringCases::fits(const CompiledZones& zones) const noexcept {
    if (count_ == 0U || count_ > kMaxMonitoringCases || zone_count_ != zones.size()) {
        return false;
    }
    const std::uint32_t known = all_zone_bits(zones.size());
    for (std::size_t k = 0U; k < count_; ++k) {
        if ((masks_[k] & ~known) != 0U) {
            return false;
        }
    }
    return true;
}

std::uint32_t MonitoringCases::settings_crc() const noexcept {
    std::array<std::uint32_t, 2U + kMaxMonitoringCases> words{};
    words[0] = static_cast<std::uint32_t>(count_);
    words[1] = static_cast<std::uint32_t>(zone_count_);
    std::size_t n = 2U;
    for (std::size_t k = 0U; k < count_ && k < kMaxMonitoringCases; ++k) {
        words[n++] = masks_[k];
    }
    return crc32(as_bytes(Span<const std::uint32_t>(words.data(), n)));
}

}  // namespace cellguard
