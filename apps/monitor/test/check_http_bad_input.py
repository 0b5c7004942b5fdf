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
advances, and the run, ended by SIGTERM, exits 0.

No step depends on the host's speed (issue 32): the monitor runs until the
checks are done (--forever, then SIGTERM), not for a fixed time they might
outlast on a loaded host; after the flood the check waits until the server
answers again (at most 120 s) instead of sleeping a fixed time; the sixth
event stream is opened once the first five have their answers.

usage: check_http_bad_input.py MONITOR WORK_DIR
"""
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

failures = []
RECOVERY_S = 120  # after the flood: the longest wait for the server to answer again (a loaded host)


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def read_until(s, marker):
    """What arrives on @p s until @p marker is in it, the peer closes, or a timeout or reset."""
    data = b""
    try:
        while marker not in data:
            chunk = s.recv(4096)
            if not chunk:
                break
            data += chunk
    except (socket.timeout, ConnectionResetError):
        pass
    return data


def status_of(reply):
    """The status code at the start of an HTTP answer (0: none)."""
    m = re.match(rb"HTTP/1\.[01] (\d{3})", reply)
    return int(m.group(1)) if m else 0


def raw(port, data, timeout=5.0, read=True):
    """Sends @p data on a new connection; returns the status code (0: closed without an answer)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    try:
        s.sendall(data)
        if not read:
            return s
        reply = read_until(s, b"\r\n")
    finally:
        if read:
            s.close()
    return status_of(reply)


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
    return status_of(reply), closed


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
    mon = subprocess.Popen([monitor, "--demo", "--paced", "--quiet", "--forever", "--budget-ms", "60000",
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
    reader = threading.Thread(target=lambda: rest.extend(mon.stdout), daemon=True)
    reader.start()
    try:
        checks(port)
    finally:
        mon.send_signal(signal.SIGTERM)
        try:
            mon.wait(timeout=120)
        except subprocess.TimeoutExpired:
            mon.kill()
            mon.wait()
    reader.join(timeout=30)
    check(mon.returncode == 0, f"the monitor exited 0 after SIGTERM (got {mon.returncode})")
    cycles = [int(m.group(1)) for line in rest for m in [re.match(r"summary: (\d+) cycles \(stopped by signal\)", line)]
              if m]
    check(len(cycles) == 1, "the summary gives the cycles run")
    frames = sum(1 for line in open(log) if re.search(r" 101#", line))
    check(cycles != [] and frames == cycles[0] and frames > 0,
          f"the CAN log holds one safety frame per cycle ({frames} of {cycles[0] if cycles else '?'})")
    summary = [line.strip() for line in rest if line.startswith("summary: http") or "overruns" in line]
    print("\n".join(summary))
    if failures:
        print(f"FAIL: {len(failures)} checks failed")
        return 1
    print("PASS")
    return 0


def served_again(port):
    """Waits until GET /api/state is answered (at most RECOVERY_S); returns the last status (0: none)."""
    deadline = time.monotonic() + RECOVERY_S
    code = 0
    while time.monotonic() < deadline:
        try:
            code = get(port, b"/api/state")
        except OSError:  # refused or timed out: the queue is still full of the flood
            code = 0
        if code == 200:
            break
        time.sleep(0.2)
    return code


def stream_head(s):
    """The status of an event stream's answer head (0: none)."""
    s.settimeout(30)
    return status_of(read_until(s, b"\r\n\r\n"))


def checks(port):
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
    slow.settimeout(30.0)  # dropped after 2 s; a loaded host may take longer, never forever
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
    # The workers drop the flood's connections after their request timeout (2 s each, a few at a time).
    start = time.monotonic()
    code = served_again(port)
    check(code == 200, f"after the flood, /api/state is served again (got {code} after "
          f"{time.monotonic() - start:.1f} s)")
    # Six event streams: five served, the sixth refused with 503.
    streams = [raw(port, b"GET /api/events HTTP/1.1\r\nHost: x\r\n\r\n", read=False) for _ in range(5)]
    heads = [stream_head(s) for s in streams]  # each counted by the server before its head is sent
    check(heads == [200] * 5, f"five event streams are served (got {heads})")
    code = get(port, b"/api/events")
    check(code == 503, f"a sixth event stream is 503 (got {code})")
    for s in streams:
        s.close()
    after = state(port)["k"]
    check(after > first, f"the cycle went on during all this (k {first} -> {after})")


if __name__ == "__main__":
    sys.exit(main())
