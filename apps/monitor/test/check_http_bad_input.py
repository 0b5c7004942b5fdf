#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""The browser view's server under bad input (issue 20).

Starts the paced demo monitor with --http 127.0.0.1:0 and a CAN log, sends
bad requests with a raw socket (a malformed request line, an oversized head,
100 header lines, path traversal, %00, a backslash, a long URI, POST, PUT,
DELETE, PROPFIND, a body, ambiguous framing: two Content-Length lines, a
Transfer-Encoding on GET or HEAD, a chunked body of non-hex size; a slow
client, a flood of connections, six event streams), and expects each answered with a 4xx (or the connection closed
without an answer where HTTP has none to give) while the monitor keeps
cycling: its CAN log carries one safety frame per cycle, /api/state's cycle
advances, and the run ends with exit status 0 and every cycle.

usage: check_http_bad_input.py MONITOR WORK_DIR
"""
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import threading
import time

CYCLES = 300  # 30 s paced: longer than the checks take
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def raw(port, data, timeout=5.0, read=True):
    """Sends @p data on a new connection; returns the status code (0: closed without an answer)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    try:
        s.sendall(data)
        if not read:
            return s
        reply = b""
        try:
            while b"\r\n" not in reply:
                chunk = s.recv(4096)
                if not chunk:
                    break
                reply += chunk
        except (socket.timeout, ConnectionResetError):
            pass
    finally:
        if read:
            s.close()
    m = re.match(rb"HTTP/1\.[01] (\d{3})", reply)
    return int(m.group(1)) if m else 0


def answer_and_close(port, data, timeout=5.0):
    """Sends @p data on a new connection and reads until the server closes it; returns
    (status code or 0, closed: the server closed the connection within @p timeout)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    reply = b""
    closed = False
    try:
        s.sendall(data)
        deadline = time.time() + timeout
        while time.time() < deadline:
            chunk = s.recv(4096)
            if not chunk:
                closed = True
                break
            reply += chunk
    except ConnectionResetError:
        closed = True
    except socket.timeout:
        pass
    finally:
        s.close()
    m = re.match(rb"HTTP/1\.[01] (\d{3})", reply)
    return (int(m.group(1)) if m else 0), closed


def get(port, path, method="GET", extra=b""):
    return raw(port, method.encode() + b" " + path + b" HTTP/1.1\r\nHost: x\r\n" + extra + b"\r\n")


def state(port):
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    s.sendall(b"GET /api/state HTTP/1.1\r\nHost: x\r\n\r\n")
    data = b""
    while True:
        chunk = s.recv(65536)
        if not chunk:
            break
        data += chunk
    s.close()
    head, _, body = data.partition(b"\r\n\r\n")
    return json.loads(body)


def main():
    monitor, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    log = os.path.join(work, "can.log")
    mon = subprocess.Popen([monitor, "--demo", "--paced", "--quiet", "--cycles", str(CYCLES), "--budget-ms", "60000",
                            "--http", "127.0.0.1:0", "--log", log],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    port = None
    for line in mon.stdout:
        m = re.search(r"http: serving on http://127\.0\.0\.1:(\d+)/", line)
        if m:
            port = int(m.group(1))
            break
    if port is None:
        print("FAIL: no URL printed")
        return 1
    rest = []
    threading.Thread(target=lambda: rest.extend(mon.stdout), daemon=True).start()
    time.sleep(0.5)
    first = state(port)["k"]
    check(get(port, b"/") == 200, "GET / is 200")
    check(get(port, b"/", "HEAD") == 200, "HEAD / is 200")
    check(get(port, b"/api/static") == 200, "GET /api/static is 200")
    check(get(port, b"/etc/passwd") == 404, "a path outside the whitelist is 404")
    for bad in [b"/../../etc/passwd", b"/three/../../../../etc/passwd", b"/%2e%2e/%2e%2e/etc/passwd",
                b"/index.html%00.txt", b"/app.js%00", b"/three\\build\\three.module.js", b"/" + b"a" * 300,
                b"//etc/passwd"]:
        code = get(port, bad)
        check(400 <= code < 500, f"GET {bad[:40]!r}... is 4xx (got {code})")
    for method in ["POST", "PUT", "DELETE", "PROPFIND", "OPTIONS", "PATCH", "TRACE", "CONNECT"]:
        code = get(port, b"/", method, b"Content-Length: 0\r\n")
        check(400 <= code < 500, f"{method} / is 4xx (got {code})")
    code = raw(port, b"GET /api/state HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\n\r\nhello")
    check(400 <= code < 500, f"a GET with a body is 4xx (got {code})")
    # Ambiguous message framing (issue 33): 400 and the connection closed, so that nothing after the
    # head is read as a second request. Two Content-Length values, equal ones too (not merged); a
    # chunked body of non-hex size on a GET; any Transfer-Encoding on GET or HEAD; Transfer-Encoding
    # beside Content-Length; a Content-Length that is a list or has a sign.
    smuggled = b"GET /api/state HTTP/1.1\r\nHost: x\r\n\r\n"
    for what, request in [
            ("two different Content-Length values",
             b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nContent-Length: 41\r\n\r\n" + smuggled),
            ("two equal Content-Length values",
             b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\ncontent-length: 0\r\n\r\n"),
            ("a GET with a chunked body of non-hex size",
             b"GET / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\nhello\r\n0\r\n\r\n"),
            ("a GET with a well-formed chunked body",
             b"GET / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n"),
            ("a HEAD with Transfer-Encoding: identity",
             b"HEAD / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: identity\r\n\r\n"),
            ("Transfer-Encoding beside Content-Length",
             b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n"),
            ("a Content-Length list",
             b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: 0, 0\r\n\r\n"),
            ("a signed Content-Length",
             b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: +0\r\n\r\n")]:
        code, closed = answer_and_close(port, request)
        check(code == 400 and closed, f"{what} is 400 and the connection closed (got {code}, closed {closed})")
    code, closed = answer_and_close(port, b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\n\r\n")
    check(code == 200 and closed, f"one Content-Length: 0 is still 200 (got {code}, closed {closed})")
    for bad in [b"GARBAGE\r\n\r\n", b"GET\r\n\r\n", b"GET / HTTP/9.9\r\n\r\n", b"\x00\x01\x02\x03\r\n\r\n",
                b"GET / HTTP/1.1\r\nBad Header Without Colon\r\n\r\n"]:
        code = raw(port, bad)
        check(code == 0 or 400 <= code < 500, f"malformed {bad[:24]!r} is 4xx or closed (got {code})")
    code = raw(port, b"GET / HTTP/1.1\r\nHost: x\r\nX-Big: " + b"a" * 20000 + b"\r\n\r\n")
    check(code == 0 or 400 <= code < 500, f"a 20 kB request head is 4xx or closed (got {code})")
    many = b"".join(b"X-H%d: v\r\n" % i for i in range(100))
    code = raw(port, b"GET / HTTP/1.1\r\nHost: x\r\n" + many + b"\r\n")
    check(code == 0 or 400 <= code < 500, f"100 header lines are 4xx or closed (got {code})")
    # A slow client: half a request line, then nothing; the server drops it after its request timeout.
    slow = raw(port, b"GET / HT", read=False)
    slow.settimeout(8.0)
    start = time.time()
    try:
        answer = slow.recv(64)
        gone = answer == b"" or re.match(rb"HTTP/1\.[01] 4\d\d", answer) is not None  # closed, or a 4xx
    except ConnectionResetError:
        gone = True
    except socket.timeout:
        gone = False
    slow.close()
    check(gone, f"the slow client was dropped after {time.time() - start:.1f} s (request timeout 2 s)")
    # A flood: 200 connections opened at once, each sending nothing; some are refused (bounded queue).
    flood = []
    for _ in range(200):
        try:
            flood.append(socket.create_connection(("127.0.0.1", port), timeout=2))
        except OSError:
            break
    check(len(flood) > 0, f"a flood of idle connections: {len(flood)} accepted of 200 tried")
    time.sleep(3.0)
    for s in flood:
        s.close()
    time.sleep(2.5)  # the workers drop the flood's connections after their request timeout
    code = get(port, b"/api/state")
    check(code == 200, f"after the flood, /api/state is served again (got {code})")
    # Six event streams: five served, the sixth refused with 503.
    streams = [raw(port, b"GET /api/events HTTP/1.1\r\nHost: x\r\n\r\n", read=False) for _ in range(5)]
    time.sleep(0.5)
    code = get(port, b"/api/events")
    check(code == 503, f"a sixth event stream is 503 (got {code})")
    for s in streams:
        s.close()
    time.sleep(0.3)
    after = state(port)["k"]
    check(after > first, f"the cycle went on during all this (k {first} -> {after})")
    mon.wait(timeout=120)
    check(mon.returncode == 0, f"the monitor exited 0 (got {mon.returncode})")
    frames = sum(1 for line in open(log) if re.search(r" 101#", line))
    check(frames == CYCLES, f"the CAN log holds one safety frame per cycle ({frames} of {CYCLES})")
    summary = [line.strip() for line in rest if line.startswith("summary: http") or "overruns" in line]
    print("\n".join(summary))
    if failures:
        print(f"FAIL: {len(failures)} checks failed")
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
