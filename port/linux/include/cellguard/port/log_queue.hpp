// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file log_queue.hpp
/// Logging that never blocks the cycle: a LogQueue of fixed line slots
/// (allocated at construction) into which any thread formats a line with a
/// syslog priority, and a LogWriter thread that takes the lines out and
/// writes them to a file descriptor (stderr).
///
/// The queue is a bounded lock-free multi-producer queue (D. Vyukov's
/// bounded MPMC queue with one consumer): a producer claims a slot with one
/// compare-and-swap, formats straight into it with vsnprintf and publishes
/// it; a full queue drops the line and counts it (dropped()). No producer
/// waits for another or for the writer; nothing is allocated after
/// construction. A producer wakes the writer with sem_post, which does not
/// block.
///
/// The writer, under systemd (journal_stream_matches(): $JOURNAL_STREAM
/// names the descriptor's device and inode, see systemd.exec(5)), starts each
/// line with the syslog prefix "<N>" so that journald records priority N;
/// otherwise it writes plain lines. When lines were dropped it writes, at
/// priority warning, how many since the last report. stop() writes what is
/// left in the queue and joins the thread.
#ifndef CELLGUARD_PORT_LOG_QUEUE_HPP
#define CELLGUARD_PORT_LOG_QUEUE_HPP

#include <semaphore.h>

#include <atomic>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>

namespace cellguard::linux_port {

/// syslog priorities (RFC 5424 severities), as journald reads them.
enum class LogPriority : std::uint8_t {
    kEmergency = 0,  ///< the system is unusable
    kAlert = 1,      ///< act now
    kCritical = 2,   ///< critical condition
    kError = 3,      ///< error: a fault latched
    kWarning = 4,    ///< warning: a protective stop, dropped log lines
    kNotice = 5,     ///< normal but significant: a release, a fault cleared
    kInfo = 6,       ///< informational: the heartbeat
    kDebug = 7,      ///< debugging
};

/// Longest line kept (without the prefix and newline); longer ones are cut.
constexpr std::size_t kLogLineMax = 238U;

/// One queued line.
struct LogLine {
    LogPriority priority = LogPriority::kInfo;  ///< its priority
    char text[kLogLineMax + 1U] = {};           ///< NUL-terminated text, no newline
};

/// See the file comment.
class LogQueue {
public:
    /// A queue of @p capacity lines (rounded up to a power of two, at least 2).
    explicit LogQueue(std::size_t capacity);

    /// Formats a line into a free slot; false (and counted in dropped()) when
    /// the queue is full. Never blocks, never allocates.
    // NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
    bool push(LogPriority priority, const char* format, ...) noexcept __attribute__((format(printf, 3, 4)));
    /// push() with the arguments in @p args.
    bool vpush(LogPriority priority, const char* format, va_list args) noexcept __attribute__((format(printf, 3, 0)));
    /// Takes the oldest line into @p out; false when none is ready. One
    /// consumer only (the writer, or a test).
    bool pop(LogLine& out) noexcept;
    /// Lines dropped because the queue was full, since construction.
    [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
    /// Lines the queue holds at most.
    [[nodiscard]] std::size_t capacity() const noexcept { return mask_ + 1U; }
    /// Binds the semaphore posted after each push (nullptr: none).
    void set_wakeup(sem_t* wakeup) noexcept { wakeup_ = wakeup; }

private:
    struct Slot {
        std::atomic<std::size_t> sequence{0U};
        LogLine line;
    };
    std::unique_ptr<Slot[]>
        slots_;  // NOLINT(cppcoreguidelines-avoid-c-arrays,hicpp-avoid-c-arrays,modernize-avoid-c-arrays): a fixed array made once
    std::size_t mask_;
    std::atomic<std::size_t> enqueue_{0U};
    std::size_t dequeue_ = 0U;
    std::atomic<std::uint64_t> dropped_{0U};
    sem_t* wakeup_ = nullptr;
};

/// Makes the calling thread a background thread: SCHED_OTHER (a thread made
/// after --realtime's SCHED_FIFO would inherit it) with nice value @p nice
/// (0..19), so that it never preempts the cycle. False when refused.
bool make_background_thread(int nice) noexcept;

/// True when $JOURNAL_STREAM ("DEVICE:INODE") names the file @p fd is open on:
/// the descriptor is connected to journald by systemd.
[[nodiscard]] bool journal_stream_matches(int fd) noexcept;

/// The thread that writes a LogQueue's lines to a file descriptor.
class LogWriter {
public:
    /// Writes @p queue's lines to @p fd, with syslog prefixes when
    /// @p syslog_prefix. Both must outlive the writer. Call start().
    LogWriter(LogQueue& queue, int fd, bool syslog_prefix) noexcept;
    LogWriter(const LogWriter&) = delete;
    LogWriter& operator=(const LogWriter&) = delete;
    LogWriter(LogWriter&&) = delete;
    LogWriter& operator=(LogWriter&&) = delete;
    /// Stops the thread (stop()).
    ~LogWriter();

    /// Starts the thread; false when it could not start (then lines stay queued).
    bool start() noexcept;
    /// Writes what is queued, ends the thread and joins it. Idempotent.
    void stop() noexcept;
    /// Lines written so far.
    [[nodiscard]] std::uint64_t written() const noexcept { return written_.load(std::memory_order_relaxed); }

private:
    void run() noexcept;
    void drain() noexcept;
    void write_line(LogPriority priority, const char* text) noexcept;

    LogQueue* queue_;
    int fd_;
    bool prefix_;
    sem_t wakeup_{};
    std::atomic<bool> stopping_{false};
    std::atomic<std::uint64_t> written_{0U};
    std::uint64_t dropped_reported_ = 0U;
    std::thread thread_;
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_LOG_QUEUE_HPP
