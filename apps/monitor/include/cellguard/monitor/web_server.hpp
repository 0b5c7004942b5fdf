// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file web_server.hpp
/// The browser view's HTTP server (issue 20), on CivetWeb (Debian's
/// libcivetweb-dev 1.15). Not a safety function: it reads the LiveView's
/// snapshots (live_view.hpp) and files fixed at start, and changes nothing.
///
/// Every CivetWeb default that is unsafe here is overridden: no document
/// root, no directory listing, no CGI or SSI, no CORS header, URLs not
/// decoded (web_content.hpp checks the raw path), keep-alive off, request
/// head at most 4096 bytes, 2 s request timeout (also the write timeout
/// that drops a client that stops reading), a fixed number of worker
/// threads and a short connection queue. Each request passes
/// check_request() first. The served files are read once at start into
/// memory. Its threads (CivetWeb's master and workers) make themselves
/// background threads (SCHED_OTHER, nice 10) when they start, so they never
/// preempt the cycle, also under --realtime.
#ifndef CELLGUARD_MONITOR_WEB_SERVER_HPP
#define CELLGUARD_MONITOR_WEB_SERVER_HPP

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/monitor/live_view.hpp"

struct mg_context;
struct mg_connection;

namespace cellguard::monitor {

/// How the server is set up.
struct WebServerSettings {
    std::string address = "127.0.0.1";                      ///< IPv4 address to bind
    int port = 0;                                           ///< 0: a free port
    std::string page_dir;                                   ///< the page's files (index.html, app.js, style.css)
    std::string three_dir = "/usr/share/javascript/three";  ///< libjs-three's directory
    std::string snapshot_dir;                               ///< --snapshot-dir ("": no stop history)
    int threads = 8;                                        ///< worker threads (connections served at once)
    int max_streams = 5;                                    ///< concurrent /api/events streams (more: 503)
    int event_period_ms = 100;                              ///< SSE period (10 Hz)
    int read_attempts = 8;                                  ///< snapshot reads before 503
};

/// What the server did (read any time).
struct WebCounts {
    std::uint64_t requests = 0U;  ///< requests seen by the handler
    std::uint64_t refused = 0U;   ///< answered 4xx by check_request
    std::uint64_t busy = 0U;      ///< answered 503 (torn reads, streams full)
    std::uint64_t events = 0U;    ///< SSE events sent
};

/// See the file comment. start() once, stop() (or the destructor) once.
class WebServer {
public:
    /// Serves @p channel's snapshots and @p static_json as /api/static.
    WebServer(const SnapshotChannel& channel, std::string static_json);
    WebServer(const WebServer&) = delete;
    WebServer& operator=(const WebServer&) = delete;
    WebServer(WebServer&&) = delete;
    WebServer& operator=(WebServer&&) = delete;
    /// stop().
    ~WebServer();
    /// Reads the files and starts CivetWeb; false with @p error set otherwise.
    [[nodiscard]] bool start(const WebServerSettings& settings, std::string& error);
    /// Ends the streams and stops CivetWeb (waits for its threads).
    void stop() noexcept;
    /// The port bound (after start()).
    [[nodiscard]] int port() const noexcept { return port_; }
    /// See WebCounts.
    [[nodiscard]] WebCounts counts() const noexcept;

    /// CivetWeb's request handler (internal; public for the C callback).
    int handle(mg_connection* conn) noexcept;

private:
    int serve(mg_connection* conn, bool head);
    int serve_events(mg_connection* conn);
    int serve_stops(mg_connection* conn, bool head) const;
    int serve_picture(mg_connection* conn, bool head, std::uint32_t number);
    static int reply(mg_connection* conn, int status, const char* type, const char* body, std::size_t size, bool head);
    [[nodiscard]] bool read_snapshot(LiveSnapshot& s) const noexcept;
    const SnapshotChannel* channel_;
    std::string static_json_;
    WebServerSettings settings_;
    std::vector<std::string> files_;  ///< web_files()' contents, read at start
    mg_context* ctx_ = nullptr;
    int port_ = 0;
    std::atomic<bool> stopping_{false};
    std::atomic<int> streams_{0};
    std::atomic<std::uint64_t> requests_{0U};
    std::atomic<std::uint64_t> refused_{0U};
    std::atomic<std::uint64_t> busy_{0U};
    std::atomic<std::uint64_t> events_{0U};
};

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_WEB_SERVER_HPP
