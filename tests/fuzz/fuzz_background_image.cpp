// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the background view image loader (background_image.hpp). No
// crash, no read outside the input (ASan: the image is copied into a heap
// buffer of exactly its size); an accepted image's views, written again
// with the identities and depths it holds, give the identical bytes; a
// view loads only for its own identity.
//
// Input: one mode byte, then the image bytes.
// - mode bit 0: recompute the file header's and every record's CRCs
//   first, so mutations reach the field checks behind them.
// - mode bits 1..7: unused (kept for seeds).
// Records of both view kinds (0 depth image, 1 direction grid of a
// point-set sensor: farthest then nearest range per bin).
// The expected sensor count and prior CRC are the ones the header states, so
// mutations get past those checks (the refusals are unit-tested).
// Seeds: tests/fuzz/corpus/fuzz_background_image/.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/prior/background_image.hpp"
#include "cellguard/prior/prior_image.hpp"

using namespace cellguard;

namespace {

void require(bool condition) {
    if (!condition) {
        std::abort();
    }
}

void put_u32(std::vector<std::uint8_t>& img, std::size_t offset, std::uint32_t v) {
    for (std::size_t i = 0; i < 4; ++i)
        img[offset + i] = static_cast<std::uint8_t>(v >> (8U * i));
}

// Recomputes the CRCs of the header and of each record that fits.
void fix_crcs(std::vector<std::uint8_t>& img) {
    if (img.size() < kBackgroundImageHeaderSize) {
        return;
    }
    const Span<const std::uint8_t> s(img.data(), img.size());
    put_u32(img, 28U, crc32(s.subspan(0U, 28U)));
    std::size_t at = kBackgroundImageHeaderSize;
    const std::uint32_t count = load_le_u32(s, 8U);
    for (std::uint32_t r = 0U; r < count && r < 8U; ++r) {
        if (img.size() - at < kBackgroundRecordHeaderSize) {
            return;
        }
        const std::uint64_t length = load_le_u32(s, at + 104U);
        const std::size_t start = at + kBackgroundRecordHeaderSize;
        if (img.size() - start >= length) {
            put_u32(img, at + 108U, crc32(s.subspan(start, static_cast<std::size_t>(length))));
        }
        put_u32(img, at + 116U, crc32(s.subspan(at, 116U)));
        if (img.size() - start < length) {
            return;
        }
        at = start + static_cast<std::size_t>(length);
    }
}

BackgroundSensorIdentity identity_at(Span<const std::uint8_t> s, std::size_t at) {
    BackgroundSensorIdentity id;
    id.name_crc = load_le_u32(s, at);
    id.kind = load_le_u32(s, at + 12U);
    id.width = load_le_u32(s, at + 4U);
    id.height = load_le_u32(s, at + 8U);
    for (std::size_t i = 0; i < 3; ++i) {
        const std::uint64_t b = load_le_u64(s, at + 16U + 8U * i);
        std::memcpy(&id.position[i], &b, sizeof b);
    }
    for (std::size_t i = 0; i < 4; ++i) {
        const std::uint64_t r = load_le_u64(s, at + 40U + 8U * i);
        std::memcpy(&id.rotation[i], &r, sizeof r);
        const std::uint64_t k = load_le_u64(s, at + 72U + 8U * i);
        std::memcpy(&id.intrinsics[i], &k, sizeof k);
    }
    return id;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1U) {
        return 0;
    }
    const std::uint8_t mode = data[0];
    std::vector<std::uint8_t> img(data + 1, data + size);
    if ((mode & 1U) != 0U) {
        fix_crcs(img);
    }
    const Span<const std::uint8_t> s(img.data(), img.size());
    const std::uint32_t count = img.size() >= 12U ? load_le_u32(s, 8U) : 1U;
    const std::uint32_t prior_crc = img.size() >= 16U ? load_le_u32(s, 12U) : 0U;
    const Result<BackgroundImageInfo, BackgroundImageError> r = check_background_image(s, count, prior_crc);
    require(r.ok() == (r.error() == BackgroundImageError::kNone));
    require(to_string(r.error()) != nullptr);
    if (!r.ok()) {
        return 0;
    }
    const BackgroundImageInfo info = r.value();
    require(info.sensor_count == count && info.prior_crc == prior_crc && info.frames > 0U);

    // Every view loads for its own identity, not for another name; then the
    // views written again give the identical bytes.
    std::vector<std::vector<float>> views(count);
    std::vector<BackgroundViewRecord> records(count);
    std::size_t at = kBackgroundImageHeaderSize;
    for (std::uint32_t i = 0U; i < count; ++i) {
        const BackgroundSensorIdentity id = identity_at(s, at);
        views[i].assign(background_view_values(id), -1.0F);  // a direction grid: farthest, then nearest
        const Result<std::size_t, BackgroundImageError> got = load_background_view(
            s, count, prior_crc, i, id, Span<float>(views[i].data(), views[i].size()));
        require(got.ok() && got.value() == views[i].size());
        for (const float d : views[i])
            require(d >= 0.0F);
        if (id.kind == kBackgroundViewDirectionGrid) {  // an accepted grid is a valid one, each bin near <= far
            require(check_direction_grid(direction_grid_of(id)).ok());
            const std::size_t bins = views[i].size() / 2U;
            for (std::size_t b = 0U; b < bins; ++b)
                require(views[i][bins + b] <= views[i][b]);
        }
        BackgroundSensorIdentity other = id;
        other.name_crc ^= 1U;
        require(load_background_view(s, count, prior_crc, i, other, Span<float>(views[i].data(), views[i].size()))
                    .error() == BackgroundImageError::kWrongSensor);
        records[i] = BackgroundViewRecord{id, Span<const float>(views[i].data(), views[i].size())};
        at += kBackgroundRecordHeaderSize + 4U * views[i].size();
    }
    std::vector<std::uint8_t> again(img.size());
    const Result<std::size_t> w = write_background_image(Span<const BackgroundViewRecord>(records.data(), count),
                                                         prior_crc, info.frames,
                                                         Span<std::uint8_t>(again.data(), again.size()));
    require(w.ok() && w.value() == img.size());
    require(again == img);
    return 0;
}
