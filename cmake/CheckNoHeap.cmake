# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Fails when the static library LIB references a forbidden symbol: the heap
# (malloc family, operator new/delete), the exception runtime or RTTI.
# Run as: cmake -DNM=<nm> -DLIB=<libcellguard.a> -P CheckNoHeap.cmake
execute_process(COMMAND ${NM} --undefined-only ${LIB}
  OUTPUT_VARIABLE undefined RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${LIB}: ${err}")
endif()
set(forbidden
  "malloc" "calloc" "realloc" "free" "aligned_alloc" "posix_memalign" "memalign" "_sbrk" "sbrk"
  "_Znwm" "_Znam" "_Znwj" "_Znaj" "_ZdlPv" "_ZdaPv" "_ZnwmRKSt9nothrow_t" "_ZnamRKSt9nothrow_t"
  "_ZnwmSt11align_val_t" "_ZdlPvm" "_ZdlPvSt11align_val_t" "_ZdaPvm" "_ZdlPvj" "_ZdaPvj"
  "__cxa_allocate_exception" "__cxa_throw" "__cxa_begin_catch" "__cxa_end_catch" "__cxa_rethrow"
  "__gxx_personality_v0" "_Unwind_Resume" "__dynamic_cast" "_ZTVN10__cxxabiv117__class_type_infoE"
  "_ZTVN10__cxxabiv120__si_class_type_infoE" "__cxa_guard_acquire")
string(REPLACE "\n" ";" lines "${undefined}")
set(found "")
foreach(line IN LISTS lines)
  string(STRIP "${line}" line)
  string(REGEX REPLACE "^U[ \t]+" "" sym "${line}")
  list(FIND forbidden "${sym}" idx)
  if(NOT idx EQUAL -1)
    list(APPEND found "${sym}")
  endif()
endforeach()
if(found)
  list(REMOVE_DUPLICATES found)
  message(FATAL_ERROR "lib/ references forbidden symbols (heap, exceptions or RTTI): ${found}")
endif()
message(STATUS "no-heap check passed: ${LIB}")
