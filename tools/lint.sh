#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Static analysis of lib/, port/ and apps/: cppcheck and clang-tidy, findings are errors.
# apps/.clang-tidy adapts the checks to host code (heap, exceptions, iostreams allowed).
# Usage: tools/lint.sh [build-dir]   (the build dir must have compile_commands.json)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}

# ../shared (the development machine's notes, papers and data, beside the
# checkout) is not in a clone: a tracked file that reads it works here and
# fails on a fresh machine. Markdown may mention it; nothing else may use it
# (this file names it only to look for it).
echo "== no references to ../shared or /shared/data outside Markdown"
if git rev-parse --git-dir >/dev/null 2>&1; then
  if git grep -nE '\.\./shared|/shared/data' -- ':!*.md' ':!tools/lint.sh'; then
    echo "lint: the tracked files above refer to ../shared or /shared/data, which a clone does not have;" \
         "commit what they need into the repository (e.g. tests/data) and refer to it there" >&2
    exit 1
  fi
else
  echo "lint: not a git checkout, the ../shared check is skipped"
fi

# Style: every hand-written C++ file as .clang-format has it (the generated
# test header is compared byte for byte with its generator's output instead).
# Licences: every file states its licence (SPDX header or .reuse/dep5).
# Both need the file list of a git checkout (tools/install-deps.sh --lint).
if git rev-parse --git-dir >/dev/null 2>&1; then
  echo "== $(clang-format --version | head -n 1): format check"
  mapfile -t fmt_files < <(git ls-files 'lib/*.cpp' 'lib/*.hpp' 'port/*.cpp' 'port/*.hpp' 'apps/*.cpp' 'apps/*.hpp' \
                                        'tests/*.cpp' 'tests/*.hpp' |
                           grep -v -e '^tests/unit/data/prior_example.hpp$' -e '^apps/firmware/generated/')
  clang-format --dry-run --Werror "${fmt_files[@]}" ||
    { echo "lint: the files above differ from .clang-format: run clang-format -i on them" >&2; exit 1; }
  echo "== reuse lint ($(reuse --version | head -n 1))"
  reuse lint --quiet || { reuse lint | tail -n 20; echo "lint: a file without licence information (reuse lint)" >&2; exit 1; }
fi

[ -f "$build/compile_commands.json" ] || { echo "lint: no $build/compile_commands.json; configure first" >&2; exit 2; }
mapfile -t sources < <(find lib port -name '*.cpp' | sort)
# apps/: the host programs and the host floor, as compiled on the host (in the
# compile database: not the firmware's bare-metal main, not generated data).
mapfile -t app_sources < <(find apps -name '*.cpp' -not -path 'apps/firmware/generated/*' | sort |
                           while read -r f; do grep -q "\"file\": \"$PWD/$f\"" "$build/compile_commands.json" && echo "$f"; done)
app_includes=()
for d in apps/*/include; do app_includes+=(-I "$d"); done
# Every lib/ module's include root (lib/<module>/include, lib/<module>/<part>/include).
lib_includes=()
for d in lib/*/include lib/*/*/include; do lib_includes+=(-I "$d"); done

echo "== cppcheck $(cppcheck --version)"
# lib/ and port/ beside apps/: two single-threaded runs, one per core.
cppcheck --std=c++17 --language=c++ --enable=warning,style,performance,portability \
  --inline-suppr --error-exitcode=1 --quiet \
  --suppressions-list=tools/cppcheck-suppressions.txt \
  "${lib_includes[@]}" -I port/linux/include -D__GNUC__ -DEIGEN_NO_MALLOC \
  "${sources[@]}" &
cppcheck_lib=$!
cppcheck --std=c++17 --language=c++ --enable=warning,style,performance,portability \
  --inline-suppr --error-exitcode=1 --quiet \
  --suppressions-list=tools/cppcheck-suppressions.txt \
  "${lib_includes[@]}" -I port/linux/include "${app_includes[@]}" -I "$build/apps/host/include" -D__GNUC__ \
  "${app_sources[@]}"
wait "$cppcheck_lib"

echo "== clang-tidy $(clang-tidy --version | head -n 2 | tail -n 1)"
# One clang-tidy per file, as many at once as there are cores; any finding fails. The largest
# files go first (a big program file takes 15-31 s), so the run does not end on one core.
# lib/ and port/linux: with the host build's compile database.
mapfile -t host_sources < <(printf '%s\n' "${sources[@]}" "${app_sources[@]}" | grep -v '^port/baremetal/' |
                            while read -r f; do echo "$(wc -c <"$f") $f"; done | sort -k1,1nr -k2 | cut -d' ' -f2-)
log=$(mktemp)
status=0
printf '%s\n' "${host_sources[@]}" | xargs -P "$(nproc)" -n 1 sh -c 'out=$(clang-tidy -p "$0" --quiet "$1" 2>&1) || { printf "%s\n" "$out"; echo "clang-tidy: findings in $1"; exit 1; }' "$build" >"$log" 2>&1 || status=1

# port/baremetal is not in the host's compile database (it builds only for
# the Cortex-M7): clang-tidy parses it as clang would compile it for that
# target, with arm-none-eabi-g++'s own header search paths (newlib, libstdc++).
mapfile -t bm_sources < <(printf '%s\n' "${sources[@]}" | grep '^port/baremetal/' || true)
if [ ${#bm_sources[@]} -gt 0 ]; then
  bm_cpu=(-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb)
  if command -v arm-none-eabi-g++ >/dev/null; then
    mapfile -t bm_inc < <(arm-none-eabi-g++ "${bm_cpu[@]}" -std=c++17 -E -x c++ -v - </dev/null 2>&1 >/dev/null |
                          sed -n '/^#include <...> search starts here:/,/^End of search list./p' | sed '1d;$d' | sed 's/^ *//')
    bm_flags=(--target=arm-none-eabi "${bm_cpu[@]}" -std=c++17 -fno-exceptions -fno-rtti -DNDEBUG -DEIGEN_NO_MALLOC
              -DEIGEN_MAX_STATIC_ALIGN_BYTES=16 "${lib_includes[@]}" -Iport/baremetal/include -isystem /usr/include/eigen3)
    for d in "${bm_inc[@]}"; do bm_flags+=(-isystem "$d"); done
    for f in "${bm_sources[@]}"; do
      out=$(clang-tidy --quiet "$f" -- "${bm_flags[@]}" 2>&1) || { printf '%s\n' "$out" >>"$log"; echo "clang-tidy: findings in $f" >>"$log"; status=1; }
    done
    echo "== clang-tidy on port/baremetal: ${#bm_sources[@]} files for arm-none-eabi (cortex-m7)"
  elif [ "${CELLGUARD_LINT_REQUIRE_BAREMETAL:-0}" = 1 ]; then
    echo "lint: arm-none-eabi-g++ missing, port/baremetal cannot be analysed (tools/install-deps.sh --cross)" >&2
    exit 1
  else
    echo "== clang-tidy on port/baremetal: SKIPPED (no arm-none-eabi-g++; tools/install-deps.sh --cross)"
  fi
fi
grep -v -E '^[0-9]+ warnings? generated|^Suppressed|^Use -header-filter' "$log" || true
rm -f "$log"
[ "$status" -eq 0 ] || { echo "lint: clang-tidy findings (see above)"; exit 1; }
echo "lint: no findings"
