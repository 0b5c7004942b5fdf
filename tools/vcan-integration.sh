#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Integration test on a real kernel CAN stack (issue 6): cellguard-monitor
# sends its safety output on vcan0, candump -L records it, the PLC-side
# receiver checks the recording; then vcan0 goes down mid-run and the fault
# path and the recovery are checked; then (issue 17) both directions in a
# robot cell: cellguard-vcan-plc sends the PLC's command on vcan0 with the
# PLC-side sender and checks the monitor's frames live with the PLC-side
# receiver (tests/integration/vcan/vcan-test.sh, vcan_plc.cpp).
#
# usage: tools/vcan-integration.sh [--vm] [BUILD_DIR]
#   BUILD_DIR  CMake build directory (Ninja) to build the programs in;
#              default build-vcan (configured here if it does not exist)
#   --vm       use the VM even when the host has vcan
#
# Where the host has vcan (`ip link add dev vcan0 type vcan` works: root and
# the vcan module) the test runs here. Otherwise it boots Debian's kernel
# (linux-image-amd64) under qemu-system-x86_64 with software emulation
# (-accel tcg; KVM hung on this kind of machine) and an initramfs assembled
# under BUILD_DIR/vcan: busybox-static, the modules can, can-raw, can-dev and
# vcan, the programs and candump with the shared libraries ldd lists (the
# monitor links tomlplusplus dynamically; they are copied, not linked
# statically) and the dynamic loader. CELLGUARD_VCAN_APPEND is added to the
# kernel command line (e.g. RUNS=robot: the kernel hands it to /init's
# environment, vcan-test.sh runs only that run). No network; the VM (or the test on the
# host) has a hard timeout (CELLGUARD_VCAN_TIMEOUT seconds, default 180).
# Measured in the VM on a loaded 2-core machine (runs 1 and 2 only): /init
# after 5-9 s, the test done 52-59 s after boot, qemu 58-73 s. The robot run
# (3) adds its start-up and 20 cycles of 2 s; the default timeout is 420 s.
# Packages: tools/install-deps.sh --vcan. Exit status 0 exactly when every
# check passed.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
force_vm=0
build=""
for arg in "$@"; do
  case "$arg" in
    --vm) force_vm=1 ;;
    -*) echo "usage: $0 [--vm] [BUILD_DIR]" >&2; exit 2 ;;
    *) build=$arg ;;
  esac
done
build=${build:-build-vcan}
case "$build" in /*) ;; *) build=$root/$build ;; esac
vm_timeout=${CELLGUARD_VCAN_TIMEOUT:-420}
here=$root/tests/integration/vcan
work=$build/vcan
t_start=$(date +%s)
say() { echo "vcan-integration: $*"; }
die() { say "FAIL: $*"; exit 1; }

# --- build ------------------------------------------------------------------
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake --preset release -B "$build" -DCELLGUARD_BUILD_TESTS=OFF -DCELLGUARD_BUILD_BENCH=OFF > /dev/null
fi
[ -f "$build/build.ninja" ] || die "$build is not a Ninja build directory"
cmake --build "$build" -j 2 --target cellguard-monitor cellguard-monitor-check-log
mkdir -p "$work/bin"
# cellguard-vcan-check and cellguard-vcan-plc: compiled with the flags CMake
# uses for cellguard-monitor-check-log (same defines, so the same ABI) and
# linked against the same libraries.
for prog in check_vcan_log:cellguard-vcan-check vcan_plc:cellguard-vcan-plc; do
python3 - "$build" "$here/${prog%%:*}.cpp" "$work/bin/${prog#*:}" <<'EOF'
import json, os, shlex, subprocess, sys
build, src, out = sys.argv[1:4]
entries = [e for e in json.load(open(os.path.join(build, "compile_commands.json")))
           if e["file"].replace("\\", "/").endswith("apps/monitor/src/check_demo_log.cpp")]
if not entries:
    sys.exit("vcan-integration: no compile command for check_demo_log.cpp in " + build)
cc = shlex.split(entries[0]["command"]) if "command" in entries[0] else entries[0]["arguments"]
flags, skip = [], False
for a in cc[1:]:
    if skip:
        skip = False
    elif a in ("-o", "-c"):
        skip = True
    elif a != entries[0]["file"]:
        flags.append(a)
link = subprocess.check_output(["ninja", "-C", build, "-t", "commands", "cellguard-monitor-check-log"],
                               text=True).strip().splitlines()[-1]
# The link command without the compiler, the object file and -o OUTPUT:
# libraries and link flags (sanitizers, coverage) as CMake gave them.
libs, skip = [], False
for a in shlex.split(link.replace(": &&", "").replace("&& :", ""))[1:]:
    if skip:
        skip = False
    elif a == "-o":
        skip = True
    elif not a.endswith(".o"):
        libs.append(a)
deps = [src] + [os.path.join(build, l) for l in libs if l.endswith(".a")]
if os.path.exists(out) and all(os.path.getmtime(out) >= os.path.getmtime(d) for d in deps):
    sys.exit(0)
cmd = [cc[0]] + flags + [src, "-o", out] + libs
print("vcan-integration: building " + os.path.basename(out), flush=True)
sys.exit(subprocess.call(cmd, cwd=build))
EOF
done
candump=$(command -v candump || true)
[ -n "$candump" ] || die "candump not found (can-utils; tools/install-deps.sh --vcan)"
cp "$build/apps/monitor/cellguard-monitor" "$candump" "$work/bin/"
cp "$here/vcan-cell.toml" "$here/vcan-robot-cell.toml" "$here/vcan-robot-scene.toml" "$here/vcan-test.sh" \
   "$root/apps/monitor/config/robot-arm.urdf" "$work/"

# --- on the host, where it has vcan -------------------------------------------
if [ $force_vm -eq 0 ] && ip link add dev vcan0 type vcan 2> /dev/null; then
  trap 'ip link del dev vcan0 2> /dev/null || true' EXIT
  ip link set vcan0 up
  say "the host has vcan: running on the host (kernel $(uname -r))"
  set +e
  timeout -k 10 "$vm_timeout" sh "$work/vcan-test.sh" "$work/bin" "$work/vcan-cell.toml" "$work/host" vcan0
  rc=$?
  [ $rc -ne 124 ] || say "FAIL: the test did not finish within $vm_timeout s"
  set -e
  say "$([ $rc -eq 0 ] && echo PASS || echo FAIL) on the host in $(( $(date +%s) - t_start )) s"
  exit $rc
fi

# --- in a VM -----------------------------------------------------------------
say "the host has no vcan (or --vm): booting a VM"
command -v qemu-system-x86_64 > /dev/null || die "qemu-system-x86_64 not found (tools/install-deps.sh --vcan)"
kernel="" kver=""
for k in $(ls -1 /boot/vmlinuz-*-amd64 2> /dev/null | sort -V -r); do
  v=${k#/boot/vmlinuz-}
  if [ -n "$(find "/lib/modules/$v/kernel/drivers/net/can" -name 'vcan.ko*' 2> /dev/null)" ]; then
    kernel=$k kver=$v
    break
  fi
done
[ -n "$kernel" ] || die "no Debian kernel with vcan in /boot (linux-image-amd64; tools/install-deps.sh --vcan)"
[ -r "$kernel" ] || die "$kernel is not readable (Debian installs it mode 0600: run as root)"
busybox=""
for b in /bin/busybox /usr/bin/busybox; do
  if [ -x "$b" ] && ! ldd "$b" > /dev/null 2>&1; then busybox=$b; break; fi
done
[ -n "$busybox" ] || die "no statically linked busybox (busybox-static; tools/install-deps.sh --vcan)"

# The initramfs.
fs=$work/initramfs
rm -rf "$fs"
mkdir -p "$fs"/{bin,proc,sys,dev,tmp,cellguard/bin,lib/modules/cellguard}
cp "$busybox" "$fs/bin/busybox"
ln -s busybox "$fs/bin/sh"
install -m 0755 "$here/init" "$fs/init"
# The unprivileged run (vcan-test.sh, run 4) starts the monitor as nobody with su.
mkdir -p "$fs/etc"
printf 'root:x:0:0:root:/:/bin/sh\nnobody:x:65534:65534:nobody:/nonexistent:/bin/sh\n' > "$fs/etc/passwd"
printf 'root:x:0:\nnogroup:x:65534:\n' > "$fs/etc/group"
cp "$work/vcan-cell.toml" "$work/vcan-robot-cell.toml" "$work/vcan-robot-scene.toml" "$work/robot-arm.urdf" \
   "$work/vcan-test.sh" "$fs/cellguard/"
cp "$work/bin/"* "$fs/cellguard/bin/"
command -v strip > /dev/null && strip "$fs"/cellguard/bin/* 2> /dev/null || true  # smaller without debug info
for m in can can-raw can-dev vcan; do          # insmod order: can, can-raw, can-dev, vcan
  f=$(find "/lib/modules/$kver/kernel/net/can" "/lib/modules/$kver/kernel/drivers/net/can" \
        -name "$m.ko*" | head -n 1)
  [ -n "$f" ] || die "module $m missing in /lib/modules/$kver"
  case "$f" in
    *.ko) cp "$f" "$fs/lib/modules/cellguard/$m.ko" ;;
    *.ko.xz) xz -dc "$f" > "$fs/lib/modules/cellguard/$m.ko" ;;
    *.ko.zst) zstd -qdc "$f" > "$fs/lib/modules/cellguard/$m.ko" ;;
    *.ko.gz) gzip -dc "$f" > "$fs/lib/modules/cellguard/$m.ko" ;;
    *) die "cannot unpack $f" ;;
  esac
done
# softdog and the watchdog core it needs, if the kernel has them as modules:
# the opt-in watchdog run (CELLGUARD_VCAN_APPEND=RUNS=watchdog).
for m in watchdog softdog; do
  f=$(find "/lib/modules/$kver/kernel/drivers/watchdog" -name "$m.ko*" 2> /dev/null | head -n 1)
  case "$f" in
    *.ko) cp "$f" "$fs/lib/modules/cellguard/$m.ko" ;;
    *.ko.xz) xz -dc "$f" > "$fs/lib/modules/cellguard/$m.ko" ;;
    *.ko.zst) zstd -qdc "$f" > "$fs/lib/modules/cellguard/$m.ko" ;;
    *.ko.gz) gzip -dc "$f" > "$fs/lib/modules/cellguard/$m.ko" ;;
    *) ;;
  esac
done
# Shared libraries and the loader, at the paths the programs ask for.
for lib in $(for p in "$fs"/cellguard/bin/*; do ldd "$p"; done |
             awk '$2 == "=>" && $3 ~ /^\// { print $3 } $1 ~ /^\// && NF == 2 { print $1 }' | sort -u); do
  mkdir -p "$fs$(dirname "$lib")"
  cp -L "$lib" "$fs$lib"
done
if command -v cpio > /dev/null; then cpio_cmd=(cpio -o -H newc --quiet); else cpio_cmd=("$busybox" cpio -o -H newc); fi
(cd "$fs" && find . | LC_ALL=C sort | "${cpio_cmd[@]}") | gzip -1 > "$work/initramfs.cpio.gz"
say "initramfs $(du -k "$work/initramfs.cpio.gz" | cut -f1) KiB; kernel $kernel"

# Boot. TCG only; no network; console on the serial port; the VM powers off
# at the end, a kernel panic reboots and -no-reboot ends qemu; timeout ends
# it in any case.
console=$work/console.log
t_vm=$(date +%s)
set +e
timeout -k 10 "$vm_timeout" qemu-system-x86_64 -accel tcg -cpu max -smp 2 -m 512 \
  -nographic -no-reboot -nic none \
  -kernel "$kernel" -initrd "$work/initramfs.cpio.gz" \
  -append "console=ttyS0 panic=-1 quiet loglevel=3 rdinit=/init ${CELLGUARD_VCAN_APPEND:-}" \
  < /dev/null > "$console" 2>&1
qemu_rc=$?
set -e
vm_s=$(( $(date +%s) - t_vm ))
tr -d '\r' < "$console" | sed -n '/vcan-init:/,$p' | sed -e 's/\x1b\[[0-9;?]*[A-Za-z]//g' -e 's/\x1bc//g'
if [ $qemu_rc -eq 124 ] || [ $qemu_rc -eq 137 ]; then
  say "FAIL: the VM did not finish within $vm_timeout s (console: $console)"
  exit 1
fi
# The watchdog run passes when softdog restarted the machine: the console
# ends after the monitor was stopped, without NO RESET or the run's end.
if tr -d '\r' < "$console" | grep -q '^CELLGUARD-WATCHDOG: stopped'; then
  if ! tr -d '\r' < "$console" | grep -q -e '^CELLGUARD-WATCHDOG: NO RESET' -e '^vcan-init: done'; then
    say "PASS in the VM: softdog restarted the machine after the monitor stopped (qemu $vm_s s)"
    exit 0
  fi
  say "FAIL in the VM: no reset after the monitor stopped (console: $console)"
  exit 1
fi
if tr -d '\r' < "$console" | grep -q '^CELLGUARD-VCAN-RESULT: PASS$' &&
   ! tr -d '\r' < "$console" | grep -q '^CELLGUARD-VCAN-RESULT: FAIL'; then
  say "PASS in the VM (qemu $vm_s s, total $(( $(date +%s) - t_start )) s)"
  exit 0
fi
say "FAIL in the VM (qemu exit $qemu_rc after $vm_s s; console: $console)"
exit 1
