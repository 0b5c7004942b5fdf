# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Fails when the program or library FILE holds a symbol whose demangled name
# matches the regex PATTERN (defined or referenced): a link-time proof that a
# program does not carry code it must not use.
# Run as: cmake -DNM=<nm> -DFILE=<binary> -DPATTERN=<regex> -P CheckNoSymbol.cmake
execute_process(COMMAND ${NM} -C ${FILE} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${FILE}: ${err}")
endif()
string(REGEX MATCH "[^\n]*(${PATTERN})[^\n]*" hit "${symbols}")
if(hit)
  message(FATAL_ERROR "${FILE} holds a symbol matching '${PATTERN}': ${hit}")
endif()
message(STATUS "no symbol matching '${PATTERN}' in ${FILE}")
