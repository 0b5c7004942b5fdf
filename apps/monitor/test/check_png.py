#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Checks a PNG written by cellguard-monitor --picture with Python's own zlib:
signature, IHDR, every chunk's CRC-32, the zlib stream (decompressed by
zlib, Adler-32 checked by it), one filter byte 0 or 2 (Up) per row, and that pixels of
both zone colours appear (the demo has a protective and a warning zone).
With --robot: also the robot's blue capsules and the S_p ring of speed
class 0 (magenta, 200/0/200) appear.

Usage: check_png.py [--robot] FILE [min-width min-height]"""
import struct
import sys
import zlib


def fail(msg):
    print(f"check_png: {sys.argv[1]}: {msg}")
    sys.exit(1)


def main():
    robot = "--robot" in sys.argv
    if robot:
        sys.argv.remove("--robot")
    data = open(sys.argv[1], "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("bad signature")
    pos, chunks, idat, ihdr = 8, [], b"", None
    while pos < len(data):
        if pos + 12 > len(data):
            fail(f"truncated chunk at byte {pos}")
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        ctype = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        if zlib.crc32(ctype + body) & 0xFFFFFFFF != crc:
            fail(f"chunk {ctype!r} at byte {pos}: CRC mismatch")
        chunks.append(ctype)
        if ctype == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif ctype == b"IDAT":
            idat += body
        pos += 12 + length
    if chunks[0] != b"IHDR" or chunks[-1] != b"IEND" or ihdr is None:
        fail(f"chunk order {chunks}")
    w, h, depth, colour, comp, filt, interlace = ihdr
    if (depth, colour, comp, filt, interlace) != (8, 2, 0, 0, 0):
        fail(f"unexpected IHDR {ihdr}")
    if len(sys.argv) >= 4 and (w < int(sys.argv[2]) or h < int(sys.argv[3])):
        fail(f"{w} x {h} is smaller than expected")
    raw = zlib.decompress(idat)
    row = 3 * w + 1
    if len(raw) != row * h:
        fail(f"{len(raw)} bytes of scanlines, expected {row * h}")
    if any(raw[y * row] not in (0, 2) for y in range(h)):
        fail("a row with a filter other than 0 (None) or 2 (Up)")
    # Undo the Up filter: each byte plus the (unfiltered) byte above.
    rows = []
    for y in range(h):
        line = bytearray(raw[y * row:(y + 1) * row])
        if line[0] == 2 and rows:
            above = rows[-1]
            for x in range(1, row):
                line[x] = (line[x] + above[x]) & 0xFF
        line[0] = 0
        rows.append(line)
    raw = b"".join(rows)
    red = yellow = blue = ring = 0
    for y in range(h):
        line = raw[y * row + 1:(y + 1) * row]
        for x in range(0, len(line), 3):
            r, g, b = line[x], line[x + 1], line[x + 2]
            red += r > g + 60 and r > b + 60
            yellow += r > b + 60 and g > b + 40 and abs(r - g) < 70
            blue += b > r + 60 and b > g + 40
            ring += (r, g, b) == (200, 0, 200)
    if red < 500 or yellow < 500:
        fail(f"too few zone pixels: {red} red, {yellow} yellow")
    if robot and (blue < 500 or ring < 200):
        fail(f"too few robot pixels: {blue} blue, {ring} on the S_p ring")
    print(f"check_png: {sys.argv[1]}: valid PNG {w} x {h}, chunks {[c.decode() for c in chunks]}, "
          f"{red} protective and {yellow} warning pixels" + (f", {blue} robot and {ring} S_p ring pixels" if robot else ""))


if __name__ == "__main__":
    main()
