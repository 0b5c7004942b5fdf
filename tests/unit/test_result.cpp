// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: Result and Status, the return types of every operation that
// can fail on outside input, and the names of their error codes.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>

#include "cellguard/base/result.hpp"
#include "cellguard/safety/zones.hpp"
#include "contract_capture.hpp"
#include "enum_names.hpp"

using namespace cellguard;

// verifies: SR-GEN-004
TEST_CASE("result: every error code has its own name, and a code outside the enumeration is named unknown error") {
    // Stable values (result.hpp: append only): logs and CAN frames carry them.
    CHECK(static_cast<int>(ErrorCode::kOk) == 0);
    CHECK(static_cast<int>(ErrorCode::kUnsupportedType) == 13);
    test::check_enum_names<ErrorCode>(14U, "unknown error");
    CHECK(std::strcmp(to_string(ErrorCode::kOk), "ok") == 0);
    CHECK(std::strcmp(to_string(ErrorCode::kCrcMismatch), "CRC mismatch") == 0);
}

// verifies: SR-GEN-004
TEST_CASE("result: a failed Result holds its code and no value, a successful one its value") {
    const Result<std::int32_t> good(42);
    CHECK(good.ok());
    CHECK(static_cast<bool>(good));
    CHECK(good.error() == ErrorCode::kOk);
    CHECK(good.value() == 42);
    CHECK(good.value_or(7) == 42);

    const Result<std::int32_t> bad(ErrorCode::kCrcMismatch);
    CHECK_FALSE(bad.ok());
    CHECK_FALSE(static_cast<bool>(bad));
    CHECK(bad.error() == ErrorCode::kCrcMismatch);
    CHECK(bad.value_or(7) == 7);
}

// verifies: SR-GEN-003, SR-GEN-004
TEST_CASE("result: reading the value of a failed Result, or failing without a code, violates the contract") {
    const Result<std::int32_t> bad(ErrorCode::kTruncatedInput);
    CHECK(test::violates_contract([&] { (void)bad.value(); }));
    CHECK(test::violates_contract([] {
        const Result<std::int32_t> r(ErrorCode::kOk);
        (void)r;
    }));
    const Result<std::int32_t> good(1);
    CHECK_FALSE(test::violates_contract([&] { (void)good.value(); }));
}

// verifies: SR-GEN-004
TEST_CASE("result: a default Status is success and a Status from a code other than kOk is that failure") {
    constexpr Status success;
    static_assert(success.ok(), "a default Status is success");
    CHECK(static_cast<bool>(success));
    CHECK(success.error() == ErrorCode::kOk);
    constexpr Status failed(ErrorCode::kOutOfGrid);
    static_assert(!failed.ok(), "a Status with an error code is a failure");
    CHECK_FALSE(static_cast<bool>(failed));
    CHECK(failed.error() == ErrorCode::kOutOfGrid);
    CHECK(Status(ErrorCode::kOk).ok());
}

namespace {

/// A value type with no default constructor that counts its live objects.
struct Counted {
    explicit Counted(int v) : value(v) { ++live; }
    Counted(const Counted& o) : value(o.value) { ++live; }
    Counted(Counted&& o) noexcept : value(o.value) { ++live; }
    Counted& operator=(const Counted&) = default;
    Counted& operator=(Counted&&) = default;
    ~Counted() { --live; }
    int value;
    static int live;
};
int Counted::live = 0;

}  // namespace

// verifies: SR-GEN-004
TEST_CASE("result: a Result needs no default-constructed value and destroys exactly what it built") {
    static_assert(!std::is_default_constructible<Counted>::value, "the test type must have no default constructor");
    {
        const Result<Counted> failed = ErrorCode::kMalformedInput;
        CHECK(Counted::live == 0);  // no value was built for the failure
        CHECK(failed.error() == ErrorCode::kMalformedInput);
        Result<Counted> good = Counted(7);
        CHECK(Counted::live == 1);
        Result<Counted> copy = good;
        CHECK(Counted::live == 2);
        CHECK(copy.value().value == 7);
        copy = failed;  // the value is destroyed, the error taken
        CHECK(Counted::live == 1);
        CHECK(copy.error() == ErrorCode::kMalformedInput);
        copy = std::move(good);
        CHECK(Counted::live == 2);  // the moved-from Result keeps its (moved-from) value until it ends
        CHECK(copy.value().value == 7);
        CHECK(copy.value_or(Counted(1)).value == 7);
        CHECK(failed.value_or(Counted(3)).value == 3);
    }
    CHECK(Counted::live == 0);
}

// verifies: SR-GEN-004
TEST_CASE("result: a Result carries a richer error type, and its success reports that type's no-error value") {
    const Result<int, ZoneError> bad = ZoneError{ErrorCode::kOutOfGrid, 3U, "outside"};
    CHECK_FALSE(bad.ok());
    CHECK(bad.error().code == ErrorCode::kOutOfGrid);
    CHECK(bad.error().zone == 3U);
    CHECK(std::string(bad.error().reason) == "outside");
    const Result<int, ZoneError> good = 5;
    CHECK(good.ok());
    CHECK(good.value() == 5);
    CHECK(is_no_error(good.error()));
}

// verifies: SR-GEN-004
TEST_CASE("result: a Result of trivially copyable types is itself trivially copyable, and copies keep value or error") {
    static_assert(std::is_trivially_copyable<Result<std::int32_t>>::value, "byte copies, no branch on the member");
    static_assert(std::is_trivially_copyable<Result<int, ZoneError>>::value, "a richer but plain error type too");
    static_assert(std::is_trivially_destructible<Result<std::int32_t>>::value, "nothing to destroy");
    static_assert(!std::is_trivially_copyable<Result<Counted>>::value, "a counted value is copied by its constructor");
    const Result<std::int32_t> good(9);
    const Result<std::int32_t> bad(ErrorCode::kOutOfGrid);
    Result<std::int32_t> r = bad;
    CHECK(r.error() == ErrorCode::kOutOfGrid);
    r = good;
    CHECK(r.value() == 9);
    r = bad;
    CHECK_FALSE(r.ok());
    CHECK(r.error() == ErrorCode::kOutOfGrid);
}

// verifies: SR-GEN-004
TEST_CASE("result: a Result assigned to itself keeps its value or error and builds or destroys nothing") {
    {
        Result<Counted> good = Counted(4);
        Result<Counted>& alias = good;
        good = alias;
        CHECK(Counted::live == 1);
        CHECK(good.value().value == 4);
        good = std::move(alias);
        CHECK(Counted::live == 1);
        CHECK(good.value().value == 4);
        Result<Counted> bad = ErrorCode::kBadMagic;
        Result<Counted>& bad_alias = bad;
        bad = bad_alias;
        bad = std::move(bad_alias);
        CHECK(bad.error() == ErrorCode::kBadMagic);
        Result<Counted> moved_error(std::move(bad));  // an error moves too
        CHECK(moved_error.error() == ErrorCode::kBadMagic);
        good = std::move(moved_error);  // the value is destroyed, the error taken
        CHECK(Counted::live == 0);
        CHECK(good.error() == ErrorCode::kBadMagic);
    }
    CHECK(Counted::live == 0);
}
