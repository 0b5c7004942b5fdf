/// @file result.hpp
/// Error codes and `Result<T>`, the return type of every operation that can
/// fail on input from outside (a frame, a config, a prior image, a CAN frame).
///
/// `Result<T>` holds either a value or an `ErrorCode`, never both, and is
/// `[[nodiscard]]`: a caller cannot drop an error silently. It needs no heap
/// and no exceptions; `T` must be default-constructible and copyable (the
/// types lib/ returns this way are small value types).
#ifndef CELLGUARD_RESULT_HPP
#define CELLGUARD_RESULT_HPP

#include <cstdint>
#include <utility>

#include "cellguard/contract.hpp"

namespace cellguard {

/// Every recoverable error of lib/. Values are stable: they appear in logs,
/// in the diagnostics CAN frame and in the certification pack. Append only.
enum class ErrorCode : std::uint16_t {
    kOk = 0,                   ///< no error (never stored in a failed Result)
    kInvalidArgument = 1,      ///< a parameter is outside its documented range
    kCapacityExceeded = 2,     ///< more items than the compile-time capacity
    kStorageTooSmall = 3,      ///< caller-provided storage does not fit the grid
    kGeometryMismatch = 4,     ///< grid geometry differs from the expected one
    kTruncatedInput = 5,       ///< input ends before its declared size
    kBadMagic = 6,             ///< input does not start with the expected magic
    kUnsupportedVersion = 7,   ///< a format version this build cannot read
    kCrcMismatch = 8,          ///< checksum over the input does not match
    kMalformedInput = 9,       ///< input is structurally wrong (bad field)
    kSensorIndexOutOfRange = 10,  ///< a sensor id beyond the configured sensors
    kNonFiniteValue = 11,      ///< NaN or infinity where a finite number is needed
    kOutOfGrid = 12,           ///< a position or box outside the grid
    kUnsupportedType = 13,     ///< a field type or layout this build cannot read
};

/// A short, static, human-readable name for @p code (never nullptr).
const char* to_string(ErrorCode code) noexcept;

/// Either a value of type T or an error code. Constructed from a T (success)
/// or from an ErrorCode other than kOk (failure).
template <typename T>
class [[nodiscard]] Result {
public:
    /// A successful result holding @p value.
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    Result(T value) noexcept : value_(std::move(value)), error_(ErrorCode::kOk) {}  // NOLINT(google-explicit-constructor,hicpp-explicit-conversions): implicit by design, like std::expected
    /// A failed result; @p error must not be kOk (contract).
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    Result(ErrorCode error) noexcept : value_(), error_(error) {  // NOLINT(google-explicit-constructor,hicpp-explicit-conversions): implicit by design
        CG_ENFORCE(error != ErrorCode::kOk, "a failed Result needs an error code");
    }

    /// True when the result holds a value.
    [[nodiscard]] bool ok() const noexcept { return error_ == ErrorCode::kOk; }
    /// Same as ok().
    explicit operator bool() const noexcept { return ok(); }
    /// The error code; kOk when the result holds a value.
    [[nodiscard]] ErrorCode error() const noexcept { return error_; }
    /// The value; calling it on a failed result is a contract violation.
    [[nodiscard]] const T& value() const noexcept {
        CG_ENFORCE(ok(), "value() of a failed Result");
        return value_;
    }
    /// The value, or @p fallback when the result failed.
    [[nodiscard]] T value_or(const T& fallback) const noexcept { return ok() ? value_ : fallback; }

private:
    T value_;
    ErrorCode error_;
};

/// The result of an operation that returns nothing but may fail.
class [[nodiscard]] Status {
public:
    /// Success.
    constexpr Status() noexcept = default;
    /// Failure with @p error (kOk means success).
    // cppcheck-suppress noExplicitConstructor ; implicit by design, like std::expected
    constexpr Status(ErrorCode error) noexcept : error_(error) {}  // NOLINT(google-explicit-constructor,hicpp-explicit-conversions): implicit by design
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
