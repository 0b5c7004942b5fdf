#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Builds tests/consumer, a small program that uses cellguard::cellguard, in
# the two ways another project would use cellguard, and runs it:
#  (a) package:      cellguard's lib/ built and installed (`cmake --install`)
#                    into a temporary prefix, the consumer configured with
#                    find_package(cellguard CONFIG REQUIRED) against it;
#  (b) subdirectory: the consumer adds this source tree with add_subdirectory.
# Both consumer builds are Debug (Eigen's assertions on), so a leaked
# EIGEN_NO_MALLOC would stop the consumer's own dynamic-size Eigen matrix (the
# consumer also refuses to compile if it sees the macro). In (b) no cellguard
# test, program or benchmark target may exist, -Werror must be off and the
# consumer's build type must be its own.
# Usage: tools/consumer-check.sh [work-dir]   (default: a temporary directory, removed at the end)
# Environment: CELLGUARD_JOBS (default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=${CELLGUARD_JOBS:-2}
if [ "$#" -ge 1 ]; then
  work=$1
  rm -rf "$work"
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
say() { echo "consumer-check: $*"; }
die() { say "FAIL: $*"; exit 1; }

say "(a) package: building lib/ and installing it into $work/prefix"
cmake --preset package -B "$work/cellguard" >"$work/cellguard-configure.log" 2>&1 ||
  { cat "$work/cellguard-configure.log"; die "configuring cellguard"; }
cmake --build "$work/cellguard" -j "$jobs" >"$work/cellguard-build.log" 2>&1 ||
  { cat "$work/cellguard-build.log"; die "building cellguard"; }
cmake --install "$work/cellguard" --prefix "$work/prefix" >"$work/cellguard-install.log" ||
  die "cmake --install"
[ -f "$work/prefix/lib/cmake/cellguard/cellguardConfig.cmake" ] || die "no cellguardConfig.cmake installed"
if grep -rl -e "$root" -e "$work/cellguard" "$work/prefix/lib/cmake/cellguard"; then
  die "the installed package configuration names the source or build tree"
fi
grep -q "cellguard::port_linux" "$work/prefix/lib/cmake/cellguard/cellguardTargets.cmake" ||
  die "the package has no cellguard::port_linux (the configure step says why: $(grep 'is not installed' "$work/cellguard-configure.log" || true))"
cmake -S tests/consumer -B "$work/consumer-package" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
  -DCELLGUARD_CONSUMER_MODE=package -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/consumer-package.log" 2>&1 ||
  { cat "$work/consumer-package.log"; die "configuring the consumer against the installed package"; }
cmake --build "$work/consumer-package" -j "$jobs" >>"$work/consumer-package.log" 2>&1 ||
  { cat "$work/consumer-package.log"; die "building the consumer against the installed package"; }
"$work/consumer-package/cellguard_consumer" || die "the consumer built against the installed package failed"

say "(b) subdirectory: the consumer adds $root with add_subdirectory"
cmake -S tests/consumer -B "$work/consumer-subdir" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
  -DCELLGUARD_CONSUMER_MODE=subdirectory -DCELLGUARD_SOURCE_DIR="$root" >"$work/consumer-subdir.log" 2>&1 ||
  { cat "$work/consumer-subdir.log"; die "configuring the consumer with add_subdirectory"; }
cache=$work/consumer-subdir/CMakeCache.txt
for option in CELLGUARD_BUILD_TESTS CELLGUARD_BUILD_APPS CELLGUARD_BUILD_BENCH CELLGUARD_WERROR; do
  grep -qx "$option:BOOL=OFF" "$cache" || die "$option is not OFF when cellguard is not the top-level project"
done
grep -qx "CMAKE_BUILD_TYPE:STRING=Debug" "$cache" || die "cellguard changed the consumer's build type"
targets=$(cmake --build "$work/consumer-subdir" --target help)
if printf '%s\n' "$targets" | grep -E '(cellguard_unit_tests|cellguard-|bench_|fuzz_|cellguard_sim|cellguard_host|firmware)'; then
  die "cellguard test, program or benchmark targets exist in the consumer's build (above)"
fi
cmake --build "$work/consumer-subdir" -j "$jobs" >>"$work/consumer-subdir.log" 2>&1 ||
  { cat "$work/consumer-subdir.log"; die "building the consumer with add_subdirectory"; }
"$work/consumer-subdir/cellguard_consumer" || die "the consumer built with add_subdirectory failed"
say "PASS (both ways)"
