// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file io_status.hpp
/// `IoStatus`: the result of reading or writing a host-side file (.npy,
/// .pcd): an ErrorCode plus a human-readable message such as
/// "pcd: line 4: FIELDS has 4 names but SIZE has 3".
///
/// The message lives in a fixed buffer inside the object, so making an error
/// never allocates and never throws; a longer message is cut at
/// kMessageCapacity - 1 characters (512 bytes: room for a file path of a
/// deep checkout in front of a message that ends with its advice or a list
/// of names).
#ifndef CELLGUARD_HOST_IO_IO_STATUS_HPP
#define CELLGUARD_HOST_IO_IO_STATUS_HPP

#include <cstddef>

#include "cellguard/base/result.hpp"

namespace cellguard {

/// Success, or an ErrorCode with a message that says what was wrong and where.
class [[nodiscard]] IoStatus {
public:
    /// Capacity of the message buffer, terminating NUL included.
    static constexpr std::size_t kMessageCapacity = 512;

    /// Success (empty message).
    IoStatus() noexcept = default;

    /// A failure with @p code (must not be kOk: contract) and a printf-style
    /// message, cut to kMessageCapacity - 1 characters.
    // NOLINTNEXTLINE(cert-dcl50-cpp): printf-style, checked by the format attribute
    static IoStatus failure(ErrorCode code, const char* format, ...) noexcept __attribute__((format(printf, 2, 3)));

    /// The same failure with "@p prefix: " put in front of the message (used
    /// to add a file name); success stays success.
    [[nodiscard]] IoStatus prefixed(const char* prefix) const noexcept;

    /// True on success.
    [[nodiscard]] bool ok() const noexcept { return error_ == ErrorCode::kOk; }
    /// Same as ok().
    explicit operator bool() const noexcept { return ok(); }
    /// The error code; kOk on success.
    [[nodiscard]] ErrorCode error() const noexcept { return error_; }
    /// The message; "" on success, never nullptr.
    [[nodiscard]] const char* message() const noexcept { return message_; }
    /// The code alone, as the lib/ Status.
    [[nodiscard]] Status status() const noexcept { return {error_}; }

private:
    ErrorCode error_ = ErrorCode::kOk;
    char message_[kMessageCapacity] = {};
};

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_IO_STATUS_HPP
