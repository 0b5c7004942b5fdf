// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/ram_check.hpp"

#include <limits>

#include "cellguard/base/contract.hpp"
#include "cellguard/base/crc32.hpp"

namespace cellguard {

SignatureCheck::SignatureCheck(Span<const SignatureRegion> regions, std::uint32_t reference) noexcept
    : reference_(reference) {
    CG_ENFORCE(regions.size() <= kMaxSignatureRegions, "a signature check reads at most kMaxSignatureRegions regions");
    for (const SignatureRegion& region : regions) {
        CG_ENFORCE(region.size() <= std::numeric_limits<std::size_t>::max() - total_,
                   "a signature check's regions add up to more than SIZE_MAX bytes");
        regions_[region_count_] = region;  // < kMaxSignatureRegions: checked above
        ++region_count_;
        total_ += region.size();
    }
}

SignatureCheck::SignatureCheck(Span<const SignatureRegion> regions) noexcept : SignatureCheck(regions, 0U) {
    std::uint32_t crc = kCrc32Init;
    for (std::size_t r = 0U; r < region_count_; ++r) {
        crc = crc32_update(crc, regions_[r]);
    }
    reference_ = crc32_finish(crc);
}

bool SignatureCheck::step(std::size_t slice_bytes) noexcept {
    CG_ENFORCE(slice_bytes > 0U, "a check slice needs at least one byte");
    if (failed_ || total_ == 0U) {
        return failed_;
    }
    std::size_t budget = slice_bytes;
    // Regions in turn until the slice is spent or the pass is complete;
    // empty regions are passed over without using the slice.
    while (budget > 0U && position_ < total_) {
        CG_ENFORCE(region_ < region_count_, "signature check state corrupt");
        const SignatureRegion& region = regions_[region_];
        const std::size_t left = region.size() - region_offset_;
        const std::size_t n = left < budget ? left : budget;
        state_ = crc32_update(state_, region.subspan(region_offset_, n));
        region_offset_ += n;
        position_ += n;
        budget -= n;
        if (region_offset_ == region.size()) {
            ++region_;
            region_offset_ = 0U;
        }
    }
    if (position_ == total_) {  // the end of a pass: compare, start the next
        failed_ = crc32_finish(state_) != reference_;
        state_ = kCrc32Init;
        region_ = 0U;
        region_offset_ = 0U;
        position_ = 0U;
    }
    return failed_;
}

std::size_t SignatureCheck::steps_per_pass(std::size_t slice_bytes) const noexcept {
    CG_ENFORCE(slice_bytes > 0U, "a check slice needs at least one byte");
    return total_ / slice_bytes + (total_ % slice_bytes != 0U ? 1U : 0U);
}

bool SignatureCheck::reads(Span<const SignatureRegion> regions) const noexcept {
    if (regions.size() != region_count_) {
        return false;
    }
    for (std::size_t r = 0U; r < region_count_; ++r) {
        if (regions[r].data() != regions_[r].data() || regions[r].size() != regions_[r].size()) {
            return false;
        }
    }
    return true;
}

}  // namespace cellguard
