#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# README's first command: install dependencies, build the monitor, and run
# the main job on its built-in default: `cellguard-monitor --demo`, the
# simulated paper cell with a person walking through the warning and
# protective zones; the CAN frames go to monitor-demo.log (candump -L format).
# Arguments are passed to cellguard-monitor (e.g. --cycles 120, --log FILE,
# --help); with none, it runs --demo.
# On a fresh machine it installs only what the programs need (install-deps.sh
# --demo) and configures build/ with the demo preset (no tests, no benchmarks);
# a build/ that tools/test.sh configured already is reused as it is.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh --demo
if [ -f build/CMakeCache.txt ]; then
  cmake -B build >/dev/null  # keeps the preset it was configured with (release from tools/test.sh, or demo)
else
  cmake --preset demo >/dev/null  # CMakePresets.json: build/, the programs only
fi
cmake --build build -j "$(nproc)" --target cellguard-monitor
if [ "$#" -eq 0 ]; then
  set -- --demo
fi
exec build/apps/monitor/cellguard-monitor "$@"
