// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the host's whole-file read (io/file.hpp, read_whole_file),
// which the recorded-frame sources call every cycle: the file's bytes into
// the caller's buffer without allocating; a file larger than the buffer, a
// missing file and an empty one each give their answer, never a partial
// success.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/io/file.hpp"
#include "temp_dir.hpp"

using namespace cellguard;

namespace {

/// A file of @p n bytes 0, 1, 2, ... (modulo 251) in a new temporary directory, removed at the end.
struct TempFile {
    explicit TempFile(std::size_t n) : path(dir.file("data.bin")) {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        REQUIRE(f != nullptr);
        for (std::size_t i = 0U; i < n; ++i) {
            REQUIRE(std::fputc(static_cast<int>(i % 251U), f) != EOF);
        }
        REQUIRE(std::fclose(f) == 0);
    }
    test::TempDir dir{"file"};
    std::string path;
};

}  // namespace

// verifies: SR-SYS-011
TEST_CASE("file: a whole file is read into the caller's buffer without allocating, to the last byte") {
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{4095}, std::size_t{70000}}) {
        const TempFile file(n);
        std::vector<std::uint8_t> buffer(70000U, 0xEEU);
        std::size_t got = 99U;
        const test::ThreadAllocationScope allocations;
        const IoStatus st = host::read_whole_file(file.path.c_str(), {buffer.data(), buffer.size()}, got);
        CHECK(allocations.allocations() == 0U);
        REQUIRE_MESSAGE(st.ok(), st.message());
        CHECK(got == n);
        bool same = true;
        for (std::size_t i = 0U; i < n; ++i) {
            same = same && buffer[i] == static_cast<std::uint8_t>(i % 251U);
        }
        CHECK(same);
        CHECK(buffer[n < buffer.size() ? n : 0U] == (n < buffer.size() ? 0xEEU : 0U));  // nothing written beyond
    }
}

// verifies: SR-SYS-011
TEST_CASE("file: a file larger than the buffer, a missing file and a directory are refused with the path named") {
    const TempFile file(1001U);
    std::vector<std::uint8_t> buffer(1000U);
    std::size_t got = 0U;
    IoStatus st = host::read_whole_file(file.path.c_str(), {buffer.data(), buffer.size()}, got);
    CHECK(st.error() == ErrorCode::kStorageTooSmall);
    CHECK(std::string(st.message()) == file.path + ": the file is larger than 1000 bytes");
    // Exactly the buffer's size fits (the byte read beyond finds the end).
    std::vector<std::uint8_t> exact(1001U);
    CHECK(host::read_whole_file(file.path.c_str(), {exact.data(), exact.size()}, got).ok());
    CHECK(got == 1001U);
    // An empty buffer holds only an empty file.
    st = host::read_whole_file(file.path.c_str(), {exact.data(), 0U}, got);
    CHECK(st.error() == ErrorCode::kStorageTooSmall);
    const std::string missing = file.dir.file("missing.bin");
    st = host::read_whole_file(missing.c_str(), {buffer.data(), buffer.size()}, got);
    CHECK(st.error() == ErrorCode::kInvalidArgument);
    CHECK(std::string(st.message()).find(missing + ": cannot open: ") == 0U);
    st = host::read_whole_file(file.dir.path().c_str(), {buffer.data(), buffer.size()}, got);  // a directory
    CHECK_FALSE(st.ok());
    CHECK(std::string(st.message()).find(file.dir.path() + ": cannot read: ") == 0U);
}
