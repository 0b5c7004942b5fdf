// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies port/linux's service notification (service.hpp): the messages of
// the notify protocol arrive on NOTIFY_SOCKET as one datagram each, the
// watchdog is kept to one ping per half interval, nothing is sent without
// NOTIFY_SOCKET, and no call allocates (libsystemd's sd_notify included:
// counted by the test binary's malloc hook).
#include <doctest/doctest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/port/service.hpp"

using cellguard::linux_port::ServiceNotifier;

namespace {

/// A unix datagram socket bound to a fresh path, named in NOTIFY_SOCKET
/// while it lives (with WATCHDOG_USEC = @p watchdog_us, 0: unset).
class NotifySocket {
public:
    explicit NotifySocket(unsigned long watchdog_us) {
        fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        REQUIRE(fd_ >= 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::snprintf(addr.sun_path, sizeof addr.sun_path, "/tmp/cellguard-notify-test-%d.sock",
                      static_cast<int>(::getpid()));
        path_ = addr.sun_path;
        ::unlink(path_.c_str());
        REQUIRE(::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0);
        ::setenv("NOTIFY_SOCKET", path_.c_str(), 1);
        ::unsetenv("WATCHDOG_PID");
        if (watchdog_us != 0U) {
            ::setenv("WATCHDOG_USEC", std::to_string(watchdog_us).c_str(), 1);
        } else {
            ::unsetenv("WATCHDOG_USEC");
        }
    }
    ~NotifySocket() {
        ::unsetenv("NOTIFY_SOCKET");
        ::unsetenv("WATCHDOG_USEC");
        ::close(fd_);
        ::unlink(path_.c_str());
    }
    NotifySocket(const NotifySocket&) = delete;
    NotifySocket& operator=(const NotifySocket&) = delete;

    /// The datagrams received so far, one string each.
    std::vector<std::string> messages() const {
        std::vector<std::string> out;
        char buffer[512];
        for (;;) {
            const ssize_t n = ::recv(fd_, buffer, sizeof buffer, MSG_DONTWAIT);
            if (n < 0) {
                return out;
            }
            out.emplace_back(buffer, static_cast<std::size_t>(n));
        }
    }

private:
    int fd_ = -1;
    std::string path_;
};

}  // namespace

// verifies: SR-SYS-007, SR-GEN-002
TEST_CASE("service: READY, STATUS, rate-limited WATCHDOG and STOPPING arrive as datagrams, without the heap") {
    const NotifySocket socket(1000000U);
    ServiceNotifier n;
    if (!cellguard::linux_port::service_notification_built()) {
        CHECK_FALSE(n.enabled());  // built without libsystemd: off, as documented
        return;
    }
    REQUIRE(n.enabled());
    CHECK(n.watchdog_interval_us() == 1000000U);
    bool sent[8] = {};
    std::size_t allocations = 0U;
    const std::string long_status(300, 'x');
    {
        const cellguard::test::AllocationScope scope;
        sent[0] = n.ready("set up");
        sent[1] = n.status("STOP; faults sensor missing");
        sent[2] = n.watchdog(10000000U);            // the first ping
        sent[3] = n.watchdog(10000000U + 499999U);  // before half the interval: none
        sent[4] = n.watchdog(10000000U + 500000U);  // half the interval: a ping
        sent[5] = n.watchdog(10000000U + 900000U);  // none
        sent[6] = n.stopping("stopping");
        sent[7] = n.status(long_status.c_str());  // cut to kServiceStatusMax
        allocations = scope.allocations();
    }
    CHECK(allocations == 0U);
    CHECK(sent[0]);
    CHECK(sent[1]);
    CHECK(sent[2]);
    CHECK_FALSE(sent[3]);
    CHECK(sent[4]);
    CHECK_FALSE(sent[5]);
    CHECK(sent[6]);
    CHECK(sent[7]);
    const std::vector<std::string> m = socket.messages();
    REQUIRE(m.size() == 6U);
    CHECK(m[0] == "READY=1\nSTATUS=set up");
    CHECK(m[1] == "STATUS=STOP; faults sensor missing");
    CHECK(m[2] == "WATCHDOG=1");
    CHECK(m[3] == "WATCHDOG=1");
    CHECK(m[4] == "STOPPING=1\nSTATUS=stopping");
    CHECK(m[5] == "STATUS=" + std::string(cellguard::linux_port::kServiceStatusMax, 'x'));
    CHECK(n.counts().sent == 6U);
    CHECK(n.counts().watchdogs == 2U);
    CHECK(n.counts().failed == 0U);
}

// verifies: SR-SYS-007, SR-GEN-002
TEST_CASE("service: without WATCHDOG_USEC no ping is sent, without NOTIFY_SOCKET nothing is") {
    {
        const NotifySocket socket(0U);
        ServiceNotifier n;
        CHECK(n.watchdog_interval_us() == 0U);
        CHECK_FALSE(n.watchdog(1U));
        if (cellguard::linux_port::service_notification_built()) {
            CHECK(n.ready("x"));
            CHECK(socket.messages().size() == 1U);
        }
    }
    ::unsetenv("NOTIFY_SOCKET");
    ServiceNotifier off;
    CHECK_FALSE(off.enabled());
    CHECK_FALSE(off.ready("x"));
    CHECK_FALSE(off.status("x"));
    CHECK_FALSE(off.watchdog(1U));
    CHECK_FALSE(off.stopping("x"));
    CHECK(off.counts().sent == 0U);
    CHECK(off.counts().failed == 0U);
}

// verifies: SR-SYS-007, SR-GEN-002
TEST_CASE("service: a NOTIFY_SOCKET nobody listens on counts failures, never blocks or crashes") {
    ::setenv("NOTIFY_SOCKET", "/tmp/cellguard-no-such-notify-socket", 1);
    ::unlink("/tmp/cellguard-no-such-notify-socket");
    ServiceNotifier n;
    CHECK_FALSE(n.ready("x"));
    CHECK_FALSE(n.stopping("x"));
    if (cellguard::linux_port::service_notification_built()) {
        CHECK(n.counts().failed == 2U);
    }
    ::unsetenv("NOTIFY_SOCKET");
}
