// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/contract.hpp"

namespace cellguard {
namespace {
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): the one error handler, set at start-up
ContractHandler g_handler = nullptr;
}  // namespace

ContractHandler set_contract_handler(ContractHandler handler) noexcept {
    const ContractHandler previous = g_handler;
    g_handler = handler;
    return previous;
}

void contract_violated(const char* file, int line, const char* condition, const char* message) noexcept {
    if (g_handler != nullptr) {
        g_handler(ContractViolation{file, line, condition, message});
    }
    // A handler that returns, or none installed: stop here. No OS call in lib/.
    __builtin_trap();
}

}  // namespace cellguard
