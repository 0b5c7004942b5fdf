#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Runs a command in a new user and network namespace whose only interface is
# loopback, up, with the addresses 127.0.0.1 to 127.0.0.8 (issue 19: several
# fake GigE Vision cameras each bind UDP 3956 on their own 127.0.0.N, and
# Aravis's fake camera binds only an address some interface has: on a host
# whose loopback has 127.0.0.1 alone, 127.0.0.2 fails to start). Nothing the
# command sends can leave the namespace, and no camera discovery reaches the
# host's networks. Works unprivileged (unshare -r maps the caller to root in
# the namespace) where the kernel allows user namespaces; as root also with a
# network namespace alone where user namespaces are refused (a chroot).
#
# usage: tools/netns-run.sh COMMAND [ARG...]
# Exit status: the command's; 77 (ctest's skip code as the tests use it) when
# the namespace cannot be made (no unshare or ip, or user namespaces off).
set -euo pipefail
if [[ $# -lt 1 ]]; then
    echo "usage: tools/netns-run.sh COMMAND [ARG...]" >&2
    exit 2
fi
if [[ "${CELLGUARD_IN_NETNS:-}" != 1 ]]; then
    for tool in unshare ip; do
        if ! command -v "$tool" >/dev/null 2>&1 && [[ ! -x /usr/sbin/$tool && ! -x /sbin/$tool ]]; then
            echo "netns-run: $tool not found (util-linux, iproute2): cannot make the namespace" >&2
            exit 77
        fi
    done
    # A user and network namespace where the kernel allows one; as root, a network namespace alone
    # (a chroot, such as tools/bare-root-test.sh's, may not make user namespaces, but root may make
    # network namespaces there). CELLGUARD_NETNS_NO_USERNS=1 skips the first, to test the second.
    if [[ "${CELLGUARD_NETNS_NO_USERNS:-}" != 1 ]] && unshare -rn true 2>/dev/null; then
        export CELLGUARD_IN_NETNS=1
        exec unshare -rn "$0" "$@"
    fi
    if [[ $(id -u) -eq 0 ]] && unshare -n true 2>/dev/null; then
        export CELLGUARD_IN_NETNS=1
        exec unshare -n "$0" "$@"
    fi
    echo "netns-run: neither unshare -rn nor (as root) unshare -n works: cannot make the namespace" >&2
    exit 77
fi
# Inside the namespace.
export PATH="$PATH:/usr/sbin:/sbin"
ip link set lo up
have=$(ip -4 addr show dev lo)  # called again inside the namespace: the addresses are there
for n in 2 3 4 5 6 7 8; do
    [[ "$have" == *" 127.0.0.$n/"* ]] || ip addr add "127.0.0.$n/8" dev lo
done
exec "$@"
