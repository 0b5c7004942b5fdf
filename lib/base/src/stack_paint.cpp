// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/stack_paint.hpp"

#include "cellguard/base/contract.hpp"

namespace cellguard {

StackPaint::StackPaint(Span<std::uint32_t> region, std::size_t guard_words) noexcept
    : region_(region), guard_words_(guard_words) {
    CG_ENFORCE(guard_words <= region.size(), "the guard band lies inside the painted region");
}

void StackPaint::paint() noexcept {
    volatile std::uint32_t* const words = region_.data();
    for (std::size_t i = 0U; i < region_.size(); ++i) {
        words[i] = kStackPaintWord;  // NOLINT(cppcoreguidelines-pro-bounds-pointer-arithmetic): i < the region's size
    }
}

bool StackPaint::guard_intact() const noexcept {
    const volatile std::uint32_t* const words = region_.data();
    bool intact = true;
    for (std::size_t i = 0U; i < guard_words_; ++i) {
        // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): i < guard_words_ <= the region's size
        intact = intact && words[i] == kStackPaintWord;
    }
    return intact;
}

std::size_t StackPaint::high_water_bytes() const noexcept {
    const volatile std::uint32_t* const words = region_.data();
    std::size_t untouched = 0U;
    // NOLINTNEXTLINE(cppcoreguidelines-pro-bounds-pointer-arithmetic): untouched < the region's size
    while (untouched < region_.size() && words[untouched] == kStackPaintWord) {
        ++untouched;
    }
    return (region_.size() - untouched) * sizeof(std::uint32_t);
}

}  // namespace cellguard
