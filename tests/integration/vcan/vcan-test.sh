#!/bin/sh
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The vcan integration test proper: cellguard-monitor sends its safety output
# on a real kernel CAN interface, candump -L records it, cellguard-vcan-check
# checks the recording with the PLC-side receiver. Runs as the VM's /init
# payload (busybox ash) or directly on a host that has vcan (any POSIX sh);
# tools/vcan-integration.sh starts it either way.
#
# usage: vcan-test.sh BIN_DIR CONFIG WORK_DIR [IFACE]
#   BIN_DIR  holds cellguard-monitor, cellguard-vcan-check, cellguard-vcan-plc
#            and candump
#   CONFIG   the monitor configuration (tests/integration/vcan/vcan-cell.toml);
#            vcan-robot-cell.toml, vcan-robot-scene.toml and robot-arm.urdf
#            (run 3) are next to it
#   WORK_DIR logs and outputs go here
#   IFACE    an existing CAN interface that is up (default vcan0); this test
#            takes it down and up again
# Needs CAP_NET_ADMIN (ip link set). The last line of output is
#   CELLGUARD-VCAN-RESULT: PASS   or   CELLGUARD-VCAN-RESULT: FAIL
# and the exit status is 0 exactly for PASS.
#
# Three runs (a fourth and fifth below), all paced (one cycle per period on the real clock); RUNS
# (default "normal fault robot") selects them:
# 1. normal: NORMAL_CYCLES cycles undisturbed; every frame recorded and valid,
#    the stop in the entry cycle (cellguard-vcan-check normal). Protocol 0.2:
#    in runs 1 and 2 (a cell without a robot) cellguard-vcan-plc runs in its
#    link mode, the PLC's link frame alone in reply to each of the monitor's,
#    so that the monitor echoes it and the check's PLC receiver accepts pairs.
# 2. fault: after the monitor has reported cycle DOWN_AT the interface is
#    set down, after cycle UP_AT up again; the fault path and the recovery
#    (cellguard-vcan-check fault). DOWN_AT is after the person has left both
#    zones and the stop was released, so the stop comes from the fault alone;
#    FAULT_CYCLES leaves time for fault_recovery_cycles (10) and the restart
#    delay after UP_AT.
# 3. robot: both directions in a robot cell (vcan-robot-cell.toml: frames
#    from a simulated scene, the command from vcan0: --commands can).
#    cellguard-vcan-plc is the PLC: from the monitor's first frame it sends
#    the command (PlcCommandSender) every half period, case 0, case 2 from
#    cycle SWITCH_AT, nothing from cycle SILENT_AT, and checks the monitor's
#    frames live (PlcReceiver): commands accepted and their case echoed, the
#    stop released, then the stop within SCT + 2 T after the PLC fell silent;
#    then, at cycle DELAY_AT, a sample held since the silence (older than the
#    watchdog time), and at cycle REPLAY_AT a whole sample from 15 samples
#    before it: the monitor refuses both (CommandValid stays 0; its status
#    lines name the reason: the watchdog and the repeated sequence).
# 4. unprivileged: UNPRIV_CYCLES cycles as user nobody with no capabilities,
#    as the systemd unit runs it (apps/monitor/systemd: DynamicUser, an empty
#    CapabilityBoundingSet): the CAN_RAW socket on the interface, which is
#    up, opens and every frame is sent, four a cycle (needs root and su to
#    start it; no PLC: its link frames echo nothing).
set -u
bin=$1
cfg=$2
work=$3
ifc=${4:-vcan0}
NORMAL_CYCLES=${NORMAL_CYCLES:-20}
FAULT_CYCLES=${FAULT_CYCLES:-60}
DOWN_AT=${DOWN_AT:-36}
UP_AT=${UP_AT:-41}
SWITCH_AT=${SWITCH_AT:-8}
SILENT_AT=${SILENT_AT:-11}
DELAY_AT=${DELAY_AT:-17}
REPLAY_AT=${REPLAY_AT:-19}
END_AT=${END_AT:-21}
# The robot run's cycle budget (--budget-ms): two periods, so that the session
# link's watchdog time (two periods plus the budget: 8 s) is shorter than the
# delayed sample's hold (SILENT_AT to DELAY_AT, 12 s).
ROBOT_BUDGET_MS=${ROBOT_BUDGET_MS:-4000}
UNPRIV_CYCLES=${UNPRIV_CYCLES:-10}
RUNS=${RUNS:-normal fault robot unprivileged}
rcfg=$(dirname "$cfg")/vcan-robot-cell.toml

failures=0
say() { echo "vcan-test: $*"; }
fail() { say "FAIL: $*"; failures=$((failures + 1)); }
uptime_s() { cut -d' ' -f1 /proc/uptime; }
finish() {
    if [ "$failures" -eq 0 ]; then
        say "all checks passed ($(uptime_s) s since boot)"
        echo "CELLGUARD-VCAN-RESULT: PASS"
        exit 0
    fi
    say "$failures check(s) failed"
    echo "CELLGUARD-VCAN-RESULT: FAIL"
    exit 1
}
show() {  # show FILE: its last lines, indented, for a failure report
    [ -f "$1" ] && tail -n "${2:-15}" "$1" | sed 's/^/    | /'
}

mkdir -p "$work" || { fail "cannot create $work"; finish; }
for p in cellguard-monitor cellguard-vcan-check cellguard-vcan-plc candump; do
    [ -x "$bin/$p" ] || fail "$bin/$p missing"
done
[ -f "$cfg" ] || fail "configuration $cfg missing"
[ -f "$rcfg" ] || fail "configuration $rcfg missing"
ip link show "$ifc" > /dev/null 2>&1 || fail "no interface $ifc"
[ "$failures" -eq 0 ] || finish

# Starts candump -L on the interface into $1 (extra options after it) and
# returns once its socket is bound: /proc/net/can/rcvlist_all then lists a
# receiver on the interface (or after 2 s where the kernel has no such file).
start_candump() {
    out=$1
    shift
    "$bin/candump" -L "$@" "$ifc" > "$out" 2> "$out.err" &
    candump_pid=$!
    i=0
    while [ $i -lt 100 ]; do
        if [ -r /proc/net/can/rcvlist_all ]; then
            awk -v i="$ifc" '$1 == i { found = 1 } END { exit !found }' /proc/net/can/rcvlist_all && return 0
        elif [ $i -ge 40 ]; then
            return 0
        fi
        kill -0 "$candump_pid" 2> /dev/null || { fail "candump exited at start"; show "$out.err"; return 1; }
        sleep 0.05
        i=$((i + 1))
    done
    fail "candump did not bind to $ifc within 5 s"
    return 1
}

# Waits (at most $2 s) until the monitor's stdout $1 shows the status line of
# cycle $3. Polls every 0.1 s: under TCG every grep is a costly fork and exec
# that slows the monitor's cycles (every 20 ms doubled them).
wait_for_cycle() {
    i=0
    while [ $i -lt $(($2 * 10)) ]; do
        grep -q "cycle *$3 person" "$1" && return 0
        kill -0 "$monitor_pid" 2> /dev/null || return 1
        sleep 0.1
        i=$((i + 1))
    done
    return 1
}

# Starts cellguard-vcan-plc in its link mode on the interface (run 1, 2) and
# returns once it listens; its output goes to $1.
# Waits up to 60 s for the PLC program (pid $2) to write its first line ("PLC: ...") to $1; fails when it
# did not (it exited, or took longer).
wait_plc_started() {
    i=0
    while [ $i -lt 600 ] && ! grep -q '^PLC: ' "$1" && kill -0 "$2" 2> /dev/null; do
        sleep 0.1
        i=$((i + 1))
    done
    grep -q '^PLC: ' "$1"
}

start_link_plc() {
    "$bin/cellguard-vcan-plc" link "$cfg" "$ifc" > "$1" 2>&1 &
    link_plc_pid=$!
    wait_plc_started "$1" "$link_plc_pid" || { fail "the link PLC did not start"; show "$1"; return 1; }
}

# Waits up to $2 s for process $1 to exit, then interrupts it.
wait_or_interrupt() {
    i=0
    while kill -0 "$1" 2> /dev/null && [ $i -lt $(($2 * 20)) ]; do
        sleep 0.05
        i=$((i + 1))
    done
    kill -INT "$1" 2> /dev/null
    wait "$1" 2> /dev/null
}

say "kernel $(uname -r), interface $ifc, $(uptime_s) s since boot"

case " $RUNS " in *" normal "*) ;; *) NORMAL_CYCLES=0 ;; esac
case " $RUNS " in *" fault "*) ;; *) FAULT_CYCLES=0 ;; esac

# --- 1. normal run --------------------------------------------------------
if [ "$NORMAL_CYCLES" -gt 0 ]; then
say "normal run: $NORMAL_CYCLES cycles, paced"
start_candump "$work/normal.log" -n $((5 * NORMAL_CYCLES)) || finish
start_link_plc "$work/normal.plc" || finish
t0=$(uptime_s)
"$bin/cellguard-monitor" --config "$cfg" --can-interface "$ifc" --cycles "$NORMAL_CYCLES" --paced \
    > "$work/normal.out" 2>&1
rc=$?
say "normal run: monitor exited $rc after $(awk -v a="$t0" -v b="$(uptime_s)" 'BEGIN { printf "%.1f", b - a }') s"
[ $rc -eq 0 ] || { fail "monitor exit status $rc"; show "$work/normal.out"; }
grep '^summary:' "$work/normal.out" | sed 's/^/    /'
# candump -n exits by itself after the expected frame count.
wait_or_interrupt "$candump_pid" 5
wait_or_interrupt "$link_plc_pid" 0
grep '^PLC: ' "$work/normal.plc" | sed 's/^/    /'
if "$bin/cellguard-vcan-check" normal "$cfg" "$work/normal.log" "$NORMAL_CYCLES" > "$work/normal.check" 2>&1; then
    say "PASS normal: $(tail -n 1 "$work/normal.check")"
else
    fail "normal run check"
    sed 's/^/    /' "$work/normal.check"
fi

fi

# --- 2. fault run: interface down and up again mid-run ---------------------
if [ "$FAULT_CYCLES" -gt 0 ]; then
say "fault run: $FAULT_CYCLES cycles, paced; $ifc down after cycle $DOWN_AT, up after cycle $UP_AT"
# -D: candump keeps running while the interface is down.
start_candump "$work/fault.log" -D || finish
start_link_plc "$work/fault.plc" || finish
"$bin/cellguard-monitor" --config "$cfg" --can-interface "$ifc" --cycles "$FAULT_CYCLES" --paced \
    > "$work/fault.out" 2> "$work/fault.err" &
monitor_pid=$!
if wait_for_cycle "$work/fault.out" 120 "$DOWN_AT"; then
    ip link set "$ifc" down || fail "ip link set $ifc down"
    say "fault run: $ifc down after cycle $DOWN_AT"
else
    fail "the monitor did not reach cycle $DOWN_AT"
fi
if wait_for_cycle "$work/fault.out" 60 "$UP_AT"; then
    ip link set "$ifc" up || fail "ip link set $ifc up"
    say "fault run: $ifc up after cycle $UP_AT"
else
    fail "the monitor did not reach cycle $UP_AT"
    ip link set "$ifc" up
fi
wait "$monitor_pid"
rc=$?
# Exit status 3: the run completed but the CAN output failed in some cycle.
[ $rc -eq 3 ] || { fail "monitor exit status $rc in the fault run (expected 3: CAN output failed)"; show "$work/fault.err"; }
grep -q 'the CAN output failed: CAN-error fault latched in' "$work/fault.err" ||
    { fail "the monitor did not say why it exited 3"; show "$work/fault.err"; }
grep '^summary:' "$work/fault.out" | sed 's/^/    /'
# Let candump read what is queued, then stop it (it flushes on SIGINT).
sleep 0.5
wait_or_interrupt "$link_plc_pid" 0
kill -INT "$candump_pid" 2> /dev/null
wait "$candump_pid" 2> /dev/null
grep '^PLC: ' "$work/fault.plc" | sed 's/^/    /'
if "$bin/cellguard-vcan-check" fault "$cfg" "$work/fault.log" "$work/fault.out" "$FAULT_CYCLES" \
    > "$work/fault.check" 2>&1; then
    say "PASS fault: $(tail -n 1 "$work/fault.check")"
else
    fail "fault run check"
    sed 's/^/    /' "$work/fault.check"
    say "monitor status lines around the outage:"
    grep "cycle *[0-9]* person" "$work/fault.out" | sed -n "$((DOWN_AT - 1)),\$p" | cut -c1-150 | sed 's/^/    | /'
fi
fi

# --- 3. robot cell: the PLC's command on the bus, both directions -----------
case " $RUNS " in *" robot "*)
# robot_run ATTEMPT: one run; 0 when it passed, 2 when it failed and the PLC
# says the host stalled its own writes (a sample spread over more than the
# monitor's sample window, whose refusal is right), 1 otherwise.
robot_run() {
say "robot run (attempt $1): $((END_AT + 1)) cycles, paced, --commands can; PLC: case 0, case 2 from cycle $SWITCH_AT, silent from cycle $SILENT_AT, a delayed sample at $DELAY_AT, a replayed one at $REPLAY_AT"
t0=$(uptime_s)
"$bin/cellguard-vcan-plc" "$rcfg" "$ifc" "$SWITCH_AT" "$SILENT_AT" "$DELAY_AT" "$REPLAY_AT" "$END_AT" \
    "$ROBOT_BUDGET_MS" \
    > "$work/robot.plc" 2>&1 &
plc_pid=$!
# The PLC listens before the monitor's first frame: its first line says so.
wait_plc_started "$work/robot.plc" "$plc_pid" || { show "$work/robot.plc"; return 1; }
# --budget-ms: two periods, not the emulator's speed alone (see ROBOT_BUDGET_MS).
"$bin/cellguard-monitor" --config "$rcfg" --can-interface "$ifc" --commands can --cycles $((END_AT + 1)) --paced \
    --budget-ms "$ROBOT_BUDGET_MS" > "$work/robot.out" 2>&1
rc=$?
say "robot run: monitor exited $rc after $(awk -v a="$t0" -v b="$(uptime_s)" 'BEGIN { printf "%.1f", b - a }') s"
[ $rc -eq 0 ] || { show "$work/robot.out"; return 1; }
grep '^summary:' "$work/robot.out" | sed 's/^/    /'
wait_or_interrupt "$plc_pid" 30
grep '^PLC: samples' "$work/robot.plc" | sed 's/^/    /'
# The monitor's status lines name why it refused the delayed and the replayed sample.
why_delay=$(grep -c 'link: round trip or data age above the watchdog time' "$work/robot.out")
# The replay is behind the link's reference: a repeated sequence (a jump only once the reference is older than W).
why_replay=$(grep -c -E 'link: (repeated sequence|sequence jump)' "$work/robot.out")
say "robot run: monitor status lines naming the watchdog: $why_delay, the replay (repeated sequence or jump): $why_replay"
if [ -s "$work/robot.plc" ] && tail -n 1 "$work/robot.plc" | grep -q '; 0 failures$' &&
    [ "$why_delay" -gt 0 ] && [ "$why_replay" -gt 0 ]; then
    say "PASS robot: $(tail -n 1 "$work/robot.plc")"
    return 0
fi
sed 's/^/    /' "$work/robot.plc"
say "monitor status lines:"
grep "cycle *[0-9]* robot" "$work/robot.out" | cut -c1-300 | sed 's/^/    | /'
grep -q '^PLC: DISTURBED' "$work/robot.plc" && return 2
return 1
}
robot_run 1
r=$?
if [ $r -eq 2 ]; then
    say "robot run: the host stalled the PLC's writes (above); once more"
    robot_run 2
    r=$?
fi
[ $r -eq 0 ] || fail "robot run check (cellguard-vcan-plc)"
;;
esac

# --- 4. unprivileged: the service's user, no capabilities -------------------
case " $RUNS " in *" unprivileged "*)
if [ "$(id -u)" -ne 0 ] || ! command -v su > /dev/null 2>&1; then
    say "unprivileged run: SKIPPED (needs root and su to start it as nobody)"
else
say "unprivileged run: $UNPRIV_CYCLES cycles as user nobody without capabilities"
# The program and configuration where nobody can read them.
upriv=$(mktemp -d /tmp/cellguard-unpriv.XXXXXX)
cp "$bin/cellguard-monitor" "$cfg" "$upriv/"
chmod 755 "$upriv" "$upriv/cellguard-monitor"
chmod 644 "$upriv/$(basename "$cfg")"
start_candump "$work/unpriv.log" -n $((4 * UNPRIV_CYCLES)) || finish
su -s /bin/sh nobody -c "cd /; grep '^Cap' /proc/self/status; exec '$upriv/cellguard-monitor' --config '$upriv/$(basename "$cfg")' --can-interface '$ifc' --cycles $UNPRIV_CYCLES --quiet --budget-ms 60000" \
    > "$work/unpriv.out" 2>&1
rc=$?
wait_or_interrupt "$candump_pid" 5
frames=$(wc -l < "$work/unpriv.log")
grep '^Cap' "$work/unpriv.out" | sed 's/^/    /'
grep -q '^CapEff:[[:space:]]*0000000000000000$' "$work/unpriv.out" ||
    { fail "the monitor did not run without capabilities"; show "$work/unpriv.out"; }
[ $rc -eq 0 ] || { fail "monitor exit status $rc as nobody"; show "$work/unpriv.out"; }
if [ "$frames" -eq $((4 * UNPRIV_CYCLES)) ]; then
    say "PASS unprivileged: $frames frames sent as nobody without capabilities"
else
    fail "unprivileged run: $frames frames on $ifc, expected $((4 * UNPRIV_CYCLES))"
    show "$work/unpriv.out"
fi
rm -rf "$upriv"
fi
;;
esac

# --- 5. watchdog (opt-in, RUNS=watchdog): softdog resets a stopped monitor --
# The monitor feeds /dev/watchdog (the softdog module, loaded by /init) after
# healthy cycles; SIGSTOP freezes it, as a hung cycle would. softdog then
# restarts the machine (qemu -no-reboot ends): tools/vcan-integration.sh
# passes the run when the console stops after CELLGUARD-WATCHDOG: stopped and
# never shows NO RESET.
case " $RUNS " in *" watchdog "*)
if [ ! -c /dev/watchdog ]; then
    fail "watchdog run: no /dev/watchdog (softdog not loaded)"
else
# The cell's configuration without its opt-out of the watchdog device (the other runs keep it: they
# must not arm softdog), which --watchdog would contradict; it names no file, so the copy loads anywhere.
grep -v '^watchdog_device = ' "$cfg" > "$work/watchdog-cell.toml"
"$bin/cellguard-monitor" --config "$work/watchdog-cell.toml" --can-interface "$ifc" --cycles 100000 --paced --quiet \
    --budget-ms 60000 --watchdog /dev/watchdog --watchdog-timeout-s 3 > "$work/watchdog.out" 2>&1 &
wd_pid=$!
sleep 8
if kill -0 "$wd_pid" 2> /dev/null; then
    grep '^watchdog:' "$work/watchdog.out" | sed 's/^/    /'
    echo "CELLGUARD-WATCHDOG: stopped the monitor (SIGSTOP) at $(uptime_s) s"
    kill -STOP "$wd_pid"
    sleep 30
    echo "CELLGUARD-WATCHDOG: NO RESET 30 s after the monitor stopped"
    fail "watchdog run: softdog did not reset the machine"
else
    fail "watchdog run: the monitor ended early"
    show "$work/watchdog.out"
fi
fi
;;
esac

finish
