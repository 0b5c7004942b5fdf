// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file file.hpp
/// `FilePtr`: a C stdio FILE* that closes itself on scope exit, and
/// `open_file` / `close_file`, so that host code that writes or reads whole
/// files with fread/fwrite owns the handle once, here, instead of pairing
/// fopen and fclose by hand on every path; and `read_whole_file`, the one
/// allocation-free read of a whole file into a caller's buffer (POSIX calls:
/// stdio's fopen and first fread allocate), for readers a cycle calls.
#ifndef CELLGUARD_HOST_IO_FILE_HPP
#define CELLGUARD_HOST_IO_FILE_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "cellguard/base/span.hpp"
#include "cellguard/host/io/io_status.hpp"

namespace cellguard::host {

/// Closes a FILE* on scope exit (the result is lost: close_file() checks it).
struct FileCloser {
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): the deleter of FilePtr, which owns the FILE*
    void operator()(std::FILE* f) const noexcept { static_cast<void>(std::fclose(f)); }
};

/// An open C stdio file; closed when it goes out of scope.
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

/// fopen(@p path, @p mode) owned by a FilePtr (empty when fopen fails; errno says why).
[[nodiscard]] inline FilePtr open_file(const char* path, const char* mode) noexcept {
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): FilePtr owns the FILE*
    return FilePtr(std::fopen(path, mode));
}

/// Closes @p file now; false when the stream had a write error or fclose
/// failed (a written file is complete only when this is true).
[[nodiscard]] inline bool close_file(FilePtr& file) noexcept {
    std::FILE* f = file.release();
    if (f == nullptr) {
        return false;
    }
    const bool clean = std::ferror(f) == 0;
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): released from FilePtr above
    return std::fclose(f) == 0 && clean;
}

/// Reads the whole file @p path into @p buffer with open, read (retried on
/// EINTR) and close, allocating nothing; @p got gets the bytes read. Fails
/// with kInvalidArgument ("PATH: cannot open: ..." or "cannot read: ...")
/// or, when the file holds more than buffer.size() bytes (one byte read
/// beyond tells), kStorageTooSmall ("PATH: the file is larger than N bytes").
[[nodiscard]] IoStatus read_whole_file(const char* path, Span<std::uint8_t> buffer, std::size_t& got) noexcept;

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_IO_FILE_HPP
