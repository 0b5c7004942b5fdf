// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file watchdog.hpp
/// A Linux watchdog device (/dev/watchdog, the kernel's watchdog API,
/// Documentation/watchdog/watchdog-api.rst): opening it arms it; the owner
/// must call keepalive() (WDIOC_KEEPALIVE) more often than its timeout, or
/// the hardware (or softdog) resets the machine. stop() is the orderly end:
/// it writes the magic character 'V' and closes, which disarms a driver
/// that allows it (not one built with nowayout). A process that dies or
/// hangs never writes 'V': the device stays armed and the reset follows.
///
/// open(): the device is opened, WDIOC_SETTIMEOUT asks for the timeout and
/// WDIOC_GETTIMEOUT reads back the one the driver took (drivers round). Any
/// failure leaves no device open (a device opened but refused is disarmed
/// with 'V' first) and a message that names the path, the step and errno's
/// text, e.g. "/tmp/x: WDIOC_SETTIMEOUT failed: Inappropriate ioctl for
/// device (not a watchdog device?)". The caller refuses to run then: the
/// watchdog was asked for.
///
/// keepalive(): one ioctl, no heap; a failure is counted and its errno kept
/// (the device can then not be fed: the reset follows, as it should for a
/// controller that cannot feed it).
///
/// The same class name as port/baremetal's watchdog (the CMSDK watchdog
/// of the Cortex-M7 board); the calls differ with the platform.
#ifndef CELLGUARD_PORT_WATCHDOG_HPP
#define CELLGUARD_PORT_WATCHDOG_HPP

#include <cstddef>
#include <cstdint>

namespace cellguard::linux_port {

/// Longest message a Watchdog keeps.
constexpr std::size_t kWatchdogMessageMax = 256U;

/// Longest timeout open() accepts, seconds (the API's unsigned int; drivers allow less).
constexpr int kWatchdogMaxTimeoutS = 3600;

/// What a Watchdog did.
struct WatchdogCounts {
    std::uint64_t keepalives = 0U;  ///< WDIOC_KEEPALIVE calls that succeeded
    std::uint64_t failures = 0U;    ///< WDIOC_KEEPALIVE calls that failed
    int last_errno = 0;             ///< errno of the last failure (0: none)
};

/// See the file comment. Not copyable; one thread calls it (the cycle's).
class Watchdog {
public:
    Watchdog() noexcept = default;
    Watchdog(const Watchdog&) = delete;
    Watchdog& operator=(const Watchdog&) = delete;
    Watchdog(Watchdog&&) = delete;
    Watchdog& operator=(Watchdog&&) = delete;
    /// Closes the device WITHOUT the magic character: a device still open
    /// here (no stop()) stays armed, so an exit that skipped stop() resets.
    ~Watchdog();

    /// Opens @p path and sets the timeout to @p timeout_s (1 .. kWatchdogMaxTimeoutS).
    /// False (nothing open, message() says why) on any failure.
    [[nodiscard]] bool open(const char* path, int timeout_s) noexcept;
    /// Feeds the device; false (counted) when the ioctl fails or none is open.
    bool keepalive() noexcept;
    /// The orderly end: 'V', then close (disarms where the driver allows). True when both succeeded.
    bool stop() noexcept;

    /// A device is open (armed).
    [[nodiscard]] bool is_open() const noexcept { return fd_ >= 0; }
    /// The timeout the driver reported after open(), seconds.
    [[nodiscard]] int timeout_s() const noexcept { return timeout_s_; }
    /// The last error's text ("" when none).
    [[nodiscard]] const char* message() const noexcept { return message_; }
    /// What keepalive() did.
    [[nodiscard]] const WatchdogCounts& counts() const noexcept { return counts_; }

private:
    void fail(const char* path, const char* step, int error) noexcept;
    void disarm_and_close() noexcept;

    int fd_ = -1;
    int timeout_s_ = 0;
    WatchdogCounts counts_{};
    char message_[kWatchdogMessageMax] = {};
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_WATCHDOG_HPP
