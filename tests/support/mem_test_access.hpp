// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Test-only access to the sealed fields of SafetyLogic and SafetyController
// (their friends, hazard H-MEM-3): each field as a named byte view, so that
// a test can flip one bit in it as a RAM fault would, and a way to point the
// controller's CRC table check at a copy of the tables.
#ifndef CELLGUARD_TESTS_MEM_TEST_ACCESS_HPP
#define CELLGUARD_TESTS_MEM_TEST_ACCESS_HPP

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cellguard/safety/safety_controller.hpp"
#include "cellguard/safety/safety_logic.hpp"

namespace cellguard {

namespace test {
/// One field of an object: its name and its bytes.
struct Field {
    const char* name;
    std::uint8_t* bytes;
    std::size_t size;
    bool calls_through = false;  ///< a pointer the cycle still calls through after the seal fails (clock, output)
};
template <typename T>
Field field(const char* name, T& value, bool calls_through = false) {
    return Field{name, reinterpret_cast<std::uint8_t*>(&value), sizeof(T), calls_through};
}
/// Flips bit 0 of the field's lowest byte (for a bool: the other valid value).
inline void flip_bit(const Field& f) { f.bytes[0] = static_cast<std::uint8_t>(f.bytes[0] ^ 1U); }
}  // namespace test

struct SafetyLogicTestAccess {
    static std::vector<test::Field> fields(SafetyLogic& l) {
        std::vector<test::Field> f = {
            test::field("config.restart_delay_us", l.config_.restart_delay_us),
            test::field("config.reset_required", l.config_.reset_required),
            test::field("config.fault_recovery_cycles", l.config_.fault_recovery_cycles),
            test::field("zones", l.zones_),
            test::field("latched", l.latched_),
            test::field("have_time", l.have_time_),
            test::field("last_now_us", l.last_now_us_),
            test::field("zone_stop", l.zone_stop_),
            test::field("clear_running", l.clear_running_),
            test::field("clear_since_us", l.clear_since_us_),
            test::field("last_reset", l.last_reset_),
            test::field("state_failed", l.state_failed_),
            test::field("seal", l.seal_),
        };
        for (std::uint32_t& c : l.clean_cycles_) {
            f.push_back(test::field("clean_cycles[]", c));
        }
        return f;
    }
};

struct SafetyControllerTestAccess {
    static std::vector<test::Field> fields(SafetyController& c) {
        ControllerConfig& k = c.config_;
        std::vector<test::Field> f = {
            test::field("config.logic.restart_delay_us", k.logic.restart_delay_us),
            test::field("config.logic.reset_required", k.logic.reset_required),
            test::field("config.logic.fault_recovery_cycles", k.logic.fault_recovery_cycles),
            test::field("config.zones.foreground_threshold", k.zones.foreground_threshold),
            test::field("config.zones.accessible_min_prior", k.zones.accessible_min_prior),
            test::field("config.sensor_count", k.sensor_count),
            test::field("config.max_frame_age_us", k.max_frame_age_us),
            test::field("config.max_repeated_frames", k.max_repeated_frames),
            test::field("config.cycle_budget_us", k.cycle_budget_us),
            test::field("config.prior_check_slice_bytes", k.prior_check_slice_bytes),
            test::field("config.table_check_slice_bytes", k.table_check_slice_bytes),
            test::field("config.zone_check_slice_bytes", k.zone_check_slice_bytes),
            test::field("config.robot_check_slice_bytes", k.robot_check_slice_bytes),
            test::field("config.crc_table_check_values", k.crc_table_check_values),
            test::field("config.rasterization", k.rasterization),
            test::field("config.footprint.method", k.footprint.method),
            test::field("config.footprint.params.exact_footprint_max", k.footprint.params.exact_footprint_max),
            test::field("config.footprint.workspaces", k.footprint.workspaces),
            test::field("config.footprint.runner", k.footprint.runner),
            test::field("config.cases", k.cases),
            test::field("config.stack", k.stack),
            test::field("config.max_command_age_us", k.max_command_age_us),
            test::field("config.robot.image_crc", k.robot.image_crc),
            test::field("config.robot.mask_margin_m", k.robot.mask_margin_m),
            test::field("config.robot.separation.human_speed_mps", k.robot.separation.human_speed_mps),
            test::field("grid", c.grid_),
            test::field("scratch", c.scratch_),
            test::field("prior", c.prior_),
            test::field("zones", c.zones_),
            test::field("model", c.model_),
            test::field("clock", c.clock_, true),
            test::field("output", c.output_, true),
            test::field("pending_faults", c.pending_faults_),
            test::field("construction_faults", c.construction_faults_),
            test::field("zone_settings_crc", c.zone_settings_crc_),
            test::field("zone_settings_failed", c.zone_settings_failed_),
            test::field("table_check_sensor", c.table_check_sensor_),
            test::field("table_failed", c.table_failed_),
            test::field("cases_crc", c.cases_crc_),
            test::field("command_expected", c.command_expected_),
            test::field("active_case", c.active_case_),
            test::field("speed_class", c.speed_class_),
            test::field("robot_settings_crc", c.robot_settings_crc_),
            test::field("crc_table_check", c.crc_table_check_),
            test::field("memory_failed", c.memory_failed_),
            test::field("seal", c.seal_),
        };
        for (auto& t : c.table_checks_) {
            f.push_back(test::field("table_checks[].table", t.table));
        }
        for (auto& h : c.frame_history_) {
            f.push_back(test::field("frame_history[].repeats", h.repeats));
            f.push_back(test::field("frame_history[].fingerprint", h.fingerprint));
        }
        return f;
    }
    /// True while the controller's seal matches its fields.
    static bool seal_matches(const SafetyController& c) { return c.seal_.matches(c.state_crc()); }
    /// Points the controller's CRC table check at @p table and reseals (no fault from the swap itself).
    static void check_crc_table(SafetyController& c, const Crc32Table& table) {
        c.crc_table_check_ = Crc32TableCheck(table);
        c.seal_.seal(c.state_crc());
    }
};

}  // namespace cellguard

#endif
