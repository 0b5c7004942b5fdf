// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Checked access to TOML tables with file:line:column error messages.
#include "cellguard/host/io/toml_loader.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

namespace cellguard::host {

std::string toml_syntax_error(const std::string& source, const toml::parse_error& e) {
    std::ostringstream m;
    m << source << ':' << e.source().begin.line << ':' << e.source().begin.column
      << ": TOML syntax: " << e.description();
    return m.str();
}

bool read_text_file(const std::string& path, std::string& text, std::string& dir) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return false;
    }
    std::ostringstream content;
    content << in.rdbuf();
    text = content.str();
    const std::size_t slash = path.find_last_of('/');
    dir = slash == std::string::npos ? "." : path.substr(0U, slash);
    return true;
}

TomlLoader::TomlLoader(std::string source) : source_(std::move(source)) {}

void TomlLoader::fail(const toml::source_region& where, const std::string& key, const std::string& what) const {
    std::ostringstream m;
    m << source_ << ':' << where.begin.line << ':' << where.begin.column << ": " << key << ": " << what;
    throw TomlError(m.str());
}

void TomlLoader::check_keys(const toml::table& t, const std::string& path,
                            std::initializer_list<const char*> known) const {
    for (const auto& [k, node] : t) {
        bool found = false;
        for (const char* name : known) {
            found = found || k.str() == name;
        }
        if (!found) {
            fail(node.source(), join(path, std::string(k.str())), "unknown key");
        }
    }
}

std::string TomlLoader::join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}

const toml::table& TomlLoader::table(const toml::table& parent, const std::string& path, const char* key) const {
    const toml::node* n = parent.get(key);
    if (n == nullptr) {
        fail(parent.source(), join(path, key), "missing table");
    }
    if (!n->is_table()) {
        fail(n->source(), join(path, key), "expected a table");
    }
    return *n->as_table();
}

const toml::node& TomlLoader::require(const toml::table& t, const std::string& path, const char* key) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) {
        fail(t.source(), join(path, key), "missing key");
    }
    return *n;
}

double TomlLoader::as_number(const toml::node& n, const std::string& key) const {
    if (!n.is_number()) {
        fail(n.source(), key, "expected a number");
    }
    const double v = n.is_integer() ? static_cast<double>(n.as_integer()->get()) : n.as_floating_point()->get();
    if (!std::isfinite(v)) {
        fail(n.source(), key, "expected a finite number");
    }
    return v;
}

std::vector<double> TomlLoader::numbers(const toml::node& n, const std::string& key, std::size_t count) const {
    const toml::array* a = n.as_array();
    if (a == nullptr || a->size() != count) {
        fail(n.source(), key, "expected an array of " + std::to_string(count) + " numbers");
    }
    std::vector<double> v;
    for (const toml::node& e : *a) {
        v.push_back(as_number(e, key));
    }
    return v;
}

Eigen::Vector3d TomlLoader::vec3(const toml::table& t, const std::string& path, const char* key) const {
    const std::vector<double> v = numbers(require(t, path, key), join(path, key), 3U);
    return {v[0], v[1], v[2]};
}

double TomlLoader::number(const toml::table& t, const std::string& path, const char* key) const {
    return as_number(require(t, path, key), join(path, key));
}

double TomlLoader::number_or(const toml::table& t, const std::string& path, const char* key, double fallback) const {
    return t.contains(key) ? number(t, path, key) : fallback;
}

std::int64_t TomlLoader::integer(const toml::table& t, const std::string& path, const char* key, std::int64_t lo,
                                 std::int64_t hi) const {
    const toml::node& n = require(t, path, key);
    if (!n.is_integer()) {
        fail(n.source(), join(path, key), "expected an integer");
    }
    const std::int64_t v = n.as_integer()->get();
    if (v < lo || v > hi) {
        fail(n.source(), join(path, key),
             "expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + std::to_string(v));
    }
    return v;
}

std::int64_t TomlLoader::integer_or(const toml::table& t, const std::string& path, const char* key, std::int64_t lo,
                                    std::int64_t hi, std::int64_t fallback) const {
    return t.contains(key) ? integer(t, path, key, lo, hi) : fallback;
}

bool TomlLoader::boolean_or(const toml::table& t, const std::string& path, const char* key, bool fallback) const {
    if (!t.contains(key)) {
        return fallback;
    }
    const toml::node& n = *t.get(key);
    if (!n.is_boolean()) {
        fail(n.source(), join(path, key), "expected true or false");
    }
    return n.as_boolean()->get();
}

std::string TomlLoader::string(const toml::table& t, const std::string& path, const char* key) const {
    const toml::node& n = require(t, path, key);
    if (!n.is_string()) {
        fail(n.source(), join(path, key), "expected a string");
    }
    return n.as_string()->get();
}

std::string TomlLoader::string_or(const toml::table& t, const std::string& path, const char* key,
                                  const std::string& fallback) const {
    return t.contains(key) ? string(t, path, key) : fallback;
}

}  // namespace cellguard::host
