#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The depth filter in the monitor's camera path ([depth_filter]): the paper
# cell's demo (frozen-sensor check on, dithered simulated frames) runs with
# the edge filter and the background tolerance on. The filter puts nearly
# every pixel onto the empty cell's depth, so the filtered frames repeat; the
# frozen-sensor check judges the frames as delivered and must not fire. The
# person is detected in the same cycles as without the filter, and the run's
# summary gives the filter's counts for each of the four sensors.
# Usage: check_depth_filter.sh MONITOR CONFIG WORKDIR
set -euo pipefail
monitor=$1 config=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
grep -q '^max_repeated_frames = 3' "$config" || { echo "FAIL: the frozen-sensor check is not on in $config"; exit 1; }
cp "$config" "$work/plain.toml"
cat "$config" - >"$work/filtered.toml" <<'TOML'

[depth_filter]
edge_jump_percent = 4
edge_jump_min_m = 0.05
edge_radius = 2
background_tolerance_percent = 5
reason = "the test of the filter in the camera path"
TOML
"$monitor" --config "$work/plain.toml" --cycles 60 --log "$work/plain.log" >"$work/plain.out" 2>&1
"$monitor" --config "$work/filtered.toml" --cycles 60 --log "$work/filtered.log" >"$work/filtered.out" 2>&1
grep -q '^depth filter: off' "$work/plain.out" || { echo "FAIL: the plain run does not say the filter is off"; exit 1; }
grep -q '^depth filter: edge jump 4.0 % of depth, at least 50 mm, radius 2; background tolerance 5.0 %' \
  "$work/filtered.out" || { echo "FAIL: the filtered run does not print its filter"; exit 1; }
counts=$(grep -c '^depth filter ([a-z0-9-]*): 60 frames' "$work/filtered.out" || true)
[ "$counts" -eq 4 ] || { echo "FAIL: $counts of 4 sensors report the filter's counts"; exit 1; }
named=$(grep -o '^depth filter ([a-z0-9-]*)' "$work/filtered.out" | sort -u | wc -l)
[ "$named" -eq 4 ] || { echo "FAIL: the filter's counts name $named sensors, not 4"; exit 1; }
if grep -E -q 'fault latched|faults latched: [^-]|[|] faults [^-]' "$work/filtered.out"; then
  grep -E 'fault latched|faults latched: [^-]|[|] faults [^-]' "$work/filtered.out" | head -n 3
  echo "FAIL: a fault in the filtered run (the frozen-sensor check on the filtered frames?)"
  exit 1
fi
transitions() { grep -E "^zone '|^protective stop|^stop released" "$1"; }
if ! diff <(transitions "$work/plain.out") <(transitions "$work/filtered.out"); then
  echo "FAIL: the zones change state in other cycles with the filter"
  exit 1
fi
grep -q "zone 'protective' (protective): CLEAR -> INTRUDED" "$work/filtered.out" ||
  { echo "FAIL: the person was not detected"; exit 1; }
echo "PASS: the filtered demo: 4 sensors filtered for 60 cycles, no fault, the zones' transitions as without the filter"
