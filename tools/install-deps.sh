#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Installs what a fresh Debian 12 machine lacks to build and test cellguard.
# Needs root (or sudo). Safe to run again.
# --cross also installs the cross toolchains and emulators of tools/cross.sh:
# aarch64 g++ with qemu-user, arm-none-eabi gcc with newlib's libstdc++ and
# qemu-system-arm (about 1 GB; not part of the default install), and the
# aarch64 libpng the host programs link (Debian multiarch: adds the arm64
# architecture to dpkg).
# --vcan also installs what tools/vcan-integration.sh needs: qemu-system-x86,
# Debian's kernel with its CAN modules, busybox-static, can-utils (candump).
# --lint also installs what tools/lint.sh needs beyond the default set:
# reuse (the licence check of every file) and clang-format (the style check).
# --demo installs only what tools/demo.sh needs to build and run the programs
# (the demo preset: no tests, benchmarks, browser or camera libraries), instead
# of the default set: the compiler, CMake and Ninja, Eigen, toml++, CLI11,
# libpng, liburdfdom and assimp (the robot demo commissions its arm from a URDF;
# assimp reads collision meshes: STL, COLLADA, OBJ).
set -euo pipefail
demo_pkgs=(build-essential cmake ninja-build pkg-config libeigen3-dev libtomlplusplus-dev libcli11-dev
           libpng-dev liburdfdom-dev libassimp-dev)
# gnuplot-nox: cellguard-eval draws the precision-recall plots with it (pngcairo).
# libcli11-dev: the host programs' command lines; libpng-dev: their PNG writer.
# python3-canmatrix: the third-party DBC decoder of tools/dbc_decode_check.py (ctest dbc_decoded_by_canmatrix).
# libaravis-dev (+ libusb-1.0-0-dev, which its pkg-config file needs): the GigE Vision camera input;
# aravis-tools: arv-fake-gv-camera-0.8, the fake camera of the gige tests; aravis-tools-cli: arv-tool, Aravis's own client, which checks the fake cameras of the tests;
# libsystemd-dev: the monitor's service notification (Type=notify, watchdog).
# iproute2: the loopback namespace of tools/netns-run.sh (fake cameras on 127.0.0.2-8).
# systemd: systemd-analyze verify of the monitor's unit; python3-numpy: the snapshot's .npy read back.
# libcivetweb-dev: the monitor's browser view (--http); libjs-three: the three.js r111 it serves;
# chromium, python3-websocket: the headless-browser test of that view (DevTools protocol).
pkgs=(build-essential cmake ninja-build clang clang-tidy cppcheck libclang-rt-14-dev
      libeigen3-dev doctest-dev libtomlplusplus-dev liboctomap-dev valgrind gcovr python3
      gnuplot-nox libcli11-dev libpng-dev liburdfdom-dev libassimp-dev python3-canmatrix
      libaravis-dev libusb-1.0-0-dev aravis-tools aravis-tools-cli libsystemd-dev pkg-config iproute2
      systemd python3-numpy libcivetweb-dev libjs-three chromium python3-websocket)
arm64=0
demo=0
extra=()
for arg in "$@"; do
  case "$arg" in
    --demo) demo=1 ;;
    --cross) extra+=(g++-aarch64-linux-gnu qemu-user gcc-arm-none-eabi binutils-arm-none-eabi
                    libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib qemu-system-arm libpng-dev:arm64)
             arm64=1 ;;
    --vcan) extra+=(qemu-system-x86 linux-image-amd64 busybox-static can-utils cpio iproute2) ;;
    --lint) extra+=(reuse clang-format) ;;
    *) echo "usage: $0 [--demo] [--cross] [--vcan] [--lint]" >&2; exit 2 ;;
  esac
done
[ "$demo" -eq 0 ] || pkgs=("${demo_pkgs[@]}")
pkgs+=("${extra[@]}")
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
# Wait for another apt/dpkg run (unattended upgrades, a parallel job) instead of failing.
lock=(-o DPkg::Lock::Timeout=600)
if [ "$arm64" -eq 1 ] && ! dpkg --print-foreign-architectures | grep -qx arm64; then
  $SUDO dpkg --add-architecture arm64
fi
$SUDO apt-get "${lock[@]}" update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get "${lock[@]}" install -y -qq --no-install-recommends "${missing[@]}"
