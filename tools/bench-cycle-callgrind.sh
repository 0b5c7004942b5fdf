#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Instructions per cycle of the cycle benchmark (tests/bench/bench_cycle.cpp),
# counted by callgrind inside SafetyController::run_cycle only (set-up such
# as building the ray tables is not counted), divided by the cycles run.
# The collection is toggled by the overload that takes the PLC's command,
# which runs the cycle: the two-argument overload only tail-calls it, so a
# toggle on that one counted a jump (9 instructions per cycle, 2026-12-05).
# A count below a floor that no real cycle goes under fails the run.
# Instruction counts do not drift with machine load (shared/BENCHMARKING.md).
#
# Usage: tools/bench-cycle-callgrind.sh [build-dir] [cycles] [bench options...]
#   build-dir: default build (must hold tests/bench_cycle, RelWithDebInfo)
#   cycles:    default 20
#   bench options: passed on, e.g. --readings grid-exit
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cycles=${2:-20}
shift $(( $# < 2 ? $# : 2 ))
bench="$build/tests/bench_cycle"
[ -x "$bench" ] || bench=$(find "$build" -name bench_cycle -type f -perm -u+x | head -n 1)
if [ -z "$bench" ] || [ ! -x "$bench" ]; then
    echo "bench-cycle-callgrind: no bench_cycle under $build (cmake --build $build --target bench_cycle)" >&2
    exit 2
fi
command -v valgrind >/dev/null || { echo "bench-cycle-callgrind: valgrind not installed" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$out/callgrind.out" \
    --collect-atstart=no \
    --toggle-collect='cellguard::SafetyController::run_cycle(*, bool, cellguard::CommandInput const&)' \
    "$bench" --cycles "$cycles" --no-timing "$@" >"$out/bench.txt" 2>"$out/valgrind.txt" || {
    cat "$out/bench.txt" "$out/valgrind.txt" >&2
    exit 1
}
total=$(awk '/^totals:/ {print $2}' "$out/callgrind.out")
[ -n "$total" ] || total=$(awk '/^summary:/ {print $2}' "$out/callgrind.out")
if [ -z "$total" ] || [ "$total" -eq 0 ]; then
    echo "bench-cycle-callgrind: callgrind counted nothing inside run_cycle" >&2
    cat "$out/valgrind.txt" >&2
    exit 1
fi
grep -E '^  (voxel steps|zone updates|measured)' "$out/bench.txt" || true
# A cycle fuses at least one sensor frame into a grid and evaluates its zones: tens of
# thousands of instructions even for the smallest cell; fewer means the toggle missed the cycle.
floor=10000
if [ "$(( total / cycles ))" -lt "$floor" ]; then
    echo "bench-cycle-callgrind: $total instructions in $cycles cycles is below $floor a cycle:" \
         "the toggle did not cover the cycle (function names in the profile follow)" >&2
    awk '/^fn=/ {print}' "$out/callgrind.out" | grep -i run_cycle >&2 || true
    exit 1
fi
echo "callgrind: $total instructions in $cycles cycles of SafetyController::run_cycle"
awk -v t="$total" -v n="$cycles" 'BEGIN { printf "instructions per cycle: %.0f (%.2f million)\n", t / n, t / n / 1e6 }'
