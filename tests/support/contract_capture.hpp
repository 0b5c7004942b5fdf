// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Observes contract violations in tests: runs a callable with a handler that
// records the violation and jumps back instead of trapping.
#ifndef CELLGUARD_TESTS_CONTRACT_CAPTURE_HPP
#define CELLGUARD_TESTS_CONTRACT_CAPTURE_HPP

#include <csetjmp>

#include "cellguard/base/contract.hpp"

namespace cellguard::test {

namespace detail {
inline std::jmp_buf& jump_buffer() {
    static std::jmp_buf buffer;
    return buffer;
}
inline const char*& last_message() {
    static const char* message = nullptr;
    return message;
}
[[noreturn]] inline void jumping_handler(const ContractViolation& v) {
    last_message() = v.message;
    std::longjmp(jump_buffer(), 1);
}
}  // namespace detail

/// True when @p f violates a contract (CG_ENFORCE or, in debug builds,
/// CG_ASSERT). Only for callables whose locals are trivially destructible.
template <typename F>
bool violates_contract(F&& f) {
    const ContractHandler previous = set_contract_handler(&detail::jumping_handler);
    bool violated = false;
    if (setjmp(detail::jump_buffer()) == 0) {
        f();
    } else {
        violated = true;
    }
    set_contract_handler(previous);
    return violated;
}

}  // namespace cellguard::test

#endif
