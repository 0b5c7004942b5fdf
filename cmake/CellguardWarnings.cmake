# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Warning flags shared by every target: gcc and clang both build warning-free.
# They are build-only: linked PRIVATE (lib/ through $<BUILD_INTERFACE:...>),
# never part of the installed package.
#
# -Werror: on by default when cellguard is the top-level project (tools/*.sh,
# .ci/run and CMakePresets.json also set it explicitly), off by default when
# a consumer builds cellguard with add_subdirectory, so that a newer compiler's
# new warning does not break someone else's build.
option(CELLGUARD_WERROR "Treat warnings as errors" ${PROJECT_IS_TOP_LEVEL})
set(cellguard_werror "")
if(CELLGUARD_WERROR)
  set(cellguard_werror -Werror)
endif()
add_library(cellguard_warnings INTERFACE)
target_compile_options(cellguard_warnings INTERFACE
  -Wall -Wextra -Wpedantic ${cellguard_werror} -Wshadow -Wnon-virtual-dtor -Wcast-align
  -Woverloaded-virtual -Wnull-dereference -Wformat=2)
# lib/ and port/ also convert nothing silently.
add_library(cellguard_strict_warnings INTERFACE)
target_link_libraries(cellguard_strict_warnings INTERFACE cellguard_warnings)
target_compile_options(cellguard_strict_warnings INTERFACE -Wconversion -Wsign-conversion -Wold-style-cast -Wdouble-promotion)
# Coverage instrumentation. Atomic counters: the worker pool's tests run lib/
# code on several threads, and plain counters then race (gcov reads negative
# branch counts).
set(cellguard_coverage_flags --coverage -fprofile-update=atomic)
if(CELLGUARD_COVERAGE)  # everything, at -O0 (the coverage-o0 preset)
  add_compile_options(${cellguard_coverage_flags} -O0)
  add_link_options(--coverage)
endif()
# lib/ only (CELLGUARD_LIB_COVERAGE, the coverage preset, tools/evidence.sh):
# linked by lib/'s modules (cellguard_lib_flags) and the unit tests, which
# compile lib/'s inline header functions; the host code the tests also run
# (the simulator, the monitor) is not instrumented. Empty otherwise.
add_library(cellguard_lib_coverage INTERFACE)
if(CELLGUARD_LIB_COVERAGE)
  target_compile_options(cellguard_lib_coverage INTERFACE ${cellguard_coverage_flags})
endif()
