# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Issue 24's trial as a user runs it: commission a prior from one real
# recorded frame with cellguard-prior (the frame given three times: the
# probabilistic method needs three), then replay the same frame with
# cellguard-monitor for one cycle. The scene is the background, so the zone
# over the whole view must be CLEAR, and the status line must not show the
# simulator's scripted person. Run as
#   cmake -DPRIOR=path -DMONITOR=path -DFRAME=file.pcd -DWORK=dir -DMETHOD=m
#         -DFORM=target|rotation [-DEMULATOR=a|b] -P RecordedTrial.cmake
#   FORM target:   the camera at the origin aimed at (3, 0, 0) (x forward)
#   FORM rotation: rotation = { w = 1, x = 0, y = 0, z = 0 }, the camera's own frame (z forward,
#                  x right, y down: a roll the simulator cannot render)
string(REPLACE "|" ";" emulator "${EMULATOR}")
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
if(FORM STREQUAL "target")
  set(pose "target = [3.0, 0.0, 0.0]")
  set(origin "[0.4, -1.6, -0.6]")
  set(dims "[64, 64, 48]")
  set(zone_min "[0.45, -1.5, -0.5]")
  set(zone_max "[3.5, 1.5, 1.5]")
else()
  set(pose "rotation = { w = 1.0, x = 0.0, y = 0.0, z = 0.0 }")
  set(origin "[-1.6, -1.2, 0.4]")
  set(dims "[64, 48, 64]")
  set(zone_min "[-1.5, -1.1, 0.45]")
  set(zone_max "[1.5, 1.1, 3.5]")
endif()
file(WRITE "${WORK}/cell.toml" "[grid]
origin = ${origin}
voxel_size = 0.05
dims = ${dims}
[[sensors]]
name = \"kinect\"
position = [0.0, 0.0, 0.0]
${pose}
resolution = [640, 480]
fov = [57.0, 43.0]
max_range = 5.0
pcd_files = [\"${FRAME}\"]
[[zones]]
name = \"view\"
kind = \"protective\"
shape = \"box\"
min = ${zone_min}
max = ${zone_max}
min_foreground_voxels = 1
max_unseen_voxels = 1000000
[thresholds]
foreground_probability = 0.73
accessible_min_p_fore = 0.05
[prior]
source = \"file\"
file = \"prior/prior.cgprior\"
[can]
log_file = \"trial.log\"
safety_id = 0x101
diagnostics_id = 0x103
safety_data_id = 0x0C51
diagnostics_data_id = 0x0D52
data_id_mode = \"both\"
[cycle]
period_ms = 100
budget_ms = 100
max_frame_age_ms = 200
background_match = 0
[restart_interlock]
delay_ms = 500
reset_required = false
[opt_out]
reset_required = \"a recorded trial of one cycle: no restart to interlock\"
background_view_check = \"the recorded frame has no commissioned view of the empty cell\"
watchdog_device = \"a test run on a build host: it must not arm the host's watchdog\"
")
set(frame "kinect=${FRAME}")
execute_process(COMMAND ${emulator} ${PRIOR} --config cell.toml --frame ${frame} --frame ${frame} --frame ${frame}
                        --method ${METHOD} --out prior
                WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "cellguard-prior failed (${status}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${emulator} ${MONITOR} --config cell.toml --cycles 1 --budget-ms 60000
                WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(report "cellguard-monitor (${status}):\n${out}\n${err}")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the monitor failed; ${report}")
endif()
if(NOT out MATCHES "cycle +0 recorded frames +\\| view:CLEAR \\|")
  message(FATAL_ERROR "the replayed background is not CLEAR, or the status line is not that of recorded frames; ${report}")
endif()
if(out MATCHES "person")
  message(FATAL_ERROR "the status line shows the simulator's person for recorded frames; ${report}")
endif()
message(STATUS "${METHOD}, ${FORM}: CLEAR")
