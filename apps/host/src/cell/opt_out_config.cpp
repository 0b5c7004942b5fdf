// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The monitor configuration's [opt_out] table: every protection the
// configuration can turn off is on unless [opt_out] names it with a stated
// reason; a protection turned off without its entry, an entry that names no
// protection, and an entry for a protection that is not off are refused.
#include <toml++/toml.h>

#include <algorithm>
#include <string>

#include "config_loader.hpp"

namespace cellguard::cell {
namespace {

/// The protections, in the order they are checked and printed.
constexpr Protection kProtections[] = {
    {"reset_required", "restart_interlock.reset_required = false",
     "the controller's own restart interlock: once the protective zones are clear for delay_ms the stop is "
     "released without a reset, so the PLC must hold the restart until its reset button is pressed "
     "(ISO 13849-1, 5.2.2)"},
    {"clock_rate_check", "can.command_period_ms absent or 0 in a cell with a robot or [[cases]]",
     "the check of the controller's clock rate against the PLC's samples (kClockFault): a controller clock "
     "that runs fast or slow shortens or stretches every time limit unnoticed"},
    {"frozen_sensor_check", "cycle.max_repeated_frames = 0",
     "the frozen-sensor check: a sensor that keeps delivering the same image (a hung driver, a stuck "
     "camera buffer) is fused as if live, and a person entering its view is not seen"},
    {"background_view_check", "cycle.background_match = 0",
     "the check that each frame still shows its sensor's view of the empty cell: a moved, turned or "
     "covered sensor is not detected"},
    {"background_change_check", "cycle.background_changed_cycles = 0",
     "the changed-background check: space seen deeper than at commissioning (a removed object, a turned "
     "sensor) does not latch the prior fault"},
    {"camera_stamp_tolerance", "a camera's max_stamp_error_ms above the default 20",
     "part of the device clock check: a camera clock that jumps or drifts by less than the widened "
     "tolerance is not detected, and a frame may be that much older than its stamp says"},
    {"camera_identity_check", "a camera opened by address without expected_serial",
     "the check of the camera's serial number at every (re)connection: another camera given that address "
     "(a swapped or misplaced device) is used as this sensor"},
    {"watchdog_device", "the monitor opens no watchdog device (/dev/watchdog by default)",
     "the hardware watchdog: a hung monitor or kernel is not reset by the machine; only systemd's "
     "WatchdogSec= (which needs a working kernel) remains"},
};

/// Where an error about a setting is reported: the key's node, else its table, else the root.
toml::source_region where(const toml::table& root, const char* table, const char* key) {
    const toml::table* t = root.get_as<toml::table>(table);
    if (t == nullptr) {
        return root.source();
    }
    const toml::node* n = t->get(key);
    return n != nullptr ? n->source() : t->source();
}

/// Whether protection @p name is off in @p c, and where the setting that turns it off is.
bool is_off(const std::string& name, const MonitorConfig& c, const toml::table& root, toml::source_region& at) {
    if (name == "reset_required") {
        at = where(root, "restart_interlock", "reset_required");
        return !c.reset_required;
    }
    if (name == "clock_rate_check") {
        at = where(root, "can", "command_period_ms");
        return (c.robot.enabled || !c.cases.empty()) && c.can.clock_rate.nominal_period_us == 0U;
    }
    if (name == "frozen_sensor_check") {
        at = where(root, "cycle", "max_repeated_frames");
        return c.max_repeated_frames == 0U;
    }
    if (name == "background_view_check") {
        at = where(root, "cycle", "background_match");
        return c.background_match <= 0.0F;
    }
    if (name == "background_change_check") {
        at = where(root, "cycle", "background_changed_cycles");
        return c.background_changed_cycles == 0U;
    }
    const bool stamp = name == "camera_stamp_tolerance";
    if (stamp || name == "camera_identity_check") {
        at = root.source();
        const toml::array* sensors = root.get_as<toml::array>("sensors");
        for (std::size_t i = 0U; i < c.sensors.size(); ++i) {
            const CameraSettings& cam = c.sensors[i].camera;
            const bool off = cam.enabled && (stamp ? cam.max_stamp_error_us > kDefaultMaxStampErrorUs
                                                   : !cam.address.empty() && cam.expected_serial.empty());
            if (off) {
                const toml::table* s = sensors != nullptr ? sensors->get_as<toml::table>(i) : nullptr;
                if (s != nullptr) {
                    at = where(*s, "camera", stamp ? "max_stamp_error_ms" : "address");
                }
                return true;
            }
        }
        return false;
    }
    return true;  // watchdog_device: the entry itself turns the device off (the monitor reads it)
}

}  // namespace

const Protection* protections(std::size_t& count) {
    count = sizeof kProtections / sizeof kProtections[0];
    return kProtections;
}

bool opted_out(const MonitorConfig& cfg, const char* name) {
    return std::any_of(cfg.opt_outs.begin(), cfg.opt_outs.end(), [name](const OptOut& o) { return o.name == name; });
}

namespace config_detail {

void load_opt_out(const Loader& L, const toml::table& root, MonitorConfig& c) {
    const toml::table* t = nullptr;
    if (root.contains("opt_out")) {
        t = &L.table(root, "", "opt_out");
    }
    std::size_t count = 0U;
    const Protection* list = protections(count);
    if (t != nullptr) {
        for (const auto& [key, node] : *t) {
            const std::string name(key.str());
            bool known = false;
            for (std::size_t i = 0U; i < count; ++i) {
                known = known || name == list[i].name;
            }
            if (!known) {
                std::string names;
                for (std::size_t i = 0U; i < count; ++i) {
                    names += std::string(i == 0U ? "" : ", ") + list[i].name;
                }
                L.fail(node.source(), "opt_out." + name, "names no protection (known: " + names + ")");
            }
            const std::string* reason = node.is_string() ? &node.as_string()->get() : nullptr;
            if (reason == nullptr || reason->find_first_not_of(" \t") == std::string::npos) {
                L.fail(node.source(), "opt_out." + name,
                       "expected the reason for turning the protection off, a non-empty string");
            }
        }
    }
    for (std::size_t i = 0U; i < count; ++i) {
        const Protection& p = list[i];
        toml::source_region at;
        const bool off = is_off(p.name, c, root, at);
        const toml::node* entry = t != nullptr ? t->get(p.name) : nullptr;
        if (entry == nullptr) {
            if (off && std::string(p.name) != "watchdog_device") {
                L.fail(at, std::string("opt_out.") + p.name,
                       std::string("missing: ") + p.setting + " turns off " + p.loses +
                           "; turn it back on, or state why in [opt_out] " + p.name + " = \"<reason>\"");
            }
            continue;
        }
        if (!off) {
            L.fail(entry->source(), std::string("opt_out.") + p.name,
                   std::string("the protection is not off (it is off only with ") + p.setting + "): remove this entry");
        }
        c.opt_outs.push_back(OptOut{p.name, entry->as_string()->get(), p.setting, p.loses});
    }
}

}  // namespace config_detail
}  // namespace cellguard::cell
