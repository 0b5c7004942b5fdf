# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Runs the firmware on qemu-system-arm -M mps2-an500 with semihosting (60 s
# timeout) and checks that it exits with 0 and prints "digest EXPECTED" and,
# given EXPECTED_ROBOT, "robot digest EXPECTED_ROBOT" (the robot-cell run),
# given EXPECTED_FOOTPRINT, "footprint digest EXPECTED_FOOTPRINT" (the
# zones-only run fused by footprint fusion).
# Run as: cmake -DQEMU=... -DELF=... -DEXPECTED=0x... [-DEXPECTED_ROBOT=0x...]
#         [-DEXPECTED_FOOTPRINT=0x...] [-DLOG=file] -P run_qemu.cmake
execute_process(COMMAND ${QEMU} -M mps2-an500 -nographic -monitor none -serial null
                        -semihosting-config enable=on,target=native -kernel ${ELF}
                TIMEOUT 60 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
# QEMU writes the semihosting console to stderr, its own messages too.
set(out "${out}${err}")
if(LOG)
  file(WRITE ${LOG} "${out}")
endif()
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the firmware failed under qemu-system-arm (exit ${rc})")
endif()
string(REGEX MATCH "digest 0x[0-9a-f]+" line "${out}")
if(NOT line STREQUAL "digest ${EXPECTED}")
  message(FATAL_ERROR "firmware printed '${line}', expected 'digest ${EXPECTED}'")
endif()
if(EXPECTED_ROBOT)
  string(REGEX MATCH "robot digest 0x[0-9a-f]+" robot_line "${out}")
  if(NOT robot_line STREQUAL "robot digest ${EXPECTED_ROBOT}")
    message(FATAL_ERROR "firmware printed '${robot_line}', expected 'robot digest ${EXPECTED_ROBOT}'")
  endif()
endif()
if(EXPECTED_FOOTPRINT)
  string(REGEX MATCH "footprint digest 0x[0-9a-f]+" footprint_line "${out}")
  if(NOT footprint_line STREQUAL "footprint digest ${EXPECTED_FOOTPRINT}")
    message(FATAL_ERROR "firmware printed '${footprint_line}', expected 'footprint digest ${EXPECTED_FOOTPRINT}'")
  endif()
endif()
message(STATUS "firmware digest ${EXPECTED} as expected; robot digest ${EXPECTED_ROBOT}; footprint digest ${EXPECTED_FOOTPRINT}")
