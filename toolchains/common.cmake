# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# Settings shared by every cellguard target (included by each toolchain file).
#
# Bit-identical results across targets: no fused multiply-add contraction
# (aarch64 and Cortex-M7 have FMA instructions, x86-64 without -mfma does
# not), so every target rounds each product and sum the same way.
set(CMAKE_C_FLAGS_INIT "-ffp-contract=off")
set(CMAKE_CXX_FLAGS_INIT "-ffp-contract=off")

# Header-only, architecture-independent packages come from the host:
# Eigen and doctest are found through their CMake configs in /usr.
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Eigen3 config (header-only, host copy)")
set(doctest_DIR /usr/lib/cmake/doctest CACHE PATH "doctest config (header-only, host copy)")
