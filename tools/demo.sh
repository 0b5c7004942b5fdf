#!/usr/bin/env bash
# README's first command: install dependencies, build, and run the main job
# on its built-in default, the simulated workcell.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)" --target cellguard-sim
exec build/apps/simulator/cellguard-sim "$@"
