# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# The SoC: aarch64 Linux, cross-compiled with g++-aarch64-linux-gnu; ctest
# runs the test binaries under qemu-user (tools/install-deps.sh --cross).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# -E LD_LIBRARY_PATH: the cross toolchain's own libc beside its loader. With
# libc6:arm64 installed (libpng-dev:arm64, tools/install-deps.sh --cross),
# ld.so.cache otherwise gives the loader of libc6-arm64-cross a libc of
# another build, and the first pthread_create hangs (the WorkerPool tests).
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64;-L;/usr/aarch64-linux-gnu;-E;LD_LIBRARY_PATH=/usr/aarch64-linux-gnu/lib)
# Libraries and headers of the target only from its sysroot; host-only
# packages (OctoMap, tomlplusplus) are then not found and their users skipped.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)
