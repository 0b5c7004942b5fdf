// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The whole-file read without allocation (file.hpp).
#include "cellguard/host/io/file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace cellguard::host {

IoStatus read_whole_file(const char* path, Span<std::uint8_t> buffer, std::size_t& got) noexcept {
    got = 0U;
    const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open: %s", path, std::strerror(errno));
    }
    IoStatus st;
    bool more = false;
    for (;;) {
        std::uint8_t probe = 0U;
        const bool full = got == buffer.size();
        const ssize_t n = full ? ::read(fd, &probe, 1U) : ::read(fd, buffer.data() + got, buffer.size() - got);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0) {
            st = IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot read: %s", path, std::strerror(errno));
            break;
        }
        if (n == 0) {
            break;  // the end of the file
        }
        if (full) {
            more = true;  // a byte beyond the buffer
            break;
        }
        got += static_cast<std::size_t>(n);
    }
    static_cast<void>(::close(fd));
    if (st && more) {
        st = IoStatus::failure(ErrorCode::kStorageTooSmall, "%s: the file is larger than %zu bytes", path,
                               buffer.size());
    }
    return st;
}

}  // namespace cellguard::host
