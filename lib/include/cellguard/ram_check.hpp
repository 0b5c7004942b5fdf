/// @file ram_check.hpp
/// A periodic signature test of a block of RAM whose contents must not
/// change after start-up (the prior values, the zone membership mask): the
/// CRC-32 of the block is taken once as the reference, then every step()
/// feeds the next bounded slice through CRC-32, and the step that ends a
/// pass compares the result with the reference. The same measure as the
/// prior image's check (prior_integrity.hpp) and the ray tables'
/// (ray_table.hpp), for RAM that the controller reads every cycle.
///
/// - Work per step: at most the slice's bytes through CRC-32, plus one
///   comparison at the end of a pass. A failed check does no more work.
/// - Detection: CRC-32 detects every single-bit error (crc32.hpp). A change
///   present when a pass starts is reported by the step that ends that
///   pass; one that appears during a pass by the end of the next pass, so
///   within 2 * steps_per_pass() steps.
/// - The verdict latches: a block that failed stays failed, even if its
///   contents are repaired.
#ifndef CELLGUARD_RAM_CHECK_HPP
#define CELLGUARD_RAM_CHECK_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/contract.hpp"
#include "cellguard/crc32.hpp"
#include "cellguard/span.hpp"

namespace cellguard {

/// See the file comment. Holds a view of the block, not a copy.
class BlockSignatureCheck {
public:
    /// A check of no block: step() does nothing and never fails.
    BlockSignatureCheck() noexcept = default;

    /// A check of @p block, whose CRC-32 now becomes the reference.
    explicit BlockSignatureCheck(Span<const std::uint8_t> block) noexcept
        : block_(block), reference_(crc32(block)) {}

    /// Covers the next @p slice_bytes bytes (> 0: contract) of the current
    /// pass; the step that ends a pass compares with the reference and
    /// starts the next pass. Returns true once any pass has not matched.
    [[nodiscard]] bool step(std::size_t slice_bytes) noexcept {
        CG_ENFORCE(slice_bytes > 0U, "a check slice needs at least one byte");
        if (failed_ || block_.empty()) {
            return failed_;
        }
        const std::size_t remaining = block_.size() - offset_;
        const std::size_t n = remaining < slice_bytes ? remaining : slice_bytes;
        state_ = crc32_update(state_, block_.subspan(offset_, n));
        offset_ += n;
        if (offset_ == block_.size()) {
            failed_ = crc32_finish(state_) != reference_;
            state_ = kCrc32Init;
            offset_ = 0U;
        }
        return failed_;
    }

    /// The CRC-32 of the block when the check was made.
    [[nodiscard]] std::uint32_t reference() const noexcept { return reference_; }
    /// True once a pass has not matched the reference (latched).
    [[nodiscard]] bool failed() const noexcept { return failed_; }
    /// Offset of the next byte the current pass covers.
    [[nodiscard]] std::size_t position() const noexcept { return offset_; }
    /// Steps of @p slice_bytes (> 0) per pass over the block: ceil(size / slice).
    [[nodiscard]] std::size_t steps_per_pass(std::size_t slice_bytes) const noexcept {
        CG_ENFORCE(slice_bytes > 0U, "a check slice needs at least one byte");
        return (block_.size() + slice_bytes - 1U) / slice_bytes;
    }

private:
    Span<const std::uint8_t> block_{};
    std::uint32_t reference_ = 0U;
    std::uint32_t state_ = kCrc32Init;
    std::size_t offset_ = 0U;
    bool failed_ = false;
};

}  // namespace cellguard

#endif  // CELLGUARD_RAM_CHECK_HPP
