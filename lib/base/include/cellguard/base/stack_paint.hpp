// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file stack_paint.hpp
/// Stack painting with a guard band (hazard H-MEM-3, the stack): the
/// portable, pure part. A port (port/linux and port/baremetal, each
/// `cellguard/port/stack.hpp`) finds the region of the cycle thread's stack
/// that lies below the frames in use, as words, lowest address first, and
/// hands it to a StackPaint, which fills it with kStackPaintWord. The stack
/// grows down: its deepest use overwrites the region from the top. The
/// lowest guard_words words are the guard band:
/// - guard_intact(): every guard word still holds the pattern. The
///   controller asks once per cycle (ControllerConfig::stack); a stack that
///   reached into the band is kInternalCheck, non-recoverable. Work:
///   guard_words volatile reads.
/// - high_water_bytes(): the deepest use so far, measured from the region's
///   top down to the lowest word that no longer holds the pattern. Work: a
///   scan of the region (for summaries, not for every cycle).
/// A word the program happens to write with the pattern's value is taken as
/// unused: the mark can read low by such words, never high. Every access is
/// volatile: the region is no object of the program. No heap, no OS call.
#ifndef CELLGUARD_STACK_PAINT_HPP
#define CELLGUARD_STACK_PAINT_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/span.hpp"

namespace cellguard {

/// The paint pattern: unlikely as data, an address or a small integer.
constexpr std::uint32_t kStackPaintWord = 0xC57AC4EDU;

/// See the file comment. Holds a view of the region; no heap.
class StackPaint {
public:
    /// No region: nothing painted, the guard is always intact, the mark 0.
    StackPaint() noexcept = default;

    /// A view of @p region (lowest address first) whose lowest
    /// @p guard_words words (<= region.size(): contract) are the guard band.
    /// Nothing is written until paint().
    StackPaint(Span<std::uint32_t> region, std::size_t guard_words) noexcept;

    /// Writes kStackPaintWord into every word of the region. Call it from a
    /// frame above the region (the port's job), before the cycles start.
    void paint() noexcept;

    /// True while every guard word holds the pattern (always, with no region).
    [[nodiscard]] bool guard_intact() const noexcept;

    /// Bytes from the region's top down to its lowest word that no longer
    /// holds the pattern (0: untouched).
    [[nodiscard]] std::size_t high_water_bytes() const noexcept;

    /// Bytes of the region (the stack budget below the painting frame).
    [[nodiscard]] std::size_t region_bytes() const noexcept { return region_.size() * sizeof(std::uint32_t); }
    /// Bytes of the guard band.
    [[nodiscard]] std::size_t guard_bytes() const noexcept { return guard_words_ * sizeof(std::uint32_t); }
    /// The region's lowest address (nullptr with no region).
    [[nodiscard]] const std::uint32_t* region_begin() const noexcept { return region_.data(); }

private:
    Span<std::uint32_t> region_{};
    std::size_t guard_words_ = 0U;
};

}  // namespace cellguard

#endif  // CELLGUARD_STACK_PAINT_HPP
