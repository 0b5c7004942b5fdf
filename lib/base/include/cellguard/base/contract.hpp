// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file contract.hpp
/// Contract checks for programmer errors, routed through one error handler.
///
/// Two kinds of check, as in iceoryx_hoofs:
/// - CG_ENFORCE(cond, msg): always on, in every build type. For preconditions
///   whose violation would corrupt memory or safety state (an index out of the
///   grid, storage of the wrong size).
/// - CG_ASSERT(cond, msg): debug builds only (compiled out with NDEBUG). For
///   internal invariants that are too expensive to check on the hot path.
///
/// Recoverable errors (bad input from outside) are never contract violations:
/// they are returned as `Result` values (see result.hpp). A contract violation
/// means the program itself is wrong; the handler must not return. The default
/// handler traps (`__builtin_trap`), which on a controller leads to the
/// watchdog and the PLC's timeout, i.e. the safe state. Tests install their
/// own handler to observe violations.
#ifndef CELLGUARD_CONTRACT_HPP
#define CELLGUARD_CONTRACT_HPP

namespace cellguard {

/// Where and why a contract was violated; the strings are static literals.
struct ContractViolation {
    const char* file;       ///< source file of the failed check
    int line;               ///< source line of the failed check
    const char* condition;  ///< the checked expression, as text
    const char* message;    ///< what the caller did wrong
};

/// Signature of a contract-violation handler. A handler must not return to
/// the failed check; if it does, the check traps anyway.
using ContractHandler = void (*)(const ContractViolation& violation);

/// Installs @p handler (nullptr restores the default, which traps) and returns
/// the previous one. Not thread-safe: set it once at start-up or in a test.
ContractHandler set_contract_handler(ContractHandler handler) noexcept;

/// Reports a violation to the installed handler and never returns.
[[noreturn]] void contract_violated(const char* file, int line, const char* condition, const char* message) noexcept;

}  // namespace cellguard

/// Always-on contract check: reports and does not return when @p cond is false.
#define CG_ENFORCE(cond, msg)                                                 \
    do {                                                                      \
        if (!(cond)) {                                                        \
            ::cellguard::contract_violated(__FILE__, __LINE__, #cond, (msg)); \
        }                                                                     \
    } while (false)

#ifdef NDEBUG
/// Debug-only contract check; compiled out with NDEBUG (the condition is not evaluated).
#define CG_ASSERT(cond, msg) \
    do {                     \
        (void)sizeof(cond);  \
    } while (false)
#else
/// Debug-only contract check; compiled out with NDEBUG.
#define CG_ASSERT(cond, msg) CG_ENFORCE(cond, msg)
#endif

#endif  // CELLGUARD_CONTRACT_HPP
