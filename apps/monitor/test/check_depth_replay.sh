#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Recorded depth images through the monitor (SR-SYS-011): `--record-depth`
# records CYCLES frames of every sensor of CONFIG (simulated), a copy of
# CONFIG with `depth_files` in every sensor table replays them, and the
# replay's decisions equal the simulated run's cycle by cycle (zone states,
# outputs, faults and the event lines), with each fusion method; a recording
# with one file truncated is refused at start.
# Usage: check_depth_replay.sh MONITOR CONFIG WORKDIR CYCLES
set -euo pipefail
monitor=$1 config=$2 work=$3 cycles=$4
rm -rf "$work"
mkdir -p "$work"
"$monitor" --config "$config" --cycles "$cycles" --record-depth "$work/rec" >"$work/record.out"
grep -c '^recorded depth images: sensor' "$work/record.out" >/dev/null
# The replay's configuration: depth_files after the name of every [[sensors]] table.
awk -v rec="$work/rec" '
  /^\[\[sensors\]\]/ { sensor = 1 }
  /^\[\[zones\]\]|^\[[a-z_]+\]/ { sensor = 0 }
  { print }
  sensor && /^name = "/ { n = $0; sub(/^name = "/, "", n); sub(/".*/, "", n); print "depth_files = \"" rec "/" n "\"" }
' "$config" >"$work/replay.toml"
[ "$(grep -c '^depth_files' "$work/replay.toml")" -eq "$(grep -c '^\[\[sensors\]\]' "$config")" ]
# A cycle's decisions: its status line without the scene text and the cycle time, and the event lines.
decisions() { sed -E -n 's/^(t= *[0-9.]+s cycle +[0-9]+) [^|]*(\|.*) \| cycle [0-9.]+ ms$/\1 \2/p; /^(zone|fault|stop|release)/p' "$1"; }
for fusion in ray footprint; do
  "$monitor" --config "$config" --cycles "$cycles" --fusion "$fusion" --log "$work/sim.log" >"$work/sim-$fusion.out"
  "$monitor" --config "$work/replay.toml" --cycles "$cycles" --fusion "$fusion" --log "$work/rep.log" \
    >"$work/rep-$fusion.out"
  grep -q "recorded depth images used, 0 refused" "$work/rep-$fusion.out"
  decisions "$work/sim-$fusion.out" >"$work/sim-$fusion.txt"
  decisions "$work/rep-$fusion.out" >"$work/rep-$fusion.txt"
  [ "$(grep -c ' cycle ' "$work/sim-$fusion.txt")" -eq "$cycles" ]
  diff "$work/sim-$fusion.txt" "$work/rep-$fusion.txt" || { echo "FAIL: the replay decides otherwise ($fusion)"; exit 1; }
done
# One file cut short: the configuration is refused at start, naming the file (exit status 2);
# a file that changes after the start is refused in its cycle (tests/unit/test_depth_input.cpp).
first=$(find "$work/rec" -name 'frame-000002.npy' | sort | head -n 1)
head -c 100 "$first" >"$first.cut" && mv "$first.cut" "$first"
rc=0
"$monitor" --config "$work/replay.toml" --cycles "$cycles" --log "$work/rep.log" >"$work/cut.out" 2>&1 || rc=$?
[ "$rc" -eq 2 ] || { echo "FAIL: a truncated recording was not refused (exit $rc)"; exit 1; }
grep -q "depth_files\[2\]: $first: npy: " "$work/cut.out"
echo "PASS: $cycles cycles replayed from recorded depth images decide as the simulated run (ray, footprint);" \
     "a truncated file is refused at start"
