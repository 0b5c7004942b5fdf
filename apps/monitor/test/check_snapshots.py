#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Runs the demo monitor with --snapshot-dir and checks the snapshots of
its protective stops.

From the status lines it finds the stops after a release (a STOP cycle
after a run cycle; the paper demo's first is cycle 15). Then:
  - the summary's count of such stops equals that number, and written plus
    skipped equals it too;
  - there is exactly one stop-* directory per written snapshot, each named
    after one of those stop cycles, and none other;
  - each grid is loadable by numpy and byte for byte what numpy.save writes
    (tools/npy_roundtrip_check.py; without numpy: the header is checked
    here), each picture.png a valid PNG with both zone colours
    (check_png.py), each can.log holds candump lines: the frames of the
    cycles up to the stop and after it (3 per cycle in this demo).

Usage: check_snapshots.py MONITOR WORK_DIR SOURCE_DIR
Exit status 0 pass, 1 fail."""
import os
import re
import shutil
import subprocess
import sys

CANDUMP = re.compile(r"^\(\d+\.\d{6}\) \S+ [0-9A-F]{3}#([0-9A-F]{2}){0,8}$")


def fail(msg):
    print(f"check_snapshots: FAIL: {msg}")
    sys.exit(1)


def main():
    monitor, work, source = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    snapdir = os.path.join(work, "snapshots")
    args = [monitor, "--demo", "--cycles", "60", "--budget-ms", "60000", "--log",
            os.path.join(work, "can.log"), "--snapshot-dir", snapdir]
    proc = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)
    if proc.returncode != 0:
        fail(f"exit {proc.returncode}: {proc.stderr}")
    stops, previous = [], None
    for line in proc.stdout.splitlines():
        m = re.match(r"^t=\s*\S+ cycle\s+(\d+) .*\| (STOP|run) ", line)
        if m:
            state = m.group(2)
            if state == "STOP" and previous == "run":
                stops.append(int(m.group(1)))
            previous = state
    if not stops or stops[0] != 15:
        fail(f"the demo's stops after a release: {stops} (expected the first in cycle 15)")
    m = re.search(r"summary: snapshots: (\d+) stops after a release, (\d+) written, (\d+) skipped.*?"
                  r"(\d+) failed, (\d+) old ones removed; longest copy in a stop cycle ([0-9.]+) ms", proc.stdout)
    if not m:
        fail("no snapshot summary line")
    triggered, written, skipped, failed, removed = (int(m.group(i)) for i in range(1, 6))
    print(f"check_snapshots: stops after a release in cycles {stops}; summary: {triggered} stops, {written} "
          f"written, {skipped} skipped, {failed} failed; longest copy {m.group(6)} ms")
    if triggered != len(stops) or written + skipped != len(stops) or failed != 0 or removed != 0:
        fail("the summary does not match the stops")
    dirs = sorted(d for d in os.listdir(snapdir))
    if len(dirs) != written or any(not d.startswith("stop-") for d in dirs):
        fail(f"{len(dirs)} entries in {snapdir}, expected {written} stop-* directories: {dirs}")
    here = os.path.dirname(os.path.abspath(__file__))
    for d in dirs:
        cycle = int(d.rsplit("-", 1)[1])
        if cycle not in stops:
            fail(f"{d}: cycle {cycle} is not a stop after a release")
        path = os.path.join(snapdir, d)
        files = sorted(os.listdir(path))
        expected = ["can.log", "grid_log_odds.npy", "grid_observed.npy", "grid_probability.npy", "picture.png",
                    "snapshot.txt"]
        if files != expected:
            fail(f"{d}: files {files}")
        npy = subprocess.run([sys.executable, os.path.join(source, "tools", "npy_roundtrip_check.py"),
                              os.path.join(path, "grid")], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True)
        if npy.returncode == 77:
            with open(os.path.join(path, "grid_log_odds.npy"), "rb") as f:
                head = f.read(128)
            if not head.startswith(b"\x93NUMPY\x01\x00") or b"'descr': '<i2'" not in head:
                fail(f"{d}: grid_log_odds.npy header {head[:60]!r}")
        elif npy.returncode != 0:
            fail(f"{d}: npy_roundtrip_check: {npy.stdout}")
        png = subprocess.run([sys.executable, os.path.join(here, "check_png.py"), os.path.join(path, "picture.png"),
                              "800", "500"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if png.returncode != 0:
            fail(f"{d}: check_png: {png.stdout}")
        lines = open(os.path.join(path, "can.log")).read().splitlines()
        frames = lines
        bad = [line for line in frames if not CANDUMP.match(line)]
        if bad:
            fail(f"{d}: not candump -L lines: {bad[:3]}")
        text = open(os.path.join(path, "snapshot.txt")).read()
        before = int(re.search(r"^can_frames_before (\d+)$", text, re.M).group(1))
        after = int(re.search(r"^can_frames_after (\d+)$", text, re.M).group(1))
        # Five frames a cycle (protocol 0.2): safety, copy, the controller's and the simulated PLC's link frames,
        # diagnostics.
        want_before = min(64, 5 * (cycle + 1))
        want_after = min(64, 5 * (60 - cycle - 1))
        if (before, after) != (want_before, want_after) or len(frames) != before + after:
            fail(f"{d}: {before} frames before and {after} after, expected {want_before} and {want_after}")
        print(f"check_snapshots: {d}: grid, picture and {before} + {after} CAN frames checked "
              f"({'numpy' if npy.returncode == 0 else 'header only, no numpy'})")
    print("check_snapshots: pass")


if __name__ == "__main__":
    main()
