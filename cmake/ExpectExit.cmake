# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Runs a host program and checks how it ends: the command-line tests of the
# programs under apps/ (--help, --version, usage errors; SR-GEN-005). Run as
#   cmake -DTOOL=path [-DEMULATOR=a|b] [-DARGS=a|b|c] -DSTATUS=n
#         [-DOUTPUT=regex] [-DVERSION=x.y.z] [-DERROR=text] -P ExpectExit.cmake
# (-D options after -P are not seen).
#   TOOL      the program; its file name (without extension) is the program name
#   EMULATOR  a cross build's emulator command, '|'-separated (optional)
#   ARGS      the arguments, '|'-separated (optional)
#   STATUS    the exact exit status expected
#   OUTPUT    a regex stdout must match (optional)
#   VERSION   stdout must be exactly "<program> <VERSION>" and a newline (optional)
#   ERROR     text stderr must hold (optional); its first line must then start
#             with "<program>: " and stdout must be empty. Without ERROR,
#             stderr must be empty.
string(REPLACE "|" ";" args "${ARGS}")
string(REPLACE "|" ";" emulator "${EMULATOR}")
get_filename_component(program "${TOOL}" NAME_WE)
execute_process(COMMAND ${emulator} ${TOOL} ${args} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(report "${program} ${ARGS}: exit status '${status}'\nstdout:\n${out}\nstderr:\n${err}")
if(NOT "${status}" STREQUAL "${STATUS}")
  message(FATAL_ERROR "expected exit status ${STATUS}; ${report}")
endif()
if(DEFINED OUTPUT AND NOT out MATCHES "${OUTPUT}")
  message(FATAL_ERROR "stdout does not match '${OUTPUT}'; ${report}")
endif()
if(DEFINED VERSION AND NOT out STREQUAL "${program} ${VERSION}\n")
  message(FATAL_ERROR "stdout is not the line '${program} ${VERSION}'; ${report}")
endif()
if(DEFINED ERROR)
  string(FIND "${err}" "${ERROR}" at)
  if(at LESS 0)
    message(FATAL_ERROR "stderr does not hold '${ERROR}'; ${report}")
  endif()
  string(FIND "${err}" "${program}: " prefix_at)
  if(NOT prefix_at EQUAL 0 OR NOT out STREQUAL "")
    message(FATAL_ERROR "a usage error goes to stderr only, starting with '${program}: '; ${report}")
  endif()
elseif(NOT err STREQUAL "")
  message(FATAL_ERROR "stderr is not empty; ${report}")
endif()
message(STATUS "${program} ${ARGS}: exit ${status} as expected")
