// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file temp_dir.hpp
/// A new directory under the system's temporary directory for one test,
/// removed with everything in it when the test ends: the one helper the
/// tests that write files share (it was written out in seven test files).
#ifndef CELLGUARD_TEST_TEMP_DIR_HPP
#define CELLGUARD_TEST_TEMP_DIR_HPP

#include <doctest/doctest.h>
#include <stdlib.h>  // mkdtemp (POSIX)

#include <filesystem>
#include <string>
#include <system_error>

namespace cellguard::test {

/// See the file comment.
class TempDir {
public:
    /// Makes TMPDIR/cellguard-@p label-XXXXXX (a test fails when it cannot).
    explicit TempDir(const char* label = "test") {
        std::string templ =
            (std::filesystem::temp_directory_path() / (std::string("cellguard-") + label + "-XXXXXX")).string();
        REQUIRE(::mkdtemp(templ.data()) != nullptr);
        path_ = templ;
    }
    /// Removes the directory and everything in it (errors ignored: a test's leftovers only).
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    TempDir(TempDir&&) = delete;
    TempDir& operator=(TempDir&&) = delete;

    /// The directory.
    [[nodiscard]] const std::string& path() const { return path_; }
    /// The path of @p name inside it.
    [[nodiscard]] std::string file(const std::string& name) const { return path_ + "/" + name; }
    /// The same as file(@p name).
    [[nodiscard]] std::string operator/(const std::string& name) const { return file(name); }

private:
    std::string path_;
};

}  // namespace cellguard::test

#endif  // CELLGUARD_TEST_TEMP_DIR_HPP
