#!/usr/bin/env bash
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# apps/monitor/config/paper-cell-cameras.toml must stay paper-cell.toml plus
# one [sensors.camera] table per sensor, its own CAN log name and its grid
# half a voxel lower (the floor off a voxel face, for quantized depth): the
# end-to-end test compares the two cells' runs. Compares both files without
# comments, blank lines, the camera tables, can.log_file, grid.origin and
# cycle.max_repeated_frames (0 with the fakes: without --dither they serve
# the same bytes while nothing moves; the simulated sensors vary) and the
# fakes' two opt-outs (opt_out.frozen_sensor_check, camera_stamp_tolerance).
# usage: cameras-config-check.sh PAPER_CELL_TOML PAPER_CELL_CAMERAS_TOML
set -euo pipefail
strip() {
    awk '/^\[sensors\.camera\]/ { skip = 1; next } /^\[/ { skip = 0 } !skip' "$1" |
        sed -e 's/[[:space:]]*#.*$//' -e '/^[[:space:]]*$/d' -e '/^log_file = /d' -e '/^origin = /d' \
            -e '/^max_repeated_frames = /d' -e '/^frozen_sensor_check = /d' -e '/^camera_stamp_tolerance = /d'
}
if diff <(strip "$1") <(strip "$2"); then
    echo "$2 is $1 with camera tables"
else
    echo "FAILED: $2 differs from $1 beyond the [sensors.camera] tables (lines above: < $1, > $2)"
    exit 1
fi
[[ $(grep -c '^\[sensors\.camera\]' "$2") -eq $(grep -c '^\[\[sensors\]\]' "$1") ]] ||
    { echo "FAILED: not one [sensors.camera] table per sensor"; exit 1; }
