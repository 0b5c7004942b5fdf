// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/io_status.hpp"

#include <cstdarg>
#include <cstdio>

namespace cellguard {

// NOLINTNEXTLINE(cert-dcl50-cpp): printf-style so that the compiler checks each format (format attribute)
IoStatus IoStatus::failure(ErrorCode code, const char* format, ...) noexcept {
    CG_ENFORCE(code != ErrorCode::kOk, "a failed IoStatus needs an error code");
    IoStatus result;
    result.error_ = code;
    std::va_list args;
    va_start(args, format);
    // NOLINTNEXTLINE(clang-diagnostic-format-nonliteral): the format is checked at each caller (format attribute)
    const int n = std::vsnprintf(result.message_, kMessageCapacity, format, args);
    va_end(args);
    if (n < 0) {
        result.message_[0] = '\0';
    }
    return result;
}

IoStatus IoStatus::prefixed(const char* prefix) const noexcept {
    if (ok()) {
        return *this;
    }
    return failure(error_, "%s: %s", prefix, message_);
}

}  // namespace cellguard
