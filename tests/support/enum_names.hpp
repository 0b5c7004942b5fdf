// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Checks the to_string of an enumeration whose values run 0 .. count - 1:
// every value has a non-empty name of its own, and values outside the
// enumeration (as from a corrupted frame or log) get the fallback name.
#ifndef CELLGUARD_TESTS_ENUM_NAMES_HPP
#define CELLGUARD_TESTS_ENUM_NAMES_HPP

#include <doctest/doctest.h>

#include <cstddef>
#include <cstring>
#include <limits>
#include <type_traits>

namespace cellguard::test {

/// CHECKs that to_string(E(0)) .. to_string(E(count - 1)) are non-empty,
/// pairwise different and not @p fallback, and that E(count) and the
/// largest value of E's underlying type are named @p fallback.
template <typename E>
void check_enum_names(std::size_t count, const char* fallback) {
    using U = std::underlying_type_t<E>;
    for (std::size_t i = 0; i < count; ++i) {
        CAPTURE(i);
        const char* name = to_string(static_cast<E>(static_cast<U>(i)));
        REQUIRE(name != nullptr);
        CHECK(std::strlen(name) > 0U);
        CHECK(std::strcmp(name, fallback) != 0);
        for (std::size_t j = 0; j < i; ++j) {
            CHECK(std::strcmp(name, to_string(static_cast<E>(static_cast<U>(j)))) != 0);
        }
    }
    CHECK(std::strcmp(to_string(static_cast<E>(static_cast<U>(count))), fallback) == 0);
    CHECK(std::strcmp(to_string(static_cast<E>(std::numeric_limits<U>::max())), fallback) == 0);
}

}  // namespace cellguard::test

#endif
