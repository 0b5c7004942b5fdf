#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Builds every tests/fuzz/fuzz_*.cpp with libFuzzer + ASan + UBSan (clang)
# and runs each for a fixed time. Usage: tools/fuzz.sh [build-dir] [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
seconds=${2:-30}
# The fuzz preset (CMakePresets.json): clang, RelWithDebInfo, the fuzz targets
# only, -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined.
cmake --preset fuzz -B "$build" >/dev/null
cmake --build "$build" -j "$(nproc)"
shopt -s nullglob
targets=("$build"/tests/fuzz_*)
if [ ${#targets[@]} -eq 0 ]; then
  echo "fuzz: no targets"
  exit 0
fi
# One target per core at a time (CELLGUARD_FUZZ_JOBS, default nproc): each libFuzzer run is one process.
jobs=${CELLGUARD_FUZZ_JOBS:-$(nproc)}
run_target() {  # <target>: runs it, prints its figures; exit 1 on a finding
  local t=$1 name corpus seeds log rc=0
  name=$(basename "$t")
  corpus="$build/corpus/$name"
  mkdir -p "$corpus"
  seeds="tests/fuzz/corpus/$name"
  local dirs=("$corpus")
  [ -d "$seeds" ] && dirs+=("$seeds")
  log="$build/$name.log"
  "$t" -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$build/$name-" "${dirs[@]}" >"$log" 2>&1 || rc=$?
  echo "fuzz: $name for ${seconds}s: $(grep -E 'stat::number_of_executed_units|stat::peak_rss' "$log" | tr -s ' ' | tr '\n' ' ')"
  if [ "$rc" -ne 0 ]; then
    tail -n 40 "$log"
    echo "fuzz: $name FAILED (exit $rc); the input is saved with prefix $build/$name-"
    return 1
  fi
}
status=0
pids=()
for t in "${targets[@]}"; do
  [ -x "$t" ] || continue
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
  run_target "$t" &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
[ "$status" -eq 0 ] || { echo "fuzz: a target failed (above)"; exit 1; }
echo "fuzz: ${#targets[@]} targets, no finding"
