#!/usr/bin/env bash
# Installs what a fresh Debian 12 machine lacks to build and test cellguard.
# Needs root (or sudo). Safe to run again.
set -euo pipefail
pkgs=(build-essential cmake ninja-build clang clang-tidy cppcheck libclang-rt-14-dev
      libeigen3-dev doctest-dev libtomlplusplus-dev liboctomap-dev valgrind gcovr python3)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
