#include "cellguard/prior_integrity.hpp"

namespace cellguard {

namespace layout = prior_image_layout;

const char* to_string(PriorIntegrityStatus status) noexcept {
    switch (status) {
        case PriorIntegrityStatus::kNotInitialised: return "prior integrity monitor not initialised";
        case PriorIntegrityStatus::kOk: return "prior integrity ok";
        case PriorIntegrityStatus::kCrcMismatch: return "prior integrity CRC mismatch";
    }
    return "unknown prior integrity status";
}

Result<PriorIntegrityMonitor> PriorIntegrityMonitor::make(const PriorImageView& image,
                                                          std::size_t slice_bytes) noexcept {
    if (image.empty() || slice_bytes == 0U) {
        return ErrorCode::kInvalidArgument;
    }
    PriorIntegrityMonitor m;
    m.image_ = image.image();
    m.slice_bytes_ = slice_bytes;
    m.status_ = PriorIntegrityStatus::kOk;
    return m;
}

PriorIntegrityStatus PriorIntegrityMonitor::step() noexcept {
    last_step_bytes_ = 0U;
    if (status_ != PriorIntegrityStatus::kOk) {
        return status_;  // not initialised, or latched: no work
    }
    const std::size_t size = image_.size();
    // The view came from load_prior_image: size > 88. A position beyond the
    // image means this object's own memory is corrupt.
    CG_ENFORCE(size > kPriorImageHeaderSize && position_ < size, "prior integrity monitor state corrupt");
    const std::size_t left = size - position_;
    const std::size_t n = slice_bytes_ < left ? slice_bytes_ : left;
    const std::size_t begin = position_;
    const std::size_t end = begin + n;

    if (begin < layout::kHeaderCrc) {  // part of [begin, end) inside [0, 84)
        const std::size_t stop = end < layout::kHeaderCrc ? end : layout::kHeaderCrc;
        header_crc_.update(image_.subspan(begin, stop - begin));
    }
    if (end > kPriorImageHeaderSize) {  // part of [begin, end) inside [88, size)
        const std::size_t start = begin > kPriorImageHeaderSize ? begin : kPriorImageHeaderSize;
        payload_crc_.update(image_.subspan(start, end - start));
    }
    last_step_bytes_ = n;
    position_ = end;

    if (position_ == size) {  // end of a pass: compare with the stored CRCs
        const bool header_ok = header_crc_.value() == load_le_u32(image_, layout::kHeaderCrc);
        const bool payload_ok = payload_crc_.value() == load_le_u32(image_, layout::kPayloadCrc);
        if (!header_ok || !payload_ok) {
            status_ = PriorIntegrityStatus::kCrcMismatch;
        }
        if (passes_completed_ != UINT32_MAX) {
            ++passes_completed_;
        }
        position_ = 0U;
        header_crc_.reset();
        payload_crc_.reset();
    }
    return status_;
}

}  // namespace cellguard
