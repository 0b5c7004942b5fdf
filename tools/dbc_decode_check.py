#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Reads certification/cellguard.dbc with a third-party decoder (canmatrix,
Debian's python3-canmatrix) and checks that it decodes cellguard's encoded
frames to the values they were encoded from.

Usage: tools/dbc_decode_check.py [--dbc DBC] (--frames FILE | --unit-tests BINARY)

The frames come from the C++ encoders: the unit test "dbc: the frames file for
the third-party decoder check" (tests/unit/test_dbc.cpp) writes one line per
frame, candump -L style, with the raw values the frame was encoded from:

  (1700000000.005000) vcan0 0C1#500C3E070180FF7F # MonitoringCase=14 SpeedClass=3 ...

With --unit-tests the script runs that test case itself (environment variable
CELLGUARD_DBC_FRAMES_OUT) into a temporary file. For each frame it checks:
  - the DBC has a message with the frame's ID and DLC;
  - canmatrix decodes exactly the signals named in the line (for the
    multiplexed diagnostics frame: the multiplexor and the selected page);
  - each decoded raw value equals the expected one (signed joints included),
    and each physical value is raw * factor + offset of the DBC;
  - the command parts, their copies and the PLC link frame are transmitted by
    the PLC node, the output frames by CELLGUARD;
and at the end that every message of the DBC was decoded at least once.

Exit status: 0 all checks pass, 1 a check failed, 2 usage or input error,
77 canmatrix is not installed (nothing checked; tools/install-deps.sh installs it).
"""
import argparse
import decimal
import os
import re
import subprocess
import sys
import tempfile

try:
    import canmatrix
    import canmatrix.formats
except ImportError:
    print("dbc_decode_check: canmatrix is not installed for %s (Debian: apt-get install python3-canmatrix, "
          "tools/install-deps.sh); skipped" % sys.executable, file=sys.stderr)
    sys.exit(77)

LINE = re.compile(r"^\((\d+\.\d+)\)\s+(\S+)\s+([0-9A-Fa-f]{3,8})#([0-9A-Fa-f]*)\s+#(.*)$")
TEST_CASE = "dbc: the frames file for the third-party decoder check*"
COMMAND_IDS = range(0x0C1, 0x0C8)  # parts A..C', then the PLC's link frame (protocol 0.2)


def read_frames(path):
    frames = []
    with open(path, encoding="ascii") as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            m = LINE.match(line)
            if not m:
                raise ValueError("%s:%d: not a frame line: %s" % (path, number, line))
            expected = {}
            for item in m.group(5).split():
                name, value = item.split("=", 1)
                expected[name] = int(value)
            frames.append((number, int(m.group(3), 16), bytes.fromhex(m.group(4)), expected))
    return frames


def frames_from_unit_tests(binary, directory):
    path = os.path.join(directory, "frames.log")
    env = dict(os.environ, CELLGUARD_DBC_FRAMES_OUT=path)
    run = subprocess.run([binary, "-tc=" + TEST_CASE], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, check=False)
    if run.returncode != 0 or not os.path.exists(path):
        raise ValueError("%s did not write the frames file (exit %d):\n%s" % (binary, run.returncode, run.stdout))
    return read_frames(path)


def check_frame(db, number, can_id, data, expected, failures):
    where = "line %d, ID 0x%03X" % (number, can_id)
    frame = db.frame_by_id(canmatrix.ArbitrationId(can_id))
    if frame is None:
        failures.append("%s: no message with this ID in the DBC" % where)
        return None
    if frame.size != len(data):
        failures.append("%s: DLC %d, the DBC says %d" % (where, len(data), frame.size))
    sender = "PLC" if can_id in COMMAND_IDS else "CELLGUARD"
    if frame.transmitters != [sender]:
        failures.append("%s (%s): transmitters %s, expected %s" % (where, frame.name, frame.transmitters, sender))
    decoded = frame.decode(data)
    if set(decoded) != set(expected):
        failures.append("%s (%s): canmatrix decoded %s, expected %s" %
                        (where, frame.name, sorted(decoded), sorted(expected)))
    for name, value in expected.items():
        if name not in decoded:
            continue
        signal = decoded[name]
        if int(signal.raw_value) != value:
            failures.append("%s (%s): %s raw %s, expected %d" % (where, frame.name, name, signal.raw_value, value))
        phys = decimal.Decimal(value) * signal.signal.factor + signal.signal.offset
        if decimal.Decimal(signal.phys_value) != phys:
            failures.append("%s (%s): %s physical %s, expected %s" % (where, frame.name, name, signal.phys_value,
                                                                       phys))
    return frame.name


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dbc", default=os.path.join(here, "..", "certification", "cellguard.dbc"))
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--frames", help="a frames file written by the unit test")
    source.add_argument("--unit-tests", help="the cellguard_unit_tests binary: run it to write the frames file")
    args = parser.parse_args()
    try:
        db = canmatrix.formats.loadp_flat(args.dbc)
        if args.frames:
            frames = read_frames(args.frames)
        else:
            with tempfile.TemporaryDirectory() as directory:
                frames = frames_from_unit_tests(args.unit_tests, directory)
    except (OSError, ValueError) as e:
        print("dbc_decode_check: %s" % e, file=sys.stderr)
        return 2
    failures = []
    seen = set()
    signals = 0
    for number, can_id, data, expected in frames:
        name = check_frame(db, number, can_id, data, expected, failures)
        if name is not None:
            seen.add(name)
            signals += len(expected)
    missing = sorted(f.name for f in db.frames if f.name not in seen)
    if missing:
        failures.append("messages of the DBC never decoded: %s" % ", ".join(missing))
    for f in failures:
        print("FAIL: %s" % f, file=sys.stderr)
    if failures:
        return 1
    print("dbc_decode_check: canmatrix decoded %d frames of %d messages, %d signal values, all as encoded"
          % (len(frames), len(seen), signals))
    return 0


if __name__ == "__main__":
    sys.exit(main())
