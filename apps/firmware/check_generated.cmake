# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Regenerates the canned inputs into OUT and compares them byte for byte
# with the checked-in copies in REF (prior.cgprior, frames.bin, robot.cgrobot, robot_prior.cgprior, robot_frames.bin). Run as: cmake -DGEN=... [-DEMULATOR=...] -DOUT=... -DREF=... -P check_generated.cmake
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${EMULATOR} ${GEN} ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cellguard-firmware-gen failed: ${rc}")
endif()
foreach(f prior.cgprior frames.bin robot.cgrobot robot_prior.cgprior robot_frames.bin)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/${f} ${REF}/${f} RESULT_VARIABLE diff)
  if(NOT diff EQUAL 0)
    message(FATAL_ERROR "apps/firmware/generated/${f} differs from the generator's output ${OUT}/${f}")
  endif()
endforeach()
message(STATUS "generated inputs match")
