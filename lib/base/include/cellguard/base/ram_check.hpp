// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file ram_check.hpp
/// The one periodic signature test of memory whose contents must not change
/// after start-up (IEC 61508-2 Annex A, table A.5, invariable memory ranges:
/// a CRC-32 signature, IEC 61508-7 A.4), spread over the control cycles in
/// bounded slices. The controller runs one over the prior values it reads,
/// one over the zone membership mask and one per sensor slot over that
/// sensor's ray table (safety_controller.hpp).
///
/// A check reads a list of at most kMaxSignatureRegions regions as one byte
/// stream, in list order. Its reference CRC-32 is either taken over all
/// regions when the check is made, or given by the caller (a ray table's
/// storage_crc(), taken by RayTable::build, so that the controller never
/// reads a whole table in one cycle). Every step() feeds the next at most
/// slice bytes of the stream through CRC-32, across region boundaries, and
/// the step that ends a pass compares the result with the reference.
///
/// - Work per step: at most the slice's bytes through CRC-32, plus one
///   comparison at the end of a pass. A failed check does no more work.
/// - A pass takes steps_per_pass(slice) = ceil(total_bytes() / slice) steps.
/// - Detection: CRC-32 detects every single-bit error (crc32.hpp). A change
///   present when a pass starts is reported by the step that ends that
///   pass; one that appears during a pass by the end of the next pass, so
///   within 2 * steps_per_pass() steps.
/// - The verdict latches: a check that failed stays failed, even if the
///   memory is repaired; only a new check starts afresh.
/// - A check holds views of the regions, not copies: it covers the bytes the
///   caller reads only when the caller reads them through the same regions.
///
/// Named SignatureCheck (formerly BlockSignatureCheck, one block) since it
/// also replaces the ray table's own sliced check and PriorIntegrityMonitor.
#ifndef CELLGUARD_RAM_CHECK_HPP
#define CELLGUARD_RAM_CHECK_HPP

#include <array>
#include <cstddef>
#include <cstdint>

#include "cellguard/base/crc32.hpp"
#include "cellguard/base/span.hpp"

namespace cellguard {

/// Most regions one SignatureCheck reads (a ray table needs 9).
constexpr std::size_t kMaxSignatureRegions = 12U;
static_assert(kMaxSignatureRegions >= 1U, "a signature check reads at least one region");

/// One region of memory a SignatureCheck reads: a read-only byte view.
using SignatureRegion = Span<const std::uint8_t>;

/// See the file comment. Holds views of the regions, one CRC-32 register
/// and counters; no heap.
class SignatureCheck {
public:
    /// A check of no memory: step() does nothing and never fails.
    SignatureCheck() noexcept = default;

    /// A check of @p regions (at most kMaxSignatureRegions: contract), whose
    /// CRC-32, read in order as one stream, now becomes the reference.
    explicit SignatureCheck(Span<const SignatureRegion> regions) noexcept;

    /// A check of @p regions (at most kMaxSignatureRegions: contract)
    /// against @p reference, the CRC-32 the caller took of them earlier.
    SignatureCheck(Span<const SignatureRegion> regions, std::uint32_t reference) noexcept;

    /// A check of the one region @p block, whose CRC-32 now becomes the reference.
    explicit SignatureCheck(SignatureRegion block) noexcept : SignatureCheck(Span<const SignatureRegion>(&block, 1U)) {}

    /// Covers the next at most @p slice_bytes bytes (> 0: contract) of the
    /// current pass; the step that ends a pass compares with the reference
    /// and starts the next pass. Returns true once any pass has not matched.
    [[nodiscard]] bool step(std::size_t slice_bytes) noexcept;

    /// The CRC-32 a pass must give: taken at construction, or the caller's.
    [[nodiscard]] std::uint32_t reference() const noexcept { return reference_; }
    /// True once a pass has not matched the reference (latched).
    [[nodiscard]] bool failed() const noexcept { return failed_; }
    /// Offset in the stream of the next byte the current pass covers.
    [[nodiscard]] std::size_t position() const noexcept { return position_; }
    /// Bytes one pass reads: the sum of the regions' sizes.
    [[nodiscard]] std::size_t total_bytes() const noexcept { return total_; }
    /// Steps of @p slice_bytes (> 0: contract) per pass: ceil(total_bytes() / slice).
    [[nodiscard]] std::size_t steps_per_pass(std::size_t slice_bytes) const noexcept;
    /// True when this check reads exactly @p regions: as many, each at the
    /// same address with the same size, in the same order. For a caller that
    /// re-derives its regions each time to see that they have not moved.
    [[nodiscard]] bool reads(Span<const SignatureRegion> regions) const noexcept;

private:
    std::array<SignatureRegion, kMaxSignatureRegions> regions_{};
    std::size_t region_count_ = 0U;
    std::size_t total_ = 0U;
    std::size_t region_ = 0U;         ///< the region the pass reads next
    std::size_t region_offset_ = 0U;  ///< bytes of that region read in this pass
    std::size_t position_ = 0U;       ///< bytes of the stream read in this pass
    std::uint32_t reference_ = 0U;
    std::uint32_t state_ = kCrc32Init;  ///< CRC-32 register of the pass
    bool failed_ = false;
};

}  // namespace cellguard

#endif  // CELLGUARD_RAM_CHECK_HPP
