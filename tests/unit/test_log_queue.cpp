// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies port/linux's log queue and writer (log_queue.hpp): lines come out
// in order with their priority, a full queue drops and counts lines instead
// of waiting, pushing allocates nothing, several producers lose no line
// uncounted, the writer writes syslog prefixes for the journal and plain
// lines otherwise, reports dropped lines, and JOURNAL_STREAM is matched
// against the descriptor's device and inode.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "alloc_counter.hpp"
#include "cellguard/port/log_queue.hpp"

using cellguard::linux_port::LogLine;
using cellguard::linux_port::LogPriority;
using cellguard::linux_port::LogQueue;
using cellguard::linux_port::LogWriter;

namespace {

/// Everything readable from @p fd now (a pipe whose write end is closed).
std::string read_all(int fd) {
    std::string out;
    char buffer[1024];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n <= 0) {
            return out;
        }
        out.append(buffer, static_cast<std::size_t>(n));
    }
}

}  // namespace

// verifies: SR-SYS-008, SR-GEN-002
TEST_CASE("log queue: lines in order with their priority, a full queue drops and counts, never blocks or allocates") {
    LogQueue q(4U);
    CHECK(q.capacity() == 4U);
    bool pushed[6] = {};
    std::size_t allocations = 0U;
    {
        const cellguard::test::AllocationScope scope;
        for (int i = 0; i < 6; ++i) {
            pushed[i] = q.push(i == 0 ? LogPriority::kError : LogPriority::kInfo, "line %d: %s %.2f ms", i, "zone",
                               1.5 * i);
        }
        allocations = scope.allocations();
    }
    CHECK(allocations == 0U);
    CHECK(pushed[0]);
    CHECK(pushed[3]);
    CHECK_FALSE(pushed[4]);
    CHECK_FALSE(pushed[5]);
    CHECK(q.dropped() == 2U);
    LogLine line;
    REQUIRE(q.pop(line));
    CHECK(std::string(line.text) == "line 0: zone 0.00 ms");
    CHECK(line.priority == LogPriority::kError);
    for (int i = 1; i < 4; ++i) {
        REQUIRE(q.pop(line));
        CHECK(std::string(line.text) == "line " + std::to_string(i) + ": zone " + std::to_string(i * 3 / 2) +
                                            (i % 2 == 1 ? ".50" : ".00") + " ms");
    }
    CHECK_FALSE(q.pop(line));
    // Room again after the writer took them; a line longer than a slot is cut.
    CHECK(q.push(LogPriority::kNotice, "%s", std::string(400, 'a').c_str()));
    REQUIRE(q.pop(line));
    CHECK(std::string(line.text) == std::string(cellguard::linux_port::kLogLineMax, 'a'));
}

// verifies: SR-SYS-008, SR-GEN-002
TEST_CASE("log queue: two producers and a consumer: every line is taken or counted as dropped") {
    LogQueue q(16U);
    constexpr int kLines = 20000;
    std::atomic<bool> done{false};
    std::uint64_t taken = 0U;
    std::thread consumer([&] {
        LogLine line;
        for (;;) {
            if (q.pop(line)) {
                ++taken;
            } else if (done.load()) {
                return;
            }
        }
    });
    const auto produce = [&q](int id) {
        for (int i = 0; i < kLines; ++i) {
            static_cast<void>(q.push(LogPriority::kInfo, "producer %d line %d", id, i));
        }
    };
    std::thread a(produce, 1);
    std::thread b(produce, 2);
    a.join();
    b.join();
    done.store(true);
    consumer.join();
    LogLine line;
    while (q.pop(line)) {
        ++taken;
    }
    CHECK(taken + q.dropped() == 2U * kLines);
    CHECK(taken > 0U);
}

// verifies: SR-SYS-008
TEST_CASE("log writer: syslog prefixes for the journal, plain lines otherwise, dropped lines reported") {
    for (const bool journal : {true, false}) {
        int fds[2];
        REQUIRE(::pipe(fds) == 0);
        LogQueue q(2U);
        {
            LogWriter w(q, fds[1], journal);
            CHECK(q.push(LogPriority::kError, "fault latched: %s", "sensor missing"));
            CHECK(q.push(LogPriority::kInfo, "heartbeat"));
            CHECK_FALSE(q.push(LogPriority::kInfo, "dropped"));  // the writer has not started: the queue is full
            REQUIRE(w.start());
            w.stop();
            CHECK(w.written() == 3U);
        }
        ::close(fds[1]);
        const std::string out = read_all(fds[0]);
        ::close(fds[0]);
        if (journal) {
            CHECK(out ==
                  "<3>fault latched: sensor missing\n<6>heartbeat\n<4>log: 1 lines dropped (queue full), 1 in all\n");
        } else {
            CHECK(out == "fault latched: sensor missing\nheartbeat\nlog: 1 lines dropped (queue full), 1 in all\n");
        }
    }
}

// verifies: SR-SYS-008
TEST_CASE("log writer: JOURNAL_STREAM matches only the descriptor's own device and inode") {
    std::FILE* f = std::tmpfile();
    REQUIRE(f != nullptr);
    const int fd = ::fileno(f);
    struct stat st {};
    REQUIRE(::fstat(fd, &st) == 0);
    const std::string mine = std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    ::setenv("JOURNAL_STREAM", mine.c_str(), 1);
    CHECK(cellguard::linux_port::journal_stream_matches(fd));
    ::setenv("JOURNAL_STREAM", (std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino + 1U)).c_str(), 1);
    CHECK_FALSE(cellguard::linux_port::journal_stream_matches(fd));
    ::setenv("JOURNAL_STREAM", "garbage", 1);
    CHECK_FALSE(cellguard::linux_port::journal_stream_matches(fd));
    ::unsetenv("JOURNAL_STREAM");
    CHECK_FALSE(cellguard::linux_port::journal_stream_matches(fd));
    std::fclose(f);
}
