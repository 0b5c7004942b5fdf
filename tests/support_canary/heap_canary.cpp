// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A deliberately heap-using translation unit: the no-heap check must reject it.
#include <cstdlib>
void* cellguard_heap_canary(std::size_t n) { return std::malloc(n); }  // NOLINT: the point of the canary
