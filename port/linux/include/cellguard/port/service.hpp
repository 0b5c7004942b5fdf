// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file service.hpp
/// systemd service notification (sd_notify(3), the notify protocol of
/// systemd.service Type=notify): READY=1 once the monitor is set up, STATUS=
/// when its state changes, WATCHDOG=1 from the cycle loop, STOPPING=1 at the
/// end. Off (every call returns false, nothing is sent) when NOTIFY_SOCKET is
/// unset, as outside systemd.
///
/// The watchdog: the constructor reads WATCHDOG_USEC (and WATCHDOG_PID) once
/// through sd_watchdog_enabled(). watchdog(now) sends WATCHDOG=1 only when at
/// least half of that interval has passed since the last one it sent, so a
/// loop may call it after every complete cycle: a loop that stops completing
/// cycles stops the pings and systemd acts (WatchdogSec, Restart=). Without
/// WATCHDOG_USEC the watchdog calls send nothing.
///
/// Allocation: the calls use libsystemd's sd_notify. Measured with the test
/// binary's malloc counter (tests/unit/test_service.cpp, libsystemd 252 of
/// Debian 12): sd_notify allocates nothing; it reads NOTIFY_SOCKET, opens a
/// datagram socket, sends one message and closes it (three system calls, no
/// heap). The test keeps that fact checked, so a libsystemd that starts
/// allocating fails it; the texts are formatted into storage of this object.
/// STATUS= texts longer than kServiceStatusMax are cut.
#ifndef CELLGUARD_PORT_SERVICE_HPP
#define CELLGUARD_PORT_SERVICE_HPP

#include <cstddef>
#include <cstdint>

namespace cellguard::linux_port {

/// Longest STATUS= text sent (without "STATUS=").
constexpr std::size_t kServiceStatusMax = 200U;

/// True when this build has libsystemd (else a ServiceNotifier is always off).
[[nodiscard]] bool service_notification_built() noexcept;

/// What a ServiceNotifier sent.
struct ServiceCounts {
    std::uint64_t sent = 0U;       ///< messages systemd accepted (sd_notify > 0)
    std::uint64_t failed = 0U;     ///< messages that could not be sent (sd_notify < 0)
    std::uint64_t watchdogs = 0U;  ///< WATCHDOG=1 messages among sent
};

/// See the file comment. Not thread safe: one thread calls it (the cycle's).
class ServiceNotifier {
public:
    /// Reads NOTIFY_SOCKET and the watchdog interval from the environment.
    ServiceNotifier() noexcept;

    /// NOTIFY_SOCKET is set: the process runs under a service manager that listens.
    [[nodiscard]] bool enabled() const noexcept { return enabled_; }
    /// WATCHDOG_USEC, microseconds (0: no watchdog asked for).
    [[nodiscard]] std::uint64_t watchdog_interval_us() const noexcept { return watchdog_us_; }

    /// Sends READY=1 with STATUS=@p status; true when sent.
    bool ready(const char* status) noexcept;
    /// Sends STATUS=@p text (cut to kServiceStatusMax); true when sent.
    bool status(const char* text) noexcept;
    /// Sends WATCHDOG=1 when the watchdog is on and at least half its
    /// interval has passed since the last ping (the first call always
    /// pings); @p now_us is CLOCK_MONOTONIC in microseconds. True when sent.
    bool watchdog(std::uint64_t now_us) noexcept;
    /// Sends STOPPING=1 with STATUS=@p status; true when sent.
    bool stopping(const char* status) noexcept;

    /// What was sent so far.
    [[nodiscard]] const ServiceCounts& counts() const noexcept { return counts_; }

private:
    bool send(const char* prefix, const char* text) noexcept;

    bool enabled_ = false;
    std::uint64_t watchdog_us_ = 0U;
    bool pinged_ = false;
    std::uint64_t last_ping_us_ = 0U;
    ServiceCounts counts_{};
    char message_[kServiceStatusMax + 32U] = {};  ///< the message being sent
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_SERVICE_HPP
