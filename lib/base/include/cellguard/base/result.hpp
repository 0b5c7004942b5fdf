// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file result.hpp
/// Error codes and `Result<T>`, the return type of every operation that can
/// fail on input from outside (a frame, a config, a prior image, a CAN frame).
///
/// `Result<T>` holds either a value or an `ErrorCode`, never both, and is
/// `[[nodiscard]]`: a caller cannot drop an error silently. It needs no heap
/// and no exceptions, and no default-constructible `T`: the value is built in
/// place only on success. `Result<T, E>` carries a richer error type E where
/// an operation has one (zones.hpp's ZoneError).
#ifndef CELLGUARD_RESULT_HPP
#define CELLGUARD_RESULT_HPP

#include <cstdint>
#include <new>
#include <utility>

#include "cellguard/base/contract.hpp"

namespace cellguard {

/// Every recoverable error of lib/. Values are stable: they appear in logs,
/// in the diagnostics CAN frame and in the certification pack. Append only.
enum class ErrorCode : std::uint16_t {
    kOk = 0,                      ///< no error (never stored in a failed Result)
    kInvalidArgument = 1,         ///< a parameter is outside its documented range
    kCapacityExceeded = 2,        ///< more items than the compile-time capacity
    kStorageTooSmall = 3,         ///< caller-provided storage does not fit the grid
    kGeometryMismatch = 4,        ///< grid geometry differs from the expected one
    kTruncatedInput = 5,          ///< input ends before its declared size
    kBadMagic = 6,                ///< input does not start with the expected magic
    kUnsupportedVersion = 7,      ///< a format version this build cannot read
    kCrcMismatch = 8,             ///< checksum over the input does not match
    kMalformedInput = 9,          ///< input is structurally wrong (bad field)
    kSensorIndexOutOfRange = 10,  ///< a sensor id beyond the configured sensors
    kNonFiniteValue = 11,         ///< NaN or infinity where a finite number is needed
    kOutOfGrid = 12,              ///< a position or box outside the grid
    kUnsupportedType = 13,        ///< a field type or layout this build cannot read
};

/// A short, static, human-readable name for @p code (never nullptr).
const char* to_string(ErrorCode code) noexcept;

/// True when @p code means "no error": the check every error type of a
/// Result provides, found by argument-dependent lookup.
constexpr bool is_no_error(ErrorCode code) noexcept { return code == ErrorCode::kOk; }

/// Either a value of type T or an error of type E (ErrorCode unless an
/// operation has a richer error, such as zones.hpp's ZoneError), never both.
/// T needs no default constructor: the value is constructed only on success
/// (iceoryx's `expected` is the model). Constructed from a T (success) or
/// from an E that is not "no error" (is_no_error(E) false; a contract).
template <typename T, typename E = ErrorCode>
class [[nodiscard]] Result {
public:
    /// A successful result holding @p value.
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit by design, like std::expected
    Result(T value) noexcept : ok_(true) { construct_value(std::move(value)); }
    /// A failed result; @p error must not be "no error" (contract).
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit by design
    Result(E error) noexcept : ok_(false) {
        CG_ENFORCE(!is_no_error(error), "a failed Result needs an error");
        construct_error(std::move(error));
    }
    /// A copy of @p other.
    Result(const Result& other) noexcept : ok_(other.ok_) {
        if (ok_) {
            construct_value(other.storage_.value);
        } else {
            construct_error(other.storage_.error);
        }
    }
    /// Takes @p other's value or error.
    Result(Result&& other) noexcept : ok_(other.ok_) {
        if (ok_) {
            construct_value(std::move(other.storage_.value));
        } else {
            construct_error(std::move(other.storage_.error));
        }
    }
    /// Becomes a copy of @p other.
    Result& operator=(const Result& other) noexcept {
        if (this != &other) {
            destroy();
            ok_ = other.ok_;
            if (ok_) {
                construct_value(other.storage_.value);
            } else {
                construct_error(other.storage_.error);
            }
        }
        return *this;
    }
    /// Takes @p other's value or error.
    Result& operator=(Result&& other) noexcept {
        if (this != &other) {
            destroy();
            ok_ = other.ok_;
            if (ok_) {
                construct_value(std::move(other.storage_.value));
            } else {
                construct_error(std::move(other.storage_.error));
            }
        }
        return *this;
    }
    /// Destroys the value or the error.
    ~Result() { destroy(); }

    /// True when the result holds a value.
    [[nodiscard]] bool ok() const noexcept { return ok_; }
    /// Same as ok().
    explicit operator bool() const noexcept { return ok(); }
    /// The error; E's "no error" value (E{}, kOk for ErrorCode) when the result holds a value.
    [[nodiscard]] E error() const noexcept { return ok_ ? E{} : storage_.error; }
    /// The value; calling it on a failed result is a contract violation.
    [[nodiscard]] const T& value() const noexcept {
        CG_ENFORCE(ok(), "value() of a failed Result");
        return storage_.value;
    }
    /// The value, or @p fallback when the result failed.
    [[nodiscard]] T value_or(const T& fallback) const noexcept { return ok_ ? storage_.value : fallback; }

private:
    /// The value or the error, constructed in place: no default T is needed.
    union Storage {
        // NOLINTNEXTLINE(modernize-use-equals-default,hicpp-use-equals-default): a union with non-trivial members needs it user-provided
        Storage() noexcept {}
        // NOLINTNEXTLINE(modernize-use-equals-default,hicpp-use-equals-default): the Result destroys the active member
        ~Storage() {}
        Storage(const Storage&) = delete;
        Storage& operator=(const Storage&) = delete;
        Storage(Storage&&) = delete;
        Storage& operator=(Storage&&) = delete;
        T value;  ///< active when ok_
        E error;  ///< active when !ok_
    };
    template <typename U>
    void construct_value(U&& v) noexcept {
        ::new (static_cast<void*>(&storage_.value)) T(std::forward<U>(v));  // placement: no allocation
    }
    template <typename U>
    void construct_error(U&& e) noexcept {
        ::new (static_cast<void*>(&storage_.error)) E(std::forward<U>(e));  // placement: no allocation
    }
    void destroy() noexcept {
        if (ok_) {
            storage_.value.~T();
        } else {
            storage_.error.~E();
        }
    }
    Storage storage_;
    bool ok_;
};

/// The result of an operation that returns nothing but may fail.
class [[nodiscard]] Status {
public:
    /// Success.
    constexpr Status() noexcept = default;
    /// Failure with @p error (kOk means success).
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit by design
    constexpr Status(ErrorCode error) noexcept : error_(error) {}
    /// True on success.
    [[nodiscard]] constexpr bool ok() const noexcept { return error_ == ErrorCode::kOk; }
    /// Same as ok().
    constexpr explicit operator bool() const noexcept { return ok(); }
    /// The error code; kOk on success.
    [[nodiscard]] constexpr ErrorCode error() const noexcept { return error_; }

private:
    ErrorCode error_ = ErrorCode::kOk;
};

}  // namespace cellguard

#endif  // CELLGUARD_RESULT_HPP
