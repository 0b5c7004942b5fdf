#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Cross-compilation CI steps (toolchains/*.cmake):
#  1. x86-64 (the industrial PC): builds cellguard-firmware-digest, runs it;
#  2. aarch64 (the SoC): builds the doctest unit tests of lib/ and the port (the preset's
#     CELLGUARD_UNIT_TEST_SUBJECTS=lib, tests/CMakeLists.txt) and the firmware digest program,
#     runs those test cases but the group "long replay" (tests/support/test_tags.hpp) under
#     qemu-aarch64 in parallel shards (tools/run-unit-tests.sh, one
#     process per shard: under qemu-user a process per case cost more than the cases), then the
#     digest. The programs' unit tests and their own CMake tests (command lines, files, sockets)
#     run natively in the README's build; they do not depend on the architecture;
#  3. Cortex-M7: builds the firmware (the build itself fails on heap or
#     exception runtime in the image, or a prior outside flash), runs it on
#     qemu-system-arm -M mps2-an500 with a timeout (its ctest), copies the size report to
#     certification/size-report.md;
#  4. compares the three digests of each run with apps/firmware/expected_digest.txt (the
#     zones-only run), expected_robot_digest.txt (the robot-cell run) and
#     expected_footprint_digest.txt (the zones-only run fused by footprint fusion).
# Needs: tools/install-deps.sh --cross.
# Usage: tools/cross.sh [--no-aarch64-tests]
#   --no-aarch64-tests: build only the firmware digest program for aarch64 and
#                       run it under qemu-user, not the unit tests (a quick local check;
#                       CI runs the unit tests).
# Environment: CELLGUARD_JOBS (default 2; the unit tests run in 3 x that many shards, that many at a time),
# CELLGUARD_CROSS_TEST_ARGS (extra doctest arguments for the aarch64 unit tests, e.g.
# "--test-case-exclude=*controller*"), CELLGUARD_CROSS_BUILD_DIR (where build-x86,
# build-aarch64, build-m7 go; default: the repository).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=${CELLGUARD_JOBS:-2}
bdir=${CELLGUARD_CROSS_BUILD_DIR:-$root}
run_ctest=1
for arg in "$@"; do
  case "$arg" in
    --no-aarch64-tests) run_ctest=0 ;;
    *) echo "usage: $0 [--no-aarch64-tests]" >&2; exit 2 ;;
  esac
done
for tool in aarch64-linux-gnu-g++ qemu-aarch64 arm-none-eabi-g++ qemu-system-arm; do
  command -v "$tool" >/dev/null || { echo "cross: $tool missing: run tools/install-deps.sh --cross" >&2; exit 1; }
done
expected=$(grep -m1 -E '^0x[0-9a-f]+$' "$root/apps/firmware/expected_digest.txt")
expected_robot=$(grep -m1 -E '^0x[0-9a-f]+$' "$root/apps/firmware/expected_robot_digest.txt")
expected_footprint=$(grep -m1 -E '^0x[0-9a-f]+$' "$root/apps/firmware/expected_footprint_digest.txt")
t0=$(date +%s)
stamp() { echo "cross: [$(( $(date +%s) - t0 )) s] $*"; }
digest_of() { sed -n 's/^digest \(0x[0-9a-f]*\)$/\1/p' "$1" | tail -1; }
robot_digest_of() { sed -n 's/^robot digest \(0x[0-9a-f]*\)$/\1/p' "$1" | tail -1; }  # the robot-cell run
footprint_digest_of() { sed -n 's/^footprint digest \(0x[0-9a-f]*\)$/\1/p' "$1" | tail -1; }  # footprint fusion

configure() {  # <dir> <preset> [cmake arguments]; the presets (CMakePresets.json) name the toolchains/ files
  mkdir -p "$1"
  cmake -S "$root" --preset "$2" -B "$1" "${@:3}" >"$1/cross-configure.log" 2>&1 ||
    { cat "$1/cross-configure.log"; exit 1; }
}

stamp "x86-64: building cellguard-firmware-digest"
mkdir -p "$bdir"
configure "$bdir/build-x86" x86_64-linux
cmake --build "$bdir/build-x86" -j "$jobs" --target cellguard-firmware-digest >/dev/null
"$bdir/build-x86/apps/firmware/cellguard-firmware-digest" >"$bdir/build-x86/firmware-digest.log"
d_x86=$(digest_of "$bdir/build-x86/firmware-digest.log")
r_x86=$(robot_digest_of "$bdir/build-x86/firmware-digest.log")
f_x86=$(footprint_digest_of "$bdir/build-x86/firmware-digest.log")

stamp "aarch64: building"
# No benchmarks (the preset): under qemu-user they would time the emulator, not the SoC.
configure "$bdir/build-aarch64" aarch64-linux
a64_targets=(--target cellguard-firmware-digest)  # the digest program: lib/ and the firmware's scenario
[ "$run_ctest" -eq 0 ] || a64_targets+=(cellguard_unit_tests)
cmake --build "$bdir/build-aarch64" -j "$jobs" "${a64_targets[@]}" >"$bdir/build-aarch64/cross-build.log" 2>&1 ||
  { tail -n 60 "$bdir/build-aarch64/cross-build.log"; echo "cross: the aarch64 build failed" >&2; exit 1; }
if [ "$run_ctest" -eq 1 ]; then
  stamp "aarch64: the unit tests under qemu-aarch64, $(( 3 * jobs )) shards, $jobs at a time"
  c0=$(date +%s)
  # Left out under qemu-user: the test cases of the group "long replay" (CELLGUARD_LONG_REPLAY,
  # tests/support/test_tags.hpp), each marked at the case: a scene replayed over tens to hundreds
  # of cycles, or a whole demo, to show that a decision holds; shorter cases run their per-cycle
  # code here, the three firmware digests compare the scenarios bit for bit, and every step but
  # this one runs the group natively. Natively the group is about 65 of the unit tests' 120
  # seconds of CPU (2026-12-06); under qemu-aarch64 a case takes about ten times as long.
  a64_emulator="qemu-aarch64 -L /usr/aarch64-linux-gnu -E LD_LIBRARY_PATH=/usr/aarch64-linux-gnu/lib"
  a64_unit="$bdir/build-aarch64/tests/cellguard_unit_tests"
  a64_count() { $a64_emulator "$a64_unit" --count --no-version "$@" 2>/dev/null | grep -o '[0-9][0-9]*' | tail -n 1; }
  a64_all=$(a64_count)
  a64_filter="--test-suite-exclude=long replay"
  a64_left=$(( a64_all - $(a64_count "$a64_filter") ))
  # The group must exist (a renamed suite would leave every case in, unnoticed) and stay a minority.
  [ "$a64_left" -ge 1 ] || { echo "cross: the test suite 'long replay' selects no case" >&2; exit 1; }
  [ $(( 10 * a64_left )) -le "$a64_all" ] ||
    { echo "cross: 'long replay' holds $a64_left of $a64_all cases (at most a tenth)" >&2; exit 1; }
  stamp "aarch64: $a64_left of $a64_all cases left out under qemu (the group 'long replay'; they run natively)"
  # shellcheck disable=SC2086
  # Three shards per core, one per core at a time: in two shards the long cases fell together
  # (269 s against 374 s, one core idle for 105 s, 2026-12-06).
  CELLGUARD_UNIT_EMULATOR="$a64_emulator" CELLGUARD_UNIT_JOBS="$jobs" \
    "$root/tools/run-unit-tests.sh" "$a64_unit" "$(( 3 * jobs ))" "$a64_filter" ${CELLGUARD_CROSS_TEST_ARGS:-}
  stamp "aarch64: the unit tests took $(( $(date +%s) - c0 )) s"
fi
qemu-aarch64 -L /usr/aarch64-linux-gnu "$bdir/build-aarch64/apps/firmware/cellguard-firmware-digest" \
  >"$bdir/build-aarch64/firmware-digest.log"
d_a64=$(digest_of "$bdir/build-aarch64/firmware-digest.log")
r_a64=$(robot_digest_of "$bdir/build-aarch64/firmware-digest.log")
f_a64=$(footprint_digest_of "$bdir/build-aarch64/firmware-digest.log")

stamp "cortex-m7: building the firmware (ELF checks and size report run as part of the build)"
# No compiler launcher for the firmware whose size is reported: with CCACHE_BASEDIR, ccache hands
# the compiler relative paths, whose __FILE__ strings -fmacro-prefix-map does not shorten; the
# report's read-only data then depended on the machine's cache settings (+80 B, 2026-11-26).
configure "$bdir/build-m7" cortex-m7 -DCMAKE_C_COMPILER_LAUNCHER= -DCMAKE_CXX_COMPILER_LAUNCHER=
cmake --build "$bdir/build-m7" -j "$jobs" >/dev/null
cp "$bdir/build-m7/size-report.md" "$root/certification/size-report.md"
stamp "cortex-m7: ELF checks, then the firmware on qemu-system-arm -M mps2-an500 (timeout 60 s)"
# The ELF checks and the three qemu runs (each single-threaded) one per core.
ctest --test-dir "$bdir/build-m7/apps/firmware" -j "$jobs" --output-on-failure >"$bdir/build-m7/ctest.log" 2>&1 ||
  { cat "$bdir/build-m7/ctest.log"; echo "cross: firmware checks or run failed" >&2; exit 1; }
d_m7=$(digest_of "$bdir/build-m7/firmware-qemu.log")
r_m7=$(robot_digest_of "$bdir/build-m7/firmware-qemu.log")
f_m7=$(footprint_digest_of "$bdir/build-m7/firmware-qemu.log")

echo "cross: digests  expected $expected  x86-64 ${d_x86:-none}  aarch64 ${d_a64:-none}  cortex-m7 ${d_m7:-none}"
echo "cross: robot-cell digests  expected $expected_robot  x86-64 ${r_x86:-none}  aarch64 ${r_a64:-none}  cortex-m7 ${r_m7:-none}"
echo "cross: footprint digests  expected $expected_footprint  x86-64 ${f_x86:-none}  aarch64 ${f_a64:-none}  cortex-m7 ${f_m7:-none}"
grep -v '^can ' "$bdir/build-m7/firmware-qemu.log"
stamp "done"
if [ "$d_x86" != "$expected" ] || [ "$d_a64" != "$expected" ] || [ "$d_m7" != "$expected" ] ||
  [ "$r_x86" != "$expected_robot" ] || [ "$r_a64" != "$expected_robot" ] || [ "$r_m7" != "$expected_robot" ] ||
  [ "$f_x86" != "$expected_footprint" ] || [ "$f_a64" != "$expected_footprint" ] || [ "$f_m7" != "$expected_footprint" ]; then
  echo "cross: DIGESTS DIFFER" >&2
  exit 1
fi
echo "cross: the three runs' digests are bit-identical on all three targets"
