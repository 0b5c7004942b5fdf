// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The configuration loader's checked getters, shared by config.cpp,
// sensor_config.cpp and robot_config.cpp (private to the host library's cell/ sources).
#ifndef CELLGUARD_HOST_CELL_CONFIG_LOADER_HPP
#define CELLGUARD_HOST_CELL_CONFIG_LOADER_HPP

#include <toml++/toml.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/io/toml_loader.hpp"

namespace cellguard::cell::config_detail {

/// The shared checked getters plus the monitor's own (positive numbers).
class Loader : public host::TomlLoader {
public:
    using TomlLoader::TomlLoader;

    void positive(const toml::table& t, const std::string& path, const char* key, double v) const {
        if (!(v > 0.0)) {
            fail(t.get(key)->source(), join(path, key), "must be greater than 0");
        }
    }
};

/// Milliseconds (finite, checked by the caller) to microseconds, rounded.
inline std::uint64_t ms_to_us(double ms) { return static_cast<std::uint64_t>(std::llround(ms * 1000.0)); }

/// The [[sensors]] tables (after [grid]; sensor_config.cpp).
void load_sensors(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir);
/// The [[cases]] tables (optional; after [[zones]]).
void load_cases(const Loader& L, const toml::table& root, MonitorConfig& c);
/// The [robot], [separation] and [[speed_classes]] tables (optional; after [cycle]).
void load_robot(const Loader& L, const toml::table& root, MonitorConfig& c, const std::string& base_dir);
/// The [opt_out] table (optional; last: it checks every other setting, opt_out_config.cpp).
void load_opt_out(const Loader& L, const toml::table& root, MonitorConfig& c);

}  // namespace cellguard::cell::config_detail

#endif  // CELLGUARD_HOST_CELL_CONFIG_LOADER_HPP
