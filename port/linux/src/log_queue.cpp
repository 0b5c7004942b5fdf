// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The bounded log queue and its writer thread (log_queue.hpp).
#include "cellguard/port/log_queue.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

namespace cellguard::linux_port {
namespace {

std::size_t round_up_to_power_of_two(std::size_t n) noexcept {
    std::size_t p = 2U;
    while (p < n) {
        p *= 2U;
    }
    return p;
}

// Writes all of @p data to @p fd (retrying after EINTR and short writes); false on an error.
bool write_all(int fd, const char* data, std::size_t size) noexcept {
    while (size > 0U) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return false;
        }
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

}  // namespace

LogQueue::LogQueue(std::size_t capacity) : mask_(round_up_to_power_of_two(capacity) - 1U) {
    slots_ = std::make_unique<Slot[]>(
        mask_ +
        1U);  // NOLINT(cppcoreguidelines-avoid-c-arrays,hicpp-avoid-c-arrays,modernize-avoid-c-arrays): see the member
    for (std::size_t i = 0U; i <= mask_; ++i) {
        slots_[i].sequence.store(i, std::memory_order_relaxed);
    }
}

// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
bool LogQueue::push(LogPriority priority, const char* format, ...) noexcept {
    va_list args;
    va_start(args, format);
    const bool queued = vpush(priority, format, args);
    va_end(args);
    return queued;
}

bool LogQueue::vpush(LogPriority priority, const char* format, va_list args) noexcept {
    std::size_t pos = enqueue_.load(std::memory_order_relaxed);
    Slot* slot = nullptr;
    for (;;) {
        slot = &slots_[pos & mask_];
        const std::size_t seq = slot->sequence.load(std::memory_order_acquire);
        const auto diff = static_cast<std::ptrdiff_t>(seq) - static_cast<std::ptrdiff_t>(pos);
        if (diff == 0) {
            if (enqueue_.compare_exchange_weak(pos, pos + 1U, std::memory_order_relaxed)) {
                break;  // the slot is this producer's until it publishes it
            }
        } else if (diff < 0) {
            dropped_.fetch_add(1U, std::memory_order_relaxed);  // full: the writer has not freed this slot yet
            return false;
        } else {
            pos = enqueue_.load(std::memory_order_relaxed);
        }
    }
    slot->line.priority = priority;
    if (std::vsnprintf(slot->line.text, sizeof slot->line.text, format, args) < 0) {
        slot->line.text[0] = '\0';
    }
    slot->sequence.store(pos + 1U, std::memory_order_release);
    if (wakeup_ != nullptr) {
        static_cast<void>(sem_post(wakeup_));
    }
    return true;
}

bool LogQueue::pop(LogLine& out) noexcept {
    Slot& slot = slots_[dequeue_ & mask_];
    if (slot.sequence.load(std::memory_order_acquire) != dequeue_ + 1U) {
        return false;  // empty, or the next line is still being formatted
    }
    out = slot.line;
    slot.sequence.store(dequeue_ + mask_ + 1U, std::memory_order_release);
    ++dequeue_;
    return true;
}

bool make_background_thread(int nice) noexcept {
    sched_param param{};
    param.sched_priority = 0;
    const bool normal = pthread_setschedparam(pthread_self(), SCHED_OTHER, &param) == 0;
    // Linux: PRIO_PROCESS with a thread id sets that thread's nice value.
    const auto tid = static_cast<id_t>(::syscall(SYS_gettid));
    return setpriority(PRIO_PROCESS, tid, nice) == 0 && normal;
}

bool journal_stream_matches(int fd) noexcept {
    const char* stream = std::getenv("JOURNAL_STREAM");  // NOLINT(concurrency-mt-unsafe): read once at start-up
    if (stream == nullptr) {
        return false;
    }
    unsigned long long device = 0U;
    unsigned long long inode = 0U;
    // NOLINTNEXTLINE(cert-err34-c): the two numbers are checked by the count and compared with fstat's
    if (std::sscanf(stream, "%llu:%llu", &device, &inode) != 2) {
        return false;
    }
    struct stat st {};
    return ::fstat(fd, &st) == 0 && static_cast<unsigned long long>(st.st_dev) == device &&
           static_cast<unsigned long long>(st.st_ino) == inode;
}

LogWriter::LogWriter(LogQueue& queue, int fd, bool syslog_prefix) noexcept
    : queue_(&queue), fd_(fd), prefix_(syslog_prefix) {
    static_cast<void>(sem_init(&wakeup_, 0, 0U));
    queue_->set_wakeup(&wakeup_);
}

LogWriter::~LogWriter() {
    stop();
    queue_->set_wakeup(nullptr);
    static_cast<void>(sem_destroy(&wakeup_));
}

bool LogWriter::start() noexcept {
    if (thread_.joinable()) {
        return true;
    }
    try {
        thread_ = std::thread([this] { run(); });
    } catch (...) {
        return false;  // no thread: the lines stay queued, stop() writes them
    }
    return true;
}

void LogWriter::stop() noexcept {
    stopping_.store(true, std::memory_order_release);
    static_cast<void>(sem_post(&wakeup_));
    if (thread_.joinable()) {
        thread_.join();
    }
    drain();
}

void LogWriter::run() noexcept {
    static_cast<void>(make_background_thread(0));
    while (!stopping_.load(std::memory_order_acquire)) {
        // A line can be published after its sem_post was consumed (the slot
        // was still being formatted when drain() looked): wake up at least
        // every 100 ms to take it.
        timespec until{};
        static_cast<void>(clock_gettime(CLOCK_REALTIME, &until));
        until.tv_nsec += 100000000L;
        until.tv_sec += until.tv_nsec / 1000000000L;
        until.tv_nsec %= 1000000000L;
        static_cast<void>(sem_timedwait(&wakeup_, &until));
        drain();
    }
}

void LogWriter::drain() noexcept {
    LogLine line;
    while (queue_->pop(line)) {
        write_line(line.priority, line.text);
    }
    const std::uint64_t dropped = queue_->dropped();
    if (dropped != dropped_reported_) {
        char text[96];
        static_cast<void>(std::snprintf(text, sizeof text,
                                        "log: %" PRIu64 " lines dropped (queue full), %" PRIu64 " in all",
                                        dropped - dropped_reported_, dropped));
        dropped_reported_ = dropped;
        write_line(LogPriority::kWarning, text);
    }
}

void LogWriter::write_line(LogPriority priority, const char* text) noexcept {
    char buffer[kLogLineMax + 8U];
    const int n = prefix_ ? std::snprintf(buffer, sizeof buffer, "<%u>%s\n", static_cast<unsigned>(priority), text)
                          : std::snprintf(buffer, sizeof buffer, "%s\n", text);
    if (n > 0 && write_all(fd_, buffer, std::min(static_cast<std::size_t>(n), sizeof buffer - 1U))) {
        written_.fetch_add(1U, std::memory_order_relaxed);
    }
}

}  // namespace cellguard::linux_port
