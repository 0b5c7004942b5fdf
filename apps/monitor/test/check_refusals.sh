#!/bin/sh
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The monitor's refusals at start-up (issue 32): each exits with the status
# --help gives (2: bad command line or configuration), says why on stderr,
# naming the file and what is wrong, and leaves the previous run's CAN log
# as it was.
# usage: check_refusals.sh MONITOR SOURCE_DIR WORK_DIR
set -u
monitor=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
failures=0
log=$work/previous-run.log
previous='(1700000000.000000) vcan0 101#0000000000000000'
# expect STATUS TEXT ARGS...: the exit status, a text stderr must hold, the log untouched.
expect() {
  status=$1 text=$2
  shift 2
  printf '%s\n' "$previous" >"$log"
  "$monitor" "$@" --log "$log" >"$work/out" 2>"$work/err"
  got=$?
  what="cellguard-monitor $*"
  if [ "$got" -ne "$status" ]; then
    echo "FAIL $what: exit status $got, expected $status"; failures=$((failures + 1))
  elif ! grep -qF -- "$text" "$work/err"; then
    echo "FAIL $what: stderr does not say '$text'"; failures=$((failures + 1))
  elif [ "$(cat "$log")" != "$previous" ]; then
    echo "FAIL $what: the previous CAN log was changed ($(wc -c <"$log") bytes)"; failures=$((failures + 1))
  else
    echo "ok   $what: exit $got, the previous log kept: $(head -n 1 "$work/err")"
  fi
}
# A configuration whose prior file is missing, and one whose zone leaves the grid.
sed -e 's|^source = "simulated-background".*|source = "file"\nfile = "no-such-prior.cgprior"|' \
  "$src/apps/monitor/config/paper-cell.toml" >"$work/missing-prior.toml"
sed -e 's|^max = \[0.4, 0.6, 1.2\]|max = [0.4, 0.6, 9.0]|' \
  "$src/apps/monitor/config/paper-cell.toml" >"$work/zone-outside.toml"
grep -q 'no-such-prior' "$work/missing-prior.toml" && grep -q '9.0\]' "$work/zone-outside.toml" ||
  { echo "FAIL: the test configurations were not made (paper-cell.toml changed?)"; exit 1; }
if "$monitor" --help | grep -q -- '--http ADDRESS:PORT' && ! "$monitor" --help | grep -q 'not in this build'; then
  expect 2 '--http 192.0.2.1:8080: cannot listen there' --demo --cycles 3 --http 192.0.2.1:8080
  expect 2 '--http 1.2.3.4:8080: cannot listen there' --demo --cycles 3 --http 1.2.3.4:8080
fi
expect 2 "$work/missing-prior.toml: prior.file: " --config "$work/missing-prior.toml" --cycles 3
expect 2 'no-such-prior.cgprior' --config "$work/missing-prior.toml" --cycles 3
expect 2 "$work/zone-outside.toml: line " --config "$work/zone-outside.toml" --cycles 3
expect 2 "the grid spans x " --config "$work/zone-outside.toml" --cycles 3
expect 2 '/tmp: not a configuration file (a directory)' --config /tmp --cycles 3
expect 2 'cannot open the configuration file' --config "$work/none.toml" --cycles 3
# The same log is replaced by a run that starts (the refusals above did not just fail to write).
printf '%s\n' "$previous" >"$log"
if "$monitor" --demo --quiet --cycles 2 --log "$log" >"$work/out" 2>"$work/err" &&
  [ "$(grep -c ' 101#' "$log")" -eq 2 ] && ! grep -qF "$previous" "$log"; then
  echo "ok   a run that starts replaces the previous log (2 safety frames)"
else
  echo "FAIL a run that starts did not replace the previous log"; failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] && echo PASS || { echo "FAIL: $failures"; exit 1; }
