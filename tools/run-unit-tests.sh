#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Runs the doctest unit-test binary in shards that run in parallel, one
# process per shard, instead of one process per test case as ctest does.
# Used where the process start per case costs more than it tells: the clang
# build's unit tests in CI and the coverage run of tools/evidence.sh (where
# libgcov merges the shards' .gcda files under a file lock).
# The shards split the cases in a fixed random order (seed 1), so a slow test
# file does not land whole in one shard. Cases marked skip (the live-camera
# cases that need a loopback namespace) stay skipped, as in a plain run.
# Usage: tools/run-unit-tests.sh <cellguard_unit_tests> [shards] [doctest arguments...]
#   shards: default 2 (this project's CI machine has 2 cores)
# Environment: CELLGUARD_UNIT_EMULATOR, words put before the binary (a cross
# build's emulator, e.g. "qemu-aarch64 -L /usr/aarch64-linux-gnu": tools/cross.sh);
# CELLGUARD_UNIT_JOBS, how many shards run at once (default: all of them).
# Exit status: 0 when every shard passed; 1 otherwise, after printing the
# failing shards' output.
set -euo pipefail
unit=${1:?usage: tools/run-unit-tests.sh <cellguard_unit_tests> [shards] [doctest arguments...]}
shards=${2:-2}
shift $(( $# >= 2 ? 2 : 1 ))
[ -x "$unit" ] || { echo "run-unit-tests: $unit is not an executable" >&2; exit 2; }
read -r -a emulator <<<"${CELLGUARD_UNIT_EMULATOR:-}"
case "$shards" in ''|*[!0-9]*|0) echo "run-unit-tests: shards must be a positive number, not '$shards'" >&2; exit 2 ;; esac
count=$("${emulator[@]}" "$unit" --count --no-version "$@" 2>/dev/null | grep -o '[0-9][0-9]*' | tail -n 1)
[ -n "$count" ] && [ "$count" -gt 0 ] || { echo "run-unit-tests: $unit selects no test case" >&2; exit 1; }
per=$(( (count + shards - 1) / shards ))
jobs=${CELLGUARD_UNIT_JOBS:-$shards}
case "$jobs" in ''|*[!0-9]*|0) echo "run-unit-tests: CELLGUARD_UNIT_JOBS must be a positive number, not '$jobs'" >&2; exit 2 ;; esac
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
ranges=()
for (( s = 0; s < shards; s++ )); do
  first=$(( s * per + 1 ))
  last=$(( first + per - 1 ))
  [ "$first" -le "$count" ] || break
  # At most $jobs shards at once: a shard starts when one ends (more shards than cores even out
  # a split in which a few long cases fall together).
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  # Each shard records its exit status and its own wall time.
  ( t=$(date +%s)
    rc=0
    "${emulator[@]}" "$unit" --no-intro --no-version --order-by=rand --rand-seed=1 --first="$first" --last="$last" "$@" \
      >"$logs/$s.log" 2>&1 || rc=$?
    echo $(( $(date +%s) - t )) >"$logs/$s.secs"
    echo "$rc" >"$logs/$s.rc" ) &
  ranges+=("cases $first to $(( last < count ? last : count ))")
done
wait
status=0
for s in "${!ranges[@]}"; do
  if [ "$(cat "$logs/$s.rc" 2>/dev/null)" = 0 ]; then
    # doctest's own case count includes the cases outside the shard's range.
    echo "shard $((s + 1)): ${ranges[$s]}, $(cat "$logs/$s.secs") s: $(grep -E '^\[doctest\] assertions:' "$logs/$s.log" | sed 's/^\[doctest\] //')"
  else
    echo "run-unit-tests: shard $((s + 1)) of ${#ranges[@]} FAILED:"
    cat "$logs/$s.log"
    status=1
  fi
done
echo "run-unit-tests: $count test cases in ${#ranges[@]} shards, $(( jobs < ${#ranges[@]} ? jobs : ${#ranges[@]} )) at a time: $([ "$status" -eq 0 ] && echo passed || echo FAILED)"
exit "$status"
