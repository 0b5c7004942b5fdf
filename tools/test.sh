#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# README's test command: install dependencies, build with warnings as errors
# (the release preset of CMakePresets.json), run every unit test.
# Usage: tools/test.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tools/install-deps.sh
cmake --preset release -B "$build"  # CMakePresets.json: RelWithDebInfo, Ninja, warnings as errors
cmake --build "$build" -j "$(nproc)"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
