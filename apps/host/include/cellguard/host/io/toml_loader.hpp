// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file toml_loader.hpp
/// What the host programs' TOML loaders (the monitor's configuration, the
/// simulator's scene files) share: the error type whose message names the
/// file, line and column, the unknown-key check and the typed getters.
#ifndef CELLGUARD_HOST_IO_TOML_LOADER_HPP
#define CELLGUARD_HOST_IO_TOML_LOADER_HPP

#include <toml++/toml.h>

#include <Eigen/Core>

#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace cellguard::host {

/// Thrown by TomlLoader::fail, caught by the loader's entry point: the first
/// error, already formatted as "source:line:column: key: what".
struct TomlError : std::runtime_error {
    /// An error that says @p text.
    explicit TomlError(const std::string& text) : std::runtime_error(text), message(text) {}
    std::string message;  ///< the formatted error
};

/// "source:line:column: TOML syntax: description" for a toml++ parse error
/// in @p source.
std::string toml_syntax_error(const std::string& source, const toml::parse_error& e);

/// Reads the file @p path into @p text and sets @p dir to its folder ("."
/// when @p path has no slash); false when the file cannot be opened.
bool read_text_file(const std::string& path, std::string& text, std::string& dir);

/// Typed, checked access to the tables of one TOML file; every error throws
/// a TomlError. Keys are named by their dotted path ("grid.voxel_size").
class TomlLoader {
public:
    /// A loader for the file named @p source in error messages.
    explicit TomlLoader(std::string source);

    /// The file's name in error messages.
    [[nodiscard]] const std::string& source() const { return source_; }

    /// Throws "source:line:column: key: what" at the start of @p where.
    [[noreturn]] void fail(const toml::source_region& where, const std::string& key, const std::string& what) const;

    /// Every key of @p t (at @p path) must be one of @p known, else "unknown key".
    void check_keys(const toml::table& t, const std::string& path, std::initializer_list<const char*> known) const;

    /// @p path + "." + @p key, or @p key at the top level (empty @p path).
    static std::string join(const std::string& path, const std::string& key);

    /// The table @p key of @p parent ("missing table", "expected a table").
    const toml::table& table(const toml::table& parent, const std::string& path, const char* key) const;

    /// The node @p key of @p t ("missing key").
    const toml::node& require(const toml::table& t, const std::string& path, const char* key) const;

    /// @p n as a finite number (an integer or a float), reported as @p key.
    [[nodiscard]] double as_number(const toml::node& n, const std::string& key) const;

    /// @p n as an array of exactly @p count finite numbers, reported as @p key.
    [[nodiscard]] std::vector<double> numbers(const toml::node& n, const std::string& key, std::size_t count) const;

    /// The array of three finite numbers @p key of @p t.
    [[nodiscard]] Eigen::Vector3d vec3(const toml::table& t, const std::string& path, const char* key) const;

    /// The finite number @p key of @p t.
    double number(const toml::table& t, const std::string& path, const char* key) const;

    /// The finite number @p key of @p t, or @p fallback when absent.
    double number_or(const toml::table& t, const std::string& path, const char* key, double fallback) const;

    /// The integer @p key of @p t, in [@p lo, @p hi].
    std::int64_t integer(const toml::table& t, const std::string& path, const char* key, std::int64_t lo,
                         std::int64_t hi) const;

    /// The integer @p key of @p t in [@p lo, @p hi], or @p fallback when absent.
    std::int64_t integer_or(const toml::table& t, const std::string& path, const char* key, std::int64_t lo,
                            std::int64_t hi, std::int64_t fallback) const;

    /// The boolean @p key of @p t, or @p fallback when absent.
    bool boolean_or(const toml::table& t, const std::string& path, const char* key, bool fallback) const;

    /// The string @p key of @p t.
    std::string string(const toml::table& t, const std::string& path, const char* key) const;

    /// The string @p key of @p t, or @p fallback when absent.
    std::string string_or(const toml::table& t, const std::string& path, const char* key,
                          const std::string& fallback) const;

private:
    std::string source_;
};

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_TOML_LOADER_HPP
