// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: port/linux's watchdog device (watchdog.hpp) refuses what is
// not a watchdog with a clear message and leaves nothing open or written:
// a missing path, a regular file, a FIFO with and without a reader, a
// character device that is no watchdog (/dev/null), bad arguments. This
// machine has no /dev/watchdog: the good path is not run here.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <linux/watchdog.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "cellguard/port/watchdog.hpp"

using cellguard::linux_port::Watchdog;

namespace {

std::string temp_path(const char* name) {
    return std::string("/tmp/cellguard-watchdog-test-") + std::to_string(::getpid()) + "-" + name;
}

bool contains(const char* text, const char* part) { return std::string(text).find(part) != std::string::npos; }

}  // namespace

// verifies: SR-WDG-002
TEST_CASE("watchdog device: a missing path and bad arguments are refused with a message") {
    Watchdog w;
    CHECK_FALSE(w.open("/nonexistent/cellguard/watchdog", 5));
    CHECK_FALSE(w.is_open());
    CHECK(contains(w.message(), "/nonexistent/cellguard/watchdog: open failed: No such file or directory"));
    CHECK_FALSE(w.open("/dev/null", 0));
    CHECK(contains(w.message(), "timeout of 1 .. 3600 s"));
    CHECK_FALSE(w.open("", 5));
    CHECK_FALSE(w.is_open());
    // Nothing open: keepalive fails and is counted, stop does nothing.
    CHECK_FALSE(w.keepalive());
    CHECK(w.counts().failures == 1U);
    CHECK(w.counts().last_errno == EBADF);
    CHECK_FALSE(w.stop());
}

// verifies: SR-WDG-002
TEST_CASE("watchdog device: a regular file opens but is no watchdog, and is never written") {
    const std::string path = temp_path("file");
    {
        std::FILE* f = std::fopen(path.c_str(), "w");
        REQUIRE(f != nullptr);
        std::fclose(f);
    }
    // What this kernel (or emulator) answers to the watchdog ioctl on a regular file: ENOTTY from
    // Linux; qemu-user answers its own errno for an ioctl it does not translate (seen on aarch64).
    int timeout = 5;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    REQUIRE(fd >= 0);
    const int answer = ::ioctl(fd, WDIOC_SETTIMEOUT, &timeout) == 0 ? 0 : errno;
    ::close(fd);
    REQUIRE(answer != 0);
    Watchdog w;
    CHECK_FALSE(w.open(path.c_str(), 5));
    CHECK_FALSE(w.is_open());
    INFO(w.message());
    const std::string expected = std::string("WDIOC_SETTIMEOUT failed: ") + std::strerror(answer) +
                                 (answer == ENOTTY ? " (not a watchdog device?)" : "");
    CHECK(contains(w.message(), expected.c_str()));
    struct stat st {};
    REQUIRE(::stat(path.c_str(), &st) == 0);
    CHECK(st.st_size == 0);  // no magic 'V' written into a file
    ::unlink(path.c_str());
}

// verifies: SR-WDG-002
TEST_CASE("watchdog device: a FIFO without a reader fails at once, with a reader it is no watchdog") {
    const std::string path = temp_path("fifo");
    ::unlink(path.c_str());
    REQUIRE(::mkfifo(path.c_str(), 0600) == 0);
    Watchdog w;
    CHECK_FALSE(w.open(path.c_str(), 5));  // must not block
    CHECK(contains(w.message(), "open failed: No such device or address (a FIFO without a reader"));
    const int reader = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    REQUIRE(reader >= 0);
    CHECK_FALSE(w.open(path.c_str(), 5));
    CHECK(contains(w.message(), "WDIOC_SETTIMEOUT failed"));
    CHECK_FALSE(w.is_open());
    char c = 0;
    CHECK(::read(reader, &c, 1U) <= 0);  // nothing was written into the FIFO
    ::close(reader);
    ::unlink(path.c_str());
}

// verifies: SR-WDG-002
TEST_CASE("watchdog device: a character device that is no watchdog is refused and closed") {
    Watchdog w;
    CHECK_FALSE(w.open("/dev/null", 5));
    CHECK_FALSE(w.is_open());
    CHECK(contains(w.message(), "/dev/null: WDIOC_SETTIMEOUT failed"));
    CHECK(w.timeout_s() == 0);
}
