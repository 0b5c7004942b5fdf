// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The browser view's HTTP server on CivetWeb (web_server.hpp).
#include "cellguard/monitor/web_server.hpp"

#include <civetweb.h>
#include <dirent.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <thread>
#include <utility>

#include "cellguard/monitor/web_content.hpp"
#include "cellguard/port/clock.hpp"
#include "cellguard/port/log_queue.hpp"

namespace cellguard::monitor {

namespace {

/// Bytes of one /api/state body at most (the snapshot's indices, 11 bytes each, and the rest).
constexpr std::size_t kStateJsonBytes = (kLiveMaxForeground + kLiveMaxUnseen) * 11U + 8192U;
/// Largest snapshot picture served.
constexpr std::streamsize kMaxPictureBytes = std::streamsize{16} * 1024 * 1024;
/// Largest page or three.js file read at start.
constexpr std::streamsize kMaxFileBytes = std::streamsize{8} * 1024 * 1024;
/// Most stops listed.
constexpr std::size_t kMaxStops = 100U;

const char* status_text(int status) noexcept {
    switch (status) {
        case 200: return "OK";
        case 400: return "Bad Request";
        case 404: return "Not Found";
        case 405: return "Method Not Allowed";
        case 413: return "Payload Too Large";
        case 503: return "Service Unavailable";
        default: return "Internal Server Error";
    }
}

int on_request(mg_connection* conn, void* data) { return static_cast<WebServer*>(data)->handle(conn); }

void* on_thread_start(const mg_context* /*ctx*/, int /*thread_type*/) {
    // Below the cycle: never preempt it, also when --realtime made the process SCHED_FIFO.
    static_cast<void>(linux_port::make_background_thread(10));
    return nullptr;
}

int on_log_message(const mg_connection* /*conn*/, const char* /*message*/) {
    return 1;  // CivetWeb's own error lines are not written: the event log belongs to the monitor
}

/// Reads file @p path whole into @p out; false when it cannot be read.
bool read_file(const std::string& path, std::string& out, std::streamsize limit) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return false;
    }
    in.seekg(0, std::ios::end);
    const std::streamsize size = in.tellg();
    if (size < 0 || size > limit) {
        return false;
    }
    in.seekg(0, std::ios::beg);
    out.assign(static_cast<std::size_t>(size), '\0');
    return static_cast<bool>(in.read(out.data(), size));
}

/// One stop snapshot directory: "stop-STAMP-NNNN-cycle-K".
struct StopEntry {
    std::uint32_t sequence = 0U;
    long cycle = -1;
    std::string name;
};

/// The complete snapshots under @p dir, newest (highest sequence) first, at most kMaxStops.
std::vector<StopEntry> list_stops(const std::string& dir) {
    std::vector<StopEntry> stops;
    DIR* d = opendir(dir.c_str());
    if (d == nullptr) {
        return stops;
    }
    while (const dirent* e = readdir(d)) {  // NOLINT(concurrency-mt-unsafe): this thread's own DIR stream
        const std::string name = e->d_name;
        if (name.rfind("stop-", 0U) != 0U ||
            name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-") !=
                std::string::npos) {
            continue;  // ".stop-..." is still being written; other names are not the recorder's
        }
        const std::size_t c = name.rfind("-cycle-");
        const std::size_t s = c == std::string::npos ? std::string::npos : name.rfind('-', c - 1U);
        if (s == std::string::npos) {
            continue;
        }
        StopEntry entry;
        entry.sequence = static_cast<std::uint32_t>(std::strtoul(name.c_str() + s + 1U, nullptr, 10));
        entry.cycle = std::strtol(name.c_str() + c + 7U, nullptr, 10);
        entry.name = name;
        stops.push_back(std::move(entry));
    }
    closedir(d);
    std::sort(stops.begin(), stops.end(),
              [](const StopEntry& a, const StopEntry& b) { return a.sequence > b.sequence; });
    if (stops.size() > kMaxStops) {
        stops.resize(kMaxStops);
    }
    return stops;
}

}  // namespace

WebServer::WebServer(const SnapshotChannel& channel, std::string static_json)
    : channel_(&channel), static_json_(std::move(static_json)) {}

WebServer::~WebServer() { stop(); }

bool WebServer::start(const WebServerSettings& settings, std::string& error) {
    settings_ = settings;
    std::size_t count = 0U;
    const WebFile* files = web_files(count);
    files_.assign(count, std::string());
    for (std::size_t i = 0U; i < count; ++i) {
        const std::string root = files[i].root == 0 ? settings.page_dir : settings.three_dir;
        if (!read_file(root + "/" + files[i].path, files_[i], kMaxFileBytes)) {
            error = "cannot read " + root + "/" + files[i].path +
                    (files[i].root == 0 ? "" : " (Debian package libjs-three)");
            return false;
        }
    }
    const std::string ports = settings.address + ":" + std::to_string(settings.port);
    const std::string threads = std::to_string(settings.threads);
    // Every unsafe default overridden (see the file comment).
    const char* options[] = {"listening_ports",
                             ports.c_str(),
                             "num_threads",
                             threads.c_str(),
                             "connection_queue",
                             "8",
                             "listen_backlog",
                             "8",
                             "max_request_size",
                             "4096",
                             "request_timeout_ms",
                             "2000",
                             "keep_alive_timeout_ms",
                             "500",
                             "enable_keep_alive",
                             "no",
                             "enable_directory_listing",
                             "no",
                             "cgi_pattern",
                             "",
                             "ssi_pattern",
                             "",
                             "access_control_allow_origin",
                             "",
                             "access_control_allow_methods",
                             "",
                             "access_control_allow_headers",
                             "",
                             "decode_url",
                             "no",
                             "enable_auth_domain_check",
                             "no",
                             nullptr,
                             nullptr};
    mg_callbacks callbacks{};
    callbacks.init_thread = on_thread_start;
    callbacks.log_message = on_log_message;
    mg_init_library(0U);
    ctx_ = mg_start(&callbacks, this, options);
    if (ctx_ == nullptr) {
        error = "the HTTP server did not start on " + ports + " (address in use or not available?)";
        return false;
    }
    mg_set_request_handler(ctx_, "/", on_request, this);
    mg_server_port bound[2]{};
    if (mg_get_server_ports(ctx_, 2, bound) >= 1) {
        port_ = bound[0].port;
    }
    return true;
}

void WebServer::stop() noexcept {
    if (ctx_ == nullptr) {
        return;
    }
    stopping_.store(true, std::memory_order_release);
    mg_stop(ctx_);
    ctx_ = nullptr;
    mg_exit_library();
}

WebCounts WebServer::counts() const noexcept {
    WebCounts c;
    c.requests = requests_.load(std::memory_order_relaxed);
    c.refused = refused_.load(std::memory_order_relaxed);
    c.busy = busy_.load(std::memory_order_relaxed);
    c.events = events_.load(std::memory_order_relaxed);
    return c;
}

bool WebServer::read_snapshot(LiveSnapshot& s) const noexcept {
    channel_->note_demand(linux_port::monotonic_now_us());  // the cycle scans the voxels while someone reads
    return channel_->read(s, settings_.read_attempts);
}

int WebServer::reply(mg_connection* conn, int status, const char* type, const char* body, std::size_t size, bool head) {
    mg_printf(conn,
              "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\nCache-Control: no-store\r\n"
              "X-Content-Type-Options: nosniff\r\nContent-Security-Policy: default-src 'self'\r\n"
              "Connection: close\r\n\r\n",
              status, status_text(status), type, size);
    if (!head && size > 0U) {
        static_cast<void>(mg_write(conn, body, size));
    }
    return status;
}

int WebServer::handle(mg_connection* conn) noexcept {
    requests_.fetch_add(1U, std::memory_order_relaxed);
    try {
        const mg_request_info* ri = mg_get_request_info(conn);
        // Ambiguous framing first, whatever the method: 400, and the connection closes (Connection: close,
        // keep-alive off), so no bytes of a smuggled body are read as another request.
        std::array<HeaderLine, MG_MAX_HEADERS> lines{};
        const int n_lines = std::min(ri->num_headers, static_cast<int>(lines.size()));
        for (int i = 0; i < n_lines; ++i) {
            lines[static_cast<std::size_t>(i)] = HeaderLine{ri->http_headers[i].name, ri->http_headers[i].value};
        }
        RequestVerdict v;
        v.status = check_framing(lines.data(), n_lines);
        if (v.status == 200) {
            v = check_request(ri->request_method, ri->local_uri_raw, ri->content_length, ri->num_headers);
        }
        const bool head = std::strcmp(ri->request_method, "HEAD") == 0;
        if (v.status != 200) {
            refused_.fetch_add(1U, std::memory_order_relaxed);
            char body[64];
            const int n = std::snprintf(body, sizeof body, "%d %s\n", v.status, status_text(v.status));
            if (v.status == 405) {
                mg_printf(conn,
                          "HTTP/1.1 405 Method Not Allowed\r\nAllow: GET, HEAD\r\nContent-Length: %d\r\n"
                          "Connection: close\r\n\r\n%s",
                          n, body);
                return 405;
            }
            return reply(conn, v.status, "text/plain", body, static_cast<std::size_t>(n), head);
        }
        switch (v.route) {
            case Route::kFile: {
                std::size_t count = 0U;
                const WebFile* files = web_files(count);
                const std::string& f = files_[v.file_index];
                return reply(conn, 200, files[v.file_index].mime, f.data(), f.size(), head);
            }
            case Route::kStatic:
                return reply(conn, 200, "application/json", static_json_.data(), static_json_.size(), head);
            case Route::kEvents: return head ? reply(conn, 200, "text/event-stream", "", 0U, true) : serve_events(conn);
            case Route::kStops: return serve_stops(conn, head);
            case Route::kPicture: return serve_picture(conn, head, v.stop_number);
            default: return serve(conn, head);
        }
    } catch (const std::exception&) {
        return reply(conn, 500, "text/plain", "500\n", 4U, false);  // out of memory: this request only
    }
}

int WebServer::serve(mg_connection* conn, bool head) {
    auto snapshot = std::make_unique<LiveSnapshot>();
    if (!read_snapshot(*snapshot)) {
        busy_.fetch_add(1U, std::memory_order_relaxed);
        return reply(conn, 503, "text/plain", "503 snapshot busy\n", 18U, head);
    }
    std::vector<char> buffer(kStateJsonBytes);
    JsonWriter w(buffer.data(), buffer.size());
    const std::uint64_t now = linux_port::monotonic_now_us();
    write_state_json(*snapshot, snapshot->valid != 0U ? now - snapshot->published_us : 0U, w);
    if (w.overflowed()) {
        return reply(conn, 500, "text/plain", "500\n", 4U, head);
    }
    return reply(conn, 200, "application/json", w.c_str(), w.size(), head);
}

int WebServer::serve_events(mg_connection* conn) {
    if (streams_.fetch_add(1) >= settings_.max_streams) {
        streams_.fetch_sub(1);
        busy_.fetch_add(1U, std::memory_order_relaxed);
        return reply(conn, 503, "text/plain", "503 too many event streams\n", 27U, false);
    }
    mg_printf(conn,
              "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n"
              "X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\nretry: 1000\n\n");
    auto snapshot = std::make_unique<LiveSnapshot>();
    std::vector<char> buffer(kStateJsonBytes);
    std::int64_t last_k = -2;
    int quiet_ticks = 0;
    while (!stopping_.load(std::memory_order_acquire)) {
        int written = 1;
        if (read_snapshot(*snapshot) && snapshot->k != last_k) {
            JsonWriter w(buffer.data(), buffer.size());
            w.raw("data: ");
            write_state_json(*snapshot, linux_port::monotonic_now_us() - snapshot->published_us, w);
            w.raw("\n\n");
            if (!w.overflowed()) {
                written = mg_write(conn, w.c_str(), w.size());
                last_k = snapshot->k;
                quiet_ticks = 0;
                events_.fetch_add(1U, std::memory_order_relaxed);
            }
        } else if (++quiet_ticks >= 10) {
            written = mg_write(conn, ": idle\n\n", 8U);  // finds a client gone while no cycle runs
            quiet_ticks = 0;
        }
        if (written <= 0) {
            break;  // the client left, or stopped reading for the write timeout
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(settings_.event_period_ms));
    }
    streams_.fetch_sub(1);
    return 200;
}

int WebServer::serve_stops(mg_connection* conn, bool head) const {
    std::string body = "[";
    if (!settings_.snapshot_dir.empty()) {
        const std::vector<StopEntry> stops = list_stops(settings_.snapshot_dir);
        for (std::size_t i = 0U; i < stops.size(); ++i) {
            const StopEntry& s = stops[i];
            body += (i == 0U ? R"({"sequence":)" : R"(,{"sequence":)") + std::to_string(s.sequence) + R"(,"cycle":)" +
                    std::to_string(s.cycle) + R"(,"name":")" + s.name + R"(","picture":"/api/stops/)" +
                    std::to_string(s.sequence) + R"(/picture.png"})";
        }
    }
    body += "]";
    return reply(conn, 200, "application/json", body.data(), body.size(), head);
}

int WebServer::serve_picture(mg_connection* conn, bool head, std::uint32_t number) {
    if (!settings_.snapshot_dir.empty()) {
        for (const StopEntry& s : list_stops(settings_.snapshot_dir)) {
            std::string png;
            if (s.sequence == number &&
                read_file(settings_.snapshot_dir + "/" + s.name + "/picture.png", png, kMaxPictureBytes)) {
                return reply(conn, 200, "image/png", png.data(), png.size(), head);
            }
        }
    }
    refused_.fetch_add(1U, std::memory_order_relaxed);
    return reply(conn, 404, "text/plain", "404 Not Found\n", 14U, head);
}

}  // namespace cellguard::monitor
