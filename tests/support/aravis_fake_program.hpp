// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Aravis' own fake GigE Vision camera program (arv-fake-gv-camera-0.8, from
// aravis-tools) on 127.0.0.1 for the tests of live cameras: started with
// posix_spawn, killed (SIGKILL) and reaped when the object goes. Only one
// fake can hold 127.0.0.1's GVCP port: the tests that use it run in a network
// namespace of their own (tools/netns-run.sh). A third party's fake, beside
// cellguard's own (apps/fake-camera): the receiver is checked against both.
#ifndef CELLGUARD_TESTS_ARAVIS_FAKE_PROGRAM_HPP
#define CELLGUARD_TESTS_ARAVIS_FAKE_PROGRAM_HPP

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <time.h>

#include <cstdint>
#include <string>
#include <vector>

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn's environment

namespace cellguard::test {

/// The address the fake listens on.
constexpr const char* kFakeCameraAddress = "127.0.0.1";

/// CLOCK_MONOTONIC, microseconds.
inline std::uint64_t monotonic_now_us() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return static_cast<std::uint64_t>(t.tv_sec) * 1000000U + static_cast<std::uint64_t>(t.tv_nsec) / 1000U;
}

/// Sleeps @p ms milliseconds.
inline void sleep_ms(long ms) {
    const timespec t{ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, nullptr);
}

/// Polls @p done every 20 ms for up to @p timeout_ms; true when it became true.
template <typename F>
bool wait_for(F done, long timeout_ms) {
    const std::uint64_t until = monotonic_now_us() + static_cast<std::uint64_t>(timeout_ms) * 1000U;
    while (monotonic_now_us() < until) {
        if (done()) {
            return true;
        }
        sleep_ms(20);
    }
    return done();
}

/// The fake camera program while the object lives.
class FakeGigeCamera {
public:
    /// Starts it with serial @p serial, losing @p loss_per_thousand of its packets.
    explicit FakeGigeCamera(const std::string& serial, int loss_per_thousand = 0) {
        started_ = start(serial, loss_per_thousand);
    }
    FakeGigeCamera(const FakeGigeCamera&) = delete;
    FakeGigeCamera& operator=(const FakeGigeCamera&) = delete;
    FakeGigeCamera(FakeGigeCamera&&) = delete;
    FakeGigeCamera& operator=(FakeGigeCamera&&) = delete;
    ~FakeGigeCamera() { kill_now(); }

    /// True when the program was started.
    [[nodiscard]] bool started() const { return started_; }

    /// (Re)starts the program (after kill_now()); true when it was started.
    bool start(const std::string& serial, int loss_per_thousand) {
        std::vector<std::string> args = {"arv-fake-gv-camera-0.8", "-i", kFakeCameraAddress, "-s", serial};
        if (loss_per_thousand > 0) {
            args.emplace_back("-r");
            args.push_back(std::to_string(loss_per_thousand));
        }
        std::vector<char*> argv;
        for (std::string& a : args) {
            argv.push_back(a.data());
        }
        argv.push_back(nullptr);
        if (posix_spawnp(&pid_, argv[0], nullptr, nullptr, argv.data(), environ) != 0) {
            pid_ = -1;
            return false;
        }
        sleep_ms(500);  // it binds its sockets
        return true;
    }

    /// Kills the program at once (a camera losing power) and reaps it.
    void kill_now() {
        if (pid_ > 0) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            waitpid(pid_, &status, 0);
            pid_ = -1;
        }
    }

private:
    pid_t pid_ = -1;
    bool started_ = false;
};

}  // namespace cellguard::test

#endif  // CELLGUARD_TESTS_ARAVIS_FAKE_PROGRAM_HPP
