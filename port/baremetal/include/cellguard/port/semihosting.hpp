// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file semihosting.hpp
/// Output and exit through ARM semihosting (bkpt 0xAB): the debugger, or
/// qemu-system-arm with -semihosting, performs the call. No buffering, no
/// heap: SYS_WRITE0 writes a NUL-terminated string, SYS_EXIT ends the run.
/// Only for bring-up and the canned run; a production image has no debugger.
#ifndef CELLGUARD_PORT_SEMIHOSTING_HPP
#define CELLGUARD_PORT_SEMIHOSTING_HPP

namespace cellguard::baremetal {

/// Writes @p text (NUL-terminated) to the host's console (SYS_WRITE0).
void semihosting_write(const char* text) noexcept;

/// Ends the program (SYS_EXIT): reason ADP_Stopped_ApplicationExit when
/// @p success (qemu exits with status 0), ADP_Stopped_RunTimeErrorUnknown
/// otherwise (qemu exits with status 1). Spins if no host answers.
[[noreturn]] void semihosting_exit(bool success) noexcept;

}  // namespace cellguard::baremetal

#endif  // CELLGUARD_PORT_SEMIHOSTING_HPP
