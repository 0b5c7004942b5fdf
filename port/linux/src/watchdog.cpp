// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A Linux watchdog device (watchdog.hpp).
#include "cellguard/port/watchdog.hpp"

#include <fcntl.h>
#include <linux/watchdog.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace cellguard::linux_port {

Watchdog::~Watchdog() {
    if (fd_ >= 0) {
        static_cast<void>(::close(fd_));  // no 'V': stays armed (see the file comment)
    }
}

void Watchdog::fail(const char* path, const char* step, int error) noexcept {
    const char* hint = error == ENOTTY  ? " (not a watchdog device?)"
                       : error == EBUSY ? " (another process holds it: one opener at a time)"
                       : error == ENXIO ? " (a FIFO without a reader, or no such device)"
                                        : "";
    static_cast<void>(
        std::snprintf(message_, sizeof message_, "%s: %s failed: %s%s", path, step, std::strerror(error), hint));
}

void Watchdog::disarm_and_close() noexcept {
    struct stat st {};
    // Only a character device gets the magic 'V': never write into a regular file or a FIFO.
    if (::fstat(fd_, &st) == 0 && S_ISCHR(st.st_mode)) {
        static_cast<void>(::write(fd_, "V", 1U));
    }
    static_cast<void>(::close(fd_));
    fd_ = -1;
}

bool Watchdog::open(const char* path, int timeout_s) noexcept {
    message_[0] = '\0';
    if (fd_ >= 0) {
        static_cast<void>(std::snprintf(message_, sizeof message_, "%s: a watchdog device is already open", path));
        return false;
    }
    if (path == nullptr || path[0] == '\0' || timeout_s < 1 || timeout_s > kWatchdogMaxTimeoutS) {
        static_cast<void>(std::snprintf(message_, sizeof message_,
                                        "watchdog: a device path and a timeout of 1 .. %d s "
                                        "are needed (got %d s)",
                                        kWatchdogMaxTimeoutS, timeout_s));
        return false;
    }
    // O_NONBLOCK: a FIFO without a reader fails at once (ENXIO) instead of blocking; a watchdog ignores it.
    fd_ = ::open(path, O_WRONLY | O_NONBLOCK | O_CLOEXEC);  // NOLINT(cppcoreguidelines-pro-type-vararg): POSIX
    if (fd_ < 0) {
        fail(path, "open", errno);
        return false;
    }
    int timeout = timeout_s;
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-vararg): the kernel's watchdog API is ioctl
    if (::ioctl(fd_, WDIOC_SETTIMEOUT, &timeout) != 0) {
        fail(path, "WDIOC_SETTIMEOUT", errno);
        disarm_and_close();
        return false;
    }
    timeout = 0;
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-vararg): the kernel's watchdog API is ioctl
    const int got = ::ioctl(fd_, WDIOC_GETTIMEOUT, &timeout);
    if (got != 0 || timeout < 1) {
        fail(path, "WDIOC_GETTIMEOUT", got != 0 ? errno : EINVAL);  // EINVAL: the driver reported no timeout
        disarm_and_close();
        return false;
    }
    timeout_s_ = timeout;
    return true;
}

bool Watchdog::keepalive() noexcept {
    int error = EBADF;
    if (fd_ >= 0) {
        int dummy = 0;
        // NOLINTNEXTLINE(cppcoreguidelines-pro-type-vararg): the kernel's watchdog API is ioctl
        if (::ioctl(fd_, WDIOC_KEEPALIVE, &dummy) == 0) {
            ++counts_.keepalives;
            return true;
        }
        error = errno;
    }
    ++counts_.failures;
    counts_.last_errno = error;
    return false;
}

bool Watchdog::stop() noexcept {
    if (fd_ < 0) {
        return false;
    }
    const bool wrote = ::write(fd_, "V", 1U) == 1;
    const bool closed = ::close(fd_) == 0;
    fd_ = -1;
    return wrote && closed;
}

}  // namespace cellguard::linux_port
