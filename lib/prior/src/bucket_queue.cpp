// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/prior/bucket_queue.hpp"

namespace cellguard {

namespace {
// Index of the lowest set bit of a non-zero word.
std::uint32_t lowest_bit(std::uint64_t word) noexcept { return static_cast<std::uint32_t>(__builtin_ctzll(word)); }
}  // namespace

Result<MonotoneBucketQueue> MonotoneBucketQueue::make(Span<const std::uint32_t> keys, Span<std::uint32_t> next,
                                                      Span<std::uint32_t> prev) noexcept {
    if (keys.size() > kMaxItems) {
        return ErrorCode::kCapacityExceeded;
    }
    const std::size_t links = link_count(keys.size());
    if (next.size() < links || prev.size() < links) {
        return ErrorCode::kStorageTooSmall;
    }
    MonotoneBucketQueue queue;
    queue.keys_ = keys;
    queue.next_ = next;
    queue.prev_ = prev;
    queue.item_count_ = static_cast<std::uint32_t>(keys.size());
    for (std::size_t h = keys.size(); h < links; ++h) {
        next[h] = static_cast<std::uint32_t>(h);
        prev[h] = static_cast<std::uint32_t>(h);
    }
    return queue;
}

void MonotoneBucketQueue::clear_bucket_bit(std::uint32_t bucket) noexcept {
    if (bucket < kFineBuckets) {
        fine_mask_[bucket >> 6U] &= ~(std::uint64_t{1} << (bucket & 63U));
    } else {
        const std::uint32_t coarse = bucket - kFineBuckets;
        coarse_mask_[coarse >> 6U] &= ~(std::uint64_t{1} << (coarse & 63U));
    }
}

bool MonotoneBucketQueue::first_fine(std::uint32_t& fine) const noexcept {
    for (std::uint32_t w = fine_cursor_; w < kFineBuckets / 64U; ++w) {
        if (fine_mask_[w] != 0U) {
            fine = (w << 6U) + lowest_bit(fine_mask_[w]);
            return true;
        }
    }
    return false;
}

// The fine level is empty: move the items of the next non-empty coarse bucket
// (all coarse buckets in use are above current_coarse_) to the fine level.
void MonotoneBucketQueue::refill_fine() noexcept {
    std::uint32_t coarse = kCoarseBuckets;
    for (std::uint32_t w = 0U; w < kCoarseBuckets / 64U; ++w) {
        if (coarse_mask_[w] != 0U) {
            coarse = (w << 6U) + lowest_bit(coarse_mask_[w]);
            break;
        }
    }
    CG_ENFORCE(coarse < kCoarseBuckets && coarse > current_coarse_, "bucket queue: no coarse bucket to refill from");
    current_coarse_ = coarse;
    fine_cursor_ = 0U;
    const std::uint32_t head = coarse_head(coarse);
    std::uint32_t item = next_[head];
    while (item != head) {
        const std::uint32_t following = next_[item];
        const std::uint32_t fine = keys_[item] & (kFineBuckets - 1U);
        link_last(item, fine_head(fine));
        fine_mask_[fine >> 6U] |= std::uint64_t{1} << (fine & 63U);
        item = following;
    }
    next_[head] = head;
    prev_[head] = head;
    coarse_mask_[coarse >> 6U] &= ~(std::uint64_t{1} << (coarse & 63U));
}

}  // namespace cellguard
