#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Aravis's own client (arv-tool-0.8, Debian aravis-tools-cli) reads the fake
# cameras of cellguard-fake-camera over GVCP and finds a GigE Vision depth
# camera: the demo's four sensors on 127.0.0.2-5, Coord3D_C16 offered and set, the Scan3d
# values (the focal length computed here from the demo's field of view,
# independently of the program), their serials, read-only Width.
# Run inside tools/netns-run.sh (addresses 127.0.0.2 and up).
# usage: arv-tool-check.sh FAKE_CAMERA ARV_TOOL
set -euo pipefail
fake=$1
arv=$2
out=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$out"' EXIT
timeout 60 "$fake" --demo --duration 30 >"$out/fake.txt" 2>&1 &
pid=$!
for _ in $(seq 50); do  # up to 5 s for the four "serving" lines
    [[ $(grep -c '^serving sensor' "$out/fake.txt" || true) -eq 4 ]] && break
    sleep 0.1
done
cat "$out/fake.txt"
fail=0
expect() {  # expect FILE REGEX: the line must be in the client's output
    if grep -Eq "$2" "$1"; then echo "ok: $2"; else echo "FAILED: no line matching '$2'"; fail=1; fi
}
timeout 20 "$arv" -a 127.0.0.2 control PixelFormat PixelFormat=Coord3D_C16 PixelFormat DeviceSerialNumber Width Height SensorWidth Scan3dDistanceUnit \
    Scan3dCoordinateScale Scan3dCoordinateOffset Scan3dFocalLength Scan3dAspectRatio Scan3dPrincipalPointU \
    Scan3dPrincipalPointV Scan3dInvalidDataFlag Scan3dInvalidDataValue AcquisitionFrameRate PayloadSize \
    Width=640 >"$out/a.txt" 2>&1 || true
cat "$out/a.txt"
# lidar-a: 176 x 144, 43.6 x 34.6 degrees: fx = 88 / tan(21.8 deg), fy = 72 / tan(17.3 deg).
fx=$(awk 'BEGIN { d = atan2(0, -1) / 180; printf "%.3f", 88 / (sin(21.8 * d) / cos(21.8 * d)) }')
ar=$(awk 'BEGIN { d = atan2(0, -1) / 180; printf "%.4f", (72 / (sin(17.3 * d) / cos(17.3 * d))) / (88 / (sin(21.8 * d) / cos(21.8 * d))) }')
expect "$out/a.txt" '^PixelFormat = Mono16$'  # the power-on format; then set:
expect "$out/a.txt" '^PixelFormat = Coord3D_C16$'
expect "$out/a.txt" '^DeviceSerialNumber = CG-lidar-a$'
expect "$out/a.txt" '^Width = 176$'
expect "$out/a.txt" '^Height = 144$'
expect "$out/a.txt" '^Scan3dDistanceUnit = Millimeter$'
expect "$out/a.txt" '^Scan3dCoordinateScale = 1$'
expect "$out/a.txt" '^Scan3dCoordinateOffset = 0$'
expect "$out/a.txt" "^Scan3dFocalLength = ${fx%?}[0-9]* px$"
expect "$out/a.txt" "^Scan3dAspectRatio = ${ar%?}[0-9]*$"
expect "$out/a.txt" '^Scan3dPrincipalPointU = 87.5 px$'
expect "$out/a.txt" '^Scan3dPrincipalPointV = 71.5 px$'
expect "$out/a.txt" '^Scan3dInvalidDataFlag = true$'
expect "$out/a.txt" '^Scan3dInvalidDataValue = 0$'
expect "$out/a.txt" '^AcquisitionFrameRate = 10 '
expect "$out/a.txt" '^PayloadSize = 50688$'  # 176 * 144 * 2
expect "$out/a.txt" '^Width write error: .*Read only'
for n in 3 4 5; do
    timeout 20 "$arv" -a "127.0.0.$n" control DeviceSerialNumber Width PixelFormat >"$out/$n.txt" 2>&1 || true
    cat "$out/$n.txt"
done
expect "$out/3.txt" '^DeviceSerialNumber = CG-lidar-b$'
expect "$out/4.txt" '^DeviceSerialNumber = CG-stereo-a$'
expect "$out/4.txt" '^Width = 320$'
expect "$out/5.txt" '^DeviceSerialNumber = CG-stereo-b$'
expect "$out/5.txt" '^PixelFormat = Mono16$'
kill -TERM "$pid"
wait "$pid" || { echo "FAILED: cellguard-fake-camera exited with $?"; fail=1; }
cat "$out/fake.txt"
expect "$out/fake.txt" "^sensor 'stereo-b': [0-9]+ frames"
exit $fail
