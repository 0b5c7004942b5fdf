// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file bucket_queue.hpp
/// A monotone two-level bucket queue over integer keys, for Dijkstra's
/// algorithm with non-negative integer edge costs (the probabilistic
/// accessibility analysis, accessibility.hpp). No heap: every link lives in
/// caller storage, so the memory is bounded by the number of items.
///
/// How it works:
/// - Keys are integers in [0, kKeyLimit) = [0, 2^21). The queue is monotone:
///   a key pushed (or lowered to) must be >= the key of the last item popped,
///   as in Dijkstra's algorithm with non-negative costs. Violations are
///   contract errors (CG_ASSERT, debug builds).
/// - The keys are not copied: the queue reads `keys[item]` from a caller
///   array (Dijkstra's distance array), so the caller lowers a key in place
///   and then calls decrease().
/// - Level 1 holds 2^10 coarse buckets of width 2^11 keys; level 2 holds
///   2^11 fine buckets of width 1 for the current coarse bucket only. When the
///   fine level runs empty, the next non-empty coarse bucket is spread over
///   the fine buckets. A bitmap per level finds the next non-empty bucket in
///   a few word scans. Each item moves from coarse to fine at most once per
///   push, so push, decrease and pop take amortised O(1) time plus the
///   bitmap scan (at most 48 words).
/// - Buckets are circular doubly linked lists threaded through the caller's
///   `next` and `prev` arrays, with one sentinel entry per bucket after the
///   items (hence link_count(items) = items + kListHeads). An item is in at
///   most one bucket; decrease() unlinks it in O(1). Within a bucket the order
///   is first in, first out; pop() returns the oldest item with the least key.
#ifndef CELLGUARD_BUCKET_QUEUE_HPP
#define CELLGUARD_BUCKET_QUEUE_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/base/contract.hpp"
#include "cellguard/base/result.hpp"
#include "cellguard/base/span.hpp"

namespace cellguard {

/// Monotone two-level bucket queue of item indices keyed by a caller array.
/// The caller tracks which items are queued (push only an item that is not,
/// decrease only one that is).
class MonotoneBucketQueue {
public:
    /// Bits of a key that select the fine bucket.
    static constexpr std::uint32_t kFineBits = 11U;
    /// Bits above kFineBits that select the coarse bucket.
    static constexpr std::uint32_t kCoarseBits = 10U;
    /// Number of fine buckets (keys of one coarse bucket).
    static constexpr std::uint32_t kFineBuckets = 1U << kFineBits;
    /// Number of coarse buckets.
    static constexpr std::uint32_t kCoarseBuckets = 1U << kCoarseBits;
    /// Keys must be below this bound: 2^21.
    static constexpr std::uint32_t kKeyLimit = 1U << (kFineBits + kCoarseBits);
    /// Sentinel list heads that follow the items in the link arrays.
    static constexpr std::size_t kListHeads = std::size_t{kFineBuckets} + std::size_t{kCoarseBuckets};
    /// Largest number of items (indices and sentinels must fit in uint32).
    static constexpr std::size_t kMaxItems = std::size_t{0xFFFFFFFFU} - kListHeads;

    /// Entries each of `next` and `prev` must hold for @p items items.
    [[nodiscard]] static constexpr std::size_t link_count(std::size_t items) noexcept { return items + kListHeads; }

    /// An unusable queue (placeholder); build one with make().
    MonotoneBucketQueue() noexcept = default;

    /// Binds a queue over items [0, keys.size()) to caller storage and
    /// empties it (only the sentinel entries of next/prev are written).
    /// Errors: kCapacityExceeded when keys.size() > kMaxItems,
    /// kStorageTooSmall when next or prev holds fewer than
    /// link_count(keys.size()) entries.
    [[nodiscard]] static Result<MonotoneBucketQueue> make(Span<const std::uint32_t> keys, Span<std::uint32_t> next,
                                                          Span<std::uint32_t> prev) noexcept;

    /// True when no item is queued.
    [[nodiscard]] bool empty() const noexcept { return size_ == 0U; }
    /// Number of queued items.
    [[nodiscard]] std::size_t size() const noexcept { return size_; }
    /// Key of the last item popped (0 before the first pop).
    [[nodiscard]] std::uint32_t last_key() const noexcept { return last_key_; }

    /// Queues @p item (not queued now) with key keys[item], which must be in
    /// [last_key(), kKeyLimit).
    void push(std::uint32_t item) noexcept {
        CG_ASSERT(item < item_count_, "bucket queue: item out of range");
        const std::uint32_t key = keys_[item];
        CG_ASSERT(key < kKeyLimit && key >= last_key_, "bucket queue: key out of range or below the last pop");
        const std::uint32_t coarse = key >> kFineBits;
        if (coarse == current_coarse_) {
            const std::uint32_t fine = key & (kFineBuckets - 1U);
            link_last(item, fine_head(fine));
            fine_mask_[fine >> 6U] |= std::uint64_t{1} << (fine & 63U);
        } else {
            link_last(item, coarse_head(coarse));
            coarse_mask_[coarse >> 6U] |= std::uint64_t{1} << (coarse & 63U);
        }
        ++size_;
    }

    /// Re-files @p item (queued now) after the caller lowered keys[item];
    /// the new key must still be >= last_key().
    void decrease(std::uint32_t item) noexcept {
        CG_ASSERT(item < item_count_, "bucket queue: item out of range");
        unlink(item);
        --size_;
        push(item);
    }

    /// Removes and returns an item with the least key; the queue must not be
    /// empty (checked always).
    [[nodiscard]] std::uint32_t pop() noexcept {
        CG_ENFORCE(size_ != 0U, "bucket queue: pop from an empty queue");
        std::uint32_t fine = 0U;
        if (!first_fine(fine)) {
            refill_fine();
            const bool found = first_fine(fine);
            CG_ENFORCE(found, "bucket queue: lost items");
        }
        const std::uint32_t head = fine_head(fine);
        const std::uint32_t item = next_[head];
        unlink(item);
        --size_;
        last_key_ = keys_[item];
        fine_cursor_ = fine >> 6U;
        return item;
    }

private:
    [[nodiscard]] std::uint32_t fine_head(std::uint32_t fine) const noexcept { return item_count_ + fine; }
    [[nodiscard]] std::uint32_t coarse_head(std::uint32_t coarse) const noexcept {
        return item_count_ + kFineBuckets + coarse;
    }
    // Appends item at the tail of the bucket whose sentinel is head (first
    // in, first out: breadth-first order within a key, which keeps the
    // wavefront of a grid search compact in memory).
    void link_last(std::uint32_t item, std::uint32_t head) noexcept {
        const std::uint32_t last = prev_[head];
        next_[last] = item;
        prev_[item] = last;
        next_[item] = head;
        prev_[head] = item;
    }
    // Unlinks item; when its bucket runs empty (only the sentinel is left,
    // so its neighbours coincide) the bucket's bitmap bit is cleared.
    void unlink(std::uint32_t item) noexcept {
        const std::uint32_t before = prev_[item];
        const std::uint32_t after = next_[item];
        next_[before] = after;
        prev_[after] = before;
        if (before == after) {
            CG_ASSERT(before >= item_count_, "bucket queue: corrupt links");
            clear_bucket_bit(before - item_count_);
        }
    }
    void clear_bucket_bit(std::uint32_t bucket) noexcept;
    [[nodiscard]] bool first_fine(std::uint32_t& fine) const noexcept;
    void refill_fine() noexcept;

    Span<const std::uint32_t> keys_{};
    Span<std::uint32_t> next_{};
    Span<std::uint32_t> prev_{};
    std::uint32_t item_count_ = 0U;
    std::size_t size_ = 0U;
    std::uint32_t last_key_ = 0U;
    std::uint32_t current_coarse_ = 0U;
    std::uint32_t fine_cursor_ = 0U;  // first fine bitmap word that may be non-zero
    std::uint64_t fine_mask_[kFineBuckets / 64U] = {};
    std::uint64_t coarse_mask_[kCoarseBuckets / 64U] = {};
};

}  // namespace cellguard

#endif  // CELLGUARD_BUCKET_QUEUE_HPP
