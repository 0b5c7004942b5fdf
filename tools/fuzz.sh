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
for t in "${targets[@]}"; do
  [ -x "$t" ] || continue
  name=$(basename "$t")
  corpus="$build/corpus/$name"
  mkdir -p "$corpus"
  seeds="tests/fuzz/corpus/$name"
  dirs=("$corpus")
  [ -d "$seeds" ] && dirs+=("$seeds")
  echo "fuzz: $name for ${seconds}s"
  log="$build/$name.log"
  rc=0
  "$t" -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$build/$name-" "${dirs[@]}" >"$log" 2>&1 || rc=$?
  grep -E 'stat::number_of_executed_units|stat::peak_rss' "$log" || true
  if [ "$rc" -ne 0 ]; then
    tail -n 40 "$log"
    echo "fuzz: $name FAILED (exit $rc); the input is saved with prefix $build/$name-"
    exit 1
  fi
done
