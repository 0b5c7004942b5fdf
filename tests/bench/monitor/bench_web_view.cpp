// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The browser view's cost to the cycle (issue 20), figures, not pass/fail:
// the demo monitor's cycle with the live view observer and the HTTP server
// on, first with no client, then with five Server-Sent Events clients
// reading the 10 Hz stream, then with those five and one client fetching
// /api/state back to back, all in the same run and process. Per phase:
// median, p99 and max of the controller's cycle time and of the whole
// run_cycle (with the observers: the live view's copy is in it), and the
// live view's own longest copy. With no client the view skips its voxel
// scan (kLiveDemandWindowUs); the second phase, still without a client,
// notes a demand before each cycle to measure the scan on its own.
//
// usage: bench_web_view [CYCLES_PER_PHASE (default 300)] [GAP_MS (default 20)]
// GAP_MS: the pause between cycles (the server threads run then, as they do
// between paced cycles); 0: back to back.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/live_view.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/web_content.hpp"
#include "cellguard/monitor/web_server.hpp"
#include "cellguard/port/clock.hpp"
#include "monitor_test_doubles.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;

namespace {

/// A client on 127.0.0.1:@p port that sends @p request and reads until @p stop.
void client(int port, const std::string& request, const std::atomic<bool>& stop, std::atomic<std::uint64_t>& bytes,
            bool repeat) {
    do {
        const int fd = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(port));
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (fd < 0 || connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 ||
            send(fd, request.data(), request.size(), 0) != static_cast<ssize_t>(request.size())) {
            if (fd >= 0) {
                close(fd);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
            continue;
        }
        timeval tv{0, 200000};
        setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        char buf[65536];
        while (!stop.load()) {
            const ssize_t n = recv(fd, buf, sizeof buf, 0);
            if (n == 0) {
                break;  // a /api/state reply ends with the connection
            }
            if (n > 0) {
                bytes += static_cast<std::uint64_t>(n);
            }
        }
        close(fd);
    } while (repeat && !stop.load());
}

/// The live view, timed per call (its share of the cycle thread's time).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class TimedView final : public CycleObserver {
public:
    explicit TimedView(LiveView& view) : view_(&view) {}
    void after_cycle(const CycleView& cycle) noexcept override {
        const std::uint64_t t0 = linux_port::monotonic_now_us();
        view_->after_cycle(cycle);
        last_us = linux_port::monotonic_now_us() - t0;
    }
    std::uint64_t last_us = 0U;  ///< the last call's time

private:
    LiveView* view_;
};

/// Median, p99, max of @p v (microseconds) as milliseconds on one line.
void print(const char* phase, const char* what, std::vector<std::uint64_t> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    const std::size_t p99 = std::min(n - 1U, (n * 99U + 99U) / 100U - 1U);
    std::printf("%-40s %-26s median %7.3f ms  p99 %7.3f ms  max %7.3f ms  (%zu cycles)\n", phase, what,
                static_cast<double>(v[n / 2U]) / 1000.0, static_cast<double>(v[p99]) / 1000.0,
                static_cast<double>(v[n - 1U]) / 1000.0, n);
}

}  // namespace

int main(int argc, char** argv) {
    const int per_phase = argc > 1 ? std::max(10, std::atoi(argv[1])) : 300;
    const int gap_ms = argc > 2 ? std::max(0, std::atoi(argv[2])) : 20;
    MonitorConfig cfg = demo_config();
    cfg.budget_us = 60000000U;
    cfg.demo_cycles = per_phase * 4;
    MonitorCell cell;
    if (cell.configure(cfg).failed() || cell.build_prior(cfg, nullptr).failed() ||
        cell.build_tables(cfg, nullptr).failed()) {
        std::fprintf(stderr, "bench_web_view: the demo cell did not build\n");
        return 1;
    }
    std::vector<std::unique_ptr<SimulatedFrameSource>> owned;
    std::vector<FrameSource*> sources;
    for (const sim::SensorSpec& spec : cell.specs) {
        owned.push_back(std::make_unique<SimulatedFrameSource>(spec));
        sources.push_back(owned.back().get());
    }
    linux_port::LinuxMonotonicClock real_clock;  // the controller times its cycles on the real clock
    CycleClock clock(false, real_clock);
    test::CountingSender sender;
    CanPort can;
    can.use_sender(sender);
    MonitorLoop loop(cfg, cell, sources, can, clock, nullptr);
    LiveView view(cfg, cell.frame_grid, cell.prior.data(), cell.prior.size(), cell.zones);
    TimedView timed(view);
    loop.set_observer(&timed);
    WebServer server(view.channel(), make_static_json(cfg, cell.grid, cell.prior.data(), cell.prior.size()));
    WebServerSettings settings;
    settings.page_dir = CELLGUARD_WEB_SOURCE_DIR;
    std::string error;
    if (!loop.status().ok() || !server.start(settings, error)) {
        std::fprintf(stderr, "bench_web_view: %s\n", error.c_str());
        return 1;
    }
    std::printf(
        "bench_web_view: the paper's demo cell (%zu voxels), %d cycles per phase, %d ms between cycles, "
        "server on 127.0.0.1:%d, %u hardware threads\n",
        cell.grid.voxel_count(), per_phase, gap_ms, server.port(), std::thread::hardware_concurrency());
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> bytes{0U};
    std::vector<std::thread> clients;
    const char* phases[4] = {"view on, 0 clients (no scan)", "0 clients, voxel scan forced", "view on, 5 SSE clients",
                             "5 SSE clients + /api/state loop"};
    int k = 0;
    for (int phase = 0; phase < 4; ++phase) {
        if (phase == 2) {
            for (int c = 0; c < 5; ++c) {
                clients.emplace_back(client, server.port(), "GET /api/events HTTP/1.1\r\nHost: b\r\n\r\n",
                                     std::cref(stop), std::ref(bytes), false);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(500));
        } else if (phase == 3) {
            clients.emplace_back(client, server.port(), "GET /api/state HTTP/1.1\r\nHost: b\r\n\r\n", std::cref(stop),
                                 std::ref(bytes), true);
        }
        const std::uint64_t bytes_before = bytes.load();
        const WebCounts before = server.counts();
        std::vector<std::uint64_t> whole;
        std::vector<std::uint64_t> controller;
        std::vector<std::uint64_t> observer;
        for (int i = 0; i < per_phase; ++i, ++k) {
            const std::uint64_t t0 = linux_port::monotonic_now_us();
            if (phase == 1) {
                view.channel().note_demand(t0);
            }
            static_cast<void>(loop.run_cycle(k));
            whole.push_back(linux_port::monotonic_now_us() - t0);
            controller.push_back(loop.stats().cycle_us[static_cast<std::size_t>(k)]);
            observer.push_back(timed.last_us);
            if (gap_ms > 0) {
                std::this_thread::sleep_for(std::chrono::milliseconds(gap_ms));
            }
        }
        const WebCounts after = server.counts();
        print(phases[phase], "controller cycle", controller);
        print(phases[phase], "live view's copy", observer);
        print(phases[phase], "run_cycle (frames+cycle+view)", whole);
        std::printf("%-40s clients read %.1f MB, %llu events sent, %llu requests, %llu busy (503)\n", phases[phase],
                    static_cast<double>(bytes.load() - bytes_before) / 1e6,
                    static_cast<unsigned long long>(after.events - before.events),
                    static_cast<unsigned long long>(after.requests - before.requests),
                    static_cast<unsigned long long>(after.busy - before.busy));
    }
    stop.store(true);
    for (std::thread& t : clients) {
        t.join();
    }
    server.stop();
    std::printf("live view's copy after each cycle (all phases): longest %.3f ms\n",
                static_cast<double>(view.max_us()) / 1000.0);
    return 0;
}
