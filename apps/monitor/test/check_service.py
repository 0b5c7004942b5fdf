#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Runs cellguard-monitor as systemd would run a Type=notify service and
checks what it tells the service manager and the journal.

A unix datagram socket of this script stands in for systemd's notify
socket (NOTIFY_SOCKET, WATCHDOG_USEC); stderr goes to a file named in
JOURNAL_STREAM, as systemd connects it to journald. Checks:
  - READY=1 comes first, STOPPING=1 last, nothing after it;
  - WATCHDOG=1 only after READY=1, never two closer than half the watchdog
    interval (less 150 ms for this machine's scheduling), and at least one
    per watchdog interval over the paced run;
  - STATUS= changes arrive (the start-up stop, the release, the stop);
  - the event log carries syslog priorities: <4> for the protective stop,
    <5> for the release, <6> for the heartbeat; no line per cycle.

Usage: check_service.py MONITOR WORK_DIR [extra monitor arguments]
Prints the figures it measured. Exit status 0 pass, 1 fail."""
import os
import socket
import subprocess
import sys
import threading
import time

WATCHDOG_US = 1_000_000
MARGIN_S = 0.15


def fail(msg):
    print(f"check_service: FAIL: {msg}")
    sys.exit(1)


def main():
    monitor, work = sys.argv[1], sys.argv[2]
    extra = sys.argv[3:]
    os.makedirs(work, exist_ok=True)
    sock_path = os.path.join(work, "notify.sock")
    if os.path.exists(sock_path):
        os.unlink(sock_path)
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(sock_path)
    sock.settimeout(0.2)
    messages = []  # (time, text)
    done = threading.Event()

    def receive():
        while not done.is_set():
            try:
                data = sock.recv(4096)
            except socket.timeout:
                continue
            messages.append((time.monotonic(), data.decode()))

    receiver = threading.Thread(target=receive)
    receiver.start()
    stderr_path = os.path.join(work, "stderr.log")
    with open(stderr_path, "w") as err:
        st = os.fstat(err.fileno())
        env = dict(os.environ)
        env.update(NOTIFY_SOCKET=sock_path, WATCHDOG_USEC=str(WATCHDOG_US),
                   JOURNAL_STREAM=f"{st.st_dev}:{st.st_ino}")
        env.pop("WATCHDOG_PID", None)
        args = [monitor, "--demo", "--paced", "--quiet", "--cycles", "60", "--budget-ms", "60000",
                "--heartbeat-s", "2", "--log", os.path.join(work, "can.log")] + extra
        start = time.monotonic()
        proc = subprocess.run(args, env=env, stdout=subprocess.PIPE, stderr=err, timeout=120)
        end = time.monotonic()
    time.sleep(0.3)
    done.set()
    receiver.join()
    if proc.returncode != 0:
        fail(f"the monitor exited {proc.returncode}")
    texts = [m for _, m in messages]
    if not texts or not texts[0].startswith("READY=1"):
        fail(f"READY=1 is not the first message: {texts[:3]}")
    if not texts[-1].startswith("STOPPING=1"):
        fail(f"STOPPING=1 is not the last message: {texts[-3:]}")
    ready_t = messages[0][0]
    stopping_t = messages[-1][0]
    pings = [t for t, m in messages if m == "WATCHDOG=1"]
    statuses = [m for _, m in messages if m.startswith("STATUS=")]
    if not pings:
        fail("no WATCHDOG=1")
    gaps = [b - a for a, b in zip(pings, pings[1:])]
    half = WATCHDOG_US / 2e6
    run_s = stopping_t - ready_t
    print(f"check_service: run {run_s:.2f} s from READY=1 to STOPPING=1, {len(pings)} WATCHDOG=1, "
          f"gaps min {min(gaps):.3f} s max {max(gaps):.3f} s (interval {WATCHDOG_US / 1e6:.1f} s, "
          f"rate limit {half:.1f} s), {len(statuses)} STATUS= messages, {len(texts)} messages in all; "
          f"whole process {end - start:.2f} s")
    if min(gaps) < half - MARGIN_S:
        fail(f"two WATCHDOG=1 only {min(gaps):.3f} s apart (rate limit {half} s)")
    if max(gaps) > WATCHDOG_US / 1e6:
        fail(f"no WATCHDOG=1 for {max(gaps):.3f} s, more than the watchdog interval")
    if pings[-1] < stopping_t - WATCHDOG_US / 1e6 or pings[0] > ready_t + WATCHDOG_US / 1e6:
        fail("the pings do not cover the run")
    if len(statuses) < 3:
        fail(f"expected STATUS= for the start-up stop, the release and the stop: {statuses}")
    log = open(stderr_path).read().splitlines()
    print(f"check_service: event log: {len(log)} lines for 60 cycles")
    for prefix, what in (("<4>protective stop (a protective zone intruded): intruded protective", "the stop at warning"),
                         ("<5>stop released", "the release at notice"),
                         ("<6>heartbeat: ", "a heartbeat at info")):
        if not any(line.startswith(prefix) for line in log):
            fail(f"no {what} ({prefix!r}) in the event log:\n" + "\n".join(log))
    if any(not line.startswith("<") for line in log):
        fail("a line without a syslog prefix under JOURNAL_STREAM")
    if len(log) >= 60:
        fail(f"{len(log)} log lines for 60 cycles: a line per cycle?")
    print("check_service: pass")


if __name__ == "__main__":
    main()
