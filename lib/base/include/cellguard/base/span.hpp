// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file span.hpp
/// `Span<T>`: a non-owning view of caller-provided contiguous storage, the way
/// lib/ receives every buffer (C++17 has no std::span). Element access is
/// bounds-checked with CG_ASSERT; `at()` is checked in every build.
#ifndef CELLGUARD_SPAN_HPP
#define CELLGUARD_SPAN_HPP

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "cellguard/base/contract.hpp"

namespace cellguard {

/// A pointer and a length; never owns, never allocates.
template <typename T>
class Span {
public:
    /// An empty span.
    constexpr Span() noexcept = default;
    /// A view of @p size elements starting at @p data (data may be null only if size is 0).
    constexpr Span(T* data, std::size_t size) noexcept : data_(data), size_(size) {}
    /// A view of a C array.
    template <std::size_t N>
    // cppcheck-suppress noExplicitConstructor ; implicit from arrays, like std::span
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit from arrays, like std::span
    constexpr Span(T (&array)[N]) noexcept : data_(array), size_(N) {}
    /// A read-only view of a mutable span (Span<T> to Span<const T>).
    template <typename U, typename = std::enable_if_t<std::is_same<const U, T>::value>>
    // cppcheck-suppress noExplicitConstructor ; implicit from mutable to const, like std::span
    // NOLINTNEXTLINE(google-explicit-constructor,hicpp-explicit-conversions): implicit from mutable to const, like std::span
    constexpr Span(Span<U> other) noexcept : data_(other.data()), size_(other.size()) {}

    /// Number of elements.
    [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
    /// True when there is no element.
    [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0U; }
    /// First element's address (may be null for an empty span).
    [[nodiscard]] constexpr T* data() const noexcept { return data_; }
    /// Element @p i; checked in debug builds only (hot path).
    [[nodiscard]] constexpr T& operator[](std::size_t i) const noexcept {
        CG_ASSERT(i < size_, "Span index out of range");
        return data_[i];
    }
    /// Element @p i; checked in every build.
    [[nodiscard]] constexpr T& at(std::size_t i) const noexcept {
        CG_ENFORCE(i < size_, "Span index out of range");
        return data_[i];
    }
    /// Iterator to the first element.
    [[nodiscard]] constexpr T* begin() const noexcept { return data_; }
    /// Iterator past the last element.
    [[nodiscard]] constexpr T* end() const noexcept { return data_ + size_; }
    /// The sub-view [offset, offset + count); checked in every build.
    [[nodiscard]] constexpr Span subspan(std::size_t offset, std::size_t count) const noexcept {
        CG_ENFORCE(offset <= size_ && count <= size_ - offset, "subspan out of range");
        return Span(data_ + offset, count);
    }

private:
    T* data_ = nullptr;
    std::size_t size_ = 0U;
};

/// The bytes of @p values, read-only: the view a CRC takes of typed storage.
/// Only trivially copyable types have a defined byte image, so only they are accepted.
template <typename T>
[[nodiscard]] Span<const std::uint8_t> as_bytes(Span<T> values) noexcept {
    static_assert(std::is_trivially_copyable<T>::value, "as_bytes needs a trivially copyable type");
    // Reading an object's bytes through unsigned char is always allowed.
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the one byte view of typed storage, for CRCs
    return {reinterpret_cast<const std::uint8_t*>(values.data()), values.size() * sizeof(T)};
}

}  // namespace cellguard

#endif  // CELLGUARD_SPAN_HPP
