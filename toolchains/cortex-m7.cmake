# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The safety MCU: Cortex-M7 with double-precision FPU, bare metal
# (arm-none-eabi g++ with newlib's libstdc++). Only lib/ and the firmware
# (port/baremetal, apps/firmware) are built: no tests, benchmarks or host apps.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR cortex-m7)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CELLGUARD_MCU_FLAGS "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb")
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)
string(APPEND CMAKE_C_FLAGS_INIT " ${CELLGUARD_MCU_FLAGS} -ffunction-sections -fdata-sections")
string(APPEND CMAKE_CXX_FLAGS_INIT
       " ${CELLGUARD_MCU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${CELLGUARD_MCU_FLAGS} -Wl,--gc-sections")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CELLGUARD_BUILD_TESTS OFF CACHE BOOL "no unit tests on the MCU")
set(CELLGUARD_BUILD_APPS OFF CACHE BOOL "no host programs on the MCU")
set(CELLGUARD_BUILD_BENCH OFF CACHE BOOL "no benchmarks on the MCU")
