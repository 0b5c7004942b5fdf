/// @file prior_integrity.hpp
/// Run-time integrity of the prior image: a periodic test of the
/// non-volatile memory that holds it (IEC 61508-2 Annex A, table A.5,
/// invariable memory ranges: a CRC-32 signature of the block, the kind of
/// measure IEC 61508-7 A.4 describes), spread over the control cycles in
/// bounded slices.
///
/// At start-up load_prior_image (prior_image.hpp) checks both CRCs and the
/// geometry; the controller refuses to run when it fails. A
/// PriorIntegrityMonitor is made from that loaded view and then, on every
/// step(), feeds the next slice of the image through CRC-32:
/// - bytes [0, 84) into the header CRC, bytes [88, end) into the payload
///   CRC; the 4 bytes [84, 88) are the stored header CRC itself, compared
///   at the end of the pass (they count towards the slice).
/// - A pass covers the whole image in steps_per_pass() = ceil(image size /
///   slice bytes) steps. The step that ends a pass reads the two stored CRCs
///   from the image and compares: both equal keeps kOk, any difference
///   latches kCrcMismatch, which stays until a new monitor is made.
/// - Work bound per step, exact: min(slice_bytes, bytes left in the pass)
///   bytes covered, at most that many table lookups; the last step of a pass
///   adds two 4-byte little-endian loads and two comparisons. A latched
///   monitor does no work. last_step_bytes() reports the bytes covered.
/// - Detection: CRC-32 detects every single-bit error (crc32.hpp). A
///   corruption present when a pass starts is reported by the step that
///   ends that pass; one that appears during a pass is reported by the end
///   of the next pass at the latest, i.e. within 2 * steps_per_pass() steps.
///
/// The monitor checks the bytes it was given: the controller must read the
/// prior from the same bytes (the PriorImageView), not from a copy, for the
/// test to cover what the subtraction uses.
#ifndef CELLGUARD_PRIOR_INTEGRITY_HPP
#define CELLGUARD_PRIOR_INTEGRITY_HPP

#include <cstddef>
#include <cstdint>

#include "cellguard/crc32.hpp"
#include "cellguard/prior_image.hpp"
#include "cellguard/result.hpp"
#include "cellguard/span.hpp"

namespace cellguard {

/// Verdict of the run-time prior check.
enum class PriorIntegrityStatus : std::uint8_t {
    kNotInitialised = 0,  ///< a default-constructed monitor: no image, never "ok"
    kOk = 1,              ///< verified at load, and every completed pass matched
    kCrcMismatch = 2,     ///< a completed pass did not match a stored CRC; latched
};

/// A short, static, human-readable name (never nullptr).
const char* to_string(PriorIntegrityStatus status) noexcept;

/// Steps per full pass over an image of @p image_bytes bytes with slices of
/// @p slice_bytes (> 0): ceil(image_bytes / slice_bytes). For sizing the
/// detection time offline.
constexpr std::size_t prior_integrity_steps_per_pass(std::size_t image_bytes, std::size_t slice_bytes) noexcept {
    return slice_bytes == 0U ? 0U : image_bytes / slice_bytes + ((image_bytes % slice_bytes) != 0U ? 1U : 0U);
}

/// The periodic re-verification of a loaded prior image, one bounded slice
/// per step(). Holds a view of the image, two CRC registers and counters;
/// no heap.
class PriorIntegrityMonitor {
public:
    /// A monitor with no image: step() does nothing and reports kNotInitialised.
    PriorIntegrityMonitor() noexcept = default;

    /// A monitor over the image of @p image (from load_prior_image, so it was
    /// verified at start-up: the status starts kOk), covering @p slice_bytes
    /// bytes per step. Errors: kInvalidArgument when the view is empty or
    /// slice_bytes is 0.
    [[nodiscard]] static Result<PriorIntegrityMonitor> make(const PriorImageView& image,
                                                            std::size_t slice_bytes) noexcept;

    /// Covers the next slice; at the end of a pass compares with the stored
    /// CRCs and starts the next pass. Returns the status after the step.
    [[nodiscard]] PriorIntegrityStatus step() noexcept;

    /// The current verdict.
    [[nodiscard]] PriorIntegrityStatus status() const noexcept { return status_; }
    /// Bytes covered per step (the last step of a pass may cover fewer).
    [[nodiscard]] std::size_t slice_bytes() const noexcept { return slice_bytes_; }
    /// ceil(image size / slice bytes); 0 for a default-constructed monitor.
    [[nodiscard]] std::size_t steps_per_pass() const noexcept {
        return prior_integrity_steps_per_pass(image_.size(), slice_bytes_);
    }
    /// Offset of the next byte the current pass will cover.
    [[nodiscard]] std::size_t position() const noexcept { return position_; }
    /// Bytes covered by the last step() (0 before the first, and for a
    /// latched or uninitialised monitor).
    [[nodiscard]] std::size_t last_step_bytes() const noexcept { return last_step_bytes_; }
    /// Completed passes since make(), saturating at UINT32_MAX.
    [[nodiscard]] std::uint32_t passes_completed() const noexcept { return passes_completed_; }

private:
    Span<const std::uint8_t> image_{};
    std::size_t slice_bytes_ = 0U;
    std::size_t position_ = 0U;
    std::size_t last_step_bytes_ = 0U;
    Crc32 header_crc_{};
    Crc32 payload_crc_{};
    std::uint32_t passes_completed_ = 0U;
    PriorIntegrityStatus status_ = PriorIntegrityStatus::kNotInitialised;
};

}  // namespace cellguard

#endif  // CELLGUARD_PRIOR_INTEGRITY_HPP
