#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The tests do not depend on the machine's load (issue 32): runs the whole
# ctest of BUILD_DIR RUNS times in a row (default 3) while two other ctests
# of the same tree run beside it without pause, plus STRESS CPU workers of
# stress-ng (default 2, when installed), and reports pass or fail per run
# with the failed tests, its time and the load average seen during it.
#
# The two ctests beside it are the load, not the measurement: each runs in
# mount and network namespaces of its own (unshare -mn, as root or in a user
# namespace) with the build tree, at its own path, a copy-on-write overlay
# of a copy taken at the start, and a private /tmp, so their files (the tests' logs, artifacts, fixed /tmp names) and
# their network (vcan, ports) never meet the measured run's. Their own
# results are counted, not judged.
#
# usage: tools/load-test.sh BUILD_DIR [--runs N] [--jobs J] [--stress N] [--log-dir DIR]
#   --jobs J    ctest -j of each of the three ctests (default 2)
#   --stress N  stress-ng --cpu N beside them (default 2; 0: none)
#   --log-dir   where each run's ctest output goes (default BUILD_DIR/load-test)
# Exit status: 0 when every measured run passed, 1 when one failed, 2 usage.
set -euo pipefail
usage() { sed -n 's/^# usage: //p' "$0" >&2; exit 2; }
[[ $# -ge 1 ]] || usage
build=$(cd "$1" && pwd) || usage
shift
runs=3 jobs=2 stress=2 logs=""
while [[ $# -gt 0 ]]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --stress) stress=$2; shift 2 ;;
    --log-dir) logs=$2; shift 2 ;;
    *) usage ;;
  esac
done
[[ -f $build/CTestTestfile.cmake ]] || { echo "load-test: $build is no configured build tree (no CTestTestfile.cmake)" >&2; exit 2; }
logs=${logs:-$build/load-test}
mkdir -p "$logs"
say() { printf 'load-test: %s\n' "$*"; }

# The namespaces for the ctests beside the measured one: root, else a user namespace.
if [[ $(id -u) -eq 0 ]]; then ns=(unshare -mn); else ns=(unshare -rmn); fi
"${ns[@]}" true 2>/dev/null || { echo "load-test: '${ns[*]}' does not work here: cannot isolate the ctests beside the run" >&2; exit 2; }

# Not under /tmp: the ctests beside the run get a private /tmp, which would hide it.
scratch=$(mktemp -d /var/tmp/cellguard-load-test.XXXXXX)
pids=()
cleanup() {
  # Each was started by setsid: its process group holds it and everything it started.
  for p in "${pids[@]}"; do kill -- "-$p" 2>/dev/null || kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 143' TERM INT

# beside N: the whole ctest again and again in namespace N, its build tree
# an overlay of the copy (an overlay's lower tree must not change under it).
beside() {
  local n=$1 d=$scratch/beside$1
  mkdir -p "$d/upper" "$d/work"
  # shellcheck disable=SC2016 # expanded by the inner shell
  setsid "${ns[@]}" bash -c '
    set -u
    mount -t overlay overlay -o "lowerdir=$4,upperdir=$2/upper,workdir=$2/work" "$1" || exit 1
    mount -t tmpfs tmpfs /tmp || exit 1
    ip link set lo up 2>/dev/null || true
    round=0
    while :; do
      round=$((round + 1))
      start=$(date +%s)
      if ctest --test-dir "$1" -j "$3" >"$2/round.log" 2>&1; then r=pass; else r=fail; fi
      echo "$round $r $(($(date +%s) - start)) s: $(sed -n "s/^[[:space:]]*[0-9]* - \([^ ]*\) .*/\1/p" "$2/round.log" | tr "\n" " ")" >>"$2/rounds"
      [ $(($(date +%s) - start)) -ge 10 ] || sleep 10  # a ctest that cannot run does not spin
    done' beside "$build" "$d" "$jobs" "$scratch/tree" >"$d/out" 2>&1 &
  pids+=("$!")
  say "ctest beside the run #$n started (pid $!, overlay in $d)"
}

loadavg() { cut -d' ' -f1 /proc/loadavg; }

say "copying $build for the ctests beside the run ($(du -sh "$build" | cut -f1))"
cp -a "$build" "$scratch/tree"
beside 1
beside 2
if [[ $stress -gt 0 ]]; then
  if command -v stress-ng >/dev/null; then
    setsid stress-ng --cpu "$stress" --quiet >/dev/null 2>&1 &
    pids+=("$!")
    say "stress-ng --cpu $stress started (pid $!)"
  else
    say "stress-ng not installed: no CPU workers beside the ctests"
  fi
fi
sleep 20  # the load builds up before the first run

failed_runs=0
for run in $(seq 1 "$runs"); do
  samples="$scratch/load$run"
  : >"$samples"
  (while :; do loadavg >>"$samples"; sleep 10; done) &
  sampler=$!
  start=$(date +%s)
  setsid ctest --test-dir "$build" -j "$jobs" --output-on-failure >"$logs/run$run.log" 2>&1 &
  measured=$!
  pids+=("$measured")  # ended with the rest if this script is stopped
  if wait "$measured"; then
    result=PASS
  else
    result=FAIL
    failed_runs=$((failed_runs + 1))
  fi
  kill "$sampler" 2>/dev/null || true
  wait "$sampler" 2>/dev/null || true
  took=$(($(date +%s) - start))
  summary=$(grep -E '^[0-9]+% tests passed' "$logs/run$run.log" || echo "no ctest summary")
  load=$(awk '{ s += $1; if (NR == 1 || $1 < lo) lo = $1; if ($1 > hi) hi = $1 } END {
    if (NR) printf "load average %.1f (%.1f..%.1f over %d samples)", s / NR, lo, hi, NR }' "$samples")
  say "run $run: $result in ${took} s, $summary; $load; log $logs/run$run.log"
  if [[ $result == FAIL ]]; then
    sed -n '/The following tests FAILED:/,$p' "$logs/run$run.log" | sed 's/^/load-test:   /'
  fi
done
for n in 1 2; do
  rounds=$scratch/beside$n/rounds
  if [[ -f $rounds ]]; then
    say "ctest beside #$n: $(wc -l <"$rounds") complete rounds, $(grep -c ' fail ' "$rounds" || true) of them failed (the load, not judged):"
    sed 's/^/load-test:   round /' "$rounds"
  else
    say "ctest beside #$n: no complete round"
  fi
done
if [[ $failed_runs -eq 0 ]]; then
  say "PASS: $runs of $runs runs passed"
else
  say "FAIL: $failed_runs of $runs runs failed"
  exit 1
fi
