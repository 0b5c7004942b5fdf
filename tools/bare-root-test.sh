#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# README's two commands on a bare Debian 12 root: `tools/demo.sh` on the fresh
# root (it installs only what the demo needs), then `tools/test.sh`, run
# exactly as README.md writes them from the top of a clone of the commit under
# test, in a chroot of a `debootstrap --variant=minbase bookworm` root that has
# nothing else in it (no compiler, no git, no build directory, nothing from
# beside the checkout) and, as debootstrap writes it, only the main archive in
# its apt sources (no security or point-release updates: chromium 150 where an
# updated machine has 156).
#
# Why: README.md promises that these two commands work on a fresh Debian 12
# machine. A developer's machine or the CI host already has every package and
# file the project needs, so a missing package in tools/install-deps.sh, a
# file that is not committed, or a path outside the repository goes unnoticed
# there. This script shows them on every CI run (.ci/run).
#
# What it does:
#   1. Installs debootstrap on the host if missing (apt-get).
#   2. Reuses the base root cached as a tarball (default
#      /var/cache/cellguard-ci/bookworm-minbase.tar) or, if it is missing or
#      unreadable, builds it with debootstrap from the Debian mirror the
#      host's apt sources already use (/etc/apt/sources.list,
#      /etc/apt/sources.list.d/*.list and *.sources).
#   3. Unpacks it into a fresh temporary directory, points its apt at the
#      host's bookworm mirror, main archive only (--updated: all of the host's
#      bookworm sources), copies /etc/resolv.conf in, and clones the commit
#      under test (HEAD of the checkout this script lives in; not the
#      uncommitted changes) to <root>/root/cellguard with git on the host
#      (--clone-at DIR: to DIR on the host, bind-mounted at the same path in
#      the root, so that the build stays usable on the host afterwards: .ci/run
#      runs its later steps on it).
#   4. Mounts /proc, /dev (with /dev/pts and /dev/shm) and /sys into the root,
#      runs the two commands in a chroot, each under a time bound, and prints
#      how long each took.
#   5. On exit, failure or interruption: stops what still runs in the root,
#      unmounts (lazily if need be) and deletes the temporary root (never while
#      anything is still mounted in it).
# Exits non-zero if any step or either command fails or times out.
#
# Needs root (debootstrap, mount, chroot) and Debian's package mirror.
# Usage: tools/bare-root-test.sh [--rebuild] [--apt-cache] [--keep-root] [--updated] [--clone-at DIR]
#   --rebuild    build the base root with debootstrap even if the cached tarball
#                is fine (env CELLGUARD_BARE_ROOT_REBUILD=1)
#   --apt-cache  when developing: keep the .deb files tools/install-deps.sh
#                downloads in the cache directory and reuse them in later runs,
#                so they are not downloaded again (apt still installs them, and
#                still reads the mirror's package lists)
#                (env CELLGUARD_BARE_ROOT_APT_CACHE=1)
#   --keep-root  unmount but do not delete the root at the end, to look at it
#                (env CELLGUARD_BARE_ROOT_KEEP=1)
#   --updated    the host's bookworm sources (security and point-release
#                updates too) instead of the main archive alone
#   --clone-at DIR  clone to DIR on the host (absent or empty; an absolute
#                path outside the checkout) and bind-mount it at DIR inside the
#                root; DIR and its build/ stay when the root is deleted
# Environment: CELLGUARD_BARE_ROOT_CACHE (cache directory, default
# /var/cache/cellguard-ci), CELLGUARD_BARE_ROOT_TMPDIR (where the temporary
# root goes, default $TMPDIR or /var/tmp), CELLGUARD_BARE_ROOT_TEST_TIMEOUT
# and CELLGUARD_BARE_ROOT_DEMO_TIMEOUT (seconds, default 2400 and 600).
set -euo pipefail

rebuild=${CELLGUARD_BARE_ROOT_REBUILD:-0}
apt_cache=${CELLGUARD_BARE_ROOT_APT_CACHE:-0}
keep_root=${CELLGUARD_BARE_ROOT_KEEP:-0}
updated=0
clone_at=""
while [ "$#" -gt 0 ]; do
  arg=$1
  shift
  case "$arg" in
    --updated) updated=1 ;;
    --clone-at) [ "$#" -gt 0 ] || { echo "$0: --clone-at needs a directory" >&2; exit 2; }
                clone_at=$1; shift ;;
    --rebuild) rebuild=1 ;;
    --apt-cache) apt_cache=1 ;;
    --keep-root) keep_root=1 ;;
    -h|--help) sed -n '2,/^set -euo/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
    *) echo "usage: $0 [--rebuild] [--apt-cache] [--keep-root] [--updated] [--clone-at DIR]" >&2; exit 2 ;;
  esac
done

cache=${CELLGUARD_BARE_ROOT_CACHE:-/var/cache/cellguard-ci}
tarball=$cache/bookworm-minbase.tar
tmp_parent=${CELLGUARD_BARE_ROOT_TMPDIR:-${TMPDIR:-/var/tmp}}
test_timeout=${CELLGUARD_BARE_ROOT_TEST_TIMEOUT:-2400}
demo_timeout=${CELLGUARD_BARE_ROOT_DEMO_TIMEOUT:-600}
chroot_path=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin

say() { printf 'bare-root: %s\n' "$*"; }
die() { printf 'bare-root: %s\n' "$*" >&2; exit 1; }

[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, mount, chroot)"
repo=$(cd "$(dirname "$0")/.." && pwd -P)
commit=$(git -C "$repo" rev-parse --verify 'HEAD^{commit}')
say "commit under test: $(git -C "$repo" log -1 --format='%h %s' "$commit")"
if [ -n "$(git -C "$repo" status --porcelain --untracked-files=no)" ]; then
  say "note: $repo has uncommitted changes; they are not tested (only $commit is)"
fi

# --- The host's Debian sources: "uri suite components" per bookworm* suite. --
# Reads what apt itself reads: sources.list and sources.list.d/*.list in the
# one-line format, sources.list.d/*.sources in deb822 (Enabled: no skipped).
host_sources() {
  local f
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    awk '/^[ \t]*deb[ \t]/ {
           line = $0; sub(/#.*/, "", line); sub(/^[ \t]+/, "", line); gsub(/\[[^]]*\]/, "", line)
           n = split(line, F, /[ \t]+/); c = ""
           for (i = 4; i <= n; i++) c = c (c == "" ? "" : " ") F[i]
           print F[2], F[3], c }' "$f"
  done
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk 'function flush(  n, m, i, j, U, S) {
           if (types ~ /(^| )deb( |$)/ && enabled !~ /^(no|false|0)$/) {
             n = split(uris, U, /[ \t]+/); m = split(suites, S, /[ \t]+/)
             for (i = 1; i <= n; i++) for (j = 1; j <= m; j++) print U[i], S[j], comps
           }
           types = uris = suites = comps = enabled = last = ""
         }
         /^#/ { next }
         /^[ \t]*$/ { flush(); next }
         /^[ \t]/ { v = $0; sub(/^[ \t]+/, "", v)
                    if (last == "uris") uris = uris " " v; else if (last == "suites") suites = suites " " v
                    else if (last == "components") comps = comps " " v
                    next }
         { k = tolower(substr($0, 1, index($0, ":") - 1)); v = substr($0, index($0, ":") + 1)
           gsub(/^[ \t]+|[ \t]+$/, "", v); last = k
           if (k == "types") types = v; else if (k == "uris") uris = v; else if (k == "suites") suites = v
           else if (k == "components") comps = v; else if (k == "enabled") enabled = tolower(v) }
         END { flush() }' "$f"
  done
}
mapfile -t sources < <(host_sources | awk '$2 ~ /^bookworm(-|$)/ && !seen[$0]++')
mirror=$(printf '%s\n' "${sources[@]}" | awk '$2 == "bookworm" { print $1; exit }')
[ -n "$mirror" ] || die "no 'deb <uri> bookworm' entry in the host's apt sources (/etc/apt/sources.list, /etc/apt/sources.list.d/); debootstrap needs one"
case "$mirror" in
  http://*|https://*|file:/*) ;;
  *) die "the host's bookworm source $mirror is not http(s) or file: debootstrap cannot use it" ;;
esac

# --- Cleanup: runs on every exit, failure and interruption. -----------------
root=""
build_root=""
child=""
mounted_under() {  # mount points at or below $1, deepest first
  awk -v p="$1" '$5 == p || index($5, p "/") == 1 { print $5 }' /proc/self/mountinfo | sort -r
}
release() {  # stop what runs in $1, unmount everything below it, delete it unless $2 = keep
  local dir=$1 keep=${2:-} sig pid pids m left
  [ -n "$dir" ] && [ -d "$dir" ] || return 0
  # Processes left in the root (started by this script's chroot): by their ids.
  for sig in TERM KILL; do
    pids=()
    for pid in /proc/[0-9]*; do
      case "$(readlink "$pid/root" 2>/dev/null)" in "$dir"|"$dir"/*) pids+=("${pid#/proc/}") ;; esac
    done
    [ ${#pids[@]} -eq 0 ] && break
    say "stopping ${#pids[@]} process(es) still running in $dir (SIG$sig): ${pids[*]}"
    kill -s "$sig" "${pids[@]}" 2>/dev/null || true
    sleep 2
  done
  for m in $(mounted_under "$dir"); do
    umount "$m" 2>/dev/null || umount -R "$m" 2>/dev/null || umount -l "$m" 2>/dev/null ||
      say "could not unmount $m"
  done
  left=$(mounted_under "$dir")
  if [ -n "$left" ]; then
    say "still mounted below $dir, NOT deleting it:"$'\n'"$left"
    return 1
  fi
  if [ "$keep" = keep ]; then
    say "kept the root (unmounted): $dir"
  else
    rm -rf --one-file-system "$dir"
  fi
}
cleanup() {
  local status=$? ok=0
  trap - EXIT INT TERM HUP
  if [ -n "$child" ] && kill -0 "$child" 2>/dev/null; then
    kill -s TERM "$child" 2>/dev/null || true   # timeout passes it on to the command's process group
    wait "$child" 2>/dev/null || true
  fi
  release "$build_root" || ok=1
  release "$root" "$([ "$keep_root" = 1 ] && echo keep)" || ok=1
  [ "$status" -ne 0 ] || status=$ok
  exit "$status"
}
trap cleanup EXIT
trap 'say "interrupted"; exit 130' INT
trap 'say "terminated"; exit 143' TERM HUP

# --- debootstrap on the host. -------------------------------------------------
if ! command -v debootstrap >/dev/null; then
  say "installing debootstrap on the host"
  apt-get -o DPkg::Lock::Timeout=600 update -qq
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends debootstrap
fi

# --- The base root: cached tarball, or debootstrap. ---------------------------
mkdir -p "$cache"
exec 9>"$cache/lock"
flock -w 1800 9 || die "another run holds $cache/lock for 30 min"
tarball_ok() {
  local list
  [ -r "$tarball" ] || return 1
  list=$(tar -tf "$tarball" 2>/dev/null) || return 1
  grep -qx './usr/bin/apt-get' <<<"$list"
}
if [ "$rebuild" = 1 ] || ! tarball_ok; then
  if [ "$rebuild" = 1 ]; then say "rebuilding $tarball (--rebuild)"; else say "no usable $tarball: building it"; fi
  build_root=$(realpath "$(mktemp -d "$cache/debootstrap.XXXXXX")")
  say "debootstrap --variant=minbase bookworm $build_root/root $mirror"
  t0=$(date +%s)
  timeout 1800 debootstrap --variant=minbase bookworm "$build_root/root" "$mirror" >"$build_root/debootstrap.log" 2>&1 ||
    { tail -n 40 "$build_root/debootstrap.log" >&2; die "debootstrap failed (the end of its log is above)"; }
  t1=$(date +%s)
  tar --numeric-owner -C "$build_root/root" -cpf "$tarball.tmp" .
  mv -f "$tarball.tmp" "$tarball"
  release "$build_root"
  build_root=""
  say "debootstrap (cold): $(( t1 - t0 )) s; writing $tarball ($(du -h "$tarball" | cut -f1)): $(( $(date +%s) - t1 )) s"
else
  say "reusing $tarball (--rebuild to build it again)"
fi

mkdir -p "$tmp_parent"
root=$(realpath "$(mktemp -d "$tmp_parent/cellguard-bare-root.XXXXXX")")
t0=$(date +%s)
tar --numeric-owner -C "$root" -xpf "$tarball"
flock -u 9
exec 9>&-
say "unpacked the cached base root into $root (warm): $(( $(date +%s) - t0 )) s"

# --- Inside the root: apt sources, DNS, no services, the clone. --------------
if [ "$updated" = 1 ]; then
  {
    echo "# Written by tools/bare-root-test.sh --updated from the host's apt sources."
    printf '%s\n' "${sources[@]}" | awk '{ printf "deb %s %s", $1, $2; for (i = 3; i <= NF; i++) printf " %s", $i; print "" }'
  } >"$root/etc/apt/sources.list"
else
  # What debootstrap itself writes: the main archive of the release, nothing else.
  printf '# Written by tools/bare-root-test.sh as debootstrap writes it.\ndeb %s bookworm main\n' "$mirror" \
    >"$root/etc/apt/sources.list"
fi
say "apt sources in the root: $(grep -v '^#' "$root/etc/apt/sources.list" | tr '\n' ';')"
rm -f "$root/etc/resolv.conf"
cp -L /etc/resolv.conf "$root/etc/resolv.conf"
# Nothing runs an init system here: packages must not start services.
printf '#!/bin/sh\nexit 101\n' >"$root/usr/sbin/policy-rc.d"
chmod 755 "$root/usr/sbin/policy-rc.d"

if [ -n "$clone_at" ]; then
  case "$clone_at" in /*) ;; *) die "--clone-at needs an absolute path" ;; esac
  [ ! -e "$clone_at" ] || [ -z "$(ls -A "$clone_at")" ] || die "--clone-at $clone_at exists and is not empty"
  mkdir -p "$clone_at" "$root$clone_at"
  clone=$clone_at
  in_root=$clone_at
else
  clone=$root/root/cellguard
  in_root=/root/cellguard
fi
git clone --quiet --no-hardlinks --no-checkout "$repo" "$clone"
git -C "$clone" checkout --quiet --detach "$commit"
git -C "$clone" remote remove origin   # it names a host path
[ "$(git -C "$clone" rev-parse HEAD)" = "$commit" ] || die "the clone is not at $commit"
say "cloned $commit into $in_root (the root has no git)"

# --- Mounts. -------------------------------------------------------------------
mount -t proc proc "$root/proc"
mount --rbind /dev "$root/dev"
mount --make-rslave "$root/dev"
mount --rbind /sys "$root/sys"
mount --make-rslave "$root/sys"
if [ -n "$clone_at" ]; then
  mount --bind "$clone_at" "$root$clone_at"
fi
if [ "$apt_cache" = 1 ]; then
  mkdir -p "$cache/apt-archives/partial"
  mount --bind "$cache/apt-archives" "$root/var/cache/apt/archives"
  say "--apt-cache: downloaded packages are kept in $cache/apt-archives"
fi

# --- The two commands. ----------------------------------------------------------
# A login-like environment: nothing of this shell's environment but a proxy.
env_in=(HOME=/root USER=root LOGNAME=root PATH="$chroot_path" TERM="${TERM:-dumb}")
for v in http_proxy https_proxy no_proxy HTTP_PROXY HTTPS_PROXY NO_PROXY; do
  [ -n "${!v:-}" ] && env_in+=("$v=${!v}")
done
declare -A took
run_in_root() {  # name, time bound in seconds, command as README writes it
  local name=$1 limit=$2 cmd=$3 rc=0 t0 dt
  say "running '$cmd' in $in_root (chroot, at most $limit s)"
  t0=$(date +%s)
  # In the background and waited for, so that an interruption reaches the
  # trap at once; timeout signals the command's whole process group.
  timeout --kill-after=30 "$limit" chroot "$root" /usr/bin/env -i "${env_in[@]}" \
    /bin/bash -c 'cd "$0" && exec '"$cmd" "$in_root" </dev/null &
  child=$!
  wait "$child" || rc=$?
  child=""
  dt=$(( $(date +%s) - t0 ))
  took[$name]=$dt
  if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
    say "'$cmd' timed out after $dt s (bound $limit s)"
  fi
  say "'$cmd': ${dt} s, exit status $rc"
  return "$rc"
}
# The demo first: on the fresh root it shows what it installs and builds alone.
run_in_root demo "$demo_timeout" tools/demo.sh
# README: the demo's CAN frames go to monitor-demo.log (candump -L format).
log=$clone/monitor-demo.log
[ -s "$log" ] || die "tools/demo.sh exited 0 but wrote no monitor-demo.log"
say "monitor-demo.log: $(wc -l <"$log") CAN frames"
run_in_root test "$test_timeout" tools/test.sh
say "chromium in the root: $(chroot "$root" /usr/bin/chromium --version 2>/dev/null || echo none)"

say "passed on a bare Debian 12 root: tools/demo.sh ${took[demo]} s, then tools/test.sh ${took[test]} s"
