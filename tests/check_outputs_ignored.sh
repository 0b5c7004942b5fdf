#!/bin/sh
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# What README's commands write into the clone is ignored by git (issue 32:
# the demos left their CAN logs and the robot image in `git status`, and
# README's evaluation command overwrote 11 committed files): every
# configuration's default CAN log (can.log_file) and every `--out PATH` or
# `--picture PATH` in README.md and apps/*/README.md must be ignored, and
# none may name a tracked file or folder.
# usage: check_outputs_ignored.sh SOURCE_DIR   (exit 77: not a git checkout)
cd "$1" || exit 1
git rev-parse --is-inside-work-tree >/dev/null 2>&1 || { echo "SKIP: not a git checkout"; exit 77; }
failures=0
outputs=$(sed -n 's/^log_file = "\([^"]*\)".*/\1/p' apps/monitor/config/*.toml
          grep -ohE -- '(--out|--picture) [^ `]+' README.md apps/*/README.md | cut -d' ' -f2)
[ -n "$outputs" ] || { echo "FAIL: no outputs found in the configurations and READMEs"; exit 1; }
for f in $outputs; do
  if [ -n "$(git ls-files -- "$f")" ]; then
    echo "FAIL $f: a command writes over tracked files"; failures=$((failures + 1))
  elif git check-ignore -q -- "$f" || git check-ignore -q -- "$f/x"; then
    echo "ok   $f: ignored by git"
  else
    echo "FAIL $f: would show in git status"; failures=$((failures + 1))
  fi
done
[ "$failures" -eq 0 ] && echo PASS || { echo "FAIL: $failures"; exit 1; }
