// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// What the browser view's server answers (web_content.hpp).
#include "cellguard/monitor/web_content.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "cellguard/grid/log_odds.hpp"

namespace cellguard::monitor {

namespace {

constexpr WebFile kFiles[] = {
    {"/", 0, "index.html", "text/html; charset=utf-8"},
    {"/index.html", 0, "index.html", "text/html; charset=utf-8"},
    {"/app.js", 0, "app.js", "text/javascript; charset=utf-8"},
    {"/style.css", 0, "style.css", "text/css; charset=utf-8"},
    {"/favicon.svg", 0, "favicon.svg", "image/svg+xml"},  // linked by index.html: no request for a missing icon
    // three.js r111 (libjs-three) in its own layout: OrbitControls imports ../../../build/three.module.js.
    {"/three/build/three.module.js", 1, "build/three.module.js", "text/javascript; charset=utf-8"},
    {"/three/examples/jsm/controls/OrbitControls.js", 1, "examples/jsm/controls/OrbitControls.js",
     "text/javascript; charset=utf-8"},
};

constexpr const char* kPicturePrefix = "/api/stops/";
constexpr const char* kPictureSuffix = "/picture.png";

/// True when @p uri holds a character or sequence no route has.
bool suspicious(const char* uri, std::size_t n) noexcept {
    for (std::size_t i = 0U; i < n; ++i) {
        const auto c = static_cast<unsigned char>(uri[i]);
        if (c < 0x20U || c >= 0x7FU || c == '\\' || c == '%') {
            return true;  // control, non-ASCII, backslash, any escape (%00, %2e, ...): no route needs them
        }
    }
    return std::strstr(uri, "..") != nullptr || std::strstr(uri, "//") != nullptr;
}

/// /api/stops/<N>/picture.png: N (1..9 digits) into @p number.
bool parse_picture(const char* uri, std::size_t n, std::uint32_t& number) noexcept {
    const std::size_t pre = std::strlen(kPicturePrefix);
    const std::size_t post = std::strlen(kPictureSuffix);
    if (n <= pre + post || std::strncmp(uri, kPicturePrefix, pre) != 0 ||
        std::strcmp(uri + n - post, kPictureSuffix) != 0) {
        return false;
    }
    const std::size_t digits = n - pre - post;
    if (digits > 9U) {
        return false;
    }
    std::uint32_t v = 0U;
    for (std::size_t i = pre; i < pre + digits; ++i) {
        if (uri[i] < '0' || uri[i] > '9') {
            return false;
        }
        v = v * 10U + static_cast<std::uint32_t>(uri[i] - '0');
    }
    number = v;
    return true;
}

}  // namespace

const WebFile* web_files(std::size_t& count) noexcept {
    count = sizeof kFiles / sizeof kFiles[0];
    return kFiles;
}

namespace {

/// ASCII case-insensitive equality of @p a (may be nullptr) and the lower-case @p lower.
bool same_name(const char* a, const char* lower) noexcept {
    if (a == nullptr) {
        return false;
    }
    std::size_t i = 0U;
    for (; lower[i] != '\0'; ++i) {
        const char c = (a[i] >= 'A' && a[i] <= 'Z') ? static_cast<char>(a[i] - 'A' + 'a') : a[i];
        if (c != lower[i]) {
            return false;
        }
    }
    return a[i] == '\0';
}

/// 1 to 18 decimal digits and nothing else (no sign, no blank, no list).
bool plain_length(const char* v) noexcept {
    if (v == nullptr) {
        return false;
    }
    std::size_t n = 0U;
    for (; v[n] != '\0'; ++n) {
        if (v[n] < '0' || v[n] > '9' || n >= 18U) {
            return false;
        }
    }
    return n > 0U;
}

}  // namespace

int check_framing(const HeaderLine* headers, int count) noexcept {
    int lengths = 0;
    for (int i = 0; headers != nullptr && i < count; ++i) {
        const HeaderLine& h = headers[i];
        if (same_name(h.name, "transfer-encoding")) {
            return 400;  // no request here has a body: chunked or not, it is not read (RFC 9112, 6.1)
        }
        if (same_name(h.name, "content-length")) {
            if (++lengths > 1 || !plain_length(h.value)) {
                return 400;  // two lengths, equal or not, or one that is no single number (RFC 9112, 6.3)
            }
        }
    }
    return 200;
}

RequestVerdict check_request(const char* method, const char* uri, long long content_length, int header_lines) noexcept {
    RequestVerdict v;
    const char* m = method == nullptr ? "" : method;
    if (std::strcmp(m, "GET") != 0 && std::strcmp(m, "HEAD") != 0) {
        v.status = 405;
        return v;
    }
    if (content_length > 0) {
        v.status = 413;  // read-only: no request carries a body
        return v;
    }
    const char* u = uri == nullptr ? "" : uri;
    const std::size_t n = strnlen(u, kMaxUriLength + 1U);
    if (n == 0U || n > kMaxUriLength || u[0] != '/' || suspicious(u, n) || header_lines > kMaxHeaderLines ||
        header_lines < 0) {
        v.status = 400;
        return v;
    }
    v.status = 200;
    for (std::size_t i = 0U; i < sizeof kFiles / sizeof kFiles[0]; ++i) {
        if (std::strcmp(u, kFiles[i].url) == 0) {
            v.route = Route::kFile;
            v.file_index = i;
            return v;
        }
    }
    if (std::strcmp(u, "/api/static") == 0) {
        v.route = Route::kStatic;
    } else if (std::strcmp(u, "/api/state") == 0) {
        v.route = Route::kState;
    } else if (std::strcmp(u, "/api/events") == 0) {
        v.route = Route::kEvents;
    } else if (std::strcmp(u, "/api/stops") == 0) {
        v.route = Route::kStops;
    } else if (parse_picture(u, n, v.stop_number)) {
        v.route = Route::kPicture;
    } else {
        v.status = 404;
    }
    return v;
}

JsonWriter::JsonWriter(char* buffer, std::size_t capacity) noexcept : buffer_(buffer), capacity_(capacity) {
    if (capacity_ == 0U) {
        overflow_ = true;
    } else {
        buffer_[0] = '\0';
    }
}

void JsonWriter::put(const char* text, std::size_t n) noexcept {
    if (overflow_) {
        return;
    }
    if (n >= capacity_ - length_) {  // one byte stays for the NUL
        overflow_ = true;
        return;
    }
    std::memcpy(buffer_ + length_, text, n);
    length_ += n;
    buffer_[length_] = '\0';
}

JsonWriter& JsonWriter::raw(const char* text) noexcept {
    put(text, std::strlen(text));
    return *this;
}

JsonWriter& JsonWriter::str(const char* text) noexcept {
    put("\"", 1U);
    for (const char* p = text; *p != '\0'; ++p) {
        const auto c = static_cast<unsigned char>(*p);
        if (c == '"' || c == '\\') {
            const char esc[2] = {'\\', static_cast<char>(c)};
            put(esc, 2U);
        } else if (c < 0x20U) {
            char esc[8];
            const int k = std::snprintf(esc, sizeof esc, "\\u%04x", static_cast<unsigned>(c));
            put(esc, static_cast<std::size_t>(k));
        } else {
            put(p, 1U);
        }
    }
    put("\"", 1U);
    return *this;
}

JsonWriter& JsonWriter::u64(std::uint64_t v) noexcept {
    char t[24];
    const int k = std::snprintf(t, sizeof t, "%" PRIu64, v);
    put(t, static_cast<std::size_t>(k));
    return *this;
}

JsonWriter& JsonWriter::i64(std::int64_t v) noexcept {
    char t[24];
    const int k = std::snprintf(t, sizeof t, "%" PRId64, v);
    put(t, static_cast<std::size_t>(k));
    return *this;
}

JsonWriter& JsonWriter::num(double v) noexcept {
    if (!std::isfinite(v)) {
        return raw("null");
    }
    char t[32];
    const int k = std::snprintf(t, sizeof t, "%.6g", v);
    put(t, static_cast<std::size_t>(k));
    return *this;
}

const char* zone_state_name(std::uint8_t state) noexcept {
    switch (state) {
        case 0U: return "CLEAR";
        case 1U: return "INTRUDED";
        case 2U: return "UNSEEN";
        default: return "FAULT";
    }
}

const char* zone_shown_state(const LiveSnapshot& s, std::size_t zone) noexcept {
    const std::uint32_t bit = 1U << zone;
    if ((s.active_mask & bit) == 0U) {
        return "INACTIVE";
    }
    if (s.latched_faults != 0U) {
        return "FAULT";  // the CAN frame's Fault bit: every zone's state is FAULT then
    }
    if ((s.intruded_mask & bit) != 0U) {
        return "INTRUDED";
    }
    return (s.unseen_mask & bit) != 0U ? "UNSEEN" : "CLEAR";
}

void write_state_json(const LiveSnapshot& s, std::uint64_t age_us, JsonWriter& out) noexcept {
    out.raw("{\"valid\":").raw(s.valid != 0U ? "true" : "false");
    out.raw(",\"voxels\":").raw(s.voxels != 0U ? "true" : "false");
    out.raw(",\"k\":").i64(s.k).raw(",\"cycle\":").u64(s.cycle).raw(",\"started_us\":").u64(s.started_us);
    out.raw(",\"age_ms\":").num(static_cast<double>(age_us) / 1000.0);
    out.raw(",\"cycle_ms\":").num(static_cast<double>(s.cycle_us) / 1000.0);
    out.raw(",\"stop\":")
        .raw(s.stop != 0U ? "true" : "false")
        .raw(",\"warning\":")
        .raw(s.warning != 0U ? "true" : "false");
    out.raw(",\"reduced_speed\":").raw(s.reduced_speed != 0U ? "true" : "false");
    out.raw(",\"separation_stop\":").raw(s.separation_stop != 0U ? "true" : "false");
    out.raw(",\"robot\":").raw(s.robot != 0U ? "true" : "false").raw(",\"active_case\":").u64(s.active_case);
    out.raw(",\"distance_mm\":").u64(s.distance_mm).raw(",\"required_mm\":").u64(s.required_mm);
    out.raw(",\"latched_faults\":").u64(s.latched_faults);
    out.raw(",\"intruded_mask\":").u64(s.intruded_mask).raw(",\"unseen_mask\":").u64(s.unseen_mask);
    out.raw(",\"active_mask\":").u64(s.active_mask).raw(",\"zones\":[");
    for (std::size_t z = 0U; z < s.zone_count && z < kMaxZones; ++z) {
        const LiveZone& lz = s.zones[z];
        out.raw(z == 0U ? "{" : ",{").raw("\"state\":").str(zone_shown_state(s, z));
        out.raw(",\"evaluated\":").str(zone_state_name(lz.state)).raw(",\"foreground\":").u64(lz.foreground);
        out.raw(",\"unseen\":").u64(lz.unseen).raw(",\"robot\":").u64(lz.robot).raw("}");
    }
    out.raw("],\"capsules\":[");
    for (std::uint32_t c = 0U; c < s.capsule_count && c < kMaxRobotCapsules; ++c) {
        const LiveCapsule& k = s.capsules[c];
        out.raw(c == 0U ? "[" : ",[");
        for (const float v : k.a) {
            out.num(static_cast<double>(v)).raw(",");
        }
        for (const float v : k.b) {
            out.num(static_cast<double>(v)).raw(",");
        }
        out.num(static_cast<double>(k.radius)).raw("]");
    }
    out.raw("],\"foreground_total\":").u64(s.foreground_total);
    out.raw(",\"foreground_truncated\":").raw(s.foreground_total > s.foreground_count ? "true" : "false");
    out.raw(",\"foreground\":[");
    for (std::uint32_t i = 0U; i < s.foreground_count && i < kLiveMaxForeground; ++i) {
        out.raw(i == 0U ? "" : ",").u64(s.foreground[i]);
    }
    out.raw("],\"unseen_total\":").u64(s.unseen_total);
    out.raw(",\"unseen_truncated\":").raw(s.unseen_total > s.unseen_count ? "true" : "false");
    out.raw(",\"unseen\":[");
    for (std::uint32_t i = 0U; i < s.unseen_count && i < kLiveMaxUnseen; ++i) {
        out.raw(i == 0U ? "" : ",").u64(s.unseen[i]);
    }
    out.raw("]}");
}

namespace {

/// Appends @p v to @p out.
void append_num(std::string& out, double v) {
    char t[32];
    static_cast<void>(std::snprintf(t, sizeof t, "%.6g", v));
    out += t;
}

/// True when the prior says no person can be at voxel @p i.
bool inaccessible(const std::int16_t* prior, std::size_t i, std::int16_t min_prior) noexcept {
    return prior[i] == kNeverForeground || prior[i] < min_prior;
}

/// The zones of @p cfg as JSON objects.
void append_zones(std::string& out, const cell::MonitorConfig& cfg) {
    out += "\"zones\":[";
    for (std::size_t z = 0U; z < cfg.zones.size(); ++z) {
        const ZoneConfig& c = cfg.zones[z].zone;
        char name[128];
        JsonWriter w(name, sizeof name);
        w.str(cfg.zones[z].name.c_str());
        out += z == 0U ? "{\"name\":" : ",{\"name\":";
        out += w.overflowed() ? "\"?\"" : w.c_str();
        out += c.kind == ZoneKind::kProtective ? R"(,"kind":"protective")" : R"(,"kind":"warning")";
        if (c.shape == ZoneShape::kBox) {
            out += R"(,"shape":"box","min":[)";
            append_num(out, c.box_min.x());
            out += ",";
            append_num(out, c.box_min.y());
            out += ",";
            append_num(out, c.box_min.z());
            out += "],\"max\":[";
            append_num(out, c.box_max.x());
            out += ",";
            append_num(out, c.box_max.y());
            out += ",";
            append_num(out, c.box_max.z());
            out += "]";
        } else {
            out += R"(,"shape":"prism","z_min":)";
            append_num(out, c.z_min);
            out += ",\"z_max\":";
            append_num(out, c.z_max);
            out += ",\"polygon\":[";
            for (std::size_t p = 0U; p < c.polygon_size && p < kMaxPolygonVertices; ++p) {
                out += p == 0U ? "[" : ",[";
                append_num(out, c.polygon[p].x);
                out += ",";
                append_num(out, c.polygon[p].y);
                out += "]";
            }
            out += "]";
        }
        out += "}";
    }
    out += "]";
}

}  // namespace

std::string make_static_json(const cell::MonitorConfig& cfg, const GridGeometry& grid, const std::int16_t* prior,
                             std::size_t prior_size, bool snapshots) {
    const GridDims d = grid.dims();
    std::string out = "{\"dims\":[" + std::to_string(d.nx) + "," + std::to_string(d.ny) + "," + std::to_string(d.nz) +
                      "],\"voxel_size\":";
    append_num(out, grid.voxel_size());
    out += ",\"origin\":[";
    append_num(out, grid.origin().x());
    out += ",";
    append_num(out, grid.origin().y());
    out += ",";
    append_num(out, grid.origin().z());
    out += std::string("],\"snapshots\":") + (snapshots ? "true" : "false") + ",";
    append_zones(out, cfg);
    out += ",\"cases\":[";
    for (std::size_t c = 0U; c < cfg.cases.size(); ++c) {
        out += (c == 0U ? "{\"number\":" : ",{\"number\":") + std::to_string(cfg.cases[c].number) +
               ",\"zone_mask\":" + std::to_string(cfg.cases[c].zone_mask) + "}";
    }
    // The prior's inaccessible voxels: those next to an accessible one are the background's surfaces
    // ("background"), the rest the interiors the prior removed as inaccessible ("interior").
    std::string background = "\"background\":[";
    std::string interior = "\"interior\":[";
    bool first_b = true;
    bool first_i = true;
    const std::size_t n = std::min(grid.voxel_count(), prior_size);
    for (std::size_t i = 0U; i < n; ++i) {
        if (!inaccessible(prior, i, cfg.accessible_min_prior)) {
            continue;
        }
        const VoxelCoord v = grid.coord_of(i);
        bool surface = false;
        const int off[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (const int* o : off) {
            const VoxelCoord nb{v.x + o[0], v.y + o[1], v.z + o[2]};
            if (grid.contains(nb) && !inaccessible(prior, grid.index_of(nb), cfg.accessible_min_prior)) {
                surface = true;
                break;
            }
        }
        std::string& list = surface ? background : interior;
        bool& first = surface ? first_b : first_i;
        if (!first) {
            list += ",";
        }
        first = false;
        list += std::to_string(i);
    }
    out += "]," + background + "]," + interior + "]}";
    return out;
}

}  // namespace cellguard::monitor

namespace cellguard::monitor {

namespace {

/// True when @p host is A.B.C.D with four numbers 0..255 of 1..3 digits.
bool is_ipv4(const std::string& host) {
    std::size_t start = 0U;
    for (int part = 0; part < 4; ++part) {
        const std::size_t end = part < 3 ? host.find('.', start) : host.size();
        if (end == std::string::npos || end == start || end - start > 3U) {
            return false;
        }
        const std::string digits = host.substr(start, end - start);
        if (digits.find_first_not_of("0123456789") != std::string::npos || std::stoi(digits) > 255) {
            return false;
        }
        start = end + 1U;
    }
    return true;
}

}  // namespace

bool parse_http_address(const std::string& text, std::string& address, int& port, std::string& error) {
    const std::size_t colon = text.rfind(':');
    const std::string host = colon == std::string::npos ? std::string() : text.substr(0U, colon);
    const std::string digits = colon == std::string::npos ? text : text.substr(colon + 1U);
    if (digits.empty() || digits.size() > 5U || digits.find_first_not_of("0123456789") != std::string::npos) {
        error = "--http " + text + ": the port must be a number 0..65535 (ADDRESS:PORT, :PORT or PORT)";
        return false;
    }
    const long p = std::strtol(digits.c_str(), nullptr, 10);
    if (p > 65535L) {
        error = "--http " + text + ": the port must be a number 0..65535";
        return false;
    }
    if (!host.empty() && !is_ipv4(host)) {
        error = "--http " + text + ": the address must be an IPv4 address A.B.C.D";
        return false;
    }
    address = host.empty() ? std::string("127.0.0.1") : host;
    port = static_cast<int>(p);
    return true;
}

bool can_listen_on(const std::string& text, const std::string& address, int port, std::string& error) {
    sockaddr_in where{};
    where.sin_family = AF_INET;
    where.sin_port = htons(static_cast<std::uint16_t>(port));
    if (inet_pton(AF_INET, address.c_str(), &where.sin_addr) != 1) {
        error = "--http " + text + ": the address must be an IPv4 address A.B.C.D";
        return false;
    }
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        error = "--http " + text + ": cannot listen there: " + std::strerror(errno);
        return false;
    }
    const int one = 1;
    static_cast<void>(::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one));  // as the server does
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API takes a sockaddr*
    const bool ok = ::bind(fd, reinterpret_cast<const sockaddr*>(&where), sizeof where) == 0;
    const int bind_errno = errno;
    static_cast<void>(::close(fd));
    if (!ok) {
        error = "--http " + text + ": cannot listen there: " + std::strerror(bind_errno);
    }
    return ok;
}

}  // namespace cellguard::monitor
