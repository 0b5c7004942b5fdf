// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies the browser view's parts that run without the HTTP library
// (apps/monitor: live_view.hpp, web_content.hpp): the snapshot's seqlock
// (a copy is whole or refused, a write in progress is seen, a reader never
// sees a torn snapshot while a writer publishes), the request checks, the
// bounded JSON writer, the zone states as the CAN frame carries them, the
// --http address, and the live view on the demo's cycles (no allocation).
#include <doctest/doctest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/host/cell/config.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/cell/scenario.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/live_view.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/picture.hpp"
#include "cellguard/monitor/web_content.hpp"
#include "cellguard/port/clock.hpp"
#include "monitor_test_doubles.hpp"

using namespace cellguard;
using namespace cellguard::cell;
using namespace cellguard::monitor;

namespace {

/// A snapshot whose every index and count says @p v.
void fill(LiveSnapshot& s, std::uint32_t v) {
    s.valid = 1U;
    s.k = static_cast<std::int64_t>(v);
    s.cycle = v;
    s.foreground_count = static_cast<std::uint32_t>(kLiveMaxForeground);
    s.unseen_count = static_cast<std::uint32_t>(kLiveMaxUnseen);
    for (std::uint32_t& x : s.foreground) {
        x = v;
    }
    for (std::uint32_t& x : s.unseen) {
        x = v;
    }
}

/// True when every field fill() wrote says the same value.
bool consistent(const LiveSnapshot& s) {
    const auto v = static_cast<std::uint32_t>(s.k);
    if (s.cycle != v) {
        return false;
    }
    for (const std::uint32_t x : s.foreground) {
        if (x != v) {
            return false;
        }
    }
    for (const std::uint32_t x : s.unseen) {
        if (x != v) {
            return false;
        }
    }
    return true;
}

}  // namespace

// verifies: SR-WEB-001
TEST_CASE("web view: the seqlock hands a reader the snapshot published, and refuses while a write is in progress") {
    auto channel = std::make_unique<SnapshotChannel>();
    auto in = std::make_unique<LiveSnapshot>();
    auto out = std::make_unique<LiveSnapshot>();
    CHECK(channel->read(*out, 1));
    CHECK(out->valid == 0U);  // nothing published yet: an empty snapshot
    fill(*in, 42U);
    channel->publish(*in);
    REQUIRE(channel->read(*out, 1));
    CHECK(std::memcmp(in.get(), out.get(), sizeof(LiveSnapshot)) == 0);
    channel->begin_write_for_test();
    fill(*out, 7U);
    CHECK_FALSE(channel->read(*out, 3));  // a writer is between its two sequence steps: every attempt refused
    CHECK(channel->retries() == 3U);
    channel->end_write_for_test();
    CHECK(channel->read(*out, 1));
}

// verifies: SR-WEB-001
TEST_CASE("web view: a reader racing a writer gets only whole snapshots, and the writer never waits") {
    auto channel = std::make_unique<SnapshotChannel>();
    std::atomic<bool> done{false};
    std::atomic<std::uint32_t> published{0U};
    std::thread writer([&] {
        auto s = std::make_unique<LiveSnapshot>();
        for (std::uint32_t v = 1U; v <= 3000U; ++v) {
            fill(*s, v);
            channel->publish(*s);
            published.store(v, std::memory_order_relaxed);
        }
        done.store(true);
    });
    auto out = std::make_unique<LiveSnapshot>();
    int whole = 0;
    int torn = 0;
    int refused = 0;
    while (!done.load()) {
        if (channel->read(*out, 4)) {
            (consistent(*out) ? whole : torn) += 1;
        } else {
            ++refused;
        }
    }
    writer.join();
    CHECK(torn == 0);
    CHECK(published.load() == 3000U);
    REQUIRE(channel->read(*out, 1));
    CHECK(out->k == 3000);
    CHECK(consistent(*out));
    MESSAGE("reads: " << whole << " whole, " << refused << " refused after 4 attempts, retries " << channel->retries());
}

// verifies: SR-WEB-003
TEST_CASE("web view: requests are checked for method, body, path characters, length and the whitelist") {
    CHECK(check_request("GET", "/", -1, 5).status == 200);
    CHECK(check_request("GET", "/", -1, 5).route == Route::kFile);
    CHECK(check_request("HEAD", "/app.js", 0, 5).status == 200);
    CHECK(check_request("GET", "/three/build/three.module.js", -1, 5).route == Route::kFile);
    CHECK(check_request("GET", "/three/examples/jsm/controls/OrbitControls.js", -1, 5).route == Route::kFile);
    CHECK(check_request("GET", "/api/state", -1, 5).route == Route::kState);
    CHECK(check_request("GET", "/api/events", -1, 5).route == Route::kEvents);
    CHECK(check_request("GET", "/api/static", -1, 5).route == Route::kStatic);
    CHECK(check_request("GET", "/api/stops", -1, 5).route == Route::kStops);
    const RequestVerdict pic = check_request("GET", "/api/stops/12/picture.png", -1, 5);
    CHECK(pic.route == Route::kPicture);
    CHECK(pic.stop_number == 12U);
    for (const char* m : {"POST", "PUT", "DELETE", "PROPFIND", "OPTIONS", "PATCH", "get", ""}) {
        CHECK(check_request(m, "/", -1, 5).status == 405);
    }
    CHECK(check_request(nullptr, "/", -1, 5).status == 405);
    CHECK(check_request("GET", "/", 1, 5).status == 413);
    for (const char* u : {"/../etc/passwd", "/three/../../etc/passwd", "/index.html%00.txt", "/%2e%2e/x",
                          "/three\\build", "//etc/passwd", "index.html", "", "/a\tb", "/\x7f", "/\xc3\xa9"}) {
        CHECK_MESSAGE(check_request("GET", u, -1, 5).status == 400, u);
    }
    CHECK(check_request("GET", nullptr, -1, 5).status == 400);
    const std::string longest = "/" + std::string(kMaxUriLength - 1U, 'a');
    CHECK(check_request("GET", longest.c_str(), -1, 5).status == 404);  // long, but allowed: not a route
    const std::string too_long = longest + "a";
    CHECK(check_request("GET", too_long.c_str(), -1, 5).status == 400);
    CHECK(check_request("GET", "/", -1, kMaxHeaderLines).status == 200);
    CHECK(check_request("GET", "/", -1, kMaxHeaderLines + 1).status == 400);
    for (const char* u : {"/etc/passwd", "/index.htm", "/api/state/", "/api/stops/x/picture.png",
                          "/api/stops//picture.png", "/api/stops/1234567890/picture.png", "/three/build/three.js"}) {
        CHECK_MESSAGE(check_request("GET", u, -1, 5).status == (std::strstr(u, "//") ? 400 : 404), u);
    }
}

// verifies: SR-WEB-010
TEST_CASE("web view: ambiguous message framing is 400: two Content-Length lines, any Transfer-Encoding") {
    const HeaderLine one[] = {{"Host", "x"}, {"Content-Length", "0"}};
    CHECK(check_framing(one, 2) == 200);
    CHECK(check_framing(one, 0) == 200);
    CHECK(check_framing(nullptr, 3) == 200);  // no headers at all
    const HeaderLine differ[] = {{"Content-Length", "0"}, {"Content-Length", "41"}};
    CHECK(check_framing(differ, 2) == 400);
    CHECK(check_framing(differ, 1) == 200);  // the count bounds what is read
    const HeaderLine equal[] = {{"content-length", "5"}, {"CONTENT-LENGTH", "5"}};
    CHECK(check_framing(equal, 2) == 400);  // equal values are not merged either
    const HeaderLine chunked[] = {{"Transfer-Encoding", "chunked"}};
    CHECK(check_framing(chunked, 1) == 400);
    const HeaderLine identity[] = {{"transfer-encoding", "identity"}};
    CHECK(check_framing(identity, 1) == 400);
    const HeaderLine both[] = {{"Content-Length", "0"}, {"Transfer-Encoding", "chunked"}};
    CHECK(check_framing(both, 2) == 400);
    for (const char* v : {"", "0, 0", "+1", "-1", " 1", "1 ", "0x10", "1234567890123456789", "1e3"}) {
        const HeaderLine bad[] = {{"Content-Length", v}};
        CHECK_MESSAGE(check_framing(bad, 1) == 400, v);
    }
    const HeaderLine longest[] = {{"Content-Length", "123456789012345678"}};
    CHECK(check_framing(longest, 1) == 200);  // 18 digits: a number (check_request then refuses the body)
    const HeaderLine nulls[] = {{nullptr, nullptr}, {"Content-Length", nullptr}};
    CHECK(check_framing(nulls, 1) == 200);
    CHECK(check_framing(nulls, 2) == 400);
    const HeaderLine near[] = {{"Content-Length2", "1"}, {"Transfer-Encodin", "chunked"}, {"X-Content-Length", "9"}};
    CHECK(check_framing(near, 3) == 200);  // other names
}

// verifies: SR-WEB-004
TEST_CASE("web view: the JSON writer stays inside its buffer and says when the text did not fit") {
    char buffer[64];
    std::memset(buffer, 'Z', sizeof buffer);
    JsonWriter w(buffer, 24U);
    w.raw("{\"a\":").str("q\"\\\n").raw("}");
    CHECK_FALSE(w.overflowed());
    CHECK(std::string(w.c_str()) == "{\"a\":\"q\\\"\\\\\\u000a\"}");
    CHECK(w.size() == 19U);
    w.raw("more!");  // 24 bytes with the NUL: does not fit, nothing written, nothing past the capacity
    CHECK(w.overflowed());
    CHECK(w.size() == 19U);
    CHECK(buffer[19] == '\0');
    for (std::size_t i = 24U; i < sizeof buffer; ++i) {
        CHECK(buffer[i] == 'Z');
    }
    JsonWriter n(buffer, sizeof buffer);
    n.u64(18446744073709551615ULL).raw(",").i64(-5).raw(",").num(0.25).raw(",").num(1.0 / 0.0);
    CHECK_FALSE(n.overflowed());
    CHECK(std::string(n.c_str()) == "18446744073709551615,-5,0.25,null");
    JsonWriter none(buffer, 0U);
    none.raw("x");
    CHECK(none.overflowed());
    // A whole snapshot: fits the server's buffer size, overflows a small one.
    auto s = std::make_unique<LiveSnapshot>();
    fill(*s, 4000000000U);
    s->zone_count = 2U;
    s->active_mask = 3U;
    std::vector<char> big((kLiveMaxForeground + kLiveMaxUnseen) * 11U + 8192U);
    JsonWriter full(big.data(), big.size());
    write_state_json(*s, 1500U, full);
    CHECK_FALSE(full.overflowed());
    CHECK(full.c_str()[0] == '{');
    CHECK(full.c_str()[full.size() - 1U] == '}');
    CHECK(std::strstr(full.c_str(), "\"age_ms\":1.5") != nullptr);
    std::vector<char> small(1024U);
    JsonWriter cut(small.data(), small.size());
    write_state_json(*s, 0U, cut);
    CHECK(cut.overflowed());
    CHECK(cut.size() < small.size());
}

// verifies: SR-WEB-005
TEST_CASE("web view: a zone's state is shown as the CAN safety frame carries it") {
    LiveSnapshot s;
    s.zone_count = 3U;
    s.active_mask = 0b011U;
    s.intruded_mask = 0b001U;
    s.unseen_mask = 0b010U;
    CHECK(std::string(zone_shown_state(s, 0U)) == "INTRUDED");
    CHECK(std::string(zone_shown_state(s, 1U)) == "UNSEEN");
    CHECK(std::string(zone_shown_state(s, 2U)) == "INACTIVE");
    s.unseen_mask = 0U;
    CHECK(std::string(zone_shown_state(s, 1U)) == "CLEAR");
    s.latched_faults = 4U;  // the frame's Fault bit: every active zone FAULT
    CHECK(std::string(zone_shown_state(s, 0U)) == "FAULT");
    CHECK(std::string(zone_shown_state(s, 1U)) == "FAULT");
    CHECK(std::string(zone_shown_state(s, 2U)) == "INACTIVE");
    CHECK(std::string(zone_state_name(0U)) == "CLEAR");
    CHECK(std::string(zone_state_name(200U)) == "FAULT");
}

// verifies: SR-WEB-002
TEST_CASE("web view: --http binds loopback unless an address is named") {
    std::string address;
    int port = -1;
    std::string error;
    REQUIRE(parse_http_address("8080", address, port, error));
    CHECK(address == "127.0.0.1");
    CHECK(port == 8080);
    REQUIRE(parse_http_address(":0", address, port, error));
    CHECK(address == "127.0.0.1");
    CHECK(port == 0);
    REQUIRE(parse_http_address("0.0.0.0:65535", address, port, error));
    CHECK(address == "0.0.0.0");
    CHECK(port == 65535);
    for (const char* bad : {"", ":", "65536", "x:80", "localhost:80", "1.2.3:80", "1.2.3.256:80", "80a", "-1",
                            "1.2.3.4:", "1.2.3.4.5:80"}) {
        CHECK_FALSE_MESSAGE(parse_http_address(bad, address, port, error), bad);
        CHECK(!error.empty());
    }
}

// Issue 32: `--http 1.2.3.4:8080` is well formed but no address of this host; the monitor
// found out only after opening its CAN log. It asks first.
// verifies: SR-WEB-002
TEST_CASE("web view: whether the monitor can listen on --http's address is known before it starts") {
    std::string error;
    CHECK(can_listen_on(":0", "127.0.0.1", 0, error));
    CHECK(error.empty());
    // 192.0.2.1 (TEST-NET-1, RFC 5737) is no address of this host.
    CHECK_FALSE(can_listen_on("192.0.2.1:8080", "192.0.2.1", 8080, error));
    CHECK(error.rfind("--http 192.0.2.1:8080: cannot listen there: ", 0) == 0U);
    // A port another socket listens on.
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof a;
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API takes a sockaddr*
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    REQUIRE(::listen(fd, 1) == 0);
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API takes a sockaddr*
    REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &length) == 0);
    const int busy = ntohs(a.sin_port);
    error.clear();
    CHECK_FALSE(can_listen_on("busy", "127.0.0.1", busy, error));
    CHECK(error.find("cannot listen there") != std::string::npos);
    static_cast<void>(::close(fd));
}

// verifies: SR-WEB-001, SR-GEN-002
TEST_CASE("web view: on the demo's cycles the live view allocates nothing and publishes each cycle") {
    MonitorConfig cfg = demo_config();
    cfg.budget_us = 60000000U;
    MonitorCell cell;
    REQUIRE_FALSE(cell.configure(cfg).failed());
    REQUIRE_FALSE(cell.build_prior(cfg, nullptr).failed());
    REQUIRE_FALSE(cell.build_tables(cfg, nullptr).failed());
    std::vector<std::unique_ptr<SimulatedFrameSource>> owned;
    std::vector<FrameSource*> sources;
    for (const sim::SensorSpec& spec : cell.specs) {
        owned.push_back(std::make_unique<SimulatedFrameSource>(spec));
        sources.push_back(owned.back().get());
    }
    test::SteppingClock source_clock;
    CycleClock clock(false, source_clock);
    test::CountingSender sender;
    CanPort can;
    can.use_sender(sender);
    MonitorLoop loop(cfg, cell, sources, can, clock, nullptr);
    REQUIRE(loop.status().ok());
    LiveView view(cfg, cell.frame_grid, cell.prior.data(), cell.prior.size(), cell.zones);
    loop.set_observer(&view);
    auto snap = std::make_unique<LiveSnapshot>();
    int allocating = 0;
    bool intruded_seen = false;
    for (int k = 0; k < 40; ++k) {
        if (k >= 20) {
            // A reader from cycle 20 on, asking every cycle as a live stream does (asked once, the demand
            // lapses after 2 s, which 20 cycles of the slow coverage build on a loaded host exceeded).
            view.channel().note_demand(linux_port::monotonic_now_us());
        }
        const test::AllocationScope scope;
        const CycleReport& r = loop.run_cycle(k);
        allocating += scope.allocations() != 0U ? 1 : 0;
        REQUIRE(view.channel().read(*snap, 1));
        CHECK(snap->k == k);
        CHECK(snap->cycle == r.cycle);
        CHECK(snap->intruded_mask == r.safety.intruded_mask);
        CHECK(snap->zone_count == r.zones.count);
        CHECK(snap->foreground_count <= kLiveMaxForeground);
        CHECK(snap->voxels == (k >= 20 ? 1U : 0U));  // nobody asked before cycle 20: no scan
        if (k < 20) {
            CHECK(snap->foreground_total == 0U);
        } else if (r.safety.intruded_mask != 0U) {
            intruded_seen = true;
            CHECK(snap->foreground_total > 0U);  // the person's voxels
        }
    }
    CHECK(allocating == 0);
    CHECK(intruded_seen);
}

namespace {

/// Pixels of @p img in @p c.
int count_colour(const host::RgbImage& img, PictureColour c) {
    int n = 0;
    for (std::size_t i = 0U; i + 2U < img.rgb.size(); i += 3U) {
        n += img.rgb[i] == c.r && img.rgb[i + 1U] == c.g && img.rgb[i + 2U] == c.b ? 1 : 0;
    }
    return n;
}

}  // namespace

// verifies: SR-WEB-009
TEST_CASE("web view: the commissioning picture hatches the zone parts no sensor sees in the empty cell") {
    const MonitorConfig cfg = demo_config();
    MonitorCell cell;
    REQUIRE_FALSE(cell.configure(cfg).failed());
    REQUIRE_FALSE(cell.build_prior(cfg, nullptr).failed());
    REQUIRE(cell.background_observed.size() == cell.grid.voxel_count());
    PictureInput in;
    std::string error;
    REQUIRE(config_picture_input("t", cfg, cell.grid, cell.zones, cell.specs, {cell.prior.data(), cell.prior.size()},
                                 "", nullptr, in, error));
    const int without = count_colour(render_config_picture(in), kUnseenColour);
    // The demo's sensors see every accessible voxel of its zones in the empty cell: nothing hatched.
    in.observed = {cell.background_observed.data(), cell.background_observed.size()};
    const int seen = count_colour(render_config_picture(in), kUnseenColour);
    // No sensor sees anything: every zone column with an accessible voxel is hatched.
    const std::vector<std::uint8_t> none(cell.grid.voxel_count(), 0U);
    in.observed = {none.data(), none.size()};
    const int blind = count_colour(render_config_picture(in), kUnseenColour);
    // Everything observed: the legend's swatch only.
    const std::vector<std::uint8_t> all(cell.grid.voxel_count(), 1U);
    in.observed = {all.data(), all.size()};
    const int swatch = count_colour(render_config_picture(in), kUnseenColour);
    CHECK(without == 0);
    CHECK(swatch > 0);
    CHECK(seen == swatch);
    CHECK(blind > swatch + 1000);
    MESSAGE("hatching pixels: " << without << " without flags, " << seen << " as observed, " << blind << " blind");
}
