# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Runs the watchdog test image (src/main_watchdog.cpp) on qemu-system-arm -M
# mps2-an500 (reboot allowed: the watchdog's reset restarts the image, 120 s
# timeout) and checks, in order: the first boot armed the watchdog, the
# injected hang, the watchdog's NMI, the second boot after the reset (no CAN
# frame between the hang and it), a fresh start of the safety frames, and
# the exit with success.
# Run as: cmake -DQEMU=... -DELF=... [-DLOG=file] -P run_qemu_watchdog.cmake
string(TIMESTAMP t0 "%s")
execute_process(COMMAND ${QEMU} -M mps2-an500 -nographic -monitor none -serial null
                        -semihosting-config enable=on,target=native -kernel ${ELF}
                TIMEOUT 120 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(TIMESTAMP t1 "%s")
set(out "${out}${err}")
if(LOG)
  file(WRITE ${LOG} "${out}")
endif()
math(EXPR seconds "${t1} - ${t0}")
message("qemu ran ${seconds} s; the lines of the test:")
string(REGEX MATCHALL "watchdog[^\n]*" lines "${out}")
foreach(line IN LISTS lines)
  message("  ${line}")
endforeach()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the watchdog test image failed under qemu-system-arm (exit ${rc})")
endif()
set(expected
    "watchdog test: first boot, watchdog armed"
    "watchdog test: cycle 3 hangs in the CAN driver"
    "watchdog: first expiry \\(NMI\\): the reset follows"
    "watchdog test: second boot, after a reset by the watchdog; cycles fed before it: 3"
    "watchdog test: the first safety frame after the reset is a fresh start \\(counter 0\\), stop requested"
    "watchdog test: passed")
set(rest "${out}")
foreach(pattern IN LISTS expected)
  string(REGEX MATCH "${pattern}" found "${rest}")
  if(NOT found)
    message(FATAL_ERROR "missing, or out of order: '${pattern}'")
  endif()
  string(FIND "${rest}" "${found}" at)
  string(LENGTH "${found}" n)
  math(EXPR at "${at} + ${n}")
  string(SUBSTRING "${rest}" ${at} -1 rest)
endforeach()
string(REGEX MATCH "hangs in the CAN driver[^\n]*\n(.*)watchdog test: second boot" silent "${out}")
if(NOT silent)
  message(FATAL_ERROR "no hang followed by a second boot in the output")
endif()
string(FIND "${CMAKE_MATCH_1}" "can 0x" frame_at)
if(NOT frame_at EQUAL -1)
  message(FATAL_ERROR "a CAN frame was sent between the hang and the reset")
endif()
message(STATUS "the watchdog reset the hung firmware, nothing was sent meanwhile, and the second boot started afresh")
