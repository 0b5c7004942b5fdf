#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Writes tests/fuzz/corpus/fuzz_robot_image/palletizer_bar, a robot image in format version 2, from the
version 1 seed test_arm, by certification/robot-image-format.md alone (struct and zlib.crc32): an image made
without the C++ writer, which test_robot_image.cpp compares with the writer's bytes.
Usage: tools/robot_image_v2_seed.py tests/fuzz/corpus/fuzz_robot_image/test_arm OUT"""
import struct, zlib, sys
src = open(sys.argv[1], 'rb').read()[1:]  # drop the mode byte
assert src[:8] == b'CGROBOT1' and struct.unpack_from('<H', src, 8)[0] == 1
links, joints, caps = src[10], src[11], src[12]
assert zlib.crc32(src[:-4]) == struct.unpack_from('<I', src, len(src) - 4)[0]
header = bytearray(src[:108])
link_recs = [src[108 + i * 108:108 + (i + 1) * 108] for i in range(links)]
cap_off = 108 + links * 108
cap_recs = [src[cap_off + i * 60:cap_off + (i + 1) * 60] for i in range(caps)]
two_pi = 6.283185307179586
m, o = -0.5, 0.25
lo, hi = sorted([m * -two_pi + o, m * two_pi + o])
bar = struct.pack('<BBBB', 1, 1, 1, 1) + struct.pack('<13d', -0.1, 0, 0, 1, 0, 0, 0, 0, 1, 0, lo, hi, 2.094)
v2_links = [r + struct.pack('<2d', 1.0, 0.0) for r in link_recs] + [bar + struct.pack('<2d', m, o)]
cap7 = struct.pack('<B3x', 7) + struct.pack('<7d', 0, 0, 0, 0, 0, 0.5, 0.04)
size = 108 + len(v2_links) * 124 + (caps + 1) * 60 + 4
struct.pack_into('<H', header, 8, 2)
header[10] = links + 1
header[12] = caps + 1
struct.pack_into('<I', header, 16, size)
body = bytes(header) + b''.join(v2_links) + b''.join(cap_recs) + cap7
img = body + struct.pack('<I', zlib.crc32(body))
assert len(img) == size
open(sys.argv[2], 'wb').write(b'\x00' + img)
print(len(img), hex(zlib.crc32(body)))
