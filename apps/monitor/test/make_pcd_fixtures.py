#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Writes the recorded-frame fixtures of apps/monitor/test/pcd-cell.toml into
apps/monitor/test/pcd/: a 16 x 12 sensor 'recorded' at (-1.9, 0, 1.9) aimed
at the centre of the floor (the simulator's pose convention: x right
and horizontal, y down, z forward), its rays cut at the floor z = 0 and the
reference scene's two background boxes (so that the frames show the empty
cell the simulated prior and the sensor's background view are made of);
points in the sensor frame, metres.

- recorded-ascii.pcd: DATA ascii, VIEWPOINT identity, one pixel NaN (no reading)
- recorded-binary.pcd: DATA binary, VIEWPOINT = the sensor's pose
- recorded-other-sensor.pcd: VIEWPOINT of another pose (must be refused)
- recorded-wrong-size.pcd: organised 8 x 12 (must be refused)
- recorded-truncated.pcd: binary data cut short (must be refused)
Run from anywhere; the output is deterministic."""
import math
import os
import struct

W, H, HFOV, VFOV = 16, 12, 40.0, 30.0
POS = (-1.9, 0.0, 1.9)
TARGET = (0.0, 0.0, 0.0)
OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pcd")


def norm(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


fwd = norm(tuple(t - p for t, p in zip(TARGET, POS)))
right = norm(cross(fwd, (0.0, 0.0, 1.0)))
down = cross(fwd, right)
R = [[right[i], down[i], fwd[i]] for i in range(3)]  # columns: sensor axes in the cell
fx = 0.5 * W / math.tan(math.radians(HFOV) / 2)
fy = 0.5 * H / math.tan(math.radians(VFOV) / 2)
cx, cy = 0.5 * (W - 1), 0.5 * (H - 1)


def quaternion(m):
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return (0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s)
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        return ((m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s)
    if m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        return ((m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s)
    s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
    return ((m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s)


# The simulator's reference scene (apps/host/src/sim/workcell.cpp,
# reference_scene): centre, edge lengths, yaw about +z (radians).
BOXES = [((-0.35, 0.2, 0.3), (0.5, 0.4, 0.6), 0.0), ((0.4, -0.25, 0.2), (0.4, 0.6, 0.4), 0.3)]


def intersect_box(box, origin, direction):
    """Entry parameter t of origin + t * direction into the box (its yaw undone), inf when it misses."""
    centre, size, yaw = box
    c, s = math.cos(-yaw), math.sin(-yaw)

    def unyaw(v):
        return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])

    o = unyaw(tuple(a - b for a, b in zip(origin, centre)))
    d = unyaw(direction)
    t0, t1 = 0.0, math.inf
    for a in range(3):
        half = 0.5 * size[a]
        if abs(d[a]) < 1e-15:
            if o[a] < -half or o[a] > half:
                return math.inf
            continue
        ta, tb = (-half - o[a]) / d[a], (half - o[a]) / d[a]
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
        if t0 > t1:
            return math.inf
    return t0


def points(width=W):
    pts = []
    for v in range(H):
        for u in range(width):
            d = ((u - cx) / fx, (v - cy) / fy, 1.0)
            world = tuple(R[i][0] * d[0] + R[i][1] * d[1] + R[i][2] * d[2] for i in range(3))
            t = -POS[2] / world[2]  # the floor z = 0
            for box in BOXES:  # the reference scene's background boxes, as the simulator casts them
                t = min(t, intersect_box(box, POS, world))
            pts.append((d[0] * t, d[1] * t, d[2] * t))
    return pts


def header(kind, n_width, viewpoint, count=None):
    n = n_width * H
    return (f"# .PCD v0.7 - cellguard monitor test fixture (make_pcd_fixtures.py)\n"
            f"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            f"WIDTH {n_width}\nHEIGHT {H}\nVIEWPOINT {viewpoint}\nPOINTS {count or n}\nDATA {kind}\n")


def fmt(x):
    return repr(float(struct.unpack("<f", struct.pack("<f", x))[0]))


def binary(pts):
    return b"".join(struct.pack("<fff", *p) for p in pts)


def main():
    os.makedirs(OUT, exist_ok=True)
    q = quaternion(R)
    pose_vp = f"{POS[0]} {POS[1]} {POS[2]} {q[0]:.9f} {q[1]:.9f} {q[2]:.9f} {q[3]:.9f}"
    pts = points()
    with open(os.path.join(OUT, "recorded-ascii.pcd"), "w") as f:
        f.write(header("ascii", W, "0 0 0 1 0 0 0"))
        for i, p in enumerate(pts):
            f.write("nan nan nan\n" if i == 5 else " ".join(fmt(c) for c in p) + "\n")
    with open(os.path.join(OUT, "recorded-binary.pcd"), "wb") as f:
        f.write(header("binary", W, pose_vp).encode() + binary(pts))
    with open(os.path.join(OUT, "recorded-other-sensor.pcd"), "wb") as f:
        f.write(header("binary", W, f"1.9 0.0 1.9 {q[0]:.9f} {q[1]:.9f} {q[2]:.9f} {q[3]:.9f}").encode() + binary(pts))
    with open(os.path.join(OUT, "recorded-wrong-size.pcd"), "wb") as f:
        f.write(header("binary", 8, "0 0 0 1 0 0 0").encode() + binary(points(8)))
    with open(os.path.join(OUT, "recorded-truncated.pcd"), "wb") as f:
        f.write(header("binary", W, "0 0 0 1 0 0 0").encode() + binary(pts)[:1000])


if __name__ == "__main__":
    main()
