// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file monitoring_cases.hpp
/// Monitoring cases (the field sets of a safety laser scanner): which of the
/// compiled zones are monitored while the PLC selects a case. The zones stay
/// one compiled set (zones.hpp, at most kMaxZones, one membership mask); a
/// case is a subset of them, a uint32 zone mask (bit z: zone z). Case numbers
/// are 0..count()-1, at most kMaxMonitoringCases (robot_command.hpp).
///
/// Rules (tested in test_monitoring_cases.cpp):
/// - Without cases in the configuration there is one case 0 that monitors
///   every zone (all_zones(): the behaviour of a cell without cases).
/// - A commissioned case names at least one zone. A case naming no zone
///   would switch all zone monitoring off, the effect of an all-zeros
///   fault pattern or a forgotten entry; a cell that wants no zone in some
///   phase names a warning zone instead, so the choice stays visible.
/// - A case naming a zone beyond the compiled zones is refused (the zone
///   may have been deleted from the configuration, not from the case).
/// - More than kMaxMonitoringCases cases are refused.
/// - Two cases may name the same zones (a PLC may number its phases freely).
///
/// The set is CRC'd (settings_crc()) like the zones' settings; the
/// controller compares it every cycle with its value at start-up.
#ifndef CELLGUARD_MONITORING_CASES_HPP
#define CELLGUARD_MONITORING_CASES_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"
#include "cellguard/safety/robot_command.hpp"
#include "cellguard/safety/zones.hpp"

namespace cellguard {

/// Why a case set was refused, with the case's number.
struct CaseError {
    ErrorCode code = ErrorCode::kOk;  ///< kInvalidArgument or kCapacityExceeded
    std::size_t case_number = 0U;     ///< the offending case (0 for errors of the whole set)
    const char* reason = "";          ///< static text: what is wrong
};

/// True when @p e means "no error": what Result<T, CaseError> checks.
constexpr bool is_no_error(const CaseError& e) noexcept { return e.code == ErrorCode::kOk; }

/// A checked set of monitoring cases over one compiled zone set. Plain
/// data, fixed capacity, no heap; copyable.
class MonitoringCases {
public:
    /// No case at all (placeholder: contains() is false for every number).
    MonitoringCases() noexcept = default;

    /// The default set for @p zones: one case 0 that monitors every zone.
    [[nodiscard]] static MonitoringCases all_zones(const CompiledZones& zones) noexcept;

    /// Checks @p zone_masks (entry k is case k's zone mask) against
    /// @p zones. An empty span gives all_zones(zones). Errors:
    /// kCapacityExceeded for more than kMaxMonitoringCases cases;
    /// kInvalidArgument for a case naming no zone or a zone beyond
    /// zones.size(); the first failure is returned.
    [[nodiscard]] static Result<MonitoringCases, CaseError> make(const CompiledZones& zones,
                                                                 Span<const std::uint32_t> zone_masks) noexcept;

    /// Number of cases (1..kMaxMonitoringCases once made; 0 for a placeholder).
    [[nodiscard]] std::size_t count() const noexcept { return count_; }
    /// Number of zones the set was made for.
    [[nodiscard]] std::size_t zone_count() const noexcept { return zone_count_; }
    /// True when case @p number exists.
    [[nodiscard]] bool contains(std::size_t number) const noexcept { return number < count_; }
    /// Zone mask of case @p number (checked: contains(number)).
    [[nodiscard]] std::uint32_t zones_of(std::size_t number) const noexcept {
        CG_ENFORCE(number < count_ && number < kMaxMonitoringCases, "monitoring case out of range");
        return masks_[number];
    }
    /// True when the set fits @p zones: made for as many zones, and no
    /// case names a zone beyond them (the controller checks this at start-up).
    [[nodiscard]] bool fits(const CompiledZones& zones) const noexcept;
    /// CRC-32 of the case count, the zone count and every case's mask (each
    /// a uint32 in host byte order: compared only within one run).
    [[nodiscard]] std::uint32_t settings_crc() const noexcept;

private:
    std::uint32_t masks_[kMaxMonitoringCases] = {};
    std::size_t count_ = 0U;
    std::size_t zone_count_ = 0U;
};

}  // namespace cellguard

#endif  // CELLGUARD_MONITORING_CASES_HPP
