// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file web_content.hpp
/// What the browser view's server (web_server.hpp) answers, without the
/// HTTP library, so that it is tested on its own:
/// - check_framing(): no ambiguous message framing (two Content-Length
///   lines, a Transfer-Encoding: 400, the connection closed);
/// - check_request(): the rules every request passes before anything is
///   read or served: only GET and HEAD (405 otherwise), no body (413), a
///   raw (not URL-decoded) path of at most kMaxUriLength characters without
///   "..", "//", '%', a backslash or a control character and at most
///   kMaxHeaderLines header lines (400), and a path that
///   is one of the fixed routes: the page's files, the three.js r111 files
///   it imports, the API endpoints (404 otherwise);
/// - JsonWriter: JSON into a caller's fixed buffer; past its end nothing
///   more is written and overflowed() says so (the server answers 503);
/// - write_state_json() and write_static_json(): the endpoints' bodies.
/// The server runs them on its own threads, never on the cycle's.
#ifndef CELLGUARD_MONITOR_WEB_CONTENT_HPP
#define CELLGUARD_MONITOR_WEB_CONTENT_HPP

#include <cstddef>
#include <cstdint>
#include <string>

#include "cellguard/host/cell/config.hpp"
#include "cellguard/monitor/live_view.hpp"

namespace cellguard::monitor {

/// Longest request path accepted (longer: 400).
constexpr std::size_t kMaxUriLength = 256U;
/// Most header lines accepted (more: 400; CivetWeb keeps 64 and drops the rest unseen).
constexpr int kMaxHeaderLines = 40;

/// What a request asks for.
enum class Route : std::uint8_t {
    kNone = 0,     ///< refused (status says why)
    kFile = 1,     ///< a whitelisted file (file_index)
    kStatic = 2,   ///< /api/static
    kState = 3,    ///< /api/state
    kEvents = 4,   ///< /api/events (Server-Sent Events)
    kStops = 5,    ///< /api/stops
    kPicture = 6,  ///< /api/stops/<N>/picture.png (stop_number)
};

/// The verdict on one request.
struct RequestVerdict {
    int status = 400;                ///< 200 when served, else the 4xx to answer
    Route route = Route::kNone;      ///< what to serve (kNone with a 4xx)
    std::size_t file_index = 0U;     ///< kFile: index into web_files()
    std::uint32_t stop_number = 0U;  ///< kPicture: the snapshot's sequence number
};

/// A whitelisted file: its URL path, its root (0: the page's directory,
/// 1: libjs-three's directory), its path under that root, its MIME type.
struct WebFile {
    const char* url;   ///< e.g. "/app.js"
    int root;          ///< 0 page, 1 three.js
    const char* path;  ///< under the root
    const char* mime;  ///< Content-Type
};

/// The whitelist (fixed, compiled in).
const WebFile* web_files(std::size_t& count) noexcept;

/// One request header line as received (name and value without the colon
/// and the blanks around the value).
struct HeaderLine {
    const char* name;   ///< e.g. "Content-Length" (nullptr counts as empty)
    const char* value;  ///< e.g. "0" (nullptr counts as empty)
};

/// The message-framing rules (RFC 9112, section 6), checked before
/// check_request(): 400 for any request whose body length a proxy in front
/// of the server could read differently from the server, else 200. Refused:
/// two or more Content-Length lines (also with equal values: a list is not
/// merged), a Content-Length that is not 1 to 18 decimal digits, and any
/// Transfer-Encoding (no request this server takes has a body; also a
/// Transfer-Encoding beside a Content-Length). Header names compare without
/// case. @p count is the number of entries of @p headers (negative: none).
[[nodiscard]] int check_framing(const HeaderLine* headers, int count) noexcept;

/// See the file comment. @p method and @p uri as received (uri raw, without
/// the query string; nullptr counts as empty); @p content_length -1 when
/// absent; @p header_lines the request's header lines (more than
/// kMaxHeaderLines: 400).
[[nodiscard]] RequestVerdict check_request(const char* method, const char* uri, long long content_length,
                                           int header_lines) noexcept;

/// See the file comment.
class JsonWriter {
public:
    /// Writes into @p buffer of @p capacity bytes (one kept for the NUL).
    JsonWriter(char* buffer, std::size_t capacity) noexcept;
    /// Appends @p text as it is (punctuation, keys written by the caller).
    JsonWriter& raw(const char* text) noexcept;
    /// Appends @p text as a JSON string, quoted and escaped.
    JsonWriter& str(const char* text) noexcept;
    /// Appends an unsigned number.
    JsonWriter& u64(std::uint64_t v) noexcept;
    /// Appends a signed number.
    JsonWriter& i64(std::int64_t v) noexcept;
    /// Appends a finite number with up to 6 significant digits (null when not finite).
    JsonWriter& num(double v) noexcept;
    /// Bytes written (without the NUL).
    [[nodiscard]] std::size_t size() const noexcept { return length_; }
    /// True when something did not fit (the text is cut, not valid JSON).
    [[nodiscard]] bool overflowed() const noexcept { return overflow_; }
    /// The text, NUL-terminated.
    [[nodiscard]] const char* c_str() const noexcept { return buffer_; }

private:
    void put(const char* text, std::size_t n) noexcept;
    char* buffer_;
    std::size_t capacity_;
    std::size_t length_ = 0U;
    bool overflow_ = false;
};

/// The name of zone state @p state (ZoneState as a number): "CLEAR", "INTRUDED", "UNSEEN", "FAULT".
const char* zone_state_name(std::uint8_t state) noexcept;

/// The state a zone shows, as its CAN bits say: FAULT (fault bit), INTRUDED,
/// UNSEEN, CLEAR, or "INACTIVE" (not in the active monitoring case).
const char* zone_shown_state(const LiveSnapshot& s, std::size_t zone) noexcept;

/// /api/state's body for @p s, its age @p age_us at the time of writing.
void write_state_json(const LiveSnapshot& s, std::uint64_t age_us, JsonWriter& out) noexcept;

/// /api/static's body: grid, zones, cases, background and inaccessible
/// interiors of the prior (made once at start, on the main thread), and
/// @p snapshots: whether the monitor writes snapshots of its stops
/// (--snapshot-dir; without, the page says why its stop history is empty).
std::string make_static_json(const cell::MonitorConfig& cfg, const GridGeometry& grid, const std::int16_t* prior,
                             std::size_t prior_size, bool snapshots = true);

/// "PORT", ":PORT" (both on 127.0.0.1) or "A.B.C.D:PORT" into @p address
/// and @p port (0..65535); false with @p error set otherwise.
[[nodiscard]] bool parse_http_address(const std::string& text, std::string& address, int& port, std::string& error);

/// Whether a TCP socket can listen on @p address (IPv4, as parse_http_address
/// gives it) and @p port now: binds one and closes it. False with @p error
/// ("--http TEXT: cannot listen there: <reason>") otherwise. The monitor asks
/// before it opens any output, so a refused address loses nothing.
[[nodiscard]] bool can_listen_on(const std::string& text, const std::string& address, int port, std::string& error);

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_WEB_CONTENT_HPP
