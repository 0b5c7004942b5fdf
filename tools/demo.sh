#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# README's first command: install dependencies, build the monitor, and run
# the main job on its built-in default: `cellguard-monitor --demo`, the
# simulated paper cell with a person walking through the warning and
# protective zones; the CAN frames go to monitor-demo.log (candump -L format).
# Arguments are passed to cellguard-monitor (e.g. --cycles 120, --log FILE,
# --help); with none, it runs --demo.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake --preset release -B build >/dev/null  # CMakePresets.json
cmake --build build -j "$(nproc)" --target cellguard-monitor
if [ "$#" -eq 0 ]; then
  set -- --demo
fi
exec build/apps/monitor/cellguard-monitor "$@"
