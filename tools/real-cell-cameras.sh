#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The real cell from live cameras (issue 34, item 5): cellguard-fake-camera
# serves apps/monitor/config/real-cell.toml's four 640x480 cameras at 30 Hz
# as fake GigE Vision depth cameras on 127.0.0.2-5, and cellguard-monitor
# --paced runs the same cell from them, on the real clock and the real budget
# (33.3 ms), each cycle started by the cameras' frames. Prints the monitor's
# summary: cycle times (wall and the cycle thread's CPU time), overruns, and the
# latency from each frame's capture and arrival to its CAN frames.
#
# The camera variant of the configuration is written from real-cell.toml
# (a [sensors.camera] table per sensor, the fakes' dither answered by the
# frozen-image check as a real camera's noise would be), so it cannot drift
# from the cell it measures.
#
# usage: tools/real-cell-cameras.sh [--cycles N] [--threads T] [--fine] [--build DIR] [--out DIR]
#   --cycles N   monitor cycles (default 300; the long run: 10000)
#   --threads T  the configuration's fusion.threads (default: real-cell.toml's)
#   --fine       the 2.5 cm variant: the same cell in 2.5 cm voxels (dims doubled per axis, each
#                zone's max_unseen_voxels times 8: the same unseen volume)
#   --build DIR  the build tree (default build)
#   --out DIR    where the configuration, the logs and the summary go (default: a new temporary directory)
# Environment: CELLGUARD_MONITOR_ARGS, more arguments for the monitor (e.g. --period-start:
# cycles on the fixed period instead of started by the cameras' frames, for a comparison).
# Nothing leaves the machine: it runs inside tools/netns-run.sh (loopback only).
# Exit status: 0 the run ended (its figures are printed: this is a measurement, not a test), 1 it did
# not, 2 usage, 77 no namespace.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cycles=300
threads=
fine=0
build=$root/build
out=
while [[ $# -gt 0 ]]; do
    case $1 in
        --cycles) cycles=$2; shift 2 ;;
        --threads) threads=$2; shift 2 ;;
        --fine) fine=1; shift ;;
        --build) build=$(realpath "$2"); shift 2 ;;
        --out) out=$2; shift 2 ;;
        *) echo "usage: tools/real-cell-cameras.sh [--cycles N] [--threads T] [--fine] [--build DIR] [--out DIR]" >&2; exit 2 ;;
    esac
done
[[ "$cycles" =~ ^[0-9]+$ && "$cycles" -gt 0 ]] || { echo "real-cell-cameras: --cycles wants a positive number" >&2; exit 2; }
if [[ "${CELLGUARD_IN_NETNS:-}" != 1 ]]; then
    args=(--cycles "$cycles" --build "$build")
    [[ -n "$threads" ]] && args+=(--threads "$threads")
    [[ $fine -eq 1 ]] && args+=(--fine)
    [[ -n "$out" ]] && args+=(--out "$(realpath -m "$out")")
    exec "$root/tools/netns-run.sh" "$0" "${args[@]}"
fi
fake=$build/apps/fake-camera/cellguard-fake-camera
monitor=$build/apps/monitor/cellguard-monitor
for p in "$fake" "$monitor"; do
    [[ -x "$p" ]] || { echo "real-cell-cameras: $p not built" >&2; exit 1; }
done
[[ -n "$out" ]] || out=$(mktemp -d)
mkdir -p "$out"
config=$out/real-cell-cameras.toml
# A camera table before the table that follows each sensor's keys; address 127.0.0.(k + 1).
awk -v threads="$threads" -v fine="$fine" '
    function camera() {
        k++
        printf "[sensors.camera]\naddress = \"127.0.0.%d\"\nexpected_serial = \"CG-%s\"\n", k + 1, name
        printf "pixel_format = \"Coord3D_C16\"\nframe_rate = 30.0\nmax_stamp_error_ms = 300\npacket_size = 8192\n\n"
    }
    /^\[/ && in_sensor { camera(); in_sensor = 0 }
    /^\[\[sensors\]\]/ { in_sensor = 1 }
    in_sensor && /^name *=/ { name = $3; gsub(/"/, "", name) }
    /^threads *=/ && threads != "" { print "threads = " threads; next }
    fine && /^voxel_size *= *0\.05( |$)/ { print "voxel_size = 0.025"; next }
    fine && /^dims *= *\[80, 80, 50\]/ { print "dims = [160, 160, 100]"; next }
    fine && /^max_unseen_voxels *=/ { print "max_unseen_voxels = " $3 * 8; next }
    /^log_file *=/ { print "log_file = \"monitor-real-cell-cameras.log\""; next }
    { print }
    END {
        printf "camera_stamp_tolerance = \"loopback fakes on a 2-core host deliver frames late (FIELD-NOTES): a measurement run, not a cell\"\n"
    }' "$root/apps/monitor/config/real-cell.toml" >"$config"
if [[ $fine -eq 1 ]] && ! { grep -q '^voxel_size = 0.025$' "$config" && grep -q '^dims = \[160, 160, 100\]$' "$config"; }; then
    echo "real-cell-cameras: --fine: real-cell.toml's grid is no longer 80 x 80 x 50 voxels of 0.05 m" >&2
    exit 1
fi
grep -q '^\[opt_out\]' "$config" || { echo "real-cell-cameras: real-cell.toml has no [opt_out] table to extend" >&2; exit 1; }
period_s=$(awk '/^period_ms/ { print $3 / 1000 }' "$config")
duration=$(awk -v c="$cycles" -v p="$period_s" 'BEGIN { printf "%d", c * p + 60 }')
cd "$out" || exit 1
# Frames rendered once at start (the person stops at cycle 50): the fakes only copy and send.
timeout $((duration + 30)) "$fake" --config "$config" --dither --prerender 60 --duration "$duration" >fake.txt 2>&1 &
fake_pid=$!
for _ in $(seq 300); do
    [[ $(grep -c '^serving sensor' fake.txt 2>/dev/null) -eq 4 ]] && break
    kill -0 "$fake_pid" 2>/dev/null || break
    sleep 0.1
done
if [[ $(grep -c '^serving sensor' fake.txt 2>/dev/null) -ne 4 ]]; then
    cat fake.txt >&2
    echo "real-cell-cameras: the fake cameras did not start" >&2
    kill "$fake_pid" 2>/dev/null
    exit 1
fi
timeout $((duration + 30)) "$monitor" --config "$config" --paced --quiet --cycles "$cycles" ${CELLGUARD_MONITOR_ARGS:-} >monitor.txt 2>&1
status=$?
kill "$fake_pid" 2>/dev/null
wait "$fake_pid" 2>/dev/null
grep -E '^summary|overrun|fault latched' monitor.txt
echo "real-cell-cameras: $cycles cycles, monitor exit status $status; configuration, logs: $out"
[[ $status -eq 0 ]]
