#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# End to end with live cameras (issue 19): cellguard-fake-camera serves the
# paper demo's four sensors as fake GigE Vision depth cameras on 127.0.0.2-5,
# and cellguard-monitor --paced runs apps/monitor/config/paper-cell-cameras.toml
# from them. Compared with the simulator run (cellguard-monitor --demo):
#   same     the zone states of every cycle and the first stop cycle, against
#            the simulator run of the same configuration without its camera
#            tables (sim-twin.toml), after the best shift of -1 to 8 cycles:
#            the fakes run with --scenario-start signal and this script sends
#            the signal when the monitor prints its first cycle, so the scene
#            starts after the monitor's cycle 0 (measured: 2 cycles later on
#            a loaded 2-core host; the bound allows a poll woken 600 ms late)
#            (before, the scene started when the last camera streamed and the
#            monitor's start-up, 7 cycles here, once took more than 15 under
#            CI load, so the scene had passed); at most 2 cycles' zone states may
#            differ (a free-running camera's frame is up to one period old when
#            a cycle takes it, so a transition can come a cycle later), the
#            first stop after release comes within 1 cycle of the shifted
#            simulator's; no fault latched
#   loss1    1 % of packets lost: incomplete frames are faults, the monitor stops
#   loss20   20 % lost: no complete frame; the monitor refuses to start ("no frame
#            with an accepted time stamp within 5 s"), or faults and stops
#   stopped  stereo-a stops sending at its frame 38 (the person is behind box A,
#            the zones clear): a stop within the stated response time, frame age
#            limit (200 ms) + one period (100 ms) = 3 cycles, plus the shift of 2
#   resolution, format
#            lidar-a serves 320x240, or has no Coord3D_C16: an error at start
#   frozen   cycle.max_repeated_frames = 3, every camera dithers one pixel (a
#            real sensor's noise); first a run without freezing latches no fault,
#            then lidar-b freezes from its frame 38: a fault and a stop
#   jump     lidar-a's device clock jumps 1 s at its frame 38: a fault
#   reboot   lidar-a powers off at its frame 30 (no control, no stream) and comes
#            back 2 s later as a new camera at its power-on defaults: a stop
#            within 3 + 2 cycles, then the monitor reconnects and, after the
#            fault recovery cycles, runs again without a fault
#   views    commissioning with cameras: the prior from cellguard-prior, the
#            cameras showing the empty cell (--empty), cellguard-monitor
#            --write-background records their views (5 frames each); then the
#            demo scene runs against those views: they load, and the person
#            (nearer than the background, never deeper) latches no fault
# Nothing leaves the machine: it runs inside tools/netns-run.sh (loopback only,
# 127.0.0.1-8), every program under a timeout.
#
# usage: run.sh FAKE_CAMERA MONITOR [CASE...]   (default: every case)
# Exit status: 0 all passed, 1 a case failed, 2 usage, 77 skipped: the monitor
# does not use [sensors.camera] yet (it rejects the table, or runs the
# simulator without noticing that no camera answers), or no namespace.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
if [[ $# -lt 2 ]]; then
    echo "usage: run.sh FAKE_CAMERA MONITOR [CASE...]" >&2
    exit 2
fi
if [[ "${CELLGUARD_IN_NETNS:-}" != 1 ]]; then
    exec "$root/tools/netns-run.sh" "$0" "$@"
fi
fake=$(realpath "$1")
monitor=$(realpath "$2")
prior_tool=$(dirname "$monitor")/../prior/cellguard-prior
shift 2
cases=("$@")
[[ ${#cases[@]} -gt 0 ]] || cases=(same loss1 loss20 stopped resolution format frozen jump reboot views)
config=${CELLGUARD_FAKE_CAMERAS_CONFIG:-$root/apps/monitor/config/paper-cell-cameras.toml}
min_shift=-1
max_shift=8
# Response bounds, milliseconds from the fault's frame to the first cycle with the fault (period 100 ms,
# cycle.max_frame_age_ms 200): a camera that stops sending is stale once its last frame is older than 200 ms,
# which a cycle sees at most one period later, + 100 ms for the last frame's own age when it was made;
# a frozen image needs 3 repeated frames (cycle.max_repeated_frames = 3 in that case) and one more cycle;
# a stamp jump refuses the next frame the cycle takes. Each bound has 200 ms of margin on top for this
# test's host (FIELD-NOTES: sleeps woke up to 249 ms late while four streams ran).
bound_stale_ms=$((200 + 100 + 100 + 200))
bound_frozen_ms=$((3 * 100 + 100 + 200))
bound_jump_ms=$((100 + 100 + 200))
out=$(mktemp -d)
fake_pid=
scene_pid=
cleanup() {
    [[ -n "$fake_pid" ]] && kill "$fake_pid" 2>/dev/null
    wait 2>/dev/null
    if [[ -n "${CELLGUARD_KEEP:-}" ]]; then echo "outputs kept in $out"; else rm -rf "$out"; fi
}
trap cleanup EXIT
cd "$out" || exit 1
failures=0
fail() { echo "FAILED ($case): $*"; failures=$((failures + 1)); }

# start_fakes NAME ARGS...: four cameras, until the monitor's run ends (bounded by --duration). Their scene
# and faults wait for SIGUSR1 (run_monitor sends it to scene_pid when the monitor runs its first cycle).
start_fakes() {
    local name=$1
    shift
    timeout 200 "$fake" --config "$config" --duration 150 --scenario-start signal ${CELLGUARD_FAKE_EXTRA:-} "$@" \
        >"$name.fake.txt" 2>&1 &
    fake_pid=$!
    scene_pid=
    for _ in $(seq 100); do
        scene_pid=$(sed -n 's/^scenario waits for SIGUSR1 to pid \([0-9]*\)$/\1/p' "$name.fake.txt" 2>/dev/null)
        [[ $(grep -c '^serving sensor' "$name.fake.txt" 2>/dev/null) -eq 4 && -n "$scene_pid" ]] && return 0
        kill -0 "$fake_pid" 2>/dev/null || break
        sleep 0.1
    done
    cat "$name.fake.txt"
    fail "the fake cameras did not start"
    return 1
}
stop_fakes() {
    kill -TERM "$fake_pid" 2>/dev/null
    wait "$fake_pid" 2>/dev/null
    fake_pid=
    grep '^sensor ' "$1.fake.txt"
}
# run_monitor NAME CONFIG ARGS...: the monitor's output in NAME.txt, its status in $status. When it prints
# its first cycle, the fakes' scene starts (SIGUSR1 to scene_pid).
run_monitor() {
    local name=$1 cfg=$2 pid
    shift 2
    timeout 300 "$monitor" --config "$cfg" --paced --budget-ms 60000 --log "$out/$name.log" "$@" >"$name.txt" 2>&1 &
    pid=$!
    while kill -0 "$pid" 2>/dev/null; do
        if grep -q '^t= *[0-9.]*s cycle' "$name.txt" 2>/dev/null; then
            [[ -n "$scene_pid" ]] && kill -USR1 "$scene_pid" 2>/dev/null
            break
        fi
        sleep 0.02
    done
    wait "$pid"
    status=$?
}
# states FILE: "cycle zones stop" per cycle line, e.g. "15 protective:INTRUDED_warning:INTRUDED STOP".
states() {
    sed -n 's/^.*cycle *\([0-9]*\) .*| \(protective:[A-Z]* warning:[A-Z]*\) | \([a-zA-Z]*\) .*$/\1 \2 \3/p' "$1" |
        awk '{ print $1, $2 "_" $3, $4 }'
}
# fault_column FILE: "cycle faults" per cycle line ("-" when none).
fault_column() { sed -n 's/^.*cycle *\([0-9]*\) .*| faults \([^|]*\) |.*$/\1 \2/p' "$1" | awk '{ print $1, $2 }'; }
# reaction NAME SENSOR: milliseconds from the fake's fault on SENSOR ("fault at t=" in NAME.fake.txt,
# CLOCK_MONOTONIC) to the first cycle of the paced monitor that starts at or after it with a fault latched
# (a fault requests the stop in its cycle); "none" when no such cycle, "already" when the cycle before
# had a fault latched. The status line's "t=" is the cycle's start on CLOCK_MONOTONIC minus 1 s (the
# simulated clock's start, kSimStartUs, which the line subtracts in both modes): 1 s is added back.
reaction() {
    local tf
    tf=$(sed -n "s/^sensor '$2': fault at t=\([0-9.]*\)s$/\1/p" "$1.fake.txt")
    [[ -n "$tf" ]] || { echo none; return; }
    sed -n 's/^t= *\([0-9.]*\)s cycle .*| faults \([^|]*\) |.*$/\1 \2/p' "$1.txt" |
        awk -v tf="$tf" '{ $1 += 1.0 } $1 >= tf && $2 != "-" { if (before != "-") { print "already"; found = 1; exit }
                                                 printf "%.0f\n", ($1 - tf) * 1000; found = 1; exit }
                         $1 < tf { before = $2 }
                         END { if (!found) print "none" }'
}
# check_reaction R BOUND WHAT: R from reaction() within BOUND ms, else a failure naming WHAT.
check_reaction() {
    case $1 in
    none) fail "no fault after $3" ;;
    already)
        # Not the monitor's reaction: a loaded host delivered a frame late before the fault was injected
        # (a stale or refused frame, latched for fault_recovery_cycles). The case runs once more.
        if [[ $attempt -eq 1 ]]; then
            echo "a fault was already latched in the cycle before $3 (a late frame on this loaded host): once more"
            again=1
        else
            fail "a fault was already latched in the cycle before $3, twice: the reaction cannot be measured"
        fi
        ;;
    *) (($1 <= $2)) || fail "the stop came $1 ms after $3 (bound $2 ms)" ;;
    esac
}
# late_only LATCHED: true when LATCHED names only faults a late or torn frame on an overloaded host
# raises ('sensor stale', 'frame inconsistent'), none that the case is about.
late_only() { [[ -n "$1" && "$1" != "-" ]] && [[ -z "$(tr ',' '\n' <<<"$1" | grep -v -x -e 'sensor stale' -e 'frame inconsistent')" ]]; }
first_stop() { sed -n 's/^summary:.*first stop after release in cycle \([0-9]*\).*/\1/p' "$1"; }
faults_latched() { sed -n 's/^summary: faults latched during the run: \([^;]*\);.*/\1/p' "$1"; }
# zone_states FILE: "cycle zones" per cycle line (no stop column: the start-up interlock is not scene-shifted).
zone_states() { states "$1" | awk '{ print $1, $2 }'; }
# best_shift SIM CAM: the shift s in min_shift..max_shift with the fewest cycles c whose zone states differ
# (cam at c against sim at c - s), as "s mismatches".
best_shift() {
    local best="" s m
    for s in $(seq -- "$min_shift" "$max_shift"); do
        m=$(awk -v s="$s" 'NR == FNR { z[$1] = $2; next } ($1 - s) in z { if (z[$1 - s] != $2) n++ } END { print n + 0 }' \
            <(zone_states "$1") <(zone_states "$2"))
        if [[ -z "$best" || $m -lt ${best#* } ]]; then best="$s $m"; fi
    done
    echo "$best"
}

# Does the monitor use the camera table? Without fakes running, a monitor that does must fail
# at start or latch faults; one that rejects the table, or runs the simulator, cannot be tested yet.
timeout 120 "$monitor" --config "$config" --cycles 3 --budget-ms 60000 --log "$out/probe.log" >probe.txt 2>&1
probe=$?
if grep -q "camera" probe.txt && [[ $probe -eq 2 ]] && grep -qi "unknown\|not allowed\|unexpected" probe.txt; then
    echo "SKIPPED: cellguard-monitor rejects the [sensors.camera] table:"
    cat probe.txt
    exit 77
fi
if [[ $probe -eq 0 ]] && [[ "$(faults_latched probe.txt)" == "-" ]]; then
    echo "SKIPPED: cellguard-monitor ran $config without any camera answering: it does not use [sensors.camera] yet"
    exit 77
fi

# The simulator's twin: the same configuration without its [sensors.camera] tables
# (and without the opt-out of the cameras' stamp tolerance: no camera, nothing to opt out of).
awk '/^\[sensors\.camera\]/ { skip = 1; next } skip && (/^$/ || /^\[/) { skip = 0 } !skip' "$config" |
    grep -v '^camera_stamp_tolerance = ' >sim-twin.toml
timeout 120 "$monitor" --config sim-twin.toml --cycles 60 --budget-ms 60000 --log "$out/sim.log" >sim.txt 2>&1 ||
    fail "the simulator run failed"
sim_stop=$(first_stop sim.txt)
echo "simulator: first stop after release in cycle $sim_stop"

# run_case CASE: one case; sets again=1 when its measurement could not be made and it may run once more.
run_case() {
    case $case in
    same)
        start_fakes same || return
        run_monitor same "$config" --cycles 60
        stop_fakes same
        if late_only "$(faults_latched same.txt)" && [[ $attempt -eq 1 ]]; then
            # A frame older than max_frame_age_ms on an overloaded host (load 12 here, 2026-12-06): the
            # fault held the stop and shifted the zone states. Once more; twice is a failure.
            echo "the run latched only $(faults_latched same.txt) (a late frame on this loaded host): once more"
            again=1
            return
        fi
        [[ $status -eq 0 ]] || fail "the monitor exited with $status"
        read -r offset mismatches < <(best_shift sim.txt same.txt)
        cam_stop=$(first_stop same.txt)
        echo "cameras: first stop in cycle $cam_stop, zone states shifted by $offset cycles, $mismatches cycles differ"
        [[ -n "$cam_stop" && -n "$sim_stop" ]] || fail "no first stop cycle"
        ((cam_stop - sim_stop - offset <= 1 && sim_stop + offset - cam_stop <= 1)) ||
            fail "first stop in cycle $cam_stop, the simulator's in $sim_stop, shifted by $offset"
        ((mismatches <= 2)) || fail "$mismatches cycles' zone states differ from the simulator's (shift $offset)"
        [[ "$(faults_latched same.txt)" == "-" ]] || fail "faults latched: $(faults_latched same.txt)"
        # The cycles follow the cameras' frames (SR-CAM-010): each starts when every camera has a new
        # frame, or at 1.125 periods; the latency is printed from each frame's capture and arrival.
        grep -E "^summary: (paced by the cameras|latency from the newest camera frame's arrival)" same.txt
        frame_starts=$(sed -n "s/^summary: paced by the cameras' frames: \([0-9]*\) cycles started.*/\1/p" same.txt)
        ((${frame_starts:-0} >= 1)) || fail "no cycle was started by the cameras' frames"
        grep -q "^summary: latency from the newest camera frame's arrival to its CAN frames over" same.txt ||
            fail "no latency from the frames' arrival in the summary"
        ;;
    loss1 | loss20)
        permille=$([[ $case == loss1 ]] && echo 10 || echo 200)
        start_fakes "$case" --loss "$permille" || return
        run_monitor "$case" "$config" --cycles 40
        stop_fakes "$case"
        if [[ $status -ne 0 ]] && grep -q "no frame with an accepted time stamp within" "$case.txt"; then
            echo "loss $permille per mille: refused at start: $(grep -m1 'no frame with' "$case.txt")"
            return
        fi
        latched=$(faults_latched "$case.txt")
        stops=$(sed -n 's/^summary: [0-9]* cycles, stop requested in \([0-9]*\),.*/\1/p' "$case.txt")
        echo "loss $permille per mille: faults latched: $latched; stop requested in $stops of 40 cycles"
        grep "^camera '.*buffers received" "$case.txt"
        [[ -n "$latched" && "$latched" != "-" ]] || fail "no fault latched"
        ((${stops:-0} >= 30)) || fail "stop requested in only ${stops:-0} of 40 cycles"
        ;;
    stopped)
        start_fakes stopped --fault-sensor stereo-a --stop-at 38 || return
        run_monitor stopped "$config" --cycles 50
        stop_fakes stopped
        r=$(reaction stopped stereo-a)
        echo "stereo-a stopped at its frame 38: the fault and the stop came $r ms later (bound $bound_stale_ms ms)"
        check_reaction "$r" "$bound_stale_ms" "the camera stopped"
        ;;
    resolution | format)
        arg=$([[ $case == resolution ]] && echo "--wrong-resolution 320x240" || echo "--no-coord3d")
        # shellcheck disable=SC2086  # two words on purpose
        start_fakes "$case" --fault-sensor lidar-a $arg || return
        run_monitor "$case" "$config" --cycles 10
        stop_fakes "$case"
        head -5 "$case.txt"
        [[ $status -ne 0 && $status -ne 124 ]] || fail "the monitor started (status $status) with lidar-a's $case wrong"
        grep -q "lidar-a\|127\.0\.0\.2\|CG-lidar-a" "$case.txt" || fail "the error does not name the camera"
        ;;
    frozen)
        # The check on: its opt-out goes too (an opt-out of a protection that is on is refused).
        sed -e 's/^max_repeated_frames = 0 /max_repeated_frames = 3 /' -e '/^frozen_sensor_check = /d' "$config" \
            >frozen.toml
        grep -q '^max_repeated_frames = 3 ' frozen.toml || { fail "cannot set max_repeated_frames"; return; }
        start_fakes dither --dither || return
        run_monitor dither frozen.toml --cycles 50
        stop_fakes dither
        latched=$(faults_latched dither.txt)
        if late_only "$latched" && [[ $attempt -eq 1 ]]; then
            # Frames older than max_frame_age_ms on an overloaded host (seen with a soak on the other core):
            # not the frozen-image check. Once more; twice is a failure.
            echo "the dithered run latched only $latched (a late frame on this loaded host): once more"
            again=1
            return
        fi
        [[ "$latched" == "-" ]] || fail "dithered frames latched: $latched"
        start_fakes frozen --dither --fault-sensor lidar-b --freeze-at 38 || return
        run_monitor frozen frozen.toml --cycles 50
        stop_fakes frozen
        latched=$(faults_latched frozen.txt)
        r=$(reaction frozen lidar-b)
        echo "lidar-b frozen from its frame 38: faults latched: $latched; the stop came $r ms later" \
            "(bound $bound_frozen_ms ms)"
        [[ -n "$latched" && "$latched" != "-" ]] || fail "the frozen image latched no fault"
        check_reaction "$r" "$bound_frozen_ms" "the freeze"
        ;;
    jump)
        start_fakes jump --fault-sensor lidar-a --stamp-jump-at 38 --stamp-jump-ms 1000 || return
        run_monitor jump "$config" --cycles 50
        stop_fakes jump
        latched=$(faults_latched jump.txt)
        r=$(reaction jump lidar-a)
        echo "lidar-a's clock jumped 1 s at its frame 38: faults latched: $latched; the stop came $r ms later" \
            "(bound $bound_jump_ms ms)"
        [[ -n "$latched" && "$latched" != "-" ]] || fail "the stamp jump latched no fault"
        check_reaction "$r" "$bound_jump_ms" "the jump"
        ;;
    reboot)
        start_fakes reboot --fault-sensor lidar-a --stop-at 30 --stop-mode power-off --restart-after-ms 2000 || return
        run_monitor reboot "$config" --cycles 150
        stop_fakes reboot
        r=$(reaction reboot lidar-a)
        c=$(sed -n 's/^t= *\([0-9.]*\)s cycle *\([0-9]*\) .*| faults \([^|]*\) |.*$/\1 \2 \3/p' reboot.txt |
            awk -v tf="$(sed -n "s/^sensor 'lidar-a': fault at t=\([0-9.]*\)s$/\1/p" reboot.fake.txt)" \
                '$3 != "-" && $1 + 1.0 >= tf { print $2; exit }')
        back=$(paste -d ' ' <(states reboot.txt) <(fault_column reboot.txt) |
            awk -v c="${c:-999}" '$1 > c && $3 == "run" && $5 == "-" { print $1; exit }')
        echo "lidar-a powered off at its frame 30, back 2 s later: the stop came $r ms later (bound" \
            "$bound_stale_ms ms), in cycle ${c:-none}; running again without a fault from cycle ${back:-never}"
        check_reaction "$r" "$bound_stale_ms" "the camera went away"
        [[ -n "$back" ]] || fail "the monitor did not recover after the camera came back"
        grep -q "lidar-a': .* 1 restarts" reboot.fake.txt || fail "the fake did not reboot lidar-a"
        ;;
    views)
        "$prior_tool" --simulated --config "$config" --out "$out/views-prior" >views.prior.txt 2>&1 ||
            { cat views.prior.txt; fail "cellguard-prior failed"; return; }
        sed "s|^source = \"simulated-background\".*|source = \"file\"\nfile = \"$out/views-prior/prior.cgprior\"|" \
            "$config" >views-rec.toml
        start_fakes views-empty --empty --dither || return
        kill -USR1 "$scene_pid" 2>/dev/null
        timeout 120 "$monitor" --config views-rec.toml --paced --write-background "$out/views.cgbv" \
            --background-frames 5 >views-rec.txt 2>&1
        status=$?
        stop_fakes views-empty
        grep '^background views' views-rec.txt
        [[ $status -eq 0 && -s "$out/views.cgbv" ]] || { cat views-rec.txt; fail "recording exited $status"; return; }
        # This case is about the recorded views (loaded, used, no fault from them); frame age has its own
        # case (stopped). Frames up to 1 s old are accepted here: at load 9 to 12 (tools/load-test.sh) late
        # frames latched 'sensor stale' with the 200 ms limit in one run of two.
        sed -e "s|^file = \"$out/views-prior/prior.cgprior\"|&\nbackground_file = \"$out/views.cgbv\"|" \
            -e 's/^max_frame_age_ms = 200.*/max_frame_age_ms = 1000/' views-rec.toml >views.toml
        grep -q '^max_frame_age_ms = 1000$' views.toml || { fail "cannot set max_frame_age_ms"; return; }
        start_fakes views --dither || return
        run_monitor views views.toml --cycles 40
        stop_fakes views
        [[ $status -eq 0 ]] || fail "the monitor exited with $status"
        grep -q "^background views: $out/views.cgbv (4 sensors" views.txt || fail "the recorded views were not loaded"
        echo "demo scene against the recorded views: stop cycles $(grep -c '| STOP' views.txt)," \
            "faults latched: $(faults_latched views.txt)"
        if late_only "$(faults_latched views.txt)" && [[ $attempt -eq 1 ]]; then
            # Seen at load 8.6 (2026-12-06): 'frame inconsistent' from a late or torn frame. Once more.
            echo "the run latched only $(faults_latched views.txt) (a late frame on this loaded host): once more"
            again=1
            return
        fi
        grep -q '| STOP' views.txt || fail "the person never stopped the robot"
        [[ "$(faults_latched views.txt)" == "-" ]] || fail "faults latched: $(faults_latched views.txt)"
        ;;
    *)
        echo "unknown case '$case'" >&2
        exit 2
        ;;
    esac
}
for case in "${cases[@]}"; do
    echo "=== $case"
    again=0
    attempt=1
    run_case
    if [[ $again -eq 1 ]]; then
        again=0
        attempt=2
        run_case
    fi
done
echo "fake cameras end to end: ${#cases[@]} cases, $failures failures"
((failures == 0))
