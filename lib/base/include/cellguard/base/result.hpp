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
#include <type_traits>
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

namespace result_detail {

/// True when a Result of T and E may be copied byte for byte and needs no
/// destruction: then its copy, move and destructor are the compiler's
/// trivial ones, which neither branch on the active member nor call anything.
template <typename T, typename E>
struct TriviallyCopyable
    : std::bool_constant<std::is_trivially_copyable<T>::value && std::is_trivially_copyable<E>::value> {};

/// The value or the error, constructed in place: no default T is needed.
/// `none` is active until a Result constructs one of the two. Its copy and
/// destructor are trivial when T and E are trivially copyable.
template <typename T, typename E, bool = TriviallyCopyable<T, E>::value>
union Storage {
    Storage() noexcept : none() {}
    char none;  ///< active only until the value or the error is constructed
    T value;    ///< active when the Result holds a value
    E error;    ///< active when the Result holds an error
};

/// Storage for a T or E that is not trivially copyable: the owning
/// Result copies, moves and destroys the active member itself.
template <typename T, typename E>
union Storage<T, E, false> {
    Storage() noexcept : none() {}
    // NOLINTNEXTLINE(modernize-use-equals-default,hicpp-use-equals-default): the Result destroys the active member
    ~Storage() {}
    Storage(const Storage&) = delete;
    Storage& operator=(const Storage&) = delete;
    Storage(Storage&&) = delete;
    Storage& operator=(Storage&&) = delete;
    char none;  ///< active only until the value or the error is constructed
    T value;    ///< active when the Result holds a value
    E error;    ///< active when the Result holds an error
};

/// The storage, the flag and the in-place construction every Result shares;
/// its copy, move and destructor are trivial (trivially copyable T and E).
template <typename T, typename E>
class Core {
protected:
    template <typename U>
    void construct_value(U&& v) noexcept {
        ::new (static_cast<void*>(&storage_.value)) T(std::forward<U>(v));  // placement: no allocation
        ok_ = true;
    }
    template <typename U>
    void construct_error(U&& e) noexcept {
        ::new (static_cast<void*>(&storage_.error)) E(std::forward<U>(e));  // placement: no allocation
        ok_ = false;
    }
    Storage<T, E> storage_;  ///< the value when ok_, else the error
    bool ok_ = false;        ///< which member of storage_ is active
};

/// Copy, move and destruction of the active member, for a T or E that is
/// not trivially copyable (the branch on ok_ is needed only here).
template <typename T, typename E, bool = TriviallyCopyable<T, E>::value>
class Base : public Core<T, E> {};

/// See the primary template.
template <typename T, typename E>
class Base<T, E, false> : public Core<T, E> {
protected:
    Base() noexcept = default;
    Base(const Base& other) noexcept : Core<T, E>() { take(other); }
    Base(Base&& other) noexcept : Core<T, E>() { take(std::move(other)); }
    Base& operator=(const Base& other) noexcept {
        if (this != &other) {
            destroy();
            take(other);
        }
        return *this;
    }
    Base& operator=(Base&& other) noexcept {
        if (this != &other) {
            destroy();
            take(std::move(other));
        }
        return *this;
    }
    ~Base() { destroy(); }

private:
    template <typename B>
    void take(B&& other) noexcept {
        if (other.ok_) {
            this->construct_value(std::forward<B>(other).storage_.value);
        } else {
            this->construct_error(std::forward<B>(other).storage_.error);
        }
    }
    void destroy() noexcept {
        if (this->ok_) {
            this->storage_.value.~T();
        } else {
            this->storage_.error.~E();
        }
    }
};

}  // namespace result_detail

/// Either a value of type T or an error of type E (ErrorCode unless an
/// operation has a richer error, such as zones.hpp's ZoneError), never both.
/// T needs no default constructor: the value is constructed only on success
/// (iceoryx's `expected` is the model). Constructed from a T (success) or
/// from an E that is not "no error" (is_no_error(E) false; a contract).
/// Trivially copyable when T and E are (result_detail::TriviallyCopyable).
template <typename T, typename E = ErrorCode>
class [[nodiscard]] Result : private result_detail::Base<T, E> {
public:
    /// A successful result holding @p value.
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit by design, like std::expected
    Result(T value) noexcept { this->construct_value(std::move(value)); }
    /// A failed result; @p error must not be "no error" (contract).
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit by design
    Result(E error) noexcept {
        CG_ENFORCE(!is_no_error(error), "a failed Result needs an error");
        this->construct_error(std::move(error));
    }

    /// True when the result holds a value.
    [[nodiscard]] bool ok() const noexcept { return this->ok_; }
    /// Same as ok().
    explicit operator bool() const noexcept { return ok(); }
    /// The error; E's "no error" value (E{}, kOk for ErrorCode) when the result holds a value.
    [[nodiscard]] E error() const noexcept { return this->ok_ ? E{} : this->storage_.error; }
    /// The value; calling it on a failed result is a contract violation.
    [[nodiscard]] const T& value() const noexcept {
        CG_ENFORCE(ok(), "value() of a failed Result");
        return this->storage_.value;
    }
    /// The value, or @p fallback when the result failed.
    [[nodiscard]] T value_or(const T& fallback) const noexcept { return this->ok_ ? this->storage_.value : fallback; }
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
