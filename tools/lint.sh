#!/usr/bin/env bash
# Static analysis of lib/ and port/: cppcheck and clang-tidy, findings are errors.
# Usage: tools/lint.sh [build-dir]   (the build dir must have compile_commands.json)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[ -f "$build/compile_commands.json" ] || { echo "lint: no $build/compile_commands.json; configure first" >&2; exit 2; }
mapfile -t sources < <(find lib/src port -name '*.cpp' | sort)

echo "== cppcheck $(cppcheck --version)"
cppcheck --std=c++17 --language=c++ --enable=warning,style,performance,portability \
  --inline-suppr --error-exitcode=1 --quiet \
  --suppressions-list=tools/cppcheck-suppressions.txt \
  -I lib/include -I port/linux/include -D__GNUC__ -DEIGEN_NO_MALLOC \
  "${sources[@]}"

echo "== clang-tidy $(clang-tidy --version | head -n 2 | tail -n 1)"
# One clang-tidy per file, as many at once as there are cores; any finding fails.
log=$(mktemp)
status=0
printf '%s\n' "${sources[@]}" | xargs -P "$(nproc)" -n 1 sh -c 'out=$(clang-tidy -p "$0" --quiet "$1" 2>&1) || { printf "%s\n" "$out"; echo "clang-tidy: findings in $1"; exit 1; }' "$build" >"$log" 2>&1 || status=1
grep -v -E '^[0-9]+ warnings? generated|^Suppressed|^Use -header-filter' "$log" || true
rm -f "$log"
[ "$status" -eq 0 ] || { echo "lint: clang-tidy findings (see above)"; exit 1; }
echo "lint: no findings"
