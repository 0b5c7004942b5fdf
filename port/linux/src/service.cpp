// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// systemd service notification through sd_notify (service.hpp).
#include "cellguard/port/service.hpp"

#if defined(CELLGUARD_HAVE_LIBSYSTEMD)
#include <systemd/sd-daemon.h>
#endif

#include <cstdio>
#include <cstdlib>

namespace cellguard::linux_port {

bool service_notification_built() noexcept {
#if defined(CELLGUARD_HAVE_LIBSYSTEMD)
    return true;
#else
    return false;
#endif
}

ServiceNotifier::ServiceNotifier() noexcept {
    const char* socket = std::getenv("NOTIFY_SOCKET");  // NOLINT(concurrency-mt-unsafe): read once at start-up
#if defined(CELLGUARD_HAVE_LIBSYSTEMD)
    enabled_ = socket != nullptr && socket[0] != '\0';
#else
    static_cast<void>(socket);  // built without libsystemd: off
#endif
    // > 0: WATCHDOG_USEC is set (and WATCHDOG_PID, if set, is this process).
#if defined(CELLGUARD_HAVE_LIBSYSTEMD)
    std::uint64_t usec = 0U;
    if (enabled_ && sd_watchdog_enabled(0, &usec) > 0) {
        watchdog_us_ = usec;
    }
#endif
}

bool ServiceNotifier::send(const char* prefix, const char* text) noexcept {
    if (!enabled_) {
        return false;
    }
    // "%.200s": a longer status is cut, never overruns message_.
    const int n = std::snprintf(message_, sizeof message_, "%s%.200s", prefix, text);
    if (n <= 0) {
        ++counts_.failed;
        return false;
    }
#if defined(CELLGUARD_HAVE_LIBSYSTEMD)
    const bool sent = sd_notify(0, message_) > 0;
#else
    const bool sent = false;
#endif
    if (sent) {
        ++counts_.sent;
        return true;
    }
    ++counts_.failed;
    return false;
}

bool ServiceNotifier::ready(const char* status) noexcept { return send("READY=1\nSTATUS=", status); }

bool ServiceNotifier::status(const char* text) noexcept { return send("STATUS=", text); }

bool ServiceNotifier::stopping(const char* status) noexcept { return send("STOPPING=1\nSTATUS=", status); }

bool ServiceNotifier::watchdog(std::uint64_t now_us) noexcept {
    if (!enabled_ || watchdog_us_ == 0U) {
        return false;
    }
    if (pinged_ && now_us - last_ping_us_ < watchdog_us_ / 2U) {
        return false;
    }
    if (!send("WATCHDOG=1", "")) {
        return false;
    }
    pinged_ = true;
    last_ping_us_ = now_us;
    ++counts_.watchdogs;
    return true;
}

}  // namespace cellguard::linux_port
