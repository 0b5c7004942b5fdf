// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// An image that links the allocator, for the test that the firmware's ELF
// check (check_elf.cmake) rejects it: never part of the firmware.
#include <cstddef>
#include <cstdlib>

extern "C" void* cellguard_firmware_heap_canary(std::size_t bytes) noexcept;

extern "C" void* cellguard_firmware_heap_canary(std::size_t bytes) noexcept {
    return std::malloc(bytes);  // NOLINT(cppcoreguidelines-no-malloc,hicpp-no-malloc): the point of the canary
}
