#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# `cellguard-monitor --write-background` records the EMPTY cell's views from
# simulated sensors (issue 35 item 5: it recorded the demo's scripted person
# into them). The paper cell with a prior file: the views recorded by the
# monitor, then the demo's 60 cycles against them; the person walking out of
# the place where a view had recorded him would make pixels deeper than the
# view and latch the changed-background fault. Passes when no such fault
# latches and the person is still detected.
# Usage: check_write_background_empty.sh MONITOR PRIOR_TOOL CONFIG WORKDIR
set -euo pipefail
monitor=$1 prior_tool=$2 config=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
"$prior_tool" --simulated --background-frames 8 --out "$work/prior" >"$work/prior.out" 2>&1
sed "s|^source = \"simulated-background\".*|source = \"file\"\nfile = \"$work/prior/prior.cgprior\"|" "$config" \
  >"$work/cell.toml"
grep -q '^source = "file"' "$work/cell.toml"
"$monitor" --config "$work/cell.toml" --write-background "$work/views.cgbv" >"$work/record.out" 2>&1
sed "s|^file = \"$work/prior/prior.cgprior\"|&\nbackground_file = \"$work/views.cgbv\"|" "$work/cell.toml" \
  >"$work/with-views.toml"
grep -q '^background_file' "$work/with-views.toml"
"$monitor" --config "$work/with-views.toml" --cycles 60 --log "$work/run.log" >"$work/run.out" 2>&1
grep -q "background views: $work/views.cgbv" "$work/run.out" || { echo "FAIL: the views were not loaded"; exit 1; }
if grep -E -q 'fault latched: [^(]*prior' "$work/run.out"; then
  grep -E 'fault latched' "$work/run.out" | head -n 3
  echo "FAIL: the recorded views hold something the empty cell has not (the changed-background fault latched)"
  exit 1
fi
grep -q 'protective:INTRUDED' "$work/run.out" || { echo "FAIL: the person was not detected"; exit 1; }
echo "PASS: the views recorded from the simulated sensors are the empty cell's: 60 demo cycles, no changed-background fault"
